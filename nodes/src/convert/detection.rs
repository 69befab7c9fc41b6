//! Detection results (docs/design.md step 3) as messages: /missing_points,
//! /completeness and the contour / skeleton markers.

use geo::{Area, LineString, MultiPolygon, Polygon};
use skyground_core::cloud::Cloud;
use skyground_core::footprint::Footprint;
use std::collections::BTreeMap;

use crate::convert::pointcloud2::{Decoded, EncodeOptions, encode_with};
use skyground_core::missing::{BuildingDetection, Detection, MissingPoint, Strategy};
use skyground_core::mission::BuildingStatus;
use skyground_core::targets::BuildingPlan;
use skyground_msgs::diagnostic_msgs::DiagnosticArray;
use skyground_msgs::sensor_msgs::PointCloud2;
use skyground_msgs::std_msgs::Header;
use skyground_msgs::visualization_msgs::MarkerArray;

use super::diagnostics::{from_status, to_status};
use super::markers::{Look, delete_all, line_list, line_strip, points, rgb, strips};

/// Namespace of a building's contour markers: `contour/<building id>`.
pub const CONTOUR_NS: &str = "contour";

/// Each detected building's outer contour back from /detection_markers (its
/// largest ring), as a footprint with the detection's building id.
pub fn detection_contours(array: &MarkerArray) -> Vec<Footprint> {
    let mut by_id: BTreeMap<u32, Polygon<f64>> = BTreeMap::new();
    for (m, ring) in strips(array) {
        let id =
            m.ns.strip_prefix(CONTOUR_NS)
                .and_then(|s| s.strip_prefix('/'))
                .and_then(|s| s.parse::<u32>().ok());
        let (Some(id), Some(ring)) = (id, ring) else {
            continue;
        };
        if ring.len() < 3 {
            continue;
        }
        let poly = Polygon::new(LineString::from(ring), vec![]);
        if by_id
            .get(&id)
            .is_none_or(|p| poly.unsigned_area() > p.unsigned_area())
        {
            by_id.insert(id, poly);
        }
    }
    by_id
        .into_iter()
        .map(|(id, p)| Footprint {
            id,
            polygon: MultiPolygon(vec![p]),
            name: format!("detected {id}"),
        })
        .collect()
}

/// The missing points as a cloud with x, y, z and building.
pub fn missing_cloud(d: &Detection, origin: [f64; 3]) -> Cloud {
    let missing = d.missing_points();
    let mut c = Cloud::from_xyz(missing.iter().map(|m| m.xyz).collect());
    c.building = Some(missing.iter().map(|m| m.building).collect());
    c.origin = origin;
    c
}

/// The extra columns of /missing_points: each point's outward normal and
/// the skeleton point its ray starts from (xy; the detector's are 2-D).
pub const MISSING_COLUMNS: [&str; 4] = ["nx", "ny", "sx", "sy"];

/// /missing_points: x, y, z, building and the [`MISSING_COLUMNS`], so the
/// target generator gets the detector's own missing points back.
pub fn missing_message(d: &Detection, origin: [f64; 3], header: Header) -> PointCloud2 {
    let missing = d.missing_points();
    let column = |f: fn(&MissingPoint) -> f32| missing.iter().map(f).collect::<Vec<f32>>();
    let columns = [
        column(|m| m.normal[0]),
        column(|m| m.normal[1]),
        column(|m| m.skeleton[0]),
        column(|m| m.skeleton[1]),
    ];
    let extra: Vec<(&str, &[f32])> = MISSING_COLUMNS
        .iter()
        .zip(&columns)
        .map(|(n, c)| (*n, c.as_slice()))
        .collect();
    let opts = EncodeOptions { double: false };
    encode_with(&missing_cloud(d, origin), &extra, header, &opts)
}

/// The missing points of a decoded /missing_points; an error names the
/// column a publisher older than the normals left out.
pub fn missing_from_message(d: &Decoded) -> Result<Vec<MissingPoint>, String> {
    let c = &d.cloud;
    let column = |name: &str| {
        d.column(name)
            .filter(|v| v.len() == c.len())
            .ok_or_else(|| format!("/missing_points has no `{name}` column: is the completeness_detector from an older skyground?"))
    };
    let [nx, ny, sx, sy] = [column("nx")?, column("ny")?, column("sx")?, column("sy")?];
    let ids = c
        .building
        .as_deref()
        .ok_or("/missing_points has no `building` field")?;
    Ok((0..c.len())
        .map(|i| MissingPoint {
            xyz: c.xyz[i],
            building: ids.get(i).copied().unwrap_or(0),
            normal: [nx[i], ny[i]],
            skeleton: [sx[i], sy[i]],
        })
        .collect())
}

/// Per-building plans (strategy, ground height) and the detection round
/// from /completeness; skipped buildings have none.
pub fn plans_from_completeness(arr: &DiagnosticArray) -> (BTreeMap<u32, BuildingPlan>, u32) {
    let mut plans = BTreeMap::new();
    let mut round = 0;
    for s in arr.status.iter().map(from_status) {
        let Ok(b) = BuildingStatus::from_wire(&s) else {
            continue;
        };
        round = b.round;
        if b.skipped.is_none() {
            let (strategy, ground_z) = (b.strategy, b.ground_z);
            plans.insert(b.building, BuildingPlan { strategy, ground_z });
        }
    }
    (plans, round)
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
            let s = BuildingStatus {
                building: b.building,
                footprint_id: b.footprint_id.clone(),
                points: b.points,
                round,
                skipped: b.skipped.as_ref().map(ToString::to_string),
                r_missing: b.r_missing,
                missing: b.missing.len(),
                boundary: b.boundary.len(),
                slices: b.slices.len(),
                structures: b.structures.len(),
                strategy: b.strategy,
                ground_z: b.ground_z,
            };
            to_status(s.to_wire())
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
    let look = |what: &str, id: usize, color| Look {
        header,
        ns: format!("{what}/{}", b.building),
        id: id as i32,
        color,
    };
    for (k, ring) in rings(&b.global_contour).iter().enumerate() {
        let pts: Vec<[f64; 3]> = ring
            .iter()
            .map(|p| [p[0], p[1], f64::from(b.ground_z)])
            .collect();
        let contour = look(CONTOUR_NS, k, rgb(0.1, 0.1, 0.1));
        out.markers.push(line_strip(contour, &pts, false, 0.2));
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
            let skeleton = look("skeleton", k, rgb(0.1, 0.3, 0.9));
            out.markers.push(line_list(skeleton, &segs, 0.15));
        }
    }
    let missing: Vec<[f64; 3]> = b.missing.iter().map(|m| m.xyz.map(f64::from)).collect();
    if !missing.is_empty() {
        let at = look("missing", 0, rgb(0.9, 0.1, 0.1));
        out.markers.push(points(at, &missing, 0.4));
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

#[cfg(test)]
mod tests {
    use crate::convert::pointcloud2::decode;
    use crate::convert::pointcloud2::tiles::{Assembler, split};
    use skyground_core::io::load_scene;
    use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
    use skyground_core::missing::{DetectParams, SceneParams, detect_scene};
    use skyground_core::targets::{
        Site, TargetParams, consolidate, generate, generate_from_missing,
    };

    use super::*;

    /// What travels: /missing_points (in tiles, as the transport sends big
    /// clouds) and /completeness, decoded as target_generator does.
    fn through_the_topics(
        d: &Detection,
        origin: [f64; 3],
    ) -> (Vec<MissingPoint>, BTreeMap<u32, BuildingPlan>) {
        let header = Header::default();
        let mut assembler = Assembler::new(500);
        let whole = split(missing_message(d, origin, header.clone()), 500)
            .into_iter()
            .find_map(|t| assembler.push(t))
            .expect("the tiles make one cloud");
        let decoded = decode(&whole).expect("decodes");
        let points = missing_from_message(&decoded).expect("has the columns");
        let (plans, _) = plans_from_completeness(&completeness_array(&header, d, 0));
        (points, plans)
    }

    #[test]
    fn targets_from_the_topics_equal_skyground_detect_on_the_reference_scene() {
        let scene = load_scene("reference").expect("the reference scene");
        let caster = Caster::new(&scene).expect("a caster");
        let aerial = airborne_scan(&caster, &AirborneConfig::default()).expect("a prior");
        // θ low enough that both strategies occur on this scene.
        let params = SceneParams {
            detect: DetectParams {
                theta: 0.12,
                ..DetectParams::default()
            },
            ..SceneParams::default()
        };
        let (d, _) = detect_scene(&aerial, None, None, &params).expect("detection");
        let tp = TargetParams::default();
        let site = Site::from_classified(&aerial, &tp).expect("a site");
        // Offline, as `skyground detect`.
        let (mut offline, _) = generate(&d, &site, &tp).expect("targets");
        offline.points = consolidate(&offline.points, &d.missing_points(), &site, &tp).0;
        // Online, as target_generator.
        let (points, plans) = through_the_topics(&d, aerial.origin);
        assert_eq!(points, d.missing_points());
        let (mut online, _) = generate_from_missing(&points, &plans, &site, &tp).expect("targets");
        online.points = consolidate(&online.points, &points, &site, &tp).0;
        println!(
            "{} missing points → {} target points, {} regions",
            points.len(),
            offline.points.len(),
            offline.regions.len()
        );
        assert!(offline.points.len() > 20 && !offline.regions.is_empty());
        assert_eq!(online, offline);
    }

    #[test]
    fn missing_points_without_their_columns_are_an_error() {
        let mut c = Cloud::from_xyz(vec![[1.0, 2.0, 3.0]]);
        c.building = Some(vec![4]);
        let msg =
            crate::convert::pointcloud2::encode(&c, Header::default(), &EncodeOptions::default());
        let e = missing_from_message(&decode(&msg).expect("decodes")).expect_err("no normals");
        assert!(e.contains("`nx`"), "{e}");
    }
}
