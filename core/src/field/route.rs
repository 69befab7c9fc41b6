//! `route.geojson`: each set-down's route as a LineString and its stops in
//! order, and the targets no set-down reaches.

use serde_json::{Value, json};

use crate::crs::SourceFrame;
use crate::io::geojson::write::{feature, feature_collection, position, ring};
use crate::route::{Route, SetDowns, Stop};
use crate::targets::TargetSet;

/// One place the robot is set down and the route it drives from there.
pub struct Leg<'a> {
    /// Where the robot is set down.
    pub start: [f32; 3],
    /// The route from there.
    pub route: &'a Route,
}

/// The routes of a plan as the field files show them.
pub struct FieldRoute<'a> {
    /// One leg per set-down, the first where the plan started.
    pub legs: Vec<Leg<'a>>,
    /// Target points no leg reaches.
    pub unreachable_points: &'a [usize],
    /// Regions no leg reaches.
    pub unreachable_regions: &'a [usize],
}

impl<'a> From<&'a SetDowns> for FieldRoute<'a> {
    fn from(s: &'a SetDowns) -> Self {
        Self {
            legs: s
                .set_downs
                .iter()
                .map(|d| Leg {
                    start: d.start,
                    route: &d.route,
                })
                .collect(),
            unreachable_points: &s.unreachable_points,
            unreachable_regions: &s.unreachable_regions,
        }
    }
}

/// Per leg: where to set the robot down (a Point, from the second leg on),
/// the route (a LineString over the graph waypoints) and one Point per stop
/// with its leg, order, building, kind and why; targets no leg reaches are
/// listed (points as Points, regions as Polygons) with `reachable: false`
/// and why.
pub fn route_geojson(plan: &FieldRoute<'_>, targets: &TargetSet, frame: &SourceFrame) -> Value {
    let pos = |p: [f32; 3]| position(frame, p.map(f64::from));
    let legs = plan.legs.len();
    let mut features = Vec::new();
    for (k, leg) in plan.legs.iter().enumerate() {
        let route = leg.route;
        let set_down = k + 1;
        // Stop and route wording names the leg only when there are several.
        let of_leg = if legs > 1 {
            format!(" of set-down {set_down}")
        } else {
            String::new()
        };
        if k > 0 {
            features.push(feature(
                json!({"type": "Point", "coordinates": pos(leg.start)}),
                json!({"kind": "set_down", "set_down": set_down, "stops": route.order.len(),
                       "why": format!("set-down {set_down} of {legs}: no drivable way reaches this ground from the earlier set-downs; set the robot down here for its {} stops", route.order.len())}),
            ));
        }
        let length = frame.length_to_source(f64::from(route.length_m));
        features.push(feature(
            json!({"type": "LineString", "coordinates": route.waypoints.iter().map(|p| pos(*p)).collect::<Vec<_>>()}),
            json!({
                "kind": "route",
                "set_down": set_down,
                "length": (length * 1e3).round() / 1e3,
                "length_m": route.length_m,
                "stops": route.order.len(),
                "why": format!("one drive{of_leg} through every target its ground reaches (the shorter of the greedy alternation and the 2-opt/Or-opt tour)"),
            }),
        ));
        let n = route.order.len();
        for (j, (stop, &at)) in route.order.iter().zip(&route.arrivals).enumerate() {
            let (kind, index, building) = match *stop {
                Stop::Point(i) => ("point", i, targets.points.get(i).map(|t| t.building)),
                Stop::Region(i) => ("region", i, targets.regions.get(i).map(|r| r.building)),
            };
            let Some(p) = route.waypoints.get(at) else {
                continue;
            };
            let b = building.map_or_else(|| "?".to_string(), |b| b.to_string());
            let why = match stop {
                Stop::Point(_) => format!(
                    "stop {} of {n}{of_leg}: scan the missing wall of building {b} from here",
                    j + 1
                ),
                Stop::Region(_) => format!(
                    "stop {} of {n}{of_leg}: explore the region around building {b}'s large gap from here",
                    j + 1
                ),
            };
            features.push(feature(
                json!({"type": "Point", "coordinates": pos(*p)}),
                json!({"kind": "stop", "set_down": set_down, "order": j + 1, "target": kind, "index": index, "building": building, "reachable": true, "why": why}),
            ));
        }
    }
    // A target no leg reaches stands in a courtyard, behind a hedge or
    // across water: plan.png shows which.
    let lost = "no ground-graph node within reach of any set-down's piece of ground (plan.png shows the ground cut off)";
    for &i in plan.unreachable_points {
        if let Some(t) = targets.points.get(i) {
            features.push(feature(
                json!({"type": "Point", "coordinates": pos(t.xyz)}),
                json!({"kind": "unreachable", "target": "point", "index": i, "building": t.building, "reachable": false,
                       "why": lost}),
            ));
        }
    }
    for &i in plan.unreachable_regions {
        if let Some(r) = targets.regions.get(i) {
            features.push(feature(
                json!({"type": "Polygon", "coordinates": [ring(frame, &r.polygon)]}),
                json!({"kind": "unreachable", "target": "region", "index": i, "building": r.building, "reachable": false,
                       "why": lost}),
            ));
        }
    }
    feature_collection(frame, "route", features)
}

/// A driven path (e.g. the demo's odometry trace) as one LineString.
pub fn path_geojson(path: &[[f32; 3]], length_m: f64, frame: &SourceFrame) -> Value {
    let coords: Vec<Value> = path
        .iter()
        .map(|p| position(frame, p.map(f64::from)))
        .collect();
    let length = frame.length_to_source(length_m);
    let line = feature(
        json!({"type": "LineString", "coordinates": coords}),
        json!({"kind": "driven", "length": (length * 1e3).round() / 1e3, "length_m": length_m,
               "why": "the path the ground vehicle drove"}),
    );
    feature_collection(frame, "route", vec![line])
}
