//! The in-memory point cloud shared by every step of the pipeline.

use crate::crs::{Crs, LinearUnit, SourceFrame, UnitSource};

/// A per-point column (labels, building ids, heights, an attribute) that
/// does not hold one value per point: the one error every step that takes
/// columns beside `xyz` gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("`{column}` has {got} values but the cloud has {expected} points")]
pub struct ColumnLength {
    /// The column's name.
    pub column: &'static str,
    /// Number of points.
    pub expected: usize,
    /// Number of values in the column.
    pub got: usize,
}

impl ColumnLength {
    /// `Ok` when `column` has one value (`got` of them) per point (`expected`).
    pub fn check(column: &'static str, expected: usize, got: usize) -> Result<(), Self> {
        if got == expected {
            return Ok(());
        }
        Err(Self {
            column,
            expected,
            got,
        })
    }
}

/// Errors about the shape of a [`Cloud`] itself (not about any file format).
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum CloudError {
    /// An optional attribute column does not have one value per point.
    #[error(transparent)]
    AttributeLength(#[from] ColumnLength),
}

/// A point cloud in a local metric frame (`map`), structure-of-arrays.
///
/// Coordinates are `f32` relative to `origin` (f64, e.g. a projected CRS offset),
/// so real-world coordinates of millions of metres keep millimetre precision.
/// Optional attributes, when present, hold exactly one value per point.
///
/// Frame: `xyz` and `origin` are in metres. For a source CRS in other units
/// (feet), `origin + xyz` is the CRS coordinate times [`Crs::to_metre`] per
/// axis, i.e. the CRS coordinate is `(origin + xyz) / to_metre`
/// ([`Cloud::source_coordinates`]); readers scale in, writers scale back.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cloud {
    /// Point positions in the local frame, metres.
    pub xyz: Vec<[f32; 3]>,
    /// Return intensity (sensor units, as read).
    pub intensity: Option<Vec<f32>>,
    /// Class label (ASPRS LAS codes: 2 ground, 5 high vegetation, 6 building, ...).
    pub label: Option<Vec<u8>>,
    /// Building id (0 = none).
    pub building: Option<Vec<u32>>,
    /// Which return of its pulse each point is (1-based, as LAS; 0 = unknown).
    pub return_number: Option<Vec<u8>>,
    /// How many returns its pulse gave (as LAS; 0 = unknown).
    pub number_of_returns: Option<Vec<u8>>,
    /// The local frame's origin: the source CRS coordinate, scaled to metres.
    pub origin: [f64; 3],
    /// The source CRS with its records; `None`: unknown CRS, metres assumed.
    pub crs: Option<Crs>,
}

/// The positions whose entry in the per-point `column` (labels, building
/// ids) equals `value`.
pub fn positions_where<T: PartialEq>(xyz: &[[f32; 3]], column: &[T], value: T) -> Vec<[f32; 3]> {
    xyz.iter()
        .zip(column)
        .filter(|(_, c)| **c == value)
        .map(|(p, _)| *p)
        .collect()
}

impl Cloud {
    /// A cloud of bare positions with origin zero.
    pub fn from_xyz(xyz: Vec<[f32; 3]>) -> Self {
        Self {
            xyz,
            ..Self::default()
        }
    }

    /// Positions of the points labelled `label` (none when the cloud is unlabelled).
    pub fn xyz_of_class(&self, label: u8) -> Vec<[f32; 3]> {
        positions_where(&self.xyz, self.label.as_deref().unwrap_or_default(), label)
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.xyz.len()
    }

    /// True when the cloud has no points.
    pub fn is_empty(&self) -> bool {
        self.xyz.is_empty()
    }

    /// Checks that every present attribute has one value per point.
    pub fn validate(&self) -> Result<(), CloudError> {
        let n = self.xyz.len();
        let columns = [
            ("intensity", self.intensity.as_ref().map(Vec::len)),
            ("label", self.label.as_ref().map(Vec::len)),
            ("building", self.building.as_ref().map(Vec::len)),
            ("return_number", self.return_number.as_ref().map(Vec::len)),
            (
                "number_of_returns",
                self.number_of_returns.as_ref().map(Vec::len),
            ),
        ];
        for (column, got) in columns {
            if let Some(got) = got {
                ColumnLength::check(column, n, got)?;
            }
        }
        Ok(())
    }

    /// Number of points per label value (index = label), when labels exist.
    pub fn label_histogram(&self) -> Option<[usize; 256]> {
        let labels = self.label.as_ref()?;
        let mut h = [0usize; 256];
        for &l in labels {
            h[usize::from(l)] += 1;
        }
        Some(h)
    }

    /// Both echo columns when the cloud has them and they say something:
    /// some pulse gave more than one return. A survey where none did (a
    /// first-return product, photogrammetry, a file whose echoes were
    /// reset) cannot tell a crown from a roof by its echoes.
    pub fn echoes(&self) -> Option<(&[u8], &[u8])> {
        let (rn, nr) = (
            self.return_number.as_deref()?,
            self.number_of_returns.as_deref()?,
        );
        (rn.len() == nr.len() && nr.iter().any(|&n| n > 1)).then_some((rn, nr))
    }

    /// The points `rows` (in that order) with all their columns.
    pub fn subset(&self, rows: &[usize]) -> Cloud {
        fn pick<T: Copy>(col: &Option<Vec<T>>, rows: &[usize]) -> Option<Vec<T>> {
            col.as_ref()
                .map(|c| rows.iter().filter_map(|&i| c.get(i).copied()).collect())
        }
        Cloud {
            xyz: rows
                .iter()
                .filter_map(|&i| self.xyz.get(i).copied())
                .collect(),
            intensity: pick(&self.intensity, rows),
            label: pick(&self.label, rows),
            building: pick(&self.building, rows),
            return_number: pick(&self.return_number, rows),
            number_of_returns: pick(&self.number_of_returns, rows),
            origin: self.origin,
            crs: self.crs.clone(),
        }
    }

    /// Metres per source unit for x, y, z (1 without a CRS).
    pub fn to_metre(&self) -> [f64; 3] {
        self.crs.as_ref().map_or([1.0; 3], Crs::to_metre)
    }

    /// The local frame and source CRS (what footprints and GeoJSON are read and written in).
    pub fn frame(&self) -> SourceFrame {
        SourceFrame::new(self.origin, self.crs.clone())
    }

    /// A local point in the source CRS and unit (what writers put in files).
    pub fn source_coordinates(&self, p: [f32; 3]) -> [f64; 3] {
        let f = self.to_metre();
        [0, 1, 2].map(|k| (self.origin[k] + f64::from(p[k])) / f[k])
    }

    /// Takes the source coordinates to be in `unit` (a user's `--units` for a
    /// file that does not say, or says wrongly): rescales points and origin
    /// from the unit assumed so far, keeps the CRS records.
    pub fn set_unit(&mut self, unit: LinearUnit) {
        let mut crs = self
            .crs
            .clone()
            .unwrap_or_else(|| Crs::user_unit(LinearUnit::Metre));
        crs.horizontal_unit = unit.clone();
        crs.vertical_unit = unit;
        crs.unit_source = UnitSource::User;
        self.set_crs(crs);
    }

    /// Takes the source coordinates to be in `crs` (a user's `--crs` for a
    /// file that states none): points and origin are rescaled from the unit
    /// assumed so far to the CRS's.
    pub fn set_crs(&mut self, crs: Crs) {
        let old = self.to_metre();
        let new = crs.to_metre();
        self.crs = Some(crs);
        self.rescale([0, 1, 2].map(|k| new[k] / old[k]));
    }

    /// Multiplies points and origin by `r` per axis (a change of unit).
    pub(crate) fn rescale(&mut self, r: [f64; 3]) {
        if r == [1.0; 3] {
            return;
        }
        for p in &mut self.xyz {
            for k in 0..3 {
                // Local offsets stay small: f32 keeps their precision after scaling.
                p[k] = (f64::from(p[k]) * r[k]) as f32;
            }
        }
        for (o, r) in self.origin.iter_mut().zip(r) {
            *o *= r;
        }
    }

    /// Axis-aligned bounds `(min, max)` of the positions, or `None` when empty.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let first = *self.xyz.first()?;
        Some(self.xyz.iter().fold((first, first), |(mut lo, mut hi), p| {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
            (lo, hi)
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validate_reports_attribute_length_mismatch() {
        let mut c = Cloud::from_xyz(vec![[0.0; 3]; 3]);
        c.label = Some(vec![1, 2]);
        assert_eq!(
            c.validate(),
            Err(CloudError::AttributeLength(ColumnLength {
                column: "label",
                expected: 3,
                got: 2
            }))
        );
        c.label = Some(vec![1, 2, 3]);
        assert_eq!(c.validate(), Ok(()));
    }

    #[test]
    fn echoes_count_only_when_some_pulse_gave_several_returns() {
        let mut c = Cloud::from_xyz(vec![[0.0; 3]; 3]);
        assert!(c.echoes().is_none());
        c.return_number = Some(vec![1, 1, 1]);
        c.number_of_returns = Some(vec![1, 1, 1]);
        assert!(c.echoes().is_none(), "every pulse one return: no echo cue");
        c.return_number = Some(vec![1, 1, 2]);
        c.number_of_returns = Some(vec![1, 2, 2]);
        assert!(c.echoes().is_some());
        c.number_of_returns = Some(vec![1, 2]);
        assert!(c.echoes().is_none(), "columns of unequal length");
    }

    #[test]
    fn bounds_cover_all_points() {
        let c = Cloud::from_xyz(vec![[1.0, -2.0, 3.0], [-1.0, 5.0, 0.5]]);
        assert_eq!(c.bounds(), Some(([-1.0, -2.0, 0.5], [1.0, 5.0, 3.0])));
        assert_eq!(Cloud::default().bounds(), None);
    }

    #[test]
    fn set_unit_rescales_to_metres_and_source_coordinates_undo_it() {
        let mut c = Cloud::from_xyz(vec![[10.0, 20.0, 5.0]]);
        c.origin = [1000.0, 2000.0, 100.0];
        assert_eq!(c.source_coordinates(c.xyz[0]), [1010.0, 2020.0, 105.0]);
        c.set_unit(LinearUnit::Foot);
        assert_eq!(c.to_metre(), [0.3048; 3]);
        assert!((c.xyz[0][0] - 3.048).abs() < 1e-6);
        assert!((c.origin[1] - 609.6).abs() < 1e-9);
        let back = c.source_coordinates(c.xyz[0]);
        for (b, want) in back.iter().zip([1010.0, 2020.0, 105.0]) {
            assert!((b - want).abs() < 1e-5, "{back:?}");
        }
        c.set_unit(LinearUnit::Metre);
        assert!((c.xyz[0][2] - 5.0).abs() < 1e-6);
        assert_eq!(
            c.crs.as_ref().map(|k| k.unit_source),
            Some(UnitSource::User)
        );
    }
}
