use geo::{LineString, Polygon};

use super::labels::{BAR_ROWS, BAR_Y, CAPTION, HEAD_ROWS, TICK_Y, TITLE, head, ticks};
use super::*;
use crate::plot::color::WHITE;
use crate::plot::font::{GLYPH_H, MISSING_GLYPH, glyph, text_width};
use crate::plot::furniture::nice_length;

const INK: Rgb = [0, 0, 0];

fn rect(w: f64, h: f64) -> MultiPolygon<f64> {
    let ring = vec![(0.0, 0.0), (w, 0.0), (w, h), (0.0, h), (0.0, 0.0)];
    MultiPolygon::new(vec![Polygon::new(LineString::from(ring), vec![])])
}

fn view(id: &str, before: f64, after: f64) -> ModelView {
    let grid = |d: f64| {
        (0..20)
            .flat_map(|i| (0..10).map(move |j| ([f64::from(i), f64::from(j)], d)))
            .collect()
    };
    ModelView {
        id: id.to_string(),
        before: grid(before),
        after: grid(after),
        outline: rect(20.0, 10.0),
    }
}

/// Ink pixels in the pixel box `x0..x1` × `y0..y1`.
fn ink(c: &Canvas, x: (i64, i64), y: (i64, i64)) -> usize {
    let cells = (x.0.max(0)..x.1).flat_map(|col| (y.0.max(0)..y.1).map(move |row| (col, row)));
    cells
        .filter(|&(col, row)| {
            let p = |v: i64| u32::try_from(v).unwrap_or(u32::MAX);
            c.pixel(p(col), p(row)) == Some(INK)
        })
        .count()
}

#[test]
fn errors_are_coloured_and_outline_drawn() {
    let v = ModelView {
        before: vec![([5.0, 5.0], 1.0)],
        after: vec![([5.0, 5.0], 0.0)],
        ..view("", 0.0, 0.0)
    };
    let c = models_picture(&[v], 0.5, 400, &LinearUnit::Metre).unwrap();
    let (w, h) = c.map_size();
    let find = |col: Rgb| (0..w).any(|x| (0..h).any(|y| c.pixel(x, y + c.map_top()) == Some(col)));
    assert!(find(ramp(1.0)) && find(ramp(0.0)) && find(OUTLINE));
    assert!(c.size().1 > h, "bands added for the words");
    assert!(models_picture(&[], 0.5, 1, &LinearUnit::Metre).is_err());
}

#[test]
fn every_word_drawn_has_a_glyph() {
    let v = view("building_01_gable (id 1)", 0.4, 0.05);
    let words = [TITLE, CAPTION, &head(&[&v], 0), &head(&[&v], 1), &v.id]
        .map(str::to_string)
        .into_iter()
        .chain(ticks(0.5));
    for w in words {
        for ch in w.chars().filter(|ch| *ch != ' ') {
            assert_ne!(glyph(ch), MISSING_GLYPH, "{ch:?} in {w:?}");
        }
    }
    assert_eq!(head(&[&v], 0), "before: mean 0.40 m");
    assert_eq!(head(&[&v], 1), "after: mean 0.05 m");
    assert_eq!(ticks(0.5), ["0 m", "0.25 m", "≥ 0.5 m"].map(String::from));
}

#[test]
fn title_heads_and_colour_bar_ticks_carry_text() {
    let c = models_picture(&[view("a", 0.4, 0.1)], 0.5, 800, &LinearUnit::Metre).unwrap();
    let s = c.text_scale();
    let (w, _) = c.size();
    let (w, top) = (i64::from(w), i64::from(c.map_top()));
    // Title: left half of the band furniture put above the heads.
    assert!(ink(&c, (0, w / 2), (0, top - HEAD_ROWS * s)) > 50, "title");
    // A head over each column.
    let heads = (top - HEAD_ROWS * s, top);
    assert!(ink(&c, (0, w / 2), heads) > 30, "head before");
    assert!(ink(&c, (w / 2, w), heads) > 30, "head after");
    // The bar: its row's coloured run, ramp(0) to ramp(1), ticks at its ends and middle.
    let y = top + i64::from(c.map_size().1);
    let row = u32::try_from(y + BAR_Y * s + 1).unwrap();
    let run: Vec<i64> = (0..w)
        .filter(|&x| {
            c.pixel(u32::try_from(x).unwrap(), row)
                .is_some_and(|p| p != WHITE)
        })
        .collect();
    let (a, b) = (run[0], *run.last().unwrap());
    assert!(b - a > 100, "bar {a}..{b}");
    let near = |x: i64, want: Rgb| {
        let got = c.pixel(u32::try_from(x).unwrap(), row).unwrap();
        (0..3).all(|k| got[k].abs_diff(want[k]) <= 12)
    };
    assert!(
        near(a + 2 * s, ramp(0.0)) && near(b - 2 * s, ramp(1.0)),
        "bar runs 0 to full scale"
    );
    let labels = (y + TICK_Y * s, y + (TICK_Y + GLYPH_H) * s);
    for tick in [a, (a + b) / 2, b] {
        assert!(
            ink(&c, (tick - 6 * s, tick + 6 * s), labels) > 5,
            "label under tick at {tick}"
        );
    }
    assert!(
        ink(&c, (0, w), (y + BAR_ROWS * s - 2 * s, y + BAR_ROWS * s)) == 0,
        "band ends blank"
    );
}

#[test]
fn scale_bar_measures_its_label_in_the_input_unit() {
    for unit in [LinearUnit::Metre, LinearUnit::Foot] {
        let c =
            models_picture(&[view("a", 0.4, 0.1), view("b", 0.2, 0.1)], 0.5, 900, &unit).unwrap();
        let s = c.text_scale();
        let (w, h) = c.size();
        // Furniture's bar: black end to end along its bottom row.
        let y0 = i64::from(h) - 14 * s;
        let row = u32::try_from(y0 + 2 * s).unwrap();
        let first = (0..w).find(|&x| c.pixel(x, row) == Some(INK)).unwrap();
        let last = (first..w)
            .take_while(|&x| c.pixel(x, row) == Some(INK))
            .last()
            .unwrap();
        let bar = f64::from(last - first + 1) - s as f64;
        let px_per_unit = c.scale() * unit.to_metre();
        let length = nice_length(f64::from(w) * 0.2 / px_per_unit);
        assert!(
            (bar - length * px_per_unit).abs() <= 1.5,
            "{unit}: {bar} px for {length}"
        );
        // Its label right of it.
        let x = i64::from(last) + 2 * s;
        assert!(
            ink(
                &c,
                (x, x + text_width("10 ft", s)),
                (y0 - 2 * s, y0 + 5 * s)
            ) > 10,
            "{unit}: label"
        );
        // North arrow: furniture's "N" top right.
        let n = i64::from(w) - 12 * s;
        assert!(ink(&c, (n - 4 * s, n + 4 * s), (4 * s, 11 * s)) > 5, "N");
    }
}

#[test]
fn rows_carry_their_ids_and_a_view_without_one_still_draws() {
    let views = [view("building_07", 0.4, 0.1), view("", 0.3, 0.2)];
    let c = models_picture(&views, 0.5, 800, &LinearUnit::Metre).unwrap();
    let s = c.text_scale();
    let lay = Layout::new(20.0, 10.0, 2, 800);
    let label = |row: usize, id: &str| {
        let o = lay.origin(row, 0);
        let [x, y] = c
            .to_px([o[0] - FRAME_M, o[1] + lay.h + FRAME_M])
            .map(|v| v.round() as i64);
        let w = text_width(id, s);
        // Ink in at least every third column of the label's box.
        let cols = (x..x + w)
            .filter(|&col| ink(&c, (col, col + 1), (y - (GLYPH_H + 3) * s, y - 3 * s)) > 0)
            .count();
        (cols, w)
    };
    let (cols, w) = label(0, "building_07");
    assert!(cols as i64 * 3 >= w, "id drawn: {cols} of {w} columns");
    assert_eq!(label(1, "building_07").0, 0, "no id, no label");
    // The unlabelled row is drawn all the same.
    let o = lay.origin(1, 1);
    let [x, y] = c.to_px([o[0] + 0.5 * lay.w, o[1] + 0.5 * lay.h]);
    assert_eq!(c.pixel(x as u32, y as u32), Some(ramp(0.4)));
}

/// Not a check: writes `models_sample.png` to the temporary directory for
/// a person to look at (`cargo test -p skyground-core --lib sample -- --ignored`).
#[test]
#[ignore]
fn sample_picture_to_look_at() {
    // Errors that vary across a building (a pseudo-random spread, worse eastwards).
    let noisy = |v: ModelView, seed: u32| {
        let spread = |s: &[([f64; 2], f64)]| -> Vec<([f64; 2], f64)> {
            let mut k = seed;
            s.iter()
                .map(|&(p, d)| {
                    k = k.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                    let n = f64::from((k >> 16) & 0xff) / 255.0;
                    (p, d * (0.3 + 1.4 * n) * (1.0 + p[0] / 20.0))
                })
                .collect()
        };
        ModelView {
            before: spread(&v.before),
            after: spread(&v.after),
            ..v
        }
    };
    let views = [
        noisy(view("building_01_gable (id 1)", 0.35, 0.06), 1),
        noisy(view("building_02_l (id 2)", 0.25, 0.08), 2),
        noisy(view("", 0.3, 0.1), 3),
    ];
    let c = models_picture(&views, 0.5, 1800, &LinearUnit::Metre).unwrap();
    c.save(&std::env::temp_dir().join("models_sample.png"))
        .unwrap();
}
