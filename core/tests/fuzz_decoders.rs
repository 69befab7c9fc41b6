//! Mutation fuzzing of every file decoder on stable Rust, inside the
//! workspace's own test build (no second, instrumented build of the
//! dependencies: see docs/conformance.md for why and for the cargo-fuzz
//! targets that do the same with coverage guidance).
//!
//! Each target starts from a seed corpus: the conformance files of its
//! format (`../shared/data/conformance`, `SKYGROUND_CONFORMANCE_DATA`
//! overrides) plus small inputs made here, so it also runs without them.
//! For `SKYGROUND_FUZZ_SECONDS` per target (default 2; CI sets more) it
//! mutates seeds (bit flips, interesting bytes and numbers, cut, duplicated
//! and spliced chunks, truncation) and feeds the decoder. A panic is a
//! crash: its input is saved under `target/tmp/fuzz-crashes/` and the test
//! fails. Executions and crashes per target go to stdout and to
//! `target/tmp/fuzz-report.md`.

use std::io::Cursor;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use skyground_core::cloud::{Cloud, parse_ply, read_las};
use skyground_core::io::parse_geojson;
use skyground_core::io::{CityJsonOptions, ObjOptions, parse_cityjson, parse_obj, parse_ply_mesh};
use skyground_core::rng::Rng;

/// A decoder under test: its name, the extensions of its seed files, its
/// own seeds, and the call (whose result only has to come back).
struct Target {
    name: &'static str,
    extensions: &'static [&'static str],
    seeds: fn() -> Vec<Vec<u8>>,
    run: fn(&[u8]),
}

const TARGETS: [Target; 7] = [
    Target {
        name: "las_laz",
        extensions: &["las", "laz"],
        seeds: las_seeds,
        run: |d| {
            if let Ok(c) = read_las(Cursor::new(d.to_vec())) {
                consistent(&c);
            }
        },
    },
    Target {
        name: "ply_cloud",
        extensions: &["ply"],
        seeds: ply_seeds,
        run: |d| {
            if let Ok(c) = parse_ply(d) {
                consistent(&c);
            }
        },
    },
    Target {
        name: "ply_mesh",
        extensions: &["ply"],
        seeds: ply_seeds,
        run: |d| drop(parse_ply_mesh(d)),
    },
    Target {
        name: "obj",
        extensions: &["obj"],
        seeds: || vec![b"o building_1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".to_vec()],
        run: |d| {
            drop(parse_obj(
                &String::from_utf8_lossy(d),
                &ObjOptions::default(),
            ))
        },
    },
    Target {
        name: "cityjson",
        extensions: &["json"],
        seeds: || vec![CITY.to_vec()],
        run: |d| drop(parse_cityjson(d, &CityJsonOptions::default())),
    },
    Target {
        name: "cityjsonseq",
        extensions: &["jsonl"],
        seeds: || vec![CITY_SEQ.to_vec()],
        run: |d| drop(parse_cityjson(d, &CityJsonOptions::default())),
    },
    Target {
        name: "geojson_footprints",
        extensions: &["geojson"],
        seeds: || vec![GEOJSON.to_vec()],
        run: |d| drop(parse_geojson(d, [0.0; 3])),
    },
];

const CITY: &[u8] = br#"{"type":"CityJSON","version":"2.0","transform":{"scale":[0.001,0.001,0.001],"translate":[0,0,0]},"CityObjects":{"b":{"type":"Building","geometry":[{"type":"Solid","lod":"1","boundaries":[[[[0,1,2,3]],[[4,5,6,7]],[[0,1,5,4]],[[1,2,6,5]],[[2,3,7,6]],[[3,0,4,7]]]]}]}},"vertices":[[0,0,0],[1000,0,0],[1000,1000,0],[0,1000,0],[0,0,1000],[1000,0,1000],[1000,1000,1000],[0,1000,1000]]}"#;
const CITY_SEQ: &[u8] = br#"{"type":"CityJSON","version":"2.0","transform":{"scale":[0.001,0.001,0.001],"translate":[0,0,0]},"CityObjects":{},"vertices":[]}
{"type":"CityJSONFeature","id":"b","CityObjects":{"b":{"type":"Building","geometry":[{"type":"MultiSurface","lod":"1","boundaries":[[[0,1,2]],[[0,2,3]]]}]}},"vertices":[[0,0,0],[1000,0,0],[1000,1000,500],[0,1000,500]]}
"#;
const GEOJSON: &[u8] = br#"{"type":"FeatureCollection","features":[{"type":"Feature","properties":{"id":1},"geometry":{"type":"Polygon","coordinates":[[[0,0],[10,0],[10,8],[0,8],[0,0]]]}}]}"#;

fn consistent(c: &Cloud) {
    assert_eq!(c.validate(), Ok(()), "an accepted cloud is consistent");
}

fn las_seeds() -> Vec<Vec<u8>> {
    let mut c = Cloud::from_xyz(vec![[0.0, 0.0, 0.0], [1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
    c.label = Some(vec![2, 6, 5]);
    c.building = Some(vec![0, 1, 1]);
    [false, true]
        .iter()
        .filter_map(|&z| skyground_core::cloud::write_las(Cursor::new(Vec::new()), &c, z).ok())
        .map(Cursor::into_inner)
        .collect()
}

fn ply_seeds() -> Vec<Vec<u8>> {
    let mut v = vec![
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n".to_vec(),
    ];
    let c = Cloud::from_xyz(vec![[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]]);
    let mut bin = Vec::new();
    if skyground_core::cloud::write_ply(&mut bin, &c).is_ok() {
        v.push(bin);
    }
    v
}

/// Bytes and numbers that break decoders' assumptions.
const BYTES: [u8; 8] = [0, 1, 0x7f, 0x80, 0xff, b'-', b'9', b'\n'];
const NUMBERS: [&[u8]; 8] = [
    b"0",
    b"-1",
    b"4294967296",
    b"1e308",
    b"NaN",
    b"-2147483649",
    b"18446744073709551615",
    b"1e-320",
];

/// One mutation of `input` (spliced with `other`).
fn mutate(input: &[u8], other: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut d = input.to_vec();
    for _ in 0..=rng.below(4) {
        let at = rng.below(d.len() + 1);
        match rng.below(8) {
            0 if !d.is_empty() => {
                let i = at.min(d.len() - 1);
                d[i] ^= 1 << rng.below(8);
            }
            1 if !d.is_empty() => {
                let i = at.min(d.len() - 1);
                d[i] = BYTES[rng.below(BYTES.len())];
            }
            2 => {
                let n = NUMBERS[rng.below(NUMBERS.len())];
                d.splice(at..at, n.iter().copied());
            }
            3 => d.truncate(at),
            4 => {
                let end = (at + rng.below(64)).min(d.len());
                d.drain(at..end);
            }
            5 => {
                let end = (at + rng.below(256)).min(d.len());
                let chunk = d[at..end].to_vec();
                d.splice(at..at, chunk);
            }
            6 if !other.is_empty() => {
                let from = rng.below(other.len());
                let end = (from + rng.below(512)).min(other.len());
                d.splice(at..at, other[from..end].iter().copied());
            }
            _ if d.len() >= 4 => {
                // A little-endian u32 field set to a large value (counts, offsets).
                let at = at.min(d.len() - 4);
                let v = [u32::MAX, 0x7fff_ffff, 0x1000_0000, 0][rng.below(4)];
                d[at..at + 4].copy_from_slice(&v.to_le_bytes());
            }
            _ => d.push(BYTES[rng.below(BYTES.len())]),
        }
    }
    d
}

fn data_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("SKYGROUND_CONFORMANCE_DATA").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/conformance"),
        PathBuf::from,
    );
    dir.is_dir().then_some(dir)
}

/// The target's seeds: its own and the conformance files of its formats
/// (up to 256 KB each: larger files make executions slow, not deeper).
fn corpus(t: &Target, dir: Option<&Path>) -> Vec<Vec<u8>> {
    let mut seeds = (t.seeds)();
    let files = dir.map(|d| std::fs::read_dir(d).into_iter().flatten().flatten());
    for e in files.into_iter().flatten() {
        let p = e.path();
        let ext = p.extension().and_then(|x| x.to_str()).unwrap_or_default();
        if t.extensions.contains(&ext.to_ascii_lowercase().as_str())
            && e.metadata().is_ok_and(|m| m.len() <= 256 * 1024)
            && let Ok(b) = std::fs::read(&p)
        {
            seeds.push(b);
        }
    }
    seeds
}

/// Executions and crashing inputs of one target over `budget`.
fn fuzz(t: &Target, seeds: &[Vec<u8>], budget: Duration, rng: &mut Rng) -> (u64, Vec<Vec<u8>>) {
    let (mut runs, mut crashes) = (0u64, Vec::new());
    let end = Instant::now() + budget;
    // Every seed as it is first, then mutations until the time is up.
    let mut queue: Vec<Vec<u8>> = seeds.to_vec();
    while Instant::now() < end && crashes.len() < 8 {
        let input = queue.pop().unwrap_or_else(|| {
            let a = &seeds[rng.below(seeds.len())];
            let b = &seeds[rng.below(seeds.len())];
            mutate(a, b, rng)
        });
        runs += 1;
        if catch_unwind(AssertUnwindSafe(|| (t.run)(&input))).is_err() {
            crashes.push(input);
        }
    }
    (runs, crashes)
}

#[test]
fn no_decoder_panics_on_mutated_inputs() {
    let seconds: f64 = std::env::var("SKYGROUND_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2.0);
    let dir = data_dir();
    if dir.is_none() {
        eprintln!("NOTE: ../shared/data/conformance not found: own seeds only");
    }
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let crash_dir = out.join("fuzz-crashes");
    // Caught panics are counted, not printed one by one.
    std::panic::set_hook(Box::new(|_| {}));
    let mut report = String::from(
        "| target | seeds | executions | executions/s | crashes |\n|---|---|---|---|---|\n",
    );
    let mut failed = Vec::new();
    for (k, t) in TARGETS.iter().enumerate() {
        let seeds = corpus(t, dir.as_deref());
        let mut rng = Rng::keyed(0xF022, k as u64);
        let started = Instant::now();
        let (runs, crashes) = fuzz(t, &seeds, Duration::from_secs_f64(seconds), &mut rng);
        let rate = runs as f64 / started.elapsed().as_secs_f64();
        report.push_str(&format!(
            "| {} | {} | {runs} | {rate:.0} | {} |\n",
            t.name,
            seeds.len(),
            crashes.len()
        ));
        for (i, c) in crashes.iter().enumerate() {
            let _ = std::fs::create_dir_all(&crash_dir);
            let path = crash_dir.join(format!("{}-{i}", t.name));
            let _ = std::fs::write(&path, c);
            failed.push(path.display().to_string());
        }
    }
    let _ = std::panic::take_hook();
    println!("{report}");
    let _ = std::fs::write(out.join("fuzz-report.md"), &report);
    assert!(
        failed.is_empty(),
        "decoders panicked; inputs saved (replay with the target's call):\n{}\n{report}",
        failed.join("\n")
    );
}
