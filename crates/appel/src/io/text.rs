//! Text files as UTF-8, with an error at the line and column of the first byte that is not.

use crate::error::{Error, Location, Result};
use std::path::Path;

/// `bytes` as a string, or an error naming `path` and the line and column (1-based, in characters)
/// of the first invalid byte.
pub fn utf8_text(bytes: Vec<u8>, path: &Path) -> Result<String> {
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let before = std::str::from_utf8(&e.as_bytes()[..valid]).unwrap_or_default();
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        Error::input(
            Location::line(path, line, Some(column)),
            format!("the file is not valid UTF-8 text (byte {valid})"),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_bad_byte_is_placed_by_line_and_column() {
        let e = utf8_text(b"ok\nd\xc3\xa9j\xff!".to_vec(), Path::new("s.toml")).unwrap_err();
        // Line 2, after "d", "é" and "j": column 4; byte 3 + 4.
        assert_eq!(
            e.to_string(),
            "s.toml:2:4: the file is not valid UTF-8 text (byte 7)"
        );
        assert_eq!(utf8_text(b"fine".to_vec(), Path::new("s")).unwrap(), "fine");
    }
}
