//! From a Mitsuba [`Document`] to Appel's [`Description`]: the integrator, sensor, film and
//! sampler here; materials and textures in `bsdf`, shapes and instancing in `shape`, emitters in
//! `emitter`. Every parameter is read with Mitsuba's default, and anything Appel cannot represent
//! is an error at its line, never dropped.

mod bsdf;
mod emitter;
mod medium;
mod origin;
mod shape;

#[cfg(test)]
mod tests;

use super::document::{Document, Object, Target};
use super::transform::to_rows;
use crate::description::origins::{key_path, Origin, Origins};
use crate::description::{
    AovParams, CameraDesc, CameraKind, Description, FilterDesc, FovAxis, IntegratorName,
    MaterialDesc, RenderDesc, SamplerName,
};
use crate::error::Result;
use glam::{DMat4, DVec3};
use origin::origin_of;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// The scene description a document stands for. File names in it are absolute.
pub fn convert(doc: &Document) -> Result<Description> {
    Ok(convert_with_origins(doc)?.0)
}

/// [`convert`], with where each entry of the description was written.
pub fn convert_with_origins(doc: &Document) -> Result<(Description, Origins)> {
    let mut c = Converter {
        doc,
        materials: BTreeMap::new(),
        material_of: HashMap::new(),
        groups: HashMap::new(),
        shapes: Vec::new(),
        lights: Vec::new(),
        meshes: BTreeMap::new(),
        instances: Vec::new(),
        origins: Origins::default(),
        media: BTreeMap::new(),
        medium_of: HashMap::new(),
    };
    let description = c.scene()?;
    Ok((description, c.origins))
}

struct Converter<'d> {
    doc: &'d Document,
    materials: BTreeMap<String, MaterialDesc>,
    /// The material name given to each BSDF object, so that a shared one is converted once.
    material_of: HashMap<*const Object, String>,
    /// Shapegroups converted so far: their meshes' names and their other shapes.
    groups: HashMap<*const Object, shape::Group>,
    shapes: Vec<crate::description::ShapeDesc>,
    lights: Vec<crate::description::LightDesc>,
    meshes: BTreeMap<String, crate::description::MeshDesc>,
    instances: Vec<crate::description::InstanceDesc>,
    origins: Origins,
    media: BTreeMap<String, crate::description::MediumDesc>,
    /// The medium name given to each `<medium>` object, so that a shared one is converted once.
    medium_of: HashMap<*const Object, String>,
}

impl Converter<'_> {
    fn scene(&mut self) -> Result<Description> {
        let doc = self.doc;
        let root = doc.root.clone();
        let mut integrator: Option<Rc<Object>> = None;
        let mut sensor: Option<Rc<Object>> = None;
        for child in root.children.iter() {
            root.take(child);
            let o = doc.target(child)?;
            // A reference at the top level adds nothing: the object is where it is declared.
            if matches!(child.target, Target::Ref(_)) {
                continue;
            }
            match o.class.as_str() {
                "integrator" if integrator.is_some() => {
                    return Err(o.error("a scene has one <integrator>"))
                }
                "integrator" => integrator = Some(o),
                "sensor" if sensor.is_some() => {
                    return Err(o.error("Appel renders one <sensor> per scene"))
                }
                "sensor" => sensor = Some(o),
                "shape" => self.shape(&o)?,
                "emitter" => self.light(&o)?,
                // Declared for reference by id; converted now so that errors surface even if
                // nothing uses them, as Mitsuba instantiates every object.
                "bsdf" => {
                    self.material(&o)?;
                }
                "texture" => {
                    bsdf::texture_node(self, &o)?;
                }
                "medium" => {
                    self.medium(&o)?;
                }
                _ => return Err(o.error("not supported in a scene")),
            }
        }
        root.finish()?;
        let sensor = sensor.ok_or_else(|| root.error("the scene has no <sensor>"))?;
        let render_origin = origin_of(integrator.as_deref().unwrap_or(&root));
        self.origins.record(key_path(&[&"render"]), render_origin);
        let mut render = match &integrator {
            Some(i) => integrator_desc(i)?,
            // Mitsuba renders a scene without an integrator with its default path tracer.
            None => RenderDesc {
                integrator: IntegratorName::Path,
                max_depth: -1,
                ..RenderDesc::default()
            },
        };
        let camera = self.sensor(&sensor, &mut render)?;
        let mut materials = std::mem::take(&mut self.materials);
        if self
            .shapes
            .iter()
            .any(|s| s.material() == Some(DEFAULT_MATERIAL))
            || self
                .meshes
                .values()
                .any(|m| m.material.as_deref() == Some(DEFAULT_MATERIAL))
        {
            materials.insert(DEFAULT_MATERIAL.into(), bsdf::mitsuba_default());
        }
        if self
            .shapes
            .iter()
            .any(|s| s.material() == Some(DEFAULT_EMITTER_MATERIAL))
        {
            materials.insert(
                DEFAULT_EMITTER_MATERIAL.into(),
                crate::description::MaterialDesc::Diffuse(crate::description::DiffuseDesc {
                    reflectance: crate::description::TextureDesc::Value(0.0),
                }),
            );
        }
        Ok(Description {
            camera,
            render,
            environment: Default::default(),
            materials,
            shapes: std::mem::take(&mut self.shapes),
            lights: std::mem::take(&mut self.lights),
            media: std::mem::take(&mut self.media),
            meshes: std::mem::take(&mut self.meshes),
            instances: std::mem::take(&mut self.instances),
            animation: None,
        })
    }

    /// A resolved file name, absolute.
    fn file(&self, o: &Object, name: &str) -> Result<String> {
        let value = o
            .string(name)?
            .ok_or_else(|| o.error(format!("needs a <string name=\"{name}\">")))?;
        let found = self.doc.resolver.resolve(value).ok_or_else(|| {
            let p = o.prop(name).expect("just read");
            p.error(format!("file \"{value}\" not found"))
        })?;
        Ok(absolute(&found).to_string_lossy().into_owned())
    }

    /// The aperture and plane in focus of a `thinlens` sensor, as Mitsuba's `thinlens` reads
    /// them: `aperture_radius` required, `focus_distance` defaulting to `far_clip`, and no scale
    /// in `to_world` (whose `axes` are the transform's columns), which would make the aperture's
    /// size ambiguous.
    fn thin_lens(
        &self,
        s: &Object,
        camera: &mut CameraDesc,
        far_clip: f64,
        axes: [DVec3; 3],
    ) -> Result<()> {
        let radius = s
            .float("aperture_radius")?
            .ok_or_else(|| s.error("a thinlens sensor needs <float name=\"aperture_radius\">"))?;
        if !(radius >= 0.0 && radius.is_finite()) {
            let p = s.prop("aperture_radius").expect("read above");
            return Err(p.error(format!(
                "aperture_radius must be 0 (a pinhole) or a positive number of scene units, got \
                 {radius}"
            )));
        }
        let focus = s.float_or("focus_distance", far_clip)?;
        if !(focus > 0.0 && focus.is_finite()) {
            let at = s.prop("focus_distance").or(s.prop("far_clip"));
            let message = format!("focus_distance must be a positive distance, got {focus}");
            return Err(at.map_or_else(|| s.error(&message), |p| p.error(&message)));
        }
        if axes.iter().any(|a| (a.length() - 1.0).abs() > 1e-3) {
            let p = s.prop("to_world").expect("a scale needs a transform");
            return Err(p.error(
                "a thinlens camera's transform must not scale (as in Mitsuba): the aperture and \
                 focus distance are in scene units",
            ));
        }
        camera.aperture_radius = radius as f32;
        camera.focus_distance = Some(focus as f32);
        Ok(())
    }

    /// The camera of a `<sensor>`, with its film and sampler written into `render`.
    fn sensor(&mut self, s: &Object, render: &mut RenderDesc) -> Result<CameraDesc> {
        let kind = match s.plugin.as_str() {
            // A thin lens is a perspective camera with an aperture.
            "perspective" | "thinlens" => CameraKind::Perspective,
            "orthographic" => CameraKind::Orthographic,
            p => {
                return Err(s.error(format!(
                    "unsupported sensor plugin \"{p}\" (supported: perspective, thinlens, \
                     orthographic)"
                )))
            }
        };
        let to_world = s.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
        let (origin, x, y, z) = columns(&to_world);
        if x.dot(y.cross(z)) <= 0.0 {
            let p = s
                .prop("to_world")
                .expect("a degenerate identity is impossible");
            return Err(p.error(
                "the camera transform mirrors or flattens the view, which Appel's camera cannot do",
            ));
        }
        let mut camera = CameraDesc {
            kind,
            eye: f32s(origin),
            look_at: f32s(origin + z.normalize()),
            up: f32s(y.normalize()),
            ..CameraDesc::default()
        };
        camera.near_clip = s.float_or("near_clip", 0.01)? as f32;
        let far_clip = s.float_or("far_clip", 1e4)?;
        if s.plugin == "thinlens" {
            self.thin_lens(s, &mut camera, far_clip, [x, y, z])?;
        } else {
            // Every projective sensor of Mitsuba reads it; only the thin lens uses it.
            s.float("focus_distance")?;
        }
        match kind {
            CameraKind::Perspective => {
                let (fov, axis) = match s.float("fov")? {
                    Some(f) => (f, s.string("fov_axis")?.unwrap_or("x")),
                    None => {
                        // Mitsuba's default: a 50 mm lens on 36 x 24 mm film, whose field of view
                        // spans the film's diagonal.
                        if s.prop("focal_length").is_some() {
                            let p = s.prop("focal_length").expect("present");
                            return Err(p.error("give the field of view as <float name=\"fov\">"));
                        }
                        let diagonal = 36.0f64.hypot(24.0);
                        (2.0 * (diagonal / 100.0).atan().to_degrees(), "diagonal")
                    }
                };
                if !(fov > 0.0 && fov < 180.0) {
                    let p = s.prop("fov").expect("read above");
                    return Err(
                        p.error(format!("the field of view must be in (0, 180), got {fov}"))
                    );
                }
                camera.fov = fov as f32;
                camera.fov_axis = fov_axis(axis).ok_or_else(|| {
                    s.prop("fov_axis").expect("read above").error(format!(
                        "unknown fov_axis \"{axis}\" (x, y, diagonal, smaller or larger)"
                    ))
                })?;
            }
            // Mitsuba's orthographic camera sees [-1, 1] across x in its own space; to_world
            // scales that.
            CameraKind::Orthographic => camera.half_width = Some(x.length() as f32),
        }
        camera.medium = self.sensor_medium(s)?;
        let mut film = None;
        let mut sampler = None;
        for child in s.unnamed_children() {
            let o = self.doc.target(child)?;
            let slot = match o.class.as_str() {
                "film" => &mut film,
                "sampler" => &mut sampler,
                _ => continue,
            };
            if slot.is_some() {
                return Err(o.error(format!("a sensor has one <{}>", o.class)));
            }
            s.take(child);
            *slot = Some(o);
        }
        let mut camera_origin = origin_of(s);
        if let Some(f) = &film {
            // The film's width and height are the camera's; its filter is the render's.
            camera_origin.parts.extend(origin_of(f).parts);
            self.origins
                .record(key_path(&[&"render", &"filter"]), origin_of(f));
        }
        self.origins.record(key_path(&[&"camera"]), camera_origin);
        if let Some(smp) = &sampler {
            let o = origin_of(smp);
            for key in ["spp", "seed"] {
                if let Some(at) = o.part(key) {
                    let at = Origin::at(at.clone());
                    self.origins.record(key_path(&[&"render", &key]), at);
                }
            }
            self.origins.record(key_path(&[&"render", &"sampler"]), o);
        }
        let (width, height) = match &film {
            Some(f) => film_desc(f, render)?,
            None => (768, 576),
        };
        camera.width = width;
        camera.height = height;
        match &sampler {
            Some(smp) => sampler_desc(smp, render)?,
            None => render.spp = 4,
        }
        s.finish()?;
        Ok(camera)
    }
}

/// The name of Mitsuba's BSDF for shapes that have none.
const DEFAULT_MATERIAL: &str = "mitsuba_default_diffuse";

/// The name of Mitsuba's BSDF for emitting shapes that have none: a black diffuse.
const DEFAULT_EMITTER_MATERIAL: &str = "mitsuba_default_emitter";

fn integrator_desc(i: &Object) -> Result<RenderDesc> {
    let mut r = RenderDesc::default();
    match i.plugin.as_str() {
        // An AOV integrator around the real one: the image is the nested integrator's.
        "moment" => {
            let mut nested = i.unnamed_children();
            let (Some(child), None) = (nested.next(), nested.next()) else {
                return Err(i.error("expected exactly one nested <integrator>"));
            };
            i.take(child);
            let Target::Object(inner) = &child.target else {
                return Err(child
                    .loc
                    .error("nest the <integrator> rather than referencing it"));
            };
            i.finish()?;
            return integrator_desc(inner);
        }
        // Named outputs of the surface each pixel sees, around an optional nested integrator
        // whose image the film holds.
        "aov" => return aov_integrator_desc(i),
        "path" => {
            r.integrator = IntegratorName::Path;
            r.max_depth = i.int_in("max_depth", -1..=i32::MAX as i64)?.unwrap_or(-1) as i32;
            r.rr_depth = i.int_in("rr_depth", 1..=u32::MAX as i64)?.unwrap_or(5) as u32;
        }
        // Appel's own: Mitsuba 3 has no bidirectional path tracer; its keys are `path`'s, and
        // `strategy_images` (`unweighted` or `weighted`) and `regularize` as in `[render.bdpt]`.
        "bdpt" => {
            r.integrator = IntegratorName::Bdpt;
            r.max_depth = i.int_in("max_depth", -1..=i32::MAX as i64)?.unwrap_or(-1) as i32;
            r.rr_depth = i.int_in("rr_depth", 1..=u32::MAX as i64)?.unwrap_or(5) as u32;
            let strategy_images = match i.string("strategy_images")? {
                None => None,
                Some("unweighted") => Some(crate::description::StrategyImages::Unweighted),
                Some("weighted") => Some(crate::description::StrategyImages::Weighted),
                Some(other) => {
                    return Err(i.error(format!(
                        "strategy_images must be \"unweighted\" or \"weighted\", got \"{other}\""
                    )))
                }
            };
            r.bdpt = Some(crate::description::BdptParams {
                strategy_images,
                regularize: i.bool_or("regularize", false)?,
            });
        }
        // Appel's own, as `bdpt`: `path`'s keys and pbrt-v4's `sppm` parameters.
        "sppm" => {
            r.integrator = IntegratorName::Sppm;
            r.max_depth = i.int_in("max_depth", -1..=i32::MAX as i64)?.unwrap_or(-1) as i32;
            r.rr_depth = i.int_in("rr_depth", 1..=u32::MAX as i64)?.unwrap_or(5) as u32;
            let radius = i.float("radius")?.unwrap_or(1.0);
            if !(radius > 0.0 && radius.is_finite()) {
                return Err(i.error(format!("radius must be positive, got {radius}")));
            }
            let photons = i.int_in("photons_per_iteration", 0..=u32::MAX as i64)?;
            r.sppm = Some(crate::description::SppmParams {
                radius: radius as f32,
                photons_per_iteration: photons.unwrap_or(0) as u32,
            });
        }
        "ptracer" => {
            r.integrator = IntegratorName::Ptracer;
            r.max_depth = i.int_in("max_depth", -1..=i32::MAX as i64)?.unwrap_or(-1) as i32;
            r.rr_depth = i.int_in("rr_depth", 1..=u32::MAX as i64)?.unwrap_or(5) as u32;
            // Mitsuba's -1 (the default): everything in one pass.
            let per_pass = i.int_in("samples_per_pass", -1..=u32::MAX as i64)?;
            r.ptracer = Some(crate::description::PtracerParams {
                samples_per_pass: per_pass.map_or(0, |n| n.max(0) as u32),
            });
        }
        "volpath" => {
            r.integrator = IntegratorName::VolPath;
            r.max_depth = i.int_in("max_depth", -1..=i32::MAX as i64)?.unwrap_or(-1) as i32;
            r.rr_depth = i.int_in("rr_depth", 1..=u32::MAX as i64)?.unwrap_or(5) as u32;
        }
        "volpathmis" => {
            return Err(i.error(
                "Appel has no volpathmis: its volpath samples distances with one RGB channel \
                 chosen per path, and the spectral MIS over the channels (Miller et al. 2019) \
                 that volpathmis adds is not implemented; use volpath",
            ))
        }
        "direct" => {
            r.integrator = IntegratorName::Direct;
            // Emitters seen directly, and direct light: Mitsuba's depth 2.
            r.max_depth = 2;
        }
        p => {
            return Err(i.error(format!(
                "unsupported integrator plugin \"{p}\" (supported: path, volpath, ptracer, bdpt, \
                 direct, aov, moment)"
            )))
        }
    }
    r.hide_emitters = i.bool_or("hide_emitters", false)?;
    i.finish()?;
    Ok(r)
}

/// Mitsuba's `aov`: its `aovs` list, and at most one nested integrator, which renders the image
/// and gives `[render]` its settings. Mitsuba names an unnamed nested object `_arg_N` (N counting
/// the element's unnamed children), and its image's channels after that name.
fn aov_integrator_desc(i: &Object) -> Result<RenderDesc> {
    let Some(aovs) = i.string("aovs")? else {
        return Err(
            i.error("the aov integrator needs <string name=\"aovs\" value=\"NAME:TYPE,...\"/>")
        );
    };
    let mut params = AovParams {
        aovs: aovs.to_string(),
        ..AovParams::default()
    };
    let prop = i.prop("aovs").expect("read above");
    params.channels().map_err(|e| prop.error(e))?;
    let mut nested = i.children.iter();
    let mut r = match (nested.next(), nested.next()) {
        (None, _) => RenderDesc {
            hide_emitters: i.bool_or("hide_emitters", false)?,
            ..RenderDesc::default()
        },
        (Some(child), None) => {
            i.take(child);
            let Target::Object(inner) = &child.target else {
                return Err(child
                    .loc
                    .error("nest the <integrator> rather than referencing it"));
            };
            if inner.class != "integrator" {
                return Err(child.loc.error(format!(
                    "the aov integrator nests integrators, not a <{}>",
                    inner.class
                )));
            }
            let r = integrator_desc(inner)?;
            if r.integrator == IntegratorName::Aov {
                return Err(child
                    .loc
                    .error("the nested integrator must compute an image, not be another aov"));
            }
            params.integrator = Some(r.integrator);
            params.image = Some(child.name.clone().unwrap_or_else(|| "_arg_0".into()));
            params.channels().map_err(|e| prop.error(e))?;
            r
        }
        (Some(_), Some(second)) => {
            return Err(second
                .loc
                .error("Appel's aov integrator takes one nested integrator"))
        }
    };
    i.finish()?;
    r.integrator = IntegratorName::Aov;
    r.aov = Some(params);
    Ok(r)
}

fn film_desc(f: &Object, render: &mut RenderDesc) -> Result<(u32, u32)> {
    if f.plugin != "hdrfilm" {
        return Err(f.error(format!(
            "unsupported film plugin \"{}\" (supported: hdrfilm)",
            f.plugin
        )));
    }
    let width = f.int_in("width", 1..=65536)?.unwrap_or(768) as u32;
    let height = f.int_in("height", 1..=65536)?.unwrap_or(576) as u32;
    // Mitsuba's film reconstructs with a Gaussian unless an <rfilter> says otherwise.
    render.filter = FilterDesc::Gaussian { stddev: 0.5 };
    // How Mitsuba would store the image: Appel's output file decides that.
    for ignored in ["pixel_format", "component_format", "file_format"] {
        f.string(ignored)?;
    }
    for child in f.unnamed_children() {
        let r = f_target(f, child)?;
        if r.class != "rfilter" {
            continue;
        }
        f.take(child);
        render.filter = match r.plugin.as_str() {
            "box" => FilterDesc::Box { radius: 0.5 },
            "tent" => FilterDesc::Tent {
                radius: r.float_or("radius", 1.0)? as f32,
            },
            "gaussian" => FilterDesc::Gaussian {
                stddev: r.float_or("stddev", 0.5)? as f32,
            },
            p => {
                return Err(r.error(format!(
                    "unsupported rfilter plugin \"{p}\" (supported: box, tent, gaussian)"
                )))
            }
        };
        r.finish()?;
    }
    f.finish()?;
    Ok((width, height))
}

/// A film's child: filters are always written in place.
fn f_target(f: &Object, child: &super::document::Child) -> Result<Rc<Object>> {
    match &child.target {
        Target::Object(o) => Ok(o.clone()),
        Target::Ref(_) => Err(f.error("nest the <rfilter> rather than referencing it")),
    }
}

fn sampler_desc(s: &Object, render: &mut RenderDesc) -> Result<()> {
    render.sampler = Some(match s.plugin.as_str() {
        "independent" => SamplerName::Independent,
        // Appel's one low-discrepancy sampler stands for Mitsuba's stratified ones.
        "stratified" | "multijitter" | "ldsampler" => SamplerName::Sobol,
        p => {
            return Err(s.error(format!(
                "unsupported sampler plugin \"{p}\" (supported: independent, stratified, \
                 multijitter, ldsampler)"
            )))
        }
    });
    render.spp = s.int_in("sample_count", 1..=65536)?.unwrap_or(4) as u32;
    render.seed = s.int_in("seed", 0..=i64::MAX)?.unwrap_or(0) as u64;
    s.finish()
}

/// Origin and the three axis columns of an affine map.
/// Mitsuba's `fov_axis` names.
fn fov_axis(name: &str) -> Option<FovAxis> {
    Some(match name {
        "x" => FovAxis::X,
        "y" => FovAxis::Y,
        "diagonal" => FovAxis::Diagonal,
        "smaller" => FovAxis::Smaller,
        "larger" => FovAxis::Larger,
        _ => return None,
    })
}

fn columns(m: &DMat4) -> (DVec3, DVec3, DVec3, DVec3) {
    (
        m.w_axis.truncate(),
        m.x_axis.truncate(),
        m.y_axis.truncate(),
        m.z_axis.truncate(),
    )
}

fn f32s(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

fn rows_f32(m: &DMat4) -> [[f32; 4]; 4] {
    to_rows(m).map(|r| r.map(|x| x as f32))
}

fn absolute(p: &Path) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}
