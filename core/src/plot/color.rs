//! Colours and the one colour ramp the pictures use.

/// An sRGB colour.
pub type Rgb = [u8; 3];

/// White.
pub const WHITE: Rgb = [255, 255, 255];
/// Building points.
pub(super) const GREY: Rgb = [200, 200, 200];
/// Missing wall points; what is out of reach.
pub(super) const MISSING: Rgb = [220, 30, 30];
/// Ground targets and the route's stops.
pub(super) const TARGET: Rgb = [150, 40, 200];
/// The route.
pub(super) const ROUTE: Rgb = [0, 150, 150];
/// The drone's flight.
pub(super) const FLIGHT: Rgb = [230, 0, 160];

/// Maps `t` in 0..=1 to a blue → green → yellow → red ramp (clamped; NaN is grey).
pub fn ramp(t: f64) -> Rgb {
    if t.is_nan() {
        return [128, 128, 128];
    }
    let t = t.clamp(0.0, 1.0);
    let stops: [(f64, Rgb); 4] = [
        (0.0, [44, 123, 182]),
        (0.35, [171, 221, 164]),
        (0.65, [253, 174, 97]),
        (1.0, [215, 25, 28]),
    ];
    let mut i = 0;
    while i + 2 < stops.len() && t > stops[i + 1].0 {
        i += 1;
    }
    let (t0, a) = stops[i];
    let (t1, b) = stops[i + 1];
    let u = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    let mix = |x: u8, y: u8| (f64::from(x) + (f64::from(y) - f64::from(x)) * u).round() as u8;
    [mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2])]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_ends_and_clamps() {
        assert_eq!(ramp(0.0), [44, 123, 182]);
        assert_eq!(ramp(1.0), [215, 25, 28]);
        assert_eq!(ramp(-3.0), ramp(0.0));
        assert_eq!(ramp(7.0), ramp(1.0));
        assert_eq!(ramp(f64::NAN), [128, 128, 128]);
    }
}
