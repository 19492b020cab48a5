//! Shapes to `[[shape]]`; `shapegroup` and `instance` to `[meshes.NAME]` and `[[instance]]`.
//! A shapegroup's meshes become declared meshes placed by each instance; its other shapes
//! (spheres, rectangles...) cannot be declared meshes, so each instance adds them as shapes with
//! the composed transform: the same image, but they count as shapes, not instances, in AOVs.

use super::super::document::{Object, Target};
use super::origin::origin_of;
use super::{columns, rows_f32, Converter, DEFAULT_EMITTER_MATERIAL, DEFAULT_MATERIAL};
use crate::description::origins::key_path;
use crate::description::{
    BasicShapeDesc, CylinderDesc, InstanceDesc, MeshDesc, MeshShapeDesc, SdfGridDesc,
    SdfNormalsDesc, ShapeDesc, SphereDesc, TransformDesc,
};
use crate::error::Result;
use glam::{DMat4, DVec3};
use std::rc::Rc;

const SHAPES: &str =
    "obj, ply, serialized, sphere, rectangle, cube, disk, cylinder, sdfgrid, shapegroup, instance";

/// A converted shapegroup.
#[derive(Clone, Default)]
pub(super) struct Group {
    /// Declared meshes and where the group places them.
    meshes: Vec<(String, DMat4)>,
    /// Shapes added again by every instance.
    others: Vec<Rc<Object>>,
}

impl Converter<'_> {
    pub(super) fn shape(&mut self, s: &Rc<Object>) -> Result<()> {
        match s.plugin.as_str() {
            "shapegroup" => {
                self.group(s)?;
            }
            "instance" => self.instance(s)?,
            _ => {
                let desc = self.shape_desc(s, DMat4::IDENTITY)?;
                self.push_shape(desc, s)?;
            }
        }
        Ok(())
    }

    /// Adds a converted shape, recording where it and its area emitter were written.
    fn push_shape(&mut self, desc: ShapeDesc, s: &Object) -> Result<()> {
        let index = self.shapes.len();
        self.origins
            .record(key_path(&[&"shape", &index]), origin_of(s));
        for child in s.unnamed_children() {
            let o = self.doc.target(child)?;
            if o.class == "emitter" {
                let path = key_path(&[&"shape", &index, &"emitter"]);
                self.origins.record(path, origin_of(&o));
            }
        }
        self.shapes.push(desc);
        Ok(())
    }

    /// A shape that is not a group or an instance, placed by `parent` after its own `to_world`.
    fn shape_desc(&mut self, s: &Object, parent: DMat4) -> Result<ShapeDesc> {
        let to_world = parent * s.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
        let placed = |m: DMat4| {
            (m != DMat4::IDENTITY).then(|| TransformDesc {
                matrix: Some(rows_f32(&m)),
                ..TransformDesc::default()
            })
        };
        let (material, emitter) = self.shape_children(s)?;
        let (interior, exterior) = self.shape_media(s)?;
        let material = Some(material);
        let emitter = match emitter {
            Some(e) => Some(self.area_emitter(&e)?),
            None => None,
        };
        // Read only for the kinds that have it, so that it is an unsupported property elsewhere.
        let flip_normals =
            |s: &Object| -> Result<bool> { Ok(s.bool("flip_normals")?.unwrap_or(false)) };
        let d = match s.plugin.as_str() {
            "obj" | "ply" | "serialized" => {
                let face_normals = s.bool("face_normals")?.unwrap_or(false);
                ShapeDesc::Mesh(MeshShapeDesc {
                    interior: interior.clone(),
                    exterior: exterior.clone(),
                    file: self.mesh_file(s)?,
                    transform: placed(to_world),
                    face_normals,
                    // Mitsuba's `obj` and `ply` compute the vertex normals a file lacks, unless
                    // `face_normals` (`serialized` meshes get theirs when they are read).
                    smooth_normals: !face_normals,
                    flip_normals: flip_normals(s)?,
                    material,
                    emitter,
                    keyframes: Vec::new(),
                })
            }
            "sphere" => {
                let center = DVec3::from(s.vector("center")?.unwrap_or([0.0; 3]));
                let radius = s.float_or("radius", 1.0)?;
                let scale = similarity_scale(&to_world).ok_or_else(|| {
                    s.error("a sphere's to_world may only rotate, translate and scale uniformly")
                })?;
                // The sphere's own frame orients Mitsuba's parameterisation.
                let (_, x, y, z) = columns(&to_world);
                let axis = |v: DVec3| super::f32s(v / scale);
                ShapeDesc::Sphere(SphereDesc {
                    interior: interior.clone(),
                    exterior: exterior.clone(),
                    center: super::f32s(to_world.transform_point3(center)),
                    radius: (radius * scale) as f32,
                    mitsuba_uv: Some([axis(x), axis(y), axis(z)]),
                    material,
                    emitter,
                })
            }
            "rectangle" | "cube" | "disk" => {
                let b = BasicShapeDesc {
                    interior: interior.clone(),
                    exterior: exterior.clone(),
                    transform: placed(to_world),
                    flip_normals: flip_normals(s)?,
                    material,
                    emitter,
                    keyframes: Vec::new(),
                };
                match s.plugin.as_str() {
                    "rectangle" => ShapeDesc::Rectangle(b),
                    "cube" => ShapeDesc::Cube(b),
                    _ => ShapeDesc::Disk(b),
                }
            }
            "sdfgrid" => {
                if emitter.is_some() {
                    return Err(s.error("an sdfgrid cannot emit (as in Mitsuba)"));
                }
                let normals = match s.string("normals")?.unwrap_or("smooth") {
                    "smooth" => SdfNormalsDesc::Smooth,
                    "analytic" => SdfNormalsDesc::Analytic,
                    other => {
                        let p = s.prop("normals").expect("read above");
                        return Err(
                            p.error(format!("unknown normals \"{other}\" (smooth or analytic)"))
                        );
                    }
                };
                ShapeDesc::SdfGrid(SdfGridDesc {
                    file: self.file(s, "filename")?,
                    transform: placed(to_world),
                    normals,
                    material,
                })
            }
            "cylinder" => {
                let point = |name: &str, default: [f64; 3]| -> Result<[f32; 3]> {
                    Ok(s.vector(name)?.unwrap_or(default).map(|x| x as f32))
                };
                let p0 = point("p0", [0.0; 3])?;
                let p1 = point("p1", [0.0, 0.0, 1.0])?;
                if p0 == p1 {
                    return Err(s.error("the cylinder's p0 and p1 coincide: it has no length"));
                }
                let radius = s.float_or("radius", 1.0)?;
                if radius.is_nan() || radius <= 0.0 {
                    let p = s.prop("radius").expect("read above");
                    return Err(p.error(format!("the radius must be positive, got {radius}")));
                }
                ShapeDesc::Cylinder(CylinderDesc {
                    p0,
                    p1,
                    radius: radius as f32,
                    transform: placed(to_world),
                    flip_normals: flip_normals(s)?,
                    material,
                    emitter,
                })
            }
            p => {
                return Err(s.error(format!(
                    "unsupported shape plugin \"{p}\" (supported: {SHAPES})"
                )))
            }
        };
        s.finish()?;
        Ok(d)
    }

    /// A mesh shape's file; for `serialized`, only its first mesh (Mitsuba's default
    /// `shape_index`) can be read.
    fn mesh_file(&self, s: &Object) -> Result<String> {
        if s.plugin == "serialized" {
            if let Some(i) = s.int_in("shape_index", 0..=i32::MAX as i64)? {
                if i != 0 {
                    let p = s.prop("shape_index").expect("read above");
                    return Err(p.error(
                        "only the first mesh of a serialized file (shape_index 0) is supported",
                    ));
                }
            }
        }
        self.file(s, "filename")
    }

    /// The shape's material name (Mitsuba's default diffuse if it has no BSDF) and its emitter.
    fn shape_children(&mut self, s: &Object) -> Result<(String, Option<Rc<Object>>)> {
        let mut material = None;
        let mut emitter = None;
        let children: Vec<_> = s.unnamed_children().collect();
        for child in children {
            let o = self.doc.target(child)?;
            match o.class.as_str() {
                "bsdf" if material.is_some() => {
                    return Err(o.error("a shape has one BSDF"));
                }
                "bsdf" => material = Some(self.material(&o)?),
                "emitter" if emitter.is_some() => {
                    return Err(o.error("a shape has one emitter"));
                }
                "emitter" => emitter = Some(o),
                _ => continue,
            }
            s.take(child);
        }
        // Mitsuba gives an emitting shape without a BSDF a black diffuse one (its `Shape`
        // constructor), so that the light it emits is all it sends.
        let default = if emitter.is_some() {
            DEFAULT_EMITTER_MATERIAL
        } else {
            DEFAULT_MATERIAL
        };
        Ok((material.unwrap_or_else(|| default.into()), emitter))
    }

    /// Converts a shapegroup once; later calls return the same group.
    fn group(&mut self, g: &Rc<Object>) -> Result<Group> {
        if let Some(group) = self.groups.get(&Rc::as_ptr(g)) {
            return Ok(group.clone());
        }
        let base = g.id.clone().unwrap_or_else(|| "shapegroup".into());
        let mut group = Group::default();
        let children: Vec<_> = g.unnamed_children().collect();
        for child in children {
            let s = self.doc.target(child)?;
            if s.class != "shape" {
                continue;
            }
            g.take(child);
            match s.plugin.as_str() {
                "obj" | "ply" | "serialized" => {
                    let file = self.mesh_file(&s)?;
                    let to_world = s.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
                    let (material, emitter) = self.shape_children(&s)?;
                    if let Some(e) = emitter {
                        return Err(e.error("emitters inside a shapegroup are not supported"));
                    }
                    for unsupported in ["face_normals", "flip_normals"] {
                        if let Some(p) = s.prop(unsupported) {
                            return Err(p.error("not supported on a mesh inside a shapegroup"));
                        }
                    }
                    s.finish()?;
                    let mut name = format!("{base}_{}", group.meshes.len());
                    while self.meshes.contains_key(&name) {
                        name.push('_');
                    }
                    self.origins
                        .record(key_path(&[&"meshes", &name]), origin_of(&s));
                    self.meshes.insert(
                        name.clone(),
                        MeshDesc {
                            file,
                            material: Some(material),
                            // Mitsuba computes the normals an OBJ or PLY file lacks.
                            smooth_normals: true,
                            triangles: Vec::new(),
                        },
                    );
                    group.meshes.push((name, to_world));
                }
                "shapegroup" | "instance" => {
                    return Err(s.error("shapegroups cannot nest groups or instances"))
                }
                _ => {
                    // Checked now, added per instance.
                    self.shape_desc(&s, DMat4::IDENTITY)?;
                    group.others.push(s);
                }
            }
        }
        g.finish()?;
        self.groups.insert(Rc::as_ptr(g), group.clone());
        Ok(group)
    }

    fn instance(&mut self, i: &Object) -> Result<()> {
        let to_world = i.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
        let mut groups = Vec::new();
        for child in i.unnamed_children() {
            let g = self.doc.target(child)?;
            if g.class == "shape" && g.plugin == "shapegroup" {
                i.take(child);
                groups.push((g, matches!(child.target, Target::Ref(_))));
            }
        }
        let [(g, _)] = groups.as_slice() else {
            return Err(i.error("an instance needs exactly one shapegroup (usually a <ref>)"));
        };
        let group = self.group(g)?;
        for (mesh, placed) in &group.meshes {
            let index = self.instances.len();
            self.origins
                .record(key_path(&[&"instance", &index]), origin_of(i));
            self.instances.push(InstanceDesc {
                mesh: mesh.clone(),
                transform: Some(TransformDesc {
                    matrix: Some(rows_f32(&(to_world * *placed))),
                    ..TransformDesc::default()
                }),
                placements: None,
                keyframes: Vec::new(),
            });
        }
        for s in &group.others {
            let desc = self.shape_desc(s, to_world)?;
            self.push_shape(desc, s)?;
        }
        i.finish()
    }
}

/// `s` if the linear part of `m` is `s` times a rotation (or reflection), within rounding.
fn similarity_scale(m: &DMat4) -> Option<f64> {
    let (_, x, y, z) = columns(m);
    let s = x.length();
    let tol = 1e-5 * s;
    let ok = s > 0.0
        && (y.length() - s).abs() <= tol
        && (z.length() - s).abs() <= tol
        && x.dot(y).abs() <= tol * s
        && y.dot(z).abs() <= tol * s
        && x.dot(z).abs() <= tol * s
        && m.row(3) == glam::DVec4::W;
    ok.then_some(s)
}
