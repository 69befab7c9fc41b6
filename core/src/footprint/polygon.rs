//! Turning raw rings from files into valid polygons: checks per ring, then one
//! boolean union so self-touching or overlapping input comes out valid.

use geo::algorithm::bool_ops::FillRule;
use geo::orient::{Direction, Orient};
use geo::{Area, BooleanOps, Coord, LineString, MultiPolygon, Polygon};

use super::error::RingProblem;

/// A ring from `[x, y]` positions (already in the local frame).
///
/// With `closed_required` (GeoJSON) the last position must equal the first;
/// otherwise the ring is closed implicitly (OBJ faces, CityJSON rings).
pub fn ring(positions: &[[f64; 2]], closed_required: bool) -> Result<LineString<f64>, RingProblem> {
    if positions.iter().flatten().any(|v| !v.is_finite()) {
        return Err(RingProblem::BadPosition);
    }
    if closed_required && positions.len() >= 2 && positions.first() != positions.last() {
        return Err(RingProblem::NotClosed);
    }
    let mut pts: Vec<Coord<f64>> = Vec::with_capacity(positions.len() + 1);
    for p in positions {
        let c = Coord { x: p[0], y: p[1] };
        if pts.last() != Some(&c) {
            pts.push(c);
        }
    }
    while pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    if pts.len() < 3 {
        return Err(RingProblem::TooFewVertices(pts.len()));
    }
    Ok(LineString::new(pts))
}

/// Unions polygons into one valid multipolygon (exteriors counter-clockwise,
/// holes clockwise); an error when nothing with area is left.
pub fn union_valid(polygons: &[Polygon<f64>]) -> Result<MultiPolygon<f64>, RingProblem> {
    // Non-zero winding keeps both lobes of a self-crossing ring and still
    // cuts holes (oriented against their exterior).
    let oriented: MultiPolygon<f64> = polygons
        .iter()
        .map(|p| p.orient(Direction::Default))
        .collect();
    let u = oriented.union_with_fill_rule(&MultiPolygon::new(vec![]), FillRule::NonZero);
    if u.unsigned_area() > 0.0 {
        Ok(u)
    } else {
        Err(RingProblem::NoArea)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_checks() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]];
        assert_eq!(ring(&sq, true).map(|r| r.0.len()), Ok(4));
        assert_eq!(ring(&sq[..4], true), Err(RingProblem::NotClosed));
        assert_eq!(ring(&sq[..4], false).map(|r| r.0.len()), Ok(4));
        assert_eq!(
            ring(&[[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]], true),
            Err(RingProblem::TooFewVertices(2))
        );
        assert_eq!(
            ring(&[[0.0, f64::NAN], [1.0, 0.0], [1.0, 1.0]], false),
            Err(RingProblem::BadPosition)
        );
    }

    #[test]
    fn bowtie_becomes_valid() {
        // Self-crossing "figure 8": its two lobes have opposite turn.
        let r = ring(&[[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]], false).unwrap();
        let u = union_valid(&[Polygon::new(r, vec![])]).unwrap();
        assert!(u.unsigned_area() > 0.9 && u.unsigned_area() <= 2.0 + 1e-9);
        let line = ring(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]], false).unwrap();
        assert_eq!(
            union_valid(&[Polygon::new(line, vec![])]),
            Err(RingProblem::NoArea)
        );
    }
}
