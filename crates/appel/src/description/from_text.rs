//! Scene text (TOML or JSON) to a validated description, with each problem placed at the line and
//! column where the value is written.

use super::parse::{self, parse_description, toml_span, PathSeg, Syntax};
use super::validate::{self, Invalid};
use super::Description;
use crate::error::{Error, Location, Result};
use std::path::Path;

/// Parses and validates scene text; `origin` names it in error messages.
pub fn description_from_str(text: &str, syntax: Syntax, origin: &Path) -> Result<Description> {
    let description = parse_description(text, syntax, origin)?;
    validate::validate(&description).map_err(|invalid| located(&invalid, text, syntax, origin))?;
    Ok(description)
}

/// A validation problem as an error at the line and column where the value is written.
pub fn located(invalid: &Invalid, text: &str, syntax: Syntax, origin: &Path) -> Error {
    let location = match syntax {
        Syntax::Toml => toml_span(text, &invalid.path)
            .map(|span| {
                let (line, col) = parse::line_column(text, span.start);
                Location::line(origin, line, Some(col))
            })
            .unwrap_or_else(|| Location::file(origin)),
        Syntax::Json => parse::json_offset(text, &invalid.path)
            .map(|at| {
                let (line, col) = parse::line_column(text, at);
                Location::line(origin, line, Some(col))
            })
            .unwrap_or_else(|| Location::file(origin)),
    };
    let message = format!("{}: {}", path_string(&invalid.path), invalid.message);
    Error::input(location, message)
}

/// `shape[2].radius`, for messages.
pub fn path_string(path: &[PathSeg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            PathSeg::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            PathSeg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}
