//! The multirotor's LiDAR: a Livox Mid-360-like sensor cast with the same
//! caster as the ground robot's ([`crate::lidar::scan`]).
//!
//! The Mid-360 sees 360° × −7…52° at 200,000 points per second, 10 frames
//! a second, 0.1–40 m (10 % reflectivity; 70 m at 80 %), ≤ 2 cm range
//! error at 10 m. Its pattern is non-repetitive; here it is 40 evenly
//! spread rings × 500 columns a frame: the same field of view, point rate
//! and range, a regular pattern (a frame covers what the real sensor covers
//! in about one frame; the real one fills the gaps between rings over a
//! few frames). Mounted upside down under the body
//! ([`super::Multirotor::sensor_pose`]), it sees from 7° above the horizon
//! to 52° below: the facades beside the drone and the roofs under it.

use crate::lidar::LidarConfig;

/// The Mid-360-like ring pattern (see the module doc).
pub fn mid360_like() -> LidarConfig {
    LidarConfig {
        beams: 40,
        fov_min_deg: -7.0,
        fov_max_deg: 52.0,
        azimuth_step_deg: 0.72,
        max_range: 40.0,
        min_range: 0.1,
        rate_hz: 10.0,
        range_noise_sigma: 0.02,
        dropout: 0.0,
        seed: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pattern_has_the_mid360s_field_of_view_and_point_rate() {
        let c = mid360_like();
        c.validate().unwrap();
        let rays_per_s = c.beams as f32 * c.columns() as f32 * c.rate_hz;
        assert!((rays_per_s - 200_000.0).abs() < 1.0, "{rays_per_s}");
        assert!((c.elevation(0).to_degrees() + 7.0).abs() < 1e-4);
        assert!((c.elevation(c.beams - 1).to_degrees() - 52.0).abs() < 1e-4);
    }
}
