//! Choosing the local frame's origin when a file holds large (projected) coordinates.
//!
//! `Cloud::xyz` is `f32`, which keeps about 1 mm of resolution up to 10 km from
//! the origin. Readers therefore move the origin close to the data, per axis:
//! an axis whose reference value lies within [`SMALL_COORDINATE`] of zero keeps
//! origin 0 (small local clouds stay untouched); otherwise the origin is the
//! reference value floored to whole metres.

/// Coordinates with an absolute value below this (metres) keep origin 0.
pub const SMALL_COORDINATE: f64 = 10_000.0;

/// The origin for data whose lowest (or first) point is `reference`.
///
/// Per axis: 0 when `|reference| < SMALL_COORDINATE` or it is not finite,
/// else `floor(reference)`.
pub fn local_origin(reference: [f64; 3]) -> [f64; 3] {
    reference.map(|r| {
        if !r.is_finite() || r.abs() < SMALL_COORDINATE {
            0.0
        } else {
            r.floor()
        }
    })
}

/// `value - origin` as `f32`, or `None` when the result is not finite.
pub fn to_local(value: f64, origin: f64) -> Option<f32> {
    // The narrowing is the point of the local frame; the check below catches overflow.
    let local = (value - origin) as f32;
    local.is_finite().then_some(local)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_axes_keep_zero_and_large_ones_are_floored() {
        assert_eq!(
            local_origin([637_012.7, -9_999.0, 12.5]),
            [637_012.0, 0.0, 0.0]
        );
        assert_eq!(
            local_origin([-20_000.5, f64::NAN, 1e4]),
            [-20_001.0, 0.0, 1e4]
        );
    }

    #[test]
    fn to_local_rejects_overflow_and_nan() {
        assert_eq!(to_local(637_013.25, 637_000.0), Some(13.25));
        assert_eq!(to_local(1e300, 0.0), None);
        assert_eq!(to_local(f64::NAN, 0.0), None);
    }
}
