//! The one list of BSDFs. Everything that enumerates BSDFs is generated from it: the description's
//! [`super::MaterialDesc`] variants, their `type` names and the list of names in messages
//! ([`super::MaterialDesc::BSDF_NAMES`], which the Mitsuba reader accepts), the per-variant
//! dispatch of the description (textures, indices of refraction, checks), and in
//! `shading` (which invokes the same list) the runtime `AnyBsdf` enum with its per-call match and
//! the textured `Material` variants.
//!
//! The material wrappers (`twosided`, `mask`, `normalmap`, `bumpmap`, `blendbsdf`) are not in the
//! list: they scatter no light of their own but name other materials, which the material layer
//! resolves around a BSDF at each hit (mirroring directions, perturbing the frame, choosing one
//! of two BSDFs), so they have no `sample` or `eval` to dispatch to and no runtime BSDF type.

/// Calls macro `$then!` with every BSDF as `Variant(module: Desc => Bsdf, Material)`:
/// `description::bsdf::module` holds `Desc` (its parameters, implementing
/// [`super::bsdf::BsdfParams`], whose `NAME` is `module`, the `type` of `[materials.NAME]`), and
/// `shading::bsdf::module` holds `Bsdf` (the BSDF of plain values, implementing
/// `shading::bsdf::Bsdf`) and `Material` (its textured parameters, implementing
/// `shading::bsdf::BsdfMaterial`); attributes before a line are its variant's in the description
/// (`phong` keeps its older name `whitted` as an alias). `Variant` is `module` in upper camel case. Adding a BSDF is
/// those two files, one line here, and the format readers that map onto it.
macro_rules! for_each_bsdf {
    ($then:ident) => {
        $then! {
            #[serde(alias = "whitted")]
            Phong(phong: PhongDesc => Phong, PhongParams),
            Diffuse(diffuse: DiffuseDesc => Diffuse, DiffuseMaterial),
            Conductor(conductor: ConductorDesc => Conductor, ConductorMaterial),
            RoughConductor(roughconductor: RoughConductorDesc => RoughConductor, RoughConductorMaterial),
            Dielectric(dielectric: DielectricDesc => Dielectric, DielectricMaterial),
            ThinDielectric(thindielectric: ThinDielectricDesc => ThinDielectric, ThinDielectricMaterial),
            RoughDielectric(roughdielectric: RoughDielectricDesc => RoughDielectric, RoughDielectricMaterial),
            Plastic(plastic: PlasticDesc => Plastic, PlasticMaterial),
            RoughPlastic(roughplastic: RoughPlasticDesc => RoughPlastic, RoughPlasticMaterial),
            Principled(principled: PrincipledDesc => Principled, PrincipledMaterial),
            PrincipledThin(principledthin: PrincipledThinDesc => PrincipledThin, PrincipledThinMaterial),
            CoatedDiffuse(coateddiffuse: CoatedDiffuseDesc => CoatedDiffuse, CoatedDiffuseMaterial),
            CoatedConductor(coatedconductor: CoatedConductorDesc => CoatedConductor, CoatedConductorMaterial),
            Null(null: NullDesc => Null, NullMaterial),
        }
    };
}
pub(crate) use for_each_bsdf;

/// Whether `a` and `b` are the same name ignoring ASCII case (the compile-time check that a
/// variant is its module's name).
pub(crate) const fn same_name_ignoring_case(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if !a[i].eq_ignore_ascii_case(&b[i]) {
            return false;
        }
        i += 1;
    }
    true
}
