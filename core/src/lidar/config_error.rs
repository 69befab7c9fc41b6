//! The error every sensor configuration reports.

/// A sensor configuration value out of its valid range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("sensor config `{field}` = {value}: {expected}")]
pub struct ConfigError {
    /// The field's name as in the YAML/JSON config.
    pub field: &'static str,
    /// The value given.
    pub value: f64,
    /// What would be valid.
    pub expected: &'static str,
}

/// `Ok` when `ok`, else the error for `field`.
pub(crate) fn check(
    ok: bool,
    field: &'static str,
    value: impl Into<f64>,
    expected: &'static str,
) -> Result<(), ConfigError> {
    if ok {
        Ok(())
    } else {
        Err(ConfigError {
            field,
            value: value.into(),
            expected,
        })
    }
}

/// `dropout`, the share of pulses lost, must lie in [0, 1].
pub(crate) fn check_dropout(dropout: f32) -> Result<(), ConfigError> {
    check(
        (0.0..=1.0).contains(&dropout),
        "dropout",
        dropout,
        "must be in [0, 1]",
    )
}
