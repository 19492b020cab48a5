use crate::description::LightDesc;
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
    /// Whitted's lights: the point and directional ones (spot lights as points with their cone
    /// ignored); environment lights have no Whitted counterpart (`environment.background` is
    /// Whitted's sky).
    pub fn new(d: &LightDesc) -> Option<Self> {
        match d {
            LightDesc::Point {
                position,
                color,
                intensity,
            }
            | LightDesc::Spot {
                position,
                color,
                intensity,
                ..
            } => Some(Light::Point {
                position: (*position).into(),
                intensity: Vec3::from(*color) * *intensity,
            }),
            LightDesc::Directional {
                direction,
                color,
                intensity,
            } => Some(Light::Directional {
                direction: Vec3::from(*direction).normalize(),
                radiance: Vec3::from(*color) * *intensity,
            }),
            // A projector's light varies across its image: no Whitted counterpart.
            LightDesc::Constant { .. } | LightDesc::Envmap { .. } | LightDesc::Projector { .. } => {
                None
            }
        }
    }
}
