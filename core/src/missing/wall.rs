//! Where the wall is near a boundary point: its direction from the band's
//! points, and whether there is a wall down to the ground at all.

use geo::{Contains, MultiPolygon, Point};

use super::band::BandIndex;
use super::coverage::{FACE_DEPTH, Strip};
use super::ground::GroundGrid;

/// Depths inside q_n (along s→q) probed for observed ground, metres: beyond
/// the outline's up-to-a-cell offset from the wall, so the ground at the
/// wall's foot does not count.
const OPEN_DEPTHS: [f64; 3] = [1.25, 1.625, 2.0];
/// Fewest band points near q that can fix the wall's direction.
const MIN_FIT_POINTS: usize = 8;
/// Largest minor/major variance ratio of points that trace one wall line.
const LINE_RATIO: f64 = 0.1;
/// Least probes inside the contour that saw ground for the base to be open.
const OPEN_MIN_SEEN: usize = 2;

/// Normal of the wall the band's points near q trace (their principal
/// line in xy), signed like `dir`; None when they are too few or not a line
/// (a corner, a roof).
pub fn wall_normal(
    index: &BandIndex,
    band: usize,
    q: [f64; 2],
    dir: [f64; 2],
    r: f64,
) -> Option<[f64; 2]> {
    let (mut n, mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0usize, 0.0, 0.0, 0.0, 0.0, 0.0);
    index.for_each_near(band, q, r, |p| {
        let (x, y) = (p[0] as f64 - q[0], p[1] as f64 - q[1]);
        if x * x + y * y > r * r {
            return;
        }
        n += 1;
        sx += x;
        sy += y;
        sxx += x * x;
        syy += y * y;
        sxy += x * y;
    });
    if n < MIN_FIT_POINTS {
        return None;
    }
    let m = n as f64;
    let (cxx, cyy, cxy) = (
        sxx / m - (sx / m).powi(2),
        syy / m - (sy / m).powi(2),
        sxy / m - sx / m * sy / m,
    );
    let half_tr = 0.5 * (cxx + cyy);
    let disc = (0.25 * (cxx - cyy).powi(2) + cxy * cxy).sqrt();
    let (big, small) = (half_tr + disc, half_tr - disc);
    if big.is_nan() || big <= 0.0 || small / big > LINE_RATIO {
        return None;
    }
    // Eigenvector of the small eigenvalue.
    let v = if cxy.abs() > 1e-12 {
        [small - cyy, cxy]
    } else if cxx < cyy {
        [1.0, 0.0]
    } else {
        [0.0, 1.0]
    };
    let len = v[0].hypot(v[1]);
    if len.is_nan() || len <= 0.0 {
        return None;
    }
    let mut nrm = [v[0] / len, v[1] / len];
    if nrm[0] * dir[0] + nrm[1] * dir[1] < 0.0 {
        nrm = [-nrm[0], -nrm[1]];
    }
    Some(nrm)
}

/// Whether ground was observed inside `contour` behind q (along -dir,
/// across ±δ/2): the outline there overhangs open ground.
pub fn open_below(
    terrain: &GroundGrid,
    contour: &MultiPolygon<f64>,
    q: [f64; 2],
    dir: [f64; 2],
    delta: f64,
) -> bool {
    let t = [-dir[1], dir[0]];
    let mut seen = 0;
    for d in OPEN_DEPTHS {
        for u in [-0.5 * delta, 0.0, 0.5 * delta] {
            let p = [q[0] - dir[0] * d + t[0] * u, q[1] - dir[1] * d + t[1] * u];
            if terrain.seen(p[0], p[1]) && contour.contains(&Point::new(p[0], p[1])) {
                seen += 1;
                if seen >= OPEN_MIN_SEEN {
                    return true;
                }
            }
        }
    }
    false
}

/// Whether the outline's own face (within [`FACE_DEPTH`] behind q, up to
/// `outside` beyond it, across ±δ of the strip) has points in a band below
/// the strip's: the wall is seen to reach further down, so the strip's band
/// is no open ground floor, whatever ground is seen behind the outline.
pub fn face_below(index: &BandIndex, s: &Strip) -> bool {
    let reach = FACE_DEPTH.max(s.outside).hypot(s.half_width);
    // Nearest band first: a wall seen at all is usually seen just below.
    (0..s.band).rev().any(|band| {
        let mut found = false;
        index.for_each_near(band, s.q, reach, |p| {
            let (v, u) = s.along_across(*p);
            found |= (-FACE_DEPTH..=s.outside).contains(&v) && u.abs() <= s.half_width;
        });
        found
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::grid::GridFrame;

    /// 20 × 20 one-metre cells from (-5, -5).
    fn frame() -> GridFrame {
        GridFrame::covering([-5.0; 2], [14.5; 2], 1.0, 0)
    }
    use geo::polygon;

    #[test]
    fn wall_direction_from_points_and_open_floor() {
        // a wall along y = 0 (x from 0 to 4), seen from a slanted s→q
        let pts: Vec<[f32; 3]> = (0..40)
            .flat_map(|i| (0..4).map(move |k| [i as f32 * 0.1, 0.0, 0.25 * k as f32]))
            .collect();
        let idx = BandIndex::new(&pts, 0.0, 1.0, 1, frame());
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let n = wall_normal(&idx, 0, [2.0, 0.2], [s, -s], 1.5).unwrap();
        assert!(n[1] < -0.99, "{n:?}");
        // a corner (two walls) is not a line
        let mut corner = pts.clone();
        corner.extend((0..40).map(|j| [0.0, -(j as f32) * 0.1, 0.5]));
        let idx = BandIndex::new(&corner, 0.0, 1.0, 1, frame());
        assert!(wall_normal(&idx, 0, [0.2, 0.2], [s, s], 1.5).is_none());
        // ground seen under a 10 × 10 outline near its edge, at y = 8..10
        let ground: Vec<[f32; 3]> = (0..100)
            .flat_map(|i| (0..40).map(move |j| [i as f32 * 0.1, 6.0 + j as f32 * 0.1, 0.0]))
            .chain((0..20).map(|i| [i as f32, -3.0, 0.0]))
            .collect();
        let t = GroundGrid::from_points(&ground, 2.0, 5).unwrap();
        let c = MultiPolygon(vec![
            polygon![(x: 0.0, y: 0.0), (x: 10.0, y: 0.0), (x: 10.0, y: 10.0), (x: 0.0, y: 10.0)],
        ]);
        assert!(open_below(&t, &c, [5.0, 10.2], [0.0, 1.0], 0.75));
        assert!(!open_below(&t, &c, [5.0, -0.2], [0.0, -1.0], 0.75));
    }

    #[test]
    fn face_seen_in_a_lower_band() {
        // the wall y = 0 (x from 0 to 4) seen in band 0 only; a pillar 1.5 m
        // in from the outline's line, past the wall's end, in band 1
        let mut pts: Vec<[f32; 3]> = (0..40).map(|i| [i as f32 * 0.1, 0.0, 0.5]).collect();
        pts.push([6.0, 1.5, 1.5]);
        let idx = BandIndex::new(&pts, 0.0, 1.0, 3, frame());
        let strip = |band: usize, q: [f64; 2]| Strip {
            q,
            dir: [0.0, -1.0],
            half_width: 0.75,
            near: 2.0,
            outside: 0.5,
            band,
            z: [band as f32, band as f32 + 1.0],
            radius: 0.25,
        };
        assert!(face_below(&idx, &strip(1, [2.0, -0.3])));
        assert!(face_below(&idx, &strip(2, [2.0, -0.3])));
        // not its own band, not past the wall's end, not points set back
        assert!(!face_below(&idx, &strip(0, [2.0, -0.3])));
        assert!(!face_below(&idx, &strip(1, [5.0, -0.3])));
        assert!(!face_below(&idx, &strip(2, [6.0, -0.3])));
        assert!(face_below(&idx, &strip(2, [6.0, 1.2])));
    }
}
