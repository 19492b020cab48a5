use super::description::MaterialDesc;
use crate::math::{Vec2, Vec3};

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
    pub fn new(d: &MaterialDesc) -> Self {
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
                let cell = (uv / c.size).floor();
                if (cell.x as i64 + cell.y as i64).rem_euclid(2) == 0 {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checker_alternates_between_neighbouring_squares() {
        let d = MaterialDesc {
            color: [1.0, 0.0, 0.0],
            checker: Some(super::super::description::CheckerDesc {
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
}
