//! City model files as one model: a CityJSON file, a CityJSONSeq stream (a
//! `CityJSON` header line with `transform` and `metadata`, then one
//! `CityJSONFeature` per line, as 3DBAG serves it), or several of either
//! (tiles), merged in one frame with real (decompressed) coordinates.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use super::boundaries::map_indices;
use super::error::CityJsonError;
use super::model::{CityObject, Document, Transform};
use crate::file;
use crate::io::SceneError;

/// City object types that are buildings (their parts included).
pub const BUILDING_TYPES: &[&str] = &["Building", "BuildingPart"];
/// City object types whose surfaces are ground the vehicle may drive on.
pub const GROUND_TYPES: &[&str] = &[
    "TINRelief",
    "LandUse",
    "Road",
    "TransportSquare",
    "PlantCover",
];

/// The buildings and ground surfaces of one or more city model files.
#[derive(Debug, Clone, Default)]
pub struct CityModel {
    /// Building and ground objects by id; boundaries index `vertices`.
    pub objects: BTreeMap<String, CityObject>,
    /// Real coordinates in the source CRS.
    pub vertices: Vec<[f64; 3]>,
    /// The first file's `transform` (how a writer compresses again).
    pub transform: Option<Transform>,
    /// The CRS the files name (`metadata.referenceSystem`), if any.
    pub reference_system: Option<String>,
    /// Objects left out because an earlier file (tile) had the same id.
    pub duplicates: usize,
}

/// Reads city model files (CityJSON or CityJSONSeq each) as one model; every
/// file that names a CRS must name the same one.
pub fn read_city_model(paths: &[PathBuf]) -> Result<CityModel, SceneError> {
    let mut model = CityModel::default();
    let mut first_crs: Option<(PathBuf, String)> = None;
    for path in paths {
        let data = file::read(path)?;
        let file_err = |source| SceneError::CityJson {
            path: path.clone(),
            source,
        };
        let docs = documents(&data).map_err(file_err)?;
        if let Some(crs) = docs.first().and_then(Document::reference_system) {
            match &first_crs {
                Some((first, want)) if !same_crs(want, crs) => {
                    return Err(SceneError::TileCrs {
                        first: first.clone(),
                        first_crs: want.clone(),
                        path: path.clone(),
                        crs: crs.to_string(),
                    });
                }
                Some(_) => {}
                None => first_crs = Some((path.clone(), crs.to_string())),
            }
        }
        model.add_file(docs).map_err(file_err)?;
    }
    model.reference_system = first_crs.map(|(_, c)| c);
    Ok(model)
}

/// Decodes one file's bytes (CityJSON or CityJSONSeq) as a model.
pub fn parse_city_model(data: &[u8]) -> Result<CityModel, CityJsonError> {
    let docs = documents(data)?;
    let mut model = CityModel {
        reference_system: docs
            .first()
            .and_then(Document::reference_system)
            .map(str::to_string),
        ..CityModel::default()
    };
    model.add_file(docs)?;
    Ok(model)
}

/// The EPSG code a CRS string names (`.../EPSG/0/7415`,
/// `urn:ogc:def:crs:EPSG::7415`), else the string itself: the one place
/// CRS names are compared.
pub fn crs_key(crs: &str) -> String {
    let upper = crs.trim().to_ascii_uppercase();
    let Some(at) = upper.rfind("EPSG") else {
        return upper;
    };
    // The code is the last run of digits (`EPSG/0/7415`: 0 is the version).
    let tail = &upper[at..];
    let digits: String = tail
        .rsplit(|c: char| !c.is_ascii_digit())
        .find(|s| !s.is_empty())
        .unwrap_or_default()
        .to_string();
    if digits.is_empty() {
        upper
    } else {
        format!("EPSG:{digits}")
    }
}

fn same_crs(a: &str, b: &str) -> bool {
    crs_key(a) == crs_key(b)
}

fn json_err(e: &serde_json::Error, line_offset: usize) -> CityJsonError {
    CityJsonError::Json {
        line: e.line() + line_offset,
        column: e.column(),
        message: e.to_string(),
    }
}

/// The documents of a file: one for CityJSON; the header then each feature
/// for CityJSONSeq (told apart by a first line that is a whole `CityJSON`
/// object followed by more lines).
fn documents(data: &[u8]) -> Result<Vec<Document>, CityJsonError> {
    let lines: Vec<&[u8]> = data.split(|&b| b == b'\n').collect();
    let more = lines
        .iter()
        .skip(1)
        .any(|l| l.iter().any(|b| !b.is_ascii_whitespace()));
    let header = if more {
        serde_json::from_slice::<Document>(lines[0])
            .ok()
            .filter(|d| d.kind == "CityJSON")
    } else {
        None
    };
    let Some(header) = header else {
        let doc: Document = serde_json::from_slice(data).map_err(|e| json_err(&e, 0))?;
        check_header(&doc)?;
        return Ok(vec![doc]);
    };
    check_header(&header)?;
    if header.transform.is_none() {
        return Err(CityJsonError::SeqWithoutTransform);
    }
    let mut docs = vec![header];
    for (k, line) in lines.iter().enumerate().skip(1) {
        if line.iter().all(u8::is_ascii_whitespace) {
            continue;
        }
        let doc: Document = serde_json::from_slice(line).map_err(|e| json_err(&e, k))?;
        if doc.kind != "CityJSONFeature" {
            return Err(CityJsonError::NotFeature {
                line: k + 1,
                found: doc.kind,
            });
        }
        docs.push(doc);
    }
    Ok(docs)
}

fn check_header(doc: &Document) -> Result<(), CityJsonError> {
    if doc.kind != "CityJSON" {
        return Err(CityJsonError::NotCityJson {
            found: doc.kind.clone(),
        });
    }
    match &doc.version {
        Some(v) if !(v.starts_with("1.") || v.starts_with("2.")) => {
            Err(CityJsonError::Version { version: v.clone() })
        }
        _ => Ok(()),
    }
}

impl CityModel {
    /// The CRS the model names, as the registry resolves it (`None` when it
    /// names none, or one without an EPSG code we know).
    pub fn crs(&self) -> Option<crate::crs::Crs> {
        let code = crate::crs::epsg_from_reference(self.reference_system.as_deref()?)?;
        crate::crs::Crs::from_epsg(code).ok()
    }

    /// Metres per unit of the model's coordinates (x, y, z): its CRS's unit,
    /// metres when it names no CRS we resolve.
    pub fn to_metre(&self) -> [f64; 3] {
        self.crs().map_or([1.0; 3], |c| c.to_metre())
    }

    /// Adds one file's documents; a Seq's features use its header's transform.
    fn add_file(&mut self, docs: Vec<Document>) -> Result<(), CityJsonError> {
        let transform = docs.first().and_then(|d| d.transform);
        if self.transform.is_none() {
            self.transform = transform;
        }
        for doc in docs {
            self.add_document(doc, transform)?;
        }
        Ok(())
    }

    fn add_document(
        &mut self,
        doc: Document,
        transform: Option<Transform>,
    ) -> Result<(), CityJsonError> {
        let vertices = real_vertices(&doc.vertices, transform.as_ref())?;
        let (base, n) = (self.vertices.len() as u64, vertices.len() as u64);
        let mut used = false;
        for (id, mut object) in doc.city_objects {
            let kind = object.kind.as_str();
            if !BUILDING_TYPES.contains(&kind) && !GROUND_TYPES.contains(&kind) {
                continue;
            }
            if self.objects.contains_key(&id) {
                self.duplicates += 1;
                continue;
            }
            for (gi, g) in object.geometry.iter_mut().enumerate() {
                if g.surface_depth().is_none() {
                    continue;
                }
                let mut bad = None;
                let moved = map_indices(&g.boundaries, &mut |i| {
                    if i < n {
                        Some(i + base)
                    } else {
                        bad = Some(i);
                        None
                    }
                });
                g.boundaries = match (moved, bad) {
                    (Some(m), _) => m,
                    (None, Some(index)) => {
                        return Err(CityJsonError::VertexIndex {
                            object: id,
                            index,
                            vertices: vertices.len(),
                        });
                    }
                    (None, None) => {
                        return Err(CityJsonError::Boundaries {
                            object: id,
                            geometry: gi,
                            kind: g.kind.clone(),
                            reason: "a vertex index must be a non-negative integer",
                        });
                    }
                };
            }
            used = true;
            self.objects.insert(id, object);
        }
        if used {
            self.vertices.extend(vertices);
        }
        Ok(())
    }

    /// Every building object's root Building id (itself for a Building),
    /// by object id: how a scene object's name leads to the building the
    /// file describes.
    pub fn roots(&self) -> BTreeMap<&str, &str> {
        let parents = super::parent_map(self);
        self.objects
            .iter()
            .filter(|(_, o)| BUILDING_TYPES.contains(&o.kind.as_str()))
            .map(|(id, _)| (id.as_str(), super::root_of(self, &parents, id)))
            .collect()
    }
}

/// Decompressed vertices (source CRS).
fn real_vertices(
    stored: &[[f64; 3]],
    transform: Option<&Transform>,
) -> Result<Vec<[f64; 3]>, CityJsonError> {
    let (scale, translate) = transform.map_or(([1.0; 3], [0.0; 3]), |t| (t.scale, t.translate));
    // A zero scale would fold every vertex onto the translate, and the
    // buildings would vanish as degenerate faces with no word why.
    let usable = scale.iter().all(|s| s.is_finite() && *s != 0.0);
    if !usable || !translate.iter().all(|v| v.is_finite()) {
        return Err(CityJsonError::Transform);
    }
    stored
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let p = [0, 1, 2].map(|a| v[a] * scale[a] + translate[a]);
            if p.iter().all(|c| c.is_finite()) {
                Ok(p)
            } else {
                Err(CityJsonError::NonFinite { vertex: k })
            }
        })
        .collect()
}

/// The city model files a spec names: a comma-separated list, each a file or
/// a directory (its `.json` / `.jsonl` files, sorted).
pub fn city_files(spec: &str) -> Result<Vec<PathBuf>, SceneError> {
    let mut out = Vec::new();
    for part in spec.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let path = Path::new(part);
        if !path.is_dir() {
            out.push(path.to_path_buf());
            continue;
        }
        let entries = file::read_dir(path)?;
        let mut files: Vec<PathBuf> = entries
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| is_city_file(p))
            .collect();
        if files.is_empty() {
            return Err(SceneError::NoCityFiles {
                path: path.to_path_buf(),
            });
        }
        files.sort();
        out.extend(files);
    }
    Ok(out)
}

/// True for `.json` and `.jsonl` files (incl. `.city.json`, `.city.jsonl`).
pub fn is_city_file(path: &Path) -> bool {
    path.is_file()
        && path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("json") || e.eq_ignore_ascii_case("jsonl"))
}

/// A `Value` that is a number or numeric string, as a CityJSON LoD string.
pub fn lod_string(lod: Option<&Value>) -> Option<String> {
    match lod? {
        Value::Number(n) => Some(n.to_string()),
        Value::String(s) => Some(s.trim().to_string()),
        _ => None,
    }
}
