//! Our ear clipper against geo's `TriangulateEarcut` on every surface of real
//! city models made by others (delft.json, zurich_subset_lod2.json):
//! `cargo bench -p skyground-core --bench earcut`. Before timing it prints,
//! per triangulator, the surfaces whose triangles leave out one of the
//! surface's vertices, or put one inside a triangle's edge (T-junctions in
//! a solid: not watertight), or whose area is off by more than 0.1 %.
//! Issue 51 asks for geo's unless this shows ours is needed.

use std::hint::black_box;
use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use geo::{Coord, LineString, Polygon, TriangulateEarcut};
use serde_json::Value;
use skyground_core::scene::polygon::triangulate_2d;

/// A surface projected onto its plane: points, and rings of indices (outer first).
type Surface = (Vec<[f64; 2]>, Vec<Vec<usize>>);

/// Every surface of every geometry of a CityJSON file, on its own plane.
fn surfaces(path: &Path) -> Vec<Surface> {
    let Ok(text) = std::fs::read_to_string(path) else {
        return Vec::new();
    };
    let Ok(doc) = serde_json::from_str::<Value>(&text) else {
        return Vec::new();
    };
    let scale = |k: usize| doc["transform"]["scale"][k].as_f64().unwrap_or(1.0);
    let verts: Vec<[f64; 3]> = doc["vertices"]
        .as_array()
        .map(|v| {
            v.iter()
                .map(|p| [0, 1, 2].map(|k| p[k].as_f64().unwrap_or(0.0) * scale(k)))
                .collect()
        })
        .unwrap_or_default();
    let mut out = Vec::new();
    for obj in doc["CityObjects"]
        .as_object()
        .into_iter()
        .flat_map(|o| o.values())
    {
        for g in obj["geometry"].as_array().into_iter().flatten() {
            collect(&g["boundaries"], &verts, &mut out);
        }
    }
    out
}

/// Walks nested boundaries down to surfaces (arrays of rings of vertex ids).
fn collect(b: &Value, verts: &[[f64; 3]], out: &mut Vec<Surface>) {
    let Some(items) = b.as_array() else { return };
    let is_surface = items
        .first()
        .and_then(|r| r.as_array())
        .and_then(|r| r.first())
        .is_some_and(Value::is_u64);
    if !is_surface {
        return items.iter().for_each(|i| collect(i, verts, out));
    }
    let rings: Vec<Vec<[f64; 3]>> = items
        .iter()
        .map(|r| {
            r.as_array()
                .into_iter()
                .flatten()
                .filter_map(|i| verts.get(i.as_u64()? as usize).copied())
                .collect()
        })
        .collect();
    if rings.first().is_none_or(|r| r.len() < 3) {
        return;
    }
    // Newell's normal; drop its largest axis.
    let mut n = [0.0f64; 3];
    for (a, b) in rings[0].iter().zip(rings[0].iter().cycle().skip(1)) {
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let drop = (0..3)
        .max_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))
        .unwrap_or(2);
    let (u, v) = ((drop + 1) % 3, (drop + 2) % 3);
    let mut pts = Vec::new();
    let mut idx = Vec::new();
    for r in &rings {
        idx.push((pts.len()..pts.len() + r.len()).collect());
        pts.extend(r.iter().map(|p| [p[u], p[v]]));
    }
    out.push((pts, idx));
}

fn ring_area(pts: &[[f64; 2]], ring: &[usize]) -> f64 {
    let a: f64 = ring
        .iter()
        .zip(ring.iter().cycle().skip(1))
        .map(|(&i, &j)| pts[i][0] * pts[j][1] - pts[j][0] * pts[i][1])
        .sum();
    (a / 2.0).abs()
}

fn tri_area(t: [[f64; 2]; 3]) -> f64 {
    ((t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1])).abs()
        / 2.0
}

fn geo_polygon((pts, rings): &Surface) -> Polygon<f64> {
    let ls = |r: &Vec<usize>| {
        LineString::from(
            r.iter()
                .map(|&i| Coord {
                    x: pts[i][0],
                    y: pts[i][1],
                })
                .collect::<Vec<_>>(),
        )
    };
    Polygon::new(ls(&rings[0]), rings[1..].iter().map(ls).collect())
}

/// Twice the signed area of `pqr`.
fn orient(p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> f64 {
    (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
}

/// Whether a vertex of the surface lies inside an edge of a triangle: a
/// T-junction (the neighbouring surface's edge has no partner there).
fn has_t_junction(pts: &[[f64; 2]], tris: &[[[f64; 2]; 3]]) -> bool {
    pts.iter().any(|p| {
        tris.iter().any(|t| {
            (0..3).any(|k| {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let len2 = (b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2);
                let within = (p[0] - a[0]) * (p[0] - b[0]) + (p[1] - a[1]) * (p[1] - b[1]) < 0.0;
                within && orient(a, b, *p).abs() <= 1e-9 * len2.max(1e-12)
            })
        })
    })
}

/// (surfaces with a vertex left out, with a T-junction, with the area off, triangles).
fn check(
    all: &[Surface],
    tris: impl Fn(&Surface) -> Vec<[[f64; 2]; 3]>,
) -> (usize, usize, usize, usize) {
    let (mut dropped, mut tj, mut off, mut count) = (0, 0, 0, 0);
    for s in all {
        let t = tris(s);
        count += t.len();
        let (pts, rings) = s;
        let want =
            ring_area(pts, &rings[0]) - rings[1..].iter().map(|r| ring_area(pts, r)).sum::<f64>();
        let got: f64 = t.iter().map(|&t| tri_area(t)).sum();
        if (got - want).abs() > 1e-3 * want.max(1e-9) {
            off += 1;
        }
        if pts.iter().any(|p| !t.iter().any(|t| t.contains(p))) {
            dropped += 1;
        }
        if has_t_junction(pts, &t) {
            tj += 1;
        }
    }
    (dropped, tj, off, count)
}

fn ours(s: &Surface) -> Vec<[[f64; 2]; 3]> {
    triangulate_2d(&s.0, &s.1)
        .into_iter()
        .map(|t| t.map(|i| s.0[i]))
        .collect()
}

fn geos(s: &Surface) -> Vec<[[f64; 2]; 3]> {
    geo_polygon(s)
        .earcut_triangles()
        .into_iter()
        .map(|t| [t.v1(), t.v2(), t.v3()].map(|c| [c.x, c.y]))
        .collect()
}

fn benches(c: &mut Criterion) {
    let data = std::env::var_os("SKYGROUND_REAL_DATA")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/real"));
    let mut g = c.benchmark_group("earcut");
    g.sample_size(10);
    for file in ["delft.json", "zurich_subset_lod2.json"] {
        let all = surfaces(&data.join(file));
        if all.is_empty() {
            eprintln!("SKIPPED {file}: not found under {}", data.display());
            continue;
        }
        for (name, (d, tj, o, n)) in [("ours", check(&all, ours)), ("geo", check(&all, geos))] {
            eprintln!(
                "{file}: {} surfaces; {name}: {n} triangles, {d} surfaces with a vertex left out, {tj} with a T-junction, {o} with the area off > 0.1 %",
                all.len()
            );
        }
        g.throughput(Throughput::Elements(all.len() as u64));
        g.bench_function(format!("ours/{file}"), |b| {
            b.iter(|| {
                black_box(&all)
                    .iter()
                    .map(|s| triangulate_2d(&s.0, &s.1).len())
                    .sum::<usize>()
            })
        });
        let polys: Vec<Polygon<f64>> = all.iter().map(geo_polygon).collect();
        g.bench_function(format!("geo/{file}"), |b| {
            b.iter(|| {
                black_box(&polys)
                    .iter()
                    .map(|p| p.earcut_triangles_raw().triangle_indices.len())
                    .sum::<usize>()
            })
        });
    }
    g.finish();
}

criterion_group!(earcut, benches);
criterion_main!(earcut);
