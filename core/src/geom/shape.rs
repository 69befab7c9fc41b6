//! Shape of one neighbourhood from the eigenvalues of its covariance:
//! how line-, plane- or volume-like it is and which way its normal points.

use std::num::NonZeroUsize;

use kiddo::{ImmutableKdTree, SquaredEuclidean};

use super::eigen::sym3_eigen;

/// The moments relative to `p` of its `k` nearest points of `xyz` (indexed by
/// `tree`); `each` is given every one's index and squared distance, nearest first.
pub fn nearest_moments(
    tree: &ImmutableKdTree<f32, 3>,
    xyz: &[[f32; 3]],
    p: [f32; 3],
    k: NonZeroUsize,
    mut each: impl FnMut(usize, f32),
) -> Moments {
    let near = tree
        .query(&p)
        .nearest_n::<SquaredEuclidean<f32>>(k)
        .execute();
    let mut m = Moments::default();
    for nb in &near {
        let q = xyz[nb.item as usize];
        m.add(std::array::from_fn(|i| f64::from(q[i]) - f64::from(p[i])));
        each(nb.item as usize, nb.distance);
    }
    m
}

/// Running sums of a neighbourhood (coordinates relative to an anchor, so
/// f64 sums stay accurate far from the origin).
#[derive(Debug, Clone, Copy, Default)]
pub struct Moments {
    n: f64,
    s: [f64; 3],
    ss: [[f64; 3]; 3],
    z_min: f64,
    z_max: f64,
}

impl Moments {
    /// Adds one point, given relative to the anchor.
    pub fn add(&mut self, d: [f64; 3]) {
        if self.n == 0.0 {
            self.z_min = d[2];
            self.z_max = d[2];
        }
        self.n += 1.0;
        for i in 0..3 {
            self.s[i] += d[i];
            for j in i..3 {
                self.ss[i][j] += d[i] * d[j];
            }
        }
        self.z_min = self.z_min.min(d[2]);
        self.z_max = self.z_max.max(d[2]);
    }

    /// Number of points added.
    pub fn count(&self) -> f64 {
        self.n
    }

    /// The shape; all zeros for fewer than 3 points.
    pub fn shape(&self) -> Shape {
        if self.n < 3.0 {
            return Shape::default();
        }
        let m = self.s.map(|v| v / self.n);
        let mut c = [[0.0f64; 3]; 3];
        for i in 0..3 {
            for j in i..3 {
                c[i][j] = self.ss[i][j] / self.n - m[i] * m[j];
                c[j][i] = c[i][j];
            }
        }
        let (l, normal) = sym3_eigen(c);
        let sum = l[0] + l[1] + l[2];
        let mut out = Shape {
            mean: m,
            z_min: self.z_min,
            z_max: self.z_max,
            normal,
            ..Shape::default()
        };
        if sum > 1e-12 && l[0] > 1e-12 {
            out.linearity = (l[0] - l[1]) / l[0];
            out.planarity = (l[1] - l[2]) / l[0];
            out.sphericity = l[2] / l[0];
            out.curvature = l[2] / sum;
            out.spread = l[0].sqrt();
        }
        out
    }
}

/// Eigen-features of a neighbourhood (λ1 ≥ λ2 ≥ λ3).
#[derive(Debug, Clone, Copy, Default)]
pub struct Shape {
    /// (λ1 − λ2) / λ1.
    pub linearity: f64,
    /// (λ2 − λ3) / λ1.
    pub planarity: f64,
    /// λ3 / λ1.
    pub sphericity: f64,
    /// λ3 / (λ1 + λ2 + λ3): change of curvature.
    pub curvature: f64,
    /// √λ1: the neighbourhood's extent along its main axis.
    pub spread: f64,
    /// Unit eigenvector of λ3.
    pub normal: [f64; 3],
    /// Centroid, relative to the anchor.
    pub mean: [f64; 3],
    /// Lowest z, relative to the anchor.
    pub z_min: f64,
    /// Highest z, relative to the anchor.
    pub z_max: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape_of(points: &[[f64; 3]]) -> Shape {
        let mut m = Moments::default();
        points.iter().for_each(|p| m.add(*p));
        m.shape()
    }

    #[test]
    fn plane_line_and_blob() {
        let plane: Vec<[f64; 3]> = (0..100)
            .map(|i| [(i % 10) as f64, (i / 10) as f64, 0.5 * (i % 10) as f64])
            .collect();
        let s = shape_of(&plane);
        assert!(s.planarity > 0.7 && s.curvature < 1e-9, "{s:?}");
        // Normal of the plane z = 0.5 x is ∝ (−0.5, 0, 1).
        let n = s.normal;
        assert!((n[2].abs() - 1.0 / 1.25f64.sqrt()).abs() < 1e-6, "{n:?}");
        assert!(n[1].abs() < 1e-6);
        let line: Vec<[f64; 3]> = (0..50).map(|i| [i as f64, 2.0 * i as f64, 0.0]).collect();
        assert!(shape_of(&line).linearity > 0.99);
        let cube: Vec<[f64; 3]> = (0..27)
            .map(|i| [(i % 3) as f64, ((i / 3) % 3) as f64, (i / 9) as f64])
            .collect();
        let s = shape_of(&cube);
        assert!((s.sphericity - 1.0).abs() < 1e-9 && (s.curvature - 1.0 / 3.0).abs() < 1e-9);
    }

    #[test]
    fn degenerate_is_zero_not_nan() {
        let s = shape_of(&[[1.0, 1.0, 1.0]; 8]);
        assert_eq!(s.linearity, 0.0);
        assert_eq!(s.curvature, 0.0);
        assert!(s.normal.iter().all(|v| v.is_finite()));
        let s = shape_of(&[[0.0; 3], [1.0, 0.0, 0.0]]);
        assert_eq!(s.planarity, 0.0);
    }
}
