//! The file's `KHR_lights_punctual` lights, placed by their nodes: point, spot and directional
//! lights shining along the node's -z (the extension's section "Adding Light Instances to
//! Nodes").
//!
//! Units: the extension gives point and spot lights in candela and directional lights in lux.
//! They are read as Appel's radiometric units as they stand, candela as W/sr and lux as W/m^2,
//! which is what the Khronos glTF Sample Viewer does (its shaders use `intensity` as radiance
//! scale with an exposure of 1, so the sample scenes are authored to look right that way) and
//! what the mesh reader does for bare glTF models. The photometric conversion (683 lm/W at 555
//! nm) would only divide every image by 683: Appel's images have no exposure to make up for it.

use super::nodes::Placed;
use crate::description::{DirectionalDesc, LightDesc, PointDesc, SpotDesc};
use ::gltf::khr_lights_punctual::{Kind, Light};
use glam::{Mat4, Vec3};
use std::path::Path;

/// Each light node's light in world space. A light whose node's transform, colour or intensity
/// is degenerate is left out with a warning; `range` is ignored with one (Appel's point lights
/// fall off with the inverse square alone, as the extension's range-less lights do).
pub fn lights(placed: &[Placed], path: &Path, warnings: &mut Vec<String>) -> Vec<LightDesc> {
    let mut out = vec![];
    for p in placed {
        let Some(light) = p.node.light() else {
            continue;
        };
        let what = format!("{}: light {}", path.display(), light.index());
        if let Some(range) = light.range() {
            warnings.push(format!(
                "{what}: `range` ({range}) is ignored; the light falls off with the inverse square of the distance everywhere"
            ));
        }
        match placed_light(&light, p.world) {
            Some(l) => out.push(l),
            None => warnings.push(format!(
                "{what}: its node's transform, its colour or its intensity is degenerate; it is left out"
            )),
        }
    }
    out
}

/// Where a light stands and where it shines, and its values, checked; `None` if degenerate (a
/// position so large that a unit step along the axis is lost to rounding has no direction).
fn placed_light(light: &Light, world: Mat4) -> Option<LightDesc> {
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
