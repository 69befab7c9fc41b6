//! The one slope rule: how steep the ground ahead is, measured over a
//! wheelbase. The vehicle stops by it and the ground graph leaves out every
//! edge along which it would stop, so routes avoid the drops instead of
//! driving into them.

/// The length over which the slope ahead is measured, metres (a small
/// robot's wheelbase): with the 20° limit, steps up to 36 cm are climbed
/// (lenient: a city model's surfaces meet with steps of 5–10 cm), a quay
/// wall is not.
pub const INCLINE_BASE_M: f32 = 1.0;

/// The slope, degrees (0–90), of ground rising or falling `dz` over `run` metres.
pub fn incline_deg(dz: f32, run: f32) -> f32 {
    (dz / run.max(1e-6)).atan().abs().to_degrees()
}

/// True when ground sampled every `step` metres along a straight line
/// (`z`; NaN where unknown, which is not judged) rises or falls no more
/// than `max_deg` over any [`INCLINE_BASE_M`] of it, in either direction:
/// what the vehicle checks at every step of the way.
pub fn profile_climbable(z: &[f32], step: f32, max_deg: f32) -> bool {
    let ahead = (INCLINE_BASE_M / step.max(1e-6)).round().max(1.0) as usize;
    let run = ahead as f32 * step;
    z.iter()
        .zip(z.iter().skip(ahead))
        .all(|(&a, &b)| !(a.is_finite() && b.is_finite()) || incline_deg(b - a, run) <= max_deg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kerbs_pass_and_quay_walls_do_not() {
        assert!((incline_deg(1.0, 1.0) - 45.0).abs() < 1e-4);
        assert!((incline_deg(-1.0, 1.0) - 45.0).abs() < 1e-4);
        let flat = vec![0.0f32; 20];
        assert!(profile_climbable(&flat, 0.25, 20.0));
        // A 30 cm kerb (17° over 1 m) and a 3 m drop, in both directions.
        let step = |h: f32| -> Vec<f32> { (0..20).map(|i| if i < 10 { 0.0 } else { h }).collect() };
        assert!(profile_climbable(&step(0.3), 0.25, 20.0));
        assert!(!profile_climbable(&step(3.0), 0.25, 20.0));
        assert!(!profile_climbable(&step(-3.0), 0.25, 20.0));
        // A spike one sample wide is seen too; unknown samples are not judged.
        let mut spike = flat.clone();
        spike[7] = 3.0;
        assert!(!profile_climbable(&spike, 0.25, 20.0));
        spike[7] = f32::NAN;
        assert!(profile_climbable(&spike, 0.25, 20.0));
        // Shorter than the base: nothing to compare.
        assert!(profile_climbable(&[0.0, 5.0], 0.25, 20.0));
    }
}
