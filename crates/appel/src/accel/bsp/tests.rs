//! The BSP tree's unit tests: agreement with brute force for each family of candidate planes,
//! degenerate inputs, and oblique planes where the scene is oblique.

use super::*;
use crate::accel::testutil::{agrees_with_brute, mesh, prims, rays, soup};
use crate::accel::KdTree;
use crate::geometry::TriangleMesh;

fn check(m: &TriangleMesh, opts: BspOptions) -> (Bsp, usize) {
    let p = prims(m);
    let b = Bsp::build_with(&p, opts);
    let hits = agrees_with_brute(
        &p,
        &rays(400, 29),
        |r, t, s| b.intersect(&p, r, t, s),
        |r, t, s| b.occluded(&p, r, t, s),
    );
    (b, hits)
}

#[test]
fn agrees_with_brute_force_with_each_family_of_planes() {
    let m = soup(1500, 12);
    for (triangle_planes, bins) in [(8, 8), (0, 8), (16, 0), (8, 1)] {
        let (b, hits) = check(
            &m,
            BspOptions {
                triangle_planes,
                bins,
                ..Default::default()
            },
        );
        assert!(hits > 200, "{hits}");
        let s = b.stats();
        assert!(s.nodes > 50, "{triangle_planes} {bins}: {} nodes", s.nodes);
        assert_eq!(s.nodes + s.leaves, b.nodes.len());
        let mut listed = vec![false; 1500];
        for &i in &b.items {
            listed[i as usize] = true;
        }
        assert!(listed.iter().all(|&l| l));
        if bins == 0 {
            // Only triangles' planes: a random soup has no axis-aligned triangles.
            assert_eq!(b.oblique_planes(), s.nodes);
        }
    }
}

#[test]
fn empty_single_and_coincident_inputs() {
    let (empty, _) = check(&mesh(vec![]), BspOptions::default());
    assert!(empty.nodes.is_empty());
    let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let (one, _) = check(&mesh(vec![t]), BspOptions::default());
    assert_eq!(one.nodes.len(), 1);
    let (same, _) = check(&mesh(vec![t; 300]), BspOptions::default());
    assert!(same.items.len() <= 300 * 4, "{}", same.items.len());
    check(&mesh(vec![[Vec3::ONE; 3]; 50]), BspOptions::default());
}

/// Rooms of walls at 30 degrees to the axes: the tree takes oblique planes (the walls' own, or
/// the 26-DOP's), and a ray meets fewer triangles than in a kd-tree, whose axis-aligned cells
/// around a slanted wall are mostly empty.
#[test]
fn slanted_walls_get_oblique_planes() {
    let (s, c) = (0.5f32, 0.75f32.sqrt());
    let rot = |p: Vec3| Vec3::new(c * p.x - s * p.y, s * p.x + c * p.y, p.z);
    let mut tris = Vec::new();
    // 30 parallel walls, each a 16 x 16 grid of quads, rotated 30 degrees about z.
    for w in 0..30 {
        let x = w as f32 * 0.2 - 3.0;
        for i in 0..16 {
            for j in 0..16 {
                let q = |a: usize, b: usize| {
                    rot(Vec3::new(x, a as f32 * 0.25 - 2.0, b as f32 * 0.25 - 2.0))
                };
                tris.push([q(i, j), q(i + 1, j), q(i + 1, j + 1)]);
                tris.push([q(i, j), q(i + 1, j + 1), q(i, j + 1)]);
            }
        }
    }
    let m = mesh(tris);
    let (b, hits) = check(&m, BspOptions::default());
    assert!(hits > 100, "{hits}");
    let st = b.stats();
    assert!(
        3 * b.oblique_planes() > st.nodes,
        "{} of {}",
        b.oblique_planes(),
        st.nodes
    );
    let p = prims(&m);
    let kd = KdTree::build(&p);
    let (mut sb, mut sk) = (TraversalStats::default(), TraversalStats::default());
    for r in rays(2000, 3) {
        let r = Ray::new(r.origin * 2.0, r.dir);
        let a = b.intersect(&p, &r, f32::INFINITY, &mut sb);
        let k = kd.intersect(&p, &r, f32::INFINITY, &mut sk);
        assert_eq!(a.map(|h| h.t), k.map(|h| h.t));
    }
    assert!(
        sb.prim_tests < sk.prim_tests,
        "bsp {} kd-tree {}",
        sb.prim_tests,
        sk.prim_tests
    );
}
