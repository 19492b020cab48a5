use super::description::LightDesc;
use crate::math::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Radiant intensity `intensity` (colour times scalar), falling off as `1 / distance^2`.
    Point { position: Vec3, intensity: Vec3 },
    /// Parallel light travelling along the unit vector `direction`, with irradiance `radiance` on a
    /// surface facing it.
    Directional { direction: Vec3, radiance: Vec3 },
}

impl Light {
    pub fn new(d: &LightDesc) -> Self {
        let power = Vec3::from(d.color) * d.intensity;
        match (d.position, d.direction) {
            (Some(p), _) => Light::Point {
                position: p.into(),
                intensity: power,
            },
            (None, Some(dir)) => Light::Directional {
                direction: Vec3::from(dir).normalize(),
                radiance: power,
            },
            (None, None) => unreachable!("validated: a light has a position or a direction"),
        }
    }
}
