//! The cloth: particles falling under gravity (Verlet), held together by
//! vertical springs, stopped where they reach the inverted surface.

use rayon::prelude::*;

use super::params::CsfParams;
use crate::geom::grid::GridFrame;

/// Downward acceleration per unit time², in the units of the paper's time step.
const GRAVITY: f32 = 0.2;
/// Fraction of velocity lost per step.
const DAMPING: f32 = 0.01;
/// Height of the cloth above the highest inverted point at the start, metres.
const START_ABOVE: f32 = 0.5;
/// Rows handed to one rayon task at a time.
const ROWS_PER_TASK: usize = 16;

/// The cloth after the simulation: inverted heights and which particles
/// reached the surface.
#[derive(Debug, Clone)]
pub(crate) struct Cloth {
    pub z: Vec<f32>,
    pub fixed: Vec<bool>,
    pub steps: u32,
}

/// How far a spring moves its particles, as a fraction of their height
/// difference: the closed form of relaxing the spring `rigidness` times,
/// each relaxation halving the gap.
fn spring_shares(rigidness: u8) -> (f32, f32) {
    let closed = 1.0 - 0.5f32.powi(i32::from(rigidness));
    (closed, 0.5 * closed)
}

/// Drops the cloth onto `surface` (one inverted height per particle).
pub(crate) fn simulate(lattice: &GridFrame, surface: &[f32], params: &CsfParams) -> Cloth {
    let top = surface.iter().copied().fold(f32::NEG_INFINITY, f32::max) + START_ABOVE;
    let n = lattice.len();
    let mut z = vec![top; n];
    let mut old = vec![top; n];
    let mut fixed = vec![false; n];
    let fall = GRAVITY * params.time_step * params.time_step;
    let (single, double) = spring_shares(params.rigidness);
    let nx = lattice.nx;
    let mut steps = 0;
    while steps < params.iterations {
        steps += 1;
        z.par_iter_mut()
            .zip(old.par_iter_mut())
            .zip(fixed.par_iter())
            .with_min_len(nx * ROWS_PER_TASK)
            .for_each(|((z, old), &f)| {
                if !f {
                    let next = *z + (*z - *old) * (1.0 - DAMPING) - fall;
                    *old = *z;
                    *z = next;
                }
            });
        relax_rows(&mut z, &fixed, nx, single, double);
        relax_columns(&mut z, &fixed, nx, single, double);
        let moved = z
            .par_iter_mut()
            .zip(old.par_iter())
            .zip(fixed.par_iter_mut())
            .zip(surface.par_iter())
            .with_min_len(nx * ROWS_PER_TASK)
            .map(|(((z, &old), f), &s)| {
                if *f {
                    return 0.0;
                }
                if *z <= s {
                    *z = s;
                    *f = true;
                }
                (*z - old).abs()
            })
            .reduce(|| 0.0, f32::max);
        if moved < params.tolerance {
            break;
        }
    }
    Cloth { z, fixed, steps }
}

/// Moves the two ends of one spring towards each other.
#[inline]
fn relax(a: &mut f32, fa: bool, b: &mut f32, fb: bool, single: f32, double: f32) {
    let gap = *b - *a;
    match (fa, fb) {
        (false, false) => {
            *a += double * gap;
            *b -= double * gap;
        }
        (false, true) => *a += single * gap,
        (true, false) => *b -= single * gap,
        (true, true) => {}
    }
}

/// Springs along x: even springs, then odd ones, so each pass touches
/// disjoint pairs and the result does not depend on the thread count.
fn relax_rows(z: &mut [f32], fixed: &[bool], nx: usize, single: f32, double: f32) {
    z.par_chunks_mut(nx)
        .zip(fixed.par_chunks(nx))
        .with_min_len(ROWS_PER_TASK)
        .for_each(|(row, f)| {
            for start in [0, 1] {
                let mut i = start;
                while i + 1 < row.len() {
                    let (l, r) = row.split_at_mut(i + 1);
                    relax(&mut l[i], f[i], &mut r[0], f[i + 1], single, double);
                    i += 2;
                }
            }
        });
}

/// Springs along y: row pairs (0,1), (2,3), … in parallel, then (1,2), (3,4), ….
fn relax_columns(z: &mut [f32], fixed: &[bool], nx: usize, single: f32, double: f32) {
    for start in [0, 1] {
        let zs = z.get_mut(start * nx..).unwrap_or_default();
        let fs = fixed.get(start * nx..).unwrap_or_default();
        zs.par_chunks_exact_mut(2 * nx)
            .zip(fs.par_chunks_exact(2 * nx))
            .with_min_len(ROWS_PER_TASK / 2)
            .for_each(|(pair, f)| {
                let (lower, upper) = pair.split_at_mut(nx);
                for i in 0..nx {
                    relax(
                        &mut lower[i],
                        f[i],
                        &mut upper[i],
                        f[nx + i],
                        single,
                        double,
                    );
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cloth_settles_on_a_flat_surface() {
        let l = super::super::grid::covering([0.0, 0.0], [20.0, 20.0], 1.0).unwrap();
        let surface = vec![-3.0; l.len()];
        let c = simulate(&l, &surface, &CsfParams::default());
        assert!(c.fixed.iter().all(|&f| f));
        assert!(c.z.iter().all(|&z| (z + 3.0).abs() < 1e-6));
        assert!(c.steps < 100, "{} steps", c.steps);
    }

    #[test]
    fn rigid_cloth_bridges_a_narrow_pit() {
        let l = super::super::grid::covering([0.0, 0.0], [40.0, 40.0], 1.0).unwrap();
        let mut surface = vec![0.0; l.len()];
        for j in 0..l.ny {
            for i in 0..l.nx {
                let p = l.centre(j * l.nx + i);
                if (18.0..22.0).contains(&p[0]) && (18.0..22.0).contains(&p[1]) {
                    surface[j * l.nx + i] = -20.0;
                }
            }
        }
        let c = simulate(&l, &surface, &CsfParams::default());
        let centre = l.clamped_index(20.0, 20.0);
        assert!(c.z[centre] > -1.0, "cloth fell to {}", c.z[centre]);
    }
}
