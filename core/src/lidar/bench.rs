//! The ray-throughput figure, printable without criterion
//! (`skyground bench lidar`).

use std::time::Instant;

use serde::Serialize;

use super::caster::{Caster, CasterError};
use super::pose::Pose;
use super::ray::{Hit, Ray};
use super::spinning::{LidarConfig, cast_revolution, revolution_rays};
use crate::scene::{ObjectKind, Scene};

/// Throughput of spinning-LiDAR ray casting on one scene: the packet path
/// ([`Caster::cast_many`]) and the ray-by-ray path ([`Caster::cast_ray`])
/// measured in the same run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BenchFigures {
    /// Rays per second on all threads of the current rayon pool (packets).
    pub rays_per_s: f64,
    /// Rays per second on one thread (packets).
    pub rays_per_s_single: f64,
    /// Rays per second on all threads, ray by ray (the path before packets).
    pub ray_by_ray_per_s: f64,
    /// Rays per second on one thread, ray by ray.
    pub ray_by_ray_per_s_single: f64,
    /// Threads of the rayon pool.
    pub threads: usize,
    /// Rays in one pass (VLP-16 revolutions from street-level poses).
    pub rays: usize,
    /// Rays of one pass that hit something.
    pub hits: usize,
    /// Rays whose packet hit differs from the ray-by-ray one (a hit against
    /// none, or distances more than 1e-6 m apart). Seen only where two
    /// objects' faces coincide: the distances are then one f32 step apart
    /// (4e-6 m at 40 m) and the order of the tests picks the face.
    pub mismatches: usize,
    /// Triangles indexed.
    pub triangles: usize,
    /// BVH build time, seconds.
    pub build_s: f64,
}

/// Builds a caster over `scene`, then casts VLP-16 revolutions from up to 8
/// street-level poses ([`street_poses`]) for about `seconds` in total: a
/// quarter each for packets and ray by ray, on one thread and on the rayon
/// pool.
pub fn bench_rays(scene: &Scene, seconds: f64) -> Result<BenchFigures, CasterError> {
    let start = Instant::now();
    let caster = Caster::new(scene)?;
    let build_s = start.elapsed().as_secs_f64();
    let config = LidarConfig::default();
    let poses = street_poses(&caster, 8);
    let rays: Vec<Ray> = poses
        .iter()
        .flat_map(|p| revolution_rays(&config, p))
        .collect();
    let revolution = config.columns() * config.beams as usize;
    let packets: Vec<Option<Hit>> = rays
        .chunks(revolution)
        .flat_map(|r| cast_revolution(&caster, &config, r))
        .collect();
    let single = caster.cast_many_single(&rays);
    let hits = packets.iter().flatten().count();
    let mismatches = packets
        .iter()
        .zip(&single)
        .filter(|(a, b)| match (a, b) {
            (Some(a), Some(b)) => (a.t - b.t).abs() > 1e-6,
            (None, None) => false,
            _ => true,
        })
        .count();
    let budget = (seconds / 4.0).max(0.01);
    let count = |h: Vec<Option<Hit>>| h.iter().flatten().count();
    Ok(BenchFigures {
        rays_per_s_single: single_thread(|| {
            throughput(rays.len(), budget, || {
                rays.chunks(revolution)
                    .map(|r| count(cast_revolution(&caster, &config, r)))
                    .sum()
            })
        }),
        rays_per_s: throughput(rays.len(), budget, || {
            rays.chunks(revolution)
                .map(|r| count(cast_revolution(&caster, &config, r)))
                .sum()
        }),
        ray_by_ray_per_s_single: throughput(rays.len(), budget, || {
            rays.iter().filter_map(|r| caster.cast_ray(r)).count()
        }),
        ray_by_ray_per_s: throughput(rays.len(), budget, || count(caster.cast_many_single(&rays))),
        threads: rayon::current_num_threads(),
        rays: rays.len(),
        hits,
        mismatches,
        triangles: caster.triangle_count(),
        build_s,
    })
}

/// Runs `f` on a one-thread rayon pool (on the current one if none can be made).
fn single_thread(f: impl FnOnce() -> f64 + Send) -> f64 {
    match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(pool) => pool.install(f),
        Err(_) => f(),
    }
}

/// Rays per second of `pass` (casting `rays` rays) repeated for `budget` seconds.
fn throughput(rays: usize, budget: f64, mut pass: impl FnMut() -> usize) -> f64 {
    let start = Instant::now();
    let mut passes = 0usize;
    let mut sink = 0usize;
    while passes == 0 || start.elapsed().as_secs_f64() < budget {
        sink = sink.wrapping_add(pass());
        passes += 1;
    }
    std::hint::black_box(sink);
    (rays * passes) as f64 / start.elapsed().as_secs_f64()
}

/// Up to `n` sensor poses 1.8 m above open ground, spread over the scene:
/// candidates on a 7 × 7 grid over the bounds, kept where a vertical ray
/// meets ground first. Falls back to the centre above the scene.
pub fn street_poses(caster: &Caster, n: usize) -> Vec<Pose> {
    let Some((lo, hi)) = caster.bounds() else {
        return vec![Pose::default()];
    };
    let top = hi[2] + 1.0;
    let mut poses = Vec::new();
    for j in 0..7 {
        for i in 0..7 {
            let x = lo[0] + (hi[0] - lo[0]) * (i as f32 + 0.5) / 7.0;
            let y = lo[1] + (hi[1] - lo[1]) * (j as f32 + 0.5) / 7.0;
            let Some(hit) = caster.cast([x, y, top], [0.0, 0.0, -1.0], top - lo[2] + 1.0) else {
                continue;
            };
            let ground = caster
                .object(hit.object)
                .is_some_and(|o| o.kind == ObjectKind::Ground);
            if ground {
                let yaw = 0.7 * poses.len() as f32;
                poses.push(Pose::new([x, y, top - hit.t + 1.8], yaw));
            }
        }
    }
    if poses.is_empty() {
        let c = std::array::from_fn(|k| 0.5 * (lo[k] + hi[k]));
        return vec![Pose::new(c, 0.0)];
    }
    // Keep n spread over the candidates.
    let m = poses.len();
    (0..n.min(m)).map(|k| poses[k * m / n.min(m)]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CPU seconds of this thread (10 ms ticks), from /proc.
    fn thread_cpu_s() -> f64 {
        let s = std::fs::read_to_string("/proc/thread-self/stat").unwrap_or_default();
        let after = s.rsplit(')').next().unwrap_or("");
        let f: Vec<f64> = after
            .split_whitespace()
            .map(|x| x.parse().unwrap_or(0.0))
            .collect();
        (f.get(11).unwrap_or(&0.0) + f.get(12).unwrap_or(&0.0)) / 100.0
    }

    /// Nodes and triangles visited per ray and CPU-time throughput on one
    /// thread (robust to a busy machine), for tuning the BVH:
    /// `STATS_SIZES=0,200000 cargo test --release -p skyground-core --lib
    /// traversal_stats -- --ignored --nocapture` (0 = the reference scene).
    #[test]
    #[ignore = "prints traversal statistics"]
    fn traversal_stats() {
        let sizes: Vec<usize> = std::env::var("STATS_SIZES")
            .ok()
            .map(|s| s.split(',').filter_map(|v| v.parse().ok()).collect())
            .unwrap_or(vec![0, 200_000, 1_000_000]);
        let budget: f64 = std::env::var("STATS_CPU_S")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(2.0);
        for n in sizes {
            let scene = if n == 0 {
                crate::scene::reference_scene(crate::scene::REFERENCE_SEED)
            } else {
                crate::lidar::synthetic::dense_scene(n, 1)
            };
            let caster = Caster::new(&scene).unwrap();
            let rays: Vec<Ray> = street_poses(&caster, 8)
                .iter()
                .flat_map(|p| revolution_rays(&LidarConfig::default(), p))
                .collect();
            use crate::lidar::bvh::stats::{NODES, TRIS};
            NODES.with(|c| c.set(0));
            TRIS.with(|c| c.set(0));
            let hits = rays.iter().filter_map(|r| caster.cast_ray(r)).count();
            let nodes = NODES.with(|c| c.get()) as f64 / rays.len() as f64;
            let tris = TRIS.with(|c| c.get()) as f64 / rays.len() as f64;
            let cpu_rate = |pass: &dyn Fn() -> usize| {
                let cpu0 = thread_cpu_s();
                let mut passes = 0;
                while thread_cpu_s() - cpu0 < budget {
                    std::hint::black_box(pass());
                    passes += 1;
                }
                (passes * rays.len()) as f64 / (thread_cpu_s() - cpu0) / 1e6
            };
            let by_ray = cpu_rate(&|| rays.iter().filter_map(|r| caster.cast_ray(r)).count());
            println!(
                "{n}: shape {:?}, {hits} hits, {nodes:.1} nodes/ray, {tris:.1} tris/ray, {by_ray:.2} M rays/s ray by ray",
                caster.bvh_shape(),
            );
            let config = LidarConfig::default();
            let revolution = config.columns() * config.beams as usize;
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap();
            for (bc, bb) in [(4, 16), (8, 8), (16, 4), (32, 2), (64, 1)] {
                use crate::lidar::bvh::stats::{PACKET_NODES, PACKET_TRIS, QUADS};
                for c in [&PACKET_NODES, &QUADS, &PACKET_TRIS] {
                    c.with(|c| c.set(0));
                }
                let per = |c: &'static std::thread::LocalKey<std::cell::Cell<u64>>| {
                    c.with(|c| c.get()) as f64 / rays.len() as f64
                };
                let counts = pool.install(|| {
                    for c in [&PACKET_NODES, &QUADS, &PACKET_TRIS] {
                        c.with(|c| c.set(0));
                    }
                    for r in rays.chunks(revolution) {
                        crate::lidar::spinning::cast_blocks(&caster, &config, r, bc, bb);
                    }
                    [per(&PACKET_NODES), per(&QUADS), per(&PACKET_TRIS)]
                });
                println!(
                    "  {bc}x{bb}: per ray {:.3} packet nodes, {:.2} quad tests, {:.2} tris",
                    counts[0], counts[1], counts[2]
                );
                let rate = pool.install(|| {
                    cpu_rate(&|| {
                        rays.chunks(revolution)
                            .map(|r| {
                                crate::lidar::spinning::cast_blocks(&caster, &config, r, bc, bb)
                                    .iter()
                                    .flatten()
                                    .count()
                            })
                            .sum()
                    })
                });
                println!("  packets {bc} columns x {bb} beams: {rate:.2} M rays/s");
            }
        }
    }
}
