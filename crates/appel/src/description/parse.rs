//! Reading a scene file into a [`Description`], with errors that name the file, line and column.

use super::Description;
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

/// Where the value at `path` starts in JSON `text` (which parsed), or the deepest enclosing value
/// found, for the same messages as [`toml_span`]. serde_json keeps no positions of values, so this
/// walks the text: strings (with their escapes) and nesting are all it needs to know.
pub fn json_offset(text: &str, path: &[PathSeg]) -> Option<usize> {
    let b = text.as_bytes();
    let mut at = skip_space(b, 0);
    for seg in path {
        let inner = match (b.get(at)?, seg) {
            (b'{', PathSeg::Key(k)) => json_member(text, at, k),
            (b'[', PathSeg::Index(i)) => json_element(b, at, *i),
            _ => None,
        };
        match inner {
            Some(i) => at = i,
            None => break,
        }
    }
    Some(at)
}

fn skip_space(b: &[u8], mut i: usize) -> usize {
    while b.get(i).is_some_and(|c| c.is_ascii_whitespace()) {
        i += 1;
    }
    i
}

/// The end of the string starting at the quote `i`.
fn string_end(b: &[u8], mut i: usize) -> Option<usize> {
    i += 1;
    loop {
        match b.get(i)? {
            b'\\' => i += 2,
            b'"' => return Some(i + 1),
            _ => i += 1,
        }
    }
}

/// The end of the value starting at `i`.
fn value_end(b: &[u8], i: usize) -> Option<usize> {
    match b.get(i)? {
        b'"' => string_end(b, i),
        b'{' | b'[' => {
            let mut depth = 0usize;
            let mut j = i;
            loop {
                match b.get(j)? {
                    b'"' => {
                        j = string_end(b, j)?;
                        continue;
                    }
                    b'{' | b'[' => depth += 1,
                    b'}' | b']' => {
                        depth -= 1;
                        if depth == 0 {
                            return Some(j + 1);
                        }
                    }
                    _ => {}
                }
                j += 1;
            }
        }
        _ => {
            let mut j = i;
            while b
                .get(j)
                .is_some_and(|c| !matches!(c, b',' | b'}' | b']') && !c.is_ascii_whitespace())
            {
                j += 1;
            }
            Some(j)
        }
    }
}

/// The start of the value of member `key` of the object at `i`.
fn json_member(text: &str, i: usize, key: &str) -> Option<usize> {
    let b = text.as_bytes();
    let mut j = skip_space(b, i + 1);
    while b.get(j)? == &b'"' {
        let end = string_end(b, j)?;
        let name: String = serde_json::from_str(&text[j..end]).ok()?;
        j = skip_space(b, end);
        if b.get(j)? != &b':' {
            return None;
        }
        j = skip_space(b, j + 1);
        if name == key {
            return Some(j);
        }
        j = skip_space(b, value_end(b, j)?);
        if b.get(j)? == &b',' {
            j = skip_space(b, j + 1);
        }
    }
    None
}

/// The start of element `index` of the array at `i`.
fn json_element(b: &[u8], i: usize, index: usize) -> Option<usize> {
    let mut j = skip_space(b, i + 1);
    for _ in 0..index {
        if b.get(j)? == &b']' {
            return None;
        }
        j = skip_space(b, value_end(b, j)?);
        if b.get(j)? != &b',' {
            return None;
        }
        j = skip_space(b, j + 1);
    }
    (b.get(j)? != &b']').then_some(j)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_values_are_found_by_their_path() {
        let text = "{\n  \"a\\\"b\": [1, {\"x\": \"]}\"}],\n  \"shape\": [\n    {\"r\": 1},\n    {\"radius\": -2}\n  ]\n}";
        let path = [
            PathSeg::Key("shape".into()),
            PathSeg::Index(1),
            PathSeg::Key("radius".into()),
        ];
        let at = json_offset(text, &path).unwrap();
        assert_eq!(&text[at..at + 2], "-2");
        assert_eq!(line_column(text, at), (5, 16));
        // A key that is not there: the deepest value found.
        let at = json_offset(text, &[PathSeg::Key("shape".into()), PathSeg::Index(7)]).unwrap();
        assert_eq!(line_column(text, at), (3, 12));
        let at = json_offset(text, &[PathSeg::Key("a\"b".into()), PathSeg::Index(1)]).unwrap();
        assert_eq!(&text[at..at + 5], "{\"x\":");
    }
}
