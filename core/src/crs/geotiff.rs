//! The GeoTIFF keys of a LAS file's `LASF_Projection` records 34735–34737.

use super::LinearUnit;

/// `GTModelTypeGeoKey`.
const MODEL_TYPE: u16 = 1024;
/// `GTCitationGeoKey`.
const CITATION: u16 = 1026;
/// `GeographicTypeGeoKey`.
const GEOGRAPHIC_TYPE: u16 = 2048;
/// `ProjectedCSTypeGeoKey`.
const PROJECTED_TYPE: u16 = 3072;
/// `PCSCitationGeoKey`.
const PCS_CITATION: u16 = 3073;
/// `ProjLinearUnitsGeoKey`.
const LINEAR_UNITS: u16 = 3076;
/// `ProjLinearUnitSizeGeoKey` (metres per unit when the unit is user-defined).
const LINEAR_UNIT_SIZE: u16 = 3077;
/// `VerticalCSTypeGeoKey`.
const VERTICAL_TYPE: u16 = 4096;
/// `VerticalUnitsGeoKey`.
const VERTICAL_UNITS: u16 = 4099;
/// Record ids of the double and ASCII parameter records.
const DOUBLES: u16 = 34736;
const ASCII: u16 = 34737;
/// A user-defined code (the value is given by other keys).
const USER_DEFINED: u16 = 32767;

/// One GeoTIFF key with its value resolved.
#[derive(Debug, Clone, PartialEq)]
pub enum GeoKeyValue {
    /// A short held in the directory itself.
    Short(u16),
    /// Doubles from record 34736.
    Doubles(Vec<f64>),
    /// Text from record 34737 (without the `|` terminator).
    Ascii(String),
}

/// The GeoTIFF key directory could not be decoded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GeoTiffError {
    /// The directory is shorter than its own key count says.
    #[error("GeoKeyDirectory record is {len} bytes but declares {keys} keys")]
    Truncated {
        /// Bytes in the record.
        len: usize,
        /// Keys declared.
        keys: u16,
    },
    /// A key points outside the double or ASCII record.
    #[error("GeoTIFF key {id} points outside its parameter record")]
    BadReference {
        /// The key id.
        id: u16,
    },
}

/// What the GeoTIFF keys say about identity and units.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GeoTiffFacts {
    /// Every key, in directory order.
    pub keys: Vec<(u16, GeoKeyValue)>,
    /// `ProjectedCSTypeGeoKey` when it is an EPSG code (1024–32766).
    pub projected_epsg: Option<u32>,
    /// `GeographicTypeGeoKey` when it is an EPSG code.
    pub geographic_epsg: Option<u32>,
    /// `VerticalCSTypeGeoKey` when it is an EPSG code.
    pub vertical_epsg: Option<u32>,
    /// The unit of `ProjLinearUnitsGeoKey` (with `ProjLinearUnitSizeGeoKey` when user-defined).
    pub horizontal_unit: Option<LinearUnit>,
    /// The unit of `VerticalUnitsGeoKey`.
    pub vertical_unit: Option<LinearUnit>,
    /// True when `GTModelTypeGeoKey` says geographic (2) or geocentric (3).
    pub geographic: bool,
    /// True when it says geocentric (3).
    pub geocentric: bool,
    /// The first citation (PCS citation, else GT citation), for a name.
    pub citation: Option<String>,
}

impl GeoTiffFacts {
    /// The value of key `id`, if present.
    pub fn get(&self, id: u16) -> Option<&GeoKeyValue> {
        self.keys.iter().find(|(k, _)| *k == id).map(|(_, v)| v)
    }

    fn short(&self, id: u16) -> Option<u16> {
        match self.get(id)? {
            GeoKeyValue::Short(v) => Some(*v),
            _ => None,
        }
    }

    fn code(&self, id: u16) -> Option<u32> {
        self.short(id)
            .filter(|v| (1024..USER_DEFINED).contains(v))
            .map(u32::from)
    }

    fn ascii(&self, id: u16) -> Option<String> {
        match self.get(id)? {
            GeoKeyValue::Ascii(s) if !s.trim().is_empty() => Some(s.trim().to_string()),
            _ => None,
        }
    }

    fn unit(&self, id: u16) -> Option<LinearUnit> {
        match self.short(id)? {
            USER_DEFINED if id == LINEAR_UNITS => match self.get(LINEAR_UNIT_SIZE)? {
                GeoKeyValue::Doubles(d) => {
                    LinearUnit::from_name_and_size("user-defined unit", *d.first()?)
                }
                _ => None,
            },
            code => LinearUnit::from_epsg(code),
        }
    }
}

fn u16_at(data: &[u8], i: usize) -> Option<u16> {
    Some(u16::from_le_bytes(
        data.get(2 * i..2 * i + 2)?.try_into().ok()?,
    ))
}

/// Decodes the key directory (record 34735) with its double and ASCII records.
pub fn geotiff_facts(
    directory: &[u8],
    doubles: Option<&[u8]>,
    ascii: Option<&[u8]>,
) -> Result<GeoTiffFacts, GeoTiffError> {
    let keys = u16_at(directory, 3).unwrap_or(0);
    let mut facts = GeoTiffFacts::default();
    for k in 0..usize::from(keys) {
        let entry = |j| u16_at(directory, 4 + 4 * k + j);
        let (Some(id), Some(location), Some(count), Some(value)) =
            (entry(0), entry(1), entry(2), entry(3))
        else {
            return Err(GeoTiffError::Truncated {
                len: directory.len(),
                keys,
            });
        };
        let (start, count) = (usize::from(value), usize::from(count));
        let bad = GeoTiffError::BadReference { id };
        let v = match location {
            0 => GeoKeyValue::Short(value),
            DOUBLES => {
                let bytes = doubles
                    .and_then(|d| d.get(8 * start..8 * (start + count)))
                    .ok_or(bad)?;
                GeoKeyValue::Doubles(
                    bytes
                        .chunks_exact(8)
                        .filter_map(|c| c.try_into().ok().map(f64::from_le_bytes))
                        .collect(),
                )
            }
            ASCII => {
                let bytes = ascii.and_then(|a| a.get(start..start + count)).ok_or(bad)?;
                let text = String::from_utf8_lossy(bytes);
                GeoKeyValue::Ascii(text.trim_end_matches(['|', '\0']).to_string())
            }
            _ => continue,
        };
        facts.keys.push((id, v));
    }
    facts.projected_epsg = facts.code(PROJECTED_TYPE);
    facts.geographic_epsg = facts.code(GEOGRAPHIC_TYPE);
    facts.vertical_epsg = facts.code(VERTICAL_TYPE);
    facts.horizontal_unit = facts.unit(LINEAR_UNITS);
    facts.vertical_unit = facts.unit(VERTICAL_UNITS);
    facts.geographic = matches!(facts.short(MODEL_TYPE), Some(2 | 3));
    facts.geocentric = facts.short(MODEL_TYPE) == Some(3);
    facts.citation = facts.ascii(PCS_CITATION).or_else(|| facts.ascii(CITATION));
    Ok(facts)
}

/// `GTRasterTypeGeoKey`.
const RASTER_TYPE: u16 = 1025;

/// A key directory (record 34735) from `(id, location, count, value)`
/// entries, sorted by id as the GeoTIFF specification asks.
pub(crate) fn directory(entries: &[[u16; 4]]) -> Vec<u8> {
    let mut sorted = entries.to_vec();
    sorted.sort_by_key(|e| e[0]);
    let n = u16::try_from(sorted.len()).unwrap_or(u16::MAX);
    [1, 1, 0, n]
        .iter()
        .chain(sorted.iter().flatten())
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// The key directory of a projected CRS known by its EPSG codes: model type
/// projected, pixel is area, the projected code and its unit, and the
/// vertical code and unit when known. `None` when a code does not fit the
/// keys' 16 bits.
pub(crate) fn projected_directory(
    projected: u32,
    unit: &LinearUnit,
    vertical: Option<(u32, &LinearUnit)>,
) -> Option<Vec<u8>> {
    let code = |c: u32| u16::try_from(c).ok();
    let mut keys = vec![
        [MODEL_TYPE, 0, 1, 1],
        [RASTER_TYPE, 0, 1, 1],
        [PROJECTED_TYPE, 0, 1, code(projected)?],
    ];
    if let Some(u) = unit.epsg() {
        keys.push([LINEAR_UNITS, 0, 1, u]);
    }
    if let Some((v, vu)) = vertical {
        keys.push([VERTICAL_TYPE, 0, 1, code(v)?]);
        if let Some(u) = vu.epsg() {
            keys.push([VERTICAL_UNITS, 0, 1, u]);
        }
    }
    Some(directory(&keys))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    #[test]
    fn nebraska_keys_give_us_feet_both_ways() {
        // The keys of laspy's file_with_both_wkt_and_geotiff_vlrs.las.
        let dir = directory(&[
            [1024, 0, 1, 1],
            [2048, 0, 1, 6318],
            [3072, 0, 1, 32104],
            [3073, ASCII, 27, 0],
            [3076, 0, 1, 9003],
            [4099, 0, 1, 9003],
        ]);
        let ascii = b"NAD83_2011 / Nebraska (ft)|";
        let f = geotiff_facts(&dir, None, Some(ascii)).unwrap();
        assert_eq!(f.horizontal_unit, Some(LinearUnit::UsSurveyFoot));
        assert_eq!(f.vertical_unit, Some(LinearUnit::UsSurveyFoot));
        assert_eq!(f.projected_epsg, Some(32104));
        assert_eq!(f.geographic_epsg, Some(6318));
        assert_eq!(f.citation.as_deref(), Some("NAD83_2011 / Nebraska (ft)"));
    }

    #[test]
    fn user_defined_codes_and_unit_sizes() {
        let dir = directory(&[
            [3072, 0, 1, USER_DEFINED],
            [3076, 0, 1, USER_DEFINED],
            [3077, DOUBLES, 1, 1],
        ]);
        let doubles: Vec<u8> = [0.0f64, 0.3048]
            .iter()
            .flat_map(|d| d.to_le_bytes())
            .collect();
        let f = geotiff_facts(&dir, Some(&doubles), None).unwrap();
        assert_eq!(f.projected_epsg, None);
        assert_eq!(f.horizontal_unit, Some(LinearUnit::Foot));
    }

    #[test]
    fn bad_directories_are_errors() {
        let mut dir = directory(&[[3076, 0, 1, 9002]]);
        dir.truncate(dir.len() - 2);
        assert!(matches!(
            geotiff_facts(&dir, None, None),
            Err(GeoTiffError::Truncated { keys: 1, .. })
        ));
        let dir = directory(&[[3073, ASCII, 40, 0]]);
        assert_eq!(
            geotiff_facts(&dir, None, Some(b"short|")),
            Err(GeoTiffError::BadReference { id: 3073 })
        );
    }
}
