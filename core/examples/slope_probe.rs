//! Temporary probe (not committed): graph edges the vehicle would refuse.
use skyground_core::cloud::read_cloud;
use skyground_core::graph::{GraphParams, GroundGraph};
use skyground_core::lidar::Caster;
use skyground_core::scene::load_scene;
use skyground_core::vehicle::Terrain;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let scene = load_scene(&a[1]).unwrap();
    let cloud = read_cloud(std::path::Path::new(&a[2])).unwrap();
    let sh = [
        (cloud.origin[0] - scene.origin[0]) as f32,
        (cloud.origin[1] - scene.origin[1]) as f32,
        (cloud.origin[2] - scene.origin[2]) as f32,
    ];
    eprintln!(
        "scene origin {:?} cloud origin {:?} shift {sh:?}",
        scene.origin, cloud.origin
    );
    let xyz: Vec<[f32; 3]> = cloud
        .xyz
        .iter()
        .map(|p| [p[0] + sh[0], p[1] + sh[1], p[2] + sh[2]])
        .collect();
    let labels = cloud.label.clone().unwrap();
    let caster = Caster::new(&scene).unwrap();
    let t = Terrain::new(&caster);
    let g = GroundGraph::build_largest(&xyz, &labels, &GraphParams::default()).unwrap();
    eprintln!("{:?}", g.report());
    let maxg = 20f32.to_radians().tan();
    let pos = g.positions();
    let mut bad = 0;
    let mut hist = [0usize; 10];
    let mut shown = 0;
    let edges = g.edges();
    for &(u, v, _) in &edges {
        let (p, q) = (pos[u], pos[v]);
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let len = dx.hypot(dy);
        let (cx, cy) = (dx / len, dy / len);
        let n = (len / 0.1).ceil() as usize;
        let mut worst = 0f32;
        let mut at = [0f32; 2];
        for s in 0..=n {
            let f = s as f32 / n as f32 * len;
            let (x, y) = (p[0] + cx * f, p[1] + cy * f);
            for dir in [1f32, -1.0] {
                let (Some(z0), Some(z1)) = (
                    t.ground_height(x, y),
                    t.ground_height(x + dir * cx, y + dir * cy),
                ) else {
                    continue;
                };
                let gr = (z1 - z0).abs();
                if gr > worst {
                    worst = gr;
                    at = [x, y];
                }
            }
        }
        if worst > maxg {
            bad += 1;
            let deg = worst.atan().to_degrees();
            hist[((deg / 10.0) as usize).min(9)] += 1;
            if shown < 12 && deg > 55.0 {
                shown += 1;
                let zt = |x: f32, y: f32| t.ground_height(x, y);
                let near: Vec<f32> = xyz
                    .iter()
                    .zip(&labels)
                    .filter(|(w, l)| **l == 2 && (w[0] - at[0]).hypot(w[1] - at[1]) < 1.2)
                    .map(|(w, _)| w[2])
                    .collect();
                let lo = near.iter().cloned().fold(f32::INFINITY, f32::min);
                let hi = near.iter().cloned().fold(f32::NEG_INFINITY, f32::max);
                let zs: Vec<String> = (-3..=3)
                    .map(|k| {
                        let f = k as f32 * 0.5;
                        format!(
                            "{:.2}",
                            t.ground_height(at[0] + cx * f, at[1] + cy * f)
                                .unwrap_or(f32::NAN)
                        )
                    })
                    .collect();
                eprintln!(
                    "  prior ground within 1.2 m: {} pts z {lo:.2}..{hi:.2}; terrain along edge every 0.5 m: {zs:?}",
                    near.len()
                );
                eprintln!(
                    "edge {u}-{v}: p {p:?} q {q:?} worst {deg:.0}° at {at:?}; terrain z p {:?} q {:?}",
                    zt(p[0], p[1]),
                    zt(q[0], q[1])
                );
            }
        }
    }
    eprintln!(
        "{bad} of {} edges the vehicle would refuse; by 10° bins {hist:?}",
        edges.len()
    );
}
