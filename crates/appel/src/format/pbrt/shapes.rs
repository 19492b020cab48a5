//! pbrt's shapes: `trianglemesh`, `bilinearmesh` (two triangles per quad), `plymesh` (PLY,
//! `.ply.gz`), `sphere` and `disk`, baked into the description in world space.
//!
//! Orientation. pbrt's triangle faces the side of `cross(p1 - p0, p2 - p0)` transformed as a
//! normal, flipped where the transform swaps handedness or `ReverseOrientation` is in effect, and
//! turned towards the vertex normals `N` where the mesh has them. Appel's triangle faces
//! `cross(p1 - p0, p2 - p0)` of its world-space vertices, which already flips with a mirroring
//! transform: so triangles are rewound where the scene's own mirror (see `convert`) or
//! `ReverseOrientation` says, and rewound to agree with `N` where it is given (the emitter
//! sampler reads the winding, not the normals).

use super::convert::{AreaLight, Converter};
use super::materials::Converted;
use super::params::ParamType;
use super::parser::Directive;
use super::tokenizer::Loc;
use crate::description::{
    AreaEmitterDesc, BasicShapeDesc, InstanceDesc, MeshDesc, ShapeDesc, SphereDesc, TextureDesc,
    TransformDesc, TriangleMeshDesc,
};
use crate::error::Result;
use glam::{DMat4, DVec3};
use std::rc::Rc;

/// A shape in its own object space, as the directive gave it.
#[derive(Debug)]
pub(super) enum ObjectShape {
    Mesh {
        positions: Vec<DVec3>,
        indices: Vec<[u32; 3]>,
        normals: Option<Vec<DVec3>>,
        uvs: Option<Vec<[f32; 2]>>,
    },
    Sphere {
        radius: f64,
    },
    Disk {
        height: f64,
        radius: f64,
    },
}

/// An object definition: its triangle meshes as one declared mesh, and its other shapes.
#[derive(Clone, Debug)]
pub(super) struct Object {
    mesh: Option<String>,
    others: Vec<Placed>,
}

/// A shape of an object definition, with the state it was declared in.
#[derive(Clone, Debug)]
pub(super) struct Placed {
    shape: Rc<ObjectShape>,
    ctm: DMat4,
    material: Option<Converted>,
    reverse: bool,
    /// The media inside and outside, where they differ (pbrt-v4: only a transition bounds a
    /// medium).
    media: (Option<String>, Option<String>),
    loc: Loc,
}

/// The material of pbrt's `interface` shapes that bound a medium.
const INTERFACE_MATERIAL: &str = "pbrt_interface";

impl Converter {
    /// The graphics state's media for a shape: both sides where they differ, none otherwise.
    fn shape_media(&self) -> (Option<String>, Option<String>) {
        let (inside, outside) = (&self.attrs.medium_inside, &self.attrs.medium_outside);
        if inside == outside {
            (None, None)
        } else {
            (inside.clone(), outside.clone())
        }
    }

    pub(super) fn shape(&mut self, d: &Directive) -> Result<()> {
        let shape = Rc::new(self.read_shape(d)?);
        let media = self.shape_media();
        if let Some((name, shapes, _)) = &mut self.object {
            if self.attrs.area_light.is_some() {
                return Err(d.loc.error(format!(
                    "an area light inside object \"{name}\": instanced shapes cannot emit (as \
                     in pbrt)"
                )));
            }
            shapes.push(Placed {
                shape,
                ctm: self.attrs.ctm,
                material: self.attrs.material.clone(),
                reverse: self.attrs.reverse_orientation,
                media: media.clone(),
                loc: d.loc.clone(),
            });
            return Ok(());
        }
        let placed = Placed {
            shape,
            ctm: self.attrs.ctm,
            material: self.attrs.material.clone(),
            reverse: self.attrs.reverse_orientation,
            media,
            loc: d.loc.clone(),
        };
        let light = self.attrs.area_light.clone();
        self.place(&placed, DMat4::IDENTITY, light.as_ref())
    }

    /// `ObjectEnd`: the object's triangle meshes become one of Appel's declared meshes (a
    /// prototype with its own acceleration structure, in the description's coordinates as
    /// declared); its other shapes are kept to be written out at each placement.
    pub(super) fn define_object(&mut self, name: &str, shapes: Vec<Placed>) -> Result<()> {
        let mut triangles = Vec::new();
        let mut others = Vec::new();
        for s in shapes {
            if matches!(*s.shape, ObjectShape::Mesh { .. }) {
                if let Some(ShapeDesc::TriangleMesh(t)) = self.bake(&s, DMat4::IDENTITY, None)? {
                    triangles.push(t);
                }
            } else {
                others.push(s);
            }
        }
        let mesh = (!triangles.is_empty()).then(|| {
            let key = format!("object {name}");
            self.meshes.insert(
                key.clone(),
                MeshDesc {
                    file: String::new(),
                    material: None,
                    smooth_normals: false,
                    triangles,
                },
            );
            key
        });
        self.objects
            .insert(name.to_string(), Object { mesh, others });
        Ok(())
    }

    /// `ObjectInstance`: the object placed by the CTM, as an instance of its mesh (the
    /// description's coordinates are pbrt's mirrored by `mirror`, so the placement is
    /// `mirror * CTM * mirror^-1`), and its other shapes written out.
    pub(super) fn object_instance(&mut self, d: &Directive) -> Result<()> {
        let name = &d.strings[0];
        let object = self.objects.get(name).cloned().ok_or_else(|| {
            d.loc
                .error(format!("no object named \"{name}\" has been defined"))
        })?;
        if self.object.is_some() {
            return Err(d
                .loc
                .error("ObjectInstance inside ObjectBegin: objects do not nest"));
        }
        let instance = self.attrs.ctm;
        if let Some(mesh) = object.mesh {
            let placement = self.mirror * instance * self.mirror.inverse();
            self.instances.push(InstanceDesc {
                mesh,
                transform: Some(TransformDesc {
                    matrix: Some(rows(&placement)),
                    ..TransformDesc::default()
                }),
                placements: None,
                keyframes: Vec::new(),
            });
        }
        for s in &object.others {
            self.place(s, instance, None)?;
        }
        Ok(())
    }

    /// Adds one shape to the description, placed by `instance * its own CTM`.
    fn place(&mut self, s: &Placed, instance: DMat4, light: Option<&AreaLight>) -> Result<()> {
        if let Some(desc) = self.bake(s, instance, light)? {
            self.shapes.push(desc);
        }
        Ok(())
    }

    /// One shape as the description holds it, placed by `instance * its own CTM`; `None` for
    /// an invisible one (an `interface`).
    fn bake(
        &mut self,
        s: &Placed,
        instance: DMat4,
        light: Option<&AreaLight>,
    ) -> Result<Option<ShapeDesc>> {
        let material = match &s.material {
            Some(Converted::Interface) => {
                if let Some(l) = light {
                    return Err(l.loc.error(
                        "an area light on a shape whose material is \"interface\" (invisible)",
                    ));
                }
                // An interface only bounds a medium: without one there is nothing to see, with
                // one it is Mitsuba's null BSDF.
                if s.media == (None, None) {
                    return Ok(None);
                }
                self.materials
                    .entry(INTERFACE_MATERIAL.to_string())
                    .or_insert(crate::description::MaterialDesc::Null(
                        crate::description::NullDesc {},
                    ));
                INTERFACE_MATERIAL.to_string()
            }
            Some(Converted::Surface { name, .. }) => name.clone(),
            None => self.default_material(),
        };
        let ctm = instance * s.ctm;
        let m = self.to_description(&ctm);
        let emitter = light.map(|l| AreaEmitterDesc {
            radiance: TextureDesc::Rgb(l.radiance),
        });
        let mirrored = self.mirror.determinant() < 0.0;
        let desc = match &*s.shape {
            ObjectShape::Mesh {
                positions,
                indices,
                normals,
                uvs,
            } => {
                let world: Vec<[f32; 3]> = positions
                    .iter()
                    .map(|p| f32s(m.transform_point3(*p)))
                    .collect();
                let normal_matrix = m.inverse().transpose();
                let sign = if s.reverse { -1.0 } else { 1.0 };
                let world_normals: Option<Vec<[f32; 3]>> = normals.as_ref().map(|ns| {
                    ns.iter()
                        .map(|n| {
                            f32s(sign * normal_matrix.transform_vector3(*n).normalize_or_zero())
                        })
                        .collect()
                });
                let rewind = mirrored != s.reverse;
                let indices = indices
                    .iter()
                    .map(|&[a, b, c]| {
                        let flip = match &world_normals {
                            Some(ns) => {
                                let v = |i: u32| glam::Vec3::from(world[i as usize]);
                                let n = |i: u32| glam::Vec3::from(ns[i as usize]);
                                let cross = (v(b) - v(a)).cross(v(c) - v(a));
                                cross.dot(n(a) + n(b) + n(c)) < 0.0
                            }
                            None => rewind,
                        };
                        if flip {
                            [a, c, b]
                        } else {
                            [a, b, c]
                        }
                    })
                    .collect();
                ShapeDesc::TriangleMesh(TriangleMeshDesc {
                    interior: s.media.0.clone(),
                    exterior: s.media.1.clone(),
                    positions: world,
                    indices,
                    normals: world_normals,
                    uvs: uvs.clone(),
                    transform: None,
                    flip_normals: false,
                    material: Some(material),
                    emitter,
                })
            }
            ObjectShape::Sphere { radius } => {
                let scale = similarity_scale(&m).ok_or_else(|| {
                    s.loc.error(
                        "a sphere under a non-uniform scale or shear (an ellipsoid) is not \
                         supported",
                    )
                })?;
                // pbrt turns a sphere inside out where ReverseOrientation or a
                // handedness-swapping transform says so; Appel's spheres face outwards.
                let inside_out = s.reverse != (ctm.determinant() < 0.0);
                if inside_out && emitter.is_some() {
                    return Err(s.loc.error(
                        "an emitting sphere turned inside out (ReverseOrientation or a mirroring \
                         transform) is not supported",
                    ));
                }
                ShapeDesc::Sphere(SphereDesc {
                    interior: s.media.0.clone(),
                    exterior: s.media.1.clone(),
                    center: f32s(m.transform_point3(DVec3::ZERO)),
                    radius: (radius * scale) as f32,
                    material: Some(material),
                    emitter,
                    mitsuba_uv: None,
                })
            }
            ObjectShape::Disk { height, radius } => {
                let local = DMat4::from_translation(DVec3::new(0.0, 0.0, *height))
                    * DMat4::from_scale(DVec3::new(*radius, *radius, 1.0));
                let full = m * local;
                ShapeDesc::Disk(BasicShapeDesc {
                    interior: s.media.0.clone(),
                    exterior: s.media.1.clone(),
                    transform: Some(TransformDesc {
                        matrix: Some(rows(&full)),
                        ..TransformDesc::default()
                    }),
                    // Appel's disk faces its transformed +z; pbrt's faces the other way where
                    // the transform swaps handedness or the orientation is reversed.
                    flip_normals: (ctm.determinant() < 0.0) != s.reverse,
                    material: Some(material),
                    emitter,
                    keyframes: Vec::new(),
                })
            }
        };
        Ok(Some(desc))
    }

    fn read_shape(&mut self, d: &Directive) -> Result<ObjectShape> {
        let p = &d.params;
        for unsupported in ["alpha", "displacement"] {
            if let Some(q) = p.get(unsupported) {
                let trivial = q.ty == ParamType::Float && q.numbers() == [1.0];
                if unsupported == "alpha" && trivial {
                    continue;
                }
                return Err(q.error(format!("the shapes' \"{unsupported}\" is not supported")));
            }
        }
        // Appel computes its own error bounds and refinement; these do not change the surface.
        p.ignore("emissionfilename");
        Ok(match d.strings[0].as_str() {
            "trianglemesh" => {
                let positions = points(p.array("P", ParamType::Point3)?.map(|q| q.numbers()))
                    .ok_or_else(|| d.loc.error("a trianglemesh needs \"point3 P\""))?;
                let n = positions.len();
                let indices =
                    match p.array("indices", ParamType::Integer)? {
                        Some(q) => {
                            let v = q.numbers();
                            if v.len() % 3 != 0 {
                                return Err(q.error("\"indices\" must hold three per triangle"));
                            }
                            triples(v, n).map_err(|m| q.error(m))?
                        }
                        None if n == 3 => vec![[0, 1, 2]],
                        None => return Err(d.loc.error(
                            "a trianglemesh needs \"integer indices\" unless it has exactly three \
                             points",
                        )),
                    };
                let (normals, uvs) = self.vertex_data(d, n)?;
                p.ignore("S");
                p.ignore("faceIndices");
                ObjectShape::Mesh {
                    positions,
                    indices,
                    normals,
                    uvs,
                }
            }
            "bilinearmesh" => {
                let positions = points(p.array("P", ParamType::Point3)?.map(|q| q.numbers()))
                    .ok_or_else(|| d.loc.error("a bilinearmesh needs \"point3 P\""))?;
                let n = positions.len();
                let quads: Vec<u32> = match p.array("indices", ParamType::Integer)? {
                    Some(q) => {
                        let v = q.numbers();
                        if v.len() % 4 != 0 {
                            return Err(q.error("\"indices\" must hold four per patch"));
                        }
                        triples(v, n).map_err(|m| q.error(m))?;
                        v.iter().map(|&x| x as u32).collect()
                    }
                    None if n == 4 => vec![0, 1, 2, 3],
                    None => return Err(d.loc.error("a bilinearmesh needs \"integer indices\"")),
                };
                // A patch's corners are p00, p10, p01, p11; a planar patch is these two triangles
                // (a curved one is approximated by them).
                let indices = quads
                    .chunks_exact(4)
                    .flat_map(|q| [[q[0], q[1], q[3]], [q[0], q[3], q[2]]])
                    .collect();
                let (normals, uvs) = self.vertex_data(d, n)?;
                p.ignore("faceIndices");
                ObjectShape::Mesh {
                    positions,
                    indices,
                    normals,
                    uvs,
                }
            }
            "plymesh" => self.ply(d)?,
            "sphere" => {
                let radius = p.float_or("radius", 1.0)?;
                if radius <= 0.0 {
                    return Err(d
                        .loc
                        .error(format!("the radius must be positive, got {radius}")));
                }
                for (partial, full) in [("zmin", -radius), ("zmax", radius), ("phimax", 360.0)] {
                    if let Some(v) = p.float(partial)? {
                        if v != full {
                            let at = &p.get(partial).expect("read").loc;
                            return Err(at.error(format!(
                                "partial spheres (\"{partial}\") are not supported"
                            )));
                        }
                    }
                }
                ObjectShape::Sphere { radius }
            }
            "disk" => {
                let radius = p.float_or("radius", 1.0)?;
                let height = p.float_or("height", 0.0)?;
                if radius <= 0.0 {
                    return Err(d
                        .loc
                        .error(format!("the radius must be positive, got {radius}")));
                }
                if p.float_or("innerradius", 0.0)? != 0.0 || p.float_or("phimax", 360.0)? != 360.0 {
                    return Err(d
                        .loc
                        .error("partial disks (\"innerradius\", \"phimax\") are not supported"));
                }
                ObjectShape::Disk { height, radius }
            }
            other => {
                return Err(d.loc.error(format!(
                    "unsupported shape \"{other}\" (supported: trianglemesh, bilinearmesh, \
                     plymesh, sphere, disk)"
                )))
            }
        })
    }

    /// `N` and `uv` of a mesh of `n` vertices.
    #[allow(clippy::type_complexity)]
    fn vertex_data(
        &self,
        d: &Directive,
        n: usize,
    ) -> Result<(Option<Vec<DVec3>>, Option<Vec<[f32; 2]>>)> {
        let p = &d.params;
        let normals = match p.array("N", ParamType::Normal)? {
            Some(q) if q.numbers().len() != 3 * n => {
                return Err(q.error(format!("{} normals for {n} points", q.numbers().len() / 3)))
            }
            Some(q) => points(Some(q.numbers())),
            None => None,
        };
        let uvs = match p.any_of("uv", &[ParamType::Point2, ParamType::Float])? {
            Some(q) if q.numbers().len() != 2 * n => {
                return Err(q.error(format!(
                    "{} texture coordinates for {n} points",
                    q.numbers().len() / 2
                )))
            }
            Some(q) => Some(
                q.numbers()
                    .chunks_exact(2)
                    .map(|c| [c[0] as f32, c[1] as f32])
                    .collect(),
            ),
            None => None,
        };
        Ok((normals, uvs))
    }

    fn ply(&mut self, d: &Directive) -> Result<ObjectShape> {
        let p = &d.params;
        let name = p
            .string("filename")?
            .ok_or_else(|| d.loc.error("a plymesh needs \"string filename\""))?;
        let path = self.base_dir.join(name);
        if !path.is_file() {
            return Err(d.loc.error(format!(
                "the PLY file \"{name}\" is missing (looked for {})",
                path.display()
            )));
        }
        p.ignore("edgelength");
        let lower = name.to_ascii_lowercase();
        if !(lower.ends_with(".ply") || lower.ends_with(".ply.gz")) {
            return Err(d
                .loc
                .error(format!("\"{name}\": a plymesh reads .ply or .ply.gz files")));
        }
        let loaded = crate::io::load_mesh(&path)?.flattened();
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        let mut normals: Option<Vec<DVec3>> = Some(Vec::new());
        let mut uvs: Option<Vec<[f32; 2]>> = Some(Vec::new());
        for part in &loaded.parts {
            let m = &part.mesh;
            let base = positions.len() as u32;
            positions.extend(m.positions.iter().map(|v| v.as_dvec3()));
            indices.extend(m.indices.iter().map(|t| t.map(|i| i + base)));
            match (&mut normals, &m.normals) {
                (Some(all), Some(ns)) => all.extend(ns.iter().map(|n| n.as_dvec3())),
                _ => normals = None,
            }
            match (&mut uvs, &m.uvs) {
                (Some(all), Some(u)) => all.extend(u.iter().map(|u| [u.x, u.y])),
                _ => uvs = None,
            }
        }
        Ok(ObjectShape::Mesh {
            positions,
            indices,
            normals,
            uvs,
        })
    }

    /// The default material (pbrt's: diffuse, reflectance 0.5), made the first time it is used.
    fn default_material(&mut self) -> String {
        const NAME: &str = "pbrt-default-diffuse";
        if !self.materials.contains_key(NAME) {
            self.materials.insert(
                NAME.to_string(),
                crate::description::MaterialDesc::TwoSided(crate::description::TwoSidedDesc {
                    front: format!("{NAME}.bsdf"),
                    back: None,
                }),
            );
            self.materials.insert(
                format!("{NAME}.bsdf"),
                crate::description::MaterialDesc::Diffuse(crate::description::DiffuseDesc {
                    reflectance: TextureDesc::Value(0.5),
                }),
            );
        }
        NAME.to_string()
    }
}

fn points(v: Option<&[f64]>) -> Option<Vec<DVec3>> {
    Some(
        v?.chunks_exact(3)
            .map(|c| DVec3::new(c[0], c[1], c[2]))
            .collect(),
    )
}

/// Indices in triples, each below `n`.
fn triples(v: &[f64], n: usize) -> std::result::Result<Vec<[u32; 3]>, String> {
    if let Some(bad) = v.iter().find(|&&i| i < 0.0 || i as usize >= n) {
        return Err(format!(
            "index {bad} is out of range: the mesh has {n} points"
        ));
    }
    Ok(v.chunks_exact(3)
        .map(|c| [c[0] as u32, c[1] as u32, c[2] as u32])
        .collect())
}

fn f32s(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// The 4x4 matrix row by row, as `TransformDesc::matrix` takes it.
pub(super) fn rows(m: &DMat4) -> [[f32; 4]; 4] {
    m.transpose()
        .to_cols_array_2d()
        .map(|r| r.map(|x| x as f32))
}

/// The common scale of a rotation-and-uniform-scale (and translation), or `None`.
fn similarity_scale(m: &DMat4) -> Option<f64> {
    let cols = [
        m.x_axis.truncate(),
        m.y_axis.truncate(),
        m.z_axis.truncate(),
    ];
    let s = cols[0].length();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-4 * s.max(1e-30);
    let ok = s > 0.0
        && cols.iter().all(|c| close(c.length(), s))
        && close(cols[0].dot(cols[1]) / s, 0.0)
        && close(cols[1].dot(cols[2]) / s, 0.0)
        && close(cols[0].dot(cols[2]) / s, 0.0);
    ok.then_some(s)
}
