//! Coordinate reference systems as files state them, and their linear units.
//!
//! skyground works in metres inside. A file in feet keeps its CRS records in
//! a [`Crs`]; readers scale coordinates to metres with [`Crs::to_metre`], and
//! every writer scales back and writes the records again, so outputs are in
//! the input's CRS and unit. A file without a CRS has `crs: None`: unknown
//! CRS, metres assumed.

mod epsg;
mod frame;
mod geotiff;
mod json;
mod unit;
mod wkt;

pub use epsg::{EpsgEntry, epsg_entry, epsg_from_reference, epsg_unit, identify_projected};
pub use frame::SourceFrame;
pub use geotiff::{GeoKeyValue, GeoTiffError, GeoTiffFacts, geotiff_facts};
pub use json::{JsonCrs, cityjson_crs, geojson_crs};
pub use unit::{FOOT_M, LinearUnit, US_SURVEY_FOOT_M};
pub use wkt::{WktArg, WktError, WktFacts, WktNode, parse_wkt, without_nodes, wkt_facts};

/// `user_id` of the LAS CRS records.
pub const LAS_PROJECTION: &str = "LASF_Projection";
/// LAS record ids: WKT, GeoTIFF key directory, doubles, ASCII.
pub const WKT_RECORD: u16 = 2112;
const GEOKEY_RECORD: u16 = 34735;
const DOUBLES_RECORD: u16 = 34736;
const ASCII_RECORD: u16 = 34737;

/// One CRS record of a LAS file (a `LASF_Projection` VLR), kept byte for byte.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CrsRecord {
    /// Record id: 2112 WKT, 34735–34737 GeoTIFF.
    pub record_id: u16,
    /// The record's description field.
    pub description: String,
    /// The payload as read.
    pub data: Vec<u8>,
}

/// Where the unit of a [`Crs`] came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum UnitSource {
    /// The WKT record's `UNIT`/`LENGTHUNIT`.
    Wkt,
    /// GeoTIFF `ProjLinearUnitsGeoKey` / `VerticalUnitsGeoKey`.
    #[serde(rename = "geotiff")]
    GeoTiff,
    /// The EPSG registry's definition of the file's EPSG code.
    Epsg,
    /// The user said so (`--units`).
    User,
    /// Nothing said: metres assumed.
    Assumed,
}

impl UnitSource {
    /// Its word, as serialised (`wkt`, `geotiff`, `epsg`, `user`, `assumed`).
    pub fn word(self) -> &'static str {
        match self {
            Self::Wkt => "wkt",
            Self::GeoTiff => "geotiff",
            Self::Epsg => "epsg",
            Self::User => "user",
            Self::Assumed => "assumed",
        }
    }

    /// The source a [`UnitSource::word`] names.
    pub fn from_word(word: &str) -> Option<Self> {
        [
            Self::Wkt,
            Self::GeoTiff,
            Self::Epsg,
            Self::User,
            Self::Assumed,
        ]
        .into_iter()
        .find(|s| s.word() == word.trim())
    }
}

/// A CRS record set that could not be understood.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CrsError {
    /// The WKT record is malformed.
    #[error("CRS WKT record: {0}")]
    Wkt(#[from] WktError),
    /// The GeoTIFF records are malformed.
    #[error("CRS GeoTIFF records: {0}")]
    GeoTiff(#[from] GeoTiffError),
    /// The CRS is geographic: coordinates are angles, not lengths.
    #[error(
        "CRS `{name}` is geographic (degrees); skyground needs a projected CRS in metres or feet: reproject the file first (e.g. `pdal translate` with filters.reprojection)"
    )]
    Geographic {
        /// The CRS name.
        name: String,
    },
    /// The CRS is geocentric: Earth-centred x, y, z, no plan axes or up.
    #[error(
        "CRS `{name}` is geocentric (Earth-centred x, y, z in metres, no plan axes or up); skyground needs a projected CRS in metres or feet: reproject the file first (e.g. `pdal translate` with filters.reprojection)"
    )]
    Geocentric {
        /// The CRS name.
        name: String,
    },
}

impl CrsError {
    /// The records themselves are malformed (not a CRS skyground refuses):
    /// a reader told the CRS another way may leave them out.
    pub fn is_malformed(&self) -> bool {
        matches!(self, Self::Wkt(_) | Self::GeoTiff(_))
    }
}

/// A coordinate reference system as a file stated it, with its linear units.
///
/// `horizontal_unit` applies to x and y, `vertical_unit` to z; when a source
/// states no vertical unit, z is taken in the horizontal unit (the LAS
/// convention for projected data).
#[derive(Debug, Clone, PartialEq)]
pub struct Crs {
    /// The CRS name (from WKT, GeoTIFF citation or the EPSG registry).
    pub name: Option<String>,
    /// The EPSG code of the whole CRS, when known.
    pub epsg: Option<u32>,
    /// The vertical CRS's EPSG code, when known.
    pub vertical_epsg: Option<u32>,
    /// WKT text (as read, or the registry's for an EPSG code).
    pub wkt: Option<String>,
    /// LAS CRS records as read, written back unchanged.
    pub las_records: Vec<CrsRecord>,
    /// Unit of x and y.
    pub horizontal_unit: LinearUnit,
    /// Unit of z.
    pub vertical_unit: LinearUnit,
    /// Where the units came from.
    pub unit_source: UnitSource,
}

impl Crs {
    /// Metres per file unit for x, y and z.
    pub fn to_metre(&self) -> [f64; 3] {
        let h = self.horizontal_unit.to_metre();
        [h, h, self.vertical_unit.to_metre()]
    }

    /// The horizontal EPSG code: the projected part of a compound CRS
    /// (EPSG:7415 = RD New + NAP height → 28992), else the CRS's own code.
    pub fn horizontal_epsg(&self) -> Option<u32> {
        self.wkt
            .as_deref()
            .and_then(|w| wkt_facts(w).ok())
            .and_then(|f| f.horizontal_epsg.or(f.epsg))
            .or(self.epsg)
    }

    /// True when every axis is in metres.
    pub fn is_metric(&self) -> bool {
        self.to_metre() == [1.0; 3]
    }

    /// `EPSG:n (name)`, or the name, or `unnamed CRS`.
    pub fn label(&self) -> String {
        match (self.epsg, &self.name) {
            (Some(c), Some(n)) => format!("EPSG:{c} ({n})"),
            (Some(c), None) => format!("EPSG:{c}"),
            (None, Some(n)) => n.clone(),
            (None, None) => "unnamed CRS".into(),
        }
    }

    /// The OGC URN of the EPSG code (what GeoJSON's legacy `crs` member names).
    pub fn urn(&self) -> Option<String> {
        self.epsg.map(|c| format!("urn:ogc:def:crs:EPSG::{c}"))
    }

    /// A CRS known only by its EPSG code; name, WKT and units from the registry.
    ///
    /// A code the registry lacks keeps metres assumed (and says so in `unit_source`).
    pub fn from_epsg(code: u32) -> Result<Self, CrsError> {
        let Some(entry) = epsg_entry(code) else {
            return Ok(Self {
                name: None,
                epsg: Some(code),
                vertical_epsg: None,
                wkt: None,
                las_records: Vec::new(),
                horizontal_unit: LinearUnit::Metre,
                vertical_unit: LinearUnit::Metre,
                unit_source: UnitSource::Assumed,
            });
        };
        let f = entry.facts;
        if f.geographic {
            let name = f.name.unwrap_or_else(|| format!("EPSG:{code}"));
            return Err(if f.geocentric {
                CrsError::Geocentric { name }
            } else {
                CrsError::Geographic { name }
            });
        }
        let h = f.horizontal_unit.unwrap_or(LinearUnit::Metre);
        Ok(Self {
            name: f.name,
            epsg: Some(code),
            vertical_epsg: f.vertical_epsg,
            // The table's WKT1 carries a datum shift (TOWGS84) for some codes
            // (RD New). The code itself defines none; GDAL 3 and PROJ write
            // none, and pyproj reads a WKT with one as a bound CRS without
            // an EPSG code.
            wkt: Some(without_nodes(entry.wkt, "TOWGS84")),
            las_records: Vec::new(),
            vertical_unit: f.vertical_unit.unwrap_or_else(|| h.clone()),
            horizontal_unit: h,
            unit_source: UnitSource::Epsg,
        })
    }

    /// No CRS known, but the user says the coordinates are in `unit`.
    pub fn user_unit(unit: LinearUnit) -> Self {
        Self {
            name: None,
            epsg: None,
            vertical_epsg: None,
            wkt: None,
            las_records: Vec::new(),
            vertical_unit: unit.clone(),
            horizontal_unit: unit,
            unit_source: UnitSource::User,
        }
    }

    /// The LAS records that state this CRS: those read from a file, when
    /// there are some; else the WKT record for the extended point formats
    /// 6–10 (which LAS 1.4 allows no other way), and GeoTIFF keys for the
    /// legacy formats 0–5 (what LAS 1.2 readers look for), the WKT record
    /// when no EPSG code is known; empty when nothing says more than a unit.
    pub fn las_records_for(&self, extended: bool) -> Vec<CrsRecord> {
        if !self.las_records.is_empty() {
            return self.las_records.clone();
        }
        let keys = || {
            let h = self.horizontal_epsg()?;
            let v = self.vertical_epsg.map(|v| (v, &self.vertical_unit));
            let data = geotiff::projected_directory(h, &self.horizontal_unit, v)?;
            Some(CrsRecord {
                record_id: GEOKEY_RECORD,
                description: "GeoTIFF GeoKeyDirectoryTag".into(),
                data,
            })
        };
        let wkt = || {
            self.wkt.as_ref().map(|w| CrsRecord {
                record_id: WKT_RECORD,
                description: "OGC WKT".into(),
                data: [w.as_bytes(), &[0u8][..]].concat(),
            })
        };
        let record = if extended { wkt() } else { keys().or_else(wkt) };
        record.into_iter().collect()
    }

    /// The CRS of a LAS file's `LASF_Projection` records (None when it has none).
    ///
    /// The WKT record decides when present (LAS 1.4 makes it authoritative),
    /// GeoTIFF keys fill what it leaves open, then the EPSG registry.
    pub fn from_las_records(records: Vec<CrsRecord>) -> Result<Option<Self>, CrsError> {
        let find = |id| {
            records
                .iter()
                .find(|r| r.record_id == id)
                .map(|r| &r.data[..])
        };
        let wkt_text = find(WKT_RECORD)
            .map(|d| {
                String::from_utf8_lossy(d)
                    .trim_end_matches('\0')
                    .trim()
                    .to_string()
            })
            .filter(|t| !t.is_empty());
        let wkt = wkt_text.as_deref().map(wkt_facts).transpose()?;
        let geo = find(GEOKEY_RECORD)
            .map(|d| geotiff_facts(d, find(DOUBLES_RECORD), find(ASCII_RECORD)))
            .transpose()?;
        if wkt.is_none() && geo.is_none() {
            return Ok(None);
        }
        let w = wkt.unwrap_or_default();
        let g = geo.unwrap_or_default();
        let name = w.name.clone().or_else(|| g.citation.clone());
        if w.geographic || (wkt_text.is_none() && g.geographic) {
            let geocentric = w.geocentric || (wkt_text.is_none() && g.geocentric);
            return Err(if geocentric {
                CrsError::Geocentric {
                    name: name.unwrap_or_else(|| "geocentric CRS".into()),
                }
            } else {
                CrsError::Geographic {
                    name: name.unwrap_or_else(|| "geographic CRS".into()),
                }
            });
        }
        let (horizontal, h_source) = match (&w.horizontal_unit, &g.horizontal_unit) {
            (Some(u), _) => (Some(u.clone()), UnitSource::Wkt),
            (None, Some(u)) => (Some(u.clone()), UnitSource::GeoTiff),
            (None, None) => (g.projected_epsg.and_then(epsg_unit), UnitSource::Epsg),
        };
        let (horizontal, unit_source) = match horizontal {
            Some(u) => (u, h_source),
            None => (LinearUnit::Metre, UnitSource::Assumed),
        };
        let vertical = w
            .vertical_unit
            .clone()
            .or_else(|| g.vertical_unit.clone())
            .unwrap_or_else(|| horizontal.clone());
        // A GeoTIFF projected code only names this CRS when its unit agrees
        // (laspy's Nebraska file says 32104, a metre CRS, with US-feet keys).
        let geo_epsg = g
            .projected_epsg
            .filter(|c| epsg_unit(*c).is_none_or(|u| u == horizontal));
        // A WKT without authority (Esri style) is matched against the registry.
        let identified = || {
            let text = wkt_text.as_deref()?;
            identify_projected(text, &horizontal, g.geographic_epsg)
        };
        let epsg = w.epsg.or(geo_epsg).or_else(identified);
        let las_records = records;
        Ok(Some(Self {
            name,
            epsg,
            vertical_epsg: w.vertical_epsg.or(g.vertical_epsg),
            wkt: wkt_text,
            las_records,
            horizontal_unit: horizontal,
            vertical_unit: vertical,
            unit_source,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_for_a_file_without_any_read_back_as_the_same_crs() {
        // RD New + NAP height, as AHN3's producer states it elsewhere.
        let stated = Crs::from_epsg(7415).unwrap();
        for extended in [false, true] {
            let records = stated.las_records_for(extended);
            assert_eq!(records.len(), 1);
            let want = if extended { WKT_RECORD } else { GEOKEY_RECORD };
            assert_eq!(records[0].record_id, want);
            let back = Crs::from_las_records(records).unwrap().unwrap();
            assert_eq!(back.horizontal_epsg(), Some(28992), "extended {extended}");
            assert_eq!(back.vertical_epsg, Some(5709), "extended {extended}");
            assert!(back.is_metric());
        }
        // The registry's datum shift is not written: the text names RD New
        // alone, as GDAL 3 writes it.
        let wkt = stated.wkt.as_deref().unwrap_or_default();
        assert!(wkt.contains("28992") && !wkt.contains("TOWGS84"), "{wkt}");
        assert!(epsg_entry(7415).unwrap().wkt.contains("TOWGS84"));
        // In feet, the keys carry the unit: read back in US survey feet.
        let feet = Crs::from_epsg(2994).unwrap();
        let back = Crs::from_las_records(feet.las_records_for(false))
            .unwrap()
            .unwrap();
        assert_eq!(back.epsg, Some(2994));
        assert_eq!(back.horizontal_unit, feet.horizontal_unit);
        // A unit alone states no CRS.
        assert!(
            Crs::user_unit(LinearUnit::Foot)
                .las_records_for(true)
                .is_empty()
        );
    }

    fn record(record_id: u16, data: &[u8]) -> CrsRecord {
        CrsRecord {
            record_id,
            description: String::new(),
            data: data.to_vec(),
        }
    }

    #[test]
    fn wkt_decides_and_geotiff_fills_the_vertical_unit() {
        let wkt = br#"PROJCS["NAD83_2011_Nebraska_ft",GEOGCS["GCS",UNIT["Degree",0.0174532925199433]],UNIT["Foot_US",0.30480060960121924]]"#;
        let keys =
            geotiff::directory(&[[3072, 0, 1, 32104], [3076, 0, 1, 9003], [4099, 0, 1, 9002]]);
        let crs =
            Crs::from_las_records(vec![record(WKT_RECORD, wkt), record(GEOKEY_RECORD, &keys)])
                .unwrap()
                .unwrap();
        assert_eq!(crs.horizontal_unit, LinearUnit::UsSurveyFoot);
        assert_eq!(crs.vertical_unit, LinearUnit::Foot);
        assert_eq!(crs.unit_source, UnitSource::Wkt);
        assert_eq!(crs.epsg, None, "32104 is a metre CRS: not this one");
        let f = crs.to_metre();
        assert!((f[0] - US_SURVEY_FOOT_M).abs() < 1e-15 && f[2] == FOOT_M);
    }

    #[test]
    fn geotiff_only_takes_the_code_and_the_registry_unit() {
        let keys = geotiff::directory(&[[1024, 0, 1, 1], [3072, 0, 1, 2154]]);
        let crs = Crs::from_las_records(vec![record(GEOKEY_RECORD, &keys)])
            .unwrap()
            .unwrap();
        assert_eq!(crs.epsg, Some(2154));
        assert_eq!(crs.horizontal_unit, LinearUnit::Metre);
        assert_eq!(crs.unit_source, UnitSource::Epsg);
        assert!(crs.is_metric());
        assert_eq!(crs.urn().as_deref(), Some("urn:ogc:def:crs:EPSG::2154"));
    }

    #[test]
    fn no_records_geographic_and_bad_records() {
        assert_eq!(Crs::from_las_records(vec![]), Ok(None));
        let keys = geotiff::directory(&[[1024, 0, 1, 2], [2048, 0, 1, 4326]]);
        let e = Crs::from_las_records(vec![record(GEOKEY_RECORD, &keys)]).unwrap_err();
        assert!(e.to_string().contains("reproject"), "{e}");
        let e = Crs::from_las_records(vec![record(WKT_RECORD, b"PROJCS[")]).unwrap_err();
        assert!(matches!(e, CrsError::Wkt(_)), "{e}");
    }

    #[test]
    fn epsg_codes_take_units_from_the_registry() {
        let crs = Crs::from_epsg(6880).unwrap();
        assert_eq!(crs.horizontal_unit, LinearUnit::UsSurveyFoot);
        assert_eq!(crs.label(), "EPSG:6880 (NAD83(2011) / Nebraska (ftUS))");
        assert!(crs.wkt.as_deref().is_some_and(|w| w.starts_with("PROJCS[")));
        let unknown = Crs::from_epsg(65000).unwrap();
        assert_eq!(unknown.unit_source, UnitSource::Assumed);
        assert!(Crs::from_epsg(4326).is_err());
    }
}
