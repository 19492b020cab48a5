//! pbrt's syntax: a stream of directives, each with its fixed arguments (names in quotes, or
//! numbers) and, for most, a parameter list. `Include` and `Import` continue in another file,
//! named relative to the folder of the first scene file (as pbrt resolves every relative name).

use super::params::{parse_number, Param, ParamSet, RawValue};
use super::tokenizer::{Loc, Tok, Token, Tokenizer};
use crate::error::{Error, Result};
use std::io::Read;
use std::path::{Path, PathBuf};

/// One directive as written.
#[derive(Debug)]
pub struct Directive {
    pub name: String,
    pub loc: Loc,
    /// The quoted arguments before the parameter list (`Shape "sphere"`, `Texture "t" "float"
    /// "imagemap"`), or `ActiveTransform`'s word.
    pub strings: Vec<String>,
    /// The numeric arguments (`Translate 1 2 3`, `Transform [ ... ]`).
    pub numbers: Vec<f64>,
    pub params: ParamSet,
}

/// What follows a directive's name.
enum Shape {
    Nothing,
    Numbers(usize),
    /// Quoted names, then a parameter list if `params`.
    Names(usize, bool),
    /// `MediumInterface "inside" ["outside"]`.
    OneOrTwoNames,
    /// `ActiveTransform StartTime`.
    Word,
}

fn shape_of(name: &str) -> Option<Shape> {
    use Shape::*;
    Some(match name {
        "AttributeBegin" | "AttributeEnd" | "TransformBegin" | "TransformEnd" | "ObjectEnd"
        | "WorldBegin" | "WorldEnd" | "ReverseOrientation" | "Identity" => Nothing,
        "Translate" | "Scale" => Numbers(3),
        "Rotate" => Numbers(4),
        "LookAt" => Numbers(9),
        "Transform" | "ConcatTransform" => Numbers(16),
        "TransformTimes" => Numbers(2),
        "ActiveTransform" => Word,
        "CoordinateSystem" | "CoordSysTransform" | "NamedMaterial" | "ObjectBegin"
        | "ObjectInstance" | "Include" | "Import" | "ColorSpace" => Names(1, false),
        "Camera" | "Film" | "Sampler" | "PixelFilter" | "Integrator" | "Accelerator" | "Shape"
        | "LightSource" | "AreaLightSource" | "Material" | "MakeNamedMaterial"
        | "MakeNamedMedium" | "Attribute" => Names(1, true),
        "Texture" => Names(3, true),
        "Option" => Names(0, true),
        "MediumInterface" => OneOrTwoNames,
        _ => return None,
    })
}

/// Includes nested deeper than this are taken for a cycle.
const MAX_INCLUDE_DEPTH: usize = 64;

pub struct Parser {
    stack: Vec<Tokenizer>,
    peeked: Option<Token>,
    base_dir: PathBuf,
    /// Where the last token read starts, for errors about the end of the scene.
    last: Loc,
}

/// The text of a scene file, gunzipped if its name ends in `.gz`.
pub fn read_text(path: &Path, at: Option<&Loc>) -> Result<String> {
    let bytes = std::fs::read(path).map_err(|e| match at {
        Some(loc) => loc.error(format!("cannot read \"{}\": {e}", path.display())),
        None => Error::io(path, e),
    })?;
    let bytes = if path.extension().is_some_and(|e| e == "gz") {
        let mut out = Vec::new();
        flate2::read::GzDecoder::new(bytes.as_slice())
            .read_to_end(&mut out)
            .map_err(|e| Error::io(path, e))?;
        out
    } else {
        bytes
    };
    String::from_utf8(bytes).map_err(|e| {
        Error::input(
            crate::error::Location::byte(path, e.utf8_error().valid_up_to() as u64),
            "the scene file is not valid UTF-8 text",
        )
    })
}

impl Parser {
    pub fn new(text: &str, file: &Path) -> Self {
        Self {
            stack: vec![Tokenizer::new(text, file)],
            peeked: None,
            last: Loc {
                file: std::rc::Rc::new(file.to_path_buf()),
                line: 1,
                column: 1,
            },
            base_dir: file.parent().map(Path::to_path_buf).unwrap_or_default(),
        }
    }

    /// Resolves a file name written in the scene: relative names start at the first file's
    /// folder.
    pub fn resolve(&self, name: &str) -> PathBuf {
        self.base_dir.join(name)
    }

    /// Where the last token read starts.
    pub fn end_loc(&self) -> Loc {
        self.last.clone()
    }

    fn next(&mut self) -> Result<Option<Token>> {
        if let Some(t) = self.peeked.take() {
            return Ok(Some(t));
        }
        while let Some(top) = self.stack.last_mut() {
            if let Some(t) = top.next_token()? {
                self.last = t.loc.clone();
                return Ok(Some(t));
            }
            self.stack.pop();
        }
        Ok(None)
    }

    fn peek(&mut self) -> Result<Option<&Token>> {
        if self.peeked.is_none() {
            self.peeked = self.next()?;
        }
        Ok(self.peeked.as_ref())
    }

    /// The next directive, after following any `Include` or `Import`; `None` at the end.
    pub fn directive(&mut self) -> Result<Option<Directive>> {
        loop {
            let Some(d) = self.one_directive()? else {
                return Ok(None);
            };
            if d.name != "Include" && d.name != "Import" {
                return Ok(Some(d));
            }
            if self.stack.len() >= MAX_INCLUDE_DEPTH {
                return Err(d
                    .loc
                    .error("includes nest too deep (does a file include itself?)"));
            }
            let path = self.resolve(&d.strings[0]);
            if !path.is_file() {
                return Err(d.loc.error(format!(
                    "{} file \"{}\" not found (looked for {})",
                    d.name,
                    d.strings[0],
                    path.display()
                )));
            }
            let text = read_text(&path, Some(&d.loc))?;
            // `Include "file"` takes no parameter list, so nothing after it has been peeked: the
            // included file's tokens come next.
            debug_assert!(self.peeked.is_none());
            self.stack.push(Tokenizer::new(&text, &path));
        }
    }

    fn one_directive(&mut self) -> Result<Option<Directive>> {
        let Some(t) = self.next()? else {
            return Ok(None);
        };
        let name = match t.tok {
            Tok::Word(w) => w,
            Tok::Str(s) => {
                return Err(t
                    .loc
                    .error(format!("expected a directive, found the string \"{s}\"")))
            }
            Tok::Open | Tok::Close => {
                return Err(t.loc.error("expected a directive, found a bracket"));
            }
        };
        let loc = t.loc;
        let shape =
            shape_of(&name).ok_or_else(|| loc.error(format!("unknown directive \"{name}\"")))?;
        let mut d = Directive {
            name,
            loc,
            strings: Vec::new(),
            numbers: Vec::new(),
            params: ParamSet::default(),
        };
        match shape {
            Shape::Nothing => {}
            Shape::Numbers(n) => d.numbers = self.numbers(&d, n)?,
            Shape::Names(n, params) => {
                for _ in 0..n {
                    d.strings.push(self.name(&d)?);
                }
                if params {
                    d.params = self.params()?;
                }
            }
            Shape::OneOrTwoNames => {
                d.strings.push(self.name(&d)?);
                if matches!(
                    self.peek()?,
                    Some(Token {
                        tok: Tok::Str(_),
                        ..
                    })
                ) {
                    d.strings.push(self.name(&d)?);
                }
            }
            Shape::Word => match self.next()? {
                Some(Token {
                    tok: Tok::Word(w), ..
                }) => d.strings.push(w),
                _ => return Err(d.loc.error(format!("{} needs a word after it", d.name))),
            },
        }
        Ok(Some(d))
    }

    fn name(&mut self, d: &Directive) -> Result<String> {
        match self.next()? {
            Some(Token {
                tok: Tok::Str(s), ..
            }) => Ok(s),
            Some(t) => Err(t.loc.error(format!(
                "{} expects a quoted name here, found {}",
                d.name,
                describe(&t.tok)
            ))),
            None => Err(d.loc.error(format!(
                "{} expects a quoted name, found the end of the file",
                d.name
            ))),
        }
    }

    /// `n` numbers, in brackets or not.
    fn numbers(&mut self, d: &Directive, n: usize) -> Result<Vec<f64>> {
        let bracketed = matches!(self.peek()?, Some(Token { tok: Tok::Open, .. }));
        if bracketed {
            self.next()?;
        }
        let mut out = Vec::with_capacity(n);
        loop {
            if !bracketed && out.len() == n {
                break;
            }
            let t = self.next()?.ok_or_else(|| {
                d.loc.error(format!(
                    "{} needs {n} numbers, found the end of the file",
                    d.name
                ))
            })?;
            match t.tok {
                Tok::Close if bracketed => break,
                Tok::Word(w) => out.push(
                    parse_number(&w)
                        .ok_or_else(|| t.loc.error(format!("bad number \"{w}\" in {}", d.name)))?,
                ),
                other => {
                    return Err(t.loc.error(format!(
                        "{} needs {n} numbers, found {}",
                        d.name,
                        describe(&other)
                    )))
                }
            }
        }
        if out.len() != n {
            return Err(d
                .loc
                .error(format!("{} needs {n} numbers, got {}", d.name, out.len())));
        }
        Ok(out)
    }

    /// A parameter list: `"type name" value` pairs, as long as a quoted string follows.
    fn params(&mut self) -> Result<ParamSet> {
        let mut set = ParamSet::default();
        while let Some(Token {
            tok: Tok::Str(_), ..
        }) = self.peek()?
        {
            let t = self.next()?.expect("peeked");
            let Tok::Str(decl) = t.tok else {
                unreachable!("peeked a string")
            };
            let loc = t.loc;
            let mut raw = Vec::new();
            let v = self
                .next()?
                .ok_or_else(|| loc.error(format!("parameter \"{decl}\" has no value")))?;
            match v.tok {
                Tok::Open => loop {
                    let t = self.next()?.ok_or_else(|| {
                        loc.error(format!(
                            "parameter \"{decl}\": no ']' before the end of the file"
                        ))
                    })?;
                    match t.tok {
                        Tok::Close => break,
                        Tok::Open => return Err(t.loc.error("'[' inside a parameter's values")),
                        Tok::Word(w) => raw.push((RawValue::Word(w), t.loc)),
                        Tok::Str(s) => raw.push((RawValue::Str(s), t.loc)),
                    }
                },
                Tok::Word(w) => raw.push((RawValue::Word(w), v.loc)),
                Tok::Str(s) => raw.push((RawValue::Str(s), v.loc)),
                Tok::Close => {
                    return Err(v.loc.error(format!("parameter \"{decl}\" has no value")))
                }
            }
            let p = Param::new(&decl, raw, loc)?;
            if set.params.iter().any(|q| q.name == p.name) {
                return Err(p.error(format!("parameter \"{}\" is given twice", p.name)));
            }
            set.params.push(p);
        }
        Ok(set)
    }
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Str(s) => format!("the string \"{s}\""),
        Tok::Word(w) => format!("\"{w}\""),
        Tok::Open => "'['".into(),
        Tok::Close => "']'".into(),
    }
}
