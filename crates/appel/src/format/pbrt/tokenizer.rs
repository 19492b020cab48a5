//! pbrt's lexical layer: quoted strings, `[` and `]`, `#` comments to the end of the line, and
//! every other run of non-blank characters as a word (directive names, numbers, `true`/`false`).
//! Each token keeps the file, line and column where it starts.

use crate::error::{Error, Location, Result};
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Where a token starts.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loc {
    pub file: Rc<PathBuf>,
    pub line: usize,
    pub column: usize,
}

impl Loc {
    pub fn error(&self, message: impl Into<String>) -> Error {
        Error::input(
            Location::line(self.file.as_path(), self.line, Some(self.column)),
            message,
        )
    }

    /// `file:line:column`, for warnings.
    pub fn describe(&self) -> String {
        format!("{}:{}:{}", self.file.display(), self.line, self.column)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    /// A quoted string, escapes resolved.
    Str(String),
    /// Anything else that is not a bracket.
    Word(String),
    Open,
    Close,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub tok: Tok,
    pub loc: Loc,
}

pub struct Tokenizer {
    text: Vec<char>,
    pos: usize,
    line: usize,
    column: usize,
    file: Rc<PathBuf>,
}

impl Tokenizer {
    pub fn new(text: &str, file: &Path) -> Self {
        Self {
            text: text.chars().collect(),
            pos: 0,
            line: 1,
            column: 1,
            file: Rc::new(file.to_path_buf()),
        }
    }

    fn loc(&self) -> Loc {
        Loc {
            file: self.file.clone(),
            line: self.line,
            column: self.column,
        }
    }

    fn bump(&mut self) -> Option<char> {
        let c = *self.text.get(self.pos)?;
        self.pos += 1;
        if c == '\n' {
            self.line += 1;
            self.column = 1;
        } else {
            self.column += 1;
        }
        Some(c)
    }

    fn peek(&self) -> Option<char> {
        self.text.get(self.pos).copied()
    }

    /// The next token, or `None` at the end of the file.
    pub fn next_token(&mut self) -> Result<Option<Token>> {
        loop {
            match self.peek() {
                None => return Ok(None),
                Some(c) if c.is_whitespace() => {
                    self.bump();
                }
                Some('#') => {
                    while !matches!(self.peek(), None | Some('\n')) {
                        self.bump();
                    }
                }
                Some(_) => break,
            }
        }
        let loc = self.loc();
        let c = self.bump().expect("peeked");
        let tok = match c {
            '[' => Tok::Open,
            ']' => Tok::Close,
            '"' => Tok::Str(self.string(&loc)?),
            _ => {
                let mut word = String::from(c);
                while let Some(c) = self.peek() {
                    if c.is_whitespace() || matches!(c, '[' | ']' | '"' | '#') {
                        break;
                    }
                    word.push(c);
                    self.bump();
                }
                Tok::Word(word)
            }
        };
        Ok(Some(Token { tok, loc }))
    }

    /// The rest of a quoted string, whose opening quote is at `start`. Strings end on their line,
    /// as in pbrt, so that a missing quote is reported where it is missing.
    fn string(&mut self, start: &Loc) -> Result<String> {
        let mut s = String::new();
        loop {
            match self.bump() {
                None | Some('\n') => {
                    return Err(start.error("unterminated string: no closing '\"' on this line"))
                }
                Some('"') => return Ok(s),
                Some('\\') => {
                    let at = self.loc();
                    let e = match self.bump() {
                        Some('n') => '\n',
                        Some('t') => '\t',
                        Some('r') => '\r',
                        Some('b') => '\u{8}',
                        Some('f') => '\u{c}',
                        Some('\\') => '\\',
                        Some('\'') => '\'',
                        Some('"') => '"',
                        other => {
                            return Err(at.error(format!(
                                "unknown escape sequence \\{}",
                                other.map_or(String::new(), String::from)
                            )))
                        }
                    };
                    s.push(e);
                }
                Some(c) => s.push(c),
            }
        }
    }
}
