//! The one error a model parameter or setting can raise: out of its allowed range.

/// A parameter or setting outside its allowed range; names the field, the value and the range
/// (a setting that is not a number, e.g. a choice of parameter, has the value
/// [`ParamError::NOT_NUMERIC`] and is named without it).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}{} is out of range: allowed {allowed}", shown(*.value))]
pub struct ParamError {
    /// The field's path as users write it (`lambda_p`, `adr`, `steady.resolution.max_step`).
    pub field: String,
    /// The rejected value.
    pub value: f64,
    /// The allowed range in words, e.g. `> 0` or `[0, 4.236)`.
    pub allowed: String,
}

impl ParamError {
    /// The value of an error about a setting that is not a number (a choice): a NaN of its
    /// own bits, unlike the NaN a user writes, which is shown.
    pub const NOT_NUMERIC: f64 = f64::from_bits(0x7ff8_0000_0000_0bad);

    /// The same error for a field inside `parent` (`max_step` inside `steady.resolution`).
    pub fn within(mut self, parent: &str) -> Self {
        self.field = format!("{parent}.{}", self.field);
        self
    }

    /// The error of a value of `field` that sets a model parameter (`values = -1` sets `adr`):
    /// named `field`, with the parameter's range.
    pub fn as_value_of(self, field: &str) -> Self {
        ParamError {
            allowed: format!("{} (as {})", self.allowed, self.field),
            field: field.to_string(),
            value: self.value,
        }
    }

    /// The same error for the field named with `suffix` (`phi_dc` of membrane II is
    /// `phi_dc_ii`).
    pub fn suffixed(mut self, suffix: &str) -> Self {
        self.field.push_str(suffix);
        self
    }
}

/// ` = value`, or nothing for a setting that is not a number.
fn shown(value: f64) -> String {
    if value.to_bits() == ParamError::NOT_NUMERIC.to_bits() {
        String::new()
    } else {
        format!(" = {}", compact(value))
    }
}

/// A number as people write it: `-2`, `0.04`, and `1e308` or `5e-324` rather than hundreds of
/// digits.
pub fn compact(value: f64) -> String {
    let plain = value.to_string();
    if plain.len() <= 16 {
        plain
    } else {
        format!("{value:?}")
    }
}

/// Accepts `value` if it is finite and `ok(value)` holds, else names the field and the range.
pub fn check(
    field: &str,
    value: f64,
    ok: impl Fn(f64) -> bool,
    allowed: impl Into<String>,
) -> Result<f64, ParamError> {
    if value.is_finite() && ok(value) {
        Ok(value)
    } else {
        Err(ParamError {
            field: field.to_string(),
            value,
            allowed: allowed.into(),
        })
    }
}

/// Accepts `value` in the closed range [`lo`, `hi`], saying so in the error.
pub fn check_in(field: &str, value: f64, lo: f64, hi: f64) -> Result<f64, ParamError> {
    check(
        field,
        value,
        |v| (lo..=hi).contains(&v),
        format!("[{lo}, {hi}]"),
    )
}
