//! The models picture's words and scales: its title, each column's head
//! with the column's mean distance, each row's id, the colour bar (m), and
//! the shared furniture's scale bar and north arrow.

use super::{FRAME_M, Layout, ModelView};
use crate::crs::LinearUnit;
use crate::plot::canvas::Canvas;
use crate::plot::color::{Rgb, ramp};
use crate::plot::font::{GLYPH_H, GLYPH_W, text_width};

const INK: Rgb = [0, 0, 0];
/// What the picture shows, over it.
pub(super) const TITLE: &str = "Model to true surface distance, before | after";
/// What the colour bar measures.
pub(super) const CAPTION: &str = "distance to the true surface";
/// Font-pixel rows kept above a row of panels for its id.
pub(super) const LABEL_ROWS: i64 = GLYPH_H + 6;
/// Font-pixel rows of the band over the map holding the column heads.
pub(super) const HEAD_ROWS: i64 = GLYPH_H + 8;
/// Font-pixel rows from the colour-bar band's top to the bar.
pub(super) const BAR_Y: i64 = 3 + GLYPH_H + 3;
/// Font-pixel rows of the bar itself.
pub(super) const BAR_H: i64 = 5;
/// Font-pixel rows from the band's top to the tick labels.
pub(super) const TICK_Y: i64 = BAR_Y + BAR_H + 3;
/// Font-pixel rows of the band under the map: caption, bar, tick labels.
pub(super) const BAR_ROWS: i64 = TICK_Y + GLYPH_H + 3;
/// Font pixels at the top right left to the north arrow.
const NORTH_COLS: i64 = 24;

/// `v` with at most three decimals and no trailing zeros.
fn number(v: f64) -> String {
    let t = format!("{v:.3}");
    t.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The head over column `col` (0 before, 1 after): its mean distance.
pub(super) fn head(views: &[&ModelView], col: usize) -> String {
    let name = ["before", "after"][col.min(1)];
    let d: Vec<f64> = views
        .iter()
        .flat_map(|v| if col == 0 { &v.before } else { &v.after })
        .map(|s| s.1)
        .collect();
    if d.is_empty() {
        format!("{name}: no samples")
    } else {
        format!(
            "{name}: mean {:.2} m",
            d.iter().sum::<f64>() / d.len() as f64
        )
    }
}

/// The colour bar's tick labels, at 0, ½ and full scale.
pub(super) fn ticks(full_scale_m: f64) -> [String; 3] {
    [
        "0 m".to_string(),
        format!("{} m", number(0.5 * full_scale_m)),
        // Errors beyond full scale are red as well.
        format!("≥ {} m", number(full_scale_m)),
    ]
}

fn px(v: f64) -> i64 {
    v.round() as i64
}

/// Adds the bands and draws everything but the panels.
pub(super) fn furnish(
    c: &mut Canvas,
    lay: &Layout,
    views: &[&ModelView],
    full_scale_m: f64,
    unit: &LinearUnit,
) {
    let s = c.text_scale();
    let band = |rows: i64| u32::try_from(rows * s).unwrap_or(0);
    c.add_bands(band(HEAD_ROWS), band(BAR_ROWS));
    c.furnish(&[], unit);
    let top = i64::from(c.map_top());
    title(c, top - HEAD_ROWS * s, s);
    for col in 0..2 {
        let t = head(views, col);
        let mid = c.to_px([lay.origin(0, col)[0] + 0.5 * lay.w, 0.0])[0];
        let x = (px(mid) - text_width(&t, s) / 2).max(2 * s);
        c.text_px(x, top - (GLYPH_H + 4) * s, &t, s, INK);
    }
    for (row, v) in views.iter().enumerate() {
        row_label(c, lay, row, &v.id, s);
    }
    colour_bar(c, lay, full_scale_m, s);
}

/// The title, twice the text size where it fits beside the north arrow,
/// centred in the `band` rows furniture left above the column heads.
fn title(c: &mut Canvas, band: i64, s: i64) {
    let room = i64::from(c.size().0) - (NORTH_COLS + 4) * s;
    let ts = if text_width(TITLE, 2 * s) <= room {
        2 * s
    } else {
        s
    };
    c.text_px(4 * s, (band - GLYPH_H * ts) / 2, TITLE, ts, INK);
}

/// `id` just above row `row`'s left frame, cut to the picture's width.
fn row_label(c: &mut Canvas, lay: &Layout, row: usize, id: &str, s: i64) {
    if id.is_empty() {
        return;
    }
    let o = lay.origin(row, 0);
    let [x, y] = c.to_px([o[0] - FRAME_M, o[1] + lay.h + FRAME_M]).map(px);
    let fits = (i64::from(c.size().0) - x - 2 * s) / ((GLYPH_W + 1) * s);
    let n = usize::try_from(fits).unwrap_or(0);
    let text: String = if id.chars().count() > n {
        id.chars()
            .take(n.saturating_sub(2))
            .chain("..".chars())
            .collect()
    } else {
        id.to_string()
    };
    c.text_px(x, y - (GLYPH_H + 3) * s, &text, s, INK);
}

/// The colour bar under the left column, 0 → full scale, its caption
/// above and its ticks' values (m) below.
fn colour_bar(c: &mut Canvas, lay: &Layout, full_scale_m: f64, s: i64) {
    let y = i64::from(c.map_top() + c.map_size().1);
    let x0 = px(c.to_px([-FRAME_M, 0.0])[0]);
    let x1 = px(c.to_px([lay.w + FRAME_M, 0.0])[0]);
    let last = (x1 - x0 - 1).max(1);
    c.text_px(x0, y + 3 * s, CAPTION, s, INK);
    for k in 0..=last {
        c.rect_px(
            x0 + k,
            y + BAR_Y * s,
            1,
            BAR_H * s,
            ramp(k as f64 / last as f64),
        );
    }
    for (i, t) in ticks(full_scale_m).iter().enumerate() {
        let tx = x0 + i as i64 * last / 2;
        c.rect_px(tx - s / 2, y + BAR_Y * s, s.max(1), (BAR_H + 2) * s, INK);
        // The end labels start or end at their tick, inside the bar's width.
        let w = text_width(t, s);
        let lx = [tx, tx - w / 2, tx - w + 1][i];
        c.text_px(lx, y + TICK_Y * s, t, s, INK);
    }
}
