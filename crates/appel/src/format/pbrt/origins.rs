//! Where each entry of the converted description was written (see `description::origins`): the
//! directive that made a shape, light, material, object or instance, with its parameters, and
//! the scene-wide directives behind the camera and the render settings.

use super::parser::Directive;
use super::tokenizer::Loc;
use crate::description::origins::{key_path, Origin, Origins};
use crate::error::Location;
use std::collections::HashSet;

/// pbrt parameters filling description keys of another name: `(key, parameter)`.
const RENAMED: &[(&str, &str)] = &[
    ("width", "xresolution"),
    ("height", "yresolution"),
    ("spp", "pixelsamples"),
    ("max_depth", "maxdepth"),
    ("int_ior", "eta"),
    ("color", "I"),
    ("color", "L"),
    ("radiance", "L"),
];

fn location(loc: &Loc) -> Location {
    Location::line(loc.file.as_path(), loc.line, Some(loc.column))
}

/// The place of a directive and of its parameters, each also under the key it fills.
fn origin(d: &Directive) -> Origin {
    let mut parts: Vec<(String, Location)> = d
        .params
        .params
        .iter()
        .map(|p| (p.name.clone(), location(&p.loc)))
        .collect();
    for (key, name) in RENAMED {
        if let Some(at) = parts
            .iter()
            .find(|(p, _)| p == name)
            .map(|(_, at)| at.clone())
        {
            if !parts.iter().any(|(p, _)| p == key) {
                parts.push((key.to_string(), at));
            }
        }
    }
    Origin {
        at: location(&d.loc),
        parts,
    }
}

/// How many entries of each kind the description had before a directive.
pub(super) struct Counts {
    shapes: usize,
    lights: usize,
    instances: usize,
    materials: usize,
    meshes: usize,
}

/// Records the entries a directive added, by comparing with the counts before it.
#[derive(Default)]
pub(super) struct Recorder {
    pub origins: Origins,
    named: HashSet<String>,
}

impl Recorder {
    pub fn counts(c: &super::convert::Converter) -> Counts {
        Counts {
            shapes: c.shapes.len(),
            lights: c.lights.len(),
            instances: c.instances.len(),
            materials: c.materials.len(),
            meshes: c.meshes.len(),
        }
    }

    pub fn record(&mut self, d: &Directive, before: &Counts, c: &super::convert::Converter) {
        let o = || origin(d);
        for i in before.shapes..c.shapes.len() {
            self.origins.record(key_path(&[&"shape", &i]), o());
        }
        for i in before.lights..c.lights.len() {
            self.origins.record(key_path(&[&"light", &i]), o());
        }
        for i in before.instances..c.instances.len() {
            self.origins.record(key_path(&[&"instance", &i]), o());
        }
        if c.materials.len() != before.materials {
            for name in c.materials.keys() {
                if self.named.insert(format!("m {name}")) {
                    self.origins.record(key_path(&[&"materials", name]), o());
                }
            }
        }
        if c.meshes.len() != before.meshes {
            for name in c.meshes.keys() {
                if self.named.insert(format!("o {name}")) {
                    self.origins.record(key_path(&[&"meshes", name]), o());
                }
            }
        }
        let scene_wide: &[&[&str]] = match d.name.as_str() {
            "Camera" => &[&["camera"]],
            "Film" => &[&["camera", "width"], &["camera", "height"]],
            "Integrator" => &[&["render"]],
            "Sampler" => &[
                &["render", "spp"],
                &["render", "sampler"],
                &["render", "seed"],
            ],
            "PixelFilter" => &[&["render", "filter"]],
            _ => &[],
        };
        for path in scene_wide {
            let segments: Vec<&dyn crate::description::origins::AsSegment> = path
                .iter()
                .map(|s| s as &dyn crate::description::origins::AsSegment)
                .collect();
            let mut at = o();
            // The parameter behind a key of its own: `camera.width` is `xresolution`.
            if let [_, key] = path {
                if let Some(p) = at.part(key).cloned() {
                    at = Origin::at(p);
                }
            }
            self.origins.record(key_path(&segments), at);
        }
    }
}
