//! The one error a model parameter can raise: out of its allowed range.

/// A parameter outside its allowed range; names the field, the value and the range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field} = {value} is out of range: allowed {allowed}")]
pub struct ParamError {
    /// The parameter's name as users write it (`lambda_p`, `adr`, `omega`...).
    pub field: &'static str,
    /// The rejected value.
    pub value: f64,
    /// The allowed range in words, e.g. `> 0` or `[0, 4.236)`.
    pub allowed: String,
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
