//! From element trees to a [`Document`]: `$name` substitution with `<default>`s and the caller's
//! parameters, `<include>`, `<path>`, `<alias>`, ids, and every element read as an object,
//! a property, a transform or a reference, following Mitsuba 3's parser.

use super::document::{Child, Document, Object, Property, Target, Value};
use super::params::{self, Attrs};
use super::resolver::FileResolver;
use super::xml::{self, Element, Loc};
use super::XmlOptions;
use crate::error::Result;
use glam::DMat4;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Tags of objects (plugins); `<spectrum>` is one too when it has a `type`.
const OBJECT_TAGS: &[&str] = &[
    "scene",
    "bsdf",
    "emitter",
    "film",
    "integrator",
    "rfilter",
    "sampler",
    "sensor",
    "shape",
    "texture",
    "medium",
    "phase",
    "volume",
];
const PROPERTY_TAGS: &[&str] = &[
    "float", "integer", "boolean", "string", "point", "vector", "rgb", "spectrum",
];
const TRANSFORM_OPS: &[&str] = &["translate", "rotate", "scale", "lookat", "matrix"];

/// Deeper includes than this are taken for a cycle.
const MAX_INCLUDE_DEPTH: usize = 16;

/// Reads the scene file at `path` with its includes.
pub fn load_document(path: &Path, options: &XmlOptions) -> Result<Document> {
    let root = xml::parse_file(path)?;
    document(root, path, options)
}

/// A document from XML text; `origin` stands for its file (names resolve from its folder).
pub fn document_from_str(text: &str, origin: &Path, options: &XmlOptions) -> Result<Document> {
    let root = xml::parse_str(text, origin)?;
    document(root, origin, options)
}

fn document(root: Element, path: &Path, options: &XmlOptions) -> Result<Document> {
    let mut ex = Expander {
        params: Vec::new(),
        ids: HashMap::new(),
        depth: 0,
    };
    for (name, value) in &options.params {
        ex.define(name, value);
    }
    let mut resolver = FileResolver::default();
    resolver.prepend(folder_of(path));
    let mut file = FileCtx { resolver };
    let attrs = ex.substitute(&root)?;
    if root.tag != "scene" {
        return Err(attrs.error("the root element must be <scene>"));
    }
    check_version(&attrs)?;
    attrs.check(&["version", "type", "id", "name"], &["version"])?;
    let mut scene = Builder::new(&root, &attrs);
    for child in &root.children {
        ex.element(child, &mut scene, &mut file, true)?;
    }
    let root = ex.finish(scene)?;
    Ok(Document {
        root,
        ids: ex.ids,
        resolver: file.resolver,
        file: path.to_path_buf(),
    })
}

fn folder_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `version="major.minor.patch"`; scenes before 2.0 used other parameter names, which Mitsuba
/// renames and Appel does not.
fn check_version(a: &Attrs) -> Result<()> {
    let v = a.require("version")?;
    let parts: Option<Vec<u32>> = v.split('.').map(|p| p.trim().parse().ok()).collect();
    match parts.as_deref() {
        Some([major, _, _]) if *major >= 2 => Ok(()),
        Some([_, _, _]) => Err(a.error(format!(
            "version {v}: scenes older than 2.0.0 (camelCase parameter names) are not supported"
        ))),
        _ => Err(a.error(format!("could not parse the version \"{v}\""))),
    }
}

/// The state of one file being read: its resolver grows with its `<path>`s.
struct FileCtx {
    resolver: FileResolver,
}

/// An object being filled.
struct Builder {
    class: String,
    plugin: String,
    id: Option<String>,
    loc: Loc,
    props: Vec<Property>,
    children: Vec<Child>,
}

impl Builder {
    fn new(el: &Element, a: &Attrs) -> Self {
        let plugin = if el.tag == "scene" {
            "scene".to_string()
        } else {
            a.get("type").unwrap_or_default().to_string()
        };
        Self {
            class: el.tag.clone(),
            plugin,
            id: a.get("id").map(str::to_string),
            loc: el.loc.clone(),
            props: Vec::new(),
            children: Vec::new(),
        }
    }

    /// Fails if parameter `name` is already set in this object.
    fn check_unique(&self, name: &str, a: &Attrs) -> Result<()> {
        let taken = self.props.iter().any(|p| p.name == name)
            || self
                .children
                .iter()
                .any(|c| c.name.as_deref() == Some(name));
        if taken {
            return Err(a.error(format!("parameter \"{name}\" is given twice")));
        }
        Ok(())
    }
}

struct Expander {
    /// `("$name", value)`, longest names first so that `$a` never eats the start of `$ab`.
    params: Vec<(String, String)>,
    ids: HashMap<String, Rc<Object>>,
    /// Include depth.
    depth: usize,
}

impl Expander {
    /// Adds a parameter unless it is already set (the caller's parameters beat `<default>`s).
    fn define(&mut self, name: &str, value: &str) {
        let key = format!("${name}");
        if self.params.iter().any(|(k, _)| *k == key) {
            return;
        }
        let at = self
            .params
            .iter()
            .position(|(k, _)| k.len() < key.len())
            .unwrap_or(self.params.len());
        self.params.insert(at, (key, value.to_string()));
    }

    /// The element's attributes with `$name` replaced; `\$` stands for a literal `$`.
    fn substitute<'e>(&self, el: &'e Element) -> Result<Attrs<'e>> {
        let mut attrs = Vec::with_capacity(el.attrs.len());
        for (k, v) in &el.attrs {
            attrs.push((k.clone(), self.substitute_value(el, v)?));
        }
        Ok(Attrs {
            tag: &el.tag,
            attrs,
            loc: &el.loc,
        })
    }

    fn substitute_value(&self, el: &Element, value: &str) -> Result<String> {
        if !value.contains('$') {
            return Ok(value.to_string());
        }
        let mut v = value.to_string();
        for (key, replacement) in &self.params {
            let mut pos = 0;
            while let Some(i) = v[pos..].find(key.as_str()).map(|i| i + pos) {
                if i > 0 && v.as_bytes()[i - 1] == b'\\' {
                    pos = i + key.len();
                } else {
                    v.replace_range(i..i + key.len(), replacement);
                    pos = i + replacement.len();
                }
            }
        }
        let bytes = v.as_bytes();
        if let Some(i) =
            (0..bytes.len()).find(|&i| bytes[i] == b'$' && (i == 0 || bytes[i - 1] != b'\\'))
        {
            let name: String = v[i + 1..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            return Err(el.error(format!(
                "undefined parameter ${name} (give it with <default name=\"{name}\" value=\"...\"/> \
                 or -D {name}=...)"
            )));
        }
        Ok(v.replace("\\$", "$"))
    }

    /// Reads `el` into `parent`. `top` is true for direct children of a file's root.
    fn element(
        &mut self,
        el: &Element,
        parent: &mut Builder,
        file: &mut FileCtx,
        top: bool,
    ) -> Result<()> {
        let a = self.substitute(el)?;
        let tag = el.tag.as_str();
        let is_object =
            OBJECT_TAGS.contains(&tag) || (tag == "spectrum" && a.get("type").is_some());
        if is_object {
            let name = a.get("name").map(str::to_string);
            if let Some(n) = &name {
                parent.check_unique(n, &a)?;
            }
            let object = self.object(el, a, file)?;
            parent
                .children
                .push(Child::new(name, Target::Object(object), el.loc.clone()));
            return Ok(());
        }
        if PROPERTY_TAGS.contains(&tag) {
            no_children(el, &a)?;
            let value = params::property(&a, &file.resolver)?;
            let name = a.require("name")?.to_string();
            parent.check_unique(&name, &a)?;
            parent
                .props
                .push(Property::new(name, el.tag.clone(), value, el.loc.clone()));
            return Ok(());
        }
        match tag {
            "transform" => {
                a.check(&["name"], &["name"])?;
                let mut m = DMat4::IDENTITY;
                for op in &el.children {
                    let oa = self.substitute(op)?;
                    no_children(op, &oa)?;
                    m = params::transform_op(&oa)? * m;
                }
                let name = a.require("name")?.to_string();
                parent.check_unique(&name, &a)?;
                parent.props.push(Property::new(
                    name,
                    "transform".into(),
                    Value::Transform(m),
                    el.loc.clone(),
                ));
            }
            "ref" => {
                a.check(&["id", "name"], &["id"])?;
                no_children(el, &a)?;
                let name = a.get("name").map(str::to_string);
                if let Some(n) = &name {
                    parent.check_unique(n, &a)?;
                }
                let id = a.require("id")?.to_string();
                parent
                    .children
                    .push(Child::new(name, Target::Ref(id), el.loc.clone()));
            }
            "default" => {
                a.check(&["name", "value"], &["name", "value"])?;
                let name = a.require("name")?;
                if name.is_empty() {
                    return Err(a.error("the name must not be empty"));
                }
                let value = a.require("value")?.to_string();
                self.define(name, &value);
            }
            "path" => {
                a.check(&["value"], &["value"])?;
                if !top {
                    return Err(a.error("<path> must be a direct child of the root element"));
                }
                let v = a.require("value")?;
                let folder = file
                    .resolver
                    .resolve(v)
                    .filter(|p| p.is_dir())
                    .ok_or_else(|| {
                        a.error(format!(
                            "folder \"{v}\" not found (searched {})",
                            searched(&file.resolver)
                        ))
                    })?;
                file.resolver.prepend(folder);
            }
            "include" => self.include(el, &a, parent, file)?,
            "alias" => {
                a.check(&["id", "as"], &["id", "as"])?;
                let (id, alias) = (a.require("id")?, a.require("as")?);
                let target = self
                    .ids
                    .get(id)
                    .cloned()
                    .ok_or_else(|| a.error(format!("no object has id \"{id}\" (yet)")))?;
                if self.ids.contains_key(alias) {
                    return Err(a.error(format!("id \"{alias}\" is already taken")));
                }
                self.ids.insert(alias.to_string(), target);
            }
            t if TRANSFORM_OPS.contains(&t) => {
                return Err(a.error("transform operations can only appear inside <transform>"))
            }
            _ => return Err(a.error("unsupported XML element")),
        }
        Ok(())
    }

    fn object(&mut self, el: &Element, a: Attrs, file: &mut FileCtx) -> Result<Rc<Object>> {
        if el.tag == "scene" {
            return Err(a.error("a <scene> cannot be nested in another object"));
        }
        a.check(&["type", "id", "name"], &["type"])?;
        if let Some(id) = a.get("id") {
            if id.starts_with('_') {
                return Err(a.error(format!("id \"{id}\": leading underscores are reserved")));
            }
        }
        let mut b = Builder::new(el, &a);
        for child in &el.children {
            self.element(child, &mut b, file, false)?;
        }
        self.finish(b)
    }

    /// The built object, registered under its id.
    fn finish(&mut self, b: Builder) -> Result<Rc<Object>> {
        let object = Rc::new(Object {
            class: b.class,
            plugin: b.plugin,
            id: b.id.clone(),
            loc: b.loc,
            props: b.props,
            children: b.children,
        });
        if let Some(id) = b.id {
            if let Some(previous) = self.ids.get(&id) {
                let p = &previous.loc;
                return Err(object.error(format!(
                    "duplicate id \"{id}\" (first at {}:{}:{})",
                    p.file.display(),
                    p.line,
                    p.column
                )));
            }
            self.ids.insert(id, object.clone());
        }
        Ok(object)
    }

    /// `<include filename="...">`: a file whose root is `<scene>` adds its children here;
    /// any other root element is one object.
    fn include(
        &mut self,
        el: &Element,
        a: &Attrs,
        parent: &mut Builder,
        file: &mut FileCtx,
    ) -> Result<()> {
        a.check(&["filename", "name"], &["filename"])?;
        no_children(el, a)?;
        let name = a.require("filename")?;
        let path = file.resolver.resolve(name).ok_or_else(|| {
            a.error(format!(
                "included file \"{name}\" not found (searched {})",
                searched(&file.resolver)
            ))
        })?;
        if self.depth >= MAX_INCLUDE_DEPTH {
            return Err(a.error(format!(
                "more than {MAX_INCLUDE_DEPTH} nested includes (does a file include itself?)"
            )));
        }
        let root = xml::parse_file(&path)?;
        let mut inner = FileCtx {
            resolver: file.resolver.clone(),
        };
        inner.resolver.prepend(folder_of(&path));
        self.depth += 1;
        let ra = self.substitute(&root)?;
        check_version(&ra)?;
        let result = if root.tag == "scene" {
            ra.check(&["version", "type", "id", "name"], &["version"])?;
            root.children
                .iter()
                .try_for_each(|c| self.element(c, parent, &mut inner, true))
        } else {
            let mut ra = ra;
            ra.attrs.retain(|(k, _)| k != "version");
            if let Some(n) = a.get("name") {
                ra.attrs.retain(|(k, _)| k != "name");
                ra.attrs.push(("name".into(), n.to_string()));
            }
            let name = ra.get("name").map(str::to_string);
            if !OBJECT_TAGS.contains(&root.tag.as_str()) {
                return Err(ra.error("an included file's root must be an object or <scene>"));
            }
            self.object(&root, ra, &mut inner).map(|o| {
                parent
                    .children
                    .push(Child::new(name, Target::Object(o), el.loc.clone()))
            })
        };
        self.depth -= 1;
        result
    }
}

fn no_children(el: &Element, a: &Attrs) -> Result<()> {
    match el.children.first() {
        Some(c) => Err(c.error(format!("cannot appear inside {}", a.describe()))),
        None => Ok(()),
    }
}

fn searched(r: &FileResolver) -> String {
    let folders: Vec<String> = r
        .folders()
        .iter()
        .map(|f| format!("\"{}\"", f.display()))
        .collect();
    folders.join(", ")
}
