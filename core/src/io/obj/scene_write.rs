//! Writing a [`Scene`] as an OBJ file that [`read_obj`](super::scene::read_obj) reads back
//! into the same objects, kinds, building ids and source coordinates.
//!
//! - Vertices are written in source coordinates (local + origin, `f64`), so
//!   the file keeps its georeference; the reader picks its own local frame
//!   by the [`crate::cloud::origin`] rule (the same one when coordinates are
//!   small, as in the reference scene).
//! - One `o` per building (ids ascending, so the reader numbers them the
//!   same), each of its objects (CityJSON BuildingParts: the ground truth
//!   treats them as separate solids) as a `g part_NAME` part when it has
//!   several; then vegetation, then
//!   ground, each `o` named so that [`kind_from_name`] announces its
//!   kind.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::fmt::Write as _;
use std::path::Path;

use crate::file;
use crate::io::SceneError;
use crate::scene::{ObjectKind, Scene, kind_from_name};

/// The scene as OBJ text.
pub fn obj_text(scene: &Scene) -> String {
    let mut out = String::from("# skyground scene\n");
    // Objects grouped as the file's `o` entries: (name, member object indices).
    let mut entries: Vec<(String, Vec<u32>)> = Vec::new();
    let mut used: HashSet<String> = HashSet::new();
    let mut buildings: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for (k, o) in (0u32..).zip(&scene.objects) {
        if o.kind == ObjectKind::Building {
            buildings.entry(o.building).or_default().push(k);
        }
    }
    for members in buildings.values() {
        let first = &scene.objects[members[0] as usize].name;
        entries.push((
            unique(&mut used, ObjectKind::Building, first),
            members.clone(),
        ));
    }
    for kind in [ObjectKind::Vegetation, ObjectKind::Ground] {
        for (k, o) in (0u32..).zip(&scene.objects) {
            if o.kind == kind {
                entries.push((unique(&mut used, kind, &o.name), vec![k]));
            }
        }
    }
    let mut triangles_of: HashMap<u32, Vec<usize>> = HashMap::new();
    for (t, &o) in scene.triangle_object.iter().enumerate() {
        triangles_of.entry(o).or_default().push(t);
    }
    let mut index: HashMap<u32, usize> = HashMap::new();
    for (name, members) in &entries {
        let _ = writeln!(out, "o {name}");
        for &m in members {
            if members.len() > 1 {
                let _ = writeln!(out, "g part_{}", clean(&scene.objects[m as usize].name));
            }
            for &t in triangles_of.get(&m).map_or(&[][..], Vec::as_slice) {
                let mut f = [0usize; 3];
                for (slot, &v) in f.iter_mut().zip(&scene.triangles[t]) {
                    let next = index.len() + 1;
                    *slot = *index.entry(v).or_insert_with(|| {
                        let p = scene.vertices.get(v as usize).copied().unwrap_or_default();
                        let q = [0, 1, 2].map(|k| f64::from(p[k]) + scene.origin[k]);
                        let _ = writeln!(out, "v {} {} {}", q[0], q[1], q[2]);
                        next
                    });
                }
                let _ = writeln!(out, "f {} {} {}", f[0], f[1], f[2]);
            }
        }
    }
    out
}

/// Writes the scene to `path` as OBJ.
pub fn write_obj(path: &Path, scene: &Scene) -> Result<(), SceneError> {
    Ok(file::write(path, obj_text(scene))?)
}

/// A name without whitespace or `#` (OBJ ends names and lines there).
fn clean(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_whitespace() || c == '#' {
                '_'
            } else {
                c
            }
        })
        .collect();
    if s.is_empty() { "unnamed".into() } else { s }
}

/// `name` cleaned, prefixed so it announces `kind`, and unique in the file
/// (a repeated name would merge two objects on reading).
fn unique(used: &mut HashSet<String>, kind: ObjectKind, name: &str) -> String {
    let name = clean(name);
    let base = if kind_from_name(&name) == Some(kind) {
        name
    } else {
        let prefix = match kind {
            ObjectKind::Building => "building",
            ObjectKind::Vegetation => "vegetation",
            ObjectKind::Ground => "ground",
        };
        format!("{prefix}_{name}")
    };
    let mut candidate = base.clone();
    let mut n = 2;
    while !used.insert(candidate.clone()) {
        candidate = format!("{base}_{n}");
        n += 1;
    }
    candidate
}

#[cfg(test)]
mod tests {
    use super::super::scene::{ObjOptions, parse_obj};
    use super::*;
    use crate::scene::{REFERENCE_SEED, reference_scene};

    /// Per building id: (triangles, area), and the kinds' triangle counts.
    fn profile(s: &Scene) -> (BTreeMap<u32, (usize, i64)>, [usize; 3]) {
        let mut per: BTreeMap<u32, (usize, i64)> = BTreeMap::new();
        let mut kinds = [0; 3];
        for t in 0..s.triangles.len() {
            let o = s.triangle_kind(t).unwrap();
            kinds[match o.kind {
                ObjectKind::Ground => 0,
                ObjectKind::Vegetation => 1,
                ObjectKind::Building => 2,
            }] += 1;
            if o.kind == ObjectKind::Building {
                let e = per.entry(o.building).or_default();
                e.0 += 1;
                // Whole cm² so f32 rounding does not count.
                e.1 += (s.triangle_area(t) * 1e4).round() as i64;
            }
        }
        (per, kinds)
    }

    #[test]
    fn reference_scene_round_trips() {
        let scene = reference_scene(REFERENCE_SEED);
        let back = parse_obj(&obj_text(&scene), &ObjOptions::default()).unwrap();
        assert_eq!(back.origin, scene.origin);
        assert_eq!(back.building_ids(), scene.building_ids());
        assert_eq!(back.objects.len(), scene.objects.len());
        assert_eq!(back.triangles.len(), scene.triangles.len());
        let (a, b) = (profile(&scene), profile(&back));
        assert_eq!(a.1, b.1);
        for (id, (n, area)) in &a.0 {
            let (m, back_area) = b.0[id];
            assert_eq!(*n, m, "building {id}");
            assert!(
                (area - back_area).abs() <= 1,
                "building {id}: {area} vs {back_area}"
            );
        }
        assert_eq!(back.bounds(), scene.bounds());
    }

    #[test]
    fn large_coordinates_keep_their_georeference_and_names_are_made_readable() {
        let mut b = crate::scene::SceneBuilder::new([2_683_000.0, 1_247_000.0, 400.0]);
        let mut m = crate::scene::MeshPart::default();
        let r = m.ring(&[[10.0, 20.0], [12.5, 20.0], [12.5, 21.25]], 3.5);
        m.triangle(r[0], r[1], r[2]);
        b.add("UUID 1#a", ObjectKind::Building, 1, &m);
        b.add("UUID 1#a", ObjectKind::Building, 2, &m);
        b.add("UUID 2 part", ObjectKind::Building, 2, &m);
        b.add("terrain", ObjectKind::Ground, 0, &m);
        let scene = b.finish();
        let text = obj_text(&scene);
        assert!(text.contains("o building_UUID_1_a\n"), "{text}");
        assert!(
            text.contains("o building_UUID_1_a_2\ng part_UUID_1_a\n"),
            "{text}"
        );
        let back = parse_obj(&text, &ObjOptions::default()).unwrap();
        assert_eq!(back.building_count(), 2);
        // Building 2's two objects stay two parts of one building.
        let parts: Vec<(&str, u32)> = back
            .objects
            .iter()
            .filter(|o| o.kind == ObjectKind::Building)
            .map(|o| (o.name.as_str(), o.building))
            .collect();
        assert_eq!(
            parts,
            vec![
                ("building_UUID_1_a", 1),
                ("UUID_1_a", 2),
                ("UUID_2_part", 2)
            ]
        );
        assert_eq!(back.object_count(ObjectKind::Ground), 1);
        let source =
            |s: &Scene, v: usize| [0, 1, 2].map(|k| f64::from(s.vertices[v][k]) + s.origin[k]);
        assert_eq!(back.origin, [2_683_010.0, 1_247_020.0, 0.0]);
        assert_eq!(source(&back, 0), [2_683_010.0, 1_247_020.0, 403.5]);
        assert_eq!(source(&back, 2), [2_683_012.5, 1_247_021.25, 403.5]);
    }
}
