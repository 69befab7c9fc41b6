//! The surface to cover: wall samples, optionally with outward normals.

/// Samples of the surface an explorer must see.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SurfaceSamples {
    /// Sample positions, metres.
    pub xyz: Vec<[f32; 3]>,
    /// Outward unit normals, one per sample, or empty when unknown (then
    /// samples count as visible from any side the line of sight allows).
    pub normal: Vec<[f32; 3]>,
}

impl From<Vec<[f32; 3]>> for SurfaceSamples {
    fn from(xyz: Vec<[f32; 3]>) -> Self {
        Self {
            xyz,
            normal: Vec::new(),
        }
    }
}
