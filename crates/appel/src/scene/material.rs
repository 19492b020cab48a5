use crate::description::{MaterialDesc, WhittedDesc};
use crate::math::{Vec2, Vec3};
use std::collections::BTreeMap;

/// Whitted's surface model, see [`MaterialDesc`] and `docs/scene-format.md`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub color: Vec3,
    pub checker: Option<Checker>,
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub shininess: f32,
    pub reflection: f32,
    pub transmission: f32,
    pub ior: f32,
    pub fresnel: bool,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checker {
    pub color: Vec3,
    pub size: f32,
}

impl Material {
    /// Whitted's view of any material: the physically based ones by their nearest Whitted
    /// equivalent (documented in docs/scene-format.md), so that raycast and Whitted render every
    /// scene. `all` resolves the materials a two-sided or mask material wraps.
    pub fn approximating(d: &MaterialDesc, all: &BTreeMap<String, MaterialDesc>) -> Self {
        Self::new(&whitted_equivalent(d, all, 0))
    }

    pub fn new(d: &WhittedDesc) -> Self {
        Self {
            color: d.color.into(),
            checker: d.checker.as_ref().map(|c| Checker {
                color: c.color.into(),
                size: c.size,
            }),
            ambient: d.ambient,
            diffuse: d.diffuse,
            specular: d.specular,
            shininess: d.shininess,
            reflection: d.reflection,
            transmission: d.transmission,
            ior: d.ior,
            fresnel: d.fresnel,
        }
    }

    /// The diffuse colour at texture coordinates `uv`: squares of side `checker.size` alternate between
    /// `color` (the square containing the origin's +u,+v corner) and `checker.color`.
    pub fn albedo(&self, uv: Vec2) -> Vec3 {
        match self.checker {
            Some(c) => {
                let cell = uv / c.size;
                if (floor_i64(cell.x) + floor_i64(cell.y)).rem_euclid(2) == 0 {
                    self.color
                } else {
                    c.color
                }
            }
            None => self.color,
        }
    }

    /// Whether [`Self::albedo`] depends on `uv`: surfaces may skip computing it otherwise.
    #[inline]
    pub fn needs_uv(&self) -> bool {
        self.checker.is_some()
    }

    pub fn is_specular(&self) -> bool {
        self.reflection > 0.0 || self.transmission > 0.0
    }
}

fn whitted_equivalent(
    d: &MaterialDesc,
    all: &BTreeMap<String, MaterialDesc>,
    depth: u32,
) -> WhittedDesc {
    if let Some(w) = d.bsdf_whitted() {
        return w;
    }
    let nested = |name: &str| match all.get(name) {
        Some(m) if depth < 8 => whitted_equivalent(m, all, depth + 1),
        _ => WhittedDesc::default(),
    };
    match d {
        MaterialDesc::Whitted(w) => w.clone(),
        MaterialDesc::TwoSided(t) => nested(&t.front),
        MaterialDesc::Mask(m) => nested(&m.material),
        MaterialDesc::NormalMap(m) => nested(&m.material),
        MaterialDesc::BumpMap(m) => nested(&m.material),
        MaterialDesc::Blend(m) => nested(&m.materials[0]),
        // Every BSDF has its view above.
        _ => WhittedDesc::default(),
    }
}

/// `x.floor() as i64`, without `floor`: x86_64 without SSE4.1 has no rounding instruction, so
/// `floor` is a library call, too slow for a per-hit texture lookup. The conversion truncates
/// towards zero (and saturates, NaN giving 0, as `floor() as i64` does); one step down fixes
/// negative non-integers.
#[inline]
fn floor_i64(x: f32) -> i64 {
    let i = x as i64;
    if (i as f32) > x {
        i.saturating_sub(1)
    } else {
        i
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checker_alternates_between_neighbouring_squares() {
        let d = WhittedDesc {
            color: [1.0, 0.0, 0.0],
            checker: Some(crate::description::CheckerDesc {
                color: [1.0, 1.0, 0.0],
                size: 2.0,
            }),
            ..Default::default()
        };
        let m = Material::new(&d);
        let red = Vec3::new(1.0, 0.0, 0.0);
        let yellow = Vec3::new(1.0, 1.0, 0.0);
        assert_eq!(m.albedo(Vec2::new(0.5, 0.5)), red);
        assert_eq!(m.albedo(Vec2::new(2.5, 0.5)), yellow);
        assert_eq!(m.albedo(Vec2::new(-0.5, 0.5)), yellow);
        assert_eq!(m.albedo(Vec2::new(-0.5, -0.5)), red);
    }

    #[test]
    fn floor_i64_is_floor_then_cast() {
        let specials = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            -1.5,
            2.999_999_8,
            -2.999_999_8,
            8_388_607.5,
            -8_388_607.5,
            1.0e10,
            -1.0e10,
            1.0e30,
            -1.0e30,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        let mut s = 1u32;
        let random = (0..100_000).map(|_| {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            f32::from_bits(s)
        });
        for x in specials.into_iter().chain(random) {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
        }
    }
}
