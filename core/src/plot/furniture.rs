//! Map furniture every picture carries: a legend, a scale bar in the input's
//! unit and a north arrow (pictures are drawn north-up: +y of the CRS is up).

use super::canvas::Canvas;
use super::color::{Rgb, WHITE};
use super::font::{GLYPH_H, GLYPH_W, glyph, text_width};
use crate::crs::LinearUnit;

const INK: Rgb = [0, 0, 0];
/// Share of the picture's width the scale bar aims at.
const BAR_SHARE: f64 = 0.2;
/// Rows (in font pixels) the north arrow takes at the top.
const NORTH_ROWS: i64 = 42;
/// Rows (in font pixels) of the band below the map that holds the scale bar.
const SCALE_ROWS: i64 = GLYPH_H + 20;
/// Font pixels kept free beside the legend for the north arrow.
const NORTH_COLS: i64 = 24;

/// How the legend's entries are laid out: as many columns as the width
/// left of the north arrow holds, so the band above the map stays low.
struct LegendLayout {
    columns: i64,
    rows: i64,
    column_w: i64,
    height: i64,
}

impl LegendLayout {
    fn new(entries: &[(Rgb, &str)], width: i64, s: i64) -> Self {
        let n = i64::try_from(entries.len()).unwrap_or(i64::MAX).max(1);
        let column_w = entries
            .iter()
            .map(|(_, t)| text_width(t, s))
            .max()
            .unwrap_or(0)
            + GLYPH_H * s
            + 8 * s;
        let room = (width - (NORTH_COLS + 8) * s).max(column_w);
        let columns = (room / column_w).clamp(1, n);
        let rows = (n + columns - 1) / columns;
        let height = if entries.is_empty() {
            0
        } else {
            (GLYPH_H + 4) * s * rows + 2 * s
        };
        Self {
            columns,
            rows,
            column_w,
            height,
        }
    }
}

/// Font pixel size for a map of `w` × `h` pixels (text stays readable on
/// large ones).
pub(super) fn text_scale_for(w: u32, h: u32) -> i64 {
    i64::from((w.min(h) / 400).clamp(1, 4))
}

/// A 1, 2 or 5 × 10^k at most `v` (v > 0).
pub fn nice_length(v: f64) -> f64 {
    let p = 10f64.powf(v.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|l| *l <= v)
        .unwrap_or(p)
}

fn format_length(v: f64) -> String {
    if v >= 1.0 {
        format!("{v:.0}")
    } else {
        format!("{v}")
    }
}

impl Canvas {
    /// Font pixel size for this picture.
    pub(super) fn text_scale(&self) -> i64 {
        let (w, h) = self.map_size();
        text_scale_for(w, h)
    }

    /// A filled pixel rectangle.
    pub fn rect_px(&mut self, x: i64, y: i64, w: i64, h: i64, c: Rgb) {
        for row in y..y + h {
            for col in x..x + w {
                self.put(col, row, c);
            }
        }
    }

    /// `text` with its top-left corner at pixel (x, y).
    pub fn text_px(&mut self, x: i64, y: i64, text: &str, scale: i64, c: Rgb) {
        for (i, ch) in text.chars().enumerate() {
            let gx = x + i as i64 * (GLYPH_W + 1) * scale;
            for (r, bits) in glyph(ch).iter().enumerate() {
                for col in 0..GLYPH_W {
                    if bits & (1 << (GLYPH_W - 1 - col)) != 0 {
                        self.rect_px(gx + col * scale, y + r as i64 * scale, scale, scale, c);
                    }
                }
            }
        }
    }

    /// Legend (top left), north arrow (top right) and scale bar (bottom left)
    /// with lengths in `unit` (the picture itself is in metres), in bands
    /// added above and below the map so they hide none of it.
    pub fn furnish(&mut self, legend: &[(Rgb, &str)], unit: &LinearUnit) {
        self.furnish_view(legend, unit, true);
    }

    /// As [`Self::furnish`], with the north arrow only when `north` (a side
    /// view has no north up; its legend says which way it looks).
    pub fn furnish_view(&mut self, legend: &[(Rgb, &str)], unit: &LinearUnit, north: bool) {
        let s = self.text_scale();
        let layout = LegendLayout::new(legend, i64::from(self.map_size().0), s);
        let top = (layout.height + 8 * s).max(NORTH_ROWS * s);
        let bottom = SCALE_ROWS * s;
        self.add_bands(
            u32::try_from(top).unwrap_or(0),
            u32::try_from(bottom).unwrap_or(0),
        );
        self.legend(legend, &layout, s);
        if north {
            self.north_arrow(s);
        }
        self.scale_bar(unit, s);
    }

    fn legend(&mut self, entries: &[(Rgb, &str)], layout: &LegendLayout, s: i64) {
        if entries.is_empty() {
            return;
        }
        let line = (GLYPH_H + 4) * s;
        let sw = GLYPH_H * s;
        let (x0, y0) = (4 * s, 4 * s);
        let (w, h) = (layout.column_w * layout.columns, layout.height);
        self.rect_px(x0 - s, y0 - s, w + 2 * s, h + 2 * s, INK);
        self.rect_px(x0, y0, w, h, WHITE);
        // Down each column, then the next: it reads as a list.
        for (i, (c, t)) in entries.iter().enumerate() {
            let (col, row) = (i as i64 / layout.rows, i as i64 % layout.rows);
            let x = x0 + col * layout.column_w;
            let y = y0 + 2 * s + row * line;
            self.rect_px(x + 2 * s, y, sw, sw, *c);
            self.text_px(x + 4 * s + sw, y, t, s, INK);
        }
    }

    fn north_arrow(&mut self, s: i64) {
        let (w, _) = self.size();
        let x = i64::from(w) - 12 * s;
        let top = 14 * s;
        let len = 24 * s;
        self.text_px(x - (GLYPH_W * s) / 2, 4 * s, "N", s, INK);
        self.rect_px(x - s / 2, top, s.max(1), len, INK);
        for d in 0..6 * s {
            // The head: a filled triangle widening downwards from the tip.
            self.rect_px(x - d / 2, top + d, d + 1, 1, INK);
        }
    }

    fn scale_bar(&mut self, unit: &LinearUnit, s: i64) {
        let (w, h) = self.size();
        let px_per_unit = self.scale() * unit.to_metre();
        let length = nice_length(f64::from(w) * BAR_SHARE / px_per_unit);
        let bar_px = (length * px_per_unit).round() as i64;
        let (x0, y0) = (6 * s, i64::from(h) - 14 * s);
        let label = format!("{} {}", format_length(length), unit.symbol());
        self.rect_px(
            x0 - 2 * s,
            y0 - (GLYPH_H + 4) * s,
            bar_px + text_width(&label, s) + 8 * s,
            (GLYPH_H + 12) * s,
            WHITE,
        );
        self.rect_px(x0, y0, bar_px, 3 * s, INK);
        for k in [1, 3] {
            // Alternate quarters white inside the black bar, as on a map.
            self.rect_px(x0 + k * bar_px / 4, y0 + s, bar_px / 4, s, WHITE);
        }
        for k in 0..=4 {
            self.rect_px(
                x0 + k * bar_px / 4 - s / 2,
                y0 - 2 * s,
                s.max(1),
                5 * s,
                INK,
            );
        }
        self.text_px(x0, y0 - (GLYPH_H + 3) * s, "0", s, INK);
        self.text_px(x0 + bar_px + 3 * s, y0 - 2 * s, &label, s, INK);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_lengths_are_1_2_5_steps() {
        assert_eq!(nice_length(7.3), 5.0);
        assert_eq!(nice_length(180.0), 100.0);
        assert_eq!(nice_length(0.27), 0.2);
        assert_eq!(nice_length(2.0), 2.0);
    }

    /// The first run of black pixels in row `row` (the bar, before its label).
    fn ink(c: &Canvas, row: u32, from: u32, to: u32) -> Vec<u32> {
        let start = (from..to)
            .find(|&x| c.pixel(x, row) == Some(INK))
            .unwrap_or(to);
        (start..to)
            .take_while(|&x| c.pixel(x, row) == Some(INK))
            .collect()
    }

    #[test]
    fn scale_bar_measures_the_unit_and_legend_and_north_are_drawn() {
        // 1000 m square at 1 px/m: a 200 m bar in metres, 500 ft in feet.
        for (unit, want_px) in [
            (LinearUnit::Metre, 200.0),
            (LinearUnit::Foot, 500.0 * 0.3048),
        ] {
            let mut c = Canvas::new([0.0, 0.0], [1000.0, 1000.0], 0.0, 1000).unwrap();
            c.furnish(&[([255, 0, 0], "missing wall")], &unit);
            let s = c.text_scale();
            let (_, h) = c.size();
            // The bar's bottom row: black end to end (the quarters are white above it).
            let row = u32::try_from(i64::from(h) - 14 * s + 2 * s).unwrap();
            let black = ink(&c, row, 0, 600);
            let (first, last) = (*black.first().unwrap(), *black.last().unwrap());
            let got = f64::from(last - first + 1);
            // The end ticks stick out half their width (s) on each side.
            let bar = got - s as f64;
            assert!(
                (bar - want_px).abs() <= 1.5,
                "{unit}: bar {bar} px, want {want_px}"
            );
            // Legend swatch in red near the top left; north arrow's shaft top right.
            let sw = u32::try_from(4 * s + 2 * s + 1).unwrap();
            assert_eq!(c.pixel(sw, sw), Some([255, 0, 0]));
            let x = u32::try_from(1000 - 12 * s).unwrap();
            let shaft = u32::try_from(14 * s + 20 * s).unwrap();
            assert_eq!(c.pixel(x, shaft), Some(INK));
        }
    }

    #[test]
    fn furniture_hides_nothing_of_the_map() {
        const MAP: Rgb = [0, 128, 255];
        let mut c = Canvas::new([0.0, 0.0], [300.0, 200.0], 0.0, 1200).unwrap();
        let square = [[0.0, 0.0], [300.0, 0.0], [300.0, 200.0], [0.0, 200.0]];
        c.fill(&[&square], MAP, 1.0);
        let entries: Vec<(Rgb, &str)> = (0..8).map(|_| ([255, 0, 0], "an entry")).collect();
        c.furnish(&entries, &LinearUnit::Metre);
        let (w, h) = c.map_size();
        let top = c.map_top();
        assert!(top > 0 && c.size().1 > top + h, "bands above and below");
        let covered = (0..w)
            .flat_map(|x| (top..top + h).map(move |y| (x, y)))
            .filter(|&(x, y)| c.pixel(x, y) != Some(MAP))
            .count();
        assert_eq!(covered, 0, "map pixels covered by furniture");
        // The map's corners still land where the plane's corners are.
        assert_eq!(c.to_px([0.0, 200.0]), [0.0, f64::from(top)]);
        assert_eq!(c.to_px([300.0, 0.0]), [1200.0, f64::from(top + h)]);
        // Eight entries on a 1,200 px map: more than one column, so the
        // band is lower than a one-column legend would make it.
        let s = c.text_scale();
        assert!(i64::from(top) < 8 * (GLYPH_H + 4) * s, "top band {top} px");
    }
}
