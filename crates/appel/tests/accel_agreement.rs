//! Every acceleration structure answers exactly like brute force: the same closest hit (primitive and
//! `t`; of a tie, either primitive, where a tie is equal rounded `t`s or, for coplanar triangles,
//! equal `t`s in exact arithmetic) and the same any-hit answer, on random and degenerate scenes
//! and random rays, including axis-aligned rays with `+0` and `-0` direction components.

use appel::accel::{Accel, AccelKind, Bvh, BvhOptions, MeshPrimitives, Primitives, TraversalStats};
use appel::geometry::{TriangleMesh, TriangleTest};
use appel::math::{Ray, Vec3};
use proptest::prelude::*;

fn mesh(tris: &[[Vec3; 3]]) -> TriangleMesh {
    TriangleMesh {
        positions: tris.iter().flatten().copied().collect(),
        indices: (0..tris.len() as u32)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect(),
        normals: None,
        uvs: None,
    }
}

/// Checks all structures against brute force with either triangle test (the wide BVH holds
/// watertight triangles as vertices, Moller-Trumbore ones as a vertex and two edges); returns the
/// number of (ray, t_max) pairs that hit.
fn check_all(m: &TriangleMesh, rays: &[Ray]) -> usize {
    [TriangleTest::Watertight, TriangleTest::Moller]
        .into_iter()
        .map(|test| check_all_with(MeshPrimitives { mesh: m, test }, rays))
        .sum()
}

fn check_all_with(prims: MeshPrimitives, rays: &[Ray]) -> usize {
    let brute = Accel::build(AccelKind::Brute, &prims);
    let mut others: Vec<(String, Accel)> = AccelKind::NAMES
        .iter()
        .map(|n| AccelKind::from_name(n).unwrap())
        .filter(|&k| k != AccelKind::Brute)
        .map(|k| (k.name().to_string(), Accel::build(k, &prims)))
        .collect();
    assert_eq!(others.len(), 5);
    // The default BVH is 8 wide; the binary and 4-wide layouts, and compact leaves, answer the same.
    for (width, compact) in [(2, false), (4, false), (4, true), (8, true)] {
        let opts = BvhOptions {
            width,
            compact,
            ..Default::default()
        };
        others.push((
            format!("bvh width {width} compact {compact}"),
            Accel::Bvh(Bvh::build_with(&prims, opts)),
        ));
    }
    let mut s = TraversalStats::default();
    let mut hits = 0;
    for ray in rays {
        for t_max in [f32::INFINITY, 7.0] {
            let want = brute.intersect(&prims, ray, t_max, &mut s);
            let occluded = brute.occluded(&prims, ray, t_max, &mut s);
            assert_eq!(want.is_some(), occluded);
            hits += want.is_some() as usize;
            for (kind, accel) in &others {
                let got = accel.intersect(&prims, ray, t_max, &mut s);
                match (want, got) {
                    (None, None) => {}
                    (Some(w), Some(g)) if w.prim == g.prim => {
                        assert_eq!(w.t, g.t, "{kind:?} {ray:?}: brute {w:?} got {g:?}");
                    }
                    (Some(w), Some(g)) => {
                        let tie = prims.intersect(g.prim as usize, ray, f32::INFINITY);
                        let rounded_tie = tie.map(|h| h.t) == Some(w.t) && g.t == w.t;
                        assert!(
                            rounded_tie || exact_tie(prims.mesh, ray, w.prim, g.prim),
                            "{kind:?} {ray:?} t_max {t_max}: brute {w:?} got {g:?}"
                        );
                    }
                    _ => panic!("{kind:?} {ray:?} t_max {t_max}: brute {want:?} got {got:?}"),
                }
                assert_eq!(
                    accel.occluded(&prims, ray, t_max, &mut s),
                    occluded,
                    "{kind:?} any-hit {ray:?} t_max {t_max}"
                );
            }
        }
    }
    hits
}

/// Whether the ray meets two triangles' planes at the same `t` in exact arithmetic (computed in
/// f64, far finer than the f32 tests): coplanar triangles are a tie that rounding breaks
/// differently in each triangle's own frame, and a structure that culls boxes by the first
/// tied hit's `t` may rightly keep it.
fn exact_tie(m: &TriangleMesh, ray: &Ray, a: u32, b: u32) -> bool {
    let plane_t = |prim: u32| {
        let [p0, p1, p2] = m.indices[prim as usize].map(|i| m.positions[i as usize].as_dvec3());
        let n = (p1 - p0).cross(p2 - p0);
        n.dot(p0 - ray.origin.as_dvec3()) / n.dot(ray.dir.as_dvec3())
    };
    let (ta, tb) = (plane_t(a), plane_t(b));
    (ta - tb).abs() <= 1e-12 * ta.abs().max(tb.abs())
}

fn v3(r: f32) -> impl Strategy<Value = Vec3> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn tri() -> impl Strategy<Value = [Vec3; 3]> {
    (v3(4.0), v3(1.5), v3(1.5)).prop_map(|(c, a, b)| [c, c + a, c + b])
}

/// The scene families: plain soup, and the degenerate cases structures get wrong.
#[derive(Clone, Copy, Debug)]
enum Family {
    Soup,
    Coplanar,
    Coincident,
    HugeAndTiny,
    Spanning,
    One,
    Empty,
}

fn scene() -> impl Strategy<Value = Vec<[Vec3; 3]>> {
    let family = prop_oneof![
        Just(Family::Soup),
        Just(Family::Coplanar),
        Just(Family::Coincident),
        Just(Family::HugeAndTiny),
        Just(Family::Spanning),
        Just(Family::One),
        Just(Family::Empty),
    ];
    (family, prop::collection::vec(tri(), 1..120)).prop_map(|(f, mut t)| {
        match f {
            Family::Soup => {}
            Family::Coplanar => t.iter_mut().flatten().for_each(|p| p.z = 0.5),
            Family::Coincident => {
                let first = t[0];
                t.iter_mut().for_each(|x| *x = first);
            }
            Family::HugeAndTiny => {
                for (k, x) in t.iter_mut().enumerate() {
                    let s = if k % 2 == 0 { 1e-4 } else { 30.0 };
                    let c = x[0];
                    *x = x.map(|p| c + (p - c) * s);
                }
            }
            Family::Spanning => t.push([
                Vec3::new(-6.0, -6.0, -6.0),
                Vec3::new(6.0, 6.0, -6.0),
                Vec3::new(6.0, -6.0, 6.0),
            ]),
            Family::One => t.truncate(1),
            Family::Empty => t.clear(),
        }
        t
    })
}

fn ray() -> impl Strategy<Value = Ray> {
    let axis = (0usize..3, prop::bool::ANY, prop::bool::ANY).prop_map(|(a, neg, neg_zero)| {
        let z = if neg_zero { -0.0 } else { 0.0 };
        let mut d = Vec3::splat(z);
        d[a] = if neg { -1.0 } else { 1.0 };
        d
    });
    let free = v3(1.0).prop_filter("non-zero direction", |d| d.length() > 1e-3);
    // A random direction with one component forced to a signed zero.
    let zeroed = (v3(1.0), 0usize..3, prop::bool::ANY)
        .prop_filter("non-zero direction", |(d, _, _)| d.length() > 1e-3)
        .prop_map(|(mut d, a, neg)| {
            d[a] = if neg { -0.0 } else { 0.0 };
            d
        });
    // Origins inside the scene and around it.
    (v3(9.0), prop_oneof![free, axis, zeroed]).prop_map(|(o, d)| Ray::new(o, d))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn every_structure_agrees_with_brute_force(
        tris in scene(),
        rays in prop::collection::vec(ray(), 1..60),
    ) {
        check_all(&mesh(&tris), &rays);
    }

    /// Rays aimed at a triangle's centroid, so most of them hit: the random rays above often miss.
    #[test]
    fn aimed_rays_agree(
        tris in scene(),
        aims in prop::collection::vec((v3(9.0), 0usize..1000), 1..40),
    ) {
        let m = mesh(&tris);
        let rays: Vec<Ray> = aims
            .iter()
            .filter(|_| !tris.is_empty())
            .map(|&(o, k)| {
                let t = tris[k % tris.len()];
                Ray::new(o, (t[0] + t[1] + t[2]) / 3.0 - o)
            })
            .collect();
        check_all(&m, &rays);
    }
}

/// Overlapping coplanar triangles hit by rays aimed at their centroids: every hit is a tie in exact
/// arithmetic that rounding breaks differently per triangle, the case `exact_tie` allows.
#[test]
fn overlapping_coplanar_triangles_agree() {
    let mut s = 0x9e37_79b9u32;
    let mut rnd = move || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s as f32 / u32::MAX as f32 * 2.0 - 1.0
    };
    let mut v = |r: f32| Vec3::new(rnd(), rnd(), rnd()) * r;
    let tris: Vec<[Vec3; 3]> = (0..100)
        .map(|_| {
            let (c, a, b) = (v(4.0), v(1.5), v(1.5));
            [c, c + a, c + b].map(|p| Vec3::new(p.x, p.y, 0.5))
        })
        .collect();
    let rays: Vec<Ray> = (0..2000)
        .map(|k| {
            let t = tris[k % tris.len()];
            let o = v(9.0);
            Ray::new(o, (t[0] + t[1] + t[2]) / 3.0 - o)
        })
        .collect();
    assert!(check_all(&mesh(&tris), &rays) > 3000);
}

#[test]
fn closed_mesh_agrees_and_no_ray_from_inside_escapes() {
    let m = appel::geometry::procedural::icosphere(4);
    assert_eq!(m.triangle_count(), 20 * 256);
    let mut rays = Vec::new();
    let mut s = 0x1234_5678u32;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        s as f32 / u32::MAX as f32 * 2.0 - 1.0
    };
    for k in 0..3000 {
        let o = Vec3::new(rnd(), rnd(), rnd()) * 3.0;
        let target = Vec3::new(rnd(), rnd(), rnd()) * 0.5;
        // Every third ray starts inside the sphere; every seventh is axis-aligned, through the
        // icosphere's vertices on the coordinate planes.
        let o = if k % 3 == 0 { o * 0.1 } else { o };
        let d = if k % 7 == 0 { Vec3::X } else { target - o };
        rays.push(Ray::new(o, d));
    }
    let hits = check_all(&m, &rays);
    assert!(hits > 2000, "{hits}");
    // A ray from inside always hits the closed, watertight-tested mesh.
    let prims = MeshPrimitives::new(&m);
    let mut st = TraversalStats::default();
    for kind in [
        AccelKind::Bvh,
        AccelKind::Grid,
        AccelKind::KdTree,
        AccelKind::Octree,
        AccelKind::Bsp,
    ] {
        let accel = Accel::build(kind, &prims);
        for r in rays.iter().step_by(3) {
            assert!(accel.intersect(&prims, r, f32::INFINITY, &mut st).is_some());
        }
    }
}

#[test]
fn flat_grid_of_triangles_agrees_with_rays_along_edges() {
    // Rays run exactly along shared edges and through shared vertices of a regular grid.
    let n = 20;
    let mut tris = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let p = |a: usize, b: usize| Vec3::new(a as f32, b as f32, 0.0);
            tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
            tris.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
        }
    }
    let mut rays = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let o = Vec3::new(i as f32, j as f32 + 0.5 * (i % 2) as f32, 3.0);
            rays.push(Ray::new(o, Vec3::new(0.0, -0.0, -1.0)));
            rays.push(Ray::new(o, Vec3::new(-0.0, 0.0, -1.0)));
            // Grazing: in the plane of the grid.
            rays.push(Ray::new(Vec3::new(-1.0, j as f32, 0.0), Vec3::X));
        }
    }
    let hits = check_all(&mesh(&tris), &rays);
    assert!(hits > (n + 1) * (n + 1));
}
