//! The value of each property element (`<float>`, `<rgb>`, `<spectrum>`, ...) and of each
//! transform operation, read from its (already substituted) attributes by Mitsuba's rules.

use super::document::{Spectrum, Value};
use super::resolver::FileResolver;
use super::transform;
use super::xml::Loc;
use crate::error::{Error, Result};
use glam::DMat4;

/// An element's attributes after `$name` substitution, with its place and tag for messages.
pub struct Attrs<'a> {
    pub tag: &'a str,
    pub attrs: Vec<(String, String)>,
    pub loc: &'a Loc,
}

impl Attrs<'_> {
    pub fn get(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    pub fn describe(&self) -> String {
        match (self.get("type"), self.get("name")) {
            (Some(t), _) => format!("<{} type=\"{t}\">", self.tag),
            (None, Some(n)) => format!("<{} name=\"{n}\">", self.tag),
            (None, None) => format!("<{}>", self.tag),
        }
    }

    pub fn error(&self, message: impl std::fmt::Display) -> Error {
        self.loc.error(format!("{}: {message}", self.describe()))
    }

    /// Fails unless every attribute is in `allowed` and every one of `required` is present.
    pub fn check(&self, allowed: &[&str], required: &[&str]) -> Result<()> {
        if let Some((k, _)) = self
            .attrs
            .iter()
            .find(|(k, _)| !allowed.contains(&k.as_str()))
        {
            return Err(self.error(format!("unexpected attribute \"{k}\"")));
        }
        if let Some(r) = required.iter().find(|r| self.get(r).is_none()) {
            return Err(self.error(format!("missing attribute \"{r}\"")));
        }
        Ok(())
    }

    /// A required attribute.
    pub fn require(&self, name: &str) -> Result<&str> {
        self.get(name)
            .ok_or_else(|| self.error(format!("missing attribute \"{name}\"")))
    }
}

/// Splits a list of numbers on commas and white space, as Mitsuba's tokenizer does.
pub fn tokens(s: &str) -> Vec<&str> {
    s.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .collect()
}

/// A floating-point number (not NaN).
pub fn parse_float(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok().filter(|v| !v.is_nan())
}

fn float_attr(a: &Attrs, s: &str) -> Result<f64> {
    parse_float(s).ok_or_else(|| a.error(format!("could not parse the number \"{s}\"")))
}

fn floats(a: &Attrs, s: &str) -> Result<Vec<f64>> {
    tokens(s).into_iter().map(|t| float_attr(a, t)).collect()
}

/// `x`, `y`, `z` attributes, or one `value` of one or three numbers (not both); components
/// not given are `default`.
fn xyz(a: &Attrs, default: f64, all_required: bool) -> Result<[f64; 3]> {
    if let Some(v) = a.get("value") {
        if ["x", "y", "z"].iter().any(|k| a.get(k).is_some()) {
            return Err(a.error("\"value\" cannot be mixed with \"x\", \"y\", \"z\""));
        }
        return match floats(a, v)?.as_slice() {
            [s] => Ok([*s; 3]),
            [x, y, z] => Ok([*x, *y, *z]),
            _ => Err(a.error(format!("\"value\" needs 1 or 3 numbers, got \"{v}\""))),
        };
    }
    let mut out = [default; 3];
    for (o, k) in out.iter_mut().zip(["x", "y", "z"]) {
        match a.get(k) {
            Some(s) => *o = float_attr(a, s)?,
            None if all_required => return Err(a.error(format!("missing attribute \"{k}\""))),
            None => {}
        }
    }
    Ok(out)
}

/// The value of a property element (`tag` is not `transform`); `resolver` finds spectrum files.
pub fn property(a: &Attrs, resolver: &FileResolver) -> Result<Value> {
    let value = || a.require("value");
    match a.tag {
        "float" => {
            a.check(&["name", "value"], &["name", "value"])?;
            Ok(Value::Float(float_attr(a, value()?)?))
        }
        "integer" => {
            a.check(&["name", "value"], &["name", "value"])?;
            let v = value()?;
            v.trim()
                .parse::<i64>()
                .map(Value::Int)
                .map_err(|_| a.error(format!("could not parse the integer \"{v}\"")))
        }
        "boolean" => {
            a.check(&["name", "value"], &["name", "value"])?;
            match value()?.trim().to_ascii_lowercase().as_str() {
                "true" => Ok(Value::Bool(true)),
                "false" => Ok(Value::Bool(false)),
                v => Err(a.error(format!("expected \"true\" or \"false\", got \"{v}\""))),
            }
        }
        "string" => {
            a.check(&["name", "value"], &["name", "value"])?;
            Ok(Value::String(value()?.to_string()))
        }
        "point" | "vector" => {
            a.check(&["name", "value", "x", "y", "z"], &["name"])?;
            Ok(Value::Vector(xyz(a, 0.0, true)?))
        }
        "rgb" => {
            a.check(&["name", "value"], &["name", "value"])?;
            match floats(a, value()?)?.as_slice() {
                [v] => Ok(Value::Rgb([*v; 3])),
                [r, g, b] => Ok(Value::Rgb([*r, *g, *b])),
                _ => Err(a.error("<rgb> needs one or three numbers")),
            }
        }
        "spectrum" => {
            a.check(&["name", "value", "filename"], &["name"])?;
            match (a.get("value"), a.get("filename")) {
                (Some(v), None) => spectrum_value(a, v).map(Value::Spectrum),
                (None, Some(f)) => spectrum_file(a, f, resolver).map(Value::Spectrum),
                _ => Err(a.error("needs either \"value\" or \"filename\" (not both)")),
            }
        }
        _ => unreachable!("not a property tag: {}", a.tag),
    }
}

/// `value="0.5"` (uniform) or `value="400:0.1, 500:0.3, ..."`.
fn spectrum_value(a: &Attrs, v: &str) -> Result<Spectrum> {
    let toks = tokens(v);
    if let [single] = toks.as_slice() {
        if !single.contains(':') {
            return Ok(Spectrum::Uniform(float_attr(a, single)?));
        }
    }
    let mut pairs = Vec::with_capacity(toks.len());
    for t in toks {
        let Some((w, x)) = t.split_once(':') else {
            return Err(a.error(format!("expected wavelength:value pairs, got \"{t}\"")));
        };
        pairs.push((float_attr(a, w)?, float_attr(a, x)?));
    }
    checked_pairs(a, pairs)
}

fn checked_pairs(a: &Attrs, pairs: Vec<(f64, f64)>) -> Result<Spectrum> {
    if pairs.len() < 2 {
        return Err(a.error("a spectrum needs at least two wavelength:value pairs"));
    }
    if pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(a.error("wavelengths must increase"));
    }
    if pairs.iter().any(|(w, v)| !w.is_finite() || !v.is_finite()) {
        return Err(a.error("wavelengths and values must be finite"));
    }
    Ok(Spectrum::Pairs(pairs))
}

/// A file of `wavelength value` lines (`#` starts a comment line).
fn spectrum_file(a: &Attrs, name: &str, resolver: &FileResolver) -> Result<Spectrum> {
    let path = resolver
        .resolve(name)
        .ok_or_else(|| a.error(format!("spectrum file \"{name}\" not found")))?;
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    let mut pairs = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let at = Loc {
            file: path.as_path().into(),
            line: i + 1,
            column: 1,
        };
        match tokens(line)
            .iter()
            .map(|t| parse_float(t))
            .collect::<Option<Vec<_>>>()
            .as_deref()
        {
            Some([w, v]) => pairs.push((*w, *v)),
            _ => return Err(at.error(format!("expected \"wavelength value\", got \"{line}\""))),
        }
    }
    checked_pairs(a, pairs)
}

/// One operation inside `<transform>`, as a matrix to multiply from the left.
pub fn transform_op(a: &Attrs) -> Result<DMat4> {
    match a.tag {
        "translate" => {
            a.check(&["x", "y", "z", "value"], &[])?;
            Ok(transform::translate(xyz(a, 0.0, false)?))
        }
        "scale" => {
            a.check(&["x", "y", "z", "value"], &[])?;
            Ok(transform::scale(xyz(a, 1.0, false)?))
        }
        "rotate" => {
            a.check(&["x", "y", "z", "value", "angle"], &["angle"])?;
            let axis = xyz(a, 0.0, false)?;
            if axis == [0.0; 3] {
                return Err(a.error("the rotation axis is zero"));
            }
            let angle = float_attr(a, a.require("angle")?)?;
            Ok(transform::rotate(axis, angle))
        }
        "lookat" => {
            a.check(&["origin", "target", "up"], &["origin", "target"])?;
            let vec3 = |k: &str| -> Result<[f64; 3]> {
                match a.get(k) {
                    None => Ok([0.0; 3]),
                    Some(s) => match floats(a, s)?.as_slice() {
                        [x, y, z] => Ok([*x, *y, *z]),
                        _ => Err(a.error(format!("\"{k}\" needs 3 numbers, got \"{s}\""))),
                    },
                }
            };
            let (origin, target, up) = (vec3("origin")?, vec3("target")?, vec3("up")?);
            transform::look_at(origin, target, up).ok_or_else(|| {
                a.error("invalid lookat: origin equals target, or up is parallel to the view")
            })
        }
        "matrix" => {
            a.check(&["value"], &["value"])?;
            let v = floats(a, a.require("value")?)?;
            transform::matrix(&v)
                .ok_or_else(|| a.error(format!("a matrix needs 16 or 9 numbers, got {}", v.len())))
        }
        other => Err(a.error(format!(
            "<{other}> cannot appear inside <transform> (expected translate, rotate, scale, \
             lookat or matrix)"
        ))),
    }
}
