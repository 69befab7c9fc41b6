//! The LoD 1.2 fallback: a building's footprint extruded from the terrain
//! to the 70th percentile of its points' heights (3DBAG's LoD 1.2 roof
//! height), for buildings whose points hold no roof plane.

use geo::orient::{Direction, Orient};
use geo::{LineString, MultiPolygon};

use super::solid::{ModelFace, Shell, SurfaceType};
use crate::missing::GroundGrid;

/// The heights a prism needs: its base and its flat top, m (local frame).
pub(crate) fn prism_heights(
    xyz: &[[f32; 3]],
    footprint: &MultiPolygon<f64>,
    ground: Option<&GroundGrid>,
) -> Option<(f64, f64)> {
    let mut z: Vec<f64> = xyz
        .iter()
        .map(|p| f64::from(p[2]))
        .filter(|v| v.is_finite())
        .collect();
    if z.is_empty() {
        return None;
    }
    z.sort_by(f64::total_cmp);
    let top = z[(z.len() * 7 / 10).min(z.len() - 1)];
    // The base is the lowest terrain under the outline's vertices; without
    // terrain, the lowest point (a wall's foot when one was scanned).
    let base = ground
        .and_then(|g| {
            footprint
                .0
                .iter()
                .flat_map(|p| p.exterior().coords())
                .filter_map(|c| g.at(c.x, c.y))
                .map(f64::from)
                .reduce(f64::min)
        })
        .unwrap_or(z[0]);
    // A top within 1 m of the base is a roof seen as ground: give the
    // prism a storey so it stays a solid.
    Some((base, top.max(base + 1.0)))
}

/// The closed prism over `footprint` between `base` and `top`: the top as
/// a roof, a wall per outline edge, the base as ground, outward-facing.
pub(crate) fn prism(footprint: &MultiPolygon<f64>, base: f64, top: f64) -> Shell {
    let mut shell = Shell::default();
    for poly in &footprint.0 {
        let poly = poly.orient(Direction::Default);
        let rings: Vec<Vec<[f64; 2]>> = std::iter::once(poly.exterior())
            .chain(poly.interiors())
            .map(open_ring)
            .filter(|r| r.len() >= 3)
            .collect();
        if rings.first().is_none_or(|r| r.len() < 3) {
            continue;
        }
        let mut low: Vec<Vec<u32>> = Vec::new();
        let mut high: Vec<Vec<u32>> = Vec::new();
        for r in &rings {
            let start = shell.vertices.len() as u32;
            let n = r.len() as u32;
            for q in r {
                shell.vertices.push([q[0], q[1], base]);
            }
            for q in r {
                shell.vertices.push([q[0], q[1], top]);
            }
            low.push((start..start + n).rev().collect());
            high.push((start + n..start + 2 * n).collect());
            for k in 0..n {
                let (a, b) = (start + k, start + (k + 1) % n);
                shell.faces.push(ModelFace {
                    kind: SurfaceType::WallSurface,
                    rings: vec![vec![a, b, b + n, a + n]],
                });
            }
        }
        shell.faces.push(ModelFace {
            kind: SurfaceType::RoofSurface,
            rings: high,
        });
        shell.faces.push(ModelFace {
            kind: SurfaceType::GroundSurface,
            rings: low,
        });
    }
    shell
}

/// A ring's vertices without the closing repeat and without consecutive repeats.
/// Footprint vertices nearer than this, m, are merged.
const DUP_M: f64 = 0.002;

fn open_ring(ring: &LineString<f64>) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::new();
    // Footprint vertices this close are one corner to val3dity (code 102
    // after the writers' 1 mm rounding): keep the first.
    let near = |a: &[f64; 2], b: &[f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < DUP_M;
    for c in ring.coords() {
        let q = [c.x, c.y];
        if out.last().is_none_or(|l| !near(l, &q)) {
            out.push(q);
        }
    }
    while out.len() > 1 && near(&out[0], &out[out.len() - 1]) {
        out.pop();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{Polygon, polygon};

    #[test]
    fn a_prism_with_a_courtyard_is_closed_and_faces_outward() {
        let outer =
            polygon![(x: 0.0, y: 0.0), (x: 10.0, y: 0.0), (x: 10.0, y: 8.0), (x: 0.0, y: 8.0)];
        let hole = polygon![(x: 3.0, y: 3.0), (x: 6.0, y: 3.0), (x: 6.0, y: 5.0), (x: 3.0, y: 5.0)];
        let fp = MultiPolygon(vec![Polygon::new(
            outer.exterior().clone(),
            vec![hole.exterior().clone()],
        )]);
        let s = prism(&fp, 1.0, 7.0);
        assert!(s.check().valid(), "{:?}", s.check());
        assert_eq!(s.faces.len(), 4 + 4 + 2);
        // Outward: the signed volume is the footprint's area × height.
        let vol: f64 = s
            .triangles()
            .iter()
            .map(|(t, _)| {
                let [a, b, c] = t;
                (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0]))
                    / 6.0
            })
            .sum();
        assert!((vol - (80.0 - 6.0) * 6.0).abs() < 1e-6, "{vol}");
    }

    #[test]
    fn heights_take_the_seventieth_percentile_and_keep_a_storey() {
        let fp = MultiPolygon(vec![
            polygon![(x: 0.0, y: 0.0), (x: 4.0, y: 0.0), (x: 4.0, y: 4.0)],
        ]);
        let pts: Vec<[f32; 3]> = (0..10).map(|k| [1.0, 1.0, k as f32]).collect();
        assert_eq!(prism_heights(&pts, &fp, None), Some((0.0, 7.0)));
        let flat = [[1.0f32, 1.0, 2.0]];
        assert_eq!(prism_heights(&flat, &fp, None), Some((2.0, 3.0)));
        assert_eq!(prism_heights(&[], &fp, None), None);
    }
}
