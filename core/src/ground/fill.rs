//! Terrain under what the cloth bridged (buildings, dense canopy): the
//! cloth there hangs by its stiffness, sagging between its supports; the
//! terrain is better guessed as the smoothest surface through the
//! particles that touched the ground (Laplace's equation, solved by
//! successive over-relaxation).

use crate::geom::grid::GridFrame;

/// Over-relaxation factor: converges in O(n) sweeps for n-cell gaps.
const OMEGA: f32 = 1.9;
/// The sweeps stop when no height changed more than this, metres.
const SETTLED: f32 = 1e-3;
/// Most sweeps.
const MAX_SWEEPS: usize = 2_000;

/// Replaces the heights of the particles that are not `fixed` by the
/// harmonic interpolation of the fixed ones; without fixed particles the
/// heights are left as they are.
pub(crate) fn fill_bridged(lattice: &GridFrame, z: &mut [f32], fixed: &[bool]) {
    if !fixed.iter().any(|&f| f) {
        return;
    }
    let free: Vec<usize> = (0..z.len()).filter(|&k| !fixed[k]).collect();
    for _ in 0..MAX_SWEEPS {
        let mut change = 0.0f32;
        for &k in &free {
            let (sum, n) = lattice
                .neighbours(k)
                .fold((0.0f32, 0u32), |(s, n), m| (s + z[m], n + 1));
            let target = sum / n.max(1) as f32;
            let step = OMEGA * (target - z[k]);
            z[k] += step;
            change = change.max(step.abs());
        }
        if change < SETTLED {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plane_is_restored_under_a_hole() {
        let l = super::super::grid::covering([0.0, 0.0], [20.0, 20.0], 1.0).unwrap();
        let plane = |k: usize| {
            let p = l.centre(k);
            (0.1 * p[0] - 0.05 * p[1]) as f32
        };
        let mut z: Vec<f32> = (0..l.len()).map(plane).collect();
        let mut fixed = vec![true; l.len()];
        for j in 5..15 {
            for i in 5..15 {
                let k = j * l.nx + i;
                fixed[k] = false;
                z[k] = -30.0;
            }
        }
        fill_bridged(&l, &mut z, &fixed);
        for (k, &got) in z.iter().enumerate() {
            assert!((got - plane(k)).abs() < 0.02, "{k}: {got} vs {}", plane(k));
        }
    }
}
