//! A parameter out of range: the one error every step's `validate` gives
//! (ground filter, features, forest, slices, skeleton, detection, targets,
//! footprints, graph, route, exploration, reconstruction, the LiDARs), so a
//! wrong value reads the same whichever section holds it.

/// A parameter outside its allowed range, named as in its params file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{section} parameter `{field}` = {value}: {expected}")]
pub struct ParamError {
    /// The section or component it belongs to (`graph`, `explore`, ...).
    pub section: &'static str,
    /// The field's name as in the params file.
    pub field: &'static str,
    /// The value given (counts and flags as numbers too).
    pub value: f64,
    /// What it must be.
    pub expected: String,
}

/// The range checks of one section: each names the field it finds wrong.
#[derive(Debug, Clone, Copy)]
pub struct Checks(pub &'static str);

impl Checks {
    /// `Ok` when `ok`, else the error for `field` = `value`, which must be
    /// `expected`.
    pub fn that(
        self,
        ok: bool,
        field: &'static str,
        value: impl Into<f64>,
        expected: &str,
    ) -> Result<(), ParamError> {
        if ok {
            return Ok(());
        }
        Err(ParamError {
            section: self.0,
            field,
            value: value.into(),
            expected: expected.to_owned(),
        })
    }

    /// `value` must be finite and > 0.
    pub fn positive(self, field: &'static str, value: impl Into<f64>) -> Result<(), ParamError> {
        let v = value.into();
        self.that(v.is_finite() && v > 0.0, field, v, "must be finite and > 0")
    }

    /// `value` must be finite and ≥ 0.
    pub fn non_negative(
        self,
        field: &'static str,
        value: impl Into<f64>,
    ) -> Result<(), ParamError> {
        let v = value.into();
        self.that(
            v.is_finite() && v >= 0.0,
            field,
            v,
            "must be finite and ≥ 0",
        )
    }

    /// `value` must lie in `[lo, hi]` (compared in `value`'s own type, so an
    /// `f32` bound means what it says).
    pub fn within<T>(self, field: &'static str, value: T, lo: T, hi: T) -> Result<(), ParamError>
    where
        T: Into<f64> + Copy + std::fmt::Display,
    {
        let v = value.into();
        // NaN fails both comparisons, so it is out of every range.
        if v >= lo.into() && v <= hi.into() {
            return Ok(());
        }
        self.that(false, field, v, &format!("must be in [{lo}, {hi}]"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_check_names_its_section_field_and_rule() {
        let c = Checks("graph");
        assert_eq!(c.positive("clearance_m", 0.5f32), Ok(()));
        let e = c.positive("clearance_m", f32::NAN).unwrap_err();
        assert_eq!((e.section, e.field), ("graph", "clearance_m"));
        assert_eq!(c.non_negative("a", 0.0), Ok(()));
        assert!(c.non_negative("a", -0.1).is_err());
        assert_eq!(c.within("k", 3u32, 3, 100), Ok(()));
        assert_eq!(c.within("r", 0.02f32, 0.02, 5.0), Ok(()));
        let e = c.within("k", f64::NAN, 3.0, 100.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "graph parameter `k` = NaN: must be in [3, 100]"
        );
    }
}
