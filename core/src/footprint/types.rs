//! A building footprint and its plain serialisable form.

use geo::{Area, BoundingRect, Coord, LineString, MultiPolygon, Polygon};

/// One building's 2D outline in the local frame (x, y in metres).
#[derive(Debug, Clone, PartialEq)]
pub struct Footprint {
    /// Building id, 1-based (0 means "no building" elsewhere, so never used here).
    pub id: u32,
    /// Outline(s) with holes, local frame xy.
    pub polygon: MultiPolygon<f64>,
    /// Name from the source (GeoJSON property, CityJSON id, OBJ object) or generated.
    pub name: String,
}

impl Footprint {
    /// Footprint `id` as the union of its `parts` (faces, features);
    /// `None` when they make no valid polygon.
    pub fn from_parts(id: u32, name: String, parts: &[Polygon<f64>]) -> Option<Self> {
        let polygon = super::polygon::union_valid(parts).ok()?;
        Some(Self { id, polygon, name })
    }

    /// Plan area, m².
    pub fn area(&self) -> f64 {
        self.polygon.unsigned_area()
    }

    /// Bounding box `[min x, min y, max x, max y]`, `None` when empty.
    pub fn bounds(&self) -> Option<[f64; 4]> {
        self.polygon
            .bounding_rect()
            .map(|r| [r.min().x, r.min().y, r.max().x, r.max().y])
    }

    /// The plain ring form (for serde, YAML, messages).
    pub fn to_rings(&self) -> FootprintRings {
        let ring = |l: &LineString<f64>| l.0.iter().map(|c| [c.x, c.y]).collect();
        FootprintRings {
            id: self.id,
            name: self.name.clone(),
            polygons: self
                .polygon
                .0
                .iter()
                .map(|p| {
                    std::iter::once(p.exterior())
                        .chain(p.interiors())
                        .map(ring)
                        .collect()
                })
                .collect(),
        }
    }
}

/// A footprint as plain nested arrays: polygons, each outer ring then holes,
/// each ring a list of `[x, y]` (closed: last = first).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FootprintRings {
    /// Building id, 1-based.
    pub id: u32,
    /// Name.
    pub name: String,
    /// Polygons: `[outer, hole, hole, ...]`.
    pub polygons: Vec<Vec<Vec<[f64; 2]>>>,
}

impl From<&FootprintRings> for Footprint {
    fn from(r: &FootprintRings) -> Self {
        let ls = |ring: &Vec<[f64; 2]>| {
            LineString::new(ring.iter().map(|p| Coord { x: p[0], y: p[1] }).collect())
        };
        let polygon = r
            .polygons
            .iter()
            .filter_map(|rings| {
                let (outer, holes) = rings.split_first()?;
                Some(Polygon::new(ls(outer), holes.iter().map(ls).collect()))
            })
            .collect();
        Footprint {
            id: r.id,
            polygon,
            name: r.name.clone(),
        }
    }
}

/// What a reader returns: the footprints (ids unique, sorted) and the
/// polygons it skipped, with reasons.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Loaded {
    /// Usable footprints, sorted by id.
    pub footprints: Vec<Footprint>,
    /// Polygons or rings left out (the rest still loads).
    pub skipped: Vec<super::error::Skipped>,
    /// Footprints read per BuildingPart: the own id of the Building each
    /// belongs to, by footprint id (empty when read per building).
    pub part_of: std::collections::BTreeMap<u32, String>,
}

impl Loaded {
    /// What a reader found, or [`ParseError::NoFootprints`](super::error::ParseError::NoFootprints)
    /// when nothing usable is left.
    pub fn new(
        footprints: Vec<Footprint>,
        skipped: Vec<super::error::Skipped>,
    ) -> Result<Self, super::error::ParseError> {
        if footprints.is_empty() {
            return Err(super::error::ParseError::NoFootprints {
                skipped: skipped.len(),
                first: skipped.first().map(ToString::to_string),
            });
        }
        Ok(Self {
            footprints,
            skipped,
            part_of: Default::default(),
        })
    }
}
