//! The line of a value in a JSON text, named by a path such as `nodes[2].children[0]`: readers
//! that check a document after parsing it (glTF's references) place their problems with it.

/// One step of a path: an object's key or an array's index.
#[derive(Clone, Debug, PartialEq)]
enum Step {
    Key(String),
    Index(usize),
}

/// Nesting deeper than this is not followed (the line then comes from the deepest value seen).
const MAX_DEPTH: usize = 128;

/// The 1-based line where the value at `path` starts, or where the deepest value on the way to it
/// starts if the path goes on beyond what the text holds (an extension's key spelled otherwise
/// in the path); `None` if the text does not even hold the path's first step.
pub fn line_of(text: &str, path: &str) -> Option<usize> {
    let steps = parse_path(path);
    let mut scan = Scan {
        bytes: text.as_bytes(),
        at: 0,
        line: 1,
    };
    scan.value(&steps, 0)
        .filter(|&(depth, _)| depth > 0)
        .map(|(_, line)| line)
}

/// `a.b[3].c` as its steps.
fn parse_path(path: &str) -> Vec<Step> {
    let mut steps = vec![];
    for part in path.split('.') {
        let (key, indices) = part.split_once('[').map_or((part, ""), |(k, r)| (k, r));
        if !key.is_empty() {
            steps.push(Step::Key(key.to_string()));
        }
        for index in indices.split('[') {
            if let Ok(i) = index.trim_end_matches(']').parse() {
                steps.push(Step::Index(i));
            }
        }
    }
    steps
}

struct Scan<'a> {
    bytes: &'a [u8],
    at: usize,
    line: usize,
}

impl Scan<'_> {
    fn skip_space(&mut self) {
        while let Some(&c) = self.bytes.get(self.at) {
            match c {
                b'\n' => self.line += 1,
                b' ' | b'\t' | b'\r' => {}
                _ => return,
            }
            self.at += 1;
        }
    }

    /// Reads a value whose path so far matches `rest`'s predecessors; returns how many steps of
    /// `rest` were matched (counting this value's own as 0) and the line of the deepest match.
    fn value(&mut self, rest: &[Step], depth: usize) -> Option<(usize, usize)> {
        self.skip_space();
        let line = self.line;
        let found = match self.bytes.get(self.at)? {
            _ if depth > MAX_DEPTH => None,
            b'{' => self.object(rest, depth),
            b'[' => self.array(rest, depth),
            b'"' => {
                self.string()?;
                None
            }
            _ => {
                while self
                    .bytes
                    .get(self.at)
                    .is_some_and(|c| !b",]} \t\r\n".contains(c))
                {
                    self.at += 1;
                }
                None
            }
        };
        Some(found.map_or((0, line), |(d, l)| (d + 1, l)))
    }

    /// The matched depth below this value, if a step of `rest` was found in it.
    fn object(&mut self, rest: &[Step], depth: usize) -> Option<(usize, usize)> {
        self.at += 1;
        let mut best = None;
        loop {
            self.skip_space();
            match self.bytes.get(self.at)? {
                b'}' => {
                    self.at += 1;
                    return best;
                }
                b',' => self.at += 1,
                b'"' => {
                    let key = self.string()?;
                    self.skip_space();
                    if self.bytes.get(self.at) != Some(&b':') {
                        return best;
                    }
                    self.at += 1;
                    let wanted = rest.first() == Some(&Step::Key(key));
                    let below = if wanted { &rest[1..] } else { &[][..] };
                    let found = self.value(below, depth + 1)?;
                    if wanted {
                        best = Some(found);
                    }
                }
                _ => return best,
            }
        }
    }

    fn array(&mut self, rest: &[Step], depth: usize) -> Option<(usize, usize)> {
        self.at += 1;
        let mut best = None;
        let mut index = 0;
        loop {
            self.skip_space();
            match self.bytes.get(self.at)? {
                b']' => {
                    self.at += 1;
                    return best;
                }
                b',' => {
                    self.at += 1;
                    index += 1;
                }
                _ => {
                    let wanted = rest.first() == Some(&Step::Index(index));
                    let below = if wanted { &rest[1..] } else { &[][..] };
                    let before = self.at;
                    let found = self.value(below, depth + 1)?;
                    if wanted {
                        best = Some(found);
                    }
                    if self.at == before {
                        return best;
                    }
                }
            }
        }
    }

    /// A string's contents (escapes left as written: keys that matter have none).
    fn string(&mut self) -> Option<String> {
        let start = self.at + 1;
        let mut i = start;
        loop {
            match self.bytes.get(i)? {
                b'\\' => i += 2,
                b'"' => break,
                b'\n' => {
                    self.line += 1;
                    i += 1
                }
                _ => i += 1,
            }
        }
        self.at = i + 1;
        Some(String::from_utf8_lossy(&self.bytes[start..i]).into_owned())
    }
}

#[cfg(test)]
mod tests {
    use super::line_of;

    #[test]
    fn paths_find_their_lines() {
        let text = "{\n  \"nodes\": [\n    {\"mesh\": 0},\n    {\"children\": [\n      1,\n      7]}\n  ],\n  \"scene\": 3\n}";
        assert_eq!(line_of(text, "nodes[0].mesh"), Some(3));
        assert_eq!(line_of(text, "nodes[1].children[1]"), Some(6));
        assert_eq!(line_of(text, "scene"), Some(8));
        // A path beyond the text: its deepest value found.
        assert_eq!(line_of(text, "nodes[1].extensions.light"), Some(4));
        assert_eq!(line_of(text, "cameras[0]"), None);
        assert_eq!(
            line_of("{\"a\": [1,\n [2, {\"b\": 1}]]}", "a[1][1].b"),
            Some(2)
        );
    }
}
