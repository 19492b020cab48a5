//! `phong`: the phenomenological model of Whitted (1980), Phong's (1975) local shading with
//! Blinn's (1977) highlight, an ideal mirror and an ideal refraction. Its runtime is
//! `shading::bsdf::phong`.

use super::BsdfParams;
use crate::description::param_error::{non_negative, positive, ParamError};
use crate::description::{TextureDesc, Vec3f};
use serde::{Deserialize, Serialize};

/// Whitted's model: `ambient * ka + sum over visible lights (kd * color * cos + ks * blinn^n) +
/// kr * reflected + kt * transmitted`. Its `type` is `phong` (`whitted` is its older name, and a
/// material without `type` is one).
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

impl BsdfParams for PhongDesc {
    const NAME: &'static str = "phong";

    /// Its colour is a plain colour or Whitted's own checkerboard, not a texture.
    fn textures(&self) -> Vec<(&'static str, &TextureDesc)> {
        Vec::new()
    }

    fn check(&self) -> Result<(), ParamError> {
        non_negative("color", &self.color)?;
        for (k, v) in [
            ("ambient", self.ambient),
            ("diffuse", self.diffuse),
            ("specular", self.specular),
            ("shininess", self.shininess),
            ("reflection", self.reflection),
            ("transmission", self.transmission),
        ] {
            non_negative(k, &[v])?;
        }
        positive("ior", self.ior)?;
        if let Some(ch) = &self.checker {
            non_negative("checker.color", &ch.color)?;
            positive("checker.size", ch.size)?;
        }
        Ok(())
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

#[cfg(test)]
mod tests {
    use crate::description::parse::Syntax;
    use crate::description::{description_from_str, MaterialDesc, PhongDesc};
    use std::path::Path;

    /// `phong`, its older name `whitted`, and a table without `type` all read as Whitted's model.
    #[test]
    fn phong_is_read_by_name_alias_and_default() {
        let text = r#"
[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]

[materials.named]
type = "phong"
reflection = 0.5

[materials.older]
type = "whitted"
reflection = 0.5

[materials.untyped]
reflection = 0.5
"#;
        let d = description_from_str(text, Syntax::Toml, Path::new("t.toml")).unwrap();
        let expected = MaterialDesc::Phong(PhongDesc {
            reflection: 0.5,
            ..PhongDesc::default()
        });
        for name in ["named", "older", "untyped"] {
            assert_eq!(d.materials[name], expected, "{name}");
        }
    }

    /// Its checks report at the value's line, inside the checkerboard's table too.
    #[test]
    fn bad_values_fail_at_their_line() {
        let scene = |material: &str| {
            format!("[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[materials.m]\n{material}")
        };
        let err = |material: &str| {
            description_from_str(&scene(material), Syntax::Toml, Path::new("t.toml"))
                .unwrap_err()
                .to_string()
        };
        let e = err("type = \"phong\"\nshininess = -1\n");
        assert!(e.starts_with("t.toml:7:") && e.contains("`shininess` must not be negative"), "{e}");
        let e = err("ior = 0\n");
        assert!(e.starts_with("t.toml:6:") && e.contains("`ior` must be a positive number"), "{e}");
        let e = err("[materials.m.checker]\ncolor = [0, 0, 0]\nsize = -2\n");
        assert!(
            e.starts_with("t.toml:8:") && e.contains("`checker.size` must be a positive number"),
            "{e}"
        );
    }
}
