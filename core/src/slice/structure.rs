//! Slice contours clustered into single structures: a component continues
//! the structure below it while it overlaps it and keeps most of its size; a
//! setback (tower on a podium) or a split starts a new structure.

use geo::MultiPolygon;

use super::levels::Level;

/// Slices that make up one structure of a building.
#[derive(Debug, Clone)]
pub struct Structure {
    /// Index of the lowest level of the structure.
    pub base_level: usize,
    /// Index of the highest level.
    pub top_level: usize,
    /// Outline at the base level (the structure's contour).
    pub contour: MultiPolygon<f64>,
    /// Cells of the base outline.
    pub cells: usize,
}

/// Groups the parts of `levels`; returns the structures and, per level, the
/// structure index of each of its parts (same order as `Level::parts`).
/// `keep_ratio` is the least share of the base size a part may have and stay
/// in its structure.
pub fn cluster_structures(levels: &[Level], keep_ratio: f64) -> (Vec<Structure>, Vec<Vec<usize>>) {
    let mut structures: Vec<Structure> = Vec::new();
    let mut assign: Vec<Vec<usize>> = Vec::with_capacity(levels.len());
    for (k, level) in levels.iter().enumerate() {
        let mut mine = Vec::with_capacity(level.parts.len());
        for (label, contour) in &level.parts {
            let size = level.sizes[*label as usize];
            let parent = k.checked_sub(1).and_then(|b| {
                let below = &levels[b];
                let mut part_of = vec![usize::MAX; below.sizes.len()];
                for (p, (bl, _)) in below.parts.iter().enumerate() {
                    part_of[*bl as usize] = p;
                }
                let mut overlap = vec![0usize; below.parts.len()];
                for (cell, &l) in level.labels.iter().enumerate() {
                    if l != *label {
                        continue;
                    }
                    let p = below
                        .labels
                        .get(cell)
                        .and_then(|&u| part_of.get(u as usize));
                    if let Some(&p) = p.filter(|&&p| p != usize::MAX) {
                        overlap[p] += 1;
                    }
                }
                let (best, &n) = overlap.iter().enumerate().max_by_key(|(_, n)| **n)?;
                (n * 2 >= size).then(|| assign[b][best])
            });
            let sid = match parent {
                Some(s) if size as f64 >= keep_ratio * structures[s].cells as f64 => {
                    structures[s].top_level = k;
                    s
                }
                _ => {
                    structures.push(Structure {
                        base_level: k,
                        top_level: k,
                        contour: contour.clone(),
                        cells: size,
                    });
                    structures.len() - 1
                }
            };
            mine.push(sid);
        }
        assign.push(mine);
    }
    (structures, assign)
}

#[cfg(test)]
mod tests {
    use super::super::levels::{SliceParams, slice_building};
    use super::*;

    #[test]
    fn podium_with_two_towers_is_three_structures() {
        let mut pts = crate::geom::fixtures::lattice(160, 80, 0.25, |x, y| {
            let t1 = (4.0..12.0).contains(&x) && (6.0..14.0).contains(&y);
            let t2 = (26.0..36.0).contains(&x) && (6.0..14.0).contains(&y);
            if t1 {
                25.0
            } else if t2 {
                15.0
            } else {
                6.0
            }
        });
        pts.push([0.0, 0.0, 0.0]);
        let s = slice_building(&pts, None, &SliceParams::default()).unwrap();
        let (structures, assign) = cluster_structures(&s.levels, 0.7);
        assert_eq!(structures.len(), 3, "{structures:?}");
        assert_eq!(structures[0].base_level, 0);
        assert_eq!(structures[0].top_level, 6); // the band [6, 7) holds the podium roof
        assert_eq!(assign[20].len(), 1);
        assert_eq!(assign[3].len(), 1);
    }
}
