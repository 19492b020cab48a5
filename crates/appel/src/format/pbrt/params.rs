//! pbrt's typed parameter lists: `"type name" value` or `"type name" [ values ]`. Values are
//! checked against their declared type as they are read; lookups check the type a directive
//! expects and mark the parameter used, so that the ones nobody read can be reported as pbrt
//! reports them.

use super::tokenizer::Loc;
use crate::error::Result;
use std::cell::Cell;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    Integer,
    Float,
    Point2,
    Vector2,
    Point3,
    Vector3,
    Normal,
    Bool,
    String,
    Texture,
    Rgb,
    Spectrum,
    Blackbody,
}

impl ParamType {
    /// pbrt-v4's names, with the older spellings its parser still accepts.
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "integer" => Self::Integer,
            "float" => Self::Float,
            "point2" => Self::Point2,
            "vector2" => Self::Vector2,
            "point3" | "point" => Self::Point3,
            "vector3" | "vector" => Self::Vector3,
            "normal" | "normal3" => Self::Normal,
            "bool" => Self::Bool,
            "string" => Self::String,
            "texture" => Self::Texture,
            "rgb" | "color" => Self::Rgb,
            "spectrum" => Self::Spectrum,
            "blackbody" => Self::Blackbody,
            _ => return None,
        })
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Integer => "integer",
            Self::Float => "float",
            Self::Point2 => "point2",
            Self::Vector2 => "vector2",
            Self::Point3 => "point3",
            Self::Vector3 => "vector3",
            Self::Normal => "normal",
            Self::Bool => "bool",
            Self::String => "string",
            Self::Texture => "texture",
            Self::Rgb => "rgb",
            Self::Spectrum => "spectrum",
            Self::Blackbody => "blackbody",
        }
    }

    /// How many numbers make one value (0: the values are not numbers).
    fn arity(self) -> usize {
        match self {
            Self::Integer | Self::Float | Self::Blackbody => 1,
            Self::Point2 | Self::Vector2 => 2,
            Self::Point3 | Self::Vector3 | Self::Normal | Self::Rgb => 3,
            Self::Spectrum => 2,
            Self::Bool | Self::String | Self::Texture => 0,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Numbers(Vec<f64>),
    Strings(Vec<String>),
    Bools(Vec<bool>),
}

/// One raw value as written, before its type is checked.
#[derive(Clone, Debug, PartialEq)]
pub enum RawValue {
    /// A word: a number, or `true`/`false`.
    Word(String),
    Str(String),
}

#[derive(Debug)]
pub struct Param {
    pub ty: ParamType,
    pub name: String,
    pub values: Values,
    pub loc: Loc,
    used: Cell<bool>,
}

impl Param {
    /// Checks `raw` against the declaration `decl` (`"float radius"`) written at `loc`.
    pub fn new(decl: &str, raw: Vec<(RawValue, Loc)>, loc: Loc) -> Result<Param> {
        let mut parts = decl.split_whitespace();
        let (Some(ty), Some(name), None) = (parts.next(), parts.next(), parts.next()) else {
            return Err(loc.error(format!(
                "expected a parameter declaration \"type name\", got \"{decl}\""
            )));
        };
        let ty = ParamType::from_name(ty).ok_or_else(|| {
            loc.error(format!(
                "unknown parameter type \"{ty}\" (integer, float, point2, vector2, point3, \
                 vector3, normal, bool, string, texture, rgb, spectrum or blackbody)"
            ))
        })?;
        let values = match ty {
            ParamType::String | ParamType::Texture => Values::Strings(strings(&raw, ty, name)?),
            ParamType::Bool => Values::Bools(
                raw.iter()
                    .map(|(v, at)| match v {
                        RawValue::Word(w) | RawValue::Str(w) if w == "true" => Ok(true),
                        RawValue::Word(w) | RawValue::Str(w) if w == "false" => Ok(false),
                        _ => Err(at.error(format!(
                            "wrong value for \"bool {name}\": expected true or false"
                        ))),
                    })
                    .collect::<Result<_>>()?,
            ),
            // A spectrum is numbers (wavelength, value pairs) or one string (a file or a named
            // spectrum).
            ParamType::Spectrum if matches!(raw.first(), Some((RawValue::Str(_), _))) => {
                Values::Strings(strings(&raw, ty, name)?)
            }
            _ => {
                let numbers = raw
                    .iter()
                    .map(|(v, at)| number(v, at, ty, name))
                    .collect::<Result<Vec<f64>>>()?;
                if ty == ParamType::Integer {
                    if let Some(((_, at), _)) =
                        raw.iter().zip(&numbers).find(|(_, x)| x.fract() != 0.0)
                    {
                        return Err(
                            at.error(format!("\"integer {name}\" takes whole numbers only"))
                        );
                    }
                }
                let n = ty.arity();
                if numbers.is_empty() || numbers.len() % n != 0 {
                    return Err(loc.error(format!(
                        "\"{} {name}\" needs a multiple of {n} numbers, got {}",
                        ty.name(),
                        numbers.len()
                    )));
                }
                Values::Numbers(numbers)
            }
        };
        Ok(Param {
            ty,
            name: name.to_string(),
            values,
            loc,
            used: Cell::new(false),
        })
    }

    pub fn numbers(&self) -> &[f64] {
        match &self.values {
            Values::Numbers(n) => n,
            _ => &[],
        }
    }

    pub fn strings(&self) -> &[String] {
        match &self.values {
            Values::Strings(s) => s,
            _ => &[],
        }
    }

    pub fn error(&self, message: impl Into<String>) -> crate::error::Error {
        self.loc.error(message)
    }
}

fn strings(raw: &[(RawValue, Loc)], ty: ParamType, name: &str) -> Result<Vec<String>> {
    raw.iter()
        .map(|(v, at)| match v {
            RawValue::Str(s) => Ok(s.clone()),
            RawValue::Word(w) => Err(at.error(format!(
                "wrong parameter type: \"{} {name}\" takes quoted strings, got {w}",
                ty.name()
            ))),
        })
        .collect()
}

fn number(v: &RawValue, at: &Loc, ty: ParamType, name: &str) -> Result<f64> {
    match v {
        RawValue::Word(w) => parse_number(w)
            .ok_or_else(|| at.error(format!("bad number \"{w}\" in \"{} {name}\"", ty.name()))),
        RawValue::Str(s) => Err(at.error(format!(
            "wrong parameter type: \"{} {name}\" takes numbers, got the string \"{s}\"",
            ty.name()
        ))),
    }
}

/// A number as pbrt writes them (no `inf` or `nan`: a scene has no business with those).
pub fn parse_number(w: &str) -> Option<f64> {
    let ok = w
        .chars()
        .all(|c| c.is_ascii_digit() || matches!(c, '+' | '-' | '.' | 'e' | 'E'));
    w.parse::<f64>().ok().filter(|x| ok && x.is_finite())
}

/// The parameters of one directive.
#[derive(Debug, Default)]
pub struct ParamSet {
    pub params: Vec<Param>,
}

impl ParamSet {
    pub fn get(&self, name: &str) -> Option<&Param> {
        let p = self.params.iter().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// Marks `name` used without reading it (a setting with no effect on Appel's image).
    pub fn ignore(&self, name: &str) {
        self.get(name);
    }

    /// The parameter, checked to be one of `types`.
    fn typed(&self, name: &str, types: &[ParamType]) -> Result<Option<&Param>> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        if !types.contains(&p.ty) {
            let want: Vec<&str> = types.iter().map(|t| t.name()).collect();
            return Err(p.error(format!(
                "wrong parameter type: \"{name}\" must be {}, not {}",
                want.join(" or "),
                p.ty.name()
            )));
        }
        Ok(Some(p))
    }

    /// A parameter of one value of type `ty`.
    fn single(&self, name: &str, ty: ParamType) -> Result<Option<&Param>> {
        let Some(p) = self.typed(name, &[ty])? else {
            return Ok(None);
        };
        let n = match &p.values {
            Values::Numbers(v) => v.len() / ty.arity(),
            Values::Strings(v) => v.len(),
            Values::Bools(v) => v.len(),
        };
        if n != 1 {
            return Err(p.error(format!("\"{} {name}\" takes one value, got {n}", ty.name())));
        }
        Ok(Some(p))
    }

    pub fn float(&self, name: &str) -> Result<Option<f64>> {
        Ok(self.single(name, ParamType::Float)?.map(|p| p.numbers()[0]))
    }

    pub fn float_or(&self, name: &str, default: f64) -> Result<f64> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    pub fn int(&self, name: &str) -> Result<Option<i64>> {
        Ok(self
            .single(name, ParamType::Integer)?
            .map(|p| p.numbers()[0] as i64))
    }

    pub fn bool_or(&self, name: &str, default: bool) -> Result<bool> {
        Ok(match self.single(name, ParamType::Bool)? {
            Some(p) => match &p.values {
                Values::Bools(b) => b[0],
                _ => unreachable!("checked type"),
            },
            None => default,
        })
    }

    pub fn string(&self, name: &str) -> Result<Option<&str>> {
        Ok(self
            .single(name, ParamType::String)?
            .map(|p| p.strings()[0].as_str()))
    }

    pub fn point3(&self, name: &str) -> Result<Option<[f64; 3]>> {
        let p = self.single(name, ParamType::Point3)?;
        Ok(p.map(|p| {
            let v = p.numbers();
            [v[0], v[1], v[2]]
        }))
    }

    /// All values of an array parameter of type `ty`, as numbers.
    pub fn array(&self, name: &str, ty: ParamType) -> Result<Option<&Param>> {
        self.typed(name, &[ty])
    }

    /// A parameter that may be given as any of `types` (a float or a texture, an rgb or a
    /// spectrum...): the caller matches on its type.
    pub fn any_of(&self, name: &str, types: &[ParamType]) -> Result<Option<&Param>> {
        self.typed(name, types)
    }

    /// Warnings for every parameter nobody read, as pbrt gives them.
    pub fn unused(&self, what: &str) -> Vec<String> {
        self.params
            .iter()
            .filter(|p| !p.used.get())
            .map(|p| {
                format!(
                    "{}: \"{} {}\" is not used by {what}",
                    p.loc.describe(),
                    p.ty.name(),
                    p.name
                )
            })
            .collect()
    }
}
