//! `route.geojson`: the route as a LineString and its stops in order.

use serde_json::{Value, json};

use super::geojson::{feature, feature_collection, position, ring};
use crate::crs::SourceFrame;
use crate::route::{Route, Stop};
use crate::targets::TargetSet;

/// The route (LineString over the graph waypoints) and one Point per stop
/// with its order, building, kind and why; unreachable targets are listed
/// (points as Points, regions as Polygons) with `reachable: false` and why.
pub fn route_geojson(route: &Route, targets: &TargetSet, frame: &SourceFrame) -> Value {
    let pos = |p: [f32; 3]| position(frame, p.map(f64::from));
    let length = frame.length_to_source(f64::from(route.length_m));
    let mut features = vec![feature(
        json!({"type": "LineString", "coordinates": route.waypoints.iter().map(|p| pos(*p)).collect::<Vec<_>>()}),
        json!({
            "kind": "route",
            "length": (length * 1e3).round() / 1e3,
            "length_m": route.length_m,
            "stops": route.order.len(),
            "why": "one drive through every reachable target (the shorter of the greedy alternation and the 2-opt/Or-opt tour)",
        }),
    )];
    let n = route.order.len();
    for (k, (stop, &at)) in route.order.iter().zip(&route.arrivals).enumerate() {
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
                "stop {} of {n}: scan the missing wall of building {b} from here",
                k + 1
            ),
            Stop::Region(_) => format!(
                "stop {} of {n}: explore the region around building {b}'s large gap from here",
                k + 1
            ),
        };
        features.push(feature(
            json!({"type": "Point", "coordinates": pos(*p)}),
            json!({"kind": "stop", "order": k + 1, "target": kind, "index": index, "building": building, "reachable": true, "why": why}),
        ));
    }
    // A target the graph does not reach stands in a courtyard, behind a
    // hedge or across water: plan.png shows which.
    let lost = "no ground-graph node within reach of the start's piece of ground (plan.png shows the ground cut off)";
    for &i in &route.unreachable_points {
        if let Some(t) = targets.points.get(i) {
            features.push(feature(
                json!({"type": "Point", "coordinates": pos(t.xyz)}),
                json!({"kind": "unreachable", "target": "point", "index": i, "building": t.building, "reachable": false,
                       "why": lost}),
            ));
        }
    }
    for &i in &route.unreachable_regions {
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
