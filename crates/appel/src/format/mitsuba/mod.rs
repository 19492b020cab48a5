//! Mitsuba 3 scene files (`.xml`): the XML layer (`xml`: elements with their lines; `expand`:
//! parameters, includes, paths, references; `params`, `transform`, `spectrum`: the values of
//! properties as Mitsuba reads them) gives a [`Document`] of objects and properties, which
//! `convert` maps onto Appel's [`Description`](crate::scene::Description).

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
) -> crate::error::Result<crate::scene::Description> {
    convert(&load_document(path, options)?)
}

/// [`load_xml`], with where each entry of the description was written, to place the problems
/// its validation finds.
pub fn load_xml_with_origins(
    path: &std::path::Path,
    options: &XmlOptions,
) -> crate::error::Result<(crate::scene::Description, crate::scene::origins::Origins)> {
    convert_with_origins(&load_document(path, options)?)
}

/// How a scene file is read.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct XmlOptions {
    /// `-D name=value` parameters: they replace `$name` in attribute values and override the
    /// file's `<default name="name" value="..."/>`.
    pub params: Vec<(String, String)>,
}
