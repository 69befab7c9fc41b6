//! Choosing the crop window automatically: the square of a given size that
//! holds the most building surface.

use super::{BuildingBox, CropError, Window, box_of, building_boxes};
use crate::scene::Scene;

/// The `size` × `size` window whose kept buildings (box centre inside) have
/// the largest total surface area, centred on those buildings (centre
/// rounded to whole metres when that keeps them all). Ties go to the lowest
/// x, then y.
pub fn busiest_window(scene: &Scene, size: f64) -> Result<Window, CropError> {
    if !(size.is_finite() && size > 0.0) {
        return Err(CropError::InvalidSize { size });
    }
    let boxes = building_boxes(scene);
    if boxes.is_empty() {
        return Err(CropError::NoBuildingsInScene);
    }
    let chosen = best_set(&boxes, size);
    let centres: Vec<[f64; 2]> = chosen.iter().map(|&k| boxes[k].xy.centre()).collect();
    let span = box_of(centres.iter().copied()).ok_or(CropError::NoBuildingsInScene)?;
    let (lo, mid) = (span.min, span.centre());
    let holds_all = |w: &Window| centres.iter().all(|c| w.contains(c[0], c[1]));
    let rounded = Window::square(mid.map(f64::round), size)?;
    if holds_all(&rounded) {
        return Ok(rounded);
    }
    let centred = Window::square(mid, size)?;
    if holds_all(&centred) {
        return Ok(centred);
    }
    // Rounding in the last bit can push an edge building out: the window
    // anchored at the set's lower-left centre holds it by construction.
    Window::new(lo[0], lo[1], lo[0] + size, lo[1] + size)
}

/// Indices of the buildings in the best window anchored at a building
/// centre's x and another's y (an optimal window can always be moved until
/// its left and bottom edges touch a centre).
fn best_set(boxes: &[BuildingBox], size: f64) -> Vec<usize> {
    let centres: Vec<[f64; 2]> = boxes.iter().map(|b| b.xy.centre()).collect();
    let mut by_y: Vec<usize> = (0..boxes.len()).collect();
    by_y.sort_by(|&a, &b| centres[a][1].total_cmp(&centres[b][1]));
    let mut xs: Vec<f64> = centres.iter().map(|c| c[0]).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let mut best: (f64, Vec<usize>) = (f64::NEG_INFINITY, Vec::new());
    for x0 in xs {
        // Buildings in the column [x0, x0 + size], ascending y.
        let column: Vec<usize> = by_y
            .iter()
            .copied()
            .filter(|&k| (x0..=x0 + size).contains(&centres[k][0]))
            .collect();
        let mut end = 0;
        let mut sum = 0.0;
        for start in 0..column.len() {
            let y0 = centres[column[start]][1];
            while end < column.len() && centres[column[end]][1] <= y0 + size {
                sum += boxes[column[end]].area;
                end += 1;
            }
            if sum > best.0 {
                best = (sum, column[start..end].to_vec());
            }
            sum -= boxes[column[start]].area;
        }
    }
    best.1
}
