//! `[render.aov]`: the parameters of Mitsuba 3's `aov` integrator, which writes named arbitrary
//! output variables of the surface each pixel sees (depth, position, normals, ids) as image
//! channels, beside the image of an optional nested integrator.

use super::super::{IntegratorName, IntegratorTable};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AovParams {
    /// Comma-separated `name:type` pairs, as Mitsuba's `aovs` string: `"dd.y:depth,nn:sh_normal"`
    /// writes channel `dd.y.T` with the depth and `nn.X`, `nn.Y`, `nn.Z` with the shading normal.
    #[serde(default)]
    pub aovs: String,
    /// The integrator whose image the film's R, G, B hold (Mitsuba's nested `<integrator>`);
    /// without one the image is black and only the AOVs carry information.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub integrator: Option<IntegratorName>,
    /// The nested integrator's name: its image is written a second time as channels `NAME.R`,
    /// `NAME.G`, `NAME.B` and `NAME.A`, as Mitsuba writes a nested integrator's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<String>,
}

/// What an AOV holds, by Mitsuba's type name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AovType {
    /// Distance along the unit camera ray from its origin (0 where the ray hits nothing).
    Depth,
    /// World-space position of the hit.
    Position,
    /// Texture coordinates of the hit.
    Uv,
    /// Unit geometric normal.
    GeoNormal,
    /// Unit shading normal (interpolated vertex normals where a mesh has them).
    ShNormal,
    /// The surface's derivative along u (zero where the surface has no parametrisation).
    DpDu,
    /// The surface's derivative along v.
    DpDv,
    /// Index of the primitive (triangle) within its shape.
    PrimIndex,
    /// Index of the shape, counted from 1 in the scene's order (0 where the ray hits nothing).
    ShapeIndex,
}

impl AovType {
    /// Every type, in the order of [`Self::NAMES`].
    pub const ALL: &'static [AovType] = &[
        AovType::Depth,
        AovType::Position,
        AovType::Uv,
        AovType::GeoNormal,
        AovType::ShNormal,
        AovType::DpDu,
        AovType::DpDv,
        AovType::PrimIndex,
        AovType::ShapeIndex,
    ];
    pub const NAMES: &'static [&'static str] = &[
        "depth",
        "position",
        "uv",
        "geo_normal",
        "sh_normal",
        "dp_du",
        "dp_dv",
        "prim_index",
        "shape_index",
    ];

    /// Mitsuba's types that Appel does not compute, and why.
    const UNSUPPORTED: &'static [(&'static str, &'static str)] = &[
        ("albedo", "Appel's BSDFs have no diffuse-reflectance query"),
        (
            "duv_dx",
            "uv derivatives need ray differentials, which Appel does not trace",
        ),
        (
            "duv_dy",
            "uv derivatives need ray differentials, which Appel does not trace",
        ),
        (
            "boundary_test",
            "it serves differentiable rendering, which Appel does not do",
        ),
    ];

    pub fn name(self) -> &'static str {
        let i = Self::ALL.iter().position(|&t| t == self).expect("listed");
        Self::NAMES[i]
    }

    pub fn from_name(name: &str) -> Option<Self> {
        let i = Self::NAMES.iter().position(|&n| n == name)?;
        Some(Self::ALL[i])
    }

    /// The suffixes of the type's channels, as Mitsuba names them (`name.T` for a depth).
    pub fn suffixes(self) -> &'static [&'static str] {
        match self {
            AovType::Depth => &["T"],
            AovType::Uv => &["U", "V"],
            AovType::Position
            | AovType::GeoNormal
            | AovType::ShNormal
            | AovType::DpDu
            | AovType::DpDv => &["X", "Y", "Z"],
            AovType::PrimIndex | AovType::ShapeIndex => &["I"],
        }
    }
}

/// One entry of `aovs`: the channels `name.SUFFIX` of one type.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AovChannel {
    pub name: String,
    pub ty: AovType,
}

impl AovChannel {
    /// The EXR channel names, in order.
    pub fn channel_names(&self) -> impl Iterator<Item = String> + '_ {
        self.ty
            .suffixes()
            .iter()
            .map(move |s| format!("{}.{s}", self.name))
    }
}

impl AovParams {
    /// The entries of `aovs`, in order; the message says what is wrong with the first bad one.
    pub fn channels(&self) -> Result<Vec<AovChannel>, String> {
        let mut out: Vec<AovChannel> = Vec::new();
        for item in self
            .aovs
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
        {
            let (name, ty) = match item.split_once(':') {
                Some((n, t)) if !n.trim().is_empty() && !t.trim().is_empty() => {
                    (n.trim(), t.trim())
                }
                _ => {
                    return Err(format!(
                        "`{item}` is not a `name:type` pair (as in \"dd.y:depth,nn:sh_normal\")"
                    ))
                }
            };
            let Some(ty) = AovType::from_name(ty) else {
                if let Some((_, why)) = AovType::UNSUPPORTED.iter().find(|(n, _)| *n == ty) {
                    return Err(format!("the AOV type `{ty}` is not supported: {why}"));
                }
                return Err(format!(
                    "unknown AOV type `{ty}`, expected one of: {}",
                    AovType::NAMES.join(", ")
                ));
            };
            if out.iter().any(|c| c.name == name) || self.image.as_deref() == Some(name) {
                return Err(format!("two outputs are named `{name}`"));
            }
            out.push(AovChannel {
                name: name.to_string(),
                ty,
            });
        }
        Ok(out)
    }
}

impl IntegratorTable for AovParams {
    fn nested(&self) -> Option<IntegratorName> {
        self.integrator
    }

    fn check(&self) -> Result<(), (&'static str, String)> {
        self.channels().map_err(|e| ("aovs", e))?;
        if self.integrator == Some(IntegratorName::Aov) {
            return Err((
                "integrator",
                "the nested integrator must compute an image, not be another `aov`".into(),
            ));
        }
        if self.image.is_some() && self.integrator.is_none() {
            return Err((
                "image",
                "`image` names the nested integrator's channels: give `integrator` too".into(),
            ));
        }
        if self.image.as_deref().is_some_and(str::is_empty) {
            return Err(("image", "the name is empty".into()));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(aovs: &str) -> AovParams {
        AovParams {
            aovs: aovs.into(),
            ..Default::default()
        }
    }

    #[test]
    fn parses_mitsubas_example_into_its_channel_names() {
        let c = params("dd.y:depth, nn:sh_normal,p:position,t:uv,i:prim_index")
            .channels()
            .unwrap();
        let names: Vec<String> = c.iter().flat_map(|c| c.channel_names()).collect();
        assert_eq!(
            names,
            ["dd.y.T", "nn.X", "nn.Y", "nn.Z", "p.X", "p.Y", "p.Z", "t.U", "t.V", "i.I"]
        );
        assert_eq!(c[1].ty, AovType::ShNormal);
        for t in AovType::ALL {
            assert_eq!(AovType::from_name(t.name()), Some(*t));
        }
    }

    #[test]
    fn bad_entries_say_what_is_wrong() {
        let e = params("d:depht").channels().unwrap_err();
        assert!(
            e.contains("unknown AOV type `depht`") && e.contains("sh_normal"),
            "{e}"
        );
        let e = params("a:albedo").channels().unwrap_err();
        assert!(e.contains("not supported"), "{e}");
        assert!(params("depth")
            .channels()
            .unwrap_err()
            .contains("name:type"));
        assert!(params(":depth").channels().is_err());
        assert!(params("a:depth,a:uv")
            .channels()
            .unwrap_err()
            .contains("two"));
        let nested_aov = AovParams {
            integrator: Some(IntegratorName::Aov),
            ..params("d:depth")
        };
        assert_eq!(nested_aov.check().unwrap_err().0, "integrator");
    }
}
