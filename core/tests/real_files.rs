//! Reading the real public files in `../shared/data/real` (see its README).
//!
//! The directory is found from `SKYGROUND_REAL_DATA` or, by default, as the
//! workspace's sibling `shared/data/real`. When it is absent each test prints
//! `SKIPPED: ...` to stderr and passes.

use std::collections::BTreeMap;

use skyground_core::cloud::{Cloud, read_cloud, write_cloud};

mod common;
use common::real_file;

fn read(name: &str) -> Option<Cloud> {
    let path = real_file(name)?;
    Some(read_cloud(&path).unwrap_or_else(|e| panic!("{e}")))
}

fn extent(cloud: &Cloud) -> [f32; 3] {
    let (lo, hi) = cloud.bounds().unwrap();
    [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]]
}

fn assert_extent(cloud: &Cloud, want: [f32; 3]) {
    let got = extent(cloud);
    for k in 0..3 {
        assert!(
            (got[k] - want[k]).abs() < 1.0,
            "extent {got:?}, want about {want:?}"
        );
    }
}

fn class_counts(cloud: &Cloud) -> BTreeMap<u8, usize> {
    let mut counts = BTreeMap::new();
    for &c in cloud.label.as_ref().unwrap() {
        *counts.entry(c).or_default() += 1;
    }
    counts
}

#[test]
fn csf_sample_ply_double_xyz() {
    let Some(c) = read("csf_sample.ply") else {
        return;
    };
    assert_eq!(c.len(), 100_000);
    c.validate().unwrap();
    assert_eq!((c.intensity.is_some(), c.label.is_some()), (false, false));
    assert_extent(&c, [235.0, 244.0, 36.0]);
    // First vertex is at (394789.7, 640623.0, 794.1): whole-metre origin from it.
    assert_eq!(c.origin, [394_789.0, 640_623.0, 0.0]);
}

#[test]
fn city3d_ply_with_normals_and_colours() {
    let Some(c) = read("city3d_001.ply") else {
        return;
    };
    assert_eq!(c.len(), 57_379);
    assert_eq!(c.building, None);
    assert_extent(&c, [96.0, 95.0, 20.0]);
}

#[test]
fn sample_c_las_classes() {
    let Some(c) = read("sample_c.las") else {
        return;
    };
    assert_eq!(c.len(), 14_408);
    c.validate().unwrap();
    let want = BTreeMap::from([
        (2, 1_368),
        (3, 93),
        (4, 29),
        (5, 7),
        (6, 12_525),
        (11, 2),
        (14, 45),
        (31, 339),
    ]);
    assert_eq!(class_counts(&c), want);
    assert_extent(&c, [83.0, 75.0, 29.0]);
    // Projected coordinates: the origin carries them, xyz stays local.
    assert!(
        c.origin[0] > 600_000.0 && c.origin[1] > 1_000_000.0,
        "{:?}",
        c.origin
    );
    let (lo, _) = c.bounds().unwrap();
    assert!(lo.iter().all(|v| v.abs() < 1.0), "{lo:?}");
}

#[test]
fn autzen_las_classes() {
    let Some(c) = read("autzen_trim.las") else {
        return;
    };
    assert_eq!(c.len(), 110_000);
    assert_eq!(class_counts(&c), BTreeMap::from([(1, 83_893), (2, 26_107)]));
    // The file is in international feet (its WKT and GeoTIFF keys say so):
    // 1178 × 563 × 114 ft is read as metres.
    assert_extent(&c, [359.1, 171.6, 34.7]);
    // Header offset is 0 there, so the origin is the floored minimum (in feet), in metres.
    let want = [636_001.0 * 0.3048, 848_935.0 * 0.3048, 0.0];
    for (got, want) in c.origin.iter().zip(want) {
        assert!((got - want).abs() < 1e-6, "{:?}", c.origin);
    }
}

#[test]
fn real_cloud_round_trips_through_every_format() {
    let Some(mut c) = read("sample_c.las") else {
        return;
    };
    c.building = Some((0..c.len() as u32).map(|i| i % 5).collect());
    let dir = std::env::temp_dir().join(format!("skyground-real-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["rt.ply", "rt.las", "rt.laz"] {
        let path = dir.join(name);
        write_cloud(&path, &c).unwrap();
        let back = read_cloud(&path).unwrap();
        assert_eq!(back.len(), c.len(), "{name}");
        assert_eq!(back.label, c.label, "{name}");
        assert_eq!(back.building, c.building, "{name}");
        assert_eq!(back.intensity, c.intensity, "{name}");
        for (p, q) in back.xyz.iter().zip(&c.xyz) {
            for k in 0..3 {
                let world = |cl: &Cloud, v: f32| cl.origin[k] + f64::from(v);
                assert!(
                    (world(&back, p[k]) - world(&c, q[k])).abs() < 1e-3,
                    "{name}"
                );
            }
        }
        std::fs::remove_file(&path).unwrap();
    }
    std::fs::remove_dir(&dir).unwrap();
}
