//! The raw element tree of one XML file: tags, attributes and where each element starts. Nothing
//! here knows Mitsuba's vocabulary; `expand` gives the tree its meaning.

use crate::error::{Error, Location, Result};
use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};
use std::path::Path;
use std::sync::Arc;

/// Where an element starts: its file, 1-based line and column (in characters).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loc {
    pub file: Arc<Path>,
    pub line: usize,
    pub column: usize,
}

impl Loc {
    pub fn location(&self) -> Location {
        Location::line(&*self.file, self.line, Some(self.column))
    }

    /// An input error at this place.
    pub fn error(&self, message: impl Into<String>) -> Error {
        Error::input(self.location(), message)
    }
}

/// One element: `<tag attr="value" ...>children</tag>`. Text and comments are dropped, as
/// Mitsuba ignores them.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    pub tag: String,
    pub attrs: Vec<(String, String)>,
    pub children: Vec<Element>,
    pub loc: Loc,
}

impl Element {
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// `<tag type="...">` or `<tag name="...">`, to name the element in messages.
    pub fn describe(&self) -> String {
        match (self.attr("type"), self.attr("name")) {
            (Some(t), _) => format!("<{} type=\"{t}\">", self.tag),
            (None, Some(n)) => format!("<{} name=\"{n}\">", self.tag),
            (None, None) => format!("<{}>", self.tag),
        }
    }

    /// An input error about this element: `file:line:col: <tag ...>: message`.
    pub fn error(&self, message: impl std::fmt::Display) -> Error {
        self.loc.error(format!("{}: {message}", self.describe()))
    }
}

/// Byte offsets of line starts, for turning offsets into lines and columns.
struct Lines<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        let starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Self { text, starts }
    }

    fn loc(&self, file: &Arc<Path>, offset: usize) -> Loc {
        let offset = offset.min(self.text.len());
        let line = self.starts.partition_point(|&s| s <= offset);
        let start = self.starts[line - 1];
        let column = self
            .text
            .get(start..offset)
            .map_or(offset - start, |s| s.chars().count())
            + 1;
        Loc {
            file: file.clone(),
            line,
            column,
        }
    }
}

/// Reads and parses a file; its root element.
pub fn parse_file(path: &Path) -> Result<Element> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let text = crate::io::text::utf8_text(bytes, path)?;
    parse_str(&text, path)
}

/// Parses XML text; `origin` names it in locations. Returns the root element.
pub fn parse_str(text: &str, origin: &Path) -> Result<Element> {
    let file: Arc<Path> = Arc::from(origin);
    let lines = Lines::new(text);
    let mut reader = Reader::from_str(text);
    let config = reader.config_mut();
    config.check_end_names = true;
    config.check_comments = true;
    let mut stack: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    loop {
        let start = reader.buffer_position() as usize;
        let event = reader.read_event().map_err(|e| {
            let at = lines.loc(&file, reader.error_position() as usize);
            at.error(format!("malformed XML: {e}"))
        })?;
        match event {
            Event::Start(ref e) | Event::Empty(ref e) => {
                let loc = lines.loc(&file, start + leading_space(&text[start..]));
                let element = element(e, loc)?;
                if stack.is_empty() && root.is_some() {
                    return Err(element.error("a second root element; a file has one"));
                }
                if matches!(event, Event::Start(_)) {
                    stack.push(element);
                } else {
                    close(element, &mut stack, &mut root);
                }
            }
            Event::End(_) => {
                // check_end_names has matched the name against the open element.
                if let Some(element) = stack.pop() {
                    close(element, &mut stack, &mut root);
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if let Some(open) = stack.pop() {
        return Err(open.error("the element is never closed (the file ends first)"));
    }
    root.ok_or_else(|| lines.loc(&file, 0).error("no root element"))
}

/// Whitespace quick-xml counts into the next event's span.
fn leading_space(s: &str) -> usize {
    s.len() - s.trim_start().len()
}

fn close(element: Element, stack: &mut [Element], root: &mut Option<Element>) {
    match stack.last_mut() {
        Some(parent) => parent.children.push(element),
        None => *root = Some(element),
    }
}

fn element(e: &BytesStart<'_>, loc: Loc) -> Result<Element> {
    let tag = e.name().as_ref().to_string();
    let mut attrs = Vec::new();
    for attr in e.attributes() {
        let attr = attr.map_err(|err| loc.error(format!("<{tag}>: malformed attribute: {err}")))?;
        let value = attr
            .normalized_value(XmlVersion::Implicit1_0)
            .map_err(|err| loc.error(format!("<{tag}>: malformed attribute value: {err}")))?;
        attrs.push((attr.key.as_ref().to_string(), value.into_owned()));
    }
    Ok(Element {
        tag,
        attrs,
        children: Vec::new(),
        loc,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Element> {
        parse_str(text, Path::new("t.xml"))
    }

    #[test]
    fn elements_have_lines_columns_and_attributes() {
        let root = parse(
            "<?xml version=\"1.0\"?>\n<scene version=\"3.0.0\">\n  <!-- c -->\n  <bsdf type=\"diffuse\" id=\"a &amp; b\">\n\t<rgb name=\"reflectance\" value=\"0.5\"/>\n  </bsdf>\n</scene>\n",
        )
        .unwrap();
        assert_eq!(root.tag, "scene");
        assert_eq!((root.loc.line, root.loc.column), (2, 1));
        assert_eq!(root.attr("version"), Some("3.0.0"));
        assert_eq!(root.children.len(), 1);
        let bsdf = &root.children[0];
        assert_eq!((bsdf.loc.line, bsdf.loc.column), (4, 3));
        assert_eq!(bsdf.attr("id"), Some("a & b"));
        assert_eq!(bsdf.describe(), "<bsdf type=\"diffuse\">");
        let rgb = &bsdf.children[0];
        assert_eq!((rgb.loc.line, rgb.loc.column), (5, 2));
        assert_eq!(rgb.describe(), "<rgb name=\"reflectance\">");
    }

    #[test]
    fn an_unclosed_element_is_an_error_at_its_start() {
        let e = parse("<scene version=\"3.0.0\">\n  <bsdf type=\"diffuse\">\n</scene>\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.xml:3:"), "{e}");
        let e = parse("<scene version=\"3.0.0\">\n  <bsdf type=\"diffuse\">\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.xml:2:3: <bsdf type=\"diffuse\">: "), "{e}");
        assert!(e.contains("never closed"), "{e}");
    }

    #[test]
    fn malformed_markup_is_an_error_with_a_line() {
        let e = parse("<scene version=\"3.0.0\">\n<float name=\"x\" value=\"1/>\n</scene>")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("t.xml:2:"), "{e}");
        let e = parse("").unwrap_err().to_string();
        assert!(e.contains("no root element"), "{e}");
        let e = parse("<a/><b/>").unwrap_err().to_string();
        assert!(e.starts_with("t.xml:1:5: <b>: a second root"), "{e}");
    }
}
