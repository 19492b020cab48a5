//! Mitsuba 3 scene files (`.xml`): the XML layer (`xml`: elements with their lines; `expand`:
//! parameters, includes, paths, references; `params`, `transform`, `spectrum`: the values of
//! properties as Mitsuba reads them) gives a [`Document`] of objects and properties, which
//! `convert` maps onto Appel's [`Description`](crate::description::Description).

mod convert;
mod document;
mod expand;
mod params;
mod resolver;
pub mod spectrum;
pub mod transform;
mod xml;

#[cfg(test)]
mod tests;

pub use convert::{convert, convert_with_origins};
pub use document::{Child, Document, Object, Property, Spectrum, Target, TextureArg, Value};
pub use expand::{document_from_str, load_document};
pub use resolver::FileResolver;
pub use xml::{Element, Loc};

/// Reads a Mitsuba 3 scene file as Appel's scene description; file names in it are absolute.
pub fn load_xml(
    path: &std::path::Path,
    options: &XmlOptions,
) -> crate::error::Result<crate::description::Description> {
    convert(&load_document(path, options)?)
}

/// [`load_xml`], with where each entry of the description was written, to place the problems
/// its validation finds.
pub fn load_xml_with_origins(
    path: &std::path::Path,
    options: &XmlOptions,
) -> crate::error::Result<(
    crate::description::Description,
    crate::description::origins::Origins,
)> {
    convert_with_origins(&load_document(path, options)?)
}

/// How a scene file is read.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct XmlOptions {
    /// `-D name=value` parameters: they replace `$name` in attribute values and override the
    /// file's `<default name="name" value="..."/>`.
    pub params: Vec<(String, String)>,
}

/// Mitsuba 3 XML scenes (`.xml`), with `-D name=value` parameters.
pub struct MitsubaFormat;

impl super::SceneFormat for MitsubaFormat {
    fn name(&self) -> &'static str {
        "mitsuba"
    }

    fn extensions(&self) -> &'static [&'static str] {
        &[".xml"]
    }

    fn takes_params(&self) -> bool {
        true
    }

    /// File names come out absolute; problems only validation sees are reported at the line of
    /// the element (or parameter) that made the description's entry, with the entry's key.
    fn load(
        &self,
        path: &std::path::Path,
        options: &super::FormatOptions,
    ) -> crate::error::Result<super::LoadedDescription> {
        let xml = XmlOptions {
            params: options.params.clone(),
        };
        let (description, origins) = load_xml_with_origins(path, &xml)?;
        super::validate_converted(description, origins, Vec::new(), path)
    }
}
