//! `[[shape]]`: one tagged table per surface, `type` naming its kind. Each kind takes exactly its
//! own keys, so a key that does not apply (a sphere's `size`, a plane's `emitter`) is a parse error
//! listing the keys it does take.

use super::{AreaEmitterDesc, TransformDesc, Vec3f};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum ShapeDesc {
    Sphere(SphereDesc),
    /// An infinite plane, or a finite one with `size`.
    Plane(PlaneDesc),
    Triangle(TriangleDesc),
    /// `f(x, y, z) = 0` searched inside `bounds` (see docs/implicit.md).
    Implicit(ImplicitDesc),
    Torus(TorusDesc),
    /// A mesh file.
    Mesh(MeshShapeDesc),
    /// Mitsuba's rectangle: the square `[-1, 1]^2` in the plane z = 0, facing +z, placed by
    /// `transform`.
    Rectangle(BasicShapeDesc),
    /// Mitsuba's cube: `[-1, 1]^3`, placed by `transform`.
    Cube(BasicShapeDesc),
    /// Mitsuba's disk: the unit disk in the plane z = 0, facing +z, placed by `transform`.
    Disk(BasicShapeDesc),
    /// Mitsuba's open cylinder (a tube without caps) from `p0` to `p1`, placed by `transform`.
    Cylinder(CylinderDesc),
    /// Mitsuba 3's signed distance grid: a `.vol` grid of distances spanning `[0, 1]^3`, whose zero
    /// set (trilinearly interpolated) is the surface, placed by `transform`.
    SdfGrid(SdfGridDesc),
    /// A triangle mesh written out in the scene (pbrt's `trianglemesh`).
    #[serde(rename = "trianglemesh")]
    TriangleMesh(TriangleMeshDesc),
}

/// `type = "trianglemesh"`: vertices and triangles given inline. The front of each triangle is
/// the side of `cross(p1 - p0, p2 - p0)`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TriangleMeshDesc {
    pub positions: Vec<Vec3f>,
    /// Three vertex indices per triangle.
    pub indices: Vec<[u32; 3]>,
    /// One shading normal per vertex.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normals: Option<Vec<Vec3f>>,
    /// One texture coordinate per vertex.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uvs: Option<Vec<[f32; 2]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
    /// Turn the normals around (which side is the front for one-sided materials and emitters).
    #[serde(default, skip_serializing_if = "is_false")]
    pub flip_normals: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// The `[media.NAME]` inside the surface (behind its normals); none is vacuum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interior: Option<String>,
    /// The `[media.NAME]` outside the surface (on the side of its normals).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exterior: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emitter: Option<AreaEmitterDesc>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SphereDesc {
    pub center: Vec3f,
    pub radius: f32,
    /// Texture coordinates as Mitsuba's sphere gives them, (azimuth / 2 pi, polar angle / pi),
    /// about the frame whose unit axes x, y, z (the pole) are these three rows. Without it, u and
    /// v are arc lengths along longitude and latitude about +y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mitsuba_uv: Option<[Vec3f; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// The `[media.NAME]` inside the surface (behind its normals); none is vacuum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interior: Option<String>,
    /// The `[media.NAME]` outside the surface (on the side of its normals).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exterior: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emitter: Option<AreaEmitterDesc>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PlaneDesc {
    pub point: Vec3f,
    pub normal: Vec3f,
    /// A finite plane: a `size[0]` x `size[1]` rectangle centred on `point`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<[f32; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TriangleDesc {
    pub vertices: [Vec3f; 3],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emitter: Option<AreaEmitterDesc>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ImplicitDesc {
    pub f: String,
    /// `[[xmin, ymin, zmin], [xmax, ymax, zmax]]`.
    pub bounds: [Vec3f; 2],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TorusDesc {
    pub center: Vec3f,
    pub major_radius: f32,
    pub minor_radius: f32,
    /// Axis of symmetry; default `[0, 1, 0]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<Vec3f>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MeshShapeDesc {
    /// A mesh file (.ply, .obj, .gltf, .glb, .ply.gz, .obj.gz), relative to the scene file's folder.
    pub file: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
    /// A moving placement, instead of `transform`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub keyframes: Vec<super::KeyframeDesc>,
    /// Ignore the file's vertex normals and shade with the triangles' own.
    #[serde(default, skip_serializing_if = "is_false")]
    pub face_normals: bool,
    /// Give the parts the file has no vertex normals for smooth ones, angle-weighted as Mitsuba 3
    /// computes them (its `obj` and `ply` shapes do unless `face_normals`); otherwise they shade
    /// with the triangles' own normals.
    #[serde(default, skip_serializing_if = "is_false")]
    pub smooth_normals: bool,
    /// Turn the normals around (which side is the front for one-sided materials and emitters).
    #[serde(default, skip_serializing_if = "is_false")]
    pub flip_normals: bool,
    /// Overrides the file's own materials.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// The `[media.NAME]` inside the surface (behind its normals); none is vacuum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interior: Option<String>,
    /// The `[media.NAME]` outside the surface (on the side of its normals).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exterior: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emitter: Option<AreaEmitterDesc>,
}

/// Rectangles, cubes and disks: a fixed mesh placed by `transform`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BasicShapeDesc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
    /// A moving placement, instead of `transform`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub keyframes: Vec<super::KeyframeDesc>,
    /// Turn the normals around (which side is the front for one-sided materials and emitters).
    #[serde(default, skip_serializing_if = "is_false")]
    pub flip_normals: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// The `[media.NAME]` inside the surface (behind its normals); none is vacuum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interior: Option<String>,
    /// The `[media.NAME]` outside the surface (on the side of its normals).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exterior: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emitter: Option<AreaEmitterDesc>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SdfGridDesc {
    /// A single-channel Mitsuba grid volume (`.vol`), relative to the scene file's folder.
    pub file: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
    /// Shading normals: `smooth` (blended across voxels, the default) or `analytic` (the
    /// interpolant's gradient).
    #[serde(default)]
    pub normals: SdfNormalsDesc,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
}

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SdfNormalsDesc {
    #[default]
    Smooth,
    Analytic,
}

/// The tube of radius `radius` around the segment `p0`-`p1` (no caps), then placed by `transform`;
/// texture coordinates are Mitsuba's (`u` the angle around the axis over 2 pi, `v` along it).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CylinderDesc {
    #[serde(default = "origin")]
    pub p0: Vec3f,
    #[serde(default = "unit_z")]
    pub p1: Vec3f,
    #[serde(default = "one")]
    pub radius: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<TransformDesc>,
    /// Normals toward the axis instead of away from it.
    #[serde(default, skip_serializing_if = "is_false")]
    pub flip_normals: bool,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub emitter: Option<AreaEmitterDesc>,
}

impl Default for CylinderDesc {
    fn default() -> Self {
        Self {
            p0: origin(),
            p1: unit_z(),
            radius: 1.0,
            transform: None,
            flip_normals: false,
            material: None,
            emitter: None,
        }
    }
}

impl CylinderDesc {
    /// Where the unit tube (`x^2 + y^2 = 1`, `0 <= z <= 1`) goes: Mitsuba's cylinder frame, with
    /// its axis along `p1 - p0` and the angle measured from the first vector of the Duff et al.
    /// basis around it.
    pub fn to_world(&self) -> glam::Mat4 {
        use glam::{Mat4, Vec3};
        let (p0, p1) = (Vec3::from(self.p0), Vec3::from(self.p1));
        let axis = p1 - p0;
        let length = axis.length();
        let z = axis / length;
        let (x, y) = crate::math::orthonormal_basis(z);
        let frame = Mat4::from_cols(
            (x * self.radius).extend(0.0),
            (y * self.radius).extend(0.0),
            axis.extend(0.0),
            p0.extend(1.0),
        );
        self.transform
            .as_ref()
            .map_or(Mat4::IDENTITY, |t| t.matrix())
            * frame
    }
}

fn origin() -> Vec3f {
    [0.0; 3]
}

fn unit_z() -> Vec3f {
    [0.0, 0.0, 1.0]
}

fn one() -> f32 {
    1.0
}

fn is_false(b: &bool) -> bool {
    !*b
}

impl ShapeDesc {
    /// The name of the `[materials.NAME]` entry the shape uses, if any.
    pub fn material(&self) -> Option<&str> {
        match self {
            ShapeDesc::Sphere(s) => s.material.as_deref(),
            ShapeDesc::Plane(s) => s.material.as_deref(),
            ShapeDesc::Triangle(s) => s.material.as_deref(),
            ShapeDesc::Implicit(s) => s.material.as_deref(),
            ShapeDesc::Torus(s) => s.material.as_deref(),
            ShapeDesc::Mesh(s) => s.material.as_deref(),
            ShapeDesc::TriangleMesh(s) => s.material.as_deref(),
            ShapeDesc::Rectangle(s) | ShapeDesc::Cube(s) | ShapeDesc::Disk(s) => {
                s.material.as_deref()
            }
            ShapeDesc::Cylinder(s) => s.material.as_deref(),
            ShapeDesc::SdfGrid(s) => s.material.as_deref(),
        }
    }

    /// The media inside and outside the surface (`interior`, `exterior`), on the kinds that
    /// can bound a medium.
    pub fn media(&self) -> (Option<&str>, Option<&str>) {
        fn pair<'a>(
            i: &'a Option<String>,
            e: &'a Option<String>,
        ) -> (Option<&'a str>, Option<&'a str>) {
            (i.as_deref(), e.as_deref())
        }
        match self {
            ShapeDesc::Sphere(s) => pair(&s.interior, &s.exterior),
            ShapeDesc::Mesh(s) => pair(&s.interior, &s.exterior),
            ShapeDesc::TriangleMesh(s) => pair(&s.interior, &s.exterior),
            ShapeDesc::Rectangle(s) | ShapeDesc::Cube(s) | ShapeDesc::Disk(s) => {
                pair(&s.interior, &s.exterior)
            }
            ShapeDesc::Plane(_)
            | ShapeDesc::Triangle(_)
            | ShapeDesc::Implicit(_)
            | ShapeDesc::Torus(_)
            | ShapeDesc::Cylinder(_)
            | ShapeDesc::SdfGrid(_) => (None, None),
        }
    }

    /// The area emitter, on the kinds that can emit.
    pub fn emitter(&self) -> Option<&AreaEmitterDesc> {
        match self {
            ShapeDesc::Sphere(s) => s.emitter.as_ref(),
            ShapeDesc::Triangle(s) => s.emitter.as_ref(),
            ShapeDesc::Mesh(s) => s.emitter.as_ref(),
            ShapeDesc::TriangleMesh(s) => s.emitter.as_ref(),
            ShapeDesc::Rectangle(s) | ShapeDesc::Cube(s) | ShapeDesc::Disk(s) => s.emitter.as_ref(),
            ShapeDesc::Cylinder(s) => s.emitter.as_ref(),
            ShapeDesc::Plane(_)
            | ShapeDesc::Implicit(_)
            | ShapeDesc::Torus(_)
            | ShapeDesc::SdfGrid(_) => None,
        }
    }

    /// Scales the shape by `s` about the origin (for [`super::Description::scaled`]).
    pub fn scale(&mut self, s: f32) {
        let sc = |v: &mut Vec3f| *v = v.map(|x| x * s);
        // s * (T R S) = T(s t) R S(s S): scale the translation and the scale.
        let scale_transform = |t: &mut Option<TransformDesc>| {
            t.get_or_insert_with(Default::default).scale_about_origin(s)
        };
        match self {
            ShapeDesc::Sphere(x) => {
                sc(&mut x.center);
                x.radius *= s;
            }
            ShapeDesc::Plane(x) => {
                sc(&mut x.point);
                x.size = x.size.map(|z| z.map(|v| v * s));
            }
            ShapeDesc::Triangle(x) => x.vertices.iter_mut().for_each(sc),
            ShapeDesc::Implicit(x) if x.transform.is_some() => scale_transform(&mut x.transform),
            ShapeDesc::Implicit(x) => {
                // Without a transform the surface lives in world coordinates: f(x/s, y/s, z/s) = 0
                // is the surface scaled by s.
                x.bounds.iter_mut().for_each(sc);
                x.f = crate::geometry::implicit::parse::substitute_scaled(&x.f, 1.0 / s as f64);
            }
            ShapeDesc::Torus(x) => {
                sc(&mut x.center);
                x.major_radius *= s;
                x.minor_radius *= s;
            }
            ShapeDesc::Mesh(x) => scale_transform(&mut x.transform),
            ShapeDesc::TriangleMesh(x) => scale_transform(&mut x.transform),
            ShapeDesc::Rectangle(x) | ShapeDesc::Cube(x) | ShapeDesc::Disk(x) => {
                scale_transform(&mut x.transform)
            }
            ShapeDesc::Cylinder(x) => scale_transform(&mut x.transform),
            ShapeDesc::SdfGrid(x) => scale_transform(&mut x.transform),
        }
    }
}
