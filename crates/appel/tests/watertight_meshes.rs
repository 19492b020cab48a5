//! Watertightness: on closed meshes, rays from outside aimed exactly at vertices and at points on
//! edges must hit the surface no later than the aimed-at point. The watertight test (Woop et al.
//! 2013) guarantees it; Moller-Trumbore does not (its misses are counted, not asserted).

use appel::geometry::procedural::{cube, icosphere, SplitMix64};
use appel::geometry::triangle::{moller_trumbore, watertight};
use appel::geometry::TriangleMesh;
use appel::io::load_mesh;
use appel::math::{Ray, Vec3};

/// Every edge of a closed manifold mesh is shared by exactly two triangles.
fn assert_closed(mesh: &TriangleMesh) {
    let mut counts = std::collections::HashMap::new();
    for t in &mesh.indices {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *counts.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    assert!(counts.values().all(|&c| c == 2), "mesh is not closed");
}

/// The OBJ reader splits vertices along texture seams; merging bit-identical positions gives back the
/// closed surface (same triangles, same coordinates).
fn weld(mesh: &TriangleMesh) -> TriangleMesh {
    let mut ids = std::collections::HashMap::new();
    let mut positions = vec![];
    let remap: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            *ids.entry(p.to_array().map(f32::to_bits))
                .or_insert_with(|| {
                    positions.push(*p);
                    positions.len() as u32 - 1
                })
        })
        .collect();
    TriangleMesh {
        positions,
        indices: mesh
            .indices
            .iter()
            .map(|t| t.map(|i| remap[i as usize]))
            .collect(),
        normals: None,
        uvs: None,
    }
}

fn unit(rng: &mut SplitMix64) -> Vec3 {
    loop {
        let v = rng.in_box(Vec3::splat(-1.0), Vec3::ONE);
        let l = v.length_squared();
        if l > 1e-4 && l <= 1.0 {
            return v / l.sqrt();
        }
    }
}

/// Aims `rays` rays from outside at vertices, edge midpoints and random edge points. Each ray
/// travels into the solid through its target: its direction has a negative dot product with the
/// normal of every triangle around the target (the negated mean normal, jittered), so the point just
/// past the target is inside, and a segment from outside to inside must cross the surface. Rays that
/// only graze the surface at a silhouette vertex could legitimately miss and are not what
/// watertightness is about. Returns (watertight misses, Moller misses).
fn shoot(mesh: &TriangleMesh, rays: usize, seed: u64) -> (usize, usize) {
    let b = mesh.bounds();
    let radius = 0.5 * b.extent().length();
    let normals: Vec<Vec3> = (0..mesh.triangle_count())
        .map(|t| {
            let [a, b, c] = mesh.vertices(t);
            (b - a).cross(c - a).normalize()
        })
        .collect();
    let mut around_vertex: Vec<Vec<usize>> = vec![vec![]; mesh.positions.len()];
    let mut around_edge: std::collections::BTreeMap<(u32, u32), Vec<usize>> = Default::default();
    for (t, tri) in mesh.indices.iter().enumerate() {
        for k in 0..3 {
            around_vertex[tri[k] as usize].push(t);
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            around_edge.entry((a.min(b), a.max(b))).or_default().push(t);
        }
    }
    let edges: Vec<((u32, u32), Vec<usize>)> = around_edge.into_iter().collect();
    let mut rng = SplitMix64(seed);
    let (mut miss_w, mut miss_m) = (0, 0);
    for i in 0..rays {
        let (target, faces): (Vec3, &[usize]) = match i % 3 {
            0 => {
                let v = i / 3 % mesh.positions.len();
                (mesh.positions[v], &around_vertex[v])
            }
            1 => {
                let ((a, b), f) = &edges[i / 3 % edges.len()];
                (
                    0.5 * (mesh.positions[*a as usize] + mesh.positions[*b as usize]),
                    f,
                )
            }
            _ => {
                let ((a, b), f) = &edges[(rng.next_u64() % edges.len() as u64) as usize];
                let s = rng.next_f32();
                (
                    mesh.positions[*a as usize].lerp(mesh.positions[*b as usize], s),
                    f,
                )
            }
        };
        let mean = -faces.iter().map(|&f| normals[f]).sum::<Vec3>().normalize();
        let inward = |d: Vec3| faces.iter().all(|&f| d.dot(normals[f]) < -1e-3);
        let mut dir = mean;
        for _ in 0..8 {
            let d = (mean + 0.3 * unit(&mut rng)).normalize();
            if inward(d) {
                dir = d;
                break;
            }
        }
        assert!(inward(dir), "no inward direction at {target}");
        let origin = target - 3.0 * radius * dir;
        let dist = (target - origin).length();
        let ray = Ray::new(origin, dir);
        // The surface is hit at or before the aimed-at point (allowing for rounding of the point).
        let limit = dist * (1.0 + 1e-5);
        let hit_by = |f: fn(&Ray, f32, Vec3, Vec3, Vec3) -> Option<appel::geometry::PrimHit>| {
            (0..mesh.triangle_count()).any(|t| {
                let [p0, p1, p2] = mesh.vertices(t);
                f(&ray, limit, p0, p1, p2).is_some()
            })
        };
        if !hit_by(watertight) {
            miss_w += 1;
        }
        if !hit_by(moller_trumbore) {
            miss_m += 1;
        }
    }
    (miss_w, miss_m)
}

fn check(name: &str, mesh: &TriangleMesh, rays: usize) {
    assert_closed(mesh);
    let (w, m) = shoot(mesh, rays, 7);
    eprintln!("{name}: {rays} rays, {w} watertight misses, {m} Moller-Trumbore misses");
    assert_eq!(w, 0, "{name}: rays slipped through the watertight test");
}

#[test]
fn no_ray_slips_through_a_cube() {
    check("cube", &cube(), 100_000);
}

#[test]
fn no_ray_slips_through_an_icosphere() {
    check("icosphere(3)", &icosphere(3), 30_000);
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn no_ray_slips_through_a_shared_manifold_mesh() {
    let p = appel_testdata::path("odedstein-meshes/spot/spot_low_resolution.obj");
    let m = load_mesh(&p).unwrap();
    assert_eq!(m.parts.len(), 1);
    check("spot_low_resolution", &weld(&m.parts[0].mesh), 20_000);
}

/// The acceptance figure: a million rays per mesh (about 8 s in release mode on 2 cores).
#[test]
fn a_million_rays_per_mesh() {
    check("cube", &cube(), 1_000_000);
    check("icosphere(2)", &icosphere(2), 1_000_000);
}
