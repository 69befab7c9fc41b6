//! Linear units of a coordinate reference system and their size in metres.

use std::fmt;

/// A linear unit: what one coordinate step of a CRS axis measures.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum LinearUnit {
    /// The metre (EPSG 9001).
    Metre,
    /// The international foot, exactly 0.3048 m (EPSG 9002).
    Foot,
    /// The US survey foot, 1200/3937 m (EPSG 9003).
    UsSurveyFoot,
    /// Any other linear unit, by name and size.
    Other {
        /// The unit's name as the source gave it.
        name: String,
        /// Metres per unit.
        to_metre: f64,
    },
}

/// Metres in one US survey foot.
pub const US_SURVEY_FOOT_M: f64 = 1200.0 / 3937.0;
/// Metres in one international foot.
pub const FOOT_M: f64 = 0.3048;

/// Relative tolerance when recognising a unit from its size (WKT rounds it).
const SIZE_TOLERANCE: f64 = 1e-9;

impl LinearUnit {
    /// Metres per unit.
    pub fn to_metre(&self) -> f64 {
        match self {
            Self::Metre => 1.0,
            Self::Foot => FOOT_M,
            Self::UsSurveyFoot => US_SURVEY_FOOT_M,
            Self::Other { to_metre, .. } => *to_metre,
        }
    }

    /// The unit's name (`metre`, `foot`, `US survey foot`, or as given).
    pub fn name(&self) -> &str {
        match self {
            Self::Metre => "metre",
            Self::Foot => "foot",
            Self::UsSurveyFoot => "US survey foot",
            Self::Other { name, .. } => name,
        }
    }

    /// A short symbol for labels and CSV headers (`m`, `ft`, `ftUS`).
    pub fn symbol(&self) -> &str {
        match self {
            Self::Metre => "m",
            Self::Foot => "ft",
            Self::UsSurveyFoot => "ftUS",
            Self::Other { name, .. } => name,
        }
    }

    /// The EPSG unit code, for the three units we name.
    pub fn epsg(&self) -> Option<u16> {
        match self {
            Self::Metre => Some(9001),
            Self::Foot => Some(9002),
            Self::UsSurveyFoot => Some(9003),
            Self::Other { .. } => None,
        }
    }

    /// The unit of an EPSG unit-of-measure code (GeoTIFF `ProjLinearUnitsGeoKey`).
    pub fn from_epsg(code: u16) -> Option<Self> {
        let other = |name: &str, to_metre: f64| {
            Some(Self::Other {
                name: name.into(),
                to_metre,
            })
        };
        match code {
            9001 => Some(Self::Metre),
            9002 => Some(Self::Foot),
            9003 => Some(Self::UsSurveyFoot),
            9005 => other("Clarke's foot", 0.304_797_265_4),
            9014 => other("fathom", 1.8288),
            9030 => other("nautical mile", 1852.0),
            9036 => other("kilometre", 1000.0),
            9070 => other("British foot (1936)", 0.304_800_749_1),
            _ => None,
        }
    }

    /// The unit a WKT `UNIT["name", size]` / `LENGTHUNIT[...]` describes.
    ///
    /// The size decides (names vary: `Foot_US`, `US survey foot`, `foot`); a size
    /// that is none of ours keeps the source's name.
    pub fn from_name_and_size(name: &str, to_metre: f64) -> Option<Self> {
        if !(to_metre.is_finite() && to_metre > 0.0) {
            return None;
        }
        let near = |v: f64| ((to_metre - v) / v).abs() < SIZE_TOLERANCE;
        Some(if near(1.0) {
            Self::Metre
        } else if near(FOOT_M) {
            Self::Foot
        } else if near(US_SURVEY_FOOT_M) {
            Self::UsSurveyFoot
        } else {
            Self::Other {
                name: name.into(),
                to_metre,
            }
        })
    }

    /// Parses a unit a user typed: `m`, `metre`, `ft`, `foot`, `ftUS`, `us-ft`, `usft`.
    pub fn parse(text: &str) -> Option<Self> {
        match text.trim().to_ascii_lowercase().as_str() {
            "m" | "metre" | "meter" | "metres" | "meters" => Some(Self::Metre),
            "ft" | "foot" | "feet" | "international foot" => Some(Self::Foot),
            "ftus" | "us-ft" | "usft" | "us survey foot" | "us_survey_foot" => {
                Some(Self::UsSurveyFoot)
            }
            _ => None,
        }
    }
}

impl fmt::Display for LinearUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn epsg_codes_give_the_three_units_and_their_sizes() {
        assert_eq!(LinearUnit::from_epsg(9001), Some(LinearUnit::Metre));
        assert_eq!(LinearUnit::from_epsg(9002).unwrap().to_metre(), 0.3048);
        let us = LinearUnit::from_epsg(9003).unwrap();
        assert!((us.to_metre() - 0.304_800_609_601_219_2).abs() < 1e-15);
        assert_eq!(LinearUnit::from_epsg(9102), None, "degree is not linear");
    }

    #[test]
    fn wkt_sizes_are_recognised_whatever_the_name() {
        let us = LinearUnit::from_name_and_size("Foot_US", 0.304_800_609_601_219_24);
        assert_eq!(us, Some(LinearUnit::UsSurveyFoot));
        let ft = LinearUnit::from_name_and_size("foot", 0.3048);
        assert_eq!(ft, Some(LinearUnit::Foot));
        let m = LinearUnit::from_name_and_size("Meter", 1.0);
        assert_eq!(m, Some(LinearUnit::Metre));
        let yard = LinearUnit::from_name_and_size("yard", 0.9144).unwrap();
        assert_eq!(yard.name(), "yard");
        assert_eq!(yard.to_metre(), 0.9144);
        assert_eq!(LinearUnit::from_name_and_size("bad", 0.0), None);
    }

    #[test]
    fn user_spellings_parse() {
        assert_eq!(LinearUnit::parse("ft"), Some(LinearUnit::Foot));
        assert_eq!(LinearUnit::parse("ftUS"), Some(LinearUnit::UsSurveyFoot));
        assert_eq!(LinearUnit::parse(" M "), Some(LinearUnit::Metre));
        assert_eq!(LinearUnit::parse("furlong"), None);
    }
}
