//! Inside/outside queries against independent answers: the exact solid for a cube, the face planes for
//! a convex icosphere, and the generalized winding number (Jacobson et al. 2013) for a real mesh.

use appel::geometry::procedural::{cube, icosphere};
use appel::geometry::TriangleMesh;
use appel::math::Vec3;
use appel::query::InsideTester;

/// A small deterministic generator (SplitMix64), so failures reproduce.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
    fn point(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next()) * (hi - lo) + Vec3::splat(lo)
    }
}

#[test]
fn cube_agrees_with_the_exact_solid_on_random_points() {
    let mesh = cube();
    let tester = InsideTester::new(&mesh);
    let mut rng = Rng(1);
    let points: Vec<Vec3> = (0..100_000).map(|_| rng.point(-1.5, 1.5)).collect();
    let answers = tester.classify(&points);
    for (p, inside) in points.iter().zip(answers) {
        let margin = 1.0 - p.abs().max_element();
        if margin.abs() > 1e-5 {
            assert_eq!(inside, margin > 0.0, "{p}");
        }
    }
}

#[test]
fn points_on_the_cube_grid_lines_are_classified_too() {
    // Points in the planes of the faces' edges, so rays start aligned with the mesh's structure.
    let mesh = cube();
    let tester = InsideTester::new(&mesh);
    for &x in &[-0.5f32, 0.0, 0.5] {
        for &y in &[-0.5f32, 0.0, 0.5] {
            assert!(tester.is_inside(Vec3::new(x, y, 0.0)));
            assert!(!tester.is_inside(Vec3::new(x, y, 1.5)));
            assert!(!tester.is_inside(Vec3::new(3.0 * x, 1.0 + y.abs() + 0.1, 0.0)));
        }
    }
}

#[test]
fn icosphere_agrees_with_its_face_planes_on_random_points() {
    let mesh = icosphere(3);
    let tester = InsideTester::new(&mesh);
    let planes: Vec<(Vec3, f32)> = (0..mesh.triangle_count())
        .map(|t| {
            let [a, b, c] = mesh.vertices(t);
            let n = (b - a).cross(c - a).normalize();
            (n, n.dot(a))
        })
        .collect();
    let mut rng = Rng(2);
    let points: Vec<Vec3> = (0..100_000).map(|_| rng.point(-1.2, 1.2)).collect();
    let answers = tester.classify(&points);
    let mut checked = 0;
    for (p, inside) in points.iter().zip(answers) {
        // Signed distance to the convex polyhedron's boundary, from its face planes.
        let outside_by = planes
            .iter()
            .map(|(n, d)| n.dot(*p) - d)
            .fold(f32::NEG_INFINITY, f32::max);
        if outside_by.abs() > 1e-5 {
            assert_eq!(inside, outside_by < 0.0, "{p}");
            checked += 1;
        }
    }
    assert!(checked > 99_000);
}

/// The generalized winding number: the sum of the signed solid angles of the triangles seen from `p`
/// (Van Oosterom & Strackee 1983), over 4 pi. 1 inside a closed outward mesh, 0 outside.
fn winding_number(mesh: &TriangleMesh, p: Vec3) -> f64 {
    let p = p.as_dvec3();
    let mut sum = 0.0;
    for t in 0..mesh.triangle_count() {
        let [a, b, c] = mesh.vertices(t).map(|v| v.as_dvec3() - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c));
        let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        sum += 2.0 * num.atan2(den);
    }
    sum / (4.0 * std::f64::consts::PI)
}

#[test]
fn winding_number_reference_is_right_on_the_icosphere() {
    let mesh = icosphere(2);
    assert!((winding_number(&mesh, Vec3::ZERO) - 1.0).abs() < 1e-9);
    assert!(winding_number(&mesh, Vec3::splat(2.0)).abs() < 1e-9);
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn real_manifold_mesh_agrees_with_the_winding_number() {
    let path = appel_testdata::path("odedstein-meshes/bunny/bunny.obj");
    let loaded = appel::io::load_mesh(&path).unwrap();
    let mut mesh = TriangleMesh::default();
    for part in &loaded.parts {
        appel::geometry::procedural::append(&mut mesh, &part.mesh);
    }
    let tester = InsideTester::new(&mesh);
    let b = mesh.bounds();
    let mut rng = Rng(3);
    let points: Vec<Vec3> = (0..3000)
        .map(|_| b.min + (b.max - b.min) * rng.point(-0.1, 1.1))
        .collect();
    let answers = tester.classify(&points);
    let (mut checked, mut inside_count) = (0, 0);
    for (p, inside) in points.iter().zip(answers) {
        let w = winding_number(&mesh, *p);
        // Points within rounding of the surface have w near 0.5: no reference answer there.
        if (w - 0.5).abs() > 0.1 {
            assert_eq!(inside, w > 0.5, "{p}: winding number {w}");
            checked += 1;
            inside_count += inside as usize;
        }
    }
    assert!(
        checked > 2900 && inside_count > 200,
        "{checked} checked, {inside_count} inside"
    );
}

/// Points a millionth inside and outside each vertex, edge midpoint and face centre of an
/// icosahedron: rays from them meet the surface within their own rounding, and the winding number
/// must take over (the parity vote alone called the vertex points outside).
#[test]
fn points_a_millionth_from_an_icosahedron_surface() {
    let mesh = icosphere(0);
    let tester = InsideTester::new(&mesh);
    let mut features: Vec<Vec3> = mesh.positions.clone();
    for t in &mesh.indices {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        features.extend([
            (a + b) * 0.5,
            (b + c) * 0.5,
            (c + a) * 0.5,
            (a + b + c) / 3.0,
        ]);
    }
    for f in features {
        assert!(tester.is_inside(f * (1.0 - 1e-6)), "{f} inside");
        assert!(!tester.is_inside(f * (1.0 + 1e-6)), "{f} outside");
    }
}
