//! The reference scene as the planners see it, shared by `plan.rs`,
//! `explore.rs` and the plan bench: the mesh, its caster, the simulated
//! aerial prior (labels are ground truth), wall ground truth, and hand-made
//! targets (the target generator is tested on its own).
#![allow(dead_code)]

use std::sync::OnceLock;

use skyground_core::cloud::class;
use skyground_core::graph::{GraphParams, GroundGraph};
use skyground_core::lidar::{AirborneConfig, Caster, airborne_scan};
use skyground_core::metrics::{GtSamples, SurfaceKind, sample_building_surfaces};
use skyground_core::missing::GroundGrid;
use skyground_core::scene::{ObjectKind, REFERENCE_SEED, Scene, reference_scene};
use skyground_core::targets::{Region, TargetPoint, TargetSet};

/// Everything built once per test binary.
pub struct World {
    pub scene: Scene,
    pub caster: Caster,
    pub xyz: Vec<[f32; 3]>,
    pub labels: Vec<u8>,
    pub gt: GtSamples,
}

/// The shared world (built on first use).
pub fn world() -> &'static World {
    static W: OnceLock<World> = OnceLock::new();
    W.get_or_init(|| {
        let scene = reference_scene(REFERENCE_SEED);
        let caster = Caster::new(&scene).unwrap();
        let cloud = airborne_scan(&caster, &AirborneConfig::default()).unwrap();
        let labels = cloud.label.clone().unwrap();
        let gt = sample_building_surfaces(&scene, 0.25);
        World {
            xyz: cloud.xyz,
            labels,
            gt,
            caster,
            scene,
        }
    })
}

/// The ground graph of the shared world's prior, from [`start`], default parameters.
pub fn graph() -> GroundGraph {
    let w = world();
    GroundGraph::build(&w.xyz, &w.labels, start(w), &GraphParams::default()).unwrap()
}

/// A scene's caster and simulated aerial prior split by its true labels.
pub struct Prior {
    /// The scene's caster (built with the default backend).
    pub caster: Caster,
    /// Every prior point and its LAS class.
    pub xyz: Vec<[f32; 3]>,
    pub labels: Vec<u8>,
    /// Building points (class 6 with a building id) and their ids.
    pub buildings: Vec<[f32; 3]>,
    pub ids: Vec<u32>,
    /// Ground points (class 2).
    pub ground: Vec<[f32; 3]>,
}

impl Prior {
    /// The detector's terrain from the ground points (2 m cells, holes filled 40 deep).
    pub fn terrain(&self) -> GroundGrid {
        GroundGrid::from_points(&self.ground, 2.0, 40).unwrap()
    }
}

/// The default airborne survey of `scene`, split into buildings and ground.
pub fn prior(scene: &Scene) -> Prior {
    let caster = Caster::new(scene).unwrap();
    let cloud = airborne_scan(&caster, &AirborneConfig::default()).unwrap();
    let labels = cloud.label.unwrap();
    let all_ids = cloud.building.unwrap();
    let (mut buildings, mut ids, mut ground) = (Vec::new(), Vec::new(), Vec::new());
    for ((&p, &l), &id) in cloud.xyz.iter().zip(&labels).zip(&all_ids) {
        if l == class::BUILDING && id > 0 {
            buildings.push(p);
            ids.push(id);
        } else if l == class::GROUND {
            ground.push(p);
        }
    }
    Prior {
        caster,
        xyz: cloud.xyz,
        labels,
        buildings,
        ids,
        ground,
    }
}

/// The object kind a ray from above hits first at `xy`.
pub fn kind_below(w: &World, xy: [f32; 2]) -> Option<ObjectKind> {
    let hit = w
        .caster
        .cast([xy[0], xy[1], 400.0], [0.0, 0.0, -1.0], 1000.0)?;
    w.caster.object(hit.object).map(|o| o.kind)
}

/// Ground height at `xy` from the mesh.
pub fn ground_z(w: &World, xy: [f32; 2]) -> f32 {
    w.caster
        .cast([xy[0], xy[1], 400.0], [0.0, 0.0, -1.0], 1000.0)
        .map_or(0.0, |h| 400.0 - h.t)
}

/// Open ground: the point and a ring of 8 points `r` around it see ground from above.
pub fn open_ground(w: &World, xy: [f32; 2], r: f32) -> bool {
    (0..9).all(|k| {
        let a = k as f32 * std::f32::consts::TAU / 8.0;
        let rr = if k == 8 { 0.0 } else { r };
        kind_below(w, [xy[0] + rr * a.cos(), xy[1] + rr * a.sin()]) == Some(ObjectKind::Ground)
    })
}

/// A start on open ground in the middle of the scene.
pub fn start(w: &World) -> [f32; 3] {
    for k in 0..400 {
        let xy = [96.0 + (k % 20) as f32, 96.0 + (k / 20) as f32];
        if open_ground(w, xy, 3.0) {
            return [xy[0], xy[1], ground_z(w, xy)];
        }
    }
    panic!("no open ground near the centre");
}

/// Point targets 8 m in front of wall samples (1–3 m up), on open ground 2 m
/// around, at most `per_building`, at least 12 m apart.
pub fn point_targets(w: &World, per_building: usize) -> Vec<TargetPoint> {
    let mut out: Vec<TargetPoint> = Vec::new();
    let gt = &w.gt;
    for i in (0..gt.len()).step_by(37) {
        let (p, n, b) = (gt.xyz[i], gt.normal[i], gt.building[i]);
        if gt.kind[i] != SurfaceKind::Wall || n[2].abs() > 0.2 {
            continue;
        }
        let g = ground_z(w, [p[0], p[1]]);
        if !(1.0..3.0).contains(&(p[2] - g)) {
            continue;
        }
        let h = (n[0] * n[0] + n[1] * n[1]).sqrt();
        let xy = [p[0] + 8.0 * n[0] / h, p[1] + 8.0 * n[1] / h];
        if out.iter().filter(|t| t.building == b).count() >= per_building
            || out
                .iter()
                .any(|t| (t.xyz[0] - xy[0]).hypot(t.xyz[1] - xy[1]) < 12.0)
            || !open_ground(w, xy, 2.0)
        {
            continue;
        }
        out.push(TargetPoint {
            xyz: [xy[0], xy[1], ground_z(w, xy)],
            building: b,
        });
    }
    out
}

/// Bounding box (xy) of a building's ground-truth samples.
pub fn building_box(w: &World, b: u32) -> ([f32; 2], [f32; 2]) {
    let mut lo = [f32::INFINITY; 2];
    let mut hi = [f32::NEG_INFINITY; 2];
    for (p, &bb) in w.gt.xyz.iter().zip(&w.gt.building) {
        if bb == b {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    (lo, hi)
}

/// A square region around the (max x, max y) corner of building `b`: `inside`
/// metres over the building, `outside` metres beyond it.
pub fn corner_region(w: &World, b: u32, inside: f64, outside: f64) -> Region {
    let (_, hi) = building_box(w, b);
    let (cx, cy) = (f64::from(hi[0]), f64::from(hi[1]));
    Region {
        building: b,
        polygon: vec![
            [cx - inside, cy - inside],
            [cx + outside, cy - inside],
            [cx + outside, cy + outside],
            [cx - inside, cy + outside],
        ],
        z: ground_z(w, [hi[0], hi[1]]),
    }
}

/// Building id of the first object whose name contains `part`.
pub fn building_named(w: &World, part: &str) -> u32 {
    w.scene
        .objects
        .iter()
        .find(|o| o.name.contains(part))
        .map(|o| o.building)
        .unwrap()
}

/// A realistic target set: up to 3 points per building and regions at three corners.
pub fn target_set(w: &World) -> TargetSet {
    let regions = [2u32, 9, 16]
        .iter()
        .map(|&b| corner_region(w, b, 6.0, 10.0))
        .collect();
    TargetSet {
        points: point_targets(w, 3),
        regions,
    }
}
