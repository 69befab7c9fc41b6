//! Rays and the hits they return.

/// A ray in the scene's local frame.
///
/// `dir` need not be unit length: casters normalize it, so every distance
/// ([`Ray::max_t`], [`Hit::t`]) is in metres along the ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Start point, metres.
    pub origin: [f32; 3],
    /// Direction (any non-zero length).
    pub dir: [f32; 3],
    /// Farthest distance of interest, metres; hits beyond it are ignored.
    pub max_t: f32,
}

impl Ray {
    /// A ray from `origin` along `dir`, looking no farther than `max_t` metres.
    pub fn new(origin: [f32; 3], dir: [f32; 3], max_t: f32) -> Self {
        Self { origin, dir, max_t }
    }

    /// The point `t` metres along the ray (with `dir` normalized); `None` when
    /// `dir` is zero or not finite.
    pub fn at(&self, t: f32) -> Option<[f32; 3]> {
        let d = normalize(self.dir)?;
        Some(std::array::from_fn(|k| self.origin[k] + t * d[k]))
    }
}

/// The closest intersection of a ray with a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Distance from the ray origin, metres.
    pub t: f32,
    /// Index of the triangle hit (into `Scene::triangles`).
    pub triangle: u32,
    /// Index of the object hit (into `Scene::objects`).
    pub object: u32,
    /// Unit geometric normal of the triangle, by its winding (counter-clockwise
    /// seen from the side it points to); it may face away from the ray.
    pub normal: [f32; 3],
}

/// `v / |v|`, or `None` for a zero or non-finite vector.
pub(crate) fn normalize(v: [f32; 3]) -> Option<[f32; 3]> {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (n.is_finite() && n > 0.0).then(|| [v[0] / n, v[1] / n, v[2] / n])
}

/// Cross product.
pub(crate) fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Dot product.
pub(crate) fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a - b`.
pub(crate) fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
