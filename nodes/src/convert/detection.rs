//! Detection results (docs/design.md step 3) as messages: /missing_points,
//! /completeness and the contour / skeleton markers.

use geo::MultiPolygon;
use skyground_core::cloud::Cloud;
use skyground_core::missing::{BuildingDetection, Detection, Strategy};
use skyground_msgs::diagnostic_msgs::{DiagnosticArray, DiagnosticStatus};
use skyground_msgs::std_msgs::Header;
use skyground_msgs::visualization_msgs::MarkerArray;

use super::diagnostics::{kv, status};
use super::markers::{delete_all, line_list, line_strip, points, rgb};

/// The missing points as a cloud with x, y, z and building.
pub fn missing_cloud(d: &Detection, origin: [f64; 3]) -> Cloud {
    let missing = d.missing_points();
    let mut c = Cloud::from_xyz(missing.iter().map(|m| m.xyz).collect());
    c.building = Some(missing.iter().map(|m| m.building).collect());
    c.origin = origin;
    c
}

/// The strategy's name on /completeness.
pub fn strategy_name(s: Strategy) -> &'static str {
    match s {
        Strategy::PointBased => "point",
        Strategy::RegionBased => "region",
    }
}

/// One status per building: completeness = 1 − R_missing, R_missing,
/// missing and boundary counts, strategy; skipped buildings are WARN with
/// the reason.
pub fn completeness_array(header: &Header, d: &Detection, round: u32) -> DiagnosticArray {
    let status = d
        .buildings
        .iter()
        .map(|b| {
            let name = format!("building {}", b.building);
            let mut values = vec![
                kv("building", b.building),
                kv("points", b.points),
                kv("round", round),
            ];
            match &b.skipped {
                Some(reason) => status(
                    name,
                    DiagnosticStatus::WARN,
                    format!("skipped: {reason}"),
                    values,
                ),
                None => {
                    values.extend([
                        kv("completeness", 1.0 - b.r_missing),
                        kv("r_missing", b.r_missing),
                        kv("missing", b.missing.len()),
                        kv("boundary", b.boundary.len()),
                        kv("slices", b.slices.len()),
                        kv("structures", b.structures.len()),
                        kv("strategy", strategy_name(b.strategy)),
                        kv("ground_z", b.ground_z),
                    ]);
                    status(
                        name,
                        DiagnosticStatus::OK,
                        format!(
                            "R_missing {:.3}, {}",
                            b.r_missing,
                            strategy_name(b.strategy)
                        ),
                        values,
                    )
                }
            }
        })
        .collect();
    DiagnosticArray {
        header: header.clone(),
        status,
    }
}

fn rings(mp: &MultiPolygon<f64>) -> Vec<Vec<[f64; 2]>> {
    mp.0.iter()
        .flat_map(|p| std::iter::once(p.exterior()).chain(p.interiors()))
        .map(|r| r.0.iter().map(|c| [c.x, c.y]).collect())
        .collect()
}

fn building_markers(header: &Header, b: &BuildingDetection, out: &mut MarkerArray) {
    let ns = |what: &str| format!("{what}/{}", b.building);
    for (k, ring) in rings(&b.global_contour).iter().enumerate() {
        let pts: Vec<[f64; 3]> = ring
            .iter()
            .map(|p| [p[0], p[1], f64::from(b.ground_z)])
            .collect();
        out.markers.push(line_strip(
            header,
            &ns("contour"),
            k as i32,
            &pts,
            false,
            0.2,
            rgb(0.1, 0.1, 0.1),
        ));
    }
    for (k, s) in b.structures.iter().enumerate() {
        let z = f64::from(s.heights[0]);
        let segs: Vec<[[f64; 3]; 2]> = s
            .skeleton
            .edges
            .iter()
            .filter_map(|e| {
                let (a, c) = (s.skeleton.nodes.get(e[0])?, s.skeleton.nodes.get(e[1])?);
                Some([[a[0], a[1], z], [c[0], c[1], z]])
            })
            .collect();
        if !segs.is_empty() {
            out.markers.push(line_list(
                header,
                &ns("skeleton"),
                k as i32,
                &segs,
                0.15,
                rgb(0.1, 0.3, 0.9),
            ));
        }
    }
    let missing: Vec<[f64; 3]> = b.missing.iter().map(|m| m.xyz.map(f64::from)).collect();
    if !missing.is_empty() {
        out.markers.push(points(
            header,
            &ns("missing"),
            0,
            &missing,
            0.4,
            rgb(0.9, 0.1, 0.1),
        ));
    }
}

/// Contours (ns `contour/ID`), skeletons (`skeleton/ID`, LINE_LIST at the
/// structure's base height) and missing points (`missing/ID`).
pub fn detection_markers(header: &Header, d: &Detection) -> MarkerArray {
    let mut out = MarkerArray {
        markers: vec![delete_all(header)],
    };
    for b in d.buildings.iter().filter(|b| b.skipped.is_none()) {
        building_markers(header, b, &mut out);
    }
    out
}

/// Skeleton segments per building back from the markers (for the target
/// generator, which aims from the skeleton through each missing point).
pub fn skeletons_from_markers(
    array: &MarkerArray,
) -> std::collections::BTreeMap<u32, Vec<[[f64; 2]; 2]>> {
    let mut out: std::collections::BTreeMap<u32, Vec<[[f64; 2]; 2]>> = Default::default();
    for m in &array.markers {
        let Some(id) =
            m.ns.strip_prefix("skeleton/")
                .and_then(|s| s.parse::<u32>().ok())
        else {
            continue;
        };
        let segs = out.entry(id).or_default();
        for pair in m.points.chunks_exact(2) {
            segs.push([[pair[0].x, pair[0].y], [pair[1].x, pair[1].y]]);
        }
    }
    out
}
