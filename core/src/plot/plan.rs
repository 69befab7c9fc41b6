//! The plan from above (`skyground plan`'s `plan.png`): where the vehicle
//! can and cannot drive, the route, its stops and the targets out of reach.
//! A survey team reads from it why a target was skipped: a garden behind a
//! hedge, a courtyard, a canal bank the graph does not join.

use super::canvas::{Canvas, PlotError};
use super::color::{GREY as BUILDING_PTS, MISSING as OUT_OF_REACH, ROUTE, Rgb, TARGET as STOP};
use super::scene::bounds;
use crate::cloud::class::{BUILDING, VEGETATION};
use crate::crs::LinearUnit;
use crate::route::{SetDowns, Stop};
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
    (START, "set-down (start)"),
];

/// What [`plan_picture`] draws.
pub struct PlanView<'a> {
    /// The classified cloud (local metres) and its LAS classes.
    pub xyz: &'a [[f32; 3]],
    /// LAS classes of `xyz`.
    pub labels: &'a [u8],
    /// The set-downs: each one's piece of ground and route.
    pub set_downs: &'a SetDowns,
    /// The targets the routes serve.
    pub targets: &'a TargetSet,
}

/// The plan from above: building and vegetation points, the ground the
/// graph reaches (blue) and the ground cut off from it (orange), one cell
/// per node; each set-down's piece, route, stops and start; the targets
/// no set-down reaches;
/// legend, north arrow and a scale bar in `unit` (the input's).
pub fn plan_picture(v: &PlanView<'_>, max_px: u32, unit: &LinearUnit) -> Result<Canvas, PlotError> {
    let xy = |p: &[f32; 3]| [f64::from(p[0]), f64::from(p[1])];
    let (lo, hi) = bounds(v.xyz.iter().map(xy)).ok_or(PlotError::EmptyArea {
        min: [0.0; 2],
        max: [0.0; 2],
    })?;
    let mut c = Canvas::new(lo, hi, 5.0, max_px)?;
    let first = v.set_downs.set_downs.first().ok_or(PlotError::NoGraph)?;
    // A node stands for its cell: drawn that wide, reached ground reads as
    // an area and a gap between areas as the obstacle that cuts it.
    let cell_px =
        ((0.5 * f64::from(first.graph.params().node_spacing()) * c.scale()).floor() as i64).max(1);
    for (p, &l) in v.xyz.iter().zip(v.labels) {
        match l {
            VEGETATION => c.dot(xy(p), 0, VEGETATION_PTS),
            BUILDING => c.dot(xy(p), 0, BUILDING_PTS),
            _ => {}
        }
    }
    // Every piece but the first's is cut off from it; the later set-downs'
    // pieces are then drawn over as reached.
    for p in first.graph.unreachable_positions() {
        c.dot(xy(p), cell_px, CUT_OFF);
    }
    for s in &v.set_downs.set_downs {
        for p in s.graph.positions() {
            c.dot(xy(p), cell_px, REACHED);
        }
    }
    for s in &v.set_downs.set_downs {
        let route = &s.route;
        for w in route.waypoints.windows(2) {
            c.line(xy(&w[0]), xy(&w[1]), 3, ROUTE);
        }
        for (k, stop) in route.order.iter().enumerate() {
            let at = route.arrivals.get(k).and_then(|&a| route.waypoints.get(a));
            if let Some(at) = at {
                // A region's stop is where its exploration starts.
                let r = if matches!(stop, Stop::Point(_)) { 4 } else { 6 };
                c.dot(xy(at), r, STOP);
            }
        }
    }
    for r in v
        .set_downs
        .unreachable_regions
        .iter()
        .filter_map(|&i| v.targets.regions.get(i))
    {
        c.polyline(&r.polygon, true, 3, OUT_OF_REACH);
    }
    for t in v
        .set_downs
        .unreachable_points
        .iter()
        .filter_map(|&i| v.targets.points.get(i))
    {
        c.dot(xy(&t.xyz), 5, OUT_OF_REACH);
    }
    for s in &v.set_downs.set_downs {
        c.dot(xy(&s.start), 7, START);
    }
    c.furnish(&LEGEND, unit);
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::fixtures::pens;
    use crate::graph::{GraphParams, GroundGraph};
    use crate::route::{Ground, RouteParams, plan_set_downs};
    use crate::targets::TargetPoint;

    #[test]
    fn reached_and_cut_off_ground_route_and_lost_target_are_drawn() {
        let (xyz, labels) = pens(&[([25.0, 5.0], [35.0, 15.0])]);
        let params = GraphParams::default();
        let start = [2.0, 2.0, 0.0];
        let first = || GroundGraph::build(&xyz, &labels, start, &params).unwrap();
        let at = |x, y| TargetPoint {
            xyz: [x, y, 0.0],
            building: 1,
        };
        let targets = TargetSet {
            points: vec![at(20.0, 10.0), at(30.0, 10.0)],
            regions: Vec::new(),
        };
        let ground = Ground {
            xyz: &xyz,
            labels: &labels,
            params: &params,
        };
        let rp = RouteParams::default();
        let one = plan_set_downs(&ground, &targets, (first(), start), &rp, 0).unwrap();
        assert_eq!(
            one.unreachable_points,
            vec![1],
            "the pen's target is out of reach"
        );
        let inside = one.set_downs[0].graph.unreachable_positions();
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
            set_downs: &one,
            targets: &targets,
        };
        let c = plan_picture(&v, 800, &LinearUnit::Metre).unwrap();
        let px = |c: &Canvas, x: f64, y: f64| {
            let [col, row] = c.to_px([x, y]);
            c.pixel(col as u32, row as u32)
        };
        assert_eq!(px(&c, 27.0, 12.5), Some(CUT_OFF), "inside the pen");
        assert_eq!(px(&c, 10.0, 17.5), Some(REACHED), "open ground");
        assert_eq!(px(&c, 30.0, 10.0), Some(OUT_OF_REACH), "the pen's target");
        let route = &one.set_downs[0].route;
        let stop = route.waypoints[route.arrivals[0]];
        assert!((stop[0] - 20.0).hypot(stop[1] - 10.0) < 1.0, "{stop:?}");
        assert_eq!(
            px(&c, f64::from(stop[0]), f64::from(stop[1])),
            Some(STOP),
            "the reachable target's stop"
        );
        // Set down in the pen as well: its ground is reached, its target a stop.
        let two = plan_set_downs(&ground, &targets, (first(), start), &rp, 1).unwrap();
        let c2 = plan_picture(
            &PlanView {
                set_downs: &two,
                ..v
            },
            800,
            &LinearUnit::Metre,
        )
        .unwrap();
        assert_eq!(px(&c2, 27.0, 12.5), Some(REACHED), "inside the pen");
        let pen = two.set_downs[1].start;
        assert_eq!(
            px(&c2, f64::from(pen[0]), f64::from(pen[1])),
            Some(START),
            "the pen's set-down"
        );
        let empty = PlanView {
            xyz: &[],
            labels: &[],
            ..v
        };
        assert!(plan_picture(&empty, 800, &LinearUnit::Metre).is_err());
    }
}
