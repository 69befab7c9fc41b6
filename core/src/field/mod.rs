//! What a survey team takes to the field: targets, the route and each
//! building's completeness as GeoJSON in the input's CRS and unit (named by
//! GeoJSON's legacy `crs` member, which GDAL and QGIS read), and the
//! completeness as CSV.

mod completeness;
mod route;
mod targets;

pub use completeness::{
    BuildingFigures, DetectedFigures, completeness_csv, completeness_geojson, detection_figures,
};
pub use route::{FieldRoute, Leg, path_geojson, route_geojson};
pub use targets::targets_geojson;

#[cfg(test)]
mod tests {
    use geo::{MultiPolygon, polygon};

    use super::*;
    use crate::crs::{Crs, SourceFrame};
    use crate::missing::{
        BoundaryPoint, BuildingDetection, Detection, MissingPoint, SkipReason, Strategy,
    };
    use crate::route::{Route, Stop};
    use crate::targets::{Region, TargetPoint, TargetSet};

    const FT: f64 = 0.3048;

    /// Autzen-like frame: EPSG:2994 (NAD83(HARN) / Oregon GIC Lambert, feet).
    fn frame() -> SourceFrame {
        SourceFrame::new(
            [636_000.0 * FT, 849_000.0 * FT, 0.0],
            Some(Crs::from_epsg(2994).unwrap()),
        )
    }

    /// One 20 m square building, 4 boundary points, 1 missing (on its east wall).
    fn detection() -> Detection {
        let mut b =
            BuildingDetection::skipped(3, 500, SkipReason::TooFewPoints { points: 0, min: 0 });
        b.skipped = None;
        b.footprint_id = "NL.IMBAG.Pand.0503100000028341".into();
        b.global_contour = MultiPolygon(vec![
            polygon![(x: 0.0, y: 0.0), (x: 20.0, y: 0.0), (x: 20.0, y: 20.0), (x: 0.0, y: 20.0)],
        ]);
        let q = |x: f32, y: f32, collected| BoundaryPoint {
            xyz: [x, y, 5.0],
            normal: [1.0, 0.0],
            skeleton: [10.0, 10.0],
            coverage: 0.0,
            collected,
            slice: 0,
        };
        b.boundary = vec![
            q(20.0, 10.0, false),
            q(10.0, 20.0, true),
            q(0.0, 10.0, true),
            q(10.0, 0.0, true),
        ];
        b.missing = vec![MissingPoint {
            xyz: [20.0, 10.0, 5.0],
            building: 3,
            normal: [1.0, 0.0],
            skeleton: [10.0, 10.0],
        }];
        b.r_missing = 0.25;
        b.strategy = Strategy::PointBased;
        Detection {
            buildings: vec![b],
            params: None,
            density: None,
        }
    }

    fn targets() -> TargetSet {
        TargetSet {
            points: vec![TargetPoint {
                xyz: [28.0, 10.0, 0.0],
                building: 3,
            }],
            regions: vec![Region {
                building: 3,
                polygon: vec![[18.0, 5.0], [25.0, 5.0], [25.0, 15.0], [18.0, 15.0]],
                z: 0.0,
            }],
        }
    }

    #[test]
    fn targets_are_in_feet_with_building_and_why() {
        let fc = targets_geojson(&targets(), &detection(), &frame());
        assert_eq!(
            fc["crs"]["properties"]["name"],
            "urn:ogc:def:crs:EPSG::2994"
        );
        assert_eq!(fc["units"]["horizontal"], "foot");
        let p = &fc["features"][0];
        let c = p["geometry"]["coordinates"].as_array().unwrap();
        assert!(
            (c[0].as_f64().unwrap() - (636_000.0 + 28.0 / FT)).abs() < 1e-3,
            "{c:?}"
        );
        assert!((c[1].as_f64().unwrap() - (849_000.0 + 10.0 / FT)).abs() < 1e-3);
        assert_eq!(p["properties"]["building"], 3);
        assert_eq!(
            p["properties"]["footprint_id"],
            "NL.IMBAG.Pand.0503100000028341"
        );
        // 8 m to the missing point = 26.247 ft, 5 m up = 16.404 ft.
        assert!((p["properties"]["gap_distance"].as_f64().unwrap() - 8.0 / FT).abs() < 1e-3);
        assert!((p["properties"]["gap_height"].as_f64().unwrap() - 5.0 / FT).abs() < 1e-3);
        assert!(
            p["properties"]["why"]
                .as_str()
                .unwrap()
                .contains("building 3")
        );
        let r = &fc["features"][1];
        assert_eq!(r["geometry"]["type"], "Polygon");
        let ring = r["geometry"]["coordinates"][0].as_array().unwrap();
        assert_eq!(ring.len(), 5, "closed ring");
        assert_eq!(ring[0], ring[4]);
        assert_eq!(r["properties"]["gap_points"], 1);
        assert!((r["properties"]["area"].as_f64().unwrap() - 70.0 / (FT * FT)).abs() < 1e-2);
    }

    fn route(order: Vec<Stop>, waypoints: Vec<[f32; 3]>, length_m: f32) -> Route {
        Route {
            arrivals: vec![waypoints.len() - 1; order.len()],
            order,
            waypoints,
            nodes: vec![],
            length_m,
            unreachable_points: vec![],
            unreachable_regions: vec![],
            greedy_length_m: length_m,
            tsp_length_m: length_m,
            streets_length_m: length_m,
        }
    }

    #[test]
    fn route_is_a_linestring_in_feet_with_ordered_stops() {
        let r = route(
            vec![Stop::Point(0)],
            vec![[0.0, -5.0, 0.0], [28.0, -5.0, 0.0], [28.0, 10.0, 0.0]],
            43.0,
        );
        let plan = FieldRoute {
            legs: vec![Leg {
                start: r.waypoints[0],
                route: &r,
            }],
            unreachable_points: &[],
            unreachable_regions: &[0],
        };
        let fc = route_geojson(&plan, &targets(), &frame());
        let line = &fc["features"][0];
        assert_eq!(line["geometry"]["type"], "LineString");
        assert_eq!(line["geometry"]["coordinates"].as_array().unwrap().len(), 3);
        assert!((line["properties"]["length"].as_f64().unwrap() - 43.0 / FT).abs() < 1e-3);
        let stop = &fc["features"][1];
        assert_eq!(stop["properties"]["order"], 1);
        assert_eq!(stop["properties"]["building"], 3);
        let why = stop["properties"]["why"].as_str().unwrap();
        assert!(
            why.contains("stop 1 of 1") && why.contains("building 3") && !why.contains("set-down"),
            "{why}"
        );
        // The region out of reach, as a closed ring in feet.
        let lost = &fc["features"][2];
        assert_eq!(lost["properties"]["reachable"], false);
        assert_eq!(lost["properties"]["target"], "region");
        assert!(
            lost["properties"]["why"]
                .as_str()
                .unwrap()
                .contains("plan.png")
        );
        let ring = lost["geometry"]["coordinates"][0].as_array().unwrap();
        assert_eq!(ring.len(), 5);
        let x = ring[0][0].as_f64().unwrap();
        assert!((x - (636_000.0 + 18.0 / FT)).abs() < 1e-3, "{x}");
        assert_eq!(fc["features"].as_array().unwrap().len(), 3);
    }

    #[test]
    fn a_second_set_down_is_a_point_with_its_own_route_and_stops() {
        let a = route(
            vec![Stop::Point(0)],
            vec![[0.0, -5.0, 0.0], [28.0, 10.0, 0.0]],
            33.0,
        );
        let b = route(
            vec![Stop::Region(0)],
            vec![[20.0, 8.0, 0.0], [21.0, 8.0, 0.0]],
            1.0,
        );
        let plan = FieldRoute {
            legs: vec![
                Leg {
                    start: a.waypoints[0],
                    route: &a,
                },
                Leg {
                    start: b.waypoints[0],
                    route: &b,
                },
            ],
            unreachable_points: &[],
            unreachable_regions: &[],
        };
        let fc = route_geojson(&plan, &targets(), &frame());
        let f = fc["features"].as_array().unwrap();
        let kinds: Vec<&str> = f
            .iter()
            .map(|f| f["properties"]["kind"].as_str().unwrap())
            .collect();
        assert_eq!(kinds, ["route", "stop", "set_down", "route", "stop"]);
        let put = &f[2];
        assert_eq!(put["properties"]["set_down"], 2);
        assert!(
            put["properties"]["why"]
                .as_str()
                .unwrap()
                .starts_with("set-down 2 of 2"),
            "{put}"
        );
        let x = put["geometry"]["coordinates"][0].as_f64().unwrap();
        assert!((x - (636_000.0 + 20.0 / FT)).abs() < 1e-3, "{x}");
        assert_eq!(f[3]["properties"]["set_down"], 2);
        let why = f[4]["properties"]["why"].as_str().unwrap();
        assert!(
            why.contains("stop 1 of 1 of set-down 2") && why.contains("explore"),
            "{why}"
        );
        assert_eq!(f[1]["properties"]["set_down"], 1);
    }

    #[test]
    fn completeness_rows_as_geojson_and_csv() {
        let rows = detection_figures(&detection(), &targets());
        assert_eq!(rows[0].target_points, 1);
        let fc = completeness_geojson(&rows, &frame());
        let f = &fc["features"][0];
        assert_eq!(f["geometry"]["type"], "MultiPolygon");
        assert_eq!(f["properties"]["detected_completeness"], 0.75);
        assert_eq!(
            f["properties"]["footprint_id"],
            "NL.IMBAG.Pand.0503100000028341"
        );
        let csv = completeness_csv(&rows, &frame());
        let lines: Vec<&str> = csv.lines().collect();
        assert!(
            lines[0].starts_with("building,footprint_id,centroid_x_ft,centroid_y_ft,"),
            "{}",
            lines[0]
        );
        let cells: Vec<&str> = lines[1].split(',').collect();
        assert_eq!(cells[0], "3");
        assert_eq!(cells[1], "NL.IMBAG.Pand.0503100000028341");
        let cx: f64 = cells[2].parse().unwrap();
        assert!((cx - (636_000.0 + 10.0 / FT)).abs() < 1e-2, "{cx}");
        assert_eq!(cells[9], "0.7500");
        assert_eq!(cells[10], "point_based");
        // A building no detection matched: empty detection cells, nulls in
        // the GeoJSON, the same number of columns.
        let mut unmatched = rows[0].clone();
        unmatched.detection = None;
        unmatched.footprint_id = "way/12,5".into();
        unmatched.before = Some(0.5);
        let csv = completeness_csv(std::slice::from_ref(&unmatched), &frame());
        let row = csv.lines().nth(1).unwrap();
        assert!(row.starts_with("3,\"way/12,5\","), "{row}");
        let unquoted = row.replace("\"way/12,5\"", "w");
        let cells: Vec<&str> = unquoted.split(',').collect();
        assert_eq!(cells.len(), lines[0].split(',').count());
        assert!(cells[4..11].iter().all(|c| c.is_empty()), "{cells:?}");
        assert_eq!(cells[13], "0.5000");
        let fc = completeness_geojson(&[unmatched], &frame());
        assert!(fc["features"][0]["properties"]["points"].is_null());
        assert!(fc["features"][0]["properties"]["detected_completeness"].is_null());
    }
}
