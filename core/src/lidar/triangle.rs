//! Watertight ray–triangle intersection (Woop, Benthin, Wald 2013).
//!
//! The ray is sheared so that it runs along +z through the origin; each
//! triangle is then tested with 2D edge functions. Rays through a shared edge
//! or vertex hit at least one of the triangles around it (no leaks through a
//! closed mesh), which a plain Möller–Trumbore test does not guarantee.

/// A ray prepared once for many box and triangle tests.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct PreparedRay {
    /// Origin.
    pub org: [f32; 3],
    /// `1 / dir` per axis; a zero component counts as ±1e-30, so box tests
    /// never see NaN (∞ · 0).
    pub inv: [f32; 3],
    /// 1 where `dir` is negative: which box bound is the near one.
    pub sign: [usize; 3],
    /// Axis permutation `(kx, ky, kz)`, `kz` the dominant axis of `dir`:
    /// `2 kz + 1` when `(kx, ky)` are swapped (`dir[kz] < 0`), else `2 kz`;
    /// traversal code is instantiated once per permutation so vertex
    /// components are read at fixed offsets.
    pub perm: usize,
    /// Shear constants `(-dx/dz, -dy/dz, 1/dz)` in the permuted frame.
    shear: [f32; 3],
}

impl PreparedRay {
    /// Prepares a ray with origin `org` and unit direction `dir`.
    pub fn new(org: [f32; 3], dir: [f32; 3]) -> Self {
        let abs = dir.map(f32::abs);
        let kz = if abs[0] >= abs[1] && abs[0] >= abs[2] {
            0
        } else if abs[1] >= abs[2] {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        let swapped = dir[kz] < 0.0;
        if swapped {
            std::mem::swap(&mut kx, &mut ky);
        }
        let dz = dir[kz];
        Self {
            org,
            inv: dir.map(|d| {
                1.0 / if d.abs() < 1e-30 {
                    1e-30f32.copysign(d)
                } else {
                    d
                }
            }),
            sign: dir.map(|d| usize::from(d.is_sign_negative())),
            perm: 2 * kz + usize::from(swapped),
            shear: [dir[kx] / dz, dir[ky] / dz, 1.0 / dz],
        }
    }
}

/// Calls `f::<KX, KY, KZ>(args)` with the axis permutation a
/// [`PreparedRay`]'s `perm` stands for (the one table of them).
macro_rules! by_perm {
    ($perm:expr, $f:ident($($arg:expr),*)) => {
        match $perm {
            0 => $f::<1, 2, 0>($($arg),*),
            1 => $f::<2, 1, 0>($($arg),*),
            2 => $f::<2, 0, 1>($($arg),*),
            3 => $f::<0, 2, 1>($($arg),*),
            4 => $f::<0, 1, 2>($($arg),*),
            _ => $f::<1, 0, 2>($($arg),*),
        }
    };
}
pub(crate) use by_perm;

/// [`intersect`] with the ray's permutation looked up at run time.
pub(crate) fn intersect_any(ray: &PreparedRay, tri: &[[f32; 3]; 3], t_max: f32) -> Option<f32> {
    by_perm!(ray.perm, intersect(ray, tri, t_max))
}

/// Distance `t` in `(0, t_max)` at which the ray hits triangle `tri`, or
/// `None`; `(KX, KY, KZ)` must be the ray's permutation.
#[inline(always)]
pub(crate) fn intersect<const KX: usize, const KY: usize, const KZ: usize>(
    ray: &PreparedRay,
    tri: &[[f32; 3]; 3],
    t_max: f32,
) -> Option<f32> {
    intersect_rel::<KX, KY, KZ>(ray, &relative(tri, ray.org), t_max)
}

/// The vertices of `tri` relative to `org` (shared by every ray from `org`).
#[inline(always)]
pub(crate) fn relative(tri: &[[f32; 3]; 3], org: [f32; 3]) -> [[f32; 3]; 3] {
    tri.map(|v| [v[0] - org[0], v[1] - org[1], v[2] - org[2]])
}

/// [`intersect`] with the vertices already made relative to the ray's origin
/// ([`relative`]), so rays sharing an origin share that step.
#[inline(always)]
pub(crate) fn intersect_rel<const KX: usize, const KY: usize, const KZ: usize>(
    ray: &PreparedRay,
    rel: &[[f32; 3]; 3],
    t_max: f32,
) -> Option<f32> {
    let (kx, ky, kz) = (KX, KY, KZ);
    let [sx, sy, sz] = ray.shear;
    let [a, b, c] = *rel;
    let (az, bz, cz) = (a[kz], b[kz], c[kz]);
    let (ax, ay) = (a[kx] - sx * az, a[ky] - sy * az);
    let (bx, by) = (b[kx] - sx * bz, b[ky] - sy * bz);
    let (cx, cy) = (c[kx] - sx * cz, c[ky] - sy * cz);
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        // On an edge in single precision: decide exactly enough in double.
        let e = |px: f32, py: f32, qx: f32, qy: f32| {
            (f64::from(px) * f64::from(qy) - f64::from(py) * f64::from(qx)) as f32
        };
        u = e(cx, cy, bx, by);
        v = e(ax, ay, cx, cy);
        w = e(bx, by, ax, ay);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let tt = u * (sz * az) + v * (sz * bz) + w * (sz * cz);
    let inside = if det > 0.0 {
        tt > 0.0 && tt < t_max * det
    } else {
        tt < 0.0 && tt > t_max * det
    };
    inside.then(|| tt / det)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: [f32; 3], d: [f32; 3]) -> PreparedRay {
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        PreparedRay::new(o, d.map(|x| x / n))
    }

    const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

    #[test]
    fn hits_inside_from_both_sides() {
        let t = intersect_any(&ray([0.2, 0.2, 5.0], [0.0, 0.0, -1.0]), &TRI, 100.0);
        assert!((t.unwrap_or(0.0) - 5.0).abs() < 1e-6);
        let t = intersect_any(&ray([0.2, 0.2, -2.0], [0.0, 0.0, 1.0]), &TRI, 100.0);
        assert!((t.unwrap_or(0.0) - 2.0).abs() < 1e-6);
    }

    #[test]
    fn misses_outside_behind_and_beyond_range() {
        assert!(intersect_any(&ray([0.8, 0.8, 5.0], [0.0, 0.0, -1.0]), &TRI, 100.0).is_none());
        assert!(intersect_any(&ray([0.2, 0.2, 5.0], [0.0, 0.0, 1.0]), &TRI, 100.0).is_none());
        assert!(intersect_any(&ray([0.2, 0.2, 5.0], [0.0, 0.0, -1.0]), &TRI, 4.0).is_none());
        // Parallel to the plane.
        assert!(intersect_any(&ray([0.2, 0.2, 0.0], [1.0, 0.0, 0.0]), &TRI, 100.0).is_none());
    }

    #[test]
    fn shared_edge_is_hit_by_one_of_two_triangles() {
        // Two triangles tile the unit square; rays through points on and right
        // next to the diagonal must hit one of them.
        let other = [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        for i in 1..1000 {
            let s = i as f32 / 1000.0;
            for dy in [-1e-7f32, 0.0, 1e-7] {
                let p = [s, 1.0 - s + dy, 0.0];
                for d in [[0.0, 0.0, -1.0], [0.3, -0.2, -1.0], [-0.7, 0.1, -0.5]] {
                    let o = [p[0] - 3.0 * d[0], p[1] - 3.0 * d[1], p[2] - 3.0 * d[2]];
                    let r = ray(o, d);
                    let hit = intersect_any(&r, &TRI, 100.0).or(intersect_any(&r, &other, 100.0));
                    assert!(hit.is_some(), "leak at {p:?} along {d:?}");
                }
            }
        }
    }
}
