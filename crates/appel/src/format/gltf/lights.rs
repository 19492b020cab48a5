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
use crate::description::LightDesc;
use crate::io::gltf_lights::placed_light;
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
