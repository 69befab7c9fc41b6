//! CRS and units on the real files in feet (`../shared/data/real`, see its
//! README): units read from their WKT and GeoTIFF records, metres inside, and
//! written files that keep the records and the feet.

use std::path::{Path, PathBuf};

use skyground_core::cloud::{Cloud, read_cloud, write_cloud};
use skyground_core::crs::{LinearUnit, UnitSource};

mod common;
use common::real_file;

/// The LASF_Projection records of a LAS file, as (record id, data).
fn projection_records(path: &Path) -> Vec<(u16, Vec<u8>)> {
    let reader = las::Reader::from_path(path).unwrap();
    reader
        .header()
        .all_vlrs()
        .filter(|v| v.user_id == "LASF_Projection")
        .map(|v| (v.record_id, v.data.clone()))
        .collect()
}

/// Header bounds (min, max) of a LAS file, in its own unit.
fn file_bounds(path: &Path) -> ([f64; 3], [f64; 3]) {
    let reader = las::Reader::from_path(path).unwrap();
    let b = reader.header().bounds();
    ([b.min.x, b.min.y, b.min.z], [b.max.x, b.max.y, b.max.z])
}

fn extent_m(c: &Cloud) -> [f32; 3] {
    let (lo, hi) = c.bounds().unwrap();
    [0, 1, 2].map(|k| hi[k] - lo[k])
}

fn assert_near<const N: usize>(got: [f64; N], want: [f64; N], tol: f64, what: &str) {
    for k in 0..N {
        assert!(
            (got[k] - want[k]).abs() <= tol,
            "{what}: {got:?} vs {want:?}"
        );
    }
}

/// Writes `c` as LAS and LAZ; each keeps the input's records and feet.
fn assert_written_in_feet(input: &Path, c: &Cloud, test: &str) {
    let dir = std::env::temp_dir().join(format!("skyground-crs-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["out.las", "out.laz"] {
        let out = dir.join(name);
        write_cloud(&out, c).unwrap();
        assert_eq!(
            projection_records(&out),
            projection_records(input),
            "{name}"
        );
        let (lo, hi) = file_bounds(&out);
        let (want_lo, want_hi) = file_bounds(input);
        assert_near(lo, want_lo, 0.002, "min in feet");
        assert_near(hi, want_hi, 0.002, "max in feet");
        let back = read_cloud(&out).unwrap();
        assert_eq!(back.crs, c.crs, "{name}");
        assert_near(back.origin, c.origin, 1e-6, "origin in metres");
        std::fs::remove_file(&out).unwrap();
    }
    std::fs::remove_dir(&dir).unwrap();
}

/// Real file `name` read, after checking that its CRS is `crs_name` with
/// x, y and z in `unit` (as its WKT says) and that its extent, `extent` in
/// that unit, is read as metres.
fn read_in_feet(
    name: &str,
    unit: LinearUnit,
    crs_name: &str,
    extent: [f64; 3],
) -> Option<(PathBuf, Cloud)> {
    let path = real_file(name)?;
    let c = read_cloud(&path).unwrap();
    let crs = c.crs.clone().expect("the file has WKT and GeoTIFF records");
    assert_eq!((&crs.horizontal_unit, &crs.vertical_unit), (&unit, &unit));
    assert_eq!(crs.unit_source, UnitSource::Wkt);
    assert_eq!(crs.name.as_deref(), Some(crs_name));
    let e = extent_m(&c).map(f64::from);
    assert_near(
        e,
        extent.map(|v| v * unit.to_metre()),
        0.01,
        "extent in metres",
    );
    Some((path, c))
}

#[test]
fn nebraska_us_survey_feet_in_metres_inside_and_feet_outside() {
    // Header: 2445180–2445239.99 × 604300–604339.98 × 1352.7–1403.96 ftUS.
    let Some((path, c)) = read_in_feet(
        "laspy_nebraska_ftus.las",
        LinearUnit::UsSurveyFoot,
        "NAD83_2011_Nebraska_ft",
        [59.99, 39.98, 51.26],
    ) else {
        return;
    };
    let first = c.source_coordinates(c.xyz[0]);
    let (lo, hi) = file_bounds(&path);
    for k in 0..3 {
        assert!(
            first[k] >= lo[k] - 1e-3 && first[k] <= hi[k] + 1e-3,
            "{first:?}"
        );
    }
    assert_written_in_feet(&path, &c, "nebraska");
}

#[test]
fn autzen_international_feet_in_metres_inside_and_feet_outside() {
    // 1178 × 563 × 114 ft (PDAL's test file; its README said metres).
    let Some((path, c)) = read_in_feet(
        "autzen_trim.las",
        LinearUnit::Foot,
        "NAD_1983_HARN_Lambert_Conformal_Conic",
        [1177.46, 562.70, 114.25],
    ) else {
        return;
    };
    assert_written_in_feet(&path, &c, "autzen");
}

#[test]
fn files_without_crs_stay_unknown_and_metric() {
    let Some(path) = real_file("sample_c.las") else {
        return;
    };
    let c = read_cloud(&path).unwrap();
    assert_eq!(c.crs, None);
    assert_eq!(c.to_metre(), [1.0; 3]);
    let Some(path) = real_file("ign_montpellier_150x100m.laz") else {
        return;
    };
    let c = read_cloud(&path).unwrap();
    let crs = c.crs.unwrap();
    assert_eq!(crs.epsg, Some(2154));
    assert!(crs.is_metric());
}
