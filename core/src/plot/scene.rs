//! Top views of the method's results: detection (contours, skeletons,
//! collected and missing boundary points, targets) and a whole mission.

use geo::MultiPolygon;

use super::canvas::{Canvas, PlotError};
use super::color::{Rgb, ramp};
use crate::crs::LinearUnit;
use crate::missing::Detection;
use crate::targets::TargetSet;

use super::color::{FLIGHT, GREY, MISSING, ROUTE, TARGET};

const CONTOUR: Rgb = [20, 20, 20];
const SKELETON: Rgb = [30, 80, 220];
const COLLECTED: Rgb = [40, 170, 60];
const REGION: Rgb = [255, 140, 0];

fn rings(mp: &MultiPolygon<f64>) -> Vec<Vec<[f64; 2]>> {
    mp.0.iter()
        .flat_map(|p| std::iter::once(p.exterior()).chain(p.interiors()))
        .map(|r| r.0.iter().map(|c| [c.x, c.y]).collect())
        .collect()
}

/// The xy extent of `points` (None when it has no area).
pub(super) fn bounds(points: impl Iterator<Item = [f64; 2]>) -> Option<([f64; 2], [f64; 2])> {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points.filter(|p| p[0].is_finite() && p[1].is_finite()) {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo[0] < hi[0] && lo[1] < hi[1]).then_some((lo, hi))
}

const DETECTION_LEGEND: [(Rgb, &str); 7] = [
    (GREY, "building points"),
    (CONTOUR, "outline"),
    (SKELETON, "skeleton"),
    (COLLECTED, "wall seen"),
    (MISSING, "wall missing"),
    (TARGET, "ground target"),
    (REGION, "region to explore"),
];

/// Detection of a scene from above: building points grey, contours black,
/// skeletons blue, collected boundary points green, missing ones red,
/// target points purple, regions orange; legend, north arrow and a scale
/// bar in `unit` (the input's). The picture spans the building points and
/// targets; where they span no area (a tile without buildings) it spans
/// `survey`, the whole cloud's xy extent, so the picture says "nothing
/// here" rather than the command failing.
pub fn detection_picture(
    building_points: &[[f32; 3]],
    detection: &Detection,
    targets: Option<&TargetSet>,
    survey: Option<([f64; 2], [f64; 2])>,
    max_px: u32,
    unit: &LinearUnit,
) -> Result<Canvas, PlotError> {
    let xy = building_points
        .iter()
        .map(|p| [f64::from(p[0]), f64::from(p[1])]);
    let tp = targets.into_iter().flat_map(|t| {
        t.points
            .iter()
            .map(|p| [f64::from(p.xyz[0]), f64::from(p.xyz[1])])
    });
    let (lo, hi) = bounds(xy.chain(tp))
        .or(survey)
        .ok_or(PlotError::EmptyArea {
            min: [0.0; 2],
            max: [0.0; 2],
        })?;
    let mut c = Canvas::new(lo, hi, 5.0, max_px)?;
    for p in building_points {
        c.dot([f64::from(p[0]), f64::from(p[1])], 0, GREY);
    }
    if let Some(t) = targets {
        for r in &t.regions {
            c.fill(&[&r.polygon], REGION, 0.25);
            c.polyline(&r.polygon, true, 2, REGION);
        }
    }
    for b in detection.buildings.iter().filter(|b| b.skipped.is_none()) {
        for ring in rings(&b.global_contour) {
            c.polyline(&ring, true, 2, CONTOUR);
        }
        for s in &b.structures {
            for e in &s.skeleton.edges {
                if let (Some(a), Some(z)) = (s.skeleton.nodes.get(e[0]), s.skeleton.nodes.get(e[1]))
                {
                    c.line(*a, *z, 2, SKELETON);
                }
            }
        }
        for q in b.boundary.iter().filter(|q| q.collected) {
            c.dot([f64::from(q.xyz[0]), f64::from(q.xyz[1])], 1, COLLECTED);
        }
        for q in &b.missing {
            c.dot([f64::from(q.xyz[0]), f64::from(q.xyz[1])], 2, MISSING);
        }
    }
    if let Some(t) = targets {
        for p in &t.points {
            c.dot([f64::from(p.xyz[0]), f64::from(p.xyz[1])], 2, TARGET);
        }
    }
    c.furnish(&DETECTION_LEGEND, unit);
    Ok(c)
}

/// One building's outline and how much it gained, for [`mission_picture`].
pub struct BuildingGain {
    /// Outline (footprint).
    pub outline: MultiPolygon<f64>,
    /// Completeness gain, 0–1 (after − before).
    pub gain: f64,
}

/// A mission from above: buildings coloured by completeness gain (blue no
/// gain → red `full_scale` or more), the driven route, the drone's flight
/// (`routes.1`, empty without a drone), targets and regions; legend (with
/// the gain ramp's ends), north arrow, scale bar in `unit`.
pub fn mission_picture(
    extent: ([f64; 2], [f64; 2]),
    buildings: &[BuildingGain],
    full_scale: f64,
    routes: (&[[f32; 3]], &[[f32; 3]]),
    targets: &TargetSet,
    max_px: u32,
    unit: &LinearUnit,
) -> Result<Canvas, PlotError> {
    let (route, flight) = routes;
    let mut c = Canvas::new(extent.0, extent.1, 5.0, max_px)?;
    for b in buildings {
        let rs = rings(&b.outline);
        let refs: Vec<&[[f64; 2]]> = rs.iter().map(Vec::as_slice).collect();
        c.fill(&refs, ramp(b.gain / full_scale.max(1e-9)), 1.0);
        for r in &rs {
            c.polyline(r, true, 1, CONTOUR);
        }
    }
    for r in &targets.regions {
        c.polyline(&r.polygon, true, 2, REGION);
    }
    for w in route.windows(2) {
        c.line(
            [f64::from(w[0][0]), f64::from(w[0][1])],
            [f64::from(w[1][0]), f64::from(w[1][1])],
            2,
            ROUTE,
        );
    }
    for w in flight.windows(2) {
        c.line(
            [f64::from(w[0][0]), f64::from(w[0][1])],
            [f64::from(w[1][0]), f64::from(w[1][1])],
            2,
            FLIGHT,
        );
    }
    for p in &targets.points {
        c.dot([f64::from(p.xyz[0]), f64::from(p.xyz[1])], 2, TARGET);
    }
    let full = format!("gain {:.0} % or more", 100.0 * full_scale);
    let half = format!("gain {:.0} %", 50.0 * full_scale);
    let mut legend = vec![
        (ramp(0.0), "no gain"),
        (ramp(0.5), half.as_str()),
        (ramp(1.0), full.as_str()),
        (ROUTE, "route driven"),
        (TARGET, "ground target"),
        (REGION, "region explored"),
    ];
    if !flight.is_empty() {
        legend.push((FLIGHT, "drone flown"));
    }
    c.furnish(&legend, unit);
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_detection_without_buildings_draws_the_survey_or_says_why_not() {
        let empty = Detection::default();
        let none = detection_picture(&[], &empty, None, None, 400, &LinearUnit::Metre);
        assert!(matches!(none, Err(PlotError::EmptyArea { .. })));
        let tile = ([500.0, 6000.0], [520.0, 6030.0]);
        let c = detection_picture(&[], &empty, None, Some(tile), 400, &LinearUnit::Metre)
            .expect("a tile without buildings is drawn");
        let (w, h) = c.size();
        assert!(h > w, "the 20 x 30 m tile is drawn upright: {w} x {h}");
        // Building points win over the survey's extent.
        let one = [[0.0f32, 0.0, 3.0], [10.0, 5.0, 3.0]];
        let c = detection_picture(&one, &empty, None, Some(tile), 400, &LinearUnit::Metre)
            .expect("drawn");
        let (w, h) = c.size();
        assert!(w > h, "the 10 x 5 m building spans the picture: {w} x {h}");
    }
}
