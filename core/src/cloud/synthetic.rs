//! Deterministic synthetic clouds for tests and transport benchmarks.

use super::Cloud;

/// A cloud of `n` points on a gently tilted 100 m × 100 m plane with a
/// repeating label pattern (2 ground, 5 vegetation, 6 building), intensity and
/// building ids. The same `n` always gives the same cloud, so a receiver can
/// check every point it got.
pub fn tilted_plane(n: usize) -> Cloud {
    let side = (n as f64).sqrt().ceil().max(1.0) as usize;
    let step = 100.0 / side as f32;
    let mut xyz = Vec::with_capacity(n);
    let mut intensity = Vec::with_capacity(n);
    let mut label = Vec::with_capacity(n);
    let mut building = Vec::with_capacity(n);
    for i in 0..n {
        let (r, c) = (i / side, i % side);
        let (x, y) = (c as f32 * step, r as f32 * step);
        xyz.push([x, y, 0.05 * x + 0.02 * y]);
        intensity.push((i % 1000) as f32);
        label.push(match i % 3 {
            0 => 2,
            1 => 5,
            _ => 6,
        });
        building.push((i % 17) as u32);
    }
    Cloud {
        xyz,
        intensity: Some(intensity),
        label: Some(label),
        building: Some(building),
        return_number: None,
        number_of_returns: None,
        origin: [0.0; 3],
        crs: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn synthetic_cloud_is_deterministic_and_valid() {
        let a = tilted_plane(1000);
        assert_eq!(a.len(), 1000);
        assert_eq!(a, tilted_plane(1000));
        assert!(a.validate().is_ok());
        let (lo, hi) = a.bounds().unwrap();
        assert!(lo[0] >= 0.0 && hi[0] <= 100.0 && hi[2] > lo[2]);
    }
}
