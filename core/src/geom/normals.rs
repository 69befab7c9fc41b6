//! Per-point normals and neighbour lists (PCA of the k nearest neighbours).

use std::num::NonZeroUsize;

use kiddo::ImmutableKdTree;
use rayon::prelude::*;

use super::shape::nearest_moments;

/// Normals (unit, z ≥ 0), curvature and the k nearest neighbours of points.
pub(crate) struct Neighbourhoods {
    /// Unit normal per point, turned upward (n_z ≥ 0).
    pub normal: Vec<[f64; 3]>,
    /// λ3 / (λ1 + λ2 + λ3) per point: 0 on a plane.
    pub curvature: Vec<f64>,
    /// `k` neighbour indices per point (the point itself left out).
    pub knn: Vec<u32>,
    /// Neighbours per point in `knn`.
    pub k: usize,
}

impl Neighbourhoods {
    /// The neighbours of point `i`.
    pub fn of(&self, i: usize) -> &[u32] {
        &self.knn[i * self.k..(i + 1) * self.k]
    }
}

/// Computes neighbourhoods of `xyz` with `k` neighbours (fewer points than
/// `k + 1` give empty lists).
pub(crate) fn neighbourhoods(xyz: &[[f32; 3]], k: usize) -> Neighbourhoods {
    let n = xyz.len();
    if n <= k {
        return Neighbourhoods {
            normal: vec![[0.0, 0.0, 1.0]; n],
            curvature: vec![1.0; n],
            knn: Vec::new(),
            k: 0,
        };
    }
    let tree = match ImmutableKdTree::<f32, 3>::new_from_slice(xyz) {
        Ok(t) => t,
        Err(_) => {
            return Neighbourhoods {
                normal: vec![[0.0, 0.0, 1.0]; n],
                curvature: vec![1.0; n],
                knn: Vec::new(),
                k: 0,
            };
        }
    };
    let kk = NonZeroUsize::new(k + 1).unwrap_or(NonZeroUsize::MIN);
    let rows: Vec<([f64; 3], f64, Vec<u32>)> = (0..n)
        .into_par_iter()
        .map(|i| {
            let p = xyz[i];
            let mut ids = Vec::with_capacity(k);
            let m = nearest_moments(&tree, xyz, p, kk, |j, _| {
                if j != i && ids.len() < k {
                    ids.push(j as u32);
                }
            });
            while ids.len() < k {
                ids.push(i as u32);
            }
            let s = m.shape();
            let mut nrm = s.normal;
            if nrm[2] < 0.0 {
                nrm = nrm.map(|v| -v);
            }
            (nrm, s.curvature, ids)
        })
        .collect();
    let mut out = Neighbourhoods {
        normal: Vec::with_capacity(n),
        curvature: Vec::with_capacity(n),
        knn: Vec::with_capacity(n * k),
        k,
    };
    for (nrm, c, ids) in rows {
        out.normal.push(nrm);
        out.curvature.push(c);
        out.knn.extend(ids);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_normals_point_up_and_walls_sideways() {
        // A roof sloping 0.5 along x (points 0..900) and a wall at x = 50 (900..1800).
        let lattice = |z: fn(f32, f32) -> f32| crate::geom::fixtures::lattice(30, 30, 0.3, z);
        let mut pts = lattice(|x, _| 10.0 + 0.5 * x);
        pts.extend(lattice(|_, _| 0.0).iter().map(|p| [50.0, p[0], p[1]]));
        let nb = neighbourhoods(&pts, 10);
        let roof = nb.normal[0];
        assert!((roof[2] - 1.0 / 1.25f64.sqrt()).abs() < 1e-3, "{roof:?}");
        assert!(nb.normal[900][2].abs() < 1e-3 && nb.normal[900][0].abs() > 0.999);
        assert!(nb.of(0).iter().all(|&j| j < 900));
        assert_eq!(neighbourhoods(&pts[..5], 10).k, 0);
    }
}
