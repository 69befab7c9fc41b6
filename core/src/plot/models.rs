//! Building models before and after, from above: each model's surface
//! samples coloured by their distance to the true surface, one row per
//! building (before left, after right), the true footprint in black, with
//! a colour bar, a scale bar and a north arrow.

use geo::MultiPolygon;

use super::canvas::{Canvas, PlotError};
use super::color::{Rgb, ramp};

const OUTLINE: Rgb = [20, 20, 20];
const FRAME: Rgb = [150, 150, 150];

/// One building's two models as error-coloured samples (local frame xy,
/// distance in m) and its true footprint.
#[derive(Debug, Clone)]
pub struct ModelView {
    /// Samples of the model from the cloud before.
    pub before: Vec<([f64; 2], f64)>,
    /// Samples of the model from the cloud after.
    pub after: Vec<([f64; 2], f64)>,
    /// The true footprint.
    pub outline: MultiPolygon<f64>,
}

fn extent(v: &ModelView) -> Option<([f64; 2], [f64; 2])> {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let outline = v
        .outline
        .0
        .iter()
        .flat_map(|p| p.exterior().0.iter().map(|c| [c.x, c.y]));
    for p in v.before.iter().chain(&v.after).map(|s| s.0).chain(outline) {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo[0] < hi[0] && lo[1] < hi[1]).then_some((lo, hi))
}

/// The picture: `views` as rows, errors coloured from 0 (blue) to
/// `full_scale_m` (red), at most `max_px` pixels on the longer side. The
/// colour bar under the panels runs 0 → `full_scale_m` (ticks at 0, ½, 1);
/// the scale bar is 10 m; north is up (arrow top right).
pub fn models_picture(
    views: &[ModelView],
    full_scale_m: f64,
    max_px: u32,
) -> Result<Canvas, PlotError> {
    let ext: Vec<([f64; 2], [f64; 2])> = views.iter().filter_map(extent).collect();
    let w = ext.iter().map(|e| e.1[0] - e.0[0]).fold(10.0, f64::max);
    let h = ext.iter().map(|e| e.1[1] - e.0[1]).fold(10.0, f64::max);
    let gap = 0.15 * w.max(h) + 4.0;
    let rows = views.len().max(1) as f64;
    let bottom = -(rows - 1.0) * (h + gap) - gap;
    let mut c = Canvas::new([0.0, bottom], [2.0 * w + gap, h + gap * 0.8], 2.0, max_px)?;
    let dot = ((0.12 * c.scale()).round() as i64).clamp(0, 3);
    let mut row = 0.0;
    for v in views {
        let Some((lo, _)) = extent(v) else { continue };
        for (col, samples) in [&v.before, &v.after].into_iter().enumerate() {
            let off = [col as f64 * (w + gap) - lo[0], -row * (h + gap) - lo[1]];
            let at = |p: [f64; 2]| [p[0] + off[0], p[1] + off[1]];
            let (x0, y0) = (col as f64 * (w + gap), -row * (h + gap));
            c.polyline(
                &[
                    [x0 - 1.0, y0 - 1.0],
                    [x0 + w + 1.0, y0 - 1.0],
                    [x0 + w + 1.0, y0 + h + 1.0],
                    [x0 - 1.0, y0 + h + 1.0],
                ],
                true,
                1,
                FRAME,
            );
            let mut s: Vec<&([f64; 2], f64)> = samples.iter().collect();
            s.sort_by(|a, b| a.1.total_cmp(&b.1));
            for (p, d) in s {
                c.dot(at(*p), dot, ramp(d / full_scale_m.max(1e-9)));
            }
            for poly in &v.outline.0 {
                for ring in std::iter::once(poly.exterior()).chain(poly.interiors()) {
                    let pts: Vec<[f64; 2]> = ring.0.iter().map(|q| at([q.x, q.y])).collect();
                    c.polyline(&pts, true, 1, OUTLINE);
                }
            }
        }
        row += 1.0;
    }
    // Colour bar under the left column: 0 → full scale, ticks at 0, ½, 1.
    let y = bottom + gap * 0.35;
    let n = 100;
    for k in 0..n {
        let t = k as f64 / n as f64;
        let x = t * w;
        c.line(
            [x, y],
            [x + w / n as f64, y],
            ((0.25 * gap * c.scale()) as i64).max(3),
            ramp(t),
        );
    }
    for t in [0.0, 0.5, 1.0] {
        c.line([t * w, y - gap * 0.25], [t * w, y + gap * 0.2], 1, OUTLINE);
    }
    // Scale bar: 10 m under the right column.
    let x = w + gap;
    c.line([x, y], [x + 10.0, y], 2, OUTLINE);
    for e in [x, x + 10.0] {
        c.line([e, y - gap * 0.15], [e, y + gap * 0.15], 2, OUTLINE);
    }
    // North arrow, top right.
    let (nx, ny) = (2.0 * w + gap * 0.6, h + gap * 0.1);
    let len = gap * 0.6;
    c.line([nx, ny], [nx, ny + len], 2, OUTLINE);
    c.line(
        [nx - len * 0.25, ny + len * 0.7],
        [nx, ny + len],
        2,
        OUTLINE,
    );
    c.line(
        [nx + len * 0.25, ny + len * 0.7],
        [nx, ny + len],
        2,
        OUTLINE,
    );
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{LineString, Polygon};

    #[test]
    fn errors_are_coloured_and_outline_drawn() {
        let sq = Polygon::new(
            LineString::from(vec![
                (0.0, 0.0),
                (20.0, 0.0),
                (20.0, 10.0),
                (0.0, 10.0),
                (0.0, 0.0),
            ]),
            vec![],
        );
        let v = ModelView {
            before: vec![([5.0, 5.0], 1.0)],
            after: vec![([5.0, 5.0], 0.0)],
            outline: MultiPolygon::new(vec![sq]),
        };
        let c = models_picture(&[v], 0.5, 400).unwrap();
        let find = |col: Rgb| {
            let (w, h) = c.size();
            (0..w).any(|x| (0..h).any(|y| c.pixel(x, y) == Some(col)))
        };
        assert!(find(ramp(1.0)) && find(ramp(0.0)) && find(OUTLINE));
        assert!(models_picture(&[], 0.5, 1).is_err());
    }
}
