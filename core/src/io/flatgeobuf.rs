//! FlatGeobuf footprints (`.fgb`, what `ogr2ogr -f FlatGeobuf` writes):
//! Polygon and MultiPolygon features with their properties; the own id as
//! for GeoJSON ([`super::ids`]), numeric ids 1.. in file order, the CRS
//! from the header.

use std::collections::HashMap;
use std::io::Cursor;

use flatgeobuf::{FallibleStreamingIterator, FeatureProperties, FgbReader, GeozeroGeometry};
use geo::{Coord, LineString, Polygon};
use geozero::GeomProcessor;
use geozero::error::Result as GzResult;
use serde_json::{Map, Value};

use crate::crs::Crs;
use crate::footprint::error::{ParseError, RingProblem, Skipped, shape};
use crate::footprint::ids::{ReadOptions, check_named_field, own_id};
use crate::footprint::{Footprint, Loaded};

/// Decodes FlatGeobuf bytes (source CRS and unit) and the CRS its header names.
pub fn parse_fgb(data: &[u8], options: &ReadOptions) -> Result<(Loaded, Option<Crs>), ParseError> {
    if data.is_empty() {
        return Err(ParseError::Empty);
    }
    // The reader indexes its buffers as the header says: a damaged file
    // must be an error, not a panic.
    std::panic::catch_unwind(|| read(data, options)).unwrap_or_else(|_| {
        Err(shape(
            "FlatGeobuf file is damaged (its buffers do not match its header)",
        ))
    })
}

fn fgb_err(e: impl std::fmt::Display) -> ParseError {
    shape(&format!("FlatGeobuf: {e}"))
}

fn read(data: &[u8], options: &ReadOptions) -> Result<(Loaded, Option<Crs>), ParseError> {
    let reader = FgbReader::open(Cursor::new(data)).map_err(fgb_err)?;
    let header = reader.header();
    let crs = header
        .crs()
        .filter(|c| c.org().is_none_or(|o| o.eq_ignore_ascii_case("EPSG")))
        .and_then(|c| u32::try_from(c.code()).ok())
        .filter(|&code| code > 0)
        .and_then(|code| Crs::from_epsg(code).ok());
    let mut features = reader.select_all_seq().map_err(fgb_err)?;
    let (mut footprints, mut skipped) = (Vec::new(), Vec::new());
    let (mut named, mut first_props) = (0usize, None::<Map<String, Value>>);
    let mut k = 0usize;
    while let Some(f) = features.next().map_err(fgb_err)? {
        let props: Map<String, Value> = f
            .properties()
            .unwrap_or_default()
            .into_iter()
            .map(|(n, v)| (n, Value::String(v)))
            .collect::<HashMap<_, _>>()
            .into_iter()
            .collect();
        let own = own_id(Some(&props), options);
        named += usize::from(own.is_some());
        first_props.get_or_insert_with(|| props.clone());
        let mut rings = Rings::default();
        let label = format!("feature {k}");
        k += 1;
        if f.process_geom(&mut rings).is_err() || rings.polygons.is_empty() {
            skipped.push(Skipped {
                source: label,
                problem: RingProblem::NotPolygon("not a (multi)polygon".into()),
            });
            continue;
        }
        let id = u32::try_from(footprints.len() + 1).unwrap_or(u32::MAX);
        let name = own.unwrap_or_else(|| format!("feature_{}", k - 1));
        match Footprint::from_parts(id, name, &rings.polygons) {
            Some(fp) => footprints.push(fp),
            None => skipped.push(Skipped {
                source: label,
                problem: RingProblem::NoArea,
            }),
        }
    }
    check_named_field(options, named, first_props.as_ref())?;
    Ok((Loaded::new(footprints, skipped)?, crs))
}

/// Collects polygons (outer ring, then holes) from geozero's callbacks.
#[derive(Default)]
struct Rings {
    polygons: Vec<Polygon<f64>>,
    current: Vec<LineString<f64>>,
    ring: Vec<Coord<f64>>,
    in_polygon: bool,
}

impl GeomProcessor for Rings {
    fn xy(&mut self, x: f64, y: f64, _idx: usize) -> GzResult<()> {
        if x.is_finite() && y.is_finite() {
            self.ring.push(Coord { x, y });
        }
        Ok(())
    }

    fn polygon_begin(&mut self, _tagged: bool, _size: usize, _idx: usize) -> GzResult<()> {
        self.in_polygon = true;
        self.current.clear();
        Ok(())
    }

    fn linestring_begin(&mut self, _tagged: bool, _size: usize, _idx: usize) -> GzResult<()> {
        self.ring.clear();
        Ok(())
    }

    fn linestring_end(&mut self, _tagged: bool, _idx: usize) -> GzResult<()> {
        if self.in_polygon && self.ring.len() >= 3 {
            self.current
                .push(LineString::new(std::mem::take(&mut self.ring)));
        }
        Ok(())
    }

    fn polygon_end(&mut self, _tagged: bool, _idx: usize) -> GzResult<()> {
        self.in_polygon = false;
        let mut rings = std::mem::take(&mut self.current).into_iter();
        if let Some(outer) = rings.next() {
            self.polygons.push(Polygon::new(outer, rings.collect()));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flatgeobuf::{FgbCrs, FgbWriter, FgbWriterOptions, GeometryType};
    use geozero::{ColumnValue, PropertyProcessor};

    /// Two BAG-like buildings, the second a MultiPolygon, EPSG:28992.
    fn sample() -> Vec<u8> {
        let options = FgbWriterOptions {
            crs: FgbCrs {
                code: 28992,
                ..Default::default()
            },
            ..Default::default()
        };
        let mut w = FgbWriter::create_with_options("panden", GeometryType::MultiPolygon, options)
            .expect("writer");
        let squares: [&[[f64; 2]]; 2] = [&[[0.0, 0.0]], &[[20.0, 0.0], [40.0, 0.0]]];
        for (k, origins) in squares.iter().enumerate() {
            w.property(
                0,
                "identificatie",
                &ColumnValue::String(&format!("050310000000{k}")),
            )
            .expect("property");
            w.multipolygon_begin(origins.len(), 0).expect("geometry");
            for (i, o) in origins.iter().enumerate() {
                w.polygon_begin(false, 1, i).expect("polygon");
                w.linestring_begin(false, 5, 0).expect("ring");
                for (j, d) in [
                    [0.0, 0.0],
                    [10.0, 0.0],
                    [10.0, 10.0],
                    [0.0, 10.0],
                    [0.0, 0.0],
                ]
                .iter()
                .enumerate()
                {
                    w.xy(o[0] + d[0], o[1] + d[1], j).expect("xy");
                }
                w.linestring_end(false, 0).expect("ring");
                w.polygon_end(false, i).expect("polygon");
            }
            w.multipolygon_end(0).expect("geometry");
            geozero::FeatureProcessor::feature_end(&mut w, k as u64).expect("feature");
        }
        let mut out = Vec::new();
        w.write(&mut out).expect("written");
        out
    }

    #[test]
    fn polygons_ids_and_crs_from_a_flatgeobuf_file() {
        let (loaded, crs) = parse_fgb(&sample(), &ReadOptions::default()).expect("reads");
        assert_eq!(crs.and_then(|c| c.epsg), Some(28992));
        // The writer's spatial index orders the features (Hilbert curve), not the file.
        let mut named: Vec<(&str, f64)> = loaded
            .footprints
            .iter()
            .map(|f| (f.name.as_str(), f.area()))
            .collect();
        named.sort_by(|a, b| a.0.cmp(b.0));
        let names: Vec<&str> = named.iter().map(|n| n.0).collect();
        assert_eq!(names, ["0503100000000", "0503100000001"]);
        assert!(
            (named[0].1 - 100.0).abs() < 1e-9 && (named[1].1 - 200.0).abs() < 1e-9,
            "{named:?}"
        );
        let e = parse_fgb(b"fgb\x03garbage", &ReadOptions::default()).expect_err("damaged");
        assert!(e.to_string().contains("FlatGeobuf"), "{e}");
        assert_eq!(
            parse_fgb(b"", &ReadOptions::default()).expect_err("empty"),
            ParseError::Empty
        );
    }
}
