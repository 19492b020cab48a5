//! Reading a scene file into a [`Description`], with errors that name the file, line and column.

use super::description::Description;
use crate::error::{Error, Location, Result};
use std::ops::Range;
use std::path::Path;

/// The syntax of a scene file, chosen by its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Syntax {
    Toml,
    Json,
}

impl Syntax {
    pub fn from_path(path: &Path) -> Option<Syntax> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("toml") => Some(Syntax::Toml),
            Some("json") => Some(Syntax::Json),
            _ => None,
        }
    }
}

/// A step in the path to a value in a scene file: a key or an array index.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PathSeg {
    Key(String),
    Index(usize),
}

/// Parses scene text. `origin` only names the file in error messages.
pub fn parse_description(text: &str, syntax: Syntax, origin: &Path) -> Result<Description> {
    match syntax {
        Syntax::Toml => toml::from_str(text).map_err(|e| {
            let (line, col) = e
                .span()
                .map(|s| line_column(text, s.start))
                .unwrap_or((0, 0));
            let location = if line > 0 {
                Location::line(origin, line, Some(col))
            } else {
                Location::file(origin)
            };
            Error::input(location, e.message().to_string())
        }),
        Syntax::Json => serde_json::from_str(text).map_err(|e| {
            let location = if e.line() > 0 {
                Location::line(origin, e.line(), Some(e.column()))
            } else {
                Location::file(origin)
            };
            // serde_json appends " at line L column C"; the location already says it.
            let msg = e.to_string();
            let msg = msg
                .rsplit_once(" at line ")
                .map(|(m, _)| m.to_string())
                .unwrap_or(msg);
            Error::input(location, msg)
        }),
    }
}

/// 1-based line and column of a byte offset.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rsplit('\n')
        .next()
        .map(|l| l.chars().count())
        .unwrap_or(0)
        + 1;
    (line, col)
}

/// Finds where the value at `path` is written in TOML `text`, for error messages about values that
/// parse but make no sense (a negative radius). Falls back to the deepest enclosing table or value
/// whose position is known.
pub fn toml_span(text: &str, path: &[PathSeg]) -> Option<Range<usize>> {
    use toml_edit::{Item, Table, Value};
    enum Node<'a> {
        Item(&'a Item),
        Table(&'a Table),
        Value(&'a Value),
    }
    impl Clone for Node<'_> {
        fn clone(&self) -> Self {
            *self
        }
    }
    impl Copy for Node<'_> {}
    impl Node<'_> {
        fn span(&self) -> Option<Range<usize>> {
            match self {
                Node::Item(i) => i.span(),
                Node::Table(t) => t.span(),
                Node::Value(v) => v.span(),
            }
        }
    }
    let doc = toml_edit::ImDocument::parse(text).ok()?;
    let mut node = Node::Table(doc.as_table());
    let mut best = None;
    for seg in path {
        let next = match (node, seg) {
            (Node::Item(Item::Table(t)) | Node::Table(t), PathSeg::Key(k)) => {
                t.get(k).map(Node::Item)
            }
            (Node::Item(Item::Value(Value::InlineTable(t))), PathSeg::Key(k))
            | (Node::Value(Value::InlineTable(t)), PathSeg::Key(k)) => t.get(k).map(Node::Value),
            (Node::Item(Item::ArrayOfTables(a)), PathSeg::Index(i)) => a.get(*i).map(Node::Table),
            (Node::Item(Item::Value(Value::Array(a))), PathSeg::Index(i))
            | (Node::Value(Value::Array(a)), PathSeg::Index(i)) => a.get(*i).map(Node::Value),
            _ => None,
        };
        match next {
            Some(n) => {
                best = n.span().or(best);
                node = n;
            }
            None => break,
        }
    }
    best
}
