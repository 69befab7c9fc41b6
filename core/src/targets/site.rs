//! The site as a 2D grid from a classified cloud: ground height, and which
//! cells buildings and trees occupy — where a ground robot may stand.

use thiserror::Error;

use crate::cloud::class;

/// Why a site could not be built.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SiteError {
    /// Labels do not match the points.
    #[error("labels ({labels}) and points ({points}) differ in length")]
    LabelLength {
        /// Labels given.
        labels: usize,
        /// Points given.
        points: usize,
    },
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
    /// World xy of the grid's lower-left corner.
    pub origin: [f32; 2],
    /// Cell edge, metres.
    pub cell: f32,
    /// Cells along x and y.
    pub size: [usize; 2],
    /// Ground height per cell (NaN: unknown, off the ground).
    pub ground: Vec<f32>,
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
        if xyz.len() != labels.len() {
            return Err(SiteError::LabelLength {
                labels: labels.len(),
                points: xyz.len(),
            });
        }
        if !(cell.is_finite() && cell > 0.0) {
            return Err(SiteError::Cell(cell));
        }
        let finite = || {
            xyz.iter()
                .zip(labels)
                .filter(|(p, _)| p.iter().all(|v| v.is_finite()))
        };
        let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
        for (p, _) in finite() {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if lo[0] > hi[0] {
            return Err(SiteError::NoGround);
        }
        let size = [
            ((hi[0] - lo[0]) / cell) as usize + 1,
            ((hi[1] - lo[1]) / cell) as usize + 1,
        ];
        let n = size[0] * size[1];
        let mut sum = vec![0.0f64; n];
        let mut count = vec![0u32; n];
        let mut building = vec![false; n];
        let mut vegetation = vec![false; n];
        let at = |p: &[f32; 3]| {
            let i = (((p[0] - lo[0]) / cell) as usize).min(size[0] - 1);
            let j = (((p[1] - lo[1]) / cell) as usize).min(size[1] - 1);
            j * size[0] + i
        };
        for (p, &l) in finite() {
            let k = at(p);
            match class::fold(l) {
                class::GROUND => {
                    sum[k] += p[2] as f64;
                    count[k] += 1;
                }
                class::VEGETATION => vegetation[k] = true,
                class::BUILDING => building[k] = true,
                _ => {}
            }
        }
        if count.iter().all(|&c| c == 0) {
            return Err(SiteError::NoGround);
        }
        let mut ground: Vec<f32> = sum
            .iter()
            .zip(&count)
            .map(|(&s, &c)| {
                if c > 0 {
                    (s / c as f64) as f32
                } else {
                    f32::NAN
                }
            })
            .collect();
        crate::geom::grid::fill_holes(&mut ground, size[0], size[1], FILL_STEPS);
        let r = (clearance / cell).ceil() as isize;
        Ok(Site {
            origin: lo,
            cell,
            size,
            ground,
            building: grow(&building, size, r),
            vegetation: grow(&vegetation, size, r),
        })
    }

    /// Cell index of a point, if on the grid.
    pub fn index(&self, x: f32, y: f32) -> Option<usize> {
        let i = ((x - self.origin[0]) / self.cell).floor();
        let j = ((y - self.origin[1]) / self.cell).floor();
        (i >= 0.0 && j >= 0.0 && (i as usize) < self.size[0] && (j as usize) < self.size[1])
            .then(|| j as usize * self.size[0] + i as usize)
    }

    /// Ground height at a point (None off the grid or off the ground).
    pub fn ground_at(&self, x: f32, y: f32) -> Option<f32> {
        self.index(x, y)
            .map(|k| self.ground[k])
            .filter(|g| g.is_finite())
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
