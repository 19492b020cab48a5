//! The kd-tree's unit tests: agreement with brute force, structure and cost on hard scenes.

use super::*;
use crate::accel::testutil::{agrees_with_brute, mesh, pinhole_rays, prims, rays, soup};
use crate::geometry::procedural::teapot_in_stadium;
use crate::math::{Ray, Vec3};

fn check(m: &crate::geometry::TriangleMesh, opts: KdOptions) -> (KdTree, usize) {
    let p = prims(m);
    let kd = KdTree::build_with(&p, opts);
    let hits = agrees_with_brute(
        &p,
        &rays(400, 17),
        |r, t, s| kd.intersect(&p, r, t, s),
        |r, t, s| kd.occluded(&p, r, t, s),
    );
    (kd, hits)
}

#[test]
fn agrees_with_brute_force() {
    let m = soup(3000, 31);
    for intersect_cost in [1.0, 80.0] {
        let (kd, hits) = check(
            &m,
            KdOptions {
                intersect_cost,
                ..Default::default()
            },
        );
        assert!(hits > 200);
        let s = kd.stats();
        let max_depth = (8.0 + 1.3 * 3000f64.log2()).round() as usize;
        assert!(s.depth <= max_depth, "{}", s.depth);
        assert_eq!(s.nodes + s.leaves, kd.binary_nodes);
        // Three binary levels per node: well under half as many nodes as interior ones (a
        // third when every node holds seven planes; cheap splits on a node's lower levels,
        // `KdOptions::inner_cost`, leave some of its planes unused: 1,600 nodes for 4,793
        // interior ones here).
        assert!(
            5 * kd.nodes.len() <= 2 * (s.nodes + 2),
            "{} of {}",
            kd.nodes.len(),
            s.nodes
        );
    }
}

#[test]
fn empty_single_and_coincident_inputs() {
    check(&mesh(vec![]), KdOptions::default());
    let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let (one, _) = check(&mesh(vec![t]), KdOptions::default());
    assert_eq!(one.binary_nodes, 1);
    assert!(one.nodes.is_empty(), "a one-leaf tree needs no node");
    let (same, _) = check(&mesh(vec![t; 300]), KdOptions::default());
    // Splitting coincident primitives duplicates them all: the tree must stay small.
    assert!(same.refs <= 300 * 4, "{}", same.refs);
}

#[test]
fn empty_space_is_cut_away() {
    // Two distant clusters: the root splits between them, and a ray through the gap visits few
    // nodes and tests nothing.
    let mut m = soup(1000, 8);
    for (k, p) in m.positions.iter_mut().enumerate() {
        *p = *p * 0.1 + Vec3::new(if k < 1500 { -5.0 } else { 5.0 }, 0.0, 0.0);
    }
    check(&m, KdOptions::default());
    let kd = KdTree::build(&prims(&m));
    let mut s = TraversalStats::default();
    let r = Ray::new(Vec3::new(0.0, -3.0, 0.0), Vec3::Y);
    assert!(kd
        .intersect(&prims(&m), &r, f32::INFINITY, &mut s)
        .is_none());
    assert_eq!(s.prim_tests, 0);
}

#[test]
fn small_dense_mesh_in_a_huge_sparse_one_is_cheap() {
    // The stadium's large triangles have bounds covering the teapot. Unless the builder clips
    // them (and the traversal mailboxes), they are copied into every leaf around the teapot and
    // retested in each: more tests per camera ray than primitives in the scene.
    let m = teapot_in_stadium(5000);
    let g = &prims(&m);
    let rays = pinhole_rays(Vec3::new(2.5, 2.2, 3.5), Vec3::Y, 45.0, 64, 48);
    let kd = KdTree::build(g);
    let bvh = crate::accel::Bvh::build(g);
    let brute = crate::accel::Brute::build(g);
    let (mut sk, mut sb, mut sr) = Default::default();
    let mut hits = 0;
    for r in &rays {
        let k = kd.intersect(g, r, f32::INFINITY, &mut sk);
        let b = bvh.intersect(g, r, f32::INFINITY, &mut sb);
        let f = brute.intersect(g, r, f32::INFINITY, &mut sr);
        assert_eq!(k.map(|h| h.t), f.map(|h| h.t));
        assert_eq!(b.map(|h| h.t), f.map(|h| h.t));
        hits += k.is_some() as usize;
    }
    assert!(hits > rays.len() / 2, "{hits}");
    let per_ray = |s: TraversalStats| s.prim_tests as f64 / s.rays as f64;
    let (k, b) = (per_ray(sk), per_ray(sb));
    // Leaves of the kd-tree are larger than the BVH's by design (their triangles are tested
    // four at a time and a triangle costs a tenth of a traversal step, `KdOptions::default`), so
    // its lane tests per ray run several times the BVH's, but not thousands of times.
    assert!(k <= 8.0 * b.max(1.0), "kd-tree {k} tests per ray, bvh {b}");
    assert!(
        sk.prim_tests <= sr.prim_tests / 20,
        "{sk:?} vs brute {sr:?}"
    );
    // Build memory: the leaves hold a primitive about twice on average (the stadium's large
    // triangles span several cells of its surface), not hundreds.
    let n = crate::accel::Primitives::count(g);
    assert!(kd.refs <= 4 * n, "{} for {n}", kd.refs);
}

#[test]
fn parallel_build_is_the_sequential_build() {
    let m = teapot_in_stadium(20000);
    let g = &prims(&m);
    let par = KdTree::build_par(g, KdOptions::default(), 2000);
    let seq = KdTree::build_par(g, KdOptions::default(), usize::MAX);
    assert!(par.nodes.len() > 300);
    assert_eq!(par.nodes, seq.nodes);
    let ids = |k: &KdTree| k.blocks.iter().map(|b| b.id).collect::<Vec<_>>();
    assert_eq!(ids(&par), ids(&seq));
    assert_eq!(par.refs, seq.refs);
    let (p, s) = (par.stats(), seq.stats());
    assert_eq!((p.nodes, p.leaves, p.depth), (s.nodes, s.leaves, s.depth));
}

#[test]
fn a_tessellated_surface_is_not_shattered() {
    // Mesh vertices lie on candidate planes, where triangles end and start; the partition sends
    // every triangle touching the plane to both sides. An SAH that does not count those copies
    // takes such planes as free and copies each triangle into many leaves: the references per
    // triangle must stay below two.
    let m = crate::geometry::procedural::icosphere(5);
    let n = m.indices.len();
    let (kd, _) = check(&m, KdOptions::default());
    assert!(kd.refs <= 2 * n, "{} refs for {n}", kd.refs);
}

#[test]
fn the_portable_node_test_agrees_with_brute_force() {
    // Machines without AVX2 test the cells lane by lane; check that path here too, on a scene with
    // axis-aligned rays and coplanar triangles as well as a random soup.
    let mut m = soup(2000, 5);
    m.positions.iter_mut().take(600).for_each(|p| p.z = 0.25);
    let p = prims(&m);
    let kd = KdTree::build(&p);
    let mut rs = rays(300, 9);
    for axis in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Z] {
        rs.push(Ray::new(Vec3::splat(0.1) - axis * 3.0, axis));
        rs.push(Ray::new(Vec3::new(0.3, -0.2, 0.25) - axis * 3.0, axis));
    }
    let hits = agrees_with_brute(
        &p,
        &rs,
        |r, t, s| kd.traverse_with::<_, false, false>(&p, r, t, s),
        |r, t, s| kd.traverse_with::<_, true, false>(&p, r, t, s).is_some(),
    );
    assert!(hits > 100, "{hits}");
}

#[test]
fn cells_follow_the_planes_of_three_levels() {
    // A tree split at x = 0, then y = 0 on both sides, then z = 0 on one: a ray along +x at
    // y, z < 0 crosses cell (below x, below y, below z) then (above x, below y).
    use super::wide::{cells_portable, is_leaf, RayPlanes};
    let mut tris = Vec::new();
    for (x, y, z) in [
        (-1.0, -1.0, -1.0),
        (1.0, -1.0, -1.0),
        (-1.0, 1.0, 1.0),
        (1.0, 1.0, 1.0),
    ] {
        for k in 0..40 {
            let c = Vec3::new(x, y, z) * (0.5 + 0.01 * k as f32);
            tris.push([c, c + Vec3::X * 0.01, c + Vec3::Y * 0.01]);
        }
    }
    let kd = KdTree::build(&prims(&mesh(tris)));
    assert!(!kd.nodes.is_empty());
    let n = &kd.nodes[0];
    let r = Ray::new(Vec3::new(-3.0, -0.75, -0.75), Vec3::X);
    let (mut near, mut far) = ([0.0; 8], [0.0; 8]);
    let mask = cells_portable(
        n,
        &RayPlanes::new(r.origin.to_array(), r.dir.recip().to_array()),
        0.0,
        10.0,
        &mut near,
        &mut far,
    );
    assert!(mask != 0);
    // The crossed cells are disjoint and tile the ray's span in order.
    let mut spans: Vec<(f32, f32)> = (0..8)
        .filter(|c| mask >> c & 1 == 1)
        .map(|c| (near[c], far[c]))
        .collect();
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    for w in spans.windows(2) {
        assert!(w[0].1 <= w[1].0, "{spans:?}");
    }
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        let (mut n2, mut f2) = ([0.0; 8], [0.0; 8]);
        let planes = RayPlanes::new(r.origin.to_array(), r.dir.recip().to_array());
        // SAFETY: the CPU has AVX2.
        let m2 = unsafe { super::wide::cells_avx2(n, &planes, 0.0, 10.0, &mut n2, &mut f2) };
        assert_eq!(m2, mask);
        for c in 0..8 {
            if mask >> c & 1 == 1 {
                assert_eq!((n2[c], f2[c]), (near[c], far[c]));
            }
        }
    }
    assert!(n.cell.iter().any(|&c| !is_leaf(c)) || n.occupied() != 0);
}
