//! Boundary points q_n: contours sampled at a spacing, each with the outward
//! normal of the contour edge it lies on.

use geo::{LineString, MultiPolygon, Orient, orient::Direction};

/// A contour sample: position and unit outward normal of its edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContourSample {
    /// Position in xy.
    pub xy: [f64; 2],
    /// Outward unit normal.
    pub normal: [f64; 2],
}

/// Samples every ring of `contour` every `spacing` metres (starting half a
/// spacing in, so short rings still get a point). Rings are oriented first
/// (outer counter-clockwise, holes clockwise), so the right-hand normal of
/// every edge points away from the building.
pub fn sample_contour(contour: &MultiPolygon<f64>, spacing: f64) -> Vec<ContourSample> {
    let oriented = contour.orient(Direction::Default);
    let mut out = Vec::new();
    for poly in &oriented.0 {
        for ring in std::iter::once(poly.exterior()).chain(poly.interiors()) {
            sample_ring(ring, spacing, &mut out);
        }
    }
    out
}

fn sample_ring(ring: &LineString<f64>, spacing: f64, out: &mut Vec<ContourSample>) {
    let mut carry = spacing / 2.0;
    for w in ring.0.windows(2) {
        let (a, b) = (w[0], w[1]);
        let d = [b.x - a.x, b.y - a.y];
        let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if !(len.is_finite() && len > 0.0) {
            continue;
        }
        let normal = [d[1] / len, -d[0] / len];
        let mut t = carry;
        while t < len {
            out.push(ContourSample {
                xy: [a.x + d[0] * t / len, a.y + d[1] * t / len],
                normal,
            });
            t += spacing;
        }
        carry = t - len;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geo::{Polygon, polygon};

    #[test]
    fn square_samples_point_outward() {
        // clockwise input: orientation must be fixed before taking normals
        let sq: Polygon<f64> =
            polygon![(x: 0.0, y: 0.0), (x: 0.0, y: 10.0), (x: 10.0, y: 10.0), (x: 10.0, y: 0.0)];
        let s = sample_contour(&MultiPolygon(vec![sq]), 1.0);
        assert_eq!(s.len(), 40);
        for c in s {
            let out = [c.xy[0] + c.normal[0], c.xy[1] + c.normal[1]];
            let inside = (0.0..=10.0).contains(&out[0]) && (0.0..=10.0).contains(&out[1]);
            assert!(!inside, "{c:?}");
        }
    }
}
