//! A Mitsuba scene after expansion: objects (`<bsdf>`, `<shape>`, ...) holding typed properties
//! and nested or referenced objects, every one with the place it was written. Readers take what
//! they understand through the typed accessors, which mark it used; `Object::finish` then turns
//! anything left unread into an error, so that nothing in a file is silently ignored.

use super::resolver::FileResolver;
use super::xml::Loc;
use crate::error::{Error, Result};
use glam::DMat4;
use std::cell::Cell;
use std::collections::HashMap;
use std::path::PathBuf;
use std::rc::Rc;

/// A spectrum as written: one value for all wavelengths, or `(wavelength, value)` points.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    Uniform(f64),
    Pairs(Vec<(f64, f64)>),
}

/// The value of a property element.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Bool(bool),
    Int(i64),
    Float(f64),
    String(String),
    /// `<point>` or `<vector>`.
    Vector([f64; 3]),
    Rgb([f64; 3]),
    Spectrum(Spectrum),
    Transform(DMat4),
}

/// `<float name="radius" value="2"/>` and the like.
#[derive(Debug)]
pub struct Property {
    pub name: String,
    /// The element's tag, to name it in messages.
    pub tag: String,
    pub value: Value,
    pub loc: Loc,
    used: Cell<bool>,
}

impl Property {
    pub fn new(name: String, tag: String, value: Value, loc: Loc) -> Self {
        Self {
            name,
            tag,
            value,
            loc,
            used: Cell::new(false),
        }
    }

    pub fn describe(&self) -> String {
        format!("<{} name=\"{}\">", self.tag, self.name)
    }

    pub fn error(&self, message: impl std::fmt::Display) -> Error {
        self.loc.error(format!("{}: {message}", self.describe()))
    }
}

/// What a child slot holds: an object written in place, or `<ref id="..."/>`.
#[derive(Debug)]
pub enum Target {
    Object(Rc<Object>),
    Ref(String),
}

/// A nested object or reference, with the parameter name it fills (`name="reflectance"`), if any.
#[derive(Debug)]
pub struct Child {
    pub name: Option<String>,
    pub target: Target,
    pub loc: Loc,
    used: Cell<bool>,
}

impl Child {
    pub fn new(name: Option<String>, target: Target, loc: Loc) -> Self {
        Self {
            name,
            target,
            loc,
            used: Cell::new(false),
        }
    }
}

/// `<bsdf type="diffuse" id="..." name="...">...</bsdf>`; the root `<scene>` has plugin "scene".
#[derive(Debug)]
pub struct Object {
    /// The tag: scene, bsdf, shape, emitter, sensor, film, rfilter, sampler, integrator,
    /// texture, spectrum, medium, phase, volume.
    pub class: String,
    pub plugin: String,
    pub id: Option<String>,
    pub loc: Loc,
    pub props: Vec<Property>,
    pub children: Vec<Child>,
}

/// A parameter's value where Mitsuba accepts a texture: a constant or a texture object.
#[derive(Clone, Debug)]
pub enum TextureArg<'a> {
    Float(f64, &'a Property),
    Rgb([f64; 3], &'a Property),
    Spectrum(&'a Spectrum, &'a Property),
    Object(Rc<Object>, &'a Child),
}

impl Object {
    pub fn describe(&self) -> String {
        format!("<{} type=\"{}\">", self.class, self.plugin)
    }

    /// An error about this object: `file:line:col: <bsdf type="x">: message`.
    pub fn error(&self, message: impl std::fmt::Display) -> Error {
        self.loc.error(format!("{}: {message}", self.describe()))
    }

    /// The property called `name`, marked used.
    pub fn prop(&self, name: &str) -> Option<&Property> {
        let p = self.props.iter().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    pub fn float(&self, name: &str) -> Result<Option<f64>> {
        let Some(p) = self.prop(name) else {
            return Ok(None);
        };
        let v = match p.value {
            Value::Float(v) => v,
            Value::Int(i) => i as f64,
            _ => return Err(p.error("expected a <float>")),
        };
        if !v.is_finite() {
            return Err(p.error(format!("expected a finite number, got {v}")));
        }
        Ok(Some(v))
    }

    pub fn float_or(&self, name: &str, default: f64) -> Result<f64> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    pub fn int(&self, name: &str) -> Result<Option<i64>> {
        let Some(p) = self.prop(name) else {
            return Ok(None);
        };
        match p.value {
            Value::Int(i) => Ok(Some(i)),
            _ => Err(p.error("expected an <integer>")),
        }
    }

    /// An integer that must lie in `range`.
    pub fn int_in(&self, name: &str, range: std::ops::RangeInclusive<i64>) -> Result<Option<i64>> {
        let Some(v) = self.int(name)? else {
            return Ok(None);
        };
        if !range.contains(&v) {
            let p = self.prop(name).expect("just read");
            return Err(p.error(format!(
                "{v} is out of range ({} to {})",
                range.start(),
                range.end()
            )));
        }
        Ok(Some(v))
    }

    pub fn bool(&self, name: &str) -> Result<Option<bool>> {
        let Some(p) = self.prop(name) else {
            return Ok(None);
        };
        match p.value {
            Value::Bool(b) => Ok(Some(b)),
            _ => Err(p.error("expected a <boolean>")),
        }
    }

    pub fn bool_or(&self, name: &str, default: bool) -> Result<bool> {
        Ok(self.bool(name)?.unwrap_or(default))
    }

    pub fn string(&self, name: &str) -> Result<Option<&str>> {
        let Some(p) = self.prop(name) else {
            return Ok(None);
        };
        match &p.value {
            Value::String(s) => Ok(Some(s)),
            _ => Err(p.error("expected a <string>")),
        }
    }

    /// A `<point>` or `<vector>`.
    pub fn vector(&self, name: &str) -> Result<Option<[f64; 3]>> {
        let Some(p) = self.prop(name) else {
            return Ok(None);
        };
        match p.value {
            Value::Vector(v) if v.iter().all(|x| x.is_finite()) => Ok(Some(v)),
            Value::Vector(_) => Err(p.error("expected finite numbers")),
            _ => Err(p.error("expected a <point> or <vector>")),
        }
    }

    pub fn transform(&self, name: &str) -> Result<Option<DMat4>> {
        let Some(p) = self.prop(name) else {
            return Ok(None);
        };
        match p.value {
            Value::Transform(m) if m.is_finite() => Ok(Some(m)),
            Value::Transform(_) => Err(p.error("the transform is not finite")),
            _ => Err(p.error("expected a <transform>")),
        }
    }

    /// The child object filling parameter `name`, marked used.
    pub fn named_child(&self, name: &str) -> Option<&Child> {
        let c = self
            .children
            .iter()
            .find(|c| c.name.as_deref() == Some(name))?;
        c.used.set(true);
        Some(c)
    }

    /// Children without a parameter name (nested BSDFs, emitters, shapes...), not marked used.
    pub fn unnamed_children(&self) -> impl Iterator<Item = &Child> {
        self.children.iter().filter(|c| c.name.is_none())
    }

    /// Marks a child as understood.
    pub fn take(&self, child: &Child) {
        child.used.set(true);
    }

    /// The value of a texture-valued parameter, marked used.
    pub fn texture<'a>(&'a self, doc: &Document, name: &str) -> Result<Option<TextureArg<'a>>> {
        if let Some(p) = self.prop(name) {
            return match &p.value {
                Value::Float(v) if v.is_finite() => Ok(Some(TextureArg::Float(*v, p))),
                Value::Int(i) => Ok(Some(TextureArg::Float(*i as f64, p))),
                Value::Rgb(c) if c.iter().all(|x| x.is_finite()) => {
                    Ok(Some(TextureArg::Rgb(*c, p)))
                }
                Value::Spectrum(s) => Ok(Some(TextureArg::Spectrum(s, p))),
                _ => Err(p.error("expected a <float>, <rgb>, <spectrum> or <texture>")),
            };
        }
        let Some(child) = self.named_child(name) else {
            return Ok(None);
        };
        Ok(Some(TextureArg::Object(doc.target(child)?, child)))
    }

    /// Fails on the first property or child that no reader took, naming the plugin.
    pub fn finish(&self) -> Result<()> {
        if let Some(p) = self.props.iter().find(|p| !p.used.get()) {
            return Err(p.error(format!(
                "parameter \"{}\" is not supported by {}",
                p.name,
                self.describe()
            )));
        }
        if let Some(c) = self.children.iter().find(|c| !c.used.get()) {
            let what = match (&c.target, &c.name) {
                (_, Some(n)) => format!("parameter \"{n}\""),
                (Target::Object(o), None) => format!("a nested {}", o.describe()),
                (Target::Ref(id), None) => format!("a reference to \"{id}\""),
            };
            return Err(c
                .loc
                .error(format!("{what} is not supported by {}", self.describe())));
        }
        Ok(())
    }
}

/// A whole scene: the root object, the objects by id, and the resolver for file names.
#[derive(Debug)]
pub struct Document {
    pub root: Rc<Object>,
    pub ids: HashMap<String, Rc<Object>>,
    /// The main file's resolver as it stands after every `<path>`: Mitsuba resolves the file
    /// names of all plugins, included files' too, with it.
    pub resolver: FileResolver,
    pub file: PathBuf,
}

impl Document {
    /// The object a child slot holds, following a reference.
    pub fn target(&self, child: &Child) -> Result<Rc<Object>> {
        match &child.target {
            Target::Object(o) => Ok(o.clone()),
            Target::Ref(id) => self.ids.get(id).cloned().ok_or_else(|| {
                child
                    .loc
                    .error(format!("<ref id=\"{id}\">: no object has id \"{id}\""))
            }),
        }
    }
}
