//! Return intensity: a simple Lambertian model per object kind.

use crate::scene::ObjectKind;

/// Full scale of intensities, as in LAS (16 bit).
pub const INTENSITY_FULL_SCALE: f32 = 65535.0;

/// Diffuse reflectance assumed per object kind at near-infrared.
pub fn reflectance(kind: ObjectKind) -> f32 {
    match kind {
        ObjectKind::Ground => 0.25,
        ObjectKind::Vegetation => 0.5,
        ObjectKind::Building => 0.35,
    }
}

/// Intensity of a return from a surface of `kind` whose unit normal makes
/// cosine `cos_incidence` with the beam (sign ignored): reflectance ×
/// |cos|, scaled to [0, 65535] and rounded (range falloff is left out: the
/// receivers of survey LiDARs compensate for it).
pub fn return_intensity(kind: ObjectKind, cos_incidence: f32) -> f32 {
    (reflectance(kind) * cos_incidence.abs().min(1.0) * INTENSITY_FULL_SCALE).round()
}
