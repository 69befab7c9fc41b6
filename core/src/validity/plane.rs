//! A surface's least-squares plane and the 2D frame its rings are drawn in.

use crate::geom::eigen::sym3_eigen;
use crate::scene::vec3::{cross, dot, normalize, sub};

/// A plane through `origin` with unit `normal`, and unit axes `u`, `v` in it
/// such that `u × v = normal` (counter-clockwise in (u, v) turns about the normal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Plane {
    /// The centroid of the fitted points.
    pub origin: [f64; 3],
    /// Unit normal, turned to agree with the outer ring's orientation.
    pub normal: [f64; 3],
    /// First in-plane axis.
    pub u: [f64; 3],
    /// Second in-plane axis.
    pub v: [f64; 3],
}

impl Plane {
    /// The least-squares plane of `points` (PCA), its normal on the side of
    /// `facing` (the outer ring's Newell normal); `None` for fewer than 3 points.
    pub fn fit(points: &[[f64; 3]], facing: [f64; 3]) -> Option<Self> {
        if points.len() < 3 {
            return None;
        }
        let n = points.len() as f64;
        let mut origin = [0.0; 3];
        for p in points {
            for k in 0..3 {
                origin[k] += p[k] / n;
            }
        }
        let mut cov = [[0.0; 3]; 3];
        for p in points {
            let d = sub(*p, origin);
            for i in 0..3 {
                for j in 0..3 {
                    cov[i][j] += d[i] * d[j];
                }
            }
        }
        let (_, mut normal) = sym3_eigen(cov);
        if dot(normal, facing) < 0.0 {
            normal = normal.map(|c| -c);
        }
        // The coordinate axis least along the normal gives a well-conditioned first in-plane axis.
        let a = normal.map(f64::abs);
        let axis = if a[0] <= a[1] && a[0] <= a[2] {
            [1.0, 0.0, 0.0]
        } else if a[1] <= a[2] {
            [0.0, 1.0, 0.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        let u = normalize(cross(normal, axis))?;
        let v = cross(normal, u);
        Some(Self {
            origin,
            normal,
            u,
            v,
        })
    }

    /// Signed distance of `p` from the plane, along the normal.
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        dot(sub(p, self.origin), self.normal)
    }

    /// `p` in the plane's 2D frame.
    pub fn project(&self, p: [f64; 3]) -> [f64; 2] {
        let d = sub(p, self.origin);
        [dot(d, self.u), dot(d, self.v)]
    }
}

/// Newell's normal of a closed ring (length twice its area; zero when degenerate).
pub(super) fn newell(ring: &[[f64; 3]]) -> [f64; 3] {
    let mut n = [0.0; 3];
    let Some(&o) = ring.first() else {
        return n;
    };
    for (i, p) in ring.iter().enumerate() {
        let q = ring[(i + 1) % ring.len()];
        // Relative to the first vertex: map coordinates of 1e5 m would cancel otherwise.
        let (p, q) = (sub(*p, o), sub(q, o));
        n[0] += (p[1] - q[1]) * (p[2] + q[2]);
        n[1] += (p[2] - q[2]) * (p[0] + q[0]);
        n[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    n
}

/// The largest distance of `points` from their least-squares plane, m
/// (`None` for fewer than 3 points): what code 203 holds against `planarity_m`.
pub fn flatness(points: &[[f64; 3]]) -> Option<f64> {
    let plane = Plane::fit(points, [0.0, 0.0, 1.0])?;
    Some(
        points
            .iter()
            .map(|p| plane.distance(*p).abs())
            .fold(0.0, f64::max),
    )
}
