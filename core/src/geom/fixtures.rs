//! Point sets the unit tests of several steps share.

/// Points on an `ni × nj` lattice of spacing `step` from the origin
/// (x = i · step outer, y = j · step inner), at height `z(x, y)`.
pub(crate) fn lattice(
    ni: usize,
    nj: usize,
    step: f32,
    z: impl Fn(f32, f32) -> f32,
) -> Vec<[f32; 3]> {
    (0..ni)
        .flat_map(|i| (0..nj).map(move |j| (i as f32 * step, j as f32 * step)))
        .map(|(x, y)| [x, y, z(x, y)])
        .collect()
}

/// Flat open ground, `ni × nj` points `step` apart from the origin at z = 0,
/// each labelled ground.
pub(crate) fn flat_ground(ni: usize, nj: usize, step: f32) -> (Vec<[f32; 3]>, Vec<u8>) {
    let xyz = lattice(ni, nj, step, |_, _| 0.0);
    let labels = vec![crate::cloud::class::GROUND; xyz.len()];
    (xyz, labels)
}
