//! From skyground's local metric frame back to the source CRS and its unit.

use serde_json::{Value, json};

use super::{Crs, LinearUnit};

/// The local frame of a cloud (origin in metres) and the CRS it came from.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SourceFrame {
    /// The local frame's origin, metres (a [`crate::cloud::Cloud`]'s `origin`).
    pub origin: [f64; 3],
    /// The source CRS; `None`: unknown CRS, metres.
    pub crs: Option<Crs>,
}

impl SourceFrame {
    /// The frame of a cloud's `origin` and `crs`.
    pub fn new(origin: [f64; 3], crs: Option<Crs>) -> Self {
        Self { origin, crs }
    }

    /// Metres per source unit for x, y, z.
    pub fn to_metre(&self) -> [f64; 3] {
        self.crs.as_ref().map_or([1.0; 3], Crs::to_metre)
    }

    /// The horizontal unit (metre when the CRS is unknown).
    pub fn unit(&self) -> LinearUnit {
        self.crs
            .as_ref()
            .map_or(LinearUnit::Metre, |c| c.horizontal_unit.clone())
    }

    /// A local point (metres) in source coordinates and unit.
    pub fn to_source(&self, p: [f64; 3]) -> [f64; 3] {
        let f = self.to_metre();
        [0, 1, 2].map(|k| (self.origin[k] + p[k]) / f[k])
    }

    /// A local xy (metres) in source coordinates and unit.
    pub fn to_source_xy(&self, p: [f64; 2]) -> [f64; 2] {
        let q = self.to_source([p[0], p[1], 0.0]);
        [q[0], q[1]]
    }

    /// A length in metres in the source's horizontal unit.
    pub fn length_to_source(&self, metres: f64) -> f64 {
        metres / self.to_metre()[0]
    }

    /// GeoJSON's legacy `crs` member naming the source CRS: the EPSG URN, else
    /// its WKT (GDAL and QGIS read both); `None` when the CRS is unknown.
    pub fn geojson_crs_member(&self) -> Option<Value> {
        let crs = self.crs.as_ref()?;
        let name = crs.urn().or_else(|| crs.wkt.clone())?;
        Some(json!({"type": "name", "properties": {"name": name}}))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_metres_go_back_to_feet_and_the_crs_is_named() {
        let crs = Crs::from_epsg(6880).unwrap();
        let ft = crs.to_metre()[0];
        let f = SourceFrame::new([2_445_000.0 * ft, 603_000.0 * ft, 0.0], Some(crs));
        let p = f.to_source([ft * 10.0, ft * 20.0, ft * 5.0]);
        for (a, b) in p.iter().zip([2_445_010.0, 603_020.0, 5.0]) {
            assert!((a - b).abs() < 1e-6, "{p:?}");
        }
        assert!((f.length_to_source(0.3048006096012192) - 1.0).abs() < 1e-12);
        let member = f.geojson_crs_member().unwrap();
        assert_eq!(member["properties"]["name"], "urn:ogc:def:crs:EPSG::6880");
        assert_eq!(SourceFrame::default().geojson_crs_member(), None);
        assert_eq!(
            SourceFrame::default().to_source([1.0, 2.0, 3.0]),
            [1.0, 2.0, 3.0]
        );
    }
}
