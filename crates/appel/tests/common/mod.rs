//! Helpers shared by the integration tests.
#![allow(dead_code)]

use appel::description::parse::Syntax;
use appel::description::{description_from_str, Description};
use appel::render::{render, Film, RenderOptions, RenderStats};
use appel::scene::builtin::builtin_scene;
use appel::scene::Scene;
use std::path::Path;

pub fn builtin(name: &str) -> Description {
    description_from_str(builtin_scene(name).unwrap(), Syntax::Toml, Path::new(name)).unwrap()
}

pub fn render_description(d: &Description) -> (Film, RenderStats, Scene) {
    let scene = Scene::new(d, Path::new(".")).unwrap();
    let (film, stats) = render(&scene, &RenderOptions::default()).unwrap();
    (film, stats, scene)
}

pub fn with_size(mut d: Description, w: u32, h: u32) -> Description {
    d.camera.width = w;
    d.camera.height = h;
    d
}

pub fn luminance(c: glam::Vec3) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}
