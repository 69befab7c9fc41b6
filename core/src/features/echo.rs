//! Echo features: how many returns a point's pulse gave, where the point sat
//! among them, and how common multiple returns are around it.
//!
//! A pulse that meets a canopy splits into several returns; one that meets
//! a roof gives one (two at an edge). Real airborne surveys record this in
//! every LAS point, and it is the strongest cue that tells trees from
//! buildings at any density. A cloud without echo information gets
//! [`UNKNOWN`] in every echo column, so one model serves both.

/// The value of every echo feature when the cloud has no echo information.
pub const UNKNOWN: f32 = -1.0;

/// The two echo columns of a cloud (LAS return number, number of returns).
#[derive(Debug, Clone, Copy)]
pub struct Echoes<'a> {
    /// 1-based return number of each point (0: unknown).
    pub return_number: &'a [u8],
    /// Returns of each point's pulse (0: unknown).
    pub number_of_returns: &'a [u8],
}

impl Echoes<'_> {
    /// True when point `i`'s pulse gave more than one return.
    pub fn is_multiple(&self, i: usize) -> bool {
        self.number_of_returns.get(i).is_some_and(|&n| n > 1)
    }

    /// The per-point echo columns of point `i`: returns of its pulse
    /// (capped at 5), and its place among them (0 first … 1 last; −0.5 for
    /// the only return of its pulse).
    pub fn point(&self, i: usize) -> [f32; 2] {
        let n = self.number_of_returns.get(i).copied().unwrap_or(0);
        let r = self.return_number.get(i).copied().unwrap_or(0);
        match n {
            0 => [UNKNOWN; 2],
            1 => [1.0, -0.5],
            _ => {
                let place = f32::from(r.clamp(1, n) - 1) / f32::from(n - 1);
                [f32::from(n.min(5)), place]
            }
        }
    }
}

/// Points and multiple-return points per voxel, for the neighbourhood shares.
pub fn voxel_counts(of_point: &[u32], voxels: usize, echoes: &Echoes<'_>) -> Vec<[u32; 2]> {
    let mut out = vec![[0u32; 2]; voxels];
    for (i, &v) in of_point.iter().enumerate() {
        if let Some(c) = out.get_mut(v as usize) {
            c[0] += 1;
            c[1] += u32::from(echoes.is_multiple(i));
        }
    }
    out
}

/// Share of multiple-return points in a set of voxels' counts.
pub fn share(points: u32, multiple: u32) -> f32 {
    if points == 0 {
        0.0
    } else {
        multiple as f32 / points as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_columns_place_returns_in_their_pulse() {
        let e = Echoes {
            return_number: &[1, 1, 2, 3, 0],
            number_of_returns: &[1, 3, 3, 3, 0],
        };
        assert_eq!(e.point(0), [1.0, -0.5]);
        assert_eq!(e.point(1), [3.0, 0.0]);
        assert_eq!(e.point(2), [3.0, 0.5]);
        assert_eq!(e.point(3), [3.0, 1.0]);
        assert_eq!(e.point(4), [UNKNOWN; 2]);
        assert!(e.is_multiple(1) && !e.is_multiple(0));
    }

    #[test]
    fn voxel_counts_count_multiple_returns() {
        let e = Echoes {
            return_number: &[1, 1, 2, 1],
            number_of_returns: &[1, 2, 2, 1],
        };
        let c = voxel_counts(&[0, 1, 1, 0], 2, &e);
        assert_eq!(c, vec![[2, 0], [2, 2]]);
        assert_eq!(share(4, 1), 0.25);
        assert_eq!(share(0, 0), 0.0);
    }
}
