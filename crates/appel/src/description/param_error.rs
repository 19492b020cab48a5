//! A plugin's parameter that makes no sense, and the checks every plugin's parameters share. A
//! plugin's description file (`bsdf/`, `emitter/`) returns these; validation turns the key into
//! the value's path and the loader into a line.

/// A parameter that makes no sense: its key (the loader turns it into a line; a key inside a
/// nested table is written with dots, `checker.size`) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    pub key: &'static str,
    pub message: String,
}

impl ParamError {
    pub fn new(key: &'static str, message: impl Into<String>) -> Self {
        ParamError {
            key,
            message: message.into(),
        }
    }
}

/// Checks that every component of `v` is finite.
pub(crate) fn finite(key: &'static str, v: &[f32]) -> Result<(), ParamError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(ParamError::new(
            key,
            format!("`{key}` must be finite, got {v:?}"),
        ))
    }
}

/// Checks that `v` is finite and not negative.
pub(crate) fn non_negative(key: &'static str, v: &[f32]) -> Result<(), ParamError> {
    finite(key, v)?;
    if v.iter().any(|&x| x < 0.0) {
        return Err(ParamError::new(
            key,
            format!("`{key}` must not be negative, got {v:?}"),
        ));
    }
    Ok(())
}

/// Checks that `v` is a finite vector other than zero.
pub(crate) fn non_zero(key: &'static str, v: &[f32]) -> Result<(), ParamError> {
    finite(key, v)?;
    if v.iter().any(|&x| x != 0.0) {
        Ok(())
    } else {
        Err(ParamError::new(
            key,
            format!("`{key}` must be a non-zero vector"),
        ))
    }
}

/// Checks that `v` is a finite number above zero.
pub(crate) fn positive(key: &'static str, v: f32) -> Result<(), ParamError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(ParamError::new(
            key,
            format!("`{key}` must be a positive number, got {v}"),
        ))
    }
}
