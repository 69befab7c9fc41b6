//! Building models before and after, from above: each model's surface
//! samples coloured by their distance to the true surface, one row per
//! building (before left, after right, each row labelled with its id), the
//! true footprint in black; a title, each column's mean distance, a colour
//! bar in metres, a scale bar in the input's unit and a north arrow.

mod labels;
#[cfg(test)]
mod tests;

use geo::MultiPolygon;

use super::canvas::{Canvas, PlotError};
use super::color::{Rgb, ramp};
use super::furniture::text_scale_for;
use crate::crs::LinearUnit;

const OUTLINE: Rgb = [20, 20, 20];
const FRAME: Rgb = [150, 150, 150];
/// Narrowest picture, as a share of its height: a column of tall
/// buildings still leaves room across for the titles and the colour bar.
const MIN_ASPECT: f64 = 0.6;
/// Plane margin (m) between a panel and its grey frame.
const FRAME_M: f64 = 1.0;

/// One building's two models as error-coloured samples (local frame xy,
/// distance in m) and its true footprint.
#[derive(Debug, Clone)]
pub struct ModelView {
    /// The building's id as the reader finds it elsewhere (footprint or
    /// CityObject id); empty: the row goes unlabelled.
    pub id: String,
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

/// Where the panels go in the plane (m): panel (row, col) spans
/// `origin(row, col) + [0, w] × [0, h]`, rows downwards.
struct Layout {
    w: f64,
    h: f64,
    gap: f64,
    /// Room (m) a row's label takes above its frame.
    label_m: f64,
    rows: usize,
}

impl Layout {
    /// Panels of at least `w` × `h` m, with gaps wide enough that a row's
    /// label fits above it at the text size a `max_px` picture gets.
    fn new(w: f64, h: f64, rows: usize, max_px: u32) -> Self {
        let label_px = (labels::LABEL_ROWS * text_scale_for(max_px, max_px)) as f64;
        let n = rows.max(1) as f64;
        let (mut w, mut gap, mut label_m) = (w, 0.15 * w.max(h) + 4.0, 0.0);
        // The gap sets the scale, the scale the gap the label needs: a few
        // rounds settle it (each needs less than the one before). The span
        // counts a whole gap above the first row where the picture keeps
        // only the label's room, so the scale is if anything larger.
        for _ in 0..8 {
            w = w.max(0.5 * (MIN_ASPECT * n * (h + gap) - gap - 2.0 * FRAME_M));
            let span = (2.0 * w + gap + 4.0 * FRAME_M).max(n * (h + gap) + 2.0 * FRAME_M);
            label_m = label_px * span / f64::from(max_px);
            if gap >= label_m + 2.0 * FRAME_M {
                break;
            }
            gap = label_m + 2.0 * FRAME_M;
        }
        Self {
            w,
            h,
            gap,
            label_m,
            rows,
        }
    }

    fn origin(&self, row: usize, col: usize) -> [f64; 2] {
        [
            col as f64 * (self.w + self.gap),
            -(row as f64) * (self.h + self.gap),
        ]
    }

    /// The plane rectangle the canvas shows: every frame, and room for
    /// the first row's label above it.
    fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let last = self.origin(self.rows.max(1) - 1, 1);
        (
            [-FRAME_M, last[1] - FRAME_M],
            [last[0] + self.w + FRAME_M, self.h + FRAME_M + self.label_m],
        )
    }
}

fn draw_panel(
    c: &mut Canvas,
    at: [f64; 2],
    lay: &Layout,
    v: &ModelView,
    samples: &[([f64; 2], f64)],
    full_scale_m: f64,
) {
    let Some((lo, hi)) = extent(v) else { return };
    let (w, h) = (lay.w, lay.h);
    let frame = [
        [at[0] - FRAME_M, at[1] - FRAME_M],
        [at[0] + w + FRAME_M, at[1] - FRAME_M],
        [at[0] + w + FRAME_M, at[1] + h + FRAME_M],
        [at[0] - FRAME_M, at[1] + h + FRAME_M],
    ];
    c.polyline(&frame, true, 1, FRAME);
    // Centred in its panel: panels are as large as the largest building.
    let off = [
        at[0] + 0.5 * (w - (hi[0] - lo[0])) - lo[0],
        at[1] + 0.5 * (h - (hi[1] - lo[1])) - lo[1],
    ];
    let to = |p: [f64; 2]| [p[0] + off[0], p[1] + off[1]];
    let dot = ((0.12 * c.scale()).round() as i64).clamp(0, 3);
    // The worst last, so a few bad samples show through many good ones.
    let mut s: Vec<&([f64; 2], f64)> = samples.iter().collect();
    s.sort_by(|a, b| a.1.total_cmp(&b.1));
    for (p, d) in s {
        c.dot(to(*p), dot, ramp(d / full_scale_m.max(1e-9)));
    }
    for poly in &v.outline.0 {
        for ring in std::iter::once(poly.exterior()).chain(poly.interiors()) {
            let pts: Vec<[f64; 2]> = ring.0.iter().map(|q| to([q.x, q.y])).collect();
            c.polyline(&pts, true, 1, OUTLINE);
        }
    }
}

/// The picture: `views` as rows, errors coloured from 0 (blue) to
/// `full_scale_m` (red), the map at most `max_px` pixels on its longer
/// side. Above: the title and each column's mean distance; over each row
/// its view's id; below: a colour bar with ticks at 0, ½ and full scale (m)
/// and a scale bar in `unit` (the input's); north arrow top right.
pub fn models_picture(
    views: &[ModelView],
    full_scale_m: f64,
    max_px: u32,
    unit: &LinearUnit,
) -> Result<Canvas, PlotError> {
    // A view with no extent has nothing to show: no row for it.
    let shown: Vec<&ModelView> = views.iter().filter(|v| extent(v).is_some()).collect();
    let sizes: Vec<[f64; 2]> = shown
        .iter()
        .filter_map(|v| extent(v))
        .map(|(lo, hi)| [hi[0] - lo[0], hi[1] - lo[1]])
        .collect();
    let w = sizes.iter().map(|d| d[0]).fold(10.0, f64::max);
    let h = sizes.iter().map(|d| d[1]).fold(10.0, f64::max);
    let lay = Layout::new(w, h, shown.len(), max_px);
    let (lo, hi) = lay.bounds();
    let mut c = Canvas::new(lo, hi, FRAME_M, max_px)?;
    for (row, v) in shown.iter().enumerate() {
        for (col, samples) in [&v.before, &v.after].into_iter().enumerate() {
            draw_panel(&mut c, lay.origin(row, col), &lay, v, samples, full_scale_m);
        }
    }
    labels::furnish(&mut c, &lay, &shown, full_scale_m, unit);
    Ok(c)
}
