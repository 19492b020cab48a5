//! Instancing: a mesh declared once (`[meshes.NAME]`) is a [`Prototype`] with its own acceleration
//! structure; each placement is an [`Instance`], one primitive of the scene's top-level structure.
//! A ray reaching an instance is taken into the prototype's object space and traced through the
//! prototype's structure, so a million placements cost a million transforms, not their triangles.

use super::Geometry;
use crate::accel::{Accel, AccelKind, AccelOptions, Primitives, TraversalStats};
use crate::geometry::{InstanceTransform, PrimHit};
use crate::math::{Aabb, Ray};

/// A declared mesh: its surfaces (one per material part) and the structure over their triangles.
#[derive(Clone, Debug)]
pub struct Prototype {
    pub geometry: Geometry,
    pub accel: Accel,
    /// Object-space bounds of all its triangles.
    pub bounds: Aabb,
}

/// One placement of a prototype.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    pub transform: InstanceTransform,
    /// Index into [`Geometry::prototypes`].
    pub prototype: u32,
    /// The `shapeid` its hits report: the number of its `[[instance]]` entry (or of the
    /// `[[shape]]` whose file placed it).
    pub source: u32,
    /// Added to the prototype's triangle index for the `primid` its hits report: 0 for
    /// `[[instance]]` entries, the placement's first triangle in the file's order for meshes a
    /// glTF file places several times.
    pub first_prim: u32,
}

impl Prototype {
    /// Builds the structure of `kind` (with the scene's parameters) over the geometry's triangles.
    pub fn new(geometry: Geometry, kind: AccelKind, options: &AccelOptions) -> Self {
        let accel = Accel::build_with(kind, &geometry, options);
        let bounds = geometry.bounds();
        Self {
            geometry,
            accel,
            bounds,
        }
    }

    /// The closest hit of `ray` with `instance` of this prototype, in `(0, t_max)`. `t` is the
    /// world ray's (the object-space direction is not renormalized); `sub` names the primitive hit
    /// among the prototype's, so the interaction can be computed later. The query of the
    /// prototype's structure is added to `stats` as an instance query.
    #[inline]
    pub fn intersect(
        &self,
        instance: &Instance,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<PrimHit> {
        let local = instance.transform.ray_to_object(ray);
        let mut inner = TraversalStats::default();
        let hit = self
            .accel
            .intersect(&self.geometry, &local, t_max, &mut inner);
        stats.add_instance_query(&inner);
        hit.map(|h| PrimHit {
            t: h.t,
            u: h.u,
            v: h.v,
            sub: h.prim,
        })
    }

    /// Whether `ray` hits `instance` of this prototype in `(0, t_max)`: the structure's any-hit
    /// query, which returns at the first hit it finds (counted in `stats` as an instance query).
    #[inline]
    pub fn occluded(
        &self,
        instance: &Instance,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> bool {
        let local = instance.transform.ray_to_object(ray);
        let mut inner = TraversalStats::default();
        let hit = self
            .accel
            .occluded(&self.geometry, &local, t_max, &mut inner);
        stats.add_instance_query(&inner);
        hit
    }

    pub fn triangle_count(&self) -> usize {
        self.geometry.count()
    }
}
