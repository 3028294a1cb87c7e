//! The one error a model parameter can raise: out of its allowed range.

/// A parameter outside its allowed range; names the field, the value and the range (a
/// setting that is not a number, e.g. a choice of parameter, has the value NaN and is named
/// without it).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}{} is out of range: allowed {allowed}", shown(*.value))]
pub struct ParamError {
    /// The parameter's name as users write it (`lambda_p`, `adr`, `omega`...).
    pub field: &'static str,
    /// The rejected value.
    pub value: f64,
    /// The allowed range in words, e.g. `> 0` or `[0, 4.236)`.
    pub allowed: String,
}

/// ` = value`, or nothing for a setting that is not a number.
fn shown(value: f64) -> String {
    if value.is_nan() {
        String::new()
    } else {
        format!(" = {value}")
    }
}

/// Accepts `value` if it is finite and `ok(value)` holds, else names the field and the range.
pub fn check(
    field: &'static str,
    value: f64,
    ok: impl Fn(f64) -> bool,
    allowed: impl Into<String>,
) -> Result<f64, ParamError> {
    if value.is_finite() && ok(value) {
        Ok(value)
    } else {
        Err(ParamError {
            field,
            value,
            allowed: allowed.into(),
        })
    }
}
