//! The octree's unit tests: agreement with brute force, adaptivity, order and early exit.

use super::*;
use crate::accel::testutil::{agrees_with_brute, mesh, prims, rays, soup, Rng};
use crate::geometry::TriangleMesh;

fn check(m: &TriangleMesh, opts: OctreeOptions) -> (Octree, usize) {
    let p = prims(m);
    let o = Octree::build_with(&p, opts);
    let hits = agrees_with_brute(
        &p,
        &rays(400, 23),
        |r, t, s| o.intersect(&p, r, t, s),
        |r, t, s| o.occluded(&p, r, t, s),
    );
    (o, hits)
}

#[test]
fn agrees_with_brute_force_at_several_leaf_sizes_and_depths() {
    let m = soup(2000, 5);
    for (max_prims, max_depth) in [(1, 24), (8, 16), (8, 2), (64, 16)] {
        let (o, hits) = check(
            &m,
            OctreeOptions {
                max_prims,
                max_depth,
            },
        );
        assert!(hits > 200, "{hits}");
        let s = o.stats();
        assert!(s.depth <= max_depth);
        // Interior nodes have eight children each: the node count is 1 + 8 * interior.
        assert_eq!(o.nodes.len(), 1 + 8 * s.nodes);
        assert_eq!(s.nodes + s.leaves, o.nodes.len());
        // Every primitive is in some leaf.
        let mut listed = vec![false; 2000];
        for &i in &o.items {
            listed[i as usize] = true;
        }
        assert!(listed.iter().all(|&l| l));
    }
}

#[test]
fn empty_single_and_coincident_inputs() {
    let (empty, _) = check(&mesh(vec![]), OctreeOptions::default());
    assert!(empty.nodes.is_empty());
    let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let (one, _) = check(&mesh(vec![t]), OctreeOptions::default());
    assert_eq!(one.nodes.len(), 1);
    // 300 copies of one triangle larger than the cells: every split copies all of them into
    // several octants, which the copy limit refuses.
    let (same, hits) = check(&mesh(vec![t; 300]), OctreeOptions::default());
    assert!(hits > 0);
    assert!(same.items.len() <= 300 * 4, "{}", same.items.len());
    // All at one point: a chain of cells down to the depth limit, not a blow-up.
    let (point, _) = check(&mesh(vec![[Vec3::ONE; 3]; 50]), OctreeOptions::default());
    assert!(point.items.len() <= 50 * 8 * 4, "{}", point.items.len());
}

/// A dense ball of small triangles in the middle of a box of large ones (the teapot in the
/// stadium): the octree refines only around the ball, and a ray into it tests a few triangles.
#[test]
fn refines_where_the_geometry_is() {
    let mut tris = Vec::new();
    let mut r = Rng(9);
    for _ in 0..4000 {
        let c = r.v(-0.05, 0.05);
        tris.push([c, c + r.v(-0.004, 0.004), c + r.v(-0.004, 0.004)]);
    }
    // A floor and a ceiling of 2 triangles each, 100 times the ball's size.
    for y in [-5.0, 5.0] {
        let p = |x: f32, z: f32| Vec3::new(x, y, z);
        tris.push([p(-5.0, -5.0), p(5.0, -5.0), p(5.0, 5.0)]);
        tris.push([p(-5.0, -5.0), p(5.0, 5.0), p(-5.0, 5.0)]);
    }
    let m = mesh(tris);
    let p = prims(&m);
    let o = Octree::build(&p);
    let s = o.stats();
    assert!(s.depth >= 8, "{}", s.depth);
    // A uniform grid of that depth would have 8^8 cells; the octree has few.
    assert!(s.leaves < 10_000, "{}", s.leaves);
    let mut st = TraversalStats::default();
    let mut hits = 0;
    for k in 0..200 {
        let o2 = Vec3::new(-3.0, 0.0, 0.0);
        let target = Vec3::new(
            0.0,
            (k % 20) as f32 * 0.004 - 0.04,
            (k / 20) as f32 * 0.008 - 0.04,
        );
        let ray = Ray::new(o2, target - o2);
        hits += o.intersect(&p, &ray, f32::INFINITY, &mut st).is_some() as usize;
    }
    assert!(hits > 100, "{hits}");
    let tests = st.prim_tests as f64 / st.rays as f64;
    assert!(tests < 50.0, "{tests} tests per ray of {}", m.indices.len());
}

/// A ray down a row of 40 parallel walls stops in the cell of the first: front-to-back order
/// and the early exit. A wall across the whole scene is listed in many cells and tested once.
#[test]
fn stops_at_the_first_wall_and_tests_each_wall_once() {
    let mut tris = Vec::new();
    for k in 0..40 {
        let x = k as f32 * 0.1;
        let p = |y: f32, z: f32| Vec3::new(x, y, z);
        tris.push([p(-1.0, -1.0), p(1.0, -1.0), p(1.0, 1.0)]);
        tris.push([p(-1.0, -1.0), p(1.0, 1.0), p(-1.0, 1.0)]);
    }
    let m = mesh(tris);
    let p = prims(&m);
    let o = Octree::build_with(
        &p,
        OctreeOptions {
            max_prims: 1,
            max_depth: 6,
        },
    );
    for (dir, first) in [(Vec3::X, 0.0), (-Vec3::X, 3.9)] {
        let mut st = TraversalStats::default();
        let origin = Vec3::new(if dir.x > 0.0 { -1.0 } else { 5.0 }, 0.31, 0.17);
        let h = o
            .intersect(&p, &Ray::new(origin, dir), f32::INFINITY, &mut st)
            .unwrap();
        assert!((origin.x + dir.x * h.t - first).abs() < 1e-5);
        assert!(st.prim_tests <= 4, "{} tests", st.prim_tests);
    }
    // Along a wall's plane (the wall at x = 0), the ray meets that wall's two triangles in every
    // cell it crosses; the mailbox tests each once.
    let mut st = TraversalStats::default();
    let r = Ray::new(Vec3::new(0.0, -2.0, 0.3), Vec3::new(0.0, 1.0, 0.0));
    o.intersect(&p, &r, f32::INFINITY, &mut st);
    assert!(st.nodes_visited > 8);
    assert!(st.prim_tests <= 2 + 2 * 2, "{}", st.prim_tests);
}
