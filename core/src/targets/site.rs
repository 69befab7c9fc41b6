//! The site as a 2D grid from a classified cloud: ground height, and which
//! cells buildings and trees occupy — where a ground robot may stand.

use thiserror::Error;

use crate::cloud::{ColumnLength, class};
use crate::geom::grid::{self, GridFrame, Neighbours};
use crate::ground::{Dtm, xy_extent};

/// Why a site could not be built.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SiteError {
    /// Labels do not match the points.
    #[error(transparent)]
    LabelLength(#[from] ColumnLength),
    /// The cell size is not positive.
    #[error("site cell must be a positive finite number, got {0}")]
    Cell(f32),
    /// No ground points to stand on.
    #[error("the cloud has no ground points (class 2): classify it first")]
    NoGround,
}

/// Grid of the site, local frame.
#[derive(Debug, Clone)]
pub struct Site {
    /// The cells.
    pub frame: GridFrame,
    /// The terrain model on `frame` (NaN: unknown, off the ground).
    pub ground: Dtm,
    /// Cells holding building points, grown by the clearance.
    pub building: Vec<bool>,
    /// Cells holding vegetation points, grown by the clearance.
    pub vegetation: Vec<bool>,
}

/// Ground heights are spread this many cells into cells without ground
/// points (under small gaps), no farther: beyond, the ground is unknown.
const FILL_STEPS: usize = 3;

impl Site {
    /// Builds the grid from points and their LAS classes (2 ground, 5
    /// vegetation, 6 building; other classes are ignored). Occupied cells are
    /// grown by `clearance` metres.
    pub fn from_cloud(
        xyz: &[[f32; 3]],
        labels: &[u8],
        cell: f32,
        clearance: f32,
    ) -> Result<Site, SiteError> {
        ColumnLength::check("labels", xyz.len(), labels.len())?;
        if !(cell.is_finite() && cell > 0.0) {
            return Err(SiteError::Cell(cell));
        }
        let finite = || {
            xyz.iter()
                .zip(labels)
                .filter(|(p, _)| p.iter().all(|v| v.is_finite()))
        };
        let (lo, hi) = xy_extent(finite().map(|(p, _)| p)).ok_or(SiteError::NoGround)?;
        let frame = GridFrame::covering(lo, hi, f64::from(cell), 0);
        let of_class = |c: u8| {
            let mut occupied = vec![false; frame.len()];
            for (p, _) in finite().filter(|(_, l)| class::fold(**l) == c) {
                occupied[frame.clamped_index(f64::from(p[0]), f64::from(p[1]))] = true;
            }
            occupied
        };
        let ground = finite()
            .filter(|(_, l)| class::fold(**l) == class::GROUND)
            .map(|(p, _)| ([f64::from(p[0]), f64::from(p[1])], p[2]));
        let mut heights = grid::cell_means(&frame, ground);
        if heights.iter().all(|z| z.is_nan()) {
            return Err(SiteError::NoGround);
        }
        grid::fill_holes(
            &mut heights,
            frame.nx,
            frame.ny,
            FILL_STEPS,
            Neighbours::Four,
        );
        let r = (clearance / cell).ceil() as isize;
        let size = [frame.nx, frame.ny];
        Ok(Site {
            building: grow(&of_class(class::BUILDING), size, r),
            vegetation: grow(&of_class(class::VEGETATION), size, r),
            ground: Dtm { frame, heights },
            frame,
        })
    }

    /// Cell edge, metres.
    pub fn cell(&self) -> f32 {
        self.frame.cell as f32
    }

    /// Cell index of a point, if on the grid.
    pub fn index(&self, x: f32, y: f32) -> Option<usize> {
        self.frame.index_of(f64::from(x), f64::from(y))
    }

    /// Ground height at a point (None off the grid or off the ground).
    pub fn ground_at(&self, x: f32, y: f32) -> Option<f32> {
        self.ground.cell_height(f64::from(x), f64::from(y))
    }
}

fn grow(occ: &[bool], size: [usize; 2], r: isize) -> Vec<bool> {
    if r <= 0 {
        return occ.to_vec();
    }
    let mut out = occ.to_vec();
    for j in 0..size[1] as isize {
        for i in 0..size[0] as isize {
            if !occ[j as usize * size[0] + i as usize] {
                continue;
            }
            for b in (j - r).max(0)..=(j + r).min(size[1] as isize - 1) {
                for a in (i - r).max(0)..=(i + r).min(size[0] as isize - 1) {
                    if (a - i).pow(2) + (b - j).pow(2) <= r * r {
                        out[b as usize * size[0] + a as usize] = true;
                    }
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_marks_ground_buildings_and_trees() {
        let mut xyz = Vec::new();
        let mut labels = Vec::new();
        for i in 0..40 {
            for j in 0..40 {
                xyz.push([i as f32 + 0.5, j as f32 + 0.5, 0.1 * i as f32]);
                labels.push(2);
            }
        }
        xyz.push([10.5, 10.5, 8.0]);
        labels.push(6);
        xyz.push([30.5, 30.5, 6.0]);
        labels.push(5);
        let site = Site::from_cloud(&xyz, &labels, 1.0, 1.0).unwrap();
        let k = site.index(11.2, 10.5).unwrap();
        assert!(site.building[k] && !site.vegetation[k]);
        assert!(site.vegetation[site.index(30.5, 31.4).unwrap()]);
        assert!((site.ground_at(20.5, 3.0).unwrap() - 2.0).abs() < 1e-4);
        assert!(site.ground_at(100.0, 0.0).is_none());
        assert!(Site::from_cloud(&xyz, &labels[1..], 1.0, 1.0).is_err());
        assert_eq!(
            Site::from_cloud(&[[0.0; 3]], &[6], 1.0, 1.0).unwrap_err(),
            SiteError::NoGround
        );
    }
}
