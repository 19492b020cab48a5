//! `[materials.NAME]`: one tagged table per material, `type` naming the model. Whitted's
//! phenomenological model sits beside the physically based BSDFs of Mitsuba 3, with Mitsuba's
//! parameter names and defaults, so that a Mitsuba scene maps onto this schema key for key.

use super::bsdf::*;
use super::bsdf_registry::for_each_bsdf;
use super::Vec3f;
use serde::{Deserialize, Serialize};

macro_rules! define_material_desc {
    ($($(#[$attr:meta])* $Variant:ident($module:ident: $Desc:ident => $Bsdf:ident, $Material:ident)),* $(,)?) => {
        /// A material: one of the BSDFs of the registry
        /// ([`super::bsdf_registry`], each documented by its parameters' struct), or a wrapper
        /// around other materials.
        #[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
        #[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
        pub enum MaterialDesc {
            $($(#[$attr])* $Variant($Desc),)*
            /// Makes one-sided materials two-sided: `front` on both sides, or `back` behind.
            TwoSided(TwoSidedDesc),
            /// Cut-outs: the surface is there with probability `opacity`, else rays pass through.
            Mask(MaskDesc),
            /// `material` shaded around the normals of a tangent-space normal map.
            NormalMap(NormalMapDesc),
            /// `material` shaded around the normals of a height field.
            BumpMap(BumpMapDesc),
            /// Two materials mixed by a weight.
            #[serde(rename = "blendbsdf")]
            Blend(BlendDesc),
        }

        impl MaterialDesc {
            /// The `type` of every BSDF, in the registry's order.
            pub const BSDF_NAMES: &'static [&'static str] = &[$(<$Desc as BsdfParams>::NAME,)*];

            /// The BSDF's textures, indices of refraction, and check; `None` for the
            /// wrappers.
            fn bsdf_textures(&self) -> Option<Vec<(&'static str, &TextureDesc)>> {
                match self {
                    $(MaterialDesc::$Variant(d) => Some(d.textures()),)*
                    _ => None,
                }
            }

            fn bsdf_iors(&self) -> Vec<(&'static str, &IorDesc)> {
                match self {
                    $(MaterialDesc::$Variant(d) => d.iors(),)*
                    _ => Vec::new(),
                }
            }

            /// [`BsdfParams::check`] of a BSDF; wrappers are checked by the
            /// validation itself.
            pub fn check_bsdf(&self) -> Result<(), ParamError> {
                match self {
                    $(MaterialDesc::$Variant(d) => d.check(),)*
                    _ => Ok(()),
                }
            }
        }
    };
}
for_each_bsdf!(define_material_desc);

/// Reads `[materials]`: a table without `type` is a `phong` (Whitted) material, as every material was before
/// the physically based ones, so that older scene files keep their meaning. Each entry is read
/// through a `toml::Table` (either syntax deserializes into one) to add the missing tag; an error
/// then points at the entry's table.
pub(super) fn deserialize_materials<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> Result<std::collections::BTreeMap<String, MaterialDesc>, D::Error> {
    struct WhittedByDefault(MaterialDesc);
    impl<'de> Deserialize<'de> for WhittedByDefault {
        fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            let mut table = toml::Table::deserialize(d)?;
            table
                .entry("type")
                .or_insert_with(|| toml::Value::String("phong".into()));
            MaterialDesc::deserialize(toml::Value::Table(table))
                .map(WhittedByDefault)
                .map_err(serde::de::Error::custom)
        }
    }
    let map = std::collections::BTreeMap::<String, WhittedByDefault>::deserialize(d)?;
    Ok(map.into_iter().map(|(k, v)| (k, v.0)).collect())
}

impl Default for MaterialDesc {
    fn default() -> Self {
        MaterialDesc::Phong(PhongDesc::default())
    }
}

impl MaterialDesc {
    /// The names of the other materials this one wraps.
    pub fn references(&self) -> Vec<&str> {
        match self {
            MaterialDesc::TwoSided(t) => std::iter::once(t.front.as_str())
                .chain(t.back.as_deref())
                .collect(),
            MaterialDesc::Mask(m) => vec![m.material.as_str()],
            MaterialDesc::NormalMap(m) => vec![m.material.as_str()],
            MaterialDesc::BumpMap(m) => vec![m.material.as_str()],
            MaterialDesc::Blend(m) => m.materials.iter().map(String::as_str).collect(),
            _ => vec![],
        }
    }

    /// The names of every material `type` that wraps others rather than scattering light itself.
    pub const WRAPPER_NAMES: &'static [&'static str] =
        &["twosided", "mask", "normalmap", "bumpmap", "blendbsdf"];

    /// Every texture the material reads, with its key.
    pub fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        if let Some(t) = self.bsdf_textures() {
            return t;
        }
        match self {
            MaterialDesc::Mask(m) => vec![("opacity", &m.opacity)],
            MaterialDesc::NormalMap(m) => vec![("normalmap", &m.normalmap)],
            MaterialDesc::BumpMap(m) => vec![("bumpmap", &m.bumpmap)],
            MaterialDesc::Blend(m) => vec![("weight", &m.weight)],
            _ => vec![],
        }
    }

    /// The indices of refraction of the interfaces the material has, with their keys.
    pub fn iors(&self) -> Vec<(&'static str, &IorDesc)> {
        self.bsdf_iors()
    }
}

/// A colour or a scalar that may vary over the surface: a number (grey), `[r, g, b]`, or a table
/// `{ type = "bitmap", ... }` / `{ type = "checkerboard", ... }`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum TextureDesc {
    Value(f32),
    Rgb(Vec3f),
    Texture(TextureNode),
}

impl TextureDesc {
    pub const fn grey(v: f32) -> Self {
        TextureDesc::Value(v)
    }
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum TextureNode {
    /// An image file (PNG, JPEG, EXR, HDR), relative to the scene file's folder.
    Bitmap {
        file: String,
        /// "bilinear" (default) or "nearest".
        #[serde(default)]
        filter: TextureFilter,
        /// "repeat" (default), "mirror" or "clamp".
        #[serde(default)]
        wrap: TextureWrap,
        /// Read 8-bit values as they are instead of decoding sRGB.
        #[serde(default)]
        raw: bool,
        /// A 3x3 row-major matrix applied to (u, v, 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        to_uv: Option<[[f32; 3]; 3]>,
    },
    /// Mitsuba's checkerboard: `color0` where `floor(2u) + floor(2v)` is even... see the docs.
    /// A mesh's named per-vertex or per-face values (Mitsuba's `mesh_attribute`): PLY files'
    /// extra properties, as `vertex_NAME` and `face_NAME`.
    MeshAttribute { name: String },
    Checkerboard {
        #[serde(default = "default_checker0")]
        color0: Vec3f,
        #[serde(default = "default_checker1")]
        color1: Vec3f,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        to_uv: Option<[[f32; 3]; 3]>,
    },
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum TextureFilter {
    #[default]
    Bilinear,
    Nearest,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum TextureWrap {
    #[default]
    Repeat,
    Mirror,
    Clamp,
}

/// An index of refraction: a number or one of Mitsuba's names (`"bk7"`, `"water"`, ...).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum IorDesc {
    Value(f32),
    Named(String),
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TwoSidedDesc {
    /// The material seen from the front (and from the back unless `back` is given).
    pub front: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub back: Option<String>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MaskDesc {
    #[serde(default = "half")]
    pub opacity: TextureDesc,
    /// The material where the surface is present.
    pub material: String,
}

/// A tangent-space normal map: RGB in [0, 1] is the normal in [-1, 1]^3 relative to the shading
/// frame (x along dp/du, z the shading normal). Give bitmaps `raw = true`: the values are not
/// colours.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct NormalMapDesc {
    pub normalmap: TextureDesc,
    /// The material shaded with the perturbed normals.
    pub material: String,
    /// Turn normals that face away from the viewer towards it (Mitsuba's default).
    #[serde(default = "yes")]
    pub flip_invalid_normals: bool,
    /// Soften the shadow terminator of tilted normals (Conty Estevez et al. 2019; Mitsuba's
    /// default).
    #[serde(default = "yes")]
    pub use_shadowing_function: bool,
}

/// A bump map: the height field's gradient in uv (its grey value or luminance), times `scale`,
/// tilts the normal.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BumpMapDesc {
    pub bumpmap: TextureDesc,
    #[serde(default = "one_f")]
    pub scale: f32,
    pub material: String,
    #[serde(default = "yes")]
    pub flip_invalid_normals: bool,
    #[serde(default = "yes")]
    pub use_shadowing_function: bool,
}

/// Mitsuba's `blendbsdf`: `(1 - weight) materials[0] + weight materials[1]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BlendDesc {
    /// Texture in [0, 1] (clamped): the share of the second material.
    #[serde(default = "half")]
    pub weight: TextureDesc,
    /// The two materials, plain BSDFs (not wrappers such as `twosided` or another blend).
    pub materials: [String; 2],
}

fn default_checker0() -> Vec3f {
    [0.4; 3]
}
fn default_checker1() -> Vec3f {
    [0.2; 3]
}
