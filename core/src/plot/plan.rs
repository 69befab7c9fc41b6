//! The plan from above (`skyground plan`'s `plan.png`): where the vehicle
//! can and cannot drive, the route, its stops and the targets out of reach.
//! A survey team reads from it why a target was skipped: a garden behind a
//! hedge, a courtyard, a canal bank the graph does not join.

use super::canvas::{Canvas, PlotError};
use super::color::{GREY as BUILDING_PTS, MISSING as OUT_OF_REACH, ROUTE, Rgb, TARGET as STOP};
use super::scene::bounds;
use crate::cloud::class::{BUILDING, VEGETATION};
use crate::crs::LinearUnit;
use crate::graph::GroundGraph;
use crate::route::{Route, Stop};
use crate::targets::TargetSet;

const VEGETATION_PTS: Rgb = [120, 200, 120];
const REACHED: Rgb = [170, 200, 245];
const CUT_OFF: Rgb = [245, 170, 60];
const START: Rgb = [0, 0, 0];

const LEGEND: [(Rgb, &str); 8] = [
    (BUILDING_PTS, "building points"),
    (VEGETATION_PTS, "vegetation points"),
    (REACHED, "ground the vehicle reaches"),
    (CUT_OFF, "ground it cannot reach"),
    (ROUTE, "route"),
    (STOP, "stop"),
    (OUT_OF_REACH, "target out of reach"),
    (START, "start"),
];

/// What [`plan_picture`] draws.
pub struct PlanView<'a> {
    /// The classified cloud (local metres) and its LAS classes.
    pub xyz: &'a [[f32; 3]],
    /// LAS classes of `xyz`.
    pub labels: &'a [u8],
    /// The ground graph the route was made on.
    pub graph: &'a GroundGraph,
    /// The route.
    pub route: &'a Route,
    /// The targets the route serves.
    pub targets: &'a TargetSet,
}

/// The plan from above: building and vegetation points, the ground the
/// graph reaches (blue) and the ground cut off from it (orange), one cell
/// per node; the route, its stops, the targets out of reach and the start;
/// legend, north arrow and a scale bar in `unit` (the input's).
pub fn plan_picture(v: &PlanView<'_>, max_px: u32, unit: &LinearUnit) -> Result<Canvas, PlotError> {
    let xy = |p: &[f32; 3]| [f64::from(p[0]), f64::from(p[1])];
    let (lo, hi) = bounds(v.xyz.iter().map(xy)).ok_or(PlotError::EmptyArea {
        min: [0.0; 2],
        max: [0.0; 2],
    })?;
    let mut c = Canvas::new(lo, hi, 5.0, max_px)?;
    // A node stands for its cell: drawn that wide, reached ground reads as
    // an area and a gap between areas as the obstacle that cuts it.
    let cell_px =
        ((0.5 * f64::from(v.graph.params().node_spacing()) * c.scale()).floor() as i64).max(1);
    for (p, &l) in v.xyz.iter().zip(v.labels) {
        match l {
            VEGETATION => c.dot(xy(p), 0, VEGETATION_PTS),
            BUILDING => c.dot(xy(p), 0, BUILDING_PTS),
            _ => {}
        }
    }
    for p in v.graph.positions() {
        c.dot(xy(p), cell_px, REACHED);
    }
    for p in v.graph.unreachable_positions() {
        c.dot(xy(p), cell_px, CUT_OFF);
    }
    for w in v.route.waypoints.windows(2) {
        c.line(xy(&w[0]), xy(&w[1]), 3, ROUTE);
    }
    for (k, s) in v.route.order.iter().enumerate() {
        let at = v
            .route
            .arrivals
            .get(k)
            .and_then(|&a| v.route.waypoints.get(a));
        if let Some(at) = at {
            // A region's stop is where its exploration starts.
            let r = if matches!(s, Stop::Point(_)) { 4 } else { 6 };
            c.dot(xy(at), r, STOP);
        }
    }
    for r in v
        .route
        .unreachable_regions
        .iter()
        .filter_map(|&i| v.targets.regions.get(i))
    {
        c.polyline(&r.polygon, true, 3, OUT_OF_REACH);
    }
    for t in v
        .route
        .unreachable_points
        .iter()
        .filter_map(|&i| v.targets.points.get(i))
    {
        c.dot(xy(&t.xyz), 5, OUT_OF_REACH);
    }
    if let Some(s) = v.graph.positions().get(v.graph.start_node()) {
        c.dot(xy(s), 7, START);
    }
    c.furnish(&LEGEND, unit);
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::GraphParams;
    use crate::route::{RouteParams, plan};
    use crate::targets::TargetPoint;

    /// Flat ground 0..40 × 0..20 and a closed 3 m pen around (30, 10).
    fn pen() -> (Vec<[f32; 3]>, Vec<u8>) {
        let mut xyz = Vec::new();
        let mut lab = Vec::new();
        for i in 0..160 {
            for j in 0..80 {
                xyz.push([i as f32 * 0.25, j as f32 * 0.25, 0.0]);
                lab.push(crate::cloud::class::GROUND);
            }
        }
        let corners = [[25.0f32, 5.0], [35.0, 5.0], [35.0, 15.0], [25.0, 15.0]];
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            for s in 0..=100 {
                let t = s as f32 / 100.0;
                for h in 0..30 {
                    xyz.push([
                        a[0] + t * (b[0] - a[0]),
                        a[1] + t * (b[1] - a[1]),
                        0.1 * h as f32,
                    ]);
                    lab.push(BUILDING);
                }
            }
        }
        (xyz, lab)
    }

    #[test]
    fn reached_and_cut_off_ground_route_and_lost_target_are_drawn() {
        let (xyz, labels) = pen();
        let graph =
            GroundGraph::build(&xyz, &labels, [2.0, 2.0, 0.0], &GraphParams::default()).unwrap();
        let at = |x, y| TargetPoint {
            xyz: [x, y, 0.0],
            building: 1,
        };
        let targets = TargetSet {
            points: vec![at(20.0, 10.0), at(30.0, 10.0)],
            regions: Vec::new(),
        };
        let route = plan(&graph, &targets, [2.0, 2.0, 0.0], &RouteParams::default()).unwrap();
        assert_eq!(
            route.unreachable_points,
            vec![1],
            "the pen's target is out of reach"
        );
        let inside = graph.unreachable_positions();
        assert!(!inside.is_empty());
        assert!(
            inside
                .iter()
                .all(|p| (25.0..35.0).contains(&p[0]) && (5.0..15.0).contains(&p[1])),
            "only the pen is cut off"
        );
        let v = PlanView {
            xyz: &xyz,
            labels: &labels,
            graph: &graph,
            route: &route,
            targets: &targets,
        };
        let c = plan_picture(&v, 800, &LinearUnit::Metre).unwrap();
        let px = |x: f64, y: f64| {
            let [col, row] = c.to_px([x, y]);
            c.pixel(col as u32, row as u32)
        };
        assert_eq!(px(27.0, 12.5), Some(CUT_OFF), "inside the pen");
        assert_eq!(px(10.0, 17.5), Some(REACHED), "open ground");
        assert_eq!(px(30.0, 10.0), Some(OUT_OF_REACH), "the pen's target");
        let stop = route.waypoints[route.arrivals[0]];
        assert!((stop[0] - 20.0).hypot(stop[1] - 10.0) < 1.0, "{stop:?}");
        assert_eq!(
            px(f64::from(stop[0]), f64::from(stop[1])),
            Some(STOP),
            "the reachable target's stop"
        );
        let empty = PlanView {
            xyz: &[],
            labels: &[],
            ..v
        };
        assert!(plan_picture(&empty, 800, &LinearUnit::Metre).is_err());
    }
}
