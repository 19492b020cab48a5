//! A glTF `KHR_lights_punctual` light as a [`LightDesc`], the one mapping the mesh reader and the
//! glTF scene format share (units: see `format::gltf::lights`).

use crate::description::{DirectionalDesc, LightDesc, PointDesc, SpotDesc};
use ::gltf::khr_lights_punctual::{Kind, Light};
use glam::{Mat4, Vec3};

/// Where a light stands and where it shines, and its values, checked; `None` if degenerate (a
/// position so large that a unit step along the axis is lost to rounding has no direction).
pub fn placed_light(light: &Light, world: Mat4) -> Option<LightDesc> {
    let position = world.transform_point3(Vec3::ZERO);
    let axis = world.transform_vector3(-Vec3::Z).normalize_or_zero();
    let (color, intensity) = (light.color(), light.intensity());
    let valid = position.is_finite()
        && axis != Vec3::ZERO
        && position + axis != position
        && intensity.is_finite()
        && intensity >= 0.0
        && color.iter().all(|c| c.is_finite() && *c >= 0.0);
    valid.then(|| light_desc(light.kind(), position, axis, color, intensity))
}

/// The one place a glTF light becomes a [`LightDesc`]. A spot light's cone: full intensity
/// inside `innerConeAngle`, none outside `outerConeAngle` (defaults 0 and pi/4), falling in
/// between linearly in angle (Appel's spot), where the extension suggests a smooth falloff in
/// the cosine: the cone's edges are the same, the transition's profile differs slightly.
fn light_desc(
    kind: Kind,
    position: Vec3,
    axis: Vec3,
    color: [f32; 3],
    intensity: f32,
) -> LightDesc {
    match kind {
        Kind::Directional => LightDesc::Directional(DirectionalDesc {
            direction: axis.into(),
            color,
            intensity,
        }),
        Kind::Point => LightDesc::Point(PointDesc {
            position: position.into(),
            color,
            intensity,
        }),
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => {
            let outer = outer_cone_angle.to_degrees().clamp(0.01, 90.0);
            // Appel's beam width must be positive: an inner cone of 0 is the smallest one.
            let inner = inner_cone_angle.to_degrees().clamp(1e-3, outer);
            LightDesc::Spot(SpotDesc {
                position: position.into(),
                look_at: (position + axis).into(),
                color,
                intensity,
                cutoff_angle: outer,
                beam_width: Some(inner),
                up: None,
                texture: None,
            })
        }
    }
}
