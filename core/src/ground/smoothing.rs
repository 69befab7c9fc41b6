//! Slope post-processing: on steep terrain the stiff cloth hangs a little
//! above the ground next to where it touched; pull such particles down.

use std::collections::VecDeque;

use crate::geom::grid::GridFrame;

/// Spreads outward from the fixed particles: a free particle next to a
/// fixed one that hangs less than `threshold` above the surface moves onto
/// it and becomes fixed, and its free neighbours are examined in turn.
pub(crate) fn smooth_slopes(
    lattice: &GridFrame,
    surface: &[f32],
    z: &mut [f32],
    fixed: &mut [bool],
    threshold: f32,
) {
    let mut queue: VecDeque<usize> = (0..z.len())
        .filter(|&k| !fixed[k] && lattice.neighbours(k).any(|n| fixed[n]))
        .collect();
    while let Some(k) = queue.pop_front() {
        if fixed[k] || z[k] - surface[k] >= threshold {
            continue;
        }
        z[k] = surface[k];
        fixed[k] = true;
        queue.extend(lattice.neighbours(k).filter(|&n| !fixed[n]));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pulls_near_particles_down_and_leaves_far_ones() {
        let l = super::super::grid::covering([0.0, 0.0], [4.0, 0.0], 1.0).unwrap();
        let n = l.len();
        let surface: Vec<f32> = (0..n)
            .map(|k| if k % l.nx < 5 { 0.0 } else { -5.0 })
            .collect();
        let mut z = vec![0.2; n];
        let mut fixed = vec![false; n];
        fixed[0] = true;
        z[0] = 0.0;
        smooth_slopes(&l, &surface, &mut z, &mut fixed, 0.3);
        for (k, &f) in fixed.iter().enumerate() {
            assert_eq!(f, k % l.nx < 5, "particle {k}");
        }
    }
}
