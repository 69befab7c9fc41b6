//! /georeference: where the mission's local metric frame sits in the
//! survey's CRS. PointCloud2, Path and Odometry carry local metres only (the
//! prior's origin subtracted, feet converted), so this latched status is what
//! lets a subscriber or a bag turn them back into survey coordinates:
//! `source = (origin + local) / to_metre`, per axis.

use super::protocol::{OK, ProtocolError, Wire};
use crate::crs::{Crs, CrsRecord, LinearUnit, SourceFrame, UnitSource};

/// Name of the georeference status.
pub const GEOREFERENCE: &str = "georeference";

/// The state word of a frame with a known CRS.
const WITH_CRS: &str = "georeferenced";
/// The state word of a frame in metres with no CRS.
const NO_CRS: &str = "local metres, no CRS";

/// The local frame (`frame_id`) and its place in the source CRS.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Georeference {
    /// The frame the clouds and poses are in (`map`).
    pub frame_id: String,
    /// Origin (metres) and CRS of that frame.
    pub frame: SourceFrame,
}

impl Georeference {
    /// As it goes on the wire (every CRS field, LAS records as hex, so a
    /// file written from it carries the input's records byte for byte).
    pub fn to_wire(&self) -> Wire {
        let crs = self.frame.crs.as_ref();
        let mut w = Wire::new(
            OK,
            GEOREFERENCE,
            if crs.is_some() { WITH_CRS } else { NO_CRS },
        );
        w.put("frame_id", &self.frame_id);
        for (k, v) in ["origin_x", "origin_y", "origin_z"]
            .into_iter()
            .zip(self.frame.origin)
        {
            w.put(k, v);
        }
        let Some(crs) = crs else {
            return w;
        };
        // Readable first (`ros2 topic echo`), exact after.
        w.put("crs", crs.label());
        let to_metre = crs.to_metre();
        w.put("to_metre_xy", to_metre[0]);
        w.put("to_metre_z", to_metre[2]);
        if let Some(c) = crs.epsg {
            w.put("epsg", c);
        }
        if let Some(c) = crs.vertical_epsg {
            w.put("vertical_epsg", c);
        }
        if let Some(n) = &crs.name {
            w.put("name", n);
        }
        w.put("horizontal_unit", crs.horizontal_unit.name());
        w.put("vertical_unit", crs.vertical_unit.name());
        w.put("unit_source", crs.unit_source.word());
        if let Some(t) = &crs.wkt {
            w.put("wkt", t);
        }
        let records: Vec<String> = crs
            .las_records
            .iter()
            .map(|r| {
                format!(
                    "{},{},{}",
                    r.record_id,
                    hex(r.description.as_bytes()),
                    hex(&r.data)
                )
            })
            .collect();
        w.put("las_records", records.join(";"));
        w
    }

    /// Read from the wire.
    pub fn from_wire(w: &Wire) -> Result<Self, ProtocolError> {
        if w.name != GEOREFERENCE {
            return Err(ProtocolError::State {
                name: w.name.clone(),
                message: w.message.clone(),
                expected: "a status named `georeference`",
            });
        }
        let origin = [w.get("origin_x")?, w.get("origin_y")?, w.get("origin_z")?];
        let bad = |key: &'static str, value: &str, expected: &'static str| ProtocolError::Bad {
            name: w.name.clone(),
            key,
            value: value.into(),
            expected,
        };
        let crs = match w.message.as_str() {
            NO_CRS => None,
            WITH_CRS => {
                let unit = |name_key, size_key| -> Result<LinearUnit, ProtocolError> {
                    let name: String = w.get(name_key)?;
                    let size: f64 = w.get(size_key)?;
                    LinearUnit::from_name_and_size(&name, size)
                        .ok_or_else(|| bad(size_key, &size.to_string(), "positive metres per unit"))
                };
                let source: String = w.get("unit_source")?;
                let records: String = w.opt("las_records")?.unwrap_or_default();
                let las_records = records
                    .split(';')
                    .filter(|r| !r.is_empty())
                    .map(|r| {
                        las_record(r)
                            .ok_or_else(|| bad("las_records", r, "LAS record (id,hex,hex)"))
                    })
                    .collect::<Result<_, ProtocolError>>()?;
                Some(Crs {
                    name: w.opt("name")?,
                    epsg: w.opt("epsg")?,
                    vertical_epsg: w.opt("vertical_epsg")?,
                    wkt: w.opt("wkt")?,
                    las_records,
                    horizontal_unit: unit("horizontal_unit", "to_metre_xy")?,
                    vertical_unit: unit("vertical_unit", "to_metre_z")?,
                    unit_source: UnitSource::from_word(&source)
                        .ok_or_else(|| bad("unit_source", &source, "unit source word"))?,
                })
            }
            _ => {
                return Err(ProtocolError::State {
                    name: w.name.clone(),
                    message: w.message.clone(),
                    expected: "`georeferenced`, `local metres, no CRS`",
                });
            }
        };
        Ok(Self {
            frame_id: w.get("frame_id")?,
            frame: SourceFrame::new(origin, crs),
        })
    }
}

/// One LAS CRS record as `id,description hex,data hex`.
fn las_record(text: &str) -> Option<CrsRecord> {
    let mut parts = text.split(',');
    let record_id = parts.next()?.trim().parse().ok()?;
    let description = String::from_utf8(unhex(parts.next()?)?).ok()?;
    let data = unhex(parts.next()?)?;
    parts.next().is_none().then_some(CrsRecord {
        record_id,
        description,
        data,
    })
}

fn hex(data: &[u8]) -> String {
    data.iter().map(|b| format!("{b:02x}")).collect()
}

fn unhex(text: &str) -> Option<Vec<u8>> {
    let t = text.trim();
    if !t.len().is_multiple_of(2) {
        return None;
    }
    (0..t.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(t.get(i..i + 2)?, 16).ok())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn feet_frame() -> Georeference {
        let mut crs = Crs::from_epsg(6880).expect("EPSG:6880 is in the registry");
        crs.las_records = vec![CrsRecord {
            record_id: 34735,
            description: "GeoKeyDirectoryTag".into(),
            data: vec![1, 0, 1, 0, 0, 255, 0x7f],
        }];
        Georeference {
            frame_id: "map".into(),
            frame: SourceFrame::new([745_000.123_456_789, 183_000.5, -12.25], Some(crs)),
        }
    }

    #[test]
    fn a_frame_in_feet_round_trips_exactly_and_maps_points_back() {
        let g = feet_frame();
        let back = Georeference::from_wire(&g.to_wire()).expect("its own wire form reads");
        assert_eq!(back, g);
        let ft = 0.304_800_609_601_219_2;
        let p = back.frame.to_source([ft, 2.0 * ft, 0.0]);
        assert!(
            (p[0] - (745_000.123_456_789 / ft + 1.0)).abs() < 1e-6,
            "{p:?}"
        );
        let no_crs = Georeference {
            frame_id: "map".into(),
            frame: SourceFrame::new([1.0, 2.0, 3.0], None),
        };
        assert_eq!(Georeference::from_wire(&no_crs.to_wire()), Ok(no_crs));
    }

    #[test]
    fn a_broken_georeference_is_refused_with_the_key_named() {
        let mut w = feet_frame().to_wire();
        for (k, v) in &mut w.values {
            if k == "las_records" {
                v.push('g');
            }
        }
        let e = Georeference::from_wire(&w).expect_err("bad hex");
        assert!(e.to_string().contains("las_records"), "{e}");
        let mut w = feet_frame().to_wire();
        w.values.retain(|(k, _)| k != "origin_y");
        let e = Georeference::from_wire(&w).expect_err("no origin_y");
        assert!(e.to_string().contains("origin_y"), "{e}");
        let mut w = feet_frame().to_wire();
        w.message = "somewhere".into();
        assert!(Georeference::from_wire(&w).is_err());
    }
}
