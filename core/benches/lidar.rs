//! Ray-casting and LiDAR benchmarks: `cargo bench -p skyground-core --bench lidar`.
//!
//! First prints [`bench_rays`] figures (single thread and the whole pool) for
//! a 1 M-triangle synthetic scene, then runs the criterion groups. Set
//! `SKYGROUND_BENCH_FIGURES_ONLY=1` to stop after the figures.

use std::hint::black_box;

use criterion::{Criterion, Throughput};
use skyground_core::lidar::bench::street_poses;
use skyground_core::lidar::spinning::{cast_revolution, revolution_rays};
use skyground_core::lidar::synthetic::dense_scene;
use skyground_core::lidar::{
    AirborneConfig, CastBackend, Caster, LidarConfig, Ray, airborne_scan, bench_rays, scan,
};
use skyground_core::scene::{REFERENCE_SEED, Scene, reference_scene};

fn print_figures(name: &str, scene: &Scene) {
    match bench_rays(scene, 4.0) {
        Ok(f) => println!(
            "{name}: {} triangles, build {:.3} s; packets {:.2} M rays/s on 1 thread, {:.2} M rays/s on {} threads; ray by ray {:.2} / {:.2} M rays/s; {} of {} rays hit, {} differ",
            f.triangles,
            f.build_s,
            f.rays_per_s_single / 1e6,
            f.rays_per_s / 1e6,
            f.threads,
            f.ray_by_ray_per_s_single / 1e6,
            f.ray_by_ray_per_s / 1e6,
            f.hits,
            f.rays,
            f.mismatches
        ),
        Err(e) => eprintln!("{name}: {e}"),
    }
}

/// Times VLP-16 revolutions from 4 street poses of `caster` as group `name`,
/// one thread and the rayon pool.
fn cast_group(c: &mut Criterion, name: &str, caster: &Caster) {
    let config = LidarConfig::default();
    let rays: Vec<Ray> = street_poses(caster, 4)
        .iter()
        .flat_map(|p| revolution_rays(&config, p))
        .collect();
    let mut g = c.benchmark_group(name);
    g.throughput(Throughput::Elements(rays.len() as u64));
    g.bench_function("one_thread", |b| {
        b.iter(|| rays.iter().filter_map(|r| caster.cast_ray(r)).count())
    });
    g.bench_function("ray_by_ray_pool", |b| {
        b.iter(|| caster.cast_many_single(black_box(&rays)).len())
    });
    let revolution = config.columns() * config.beams as usize;
    g.bench_function("packets", |b| {
        b.iter(|| {
            rays.chunks(revolution)
                .map(|r| cast_revolution(caster, &config, black_box(r)).len())
                .sum::<usize>()
        })
    });
    g.finish();
}

/// The two ray-cast backends side by side on the reference scene (build,
/// then casting), and an airborne survey with the default one.
fn reference(c: &mut Criterion) {
    let reference = reference_scene(REFERENCE_SEED);
    for (name, backend) in [("bvh", CastBackend::Bvh), ("parry", CastBackend::Parry)] {
        let mut g = c.benchmark_group(format!("build_reference/{name}"));
        g.sample_size(10);
        g.bench_function("build", |b| {
            b.iter(|| {
                Caster::with_backend(black_box(&reference), backend).map(|c| c.triangle_count())
            })
        });
        g.finish();
        match Caster::with_backend(&reference, backend) {
            Ok(rc) => cast_group(c, &format!("cast_reference/{name}"), &rc),
            Err(e) => eprintln!("reference scene did not build with {name}: {e}"),
        }
    }
    let Ok(rc) = Caster::new(&reference) else {
        return;
    };
    let mut g = c.benchmark_group("airborne_reference");
    g.sample_size(10);
    g.bench_function("default_survey", |b| {
        b.iter(|| airborne_scan(&rc, &AirborneConfig::default()).map(|c| c.len()))
    });
    g.finish();
}

fn benches(c: &mut Criterion) {
    let scene = dense_scene(1_000_000, 1);
    let mut g = c.benchmark_group("bvh_build");
    g.sample_size(10);
    g.bench_function("dense_1M", |b| {
        b.iter(|| Caster::new(black_box(&scene)).map(|c| c.triangle_count()))
    });
    g.finish();

    let Ok(caster) = Caster::new(&scene) else {
        eprintln!("dense scene did not build");
        return;
    };
    cast_group(c, "cast_dense_1M", &caster);
    let config = LidarConfig::default();
    let poses = street_poses(&caster, 4);
    let mut g = c.benchmark_group("scan_dense_1M");
    g.throughput(Throughput::Elements(
        (config.columns() * config.beams as usize) as u64,
    ));
    g.bench_function("vlp16_revolution", |b| {
        b.iter(|| scan(&caster, &config, &poses[0], 1).map(|s| s.len()))
    });
    g.finish();
}

fn main() {
    print_figures("reference", &reference_scene(REFERENCE_SEED));
    print_figures("dense_200k", &dense_scene(200_000, 1));
    print_figures("dense_1M", &dense_scene(1_000_000, 1));
    if std::env::var_os("SKYGROUND_BENCH_FIGURES_ONLY").is_some() {
        return;
    }
    let mut c = Criterion::default()
        .warm_up_time(std::time::Duration::from_secs(1))
        .measurement_time(std::time::Duration::from_secs(3))
        .configure_from_args();
    reference(&mut c);
    benches(&mut c);
    c.final_summary();
}
