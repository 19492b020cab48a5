//! Appel's own scene files: TOML, or the same schema as JSON (`docs/scene-format.md`). Problems
//! are placed at the line and column where the value is written, found from the text's spans
//! ([`crate::description::description_from_str`]).

use super::{base_dir, FormatOptions, LoadedDescription, SceneFormat};
use crate::description::origins::Origins;
use crate::description::parse::Syntax;
use crate::description::validate;
use crate::description::{description_from_str, located};
use crate::error::{Error, Location, Result};
use std::path::Path;

/// TOML (`.toml`) and JSON (`.json`) scene files.
pub struct TomlFormat;

impl SceneFormat for TomlFormat {
    fn name(&self) -> &'static str {
        "toml"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".toml", ".json"]
    }

    fn recognises(&self, path: &Path) -> bool {
        Syntax::from_path(path).is_some()
    }

    fn load(&self, path: &Path, _options: &FormatOptions) -> Result<LoadedDescription> {
        let syntax = Syntax::from_path(path)
            .ok_or_else(|| Error::input(Location::file(path), "not a .toml or .json scene file"))?;
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        let text = crate::io::text::utf8_text(bytes, path)?;
        let description = description_from_str(&text, syntax, path)?;
        let base_dir = base_dir(path);
        validate::files(&description, &base_dir)
            .map_err(|invalid| located(&invalid, &text, syntax, path))?;
        Ok(LoadedDescription {
            description,
            base_dir,
            origins: Origins::default(),
            warnings: Vec::new(),
            cameras: Vec::new(),
        })
    }
}
