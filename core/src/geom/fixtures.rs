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

/// Flat ground 0..40 × 0..20 m (0.25 m apart) with a closed 3 m wall of
/// building points around each `(lower, upper)` corner pair: pens the
/// ground graph cannot drive into.
pub(crate) fn pens(pens: &[([f32; 2], [f32; 2])]) -> (Vec<[f32; 3]>, Vec<u8>) {
    let (mut xyz, mut labels) = flat_ground(160, 80, 0.25);
    for &(lo, hi) in pens {
        let corners = [lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]];
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            for s in 0..=100 {
                let t = s as f32 / 100.0;
                for h in 0..30 {
                    xyz.push([
                        a[0] + t * (b[0] - a[0]),
                        a[1] + t * (b[1] - a[1]),
                        0.1 * h as f32,
                    ]);
                    labels.push(crate::cloud::class::BUILDING);
                }
            }
        }
    }
    (xyz, labels)
}

/// The corners of the unit cube: the bottom 0–3 counter-clockwise from the
/// origin, then the top 4–7 above them.
pub(crate) const UNIT_CUBE: [[f64; 3]; 8] = [
    [0., 0., 0.],
    [1., 0., 0.],
    [1., 1., 0.],
    [0., 1., 0.],
    [0., 0., 1.],
    [1., 0., 1.],
    [1., 1., 1.],
    [0., 1., 1.],
];

/// The six faces of a box numbered as [`UNIT_CUBE`], each counter-clockwise
/// seen from outside.
pub(crate) const BOX_FACES: [[usize; 4]; 6] = [
    [0, 3, 2, 1],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

/// The aerial prior of a 10 m cube at 20..30 × 20..30 m on 0..60 m of open
/// ground: points 0.5 m apart, the roof labelled building, the rest ground.
pub(crate) fn cube_prior() -> crate::cloud::Cloud {
    use crate::cloud::class;
    let xyz = lattice(120, 120, 0.5, |x, y| {
        if on_cube(x + 0.25, y + 0.25) {
            10.0
        } else {
            0.0
        }
    });
    let xyz: Vec<[f32; 3]> = xyz
        .into_iter()
        .map(|[x, y, z]| [x + 0.25, y + 0.25, z])
        .collect();
    let label = xyz
        .iter()
        .map(|p| {
            if on_cube(p[0], p[1]) {
                class::BUILDING
            } else {
                class::GROUND
            }
        })
        .collect();
    let mut c = crate::cloud::Cloud::from_xyz(xyz);
    c.label = Some(label);
    c
}

/// Whether `(x, y)` lies on [`cube_prior`]'s roof.
fn on_cube(x: f32, y: f32) -> bool {
    (20.0..30.0).contains(&x) && (20.0..30.0).contains(&y)
}
