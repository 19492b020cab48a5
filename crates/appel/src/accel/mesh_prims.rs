//! The triangles of one mesh as [`Primitives`]: for tests, benchmarks and tools that have a bare mesh.

use super::Primitives;
use crate::geometry::{triangle_box_overlap, PrimHit, TriangleMesh, TriangleTest};
use crate::math::{Aabb, Ray, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct MeshPrimitives<'a> {
    pub mesh: &'a TriangleMesh,
    pub test: TriangleTest,
}

impl<'a> MeshPrimitives<'a> {
    pub fn new(mesh: &'a TriangleMesh) -> Self {
        Self {
            mesh,
            test: TriangleTest::default(),
        }
    }
}

impl Primitives for MeshPrimitives<'_> {
    fn count(&self) -> usize {
        self.mesh.triangle_count()
    }

    fn bounds(&self, i: usize) -> Aabb {
        self.mesh.triangle_bounds(i)
    }

    #[inline]
    fn intersect(&self, i: usize, ray: &Ray, t_max: f32) -> Option<PrimHit> {
        self.mesh.intersect(i, ray, t_max, self.test)
    }

    fn clip_overlaps(&self, i: usize, cell: &Aabb) -> bool {
        triangle_box_overlap(self.mesh.vertices(i), cell)
    }

    #[inline]
    fn watertight_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
        (self.test == TriangleTest::Watertight).then(|| self.mesh.vertices(i))
    }

    #[inline]
    fn moller_triangle(&self, i: usize) -> Option<[Vec3; 3]> {
        (self.test == TriangleTest::Moller).then(|| self.mesh.vertices(i))
    }
}
