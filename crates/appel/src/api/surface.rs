//! Point queries over the scene's triangles in world space (instances expanded): closest point,
//! signed distance where the triangles close a volume, and inside/outside.

use super::rays::Coords;
use super::{SceneHandle, MISS};
use crate::geometry::{procedural::append, TriangleMesh};
use crate::query::InsideTester;
use crate::scene::{Scene, SceneHit, ShapeKind};
use rayon::prelude::*;
use std::collections::HashMap;

/// The scene's triangles with their ids and what answers point queries over them.
pub(super) struct Surface {
    tester: InsideTester<'static>,
    /// `(shapeid, primid, instanceid)` of each triangle.
    ids: Vec<[u32; 3]>,
    /// Whether every edge is shared by exactly two triangles that traverse it in opposite
    /// directions (vertices compared by position): a closed, consistently oriented surface.
    closed: bool,
}

/// Where the closest points go: one entry per point (`position` three).
pub struct ClosestHits<'a> {
    pub position: &'a mut [f32],
    pub distance: &'a mut [f32],
    /// Negative inside a closed surface; NaN everywhere when the surface is not closed.
    pub signed_distance: &'a mut [f32],
    pub prim_ids: &'a mut [u32],
    pub shape_ids: &'a mut [u32],
    pub instance_ids: &'a mut [u32],
}

fn world_triangles(scene: &Scene) -> (TriangleMesh, Vec<[u32; 3]>) {
    let g = &scene.geometry;
    let mut mesh = TriangleMesh::default();
    let mut ids = Vec::new();
    for (s, shape) in g.shapes.iter().enumerate() {
        let ShapeKind::Mesh(m) = shape.kind else {
            continue;
        };
        let m = &g.meshes[m as usize];
        append(&mut mesh, m);
        ids.extend((0..m.triangle_count() as u32).map(|prim| {
            let h = SceneHit {
                t: 0.0,
                shape: s as u32,
                prim,
                u: 0.0,
                v: 0.0,
                instance: MISS,
            };
            let (shape, prim) = g.source_ids(&h);
            [shape, prim, MISS]
        }));
    }
    for (k, instance) in g.instances.iter().enumerate() {
        let p = &g.prototypes[instance.prototype as usize].geometry;
        for (s, shape) in p.shapes.iter().enumerate() {
            let ShapeKind::Mesh(m) = shape.kind else {
                continue;
            };
            let m = &p.meshes[m as usize];
            let placed = TriangleMesh {
                positions: m
                    .positions
                    .iter()
                    .map(|&v| instance.transform.point_to_world(v))
                    .collect(),
                indices: m.indices.clone(),
                normals: None,
                uvs: None,
            };
            append(&mut mesh, &placed);
            ids.extend((0..m.triangle_count() as u32).map(|prim| {
                let h = SceneHit {
                    t: 0.0,
                    shape: s as u32,
                    prim,
                    u: 0.0,
                    v: 0.0,
                    instance: k as u32,
                };
                let (shape, prim) = g.source_ids(&h);
                [shape, prim, k as u32]
            }));
        }
    }
    (mesh, ids)
}

/// Whether the triangles close a consistently oriented surface.
fn is_closed(mesh: &TriangleMesh) -> bool {
    if mesh.indices.is_empty() {
        return false;
    }
    let mut weld: HashMap<[u32; 3], u32> = HashMap::new();
    let id: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            let n = weld.len() as u32;
            *weld.entry(p.to_array().map(f32::to_bits)).or_insert(n)
        })
        .collect();
    let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
    for t in &mesh.indices {
        let v = t.map(|i| id[i as usize]);
        for (a, b) in [(v[0], v[1]), (v[1], v[2]), (v[2], v[0])] {
            if a == b {
                continue;
            }
            // +1 for a -> b and -1 for b -> a on the edge (min, max).
            let (key, s) = if a < b { ((a, b), 1) } else { ((b, a), -1) };
            let e = edges.entry(key).or_insert(0);
            *e += s * 1000 + 1;
        }
    }
    // Exactly one use in each direction: +1000+1 -1000+1 = 2.
    edges.values().all(|&e| e == 2)
}

impl SceneHandle {
    fn surface(&self, scene: &Scene) -> &Surface {
        self.surface.get_or_init(|| {
            let (mesh, ids) = world_triangles(scene);
            let closed = is_closed(&mesh);
            Surface {
                tester: InsideTester::owning(mesh),
                ids,
                closed,
            }
        })
    }

    /// Whether the scene's triangles close a consistently oriented surface.
    pub fn is_closed(&self) -> bool {
        let scene = self.read();
        self.surface(&scene).closed
    }

    /// Whether each point is inside the volume the scene's triangles enclose (exact also next to
    /// the surface; see [`InsideTester`]).
    pub fn contains(&self, points: Coords, out: &mut [bool]) {
        let scene = self.read();
        let s = self.surface(&scene);
        out.par_iter_mut()
            .enumerate()
            .with_min_len(64)
            .for_each(|(i, o)| *o = s.tester.is_inside(points.get(i)));
    }

    /// The nearest point of the scene's triangles to each point, with its distance, the ids of its
    /// triangle, and the signed distance (negative inside) where the surface is closed.
    pub fn closest_point(&self, points: Coords, out: ClosestHits) {
        let scene = self.read();
        let s = self.surface(&scene);
        let ClosestHits {
            position,
            distance,
            signed_distance,
            prim_ids,
            shape_ids,
            instance_ids,
        } = out;
        position
            .par_chunks_mut(3)
            .zip(distance.par_iter_mut())
            .zip(signed_distance.par_iter_mut())
            .zip(prim_ids.par_iter_mut())
            .zip(shape_ids.par_iter_mut())
            .zip(instance_ids.par_iter_mut())
            .enumerate()
            .with_min_len(64)
            .for_each(|(i, (((((pos, d), sd), prim), shape), instance))| {
                let p = points.get(i);
                match s.tester.closest(p.as_dvec3()) {
                    None => {
                        pos.copy_from_slice(&[f32::NAN; 3]);
                        *d = f32::INFINITY;
                        *sd = f32::NAN;
                        (*prim, *shape, *instance) = (MISS, MISS, MISS);
                    }
                    Some(c) => {
                        pos.copy_from_slice(&c.point.as_vec3().to_array());
                        *d = c.distance as f32;
                        *sd = if !s.closed {
                            f32::NAN
                        } else if s.tester.is_inside(p) {
                            -*d
                        } else {
                            *d
                        };
                        [*shape, *prim, *instance] = s.ids[c.triangle as usize];
                    }
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::procedural::{cube, icosphere};

    #[test]
    fn closed_meshes_are_told_from_open_ones() {
        assert!(is_closed(&cube()));
        assert!(is_closed(&icosphere(1)));
        let mut open = icosphere(1);
        open.indices.pop();
        assert!(!is_closed(&open));
        let mut flipped = icosphere(1);
        flipped.indices[0].swap(0, 1);
        assert!(!is_closed(&flipped));
    }
}
