//! The in-memory point cloud shared by every step of the pipeline.

/// Errors about the shape of a [`Cloud`] itself (not about any file format).
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum CloudError {
    /// An optional attribute column does not have one value per point.
    #[error("attribute `{name}` has {got} values but the cloud has {expected} points")]
    AttributeLength {
        /// Attribute name (intensity, label, building).
        name: &'static str,
        /// Number of points.
        expected: usize,
        /// Number of values in the attribute.
        got: usize,
    },
}

/// A point cloud in a local metric frame (`map`), structure-of-arrays.
///
/// Coordinates are `f32` relative to `origin` (f64, e.g. a projected CRS offset),
/// so real-world coordinates of millions of metres keep millimetre precision.
/// Optional attributes, when present, hold exactly one value per point.
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
    /// The local frame's origin in the source coordinate system.
    pub origin: [f64; 3],
}

impl Cloud {
    /// A cloud of bare positions with origin zero.
    pub fn from_xyz(xyz: Vec<[f32; 3]>) -> Self {
        Self {
            xyz,
            ..Self::default()
        }
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
        let check = |name: &'static str, got: Option<usize>| match got {
            Some(got) if got != n => Err(CloudError::AttributeLength {
                name,
                expected: n,
                got,
            }),
            _ => Ok(()),
        };
        check("intensity", self.intensity.as_ref().map(Vec::len))?;
        check("label", self.label.as_ref().map(Vec::len))?;
        check("building", self.building.as_ref().map(Vec::len))?;
        check("return_number", self.return_number.as_ref().map(Vec::len))?;
        check(
            "number_of_returns",
            self.number_of_returns.as_ref().map(Vec::len),
        )
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

    /// Both echo columns when the cloud has them and they say something
    /// (some pulse gave a known number of returns).
    pub fn echoes(&self) -> Option<(&[u8], &[u8])> {
        let (rn, nr) = (
            self.return_number.as_deref()?,
            self.number_of_returns.as_deref()?,
        );
        (rn.len() == nr.len() && nr.iter().any(|&n| n > 0)).then_some((rn, nr))
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
            Err(CloudError::AttributeLength {
                name: "label",
                expected: 3,
                got: 2
            })
        );
        c.label = Some(vec![1, 2, 3]);
        assert_eq!(c.validate(), Ok(()));
    }

    #[test]
    fn bounds_cover_all_points() {
        let c = Cloud::from_xyz(vec![[1.0, -2.0, 3.0], [-1.0, 5.0, 0.5]]);
        assert_eq!(c.bounds(), Some(([-1.0, -2.0, 0.5], [1.0, 5.0, 3.0])));
        assert_eq!(Cloud::default().bounds(), None);
    }
}
