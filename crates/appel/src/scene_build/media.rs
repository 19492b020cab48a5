//! The scene's media from `[media.NAME]`, the interfaces of the surfaces that name them, and the
//! camera's medium.

use crate::description::Description;
use crate::error::Result;
use crate::scene::{Geometry, MediumInterface, SceneMedia, NO_MEDIUM};
use crate::shading::medium::build_medium;
use std::path::Path;

pub fn build(d: &Description, geometry: &Geometry, base_dir: &Path) -> Result<SceneMedia> {
    let names: Vec<&String> = d.media.keys().collect();
    let media = d
        .media
        .iter()
        .map(|(name, m)| build_medium(name, m, base_dir))
        .collect::<Result<Vec<_>>>()?;
    // Validation has checked every name.
    let index = |name: Option<&str>| {
        name.and_then(|n| names.iter().position(|k| k.as_str() == n))
            .map_or(NO_MEDIUM, |i| i as u32)
    };
    let mut of_shape = vec![MediumInterface::NONE; geometry.shapes.len()];
    if !media.is_empty() {
        for (i, surface) in geometry.shapes.iter().enumerate() {
            let Some(s) = d.shapes.get(surface.source.shape as usize) else {
                continue;
            };
            let (interior, exterior) = s.media();
            of_shape[i] = MediumInterface {
                interior: index(interior),
                exterior: index(exterior),
            };
        }
    }
    Ok(SceneMedia {
        media,
        of_shape,
        camera: index(d.camera.medium.as_deref()),
    })
}
