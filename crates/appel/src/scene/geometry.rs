//! All the surfaces of a scene, flattened into one list of primitives for the acceleration structure.

use super::instance::{Instance, Prototype};
use crate::accel::{closest_of, test_primitive, Hit, Primitives, TraversalStats, LEAF_PACKET};
use crate::description::loaded_mesh::MeshAttribute;
use crate::geometry::{
    triangle_box_overlap, Cylinder, FileTangent, Implicit, ObjectTransform, Plane, PrimHit,
    SdfGrid, Sphere, SphereBlock, SurfaceInteraction, Torus, TriangleMesh, TriangleTest,
};
use crate::math::{Aabb, Ray, RayF64, Vec3};
#[cfg(target_arch = "x86_64")]
use crate::math::{Avx2, RayF64x4};
use crate::shading::texture::AttributePoint;

/// One surface: a `[[shape]]` of the scene file, or one part of a mesh file's `[[shape]]`.
#[derive(Clone, Debug)]
pub struct Shape {
    pub kind: ShapeKind,
    pub material: u32,
    /// Where the shape comes from, for the `shapeid` and `primid` AOVs.
    pub source: ShapeSource,
}

/// The `[[shape]]` a surface comes from, and how its primitives number in the source file: a mesh
/// file split into parts (one per material) still reports the `[[shape]]`'s index and the triangle's
/// index in the file's order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ShapeSource {
    /// Index of the `[[shape]]` in the scene file's order.
    pub shape: u32,
    /// The file index of primitive `i` is `first_prim + i`...
    pub first_prim: u32,
    /// ...or `prim_table[i]` where the parts regrouped the file's triangles.
    pub prim_table: Option<Vec<u32>>,
}

#[derive(Clone, Debug)]
pub enum ShapeKind {
    Sphere(Sphere),
    Plane(Plane),
    /// Index into [`Geometry::meshes`]; a single `triangle` shape is a one-triangle mesh.
    Mesh(u32),
    /// Index into [`Geometry::implicits`] (the compiled formula lives there, not in the enum).
    Implicit(u32),
    Torus(Torus),
    /// Boxed: its two transforms would make every shape's entry several times larger.
    Cylinder(Box<Cylinder>),
    SdfGrid(std::sync::Arc<SdfGrid>),
    /// One `[[instance]]` entry: its primitives are instances, named by their index into
    /// [`Geometry::instances`].
    Instances,
}

/// A primitive the acceleration structure sees: one sphere, one rectangle or one triangle of a mesh,
/// named by its shape and its index inside that shape (8 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PrimRef {
    pub shape: u32,
    pub index: u32,
}

/// The bounded primitives, numbered as the acceleration structure indexes them: first the shapes
/// that are one primitive each (spheres, rectangles, implicit surfaces, tori), one reference
/// each, then the meshes' triangles and the placements of `[[instance]]` entries, as runs of
/// consecutive indices of one shape. A mesh is then one 12-byte run instead of 8 bytes per
/// triangle, and the lookup is still a single load for the
/// one-primitive shapes, which are always called back; a mesh's triangles are looked up by a
/// binary search over the runs (one run for a one-mesh scene), needed once per final hit when the
/// structure holds their vertices.
#[derive(Clone, Debug, Default)]
pub struct PrimRefs {
    single: Vec<PrimRef>,
    runs: Vec<Run>,
    /// Primitives in the runs.
    in_runs: u32,
}

/// Primitives `start..` (counted from the first run's) are indices `first..` of `shape`.
#[derive(Clone, Copy, Debug)]
struct Run {
    start: u32,
    shape: u32,
    first: u32,
}

impl PrimRefs {
    pub fn len(&self) -> usize {
        self.single.len() + self.in_runs as usize
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Primitive `i`'s shape and index in it.
    #[inline]
    pub fn get(&self, i: usize) -> PrimRef {
        if let Some(&r) = self.single.get(i) {
            return r;
        }
        let j = (i - self.single.len()) as u32;
        match self.runs.as_slice() {
            [r] => PrimRef {
                shape: r.shape,
                index: r.first + j,
            },
            _ => self.in_runs(j),
        }
    }

    /// The binary search for scenes of several runs, out of line: inlined into the traversals
    /// (which call it for every called-back primitive), its code would make the compiler stop
    /// inlining the triangle test's finish there.
    #[inline(never)]
    fn in_runs(&self, j: u32) -> PrimRef {
        debug_assert!(j < self.in_runs);
        let r = self.runs[self.runs.partition_point(|r| r.start <= j) - 1];
        PrimRef {
            shape: r.shape,
            index: r.first + (j - r.start),
        }
    }

    pub fn iter(&self) -> impl Iterator<Item = PrimRef> + '_ {
        (0..self.len()).map(|i| self.get(i))
    }

    fn push_single(&mut self, shape: u32) {
        self.single.push(PrimRef { shape, index: 0 });
    }

    fn push_run(&mut self, shape: u32, first: u32, count: u32) {
        if count == 0 {
            return;
        }
        self.runs.push(Run {
            start: self.in_runs,
            shape,
            first,
        });
        self.in_runs = self
            .in_runs
            .checked_add(count)
            .filter(|&n| (self.single.len() as u64 + n as u64) < u32::MAX as u64)
            .expect("a scene has fewer than 2^32 - 1 bounded primitives");
    }

    /// Heap bytes.
    pub fn bytes(&self) -> usize {
        self.single.len() * std::mem::size_of::<PrimRef>()
            + self.runs.len() * std::mem::size_of::<Run>()
    }
}

/// A one-primitive shape as a leaf tests it: spheres and rectangles stored by value, in primitive
/// order, so that a leaf's tests need neither the primitive's reference nor its shape (the shapes'
/// `kind` sits in a much larger struct), and share one conversion of the ray to f64.
#[derive(Clone, Copy, Debug)]
enum Analytic {
    Sphere(Sphere),
    Rectangle(Plane),
    /// Any other one-primitive shape (implicit surfaces, tori): tested through its shape.
    Other,
}

/// Everything that can be hit.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    pub shapes: Vec<Shape>,
    pub meshes: Vec<TriangleMesh>,
    /// Named per-vertex and per-triangle values of meshes (by index into `meshes`; shorter when
    /// the last meshes have none).
    pub mesh_attributes: Vec<Option<std::sync::Arc<Vec<MeshAttribute>>>>,
    /// Per-vertex tangents (xyz, handedness in w) of meshes whose file gives them (glTF
    /// `TANGENT`), by index into `meshes`; shorter when the last meshes have none.
    pub mesh_tangents: Vec<Option<Vec<glam::Vec4>>>,
    pub implicits: Vec<Implicit>,
    /// Where each implicit surface sits in the world, if not at its formula's own coordinates.
    pub implicit_transforms: Vec<Option<ObjectTransform>>,
    /// Bounded primitives, in the order the acceleration structure indexes them.
    pub prims: PrimRefs,
    /// Shapes without finite bounds (infinite planes), tested separately for every ray.
    pub unbounded: Vec<u32>,
    pub triangle_test: TriangleTest,
    /// Meshes declared once (`[meshes.NAME]`), each with its own acceleration structure.
    pub prototypes: Vec<Prototype>,
    /// Placements of prototypes, numbered in file order: the `instanceid` AOV.
    pub instances: Vec<Instance>,
    /// The one-primitive shapes, indexed as `prims` numbers them (they come first).
    analytic: Vec<Analytic>,
    /// The spheres among them, two to a block, for [`Primitives::intersect_all`]...
    sphere_blocks: Vec<SphereBlock>,
    /// ...the rectangles with their ids...
    rectangles: Vec<(Plane, u32)>,
    /// ...and the ids of the others.
    others: Vec<u32>,
    /// Spheres textured as Mitsuba's: the rows of their frame, by shape id (empty when none is).
    sphere_uv_frames: Vec<Option<glam::Mat3>>,
}

/// A closest hit in the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneHit {
    pub t: f32,
    pub shape: u32,
    /// Index of the primitive inside its shape; see [`Geometry::source_ids`] for the file's numbering.
    pub prim: u32,
    pub u: f32,
    pub v: f32,
    /// The instance hit, or [`NO_INSTANCE`]. For an instance hit, `shape` and `prim` name the
    /// surface and primitive inside its prototype's geometry.
    pub instance: u32,
}

/// [`SceneHit::instance`] of a hit on a surface that is not instanced (and the `instanceid` AOV of
/// such hits and of misses).
pub const NO_INSTANCE: u32 = u32::MAX;

impl Geometry {
    pub fn new(triangle_test: TriangleTest) -> Self {
        Self {
            triangle_test,
            ..Default::default()
        }
    }

    /// Adds a shape and its primitives; returns its id.
    pub fn push(&mut self, kind: ShapeKind, material: u32) -> u32 {
        let id = self.shapes.len() as u32;
        match &kind {
            ShapeKind::Sphere(s) => self.push_single(id, Analytic::Sphere(*s)),
            ShapeKind::Implicit(_)
            | ShapeKind::Torus(_)
            | ShapeKind::Cylinder(_)
            | ShapeKind::SdfGrid(_) => self.push_single(id, Analytic::Other),
            ShapeKind::Plane(p) if p.half_size.is_none() => self.unbounded.push(id),
            ShapeKind::Plane(p) => self.push_single(id, Analytic::Rectangle(*p)),
            ShapeKind::Mesh(m) => {
                let n = self.meshes[*m as usize].triangle_count() as u32;
                self.prims.push_run(id, 0, n);
            }
            ShapeKind::Instances => {}
        }
        self.shapes.push(Shape {
            kind,
            material,
            source: ShapeSource {
                shape: id,
                ..Default::default()
            },
        });
        id
    }

    /// Gives sphere `shape` Mitsuba's texture coordinates about the frame whose rows are `rows`.
    pub fn set_sphere_uv_frame(&mut self, shape: u32, rows: glam::Mat3) {
        let i = shape as usize;
        if self.sphere_uv_frames.len() <= i {
            self.sphere_uv_frames.resize(i + 1, None);
        }
        self.sphere_uv_frames[i] = Some(rows);
    }

    fn push_single(&mut self, shape: u32, analytic: Analytic) {
        let id = self.analytic.len() as u32;
        self.prims.push_single(shape);
        self.analytic.push(analytic);
        match analytic {
            Analytic::Sphere(s) => {
                if !self.sphere_blocks.last_mut().is_some_and(|b| b.push(s, id)) {
                    let mut b = SphereBlock::default();
                    b.push(s, id);
                    self.sphere_blocks.push(b);
                }
            }
            Analytic::Rectangle(p) => self.rectangles.push((p, id)),
            Analytic::Other => self.others.push(id),
        }
    }

    /// [`Primitives::intersect_ids`] with the ray already in f64.
    #[inline(always)]
    fn intersect_ids_f64<const ANY: bool>(
        &self,
        ids: impl IntoIterator<Item = u32>,
        ray: &Ray,
        r: &RayF64,
        t_max: &mut f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        closest_of::<ANY>(ids, t_max, |id, t_max| {
            let h = match self.analytic.get(id as usize) {
                Some(Analytic::Sphere(s)) => s.intersect_f64(r, t_max),
                Some(Analytic::Rectangle(p)) => p.intersect_f64(r, t_max),
                _ => return self.test_other::<ANY>(id, ray, t_max, stats),
            };
            // An any-hit query reports what `test_primitive` would.
            h.map(|h| if ANY { PrimHit::any_hit(t_max) } else { h })
        })
    }

    /// The primitives without a table entry, out of line: inlined, the dispatch over every kind
    /// of shape kept the compiler from inlining the table's tests into the leaf loop.
    #[inline(never)]
    fn test_other<const ANY: bool>(
        &self,
        id: u32,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<PrimHit> {
        test_primitive::<Self, ANY>(self, id as usize, ray, t_max, stats)
    }

    /// The `shapeid` and `primid` a hit reports: its `[[shape]]` (for an instance, its `[[instance]]`
    /// entry) and its primitive's index in the source file.
    pub fn source_ids(&self, hit: &SceneHit) -> (u32, u32) {
        if hit.instance != NO_INSTANCE {
            let inner = self.prototype_of(hit.instance);
            let (_, prim) = inner.geometry.source_ids(&SceneHit {
                instance: NO_INSTANCE,
                ..*hit
            });
            let instance = &self.instances[hit.instance as usize];
            return (instance.source, instance.first_prim + prim);
        }
        let src = &self.shapes[hit.shape as usize].source;
        let prim = match &src.prim_table {
            Some(table) => table[hit.prim as usize],
            None => src.first_prim + hit.prim,
        };
        (src.shape, prim)
    }

    /// The material of the surface hit (an index into the scene's materials).
    #[inline]
    pub fn material(&self, hit: &SceneHit) -> u32 {
        let shapes = if hit.instance == NO_INSTANCE {
            &self.shapes
        } else {
            &self.prototype_of(hit.instance).geometry.shapes
        };
        shapes[hit.shape as usize].material
    }

    fn prototype_of(&self, instance: u32) -> &Prototype {
        &self.prototypes[self.instances[instance as usize].prototype as usize]
    }

    /// Adds the placements of one `[[instance]]` entry, which AOVs report as shape `source`;
    /// returns its shape id.
    pub fn push_instances(
        &mut self,
        source: u32,
        instances: impl IntoIterator<Item = Instance>,
    ) -> u32 {
        let id = self.shapes.len() as u32;
        let first = self.instances.len() as u32;
        self.instances
            .extend(instances.into_iter().map(|i| Instance { source, ..i }));
        let last = self.instances.len() as u32;
        self.prims.push_run(id, first, last - first);
        self.shapes.push(Shape {
            kind: ShapeKind::Instances,
            material: 0,
            source: ShapeSource {
                shape: source,
                ..Default::default()
            },
        });
        id
    }

    pub fn push_mesh(&mut self, mesh: TriangleMesh, material: u32) -> u32 {
        self.meshes.push(mesh);
        self.push(ShapeKind::Mesh(self.meshes.len() as u32 - 1), material)
    }

    pub fn push_implicit(
        &mut self,
        implicit: Implicit,
        transform: Option<ObjectTransform>,
        material: u32,
    ) -> u32 {
        self.implicits.push(implicit);
        self.implicit_transforms.push(transform);
        self.push(
            ShapeKind::Implicit(self.implicits.len() as u32 - 1),
            material,
        )
    }

    /// Triangles stored: the scene's meshes and the prototypes', each counted once however often it
    /// is instanced.
    pub fn triangle_count(&self) -> usize {
        self.meshes
            .iter()
            .map(|m| m.triangle_count())
            .sum::<usize>()
            + self
                .prototypes
                .iter()
                .map(|p| p.geometry.triangle_count())
                .sum::<usize>()
    }

    /// Bytes of what the structures are built over: the meshes (the prototypes' too, with their
    /// tangents) and the
    /// primitive list; not the structures themselves (nor the prototypes'), which report their own.
    pub fn bytes(&self) -> usize {
        self.meshes.iter().map(TriangleMesh::bytes).sum::<usize>()
            + self
                .mesh_tangents
                .iter()
                .flatten()
                .map(|t| std::mem::size_of_val(t.as_slice()))
                .sum::<usize>()
            + self.prims.bytes()
            + self
                .prototypes
                .iter()
                .map(|p| p.geometry.bytes())
                .sum::<usize>()
    }

    /// Triangles as rendered: each instance counts its prototype's triangles once more.
    pub fn instanced_triangle_count(&self) -> u64 {
        let per_prototype: Vec<u64> = self
            .prototypes
            .iter()
            .map(|p| p.geometry.triangle_count() as u64)
            .collect();
        let instanced: u64 = self
            .instances
            .iter()
            .map(|i| per_prototype[i.prototype as usize])
            .sum();
        self.meshes
            .iter()
            .map(|m| m.triangle_count() as u64)
            .sum::<u64>()
            + instanced
    }

    /// Bounds of everything bounded.
    pub fn bounds(&self) -> Aabb {
        (0..self.prims.len()).fold(Aabb::EMPTY, |b, i| b.union(Primitives::bounds(self, i)))
    }

    #[inline]
    fn intersect_shape(
        &self,
        shape: u32,
        index: u32,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<PrimHit> {
        match &self.shapes[shape as usize].kind {
            ShapeKind::Sphere(s) => s.intersect(ray, t_max),
            ShapeKind::Plane(p) => p.intersect(ray, t_max),
            ShapeKind::Mesh(m) => {
                self.meshes[*m as usize].intersect(index as usize, ray, t_max, self.triangle_test)
            }
            ShapeKind::Implicit(i) => {
                let f = &self.implicits[*i as usize];
                match &self.implicit_transforms[*i as usize] {
                    Some(x) => f.intersect(&x.ray_to_object(ray), t_max),
                    None => f.intersect(ray, t_max),
                }
            }
            ShapeKind::Torus(t) => t.intersect(ray, t_max),
            ShapeKind::Cylinder(c) => c.intersect(ray, t_max),
            ShapeKind::SdfGrid(g) => g.intersect(ray, t_max),
            ShapeKind::Instances => {
                let instance = &self.instances[index as usize];
                self.prototypes[instance.prototype as usize].intersect(instance, ray, t_max, stats)
            }
        }
    }

    /// Closest hit among the unbounded shapes nearer than `t_max`.
    pub fn intersect_unbounded(&self, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        let mut best = None;
        let mut t_max = t_max;
        for &shape in &self.unbounded {
            // Unbounded shapes are planes: nothing to count.
            let mut none = TraversalStats::default();
            if let Some(h) = self.intersect_shape(shape, 0, ray, t_max, &mut none) {
                t_max = h.t;
                best = Some(SceneHit {
                    t: h.t,
                    shape,
                    prim: 0,
                    u: h.u,
                    v: h.v,
                    instance: NO_INSTANCE,
                });
            }
        }
        best
    }

    /// Whether every primitive is a sphere or a rectangle (of the flat tables `intersect_all`
    /// tests first), so that a packet can be tested on them alone.
    #[inline(always)]
    fn only_spheres_and_rectangles(&self) -> bool {
        self.others.is_empty() && self.analytic.len() == self.prims.len()
    }

    /// Whether the scene has unbounded shapes (planes), which its queries test after the structure.
    #[inline(always)]
    pub fn has_unbounded(&self) -> bool {
        !self.unbounded.is_empty()
    }

    pub fn occluded_unbounded(&self, ray: &Ray, t_max: f32) -> bool {
        // Unbounded shapes are planes: nothing to count.
        let mut none = TraversalStats::default();
        self.unbounded
            .iter()
            .any(|&s| self.intersect_shape(s, 0, ray, t_max, &mut none).is_some())
    }

    /// Turns an acceleration-structure hit into a scene hit. Inlined into each query: out of line,
    /// its call and the copy of its result would cost more than its own work.
    #[inline(always)]
    pub fn scene_hit(&self, hit: Hit) -> SceneHit {
        let r = self.prims.get(hit.prim as usize);
        if let ShapeKind::Instances = self.shapes[r.shape as usize].kind {
            let inner = self
                .prototype_of(r.index)
                .geometry
                .prims
                .get(hit.sub as usize);
            return SceneHit {
                t: hit.t,
                shape: inner.shape,
                prim: inner.index,
                u: hit.u,
                v: hit.v,
                instance: r.index,
            };
        }
        SceneHit {
            t: hit.t,
            shape: r.shape,
            prim: r.index,
            u: hit.u,
            v: hit.v,
            instance: NO_INSTANCE,
        }
    }

    /// Gives mesh `mesh` (an index into `meshes`) its attributes.
    pub fn set_mesh_attributes(&mut self, mesh: u32, attributes: Vec<MeshAttribute>) {
        let m = mesh as usize;
        if self.mesh_attributes.len() <= m {
            self.mesh_attributes.resize(m + 1, None);
        }
        self.mesh_attributes[m] = Some(std::sync::Arc::new(attributes));
    }

    /// Gives mesh `mesh` (an index into `meshes`) per-vertex tangents, one per position.
    pub fn set_mesh_tangents(&mut self, mesh: u32, tangents: Vec<glam::Vec4>) {
        let m = mesh as usize;
        debug_assert_eq!(tangents.len(), self.meshes[m].positions.len());
        if self.mesh_tangents.len() <= m {
            self.mesh_tangents.resize(m + 1, None);
        }
        self.mesh_tangents[m] = Some(tangents);
    }

    /// The mesh attributes at a hit, where the surface hit has them.
    #[inline]
    pub fn attributes_at(&self, hit: &SceneHit) -> Option<AttributePoint<'_>> {
        let geometry = if hit.instance != NO_INSTANCE {
            let instance = &self.instances[hit.instance as usize];
            &self.prototypes[instance.prototype as usize].geometry
        } else {
            self
        };
        let ShapeKind::Mesh(m) = geometry.shapes[hit.shape as usize].kind else {
            return None;
        };
        let attributes = geometry.mesh_attributes.get(m as usize)?.as_deref()?;
        let vertices = geometry.meshes[m as usize].indices[hit.prim as usize];
        Some(AttributePoint {
            attributes,
            triangle: hit.prim,
            vertices,
            barycentrics: [1.0 - hit.u - hit.v, hit.u, hit.v],
        })
    }

    pub fn interaction(&self, ray: &Ray, hit: &SceneHit) -> SurfaceInteraction {
        self.interaction_with(ray, hit, true)
    }

    /// [`Self::interaction`]; surfaces whose texture coordinates are costly (spheres) skip them and
    /// leave `uv` at zero unless `with_uv`.
    ///
    /// Inlined with the spheres' and rectangles' own, so the interaction is built in its caller's
    /// place: returned through memory, it was written a coordinate at a time and copied on with
    /// wider loads, which stalled store-to-load forwarding (a tenth of the Whitted frame, perf).
    #[inline(always)]
    pub fn interaction_with(&self, ray: &Ray, hit: &SceneHit, with_uv: bool) -> SurfaceInteraction {
        if hit.instance != NO_INSTANCE {
            return self.instance_interaction(ray, hit, with_uv);
        }
        let ph = PrimHit {
            t: hit.t,
            u: hit.u,
            v: hit.v,
            sub: 0,
        };
        match &self.shapes[hit.shape as usize].kind {
            ShapeKind::Sphere(s) => {
                let mut si = s.interaction_with(ray, &ph, with_uv);
                if let Some(Some(rows)) = self.sphere_uv_frames.get(hit.shape as usize) {
                    if with_uv {
                        mitsuba_sphere_uv(&mut si, s, rows);
                    }
                }
                si
            }
            ShapeKind::Plane(p) => p.interaction(ray, &ph),
            ShapeKind::Mesh(m) => {
                let mesh = &self.meshes[*m as usize];
                let mut si = mesh.interaction(hit.prim as usize, &ph);
                if let Some(Some(tangents)) = self.mesh_tangents.get(*m as usize) {
                    let tri = mesh.indices[hit.prim as usize];
                    si.tangent = FileTangent::at(tangents, tri, hit.u, hit.v);
                }
                si
            }
            ShapeKind::Implicit(i) => {
                let f = &self.implicits[*i as usize];
                match &self.implicit_transforms[*i as usize] {
                    Some(x) => x.interaction_to_world(&f.interaction(&x.ray_to_object(ray), &ph)),
                    None => f.interaction(ray, &ph),
                }
            }
            ShapeKind::Torus(t) => t.interaction(ray, &ph),
            ShapeKind::Cylinder(c) => c.interaction(ray, &ph),
            ShapeKind::SdfGrid(g) => g.interaction(ray, &ph),
            ShapeKind::Instances => unreachable!("instance hits are handled above"),
        }
    }
}

impl Geometry {
    /// [`Geometry::interaction_with`] of a hit inside an instance, out of line (it recurses).
    #[inline(never)]
    /// The unit geometric normal at a hit: the `n` of [`Self::interaction_with`], computed alone
    /// for mesh triangles (instanced or not), whose full interaction costs several times more.
    pub fn geometric_normal(&self, ray: &Ray, hit: &SceneHit) -> Vec3 {
        if hit.instance != NO_INSTANCE {
            let instance = &self.instances[hit.instance as usize];
            let x = &instance.transform;
            let inner = SceneHit {
                instance: NO_INSTANCE,
                ..*hit
            };
            let prototype = &self.prototypes[instance.prototype as usize].geometry;
            return x.normal_to_world(prototype.geometric_normal(&x.ray_to_object(ray), &inner));
        }
        if let ShapeKind::Mesh(m) = &self.shapes[hit.shape as usize].kind {
            return self.meshes[*m as usize].geometric_normal(hit.prim as usize, hit.u, hit.v);
        }
        self.interaction_with(ray, hit, false).n
    }

    fn instance_interaction(&self, ray: &Ray, hit: &SceneHit, with_uv: bool) -> SurfaceInteraction {
        let instance = &self.instances[hit.instance as usize];
        let x = &instance.transform;
        let inner = SceneHit {
            instance: NO_INSTANCE,
            ..*hit
        };
        let prototype = &self.prototypes[instance.prototype as usize].geometry;
        let si = prototype.interaction_with(&x.ray_to_object(ray), &inner, with_uv);
        x.interaction_to_world(&si)
    }
}

/// Mitsuba 3's sphere parameterisation at `si`: with `l` the unit normal in the sphere's frame
/// (`rows` holds its axes), u = phi / 2 pi (phi = atan2(l.y, l.x) in [0, 2 pi)), v = theta / pi
/// (theta = acos(l.z)); dp/du = 2 pi r (-l.y, l.x, 0) and dp/dv = pi r (l.z cos phi, l.z sin phi,
/// -sin theta), carried back to the world.
fn mitsuba_sphere_uv(si: &mut SurfaceInteraction, s: &Sphere, rows: &glam::Mat3) {
    use std::f32::consts::PI;
    let to_world = rows.transpose();
    let l = (*rows * si.n).normalize();
    let mut phi = l.y.atan2(l.x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let theta = l.z.clamp(-1.0, 1.0).acos();
    si.uv = crate::math::Vec2::new(phi / (2.0 * PI), theta / PI);
    let r = s.radius;
    si.dpdu = to_world * (2.0 * PI * r * Vec3::new(-l.y, l.x, 0.0));
    let sin_theta = l.x.hypot(l.y);
    let (cos_phi, sin_phi) = if sin_theta > 0.0 {
        (l.x / sin_theta, l.y / sin_theta)
    } else {
        (1.0, 0.0)
    };
    si.dpdv = to_world * (PI * r * Vec3::new(l.z * cos_phi, l.z * sin_phi, -sin_theta));
}

/// Makes hit `h` of primitive `id` the nearest so far (for an any-hit query, the stand-in that
/// [`test_primitive`] reports); `true` when an any-hit query has its answer.
/// [`Geometry::intersect_all`] of four rays in the lanes of AVX2 registers, for a set of only
/// spheres and rectangles: each primitive in `intersect_all`'s order tested on every lane still
/// looking ([`crate::geometry::Sphere::intersect_f64x4`], `Plane::intersect_f64x4`: the scalar
/// tests' operations lane by lane), each lane's `t_max` narrowed at its hits as `record` narrows
/// it, so each lane's hit is the scalar query's.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn analytic_packet<const ANY: bool>(
    g: &Geometry,
    avx: Avx2,
    rays: &[Ray; LEAF_PACKET],
    active: u32,
    t_max: &mut [f32; LEAF_PACKET],
    out: &mut [Option<Hit>; LEAF_PACKET],
) {
    let r = RayF64x4::new(avx, rays);
    let limit = *t_max;
    let mut looking = active;
    let mut found = 0u32;
    let mut ids = [0u32; LEAF_PACKET];
    let mut t = [0.0f32; LEAF_PACKET];
    // `record`'s narrowing, lane by lane.
    macro_rules! record {
        ($lanes:expr, $id:expr) => {
            let lanes = $lanes;
            if lanes != 0 {
                found |= lanes;
                for k in 0..LEAF_PACKET {
                    if lanes & (1 << k) != 0 {
                        ids[k] = $id;
                        if !ANY {
                            t_max[k] = t[k];
                        }
                    }
                }
                if ANY {
                    looking &= !lanes;
                }
            }
        };
    }
    for block in &g.sphere_blocks {
        for k in 0..block.count() {
            let (sphere, id) = block.get(k);
            if looking != 0 {
                record!(sphere.intersect_f64x4(&r, looking, t_max, &mut t), id);
            }
        }
    }
    for (rectangle, id) in &g.rectangles {
        if looking != 0 {
            record!(rectangle.intersect_f64x4(&r, looking, t_max, &mut t), *id);
        }
    }
    for k in 0..LEAF_PACKET {
        if active & (1 << k) == 0 {
            continue;
        }
        out[k] = if found & (1 << k) != 0 {
            let t = if ANY { limit[k] } else { t_max[k] };
            Some(Hit::new(ids[k] as usize, PrimHit::any_hit(t)))
        } else {
            None
        };
    }
}

#[inline(always)]
fn record<const ANY: bool>(best: &mut Option<Hit>, t_max: &mut f32, id: u32, h: PrimHit) -> bool {
    if ANY {
        *best = Some(Hit::new(id as usize, PrimHit::any_hit(*t_max)));
        return true;
    }
    *t_max = h.t;
    *best = Some(Hit::new(id as usize, h));
    false
}

impl Primitives for Geometry {
    fn count(&self) -> usize {
        self.prims.len()
    }

    /// An instance answers a shadow ray with its own structure's any-hit query, which stops at the
    /// first triangle it finds.
    fn occluded(&self, i: usize, ray: &Ray, t_max: f32) -> bool {
        self.occluded_counted(i, ray, t_max, &mut TraversalStats::default())
    }

    fn occluded_counted(
        &self,
        i: usize,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> bool {
        let r = self.prims.get(i);
        match &self.shapes[r.shape as usize].kind {
            ShapeKind::Instances => {
                let instance = &self.instances[r.index as usize];
                self.prototypes[instance.prototype as usize].occluded(instance, ray, t_max, stats)
            }
            _ => self
                .intersect_shape(r.shape, r.index, ray, t_max, stats)
                .is_some(),
        }
    }

    fn bounds(&self, i: usize) -> Aabb {
        let r = self.prims.get(i);
        match &self.shapes[r.shape as usize].kind {
            ShapeKind::Sphere(s) => s.bounds(),
            ShapeKind::Plane(p) => p.bounds().unwrap_or(Aabb::EMPTY),
            ShapeKind::Mesh(m) => self.meshes[*m as usize].triangle_bounds(r.index as usize),
            ShapeKind::Implicit(i) => {
                let b = self.implicits[*i as usize].bounds;
                match &self.implicit_transforms[*i as usize] {
                    Some(x) => x.bounds_to_world(b),
                    None => b,
                }
            }
            ShapeKind::Torus(t) => t.bounds(),
            ShapeKind::Cylinder(c) => c.bounds(),
            ShapeKind::SdfGrid(g) => g.bounds(),
            ShapeKind::Instances => {
                let instance = &self.instances[r.index as usize];
                let prototype = &self.prototypes[instance.prototype as usize];
                instance.transform.bounds_to_world(prototype.bounds)
            }
        }
    }

    #[inline]
    fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit> {
        self.intersect_counted(i, ray, t_max, &mut TraversalStats::default())
    }

    /// A mesh instance's primitive adds its prototype's traversal to `stats`.
    #[inline]
    fn intersect_counted(
        &self,
        i: usize,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<PrimHit> {
        let r = self.prims.get(i);
        self.intersect_shape(r.shape, r.index, ray, t_max, stats)
    }

    /// Spheres and rectangles straight from their table, from one f64 ray: in a scene of a few
    /// such shapes (one leaf), the way to each test cost about as much as the test.
    #[inline(always)]
    fn intersect_ids<const ANY: bool>(
        &self,
        ids: impl IntoIterator<Item = u32>,
        ray: &Ray,
        t_max: &mut f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        self.intersect_ids_f64::<ANY>(ids, ray, &RayF64::new(ray), t_max, stats)
    }

    /// The spheres by blocks ([`SphereBlock`]), then the rectangles, each from one f64 ray and
    /// without a per-primitive dispatch, then the other primitives one by one.
    #[inline(always)]
    fn intersect_all<const ANY: bool>(
        &self,
        ray: &Ray,
        t_max: &mut f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit> {
        let r = RayF64::new(ray);
        let mut best = None;
        for block in &self.sphere_blocks {
            let mut lanes = block.candidates(&r);
            while lanes != 0 {
                let (sphere, id) = block.get(lanes.trailing_zeros() as usize);
                lanes &= lanes - 1;
                if let Some(h) = sphere.intersect_f64(&r, *t_max) {
                    if record::<ANY>(&mut best, t_max, id, h) {
                        return best;
                    }
                }
            }
        }
        for (rectangle, id) in &self.rectangles {
            if let Some(h) = rectangle.intersect_f64(&r, *t_max) {
                if record::<ANY>(&mut best, t_max, *id, h) {
                    return best;
                }
            }
        }
        let runs = self.analytic.len() as u32..self.prims.len() as u32;
        let others = self.others.iter().copied().chain(runs);
        self.intersect_ids_f64::<ANY>(others, ray, &r, t_max, stats)
            .or(best)
    }

    /// Spheres and rectangles four rays at a time in AVX2 ([`analytic_packet`]) where the set is
    /// made of nothing else; otherwise, or without AVX2, lane by lane.
    #[inline(always)]
    fn intersect_all_packet<const ANY: bool>(
        &self,
        rays: &[Ray; LEAF_PACKET],
        active: u32,
        t_max: &mut [f32; LEAF_PACKET],
        out: &mut [Option<Hit>; LEAF_PACKET],
        stats: &mut TraversalStats,
    ) {
        #[cfg(target_arch = "x86_64")]
        if let (true, Some(avx)) = (self.only_spheres_and_rectangles(), Avx2::detect()) {
            // SAFETY: the token says the CPU has AVX2.
            unsafe { analytic_packet::<ANY>(self, avx, rays, active, t_max, out) };
            return;
        }
        for k in 0..LEAF_PACKET {
            if active & (1 << k) != 0 {
                out[k] = self.intersect_all::<ANY>(&rays[k], &mut t_max[k], stats);
            }
        }
    }

    fn clip_overlaps(&self, i: usize, cell: &Aabb) -> bool {
        let r = self.prims.get(i);
        match &self.shapes[r.shape as usize].kind {
            ShapeKind::Mesh(m) => {
                triangle_box_overlap(self.meshes[*m as usize].vertices(r.index as usize), cell)
            }
            _ => true,
        }
    }

    #[inline]
    fn watertight_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
        let r = self.prims.get(i);
        match &self.shapes[r.shape as usize].kind {
            ShapeKind::Mesh(m) if self.triangle_test == TriangleTest::Watertight => {
                Some(self.meshes[*m as usize].vertices(r.index as usize))
            }
            _ => None,
        }
    }

    #[inline]
    fn moller_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
        let r = self.prims.get(i);
        match &self.shapes[r.shape as usize].kind {
            ShapeKind::Mesh(m) if self.triangle_test == TriangleTest::Moller => {
                Some(self.meshes[*m as usize].vertices(r.index as usize))
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::testutil::{mesh, rays, soup};
    use crate::math::{offset_ray_origin, Vec2};

    /// `intersect_all` (spheres two at a time, rectangles, then the rest) finds what testing each
    /// primitive in turn finds: the same primitive at the same `t` for closest hits, and the same
    /// answer for any-hit queries, on rays from everywhere, from inside spheres and leaving their
    /// surfaces, and with `t_max` limits.
    #[test]
    fn intersect_all_finds_the_hits_of_one_by_one() {
        let mut g = Geometry::new(TriangleTest::Watertight);
        for i in 0..5 {
            let c = Vec3::new(i as f32 * 0.9 - 1.8, 0.3 * i as f32 - 0.6, 0.2);
            g.push(ShapeKind::Sphere(Sphere::new(c, 0.2 + 0.1 * i as f32)), 0);
        }
        let floor = Plane::rectangle(-Vec3::Y, Vec3::Y, Some(Vec2::new(4.0, 3.0)));
        let tilted = Plane::rectangle(-Vec3::Z, Vec3::new(0.2, 0.1, 1.0), Some(Vec2::ONE));
        g.push(ShapeKind::Plane(floor), 0);
        g.push(ShapeKind::Torus(Torus::new(Vec3::X, 0.5, 0.1, Vec3::Y)), 0);
        g.push(ShapeKind::Plane(tilted), 0);
        g.push_mesh(soup(30, 3), 0);
        let mut tested = rays(3000, 11);
        // Rays leaving sphere surfaces, to either side, as secondary rays do.
        for (i, ray) in tested.clone().iter().enumerate() {
            let mut t = f32::INFINITY;
            if let Some(h) = g.intersect_all::<false>(ray, &mut t, &mut TraversalStats::default()) {
                let si = g.interaction(ray, &g.scene_hit(h));
                let w = if i % 2 == 0 { si.n } else { -si.n } + 0.5 * ray.dir;
                tested.push(Ray::new(offset_ray_origin(si.p, si.p_error, si.n, w), w));
            }
        }
        let mut hits = 0;
        for (i, ray) in tested.iter().enumerate() {
            let limit = if i % 3 == 0 { 1.5 } else { f32::INFINITY };
            let one_by_one = |t_max: &mut f32| {
                closest_of::<false>(0..g.count() as u32, t_max, |id, t| {
                    g.intersect(id as usize, ray, t)
                })
            };
            let (mut t_all, mut t_one) = (limit, limit);
            let all = g.intersect_all::<false>(ray, &mut t_all, &mut TraversalStats::default());
            let one = one_by_one(&mut t_one);
            let key = |h: Option<Hit>| h.map(|h| (h.prim, h.t.to_bits()));
            assert_eq!(key(all), key(one), "ray {i}: {ray:?}");
            let mut t_any = limit;
            assert_eq!(
                g.intersect_all::<true>(ray, &mut t_any, &mut TraversalStats::default())
                    .is_some(),
                one.is_some()
            );
            hits += one.is_some() as usize;
        }
        assert!(hits > tested.len() / 4, "{hits} of {}", tested.len());
    }

    /// Shapes of one primitive come first, then each mesh as a run, in the order pushed; every
    /// primitive maps to its shape and index, and the runs cost bytes per shape, not per triangle.
    #[test]
    fn primitive_references_are_runs_after_the_single_shapes() {
        let mut g = Geometry::new(TriangleTest::Watertight);
        let a = g.push_mesh(soup(5, 1), 0);
        let s = g.push(ShapeKind::Sphere(Sphere::new(Vec3::ZERO, 1.0)), 0);
        let b = g.push_mesh(mesh(vec![]), 0);
        let c = g.push_mesh(soup(3, 2), 0);
        let t = g.push(ShapeKind::Sphere(Sphere::new(Vec3::X, 1.0)), 0);
        let want: Vec<PrimRef> = [(s, 0), (t, 0)]
            .into_iter()
            .chain((0..5).map(|i| (a, i)))
            .chain((0..3).map(|i| (c, i)))
            .map(|(shape, index)| PrimRef { shape, index })
            .collect();
        assert_eq!(g.prims.iter().collect::<Vec<_>>(), want);
        assert_eq!(g.prims.len(), 10);
        // The empty mesh (mesh 1) adds no run.
        assert!(matches!(g.shapes[b as usize].kind, ShapeKind::Mesh(1)));
        assert!(g.meshes[1].indices.is_empty());
        assert!(g.prims.bytes() < 2 * 8 + 3 * 12);
        // The structures see the same primitives in that order.
        for (i, r) in want.iter().enumerate() {
            let want_bounds = match r.shape {
                x if x == a || x == c => {
                    let m = if x == a { 0 } else { 2 };
                    g.meshes[m].triangle_bounds(r.index as usize)
                }
                _ => Primitives::bounds(&g, i),
            };
            assert_eq!(Primitives::bounds(&g, i), want_bounds);
        }
    }
}
