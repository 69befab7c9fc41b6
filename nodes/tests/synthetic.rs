//! Conformance cases no file in `../shared/data/conformance` covers, each
//! file built here in a temporary folder and run through the `skyground`
//! command a user would run on it (issue 49): a LAS 1.2 with a return
//! number of 7 through `classify`, a LAZ with variable-size chunks and no
//! chunk table, 3dfier's OBJ (classes as `usemtl` materials), `reconstruct`
//! on a cloud labelled only unclassified.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use skyground_core::cloud::{Cloud, read_cloud, write_cloud};

/// The repository root (classify finds its shipped model there).
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A fresh scratch folder for `name`.
fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("synthetic")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

fn skyground(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_skyground"))
        .args(args)
        .current_dir(root())
        .env_remove("RUST_LOG")
        .output()
        .expect("skyground runs")
}

fn text(o: &Output) -> String {
    format!(
        "exit {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// No panic, and no `.part` file left anywhere under `dir`.
fn clean(o: &Output, dir: &Path) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "{}", text(o));
    let parts: Vec<PathBuf> = walk(dir)
        .into_iter()
        .filter(|p| p.to_string_lossy().ends_with(".part"))
        .collect();
    assert!(parts.is_empty(), "left behind: {parts:?}\n{}", text(o));
}

/// Writes `points` as a LAS 1.2 file `name` in `dir`, runs `skyground CMD
/// --in FILE --out dir/out`, and checks it neither panicked nor left a
/// `.part`; returns the input, the output path and the run.
fn run_on_las12(
    cmd: &str,
    dir: &Path,
    name: &str,
    points: &[Pt],
    out: &str,
) -> (PathBuf, PathBuf, Output) {
    let input = dir.join(name);
    std::fs::write(&input, las12(points)).expect("write input");
    let out = dir.join(out);
    let o = skyground(&[
        cmd,
        "--in",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    clean(&o, dir);
    assert!(o.status.success(), "{}", text(&o));
    (input, out, o)
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}

/// One point of a LAS 1.2 point format 1 record.
struct Pt {
    xyz: [f64; 3],
    ret: u8,
    of: u8,
    class: u8,
}

/// A LAS 1.2 file, point format 1 (28-byte records), millimetre scale, no VLRs.
fn las12(points: &[Pt]) -> Vec<u8> {
    let (scale, offset): (f64, [f64; 3]) = (0.001, [1000.0, 2000.0, 0.0]);
    let mut h = vec![0u8; 227];
    h[..4].copy_from_slice(b"LASF");
    (h[24], h[25]) = (1, 2);
    h[26..26 + 9].copy_from_slice(b"synthetic");
    h[94..96].copy_from_slice(&227u16.to_le_bytes());
    h[96..100].copy_from_slice(&227u32.to_le_bytes());
    h[104] = 1;
    h[105..107].copy_from_slice(&28u16.to_le_bytes());
    h[107..111].copy_from_slice(&(points.len() as u32).to_le_bytes());
    for p in points {
        // The 1.2 header counts returns 1-5 only; a 6th or 7th is in no slot.
        if (1..=5).contains(&p.ret) {
            let at = 111 + 4 * usize::from(p.ret - 1);
            let n = u32::from_le_bytes(h[at..at + 4].try_into().unwrap()) + 1;
            h[at..at + 4].copy_from_slice(&n.to_le_bytes());
        }
    }
    for (k, off) in offset.iter().enumerate() {
        let at = 131 + 8 * k;
        h[at..at + 8].copy_from_slice(&scale.to_le_bytes());
        h[at + 24..at + 32].copy_from_slice(&off.to_le_bytes());
        let lo = points
            .iter()
            .map(|p| p.xyz[k])
            .fold(f64::INFINITY, f64::min);
        let hi = points
            .iter()
            .map(|p| p.xyz[k])
            .fold(f64::NEG_INFINITY, f64::max);
        let at = 179 + 16 * k;
        h[at..at + 8].copy_from_slice(&hi.to_le_bytes());
        h[at + 8..at + 16].copy_from_slice(&lo.to_le_bytes());
    }
    for (i, p) in points.iter().enumerate() {
        for (x, off) in p.xyz.iter().zip(offset) {
            let v = ((x - off) / scale).round() as i32;
            h.extend(v.to_le_bytes());
        }
        h.extend(100u16.to_le_bytes());
        h.push((p.ret & 7) | ((p.of & 7) << 3));
        h.push(p.class);
        h.extend([0u8, 0]);
        h.extend(1u16.to_le_bytes());
        h.extend((i as f64 * 1e-4).to_le_bytes());
    }
    h
}

/// A 60 m square of ground (0.5 m grid) with a 12 × 10 × 7 m box building
/// in it (walls and roof every 0.3 m), in LAS coordinates around (1030, 2030).
fn block() -> Vec<[f64; 3]> {
    let (x0, y0, w, d, top) = (1024.0, 2025.0, 12.0, 10.0, 7.0);
    let inside = |x: f64, y: f64| x > x0 && x < x0 + w && y > y0 && y < y0 + d;
    let mut out = Vec::new();
    for i in 0..120 {
        for j in 0..120 {
            let (x, y) = (1000.0 + i as f64 * 0.5, 2000.0 + j as f64 * 0.5);
            if !inside(x, y) {
                out.push([x, y, 0.0]);
            }
        }
    }
    out.extend(building(x0, y0, w, d, top));
    out
}

/// Walls and roof of a box building, every 0.3 m.
fn building(x0: f64, y0: f64, w: f64, d: f64, top: f64) -> Vec<[f64; 3]> {
    let step = 0.3;
    let n = |len: f64| (len / step) as usize;
    let mut out = Vec::new();
    for i in 0..=n(w) {
        for j in 0..=n(d) {
            out.push([x0 + i as f64 * step, y0 + j as f64 * step, top]);
        }
    }
    for k in 0..n(top) {
        let z = k as f64 * step;
        for i in 0..=n(w) {
            let x = x0 + i as f64 * step;
            out.extend([[x, y0, z], [x, y0 + d, z]]);
        }
        for j in 0..=n(d) {
            let y = y0 + j as f64 * step;
            out.extend([[x0, y, z], [x0 + w, y, z]]);
        }
    }
    out
}

#[test]
fn classify_copies_a_las_1_2_with_return_7_as_las_1_4_keeping_the_returns() {
    let dir = scratch("return7");
    // Returns 1-7 of 7 in turn: a LAS 1.2 header cannot count the 6th and 7th.
    let points: Vec<Pt> = block()
        .into_iter()
        .enumerate()
        .map(|(i, xyz)| Pt {
            xyz,
            ret: (i % 7) as u8 + 1,
            of: 7,
            class: 1,
        })
        .collect();
    let (input, out, _) = run_on_las12("classify", &dir, "returns7.las", &points, "out.las");
    let bytes = std::fs::read(&out).expect("the classified copy");
    assert_eq!((bytes[24], bytes[25]), (1, 4), "version of the copy");
    assert!(bytes[104] & 0x3f >= 6, "point format {}", bytes[104] & 0x3f);
    let (a, b) = (read_cloud(&input).unwrap(), read_cloud(&out).unwrap());
    assert_eq!(a.len(), b.len());
    assert_eq!(b.return_number, a.return_number);
    assert_eq!(b.number_of_returns, a.number_of_returns);
    assert!(b.return_number.iter().flatten().any(|&r| r == 7));
    assert_eq!(b.xyz, a.xyz, "point order and positions kept");
}

/// `(data offset, data length)` of the LASzip VLR in a LAZ file's bytes.
fn laszip_vlr(bytes: &[u8]) -> (usize, usize) {
    let u16_at = |a: usize| u16::from_le_bytes([bytes[a], bytes[a + 1]]);
    let u32_at = |a: usize| u32::from_le_bytes(bytes[a..a + 4].try_into().unwrap());
    let mut at = usize::from(u16_at(94));
    for _ in 0..u32_at(100) {
        let (user, record, len) = (&bytes[at + 2..at + 18], u16_at(at + 18), u16_at(at + 20));
        if user.starts_with(b"laszip encoded") && record == 22204 {
            return (at + 54, usize::from(len));
        }
        at += 54 + usize::from(len);
    }
    panic!("no LASzip VLR");
}

#[test]
fn a_laz_with_variable_size_chunks_and_no_chunk_table_is_read_or_refused_without_a_panic() {
    let dir = scratch("variable_size");
    let mut cloud = Cloud::from_xyz(
        block()
            .into_iter()
            .map(|p| [(p[0] - 1000.0) as f32, (p[1] - 2000.0) as f32, p[2] as f32])
            .collect(),
    );
    cloud.origin = [1000.0, 2000.0, 0.0];
    let fixed = dir.join("fixed.laz");
    write_cloud(&fixed, &cloud).expect("write LAZ");
    let mut bytes = std::fs::read(&fixed).unwrap();
    let (vlr, len) = laszip_vlr(&bytes);
    assert!(len >= 34);
    // Chunk size u32::MAX: variable-size chunks, whose points only a chunk
    // table counts; the table's offset (the first 8 bytes of the point
    // data) then points past the end of the file: no table.
    bytes[vlr + 12..vlr + 16].copy_from_slice(&u32::MAX.to_le_bytes());
    let data = u32::from_le_bytes(bytes[96..100].try_into().unwrap()) as usize;
    let past = (bytes.len() as i64 + 1000).to_le_bytes();
    bytes[data..data + 8].copy_from_slice(&past);
    let input = dir.join("variable_no_table.laz");
    std::fs::write(&input, &bytes).unwrap();
    let name = "variable_no_table.laz";
    for args in [vec!["info", "--json"], vec!["classify", "--out", "out.laz"]] {
        let (cmd, rest) = (args[0], &args[1..]);
        let mut argv = vec![cmd.to_string()];
        if cmd == "info" {
            argv.push(input.to_string_lossy().into_owned());
        } else {
            argv.extend(["--in".to_string(), input.to_string_lossy().into_owned()]);
        }
        argv.extend(rest.iter().map(|a| match *a {
            "out.laz" => dir.join(a).to_string_lossy().into_owned(),
            a => a.to_string(),
        }));
        let argv: Vec<&str> = argv.iter().map(String::as_str).collect();
        let o = skyground(&argv);
        clean(&o, &dir);
        if o.status.success() {
            // A correct read: every point, where it was.
            let back = read_cloud(&input).expect("read after a successful run");
            assert_eq!(back.len(), cloud.len(), "{}", text(&o));
        } else {
            let err = String::from_utf8_lossy(&o.stderr);
            // Named: the file and what is wrong with it (not the crate's
            // `failed to fill whole buffer`).
            assert!(
                err.contains(name) && err.contains("chunk table"),
                "{}",
                text(&o)
            );
            assert!(!dir.join("out.laz").exists(), "{}", text(&o));
        }
    }
}

/// 3dfier's OBJ output per feature: every vertex, then `o ID` and the class
/// as a material (`mtllib ./3dfier.mtl`, `usemtl Building`, `usemtl Terrain`...).
fn threedfier_obj() -> String {
    let mut v = vec![
        [85_000.0, 446_000.0, 0.0],
        [85_060.0, 446_000.0, 0.0],
        [85_060.0, 446_060.0, 0.0],
        [85_000.0, 446_060.0, 0.0],
    ];
    let mut f =
        String::from("o t1\nusemtl Terrain\nf 1 2 3\nf 1 3 4\no w1\nusemtl Water\nf 1 3 2\n");
    // Two LoD1 blocks (walls and roof as quads).
    for (k, (x, y)) in [(85_010.0, 446_010.0), (85_035.0, 446_030.0)]
        .into_iter()
        .enumerate()
    {
        let b = v.len() + 1;
        for z in [0.0, 9.0] {
            v.extend([
                [x, y, z],
                [x + 12.0, y, z],
                [x + 12.0, y + 8.0, z],
                [x, y + 8.0, z],
            ]);
        }
        f += &format!("o b{k}\nusemtl Building\n");
        for i in 0..4 {
            let j = (i + 1) % 4;
            f += &format!("f {} {} {} {}\n", b + i, b + j, b + j + 4, b + i + 4);
        }
        f += &format!("f {} {} {} {}\n", b + 4, b + 5, b + 6, b + 7);
    }
    let mut s = String::from("mtllib ./3dfier.mtl\n");
    for p in v {
        s += &format!("v {:.3} {:.3} {:.3}\n", p[0], p[1], p[2]);
    }
    s + &f
}

#[test]
fn threedfier_obj_is_read_as_a_scene_with_its_classes() {
    let dir = scratch("3dfier_obj");
    let input = dir.join("3dfier.obj");
    std::fs::write(&input, threedfier_obj()).unwrap();
    let o = skyground(&["info", "--json", input.to_str().unwrap()]);
    clean(&o, &dir);
    assert!(o.status.success(), "{}", text(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("info --json");
    assert_eq!(v["buildings"], 2, "{v}");
    let (lo, hi) = (&v["extent"]["min"], &v["extent"]["max"]);
    // The terrain's 60 m square, water left out.
    for k in 0..2 {
        let span = hi[k].as_f64().unwrap() - lo[k].as_f64().unwrap();
        assert!((span - 60.0).abs() < 0.01, "axis {k}: {v}");
    }
}

#[test]
fn reconstruct_on_a_cloud_labelled_only_unclassified_uses_every_point() {
    let dir = scratch("unclassified");
    // Only the building's points, all class 1 (as a scanner writes them).
    let points: Vec<Pt> = building(1024.0, 2025.0, 12.0, 10.0, 7.0)
        .into_iter()
        .map(|xyz| Pt {
            xyz,
            ret: 1,
            of: 1,
            class: 1,
        })
        .collect();
    let (_, out, o) = run_on_las12("reconstruct", &dir, "unclassified.las", &points, "models");
    let doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("models.city.json")).unwrap()).unwrap();
    let buildings = doc["CityObjects"].as_object().map_or(0, |o| {
        o.values().filter(|c| c["type"] == "Building").count()
    });
    assert_eq!(buildings, 1, "{}", text(&o));
}
