//! Wavefront OBJ scenes: `v` vertices and `f` faces grouped by `o`/`g` names.
//!
//! Rules:
//! - An object's kind comes from its name ([`kind_from_name`]): `ground*` /
//!   `terrain*`, `building*`, `tree*` / `vegetation*` (any case). Each
//!   building object is one building; ids 1.. in order of appearance.
//! - `o NAME` and `g NAME` switch to the object of that name (a name seen
//!   again continues its object). A `g` whose name announces no kind inside an
//!   object opened by `o` is a sub-group of it (`o building_3` + `g roof`),
//!   except `g part_NAME` inside a building: a part of that building, its
//!   own object `NAME` with the building's id (a CityJSON BuildingPart, as
//!   [`super::write_obj`] writes it). Any other unknown name follows
//!   [`UnknownObjects`] (default: error), unless a `usemtl` under it names
//!   a class ([`kind_from_material`]: 3dfier writes each object's class as
//!   its material, `o ID` + `usemtl Building`); materials of classes the
//!   vehicle neither drives on nor scans (water, bridges) leave the object out.
//! - Faces before any name belong to an object `building` (one building),
//!   or, after a `usemtl` that names a class, to an object of that class
//!   named by the material (3dfier's output per class has no `o` at all).
//! - Faces are fanned into triangles; indices may be negative (relative) and
//!   written `v`, `v/vt`, `v//vn` or `v/vt/vn`. `vt`, `vn`, other materials,
//!   smoothing groups, lines and points are ignored.
//! - Coordinates are moved to a local frame ([`crate::cloud::origin`] rule)
//!   kept in [`Scene::origin`]; unused vertices are dropped.

use std::collections::HashMap;
use std::path::Path;

use crate::file;
use crate::io::SceneError;
use crate::scene::indexed::{IndexedObject, scene_from_indexed};
use crate::scene::{
    MaterialClass, ObjectKind, Scene, UnknownObjects, kind_from_material, kind_from_name,
};

/// Options for reading OBJ scenes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ObjOptions {
    /// What to do with objects whose name announces no kind.
    pub unknown: UnknownObjects,
}

/// A problem in an OBJ file, on 1-based line `line`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}: {kind}")]
pub struct ObjError {
    /// 1-based line number (the last line for whole-file problems).
    pub line: usize,
    /// What is wrong.
    pub kind: ObjErrorKind,
}

/// What is wrong on an OBJ line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ObjErrorKind {
    /// A token that should be a number is not one.
    #[error("`{token}` is not a number")]
    BadNumber {
        /// The token.
        token: String,
    },
    /// A `v` line with fewer than three coordinates.
    #[error("vertex has {got} coordinates, needs 3")]
    ShortVertex {
        /// Coordinates found.
        got: usize,
    },
    /// A coordinate is NaN, infinite or too large for the local frame.
    #[error("coordinate is not finite or does not fit the local frame")]
    NonFinite,
    /// A face uses index 0 (OBJ counts from 1).
    #[error("face index 0 (OBJ indices start at 1)")]
    ZeroIndex,
    /// A face index points to a vertex not defined before it.
    #[error("face index {index} refers to a missing vertex ({vertices} defined so far)")]
    IndexOutOfRange {
        /// The index as written.
        index: i64,
        /// Vertices defined before this line.
        vertices: usize,
    },
    /// A face with fewer than three vertices.
    #[error("face has {got} vertices, needs 3")]
    ShortFace {
        /// Vertices found.
        got: usize,
    },
    /// An object whose name and materials announce no kind, with [`UnknownObjects::Error`].
    #[error(
        "object `{name}`: name announces no kind (expected ground*/terrain*, building*, tree*/vegetation*)"
    )]
    UnknownObject {
        /// The name.
        name: String,
    },
    /// The file has no faces.
    #[error("no faces")]
    NoFaces,
}

/// Reads an OBJ scene file.
pub fn read_obj(path: &Path, options: &ObjOptions) -> Result<Scene, SceneError> {
    let bytes = file::read(path)?;
    parse_obj(&String::from_utf8_lossy(&bytes), options).map_err(|source| SceneError::Obj {
        path: path.to_path_buf(),
        source,
    })
}

struct Group {
    name: String,
    kind: ObjectKind,
    opened_by_o: bool,
    triangles: Vec<[u32; 3]>,
    /// The group whose building this is a part of (its own index otherwise).
    building: usize,
    /// The line of the `o`/`g` whose name announced no kind, while no
    /// `usemtl` has given one.
    undecided: Option<usize>,
    /// A material of a class left out (water, bridges): its faces are dropped.
    left_out: bool,
    /// Opened by a `usemtl` outside any named object.
    by_material: bool,
}

impl Group {
    fn new(name: String, kind: ObjectKind, opened_by_o: bool, building: usize) -> Group {
        Group {
            name,
            kind,
            opened_by_o,
            triangles: Vec::new(),
            building,
            undecided: None,
            left_out: false,
            by_material: false,
        }
    }

    /// Takes the class a material names.
    fn take(&mut self, class: MaterialClass) {
        match class {
            MaterialClass::Kind(kind) => self.kind = kind,
            MaterialClass::LeftOut => self.left_out = true,
        }
    }
}

/// The name prefix of a `g` that is a part of the building `o` around it.
const PART: &str = "part_";

/// Parses OBJ text into a scene.
pub fn parse_obj(text: &str, options: &ObjOptions) -> Result<Scene, ObjError> {
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut groups: Vec<Group> = Vec::new();
    let mut by_name: HashMap<String, usize> = HashMap::new();
    let mut current: Option<usize> = None;
    let mut last_line = 0;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        last_line = line;
        let err = |kind| ObjError { line, kind };
        let content = raw.split('#').next().unwrap_or_default();
        let mut tokens = content.split_whitespace();
        let Some(tag) = tokens.next() else { continue };
        match tag {
            "v" => {
                let coords: Vec<&str> = tokens.take(3).collect();
                if coords.len() < 3 {
                    return Err(err(ObjErrorKind::ShortVertex { got: coords.len() }));
                }
                let mut p = [0.0; 3];
                for (slot, t) in p.iter_mut().zip(&coords) {
                    *slot = t.parse::<f64>().map_err(|_| {
                        err(ObjErrorKind::BadNumber {
                            token: (*t).to_string(),
                        })
                    })?;
                    if !slot.is_finite() {
                        return Err(err(ObjErrorKind::NonFinite));
                    }
                }
                vertices.push(p);
            }
            "o" | "g" => {
                let name = tokens.next().unwrap_or_default().to_string();
                if name.is_empty() {
                    continue;
                }
                if let Some(&i) = by_name.get(&name) {
                    current = Some(i);
                    continue;
                }
                // A part of the current building: keyed under its building so
                // two buildings may have parts of the same name.
                let root = current.map(|c| groups[c].building);
                if tag == "g"
                    && let Some(part) = name.strip_prefix(PART)
                    && let Some(r) = root.filter(|&r| {
                        groups[r].opened_by_o && groups[r].kind == ObjectKind::Building
                    })
                {
                    let key = format!("{}\0{name}", groups[r].name);
                    current = Some(*by_name.entry(key).or_insert_with(|| {
                        groups.push(Group::new(part.to_string(), ObjectKind::Building, false, r));
                        groups.len() - 1
                    }));
                    continue;
                }
                let kind = match kind_from_name(&name) {
                    Some(kind) => Some(kind),
                    None if tag == "g" && current.is_some_and(|c| groups[c].opened_by_o) => {
                        continue;
                    }
                    // Decided by a `usemtl` under it, or at the end by `options.unknown`.
                    None => None,
                };
                by_name.insert(name.clone(), groups.len());
                current = Some(groups.len());
                let mut g = Group::new(
                    name,
                    kind.unwrap_or(ObjectKind::Building),
                    tag == "o",
                    groups.len(),
                );
                g.undecided = kind.is_none().then_some(line);
                groups.push(g);
            }
            "usemtl" => {
                let material = tokens.next().unwrap_or_default();
                let Some(class) = kind_from_material(material) else {
                    continue;
                };
                match current {
                    Some(c) if groups[c].undecided.is_some() => {
                        groups[c].undecided = None;
                        groups[c].take(class);
                    }
                    // A named object keeps the kind its name gave.
                    Some(c) if !groups[c].by_material => {}
                    // No object named: the material is the object (output per class).
                    _ => current = Some(material_group(&mut groups, &mut by_name, material, class)),
                }
            }
            "f" => {
                let corners = tokens
                    .map(|t| face_index(t, vertices.len()).map_err(err))
                    .collect::<Result<Vec<u32>, _>>()?;
                if corners.len() < 3 {
                    return Err(err(ObjErrorKind::ShortFace { got: corners.len() }));
                }
                let g = match current {
                    Some(g) => g,
                    None => {
                        let name = "building".to_string();
                        by_name.insert(name.clone(), groups.len());
                        groups.push(Group::new(name, ObjectKind::Building, true, groups.len()));
                        *current.insert(groups.len() - 1)
                    }
                };
                if groups[g].left_out {
                    continue;
                }
                let tris = &mut groups[g].triangles;
                tris.extend(
                    (1..corners.len() - 1).map(|i| [corners[0], corners[i], corners[i + 1]]),
                );
            }
            _ => {}
        }
    }
    if options.unknown == UnknownObjects::Error
        && let Some(g) = groups
            .iter()
            .find(|g| g.undecided.is_some() && !g.triangles.is_empty())
    {
        return Err(ObjError {
            line: g.undecided.unwrap_or(last_line),
            kind: ObjErrorKind::UnknownObject {
                name: g.name.clone(),
            },
        });
    }
    let objects: Vec<IndexedObject> = groups
        .into_iter()
        .map(|g| IndexedObject {
            name: g.name,
            kind: g.kind,
            triangles: g.triangles,
            group: g.building,
        })
        .collect();
    let whole_file = |kind| ObjError {
        line: last_line,
        kind,
    };
    scene_from_indexed(&vertices, &objects)
        .ok_or_else(|| whole_file(ObjErrorKind::NoFaces))?
        .map_err(|_| whole_file(ObjErrorKind::NonFinite))
}

/// The object of faces under `usemtl material` outside any named object
/// (found again when the material comes back).
fn material_group(
    groups: &mut Vec<Group>,
    by_name: &mut HashMap<String, usize>,
    material: &str,
    class: MaterialClass,
) -> usize {
    *by_name
        .entry(format!("usemtl\0{material}"))
        .or_insert_with(|| {
            let mut g = Group::new(
                material.to_string(),
                ObjectKind::Building,
                true,
                groups.len(),
            );
            g.by_material = true;
            g.take(class);
            groups.push(g);
            groups.len() - 1
        })
}

/// Resolves one face token (`v`, `v/vt`, `v//vn`, `v/vt/vn`) to a 0-based index.
fn face_index(token: &str, defined: usize) -> Result<u32, ObjErrorKind> {
    let first = token.split('/').next().unwrap_or_default();
    let index: i64 = first.parse().map_err(|_| ObjErrorKind::BadNumber {
        token: token.to_string(),
    })?;
    let out_of_range = || ObjErrorKind::IndexOutOfRange {
        index,
        vertices: defined,
    };
    let resolved = match index {
        0 => return Err(ObjErrorKind::ZeroIndex),
        i if i > 0 => i - 1,
        i => i64::try_from(defined).map_err(|_| out_of_range())? + i,
    };
    if resolved < 0 || resolved >= i64::try_from(defined).unwrap_or(i64::MAX) {
        return Err(out_of_range());
    }
    u32::try_from(resolved).map_err(|_| out_of_range())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = "\
# a tiny scene
mtllib x.mtl
o Terrain
v 0 0 0
v 20 0 0
v 20 20 0
v 0 20 0
vt 0 0
vn 0 0 1
f 1/1/1 2/1/1 3/1/1 4/1/1
o building_a
v 1 1 0
v 3 1 0
v 3 3 0
v 1 3 0
g roof
usemtl red
f -4//1 -3//1 -2//1 -1//1
o building_b
v 10 10 0
v 12 10 0
v 11 11 2
f 9/1 10/1 11/1
o Tree_1
v 5 5 0
v 6 5 0
v 5 6 3
f -3 -2 -1
o building_a
f 5 7 8
";

    #[test]
    fn objects_kinds_ids_and_index_forms() {
        let s = parse_obj(SCENE, &ObjOptions::default()).unwrap_or_default();
        let names: Vec<(&str, ObjectKind, u32)> = s
            .objects
            .iter()
            .map(|o| (o.name.as_str(), o.kind, o.building))
            .collect();
        assert_eq!(
            names,
            [
                ("Terrain", ObjectKind::Ground, 0),
                ("building_a", ObjectKind::Building, 1),
                ("building_b", ObjectKind::Building, 2),
                ("Tree_1", ObjectKind::Vegetation, 0),
            ]
        );
        // Quads fanned into two triangles; building_a continued at the end.
        assert_eq!(s.object_triangles(0).count(), 2);
        assert_eq!(s.object_triangles(1).count(), 3);
        assert_eq!(s.object_triangles(2).count(), 1);
        assert_eq!(s.origin, [0.0; 3]);
        assert_eq!(s.validate(), Ok(()));
        let [_, _, c] = s
            .triangle_corners(s.object_triangles(2).next().unwrap_or(0))
            .unwrap_or_default();
        assert_eq!(c, [11.0, 11.0, 2.0]);
    }

    #[test]
    fn faces_without_a_name_make_one_building_and_large_coordinates_move() {
        let s = parse_obj("v 2600000.5 1200000.25 400\nv 2600001.5 1200000.25 400\nv 2600000.5 1200001.25 401\nf 1 2 3\n", &ObjOptions::default())
            .unwrap_or_default();
        assert_eq!(s.building_count(), 1);
        assert_eq!(s.origin, [2_600_000.0, 1_200_000.0, 0.0]);
        assert_eq!(s.vertices[0], [0.5, 0.25, 400.0]);
    }

    /// 3dfier's OBJ: every vertex first, then `o ID` and the class as a material.
    const THREEDFIER: &str = "\
mtllib ./3dfier.mtl
v 0 0 0
v 30 0 0
v 30 30 0
v 0 30 0
v 10 10 0
v 14 10 0
v 14 14 6
v 20 20 0
v 22 20 0
v 22 22 0
o b1000
usemtl Building
f 5 6 7
o t2000
usemtl Terrain
f 1 2 3
f 1 3 4
o w3000
usemtl Water
f 8 9 10
o r4000
usemtl Road
f 8 10 9
";

    /// Each object's name and kind, in file order.
    fn kinds_of(s: &Scene) -> Vec<(&str, ObjectKind)> {
        s.objects
            .iter()
            .map(|o| (o.name.as_str(), o.kind))
            .collect()
    }

    #[test]
    fn objects_whose_class_is_their_material_are_read_by_it() {
        let s = parse_obj(THREEDFIER, &ObjOptions::default()).unwrap_or_default();
        let kinds = kinds_of(&s);
        // Water is left out, as the CityJSON reader leaves out a WaterBody.
        assert_eq!(
            kinds,
            [
                ("b1000", ObjectKind::Building),
                ("t2000", ObjectKind::Ground),
                ("r4000", ObjectKind::Ground),
            ]
        );
        assert_eq!(s.building_count(), 1);
        assert_eq!(s.object_triangles(1).count(), 2);
        // Per class (no `o`): each material is one object.
        let per_class = THREEDFIER
            .lines()
            .filter(|l| !l.starts_with("o "))
            .collect::<Vec<_>>()
            .join("\n");
        let s = parse_obj(&per_class, &ObjOptions::default()).unwrap_or_default();
        let kinds = kinds_of(&s);
        assert_eq!(
            kinds,
            [
                ("Building", ObjectKind::Building),
                ("Terrain", ObjectKind::Ground),
                ("Road", ObjectKind::Ground),
            ]
        );
        // A material that names no class decides nothing: still refused, at the `o`.
        let e = err("v 0 0 0\nv 1 0 0\nv 0 1 0\no b1\nusemtl red\nf 1 2 3\n");
        assert_eq!(e.line, 4);
        assert!(e.to_string().contains("b1"), "{e}");
    }

    fn err(text: &str) -> ObjError {
        parse_obj(text, &ObjOptions::default())
            .err()
            .unwrap_or(ObjError {
                line: 0,
                kind: ObjErrorKind::NoFaces,
            })
    }

    #[test]
    fn errors_name_the_line() {
        let v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        assert_eq!(err(&format!("{v3}f 1 2 0\n")).kind, ObjErrorKind::ZeroIndex);
        assert_eq!(
            err(&format!("{v3}f 1 2 4\n")),
            ObjError {
                line: 4,
                kind: ObjErrorKind::IndexOutOfRange {
                    index: 4,
                    vertices: 3
                }
            }
        );
        assert_eq!(
            err(&format!("{v3}f -4 1 2\n")).kind,
            ObjErrorKind::IndexOutOfRange {
                index: -4,
                vertices: 3
            }
        );
        assert_eq!(
            err(&format!("{v3}f 1 2\n")).kind,
            ObjErrorKind::ShortFace { got: 2 }
        );
        assert_eq!(err("v 0 0\n").kind, ObjErrorKind::ShortVertex { got: 2 });
        assert_eq!(err("v 0 x 0\n").line, 1);
        assert_eq!(err("v 0 nan 0\n").kind, ObjErrorKind::NonFinite);
        assert_eq!(err(v3).kind, ObjErrorKind::NoFaces);
        let unknown = err(&format!("{v3}o Cube.001\nf 1 2 3\n"));
        assert_eq!(unknown.line, 4);
        assert!(unknown.to_string().contains("Cube.001"));
        let lenient = ObjOptions {
            unknown: UnknownObjects::Building,
        };
        let s = parse_obj(
            &format!("{v3}g Cube.001\nf 1 2 3\ng Cube.002\nf 3 2 1\n"),
            &lenient,
        )
        .unwrap_or_default();
        assert_eq!(s.building_count(), 2);
        // Under `o`, an unknown `g` is a sub-group of the object.
        let s = parse_obj(
            &format!("{v3}o Cube.001\nf 1 2 3\ng Cube.002\nf 3 2 1\n"),
            &lenient,
        )
        .unwrap_or_default();
        assert_eq!(s.building_count(), 1);
    }
}

#[cfg(test)]
mod props {
    use super::*;

    proptest::proptest! {
        #[test]
        fn random_lines_never_panic(lines in proptest::collection::vec("(v|f|o|g|vt|#)( -?[0-9]{1,3}(/[0-9]?)?(/[0-9])?| building| tree| x){0,5}", 0..30)) {
            let text = lines.join("\n");
            let _ = parse_obj(&text, &ObjOptions::default());
        }
    }
}
