//! Walks pbrt's directives with its graphics state: the current transformation matrix (CTM),
//! material, area light and orientation, saved and restored by `AttributeBegin`/`End`; named
//! coordinate systems; object definitions. Scene-wide options go to `options`, shapes, materials,
//! textures and lights to their modules.
//!
//! pbrt's cameras look down +z with +x to the right of the image and +y up (a left-handed frame
//! when the camera-to-world transform is a rotation, as `LookAt` makes it); Appel's camera is
//! right-handed (right = forward x up). Where the camera's frame is left-handed in world space,
//! pbrt's image is the mirror image of Appel's view, so the whole world is mirrored (x -> -x)
//! on its way into the description: every position, direction and the camera. The image is then
//! pbrt's, and orientations are kept by turning the triangles around (see `shapes`).

use super::materials::Converted;
use super::options::SceneOptions;
use super::origins::Recorder;
use super::parser::{Directive, Parser};
use super::shapes::{Object, Placed};
use super::tokenizer::Loc;
use super::PbrtScene;
use crate::description::{
    Description, InstanceDesc, LightDesc, MaterialDesc, MeshDesc, ShapeDesc, TextureDesc,
};
use crate::error::Result;
use glam::{DMat4, DVec3};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// What `AttributeBegin` saves.
#[derive(Clone, Debug)]
pub(super) struct Attributes {
    pub ctm: DMat4,
    /// `None`: pbrt's default material (diffuse, reflectance 0.5).
    pub material: Option<Converted>,
    pub area_light: Option<AreaLight>,
    pub reverse_orientation: bool,
    /// `MediumInterface`: the media inside and outside the shapes that follow (`None`: vacuum).
    pub medium_inside: Option<String>,
    pub medium_outside: Option<String>,
}

/// An `AreaLightSource "diffuse"` in effect: the radiance of the shapes that follow.
#[derive(Clone, Debug)]
pub(super) struct AreaLight {
    pub radiance: [f32; 3],
    pub loc: Loc,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Scope {
    Attribute,
    Transform,
}

pub(super) struct Converter {
    pub parser: Parser,
    /// Relative file names start here: the first scene file's folder.
    pub base_dir: PathBuf,
    pub attrs: Attributes,
    stack: Vec<(Attributes, Loc, Scope)>,
    named_coords: HashMap<String, DMat4>,
    pub options: SceneOptions,
    /// World to description: identity, or the mirror x -> -x (see the module's comment).
    pub mirror: DMat4,
    in_world: bool,
    pub materials: BTreeMap<String, MaterialDesc>,
    pub named_materials: HashMap<String, Converted>,
    pub float_textures: HashMap<String, TextureDesc>,
    pub spectrum_textures: HashMap<String, TextureDesc>,
    pub shapes: Vec<ShapeDesc>,
    pub lights: Vec<LightDesc>,
    pub objects: HashMap<String, Object>,
    pub meshes: BTreeMap<String, MeshDesc>,
    pub instances: Vec<InstanceDesc>,
    /// The object being defined between `ObjectBegin` and `ObjectEnd`.
    pub object: Option<(String, Vec<Placed>, Loc)>,
    pub warnings: Vec<String>,
    names: usize,
    /// `MakeNamedMedium`s.
    pub media: BTreeMap<String, crate::description::MediumDesc>,
    /// The outside medium when `Camera` was given: the camera's.
    camera_medium: Option<String>,
}

pub fn convert(text: &str, path: &Path) -> Result<PbrtScene> {
    let base_dir = std::path::absolute(path.parent().unwrap_or(Path::new(".")))
        .unwrap_or_else(|_| path.parent().unwrap_or(Path::new(".")).to_path_buf());
    let mut c = Converter {
        parser: Parser::new(text, path),
        base_dir,
        attrs: Attributes {
            ctm: DMat4::IDENTITY,
            material: None,
            area_light: None,
            reverse_orientation: false,
            medium_inside: None,
            medium_outside: None,
        },
        stack: Vec::new(),
        named_coords: HashMap::new(),
        options: SceneOptions::default(),
        mirror: DMat4::IDENTITY,
        in_world: false,
        materials: BTreeMap::new(),
        named_materials: HashMap::new(),
        float_textures: HashMap::new(),
        spectrum_textures: HashMap::new(),
        shapes: Vec::new(),
        lights: Vec::new(),
        objects: HashMap::new(),
        meshes: BTreeMap::new(),
        instances: Vec::new(),
        object: None,
        warnings: Vec::new(),
        names: 0,
        media: BTreeMap::new(),
        camera_medium: None,
    };
    let mut recorder = Recorder::default();
    while let Some(d) = c.parser.directive()? {
        let before = Recorder::counts(&c);
        c.directive(&d)?;
        recorder.record(&d, &before, &c);
        let what = match d.strings.first() {
            Some(s) => format!("{} \"{s}\"", d.name),
            None => d.name.clone(),
        };
        c.warnings.extend(d.params.unused(&what));
    }
    if let Some((_, loc, _)) = c.stack.last() {
        return Err(loc.error("this AttributeBegin has no AttributeEnd"));
    }
    if let Some((name, _, loc)) = &c.object {
        return Err(loc.error(format!("ObjectBegin \"{name}\" has no ObjectEnd")));
    }
    if !c.in_world {
        return Err(c
            .parser
            .end_loc()
            .error("the file has no WorldBegin: a pbrt scene describes its world after it"));
    }
    let (mut camera, mut render) = c.options.finish(&c.mirror)?;
    camera.medium = c.camera_medium.take();
    // pbrt-v4's default integrator, and its volpath, see media; its path does not (nor does
    // Appel's).
    if !c.media.is_empty() && c.options.volumetric() {
        render.integrator = crate::description::IntegratorName::VolPath;
    }
    Ok(PbrtScene {
        description: Description {
            camera,
            render,
            environment: Default::default(),
            materials: std::mem::take(&mut c.materials),
            shapes: std::mem::take(&mut c.shapes),
            lights: std::mem::take(&mut c.lights),
            media: std::mem::take(&mut c.media),
            meshes: std::mem::take(&mut c.meshes),
            instances: std::mem::take(&mut c.instances),
            animation: None,
        },
        warnings: c.warnings,
        origins: recorder.origins,
    })
}

impl Converter {
    /// A fresh name for a material or texture written without one.
    pub fn fresh_name(&mut self, base: &str) -> String {
        loop {
            self.names += 1;
            let name = format!("{base}-{}", self.names);
            if !self.materials.contains_key(&name) {
                return name;
            }
        }
    }

    /// pbrt's world-from-object transform as the description's (mirrored if need be).
    pub fn to_description(&self, ctm: &DMat4) -> DMat4 {
        self.mirror * *ctm
    }

    /// Whether `WorldBegin` has been read.
    pub(super) fn in_world(&self) -> bool {
        self.in_world
    }

    fn world_only(&self, d: &Directive) -> Result<()> {
        if !self.in_world {
            return Err(d.loc.error(format!("{} belongs after WorldBegin", d.name)));
        }
        Ok(())
    }

    fn options_only(&self, d: &Directive) -> Result<()> {
        if self.in_world {
            return Err(d.loc.error(format!(
                "{} is a scene-wide option and belongs before WorldBegin",
                d.name
            )));
        }
        Ok(())
    }

    fn concat(&mut self, m: DMat4) {
        self.attrs.ctm *= m;
    }

    fn directive(&mut self, d: &Directive) -> Result<()> {
        let n = &d.numbers;
        match d.name.as_str() {
            "Identity" => self.attrs.ctm = DMat4::IDENTITY,
            "Translate" => self.concat(DMat4::from_translation(DVec3::new(n[0], n[1], n[2]))),
            "Scale" => self.concat(DMat4::from_scale(DVec3::new(n[0], n[1], n[2]))),
            "Rotate" => {
                let axis = DVec3::new(n[1], n[2], n[3]);
                if axis.length_squared() == 0.0 {
                    return Err(d.loc.error("Rotate about a zero axis"));
                }
                self.concat(DMat4::from_axis_angle(axis.normalize(), n[0].to_radians()));
            }
            "LookAt" => {
                let m = look_at(
                    DVec3::new(n[0], n[1], n[2]),
                    DVec3::new(n[3], n[4], n[5]),
                    DVec3::new(n[6], n[7], n[8]),
                )
                .ok_or_else(|| {
                    d.loc.error(
                        "LookAt: the eye and the target coincide, or the up vector is parallel \
                         to the view direction",
                    )
                })?;
                self.concat(m);
            }
            // pbrt lists the matrix column by column (its parser transposes what it reads).
            "Transform" => self.attrs.ctm = matrix(d)?,
            "ConcatTransform" => {
                let m = matrix(d)?;
                self.concat(m);
            }
            "CoordinateSystem" => {
                self.named_coords
                    .insert(d.strings[0].clone(), self.attrs.ctm);
            }
            "CoordSysTransform" => {
                let name = &d.strings[0];
                self.attrs.ctm = *self.named_coords.get(name).ok_or_else(|| {
                    d.loc.error(format!(
                        "no coordinate system named \"{name}\" has been declared"
                    ))
                })?;
            }
            "TransformTimes" => {}
            "ActiveTransform" => {
                if d.strings[0] != "All" {
                    return Err(d.loc.error(format!(
                        "ActiveTransform {}: motion blur (animated transforms) is not supported",
                        d.strings[0]
                    )));
                }
            }
            "ReverseOrientation" => {
                self.attrs.reverse_orientation = !self.attrs.reverse_orientation
            }
            "AttributeBegin" => self.push(d, Scope::Attribute),
            "AttributeEnd" => self.pop(d, Scope::Attribute)?,
            "TransformBegin" => self.push(d, Scope::Transform),
            "TransformEnd" => self.pop(d, Scope::Transform)?,
            "Option" => {
                for p in &d.params.params {
                    self.warnings.push(format!(
                        "{}: Option \"{}\" is ignored (it does not change Appel's image)",
                        p.loc.describe(),
                        p.name
                    ));
                    d.params.ignore(&p.name);
                }
            }
            "ColorSpace" => {
                if d.strings[0] != "srgb" {
                    return Err(d.loc.error(format!(
                        "ColorSpace \"{}\": Appel renders in linear sRGB only",
                        d.strings[0]
                    )));
                }
            }
            "Camera" => {
                self.options_only(d)?;
                self.options.camera(d, self.attrs.ctm)?;
                let camera_to_world = self.attrs.ctm.inverse();
                if !camera_to_world.is_finite() {
                    return Err(d.loc.error("the camera transform cannot be inverted"));
                }
                self.named_coords
                    .insert("camera".to_string(), camera_to_world);
                self.camera_medium = self.attrs.medium_outside.clone();
            }
            "Film" => {
                self.options_only(d)?;
                self.options.film(d)?;
            }
            "Sampler" => {
                self.options_only(d)?;
                self.options.sampler(d)?;
            }
            "PixelFilter" => {
                self.options_only(d)?;
                self.options.filter(d)?;
            }
            "Integrator" => {
                self.options_only(d)?;
                self.options.integrator(d, &mut self.warnings)?;
            }
            "Accelerator" => {
                self.options_only(d)?;
                // Appel builds its own structure; pbrt's settings for its own do not apply.
                for p in &d.params.params {
                    d.params.ignore(&p.name);
                }
            }
            "WorldBegin" => {
                if self.in_world {
                    return Err(d.loc.error("a second WorldBegin"));
                }
                self.in_world = true;
                self.mirror = self.options.world_mirror();
                self.attrs.ctm = DMat4::IDENTITY;
                self.named_coords
                    .insert("world".to_string(), DMat4::IDENTITY);
            }
            "WorldEnd" => self.world_only(d)?,
            "MakeNamedMedium" => self.named_medium(d)?,
            "MediumInterface" => self.medium_interface(d)?,
            "Attribute" => {
                return Err(d.loc.error(
                    "Attribute (default parameters for a kind of directive) is not supported",
                ))
            }
            "Texture" => {
                self.world_only(d)?;
                self.texture(d)?;
            }
            "Material" => {
                self.world_only(d)?;
                let name = self.fresh_name(&d.strings[0]);
                let m = self.material(&d.strings[0], &d.params, &d.loc, &name)?;
                self.attrs.material = Some(m);
            }
            "MakeNamedMaterial" => {
                self.world_only(d)?;
                self.make_named_material(d)?;
            }
            "NamedMaterial" => {
                self.world_only(d)?;
                let name = &d.strings[0];
                let m = self.named_materials.get(name).ok_or_else(|| {
                    d.loc
                        .error(format!("no material named \"{name}\" has been made"))
                })?;
                self.attrs.material = Some(m.clone());
            }
            "LightSource" => {
                self.world_only(d)?;
                self.light(d)?;
            }
            "AreaLightSource" => {
                self.world_only(d)?;
                self.area_light(d)?;
            }
            "Shape" => {
                self.world_only(d)?;
                self.shape(d)?;
            }
            "ObjectBegin" => {
                self.world_only(d)?;
                if let Some((name, _, _)) = &self.object {
                    return Err(d.loc.error(format!(
                        "ObjectBegin inside the definition of \"{name}\": objects do not nest"
                    )));
                }
                // pbrt-v4's ObjectBegin also begins an attribute scope.
                self.push(d, Scope::Attribute);
                self.object = Some((d.strings[0].clone(), Vec::new(), d.loc.clone()));
            }
            "ObjectEnd" => {
                let Some((name, shapes, _)) = self.object.take() else {
                    return Err(d.loc.error("ObjectEnd without ObjectBegin"));
                };
                if self.objects.contains_key(&name) {
                    return Err(d.loc.error(format!("object \"{name}\" is defined twice")));
                }
                self.pop(d, Scope::Attribute)?;
                self.define_object(&name, shapes)?;
            }
            "ObjectInstance" => {
                self.world_only(d)?;
                self.object_instance(d)?;
            }
            // `Include` and `Import` are followed by the parser.
            other => {
                return Err(d
                    .loc
                    .error(format!("the directive {other} is not supported")))
            }
        }
        Ok(())
    }

    fn push(&mut self, d: &Directive, scope: Scope) {
        self.stack.push((self.attrs.clone(), d.loc.clone(), scope));
    }

    fn pop(&mut self, d: &Directive, scope: Scope) -> Result<()> {
        match self.stack.pop() {
            Some((saved, _, s)) if s == scope => {
                if scope == Scope::Attribute {
                    self.attrs = saved;
                } else {
                    self.attrs.ctm = saved.ctm;
                }
                Ok(())
            }
            Some((_, loc, _)) => Err(d.loc.error(format!(
                "{} does not match the scope opened at {}",
                d.name,
                loc.describe()
            ))),
            None => Err(d.loc.error(format!("{} without a matching begin", d.name))),
        }
    }
}

/// pbrt's `LookAt`: the camera-from-world transform of an eye at `eye` looking at `target`.
fn look_at(eye: DVec3, target: DVec3, up: DVec3) -> Option<DMat4> {
    let dir = (target - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        eye.extend(1.0),
    );
    Some(world_from_camera.inverse())
}

fn matrix(d: &Directive) -> Result<DMat4> {
    let cols: [f64; 16] = d
        .numbers
        .as_slice()
        .try_into()
        .expect("16 numbers, checked");
    let m = DMat4::from_cols_array(&cols);
    if m.determinant() == 0.0 || !m.is_finite() {
        return Err(d
            .loc
            .error(format!("{}: the matrix cannot be inverted", d.name)));
    }
    Ok(m)
}
