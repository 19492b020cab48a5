//! `[materials.NAME]`: one tagged table per material, `type` naming the model. Whitted's
//! phenomenological model (`phong`) sits beside the physically based BSDFs of Mitsuba 3, with
//! Mitsuba's parameter names and defaults, so that a Mitsuba scene maps onto this schema key for
//! key.

use super::Vec3f;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum MaterialDesc {
    /// Whitted's model: `ambient * ka + sum over visible lights (kd * color * cos + ks * blinn^n) +
    /// kr * reflected + kt * transmitted`. `whitted` is its older name.
    #[serde(alias = "whitted")]
    Phong(PhongDesc),
    /// Lambertian reflection.
    Diffuse(DiffuseDesc),
    /// A smooth metal: a mirror weighted by the complex Fresnel reflectance.
    Conductor(ConductorDesc),
    /// A rough metal: a microfacet model (Walter et al. 2007) over the same Fresnel.
    RoughConductor(RoughConductorDesc),
    /// A smooth interface between two indices of refraction.
    Dielectric(DielectricDesc),
    /// An infinitely thin dielectric sheet (window glass): no refraction, inter-reflections summed.
    ThinDielectric(DielectricDesc),
    /// A rough dielectric interface (Walter et al. 2007).
    RoughDielectric(RoughDielectricDesc),
    /// A diffuse base under a smooth dielectric coating.
    Plastic(PlasticDesc),
    /// A diffuse base under a rough dielectric coating.
    RoughPlastic(RoughPlasticDesc),
    /// Burley's Disney BSDF as Mitsuba's `principled`: diffuse with retro-reflection and sheen,
    /// a GGX specular lobe blending dielectric, metallic and transmitting responses, a clearcoat.
    Principled(PrincipledDesc),
    /// Mitsuba's `principledthin`: the Disney BSDF of a thin sheet (leaves, paper, fabric).
    PrincipledThin(PrincipledThinDesc),
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

/// Reads `[materials]`: a table without `type` is a `phong` (Whitted) material, as every material
/// was before the physically based ones, so that older scene files keep their meaning. Each entry is read
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

    /// Every texture the material reads, with its key.
    pub fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        fn opt<'a>(
            k: &'static str,
            v: &'a Option<TextureDesc>,
        ) -> Option<(&'static str, &'a TextureDesc)> {
            v.as_ref().map(|v| (k, v))
        }
        let t: Vec<Option<(&'static str, &TextureDesc)>> = match self {
            MaterialDesc::Phong(_) | MaterialDesc::TwoSided(_) => vec![],
            MaterialDesc::Diffuse(d) => vec![Some(("reflectance", &d.reflectance))],
            MaterialDesc::Conductor(c) => {
                vec![Some(("specular_reflectance", &c.specular_reflectance))]
            }
            MaterialDesc::RoughConductor(c) => vec![
                Some(("specular_reflectance", &c.specular_reflectance)),
                opt("alpha", &c.alpha),
                opt("alpha_u", &c.alpha_u),
                opt("alpha_v", &c.alpha_v),
            ],
            MaterialDesc::Dielectric(d) | MaterialDesc::ThinDielectric(d) => vec![
                Some(("specular_reflectance", &d.specular_reflectance)),
                Some(("specular_transmittance", &d.specular_transmittance)),
            ],
            MaterialDesc::RoughDielectric(d) => vec![
                Some(("specular_reflectance", &d.specular_reflectance)),
                Some(("specular_transmittance", &d.specular_transmittance)),
                opt("alpha", &d.alpha),
                opt("alpha_u", &d.alpha_u),
                opt("alpha_v", &d.alpha_v),
            ],
            MaterialDesc::Plastic(p) => vec![
                Some(("diffuse_reflectance", &p.diffuse_reflectance)),
                Some(("specular_reflectance", &p.specular_reflectance)),
            ],
            MaterialDesc::RoughPlastic(p) => vec![
                Some(("diffuse_reflectance", &p.diffuse_reflectance)),
                Some(("specular_reflectance", &p.specular_reflectance)),
                opt("alpha", &p.alpha),
                opt("alpha_u", &p.alpha_u),
                opt("alpha_v", &p.alpha_v),
            ],
            MaterialDesc::Mask(m) => vec![Some(("opacity", &m.opacity))],
            MaterialDesc::NormalMap(m) => vec![Some(("normalmap", &m.normalmap))],
            MaterialDesc::BumpMap(m) => vec![Some(("bumpmap", &m.bumpmap))],
            MaterialDesc::Blend(m) => vec![Some(("weight", &m.weight))],
            MaterialDesc::Principled(p) => vec![
                Some(("base_color", &p.base_color)),
                Some(("roughness", &p.roughness)),
                Some(("anisotropic", &p.anisotropic)),
                Some(("metallic", &p.metallic)),
                Some(("spec_trans", &p.spec_trans)),
                Some(("spec_tint", &p.spec_tint)),
                Some(("sheen", &p.sheen)),
                Some(("sheen_tint", &p.sheen_tint)),
                Some(("flatness", &p.flatness)),
                Some(("clearcoat", &p.clearcoat)),
                Some(("clearcoat_gloss", &p.clearcoat_gloss)),
            ],
            MaterialDesc::PrincipledThin(p) => vec![
                Some(("base_color", &p.base_color)),
                Some(("roughness", &p.roughness)),
                Some(("anisotropic", &p.anisotropic)),
                Some(("spec_trans", &p.spec_trans)),
                Some(("spec_tint", &p.spec_tint)),
                Some(("sheen", &p.sheen)),
                Some(("sheen_tint", &p.sheen_tint)),
                Some(("flatness", &p.flatness)),
                Some(("diff_trans", &p.diff_trans)),
                Some(("eta", &p.eta)),
            ],
        };
        t.into_iter().flatten().collect()
    }

    /// The indices of refraction of the interfaces the material has, with their keys.
    pub fn iors(&self) -> Vec<(&'static str, &IorDesc)> {
        match self {
            MaterialDesc::Dielectric(d) | MaterialDesc::ThinDielectric(d) => {
                vec![("int_ior", &d.int_ior), ("ext_ior", &d.ext_ior)]
            }
            MaterialDesc::RoughDielectric(d) => {
                vec![("int_ior", &d.int_ior), ("ext_ior", &d.ext_ior)]
            }
            MaterialDesc::Plastic(p) => vec![("int_ior", &p.int_ior), ("ext_ior", &p.ext_ior)],
            MaterialDesc::RoughPlastic(p) => {
                vec![("int_ior", &p.int_ior), ("ext_ior", &p.ext_ior)]
            }
            _ => vec![],
        }
    }
}

/// Whitted's shading model, the `phong` BSDF; see [`MaterialDesc::Phong`].
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PhongDesc {
    /// Base (diffuse) colour, linear RGB.
    #[serde(default = "default_color")]
    pub color: Vec3f,
    /// Optional procedural checkerboard alternating `color` and `checker.color`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checker: Option<CheckerDesc>,
    #[serde(default = "default_ka")]
    pub ambient: f32,
    #[serde(default = "default_kd")]
    pub diffuse: f32,
    #[serde(default)]
    pub specular: f32,
    #[serde(default = "default_shininess")]
    pub shininess: f32,
    #[serde(default)]
    pub reflection: f32,
    #[serde(default)]
    pub transmission: f32,
    #[serde(default = "default_ior")]
    pub ior: f32,
    /// Weight reflection and transmission by the Fresnel reflectance instead of fixed coefficients.
    #[serde(default)]
    pub fresnel: bool,
}

impl Default for PhongDesc {
    fn default() -> Self {
        Self {
            color: default_color(),
            checker: None,
            ambient: default_ka(),
            diffuse: default_kd(),
            specular: 0.0,
            shininess: default_shininess(),
            reflection: 0.0,
            transmission: 0.0,
            ior: default_ior(),
            fresnel: false,
        }
    }
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CheckerDesc {
    /// The second colour of the board.
    pub color: Vec3f,
    /// Side of one square in surface units (scene units on planes).
    #[serde(default = "default_checker_size")]
    pub size: f32,
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
pub struct DiffuseDesc {
    #[serde(default = "half")]
    pub reflectance: TextureDesc,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ConductorDesc {
    /// One of Mitsuba's named metals (`"Au"`, `"Cu"`, ...; `"none"`: a perfect mirror). Ignored
    /// where `eta` and `k` are given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Real part of the complex index of refraction, per RGB channel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<Vec3f>,
    /// Imaginary part (absorption coefficient).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<Vec3f>,
    #[serde(default = "one")]
    pub specular_reflectance: TextureDesc,
}

/// The microfacet normal distribution.
#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum DistributionDesc {
    #[default]
    Beckmann,
    Ggx,
}

/// Roughness: `alpha` (isotropic) or `alpha_u` and `alpha_v` (anisotropic); 0.1 by default. The
/// rough materials repeat these keys rather than flattening a shared struct, because serde cannot
/// reject unknown keys through `flatten`.
macro_rules! rough_fields {
    ($(#[$m:meta])* pub struct $name:ident { $($body:tt)* }) => {
        $(#[$m])*
        #[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            $($body)*
            #[serde(default)]
            pub distribution: DistributionDesc,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub alpha: Option<TextureDesc>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub alpha_u: Option<TextureDesc>,
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub alpha_v: Option<TextureDesc>,
            /// Sample only the visible normals (Heitz and d'Eon 2014).
            #[serde(default = "yes")]
            pub sample_visible: bool,
        }
    };
}

rough_fields! {
    pub struct RoughConductorDesc {
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub material: Option<String>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub eta: Option<Vec3f>,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        pub k: Option<Vec3f>,
        #[serde(default = "one")]
        pub specular_reflectance: TextureDesc,
    }
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DielectricDesc {
    /// Inside (the side opposite the normal); Mitsuba's default is BK7 glass.
    #[serde(default = "bk7")]
    pub int_ior: IorDesc,
    #[serde(default = "air")]
    pub ext_ior: IorDesc,
    #[serde(default = "one")]
    pub specular_reflectance: TextureDesc,
    #[serde(default = "one")]
    pub specular_transmittance: TextureDesc,
}

rough_fields! {
    pub struct RoughDielectricDesc {
        #[serde(default = "bk7")]
        pub int_ior: IorDesc,
        #[serde(default = "air")]
        pub ext_ior: IorDesc,
        #[serde(default = "one")]
        pub specular_reflectance: TextureDesc,
        #[serde(default = "one")]
        pub specular_transmittance: TextureDesc,
    }
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PlasticDesc {
    /// Mitsuba's default is polypropylene (1.49).
    #[serde(default = "polypropylene")]
    pub int_ior: IorDesc,
    #[serde(default = "air")]
    pub ext_ior: IorDesc,
    #[serde(default = "half")]
    pub diffuse_reflectance: TextureDesc,
    #[serde(default = "one")]
    pub specular_reflectance: TextureDesc,
    /// Account for the colour shift of light scattered several times under the coating.
    #[serde(default)]
    pub nonlinear: bool,
}

rough_fields! {
    pub struct RoughPlasticDesc {
        #[serde(default = "polypropylene")]
        pub int_ior: IorDesc,
        #[serde(default = "air")]
        pub ext_ior: IorDesc,
        #[serde(default = "half")]
        pub diffuse_reflectance: TextureDesc,
        #[serde(default = "one")]
        pub specular_reflectance: TextureDesc,
        #[serde(default)]
        pub nonlinear: bool,
    }
}

/// Mitsuba's `principled`, key for key: every weight is a texture in [0, 1] (Burley 2012).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PrincipledDesc {
    #[serde(default = "half")]
    pub base_color: TextureDesc,
    #[serde(default = "half")]
    pub roughness: TextureDesc,
    /// 0: isotropic; towards 1, stretched along the surface's u tangent.
    #[serde(default = "zero")]
    pub anisotropic: TextureDesc,
    #[serde(default = "zero")]
    pub metallic: TextureDesc,
    /// The share of the dielectric part that transmits (rough glass) instead of diffusing.
    #[serde(default = "zero")]
    pub spec_trans: TextureDesc,
    #[serde(default = "zero")]
    pub spec_tint: TextureDesc,
    #[serde(default = "zero")]
    pub sheen: TextureDesc,
    #[serde(default = "zero")]
    pub sheen_tint: TextureDesc,
    /// Blends the diffuse lobe towards Burley's fake subsurface term.
    #[serde(default = "zero")]
    pub flatness: TextureDesc,
    #[serde(default = "zero")]
    pub clearcoat: TextureDesc,
    #[serde(default = "zero")]
    pub clearcoat_gloss: TextureDesc,
    /// Relative IOR of the dielectric part (inside over outside); give this or `specular`, not
    /// both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eta: Option<f32>,
    /// Reflectance at normal incidence as `0.08 specular` (0.5 by default: eta 1.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular: Option<f32>,
    #[serde(default = "one_f")]
    pub diffuse_reflectance_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub main_specular_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub clearcoat_sampling_rate: f32,
}

/// Mitsuba's `principledthin`, key for key.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PrincipledThinDesc {
    #[serde(default = "half")]
    pub base_color: TextureDesc,
    #[serde(default = "half")]
    pub roughness: TextureDesc,
    #[serde(default = "zero")]
    pub anisotropic: TextureDesc,
    /// The share of specular (reflection and straight transmission) against diffuse scattering.
    #[serde(default = "zero")]
    pub spec_trans: TextureDesc,
    #[serde(default = "zero")]
    pub spec_tint: TextureDesc,
    #[serde(default = "zero")]
    pub sheen: TextureDesc,
    #[serde(default = "zero")]
    pub sheen_tint: TextureDesc,
    #[serde(default = "zero")]
    pub flatness: TextureDesc,
    /// Diffuse transmission, from 0 (none) to 2 (all of the diffuse part).
    #[serde(default = "zero")]
    pub diff_trans: TextureDesc,
    /// The sheet's IOR.
    #[serde(default = "one_and_a_half")]
    pub eta: TextureDesc,
    #[serde(default = "one_f")]
    pub specular_reflectance_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub specular_transmittance_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub diffuse_reflectance_sampling_rate: f32,
    #[serde(default = "one_f")]
    pub diffuse_transmittance_sampling_rate: f32,
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

fn half() -> TextureDesc {
    TextureDesc::Value(0.5)
}
fn one() -> TextureDesc {
    TextureDesc::Value(1.0)
}
fn zero() -> TextureDesc {
    TextureDesc::Value(0.0)
}
fn one_and_a_half() -> TextureDesc {
    TextureDesc::Value(1.5)
}
fn one_f() -> f32 {
    1.0
}
fn yes() -> bool {
    true
}
fn bk7() -> IorDesc {
    IorDesc::Named("bk7".into())
}
fn air() -> IorDesc {
    IorDesc::Named("air".into())
}
fn polypropylene() -> IorDesc {
    IorDesc::Named("polypropylene".into())
}
fn default_checker0() -> Vec3f {
    [0.4; 3]
}
fn default_checker1() -> Vec3f {
    [0.2; 3]
}
fn default_color() -> Vec3f {
    [0.8, 0.8, 0.8]
}
fn default_ka() -> f32 {
    0.1
}
fn default_kd() -> f32 {
    0.9
}
fn default_shininess() -> f32 {
    32.0
}
fn default_ior() -> f32 {
    1.5
}
fn default_checker_size() -> f32 {
    1.0
}
