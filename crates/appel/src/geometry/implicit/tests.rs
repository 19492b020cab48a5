use super::interval::Interval;
use super::num::Num;
use super::*;
use crate::geometry::Sphere;
use proptest::prelude::*;

/// SplitMix64 (Steele et al. 2014): a small deterministic generator for random rays.
pub(crate) struct Rng(pub u64);

impl Rng {
    pub fn next_f32(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32
    }

    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next_f32()
    }

    pub fn unit_vector(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

fn implicit(f: &str, half: f32) -> Implicit {
    Implicit::new(f, Aabb::new(Vec3::splat(-half), Vec3::splat(half))).unwrap()
}

const HEART: &str = "(x^2 + 9*z^2/4 + y^2 - 1)^3 - x^2*y^3 - 9*z^2*y^3/80";

#[test]
fn sphere_as_implicit_agrees_with_the_analytic_sphere() {
    let imp = implicit("x^2 + y^2 + z^2 - 1", 1.1);
    let sphere = Sphere::new(Vec3::ZERO, 1.0);
    let mut rng = Rng(7);
    let (mut hits, mut graze) = (0, 0);
    for _ in 0..20_000 {
        let o = rng.unit_vector() * rng.range(1.2, 4.0);
        // Aim near the sphere so about half the rays hit.
        let target = rng.unit_vector() * rng.range(0.0, 1.4);
        let ray = Ray::new(o, (target - o).normalize());
        let a = imp.intersect(&ray, f32::INFINITY);
        let b = sphere.intersect(&ray, f32::INFINITY);
        // Distance of the line from the centre: rays within 1e-5 of tangency may legitimately differ.
        let closest = (o - ray.dir * o.dot(ray.dir)).length();
        if (closest - 1.0).abs() < 1e-5 {
            graze += 1;
            continue;
        }
        match (a, b) {
            (Some(a), Some(b)) => {
                hits += 1;
                let ta = a.t as f64 + a.u as f64;
                assert!(
                    (ta - b.t as f64).abs() < 2e-6 * b.t as f64,
                    "{ray:?} {a:?} {b:?}"
                );
                let si = imp.interaction(&ray, &a);
                let sb = sphere.interaction(&ray, &b);
                assert!((si.n - sb.n).length() < 1e-5, "{:?} {:?}", si.n, sb.n);
                assert!((si.p - sb.p).length() < 1e-5);
            }
            (None, None) => {}
            _ => panic!("disagree on {ray:?}: implicit {a:?}, sphere {b:?}"),
        }
    }
    assert!(hits > 5_000, "{hits}");
    assert!(graze < 10, "{graze}");
}

#[test]
fn tiny_sphere_far_along_a_long_box_is_found() {
    let imp = Implicit::new(
        "x^2 + y^2 + (z - 90)^2 - 1e-6",
        Aabb::new(Vec3::new(-1.0, -1.0, -100.0), Vec3::new(1.0, 1.0, 100.0)),
    )
    .unwrap();
    let ray = Ray::new(Vec3::new(0.0, 0.0, -100.0), Vec3::Z);
    let h = imp.intersect(&ray, f32::INFINITY).unwrap();
    assert!(
        (h.t as f64 + h.u as f64 - (190.0 - 1e-3)).abs() < 1e-6,
        "{h:?}"
    );
    // Off by 2 radii: missed.
    let ray = Ray::new(Vec3::new(0.002, 0.0, -100.0), Vec3::Z);
    assert!(imp.intersect(&ray, f32::INFINITY).is_none());
}

#[test]
fn tangent_ray_touching_a_sphere_is_found() {
    let imp = implicit("x^2 + y^2 + z^2 - 1", 2.0);
    let ray = Ray::new(Vec3::new(0.0, 1.0, -3.0), Vec3::Z);
    let h = imp.intersect(&ray, f32::INFINITY).unwrap();
    assert!((h.t - 3.0).abs() < 1e-4, "{h:?}");
}

#[test]
fn reflected_rays_do_not_rehit_the_surface_they_leave() {
    for f in [
        "x^2 + y^2 + z^2 - 1",
        HEART,
        "(x^2+y^2+z^2+1-0.09)^2 - 4*(x^2+z^2)",
    ] {
        let imp = implicit(f, 1.6);
        let mut rng = Rng(11);
        let mut tested = 0;
        for _ in 0..4_000 {
            let o = rng.unit_vector() * 4.0;
            let target = rng.unit_vector() * rng.range(0.0, 1.0);
            let ray = Ray::new(o, (target - o).normalize());
            let Some(h) = imp.intersect(&ray, f32::INFINITY) else {
                continue;
            };
            let si = imp.interaction(&ray, &h);
            assert!(si.n.is_finite() && si.p.is_finite());
            let n = if si.n.dot(ray.dir) < 0.0 { si.n } else { -si.n };
            let refl = ray.dir - 2.0 * ray.dir.dot(n) * n;
            let origin = crate::math::offset_ray_origin(si.p, si.p_error, si.n, refl);
            let r2 = Ray::new(origin, refl);
            if let Some(h2) = imp.intersect(&r2, f32::INFINITY) {
                // A second hit is fine (concave parts, the torus' far side), but not one at the start.
                assert!(h2.t > 1e-4, "{f}: re-hit at t = {} from {:?}", h2.t, si.p);
            }
            // Shadow-style rays leaving to the other side of the normal go inward and must not stop
            // at t ~ 0 either.
            let inward = Ray::new(
                crate::math::offset_ray_origin(si.p, si.p_error, si.n, -n),
                -n,
            );
            if let Some(h3) = imp.intersect(&inward, f32::INFINITY) {
                assert!(h3.t > 1e-4, "{f}: inward re-hit at t = {}", h3.t);
            }
            tested += 1;
        }
        assert!(tested > 500, "{f}: {tested}");
    }
}

#[test]
fn dual_gradients_match_analytic_gradients() {
    let tape = Tape::compile(&parse::parse("x^3*y - sin(z)*exp(x) + sqrt(x^2 + 1)/y").unwrap());
    let mut rng = Rng(3);
    for _ in 0..1000 {
        let (x, y, z) = (
            rng.range(-2.0, 2.0) as f64,
            rng.range(0.5, 2.0) as f64,
            rng.range(-3.0, 3.0) as f64,
        );
        let g = tape.eval(
            [Dual::var(x, 0), Dual::var(y, 1), Dual::var(z, 2)],
            &mut Vec::new(),
        );
        let s = (x * x + 1.0).sqrt();
        let expect = DVec3::new(
            3.0 * x * x * y - z.sin() * x.exp() + x / (s * y),
            x.powi(3) - s / (y * y),
            -z.cos() * x.exp(),
        );
        assert!(
            (g.g - expect).length() < 1e-10 * (1.0 + expect.length()),
            "{g:?} {expect}"
        );
        assert!((g.v - tape.eval_f64([x, y, z])).abs() < 1e-12);
    }
}

#[test]
fn heart_cusp_gets_a_defined_normal() {
    let imp = implicit(HEART, 1.6);
    // Straight down the axis onto the top cusp at (0, 1, 0), where the gradient vanishes.
    let ray = Ray::new(Vec3::new(0.0, 3.0, 0.0), -Vec3::Y);
    let h = imp.intersect(&ray, f32::INFINITY).unwrap();
    let si = imp.interaction(&ray, &h);
    assert!(
        si.n.is_finite() && (si.n.length() - 1.0).abs() < 1e-5,
        "{si:?}"
    );
    assert!((si.p.y - 1.0).abs() < 1e-2, "{si:?}");
}

#[test]
fn formula_errors_have_columns() {
    let e = Implicit::new("x^2 + tan(y)", Aabb::new(Vec3::ZERO, Vec3::ONE)).unwrap_err();
    assert_eq!(e.column, 7);
}

/// A formula drawn from a small grammar, for the enclosure property.
fn formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        Just("x".to_string()),
        Just("y".to_string()),
        Just("z".to_string()),
        (-3.0f64..3.0).prop_map(|c| format!("{c:.3}")),
    ];
    leaf.prop_recursive(5, 40, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} + {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} - {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} * {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} / {b})")),
            (inner.clone(), -3i32..5).prop_map(|(a, n)| format!("({a})^{n}")),
            inner.clone().prop_map(|a| format!("sqrt({a})")),
            inner.clone().prop_map(|a| format!("abs({a})")),
            inner.clone().prop_map(|a| format!("sin({a})")),
            inner.clone().prop_map(|a| format!("cos({a})")),
            inner.clone().prop_map(|a| format!("exp({a})")),
            inner.clone().prop_map(|a| format!("-{a}")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("min({a}, {b})")),
            (inner.clone(), inner).prop_map(|(a, b)| format!("max({a}, {b})")),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// The interval evaluation over a box encloses the point evaluation at points of the box.
    #[test]
    fn interval_enclosure_contains_point_values(
        f in formula(),
        lo in proptest::array::uniform3(-4.0f64..4.0),
        size in proptest::array::uniform3(0.0f64..3.0),
        fr in proptest::collection::vec(proptest::array::uniform3(0.0f64..=1.0), 8),
    ) {
        let tape = Tape::compile(&parse::parse(&f).unwrap());
        let boxed = [0, 1, 2].map(|i| Interval::new(lo[i], lo[i] + size[i]));
        let enclosure = tape.eval(boxed, &mut Vec::new());
        for t in fr {
            let p = [0, 1, 2].map(|i| lo[i] + t[i] * size[i]);
            let p = [0, 1, 2].map(|i| p[i].min(boxed[i].hi));
            let v = tape.eval_f64(p);
            if v.is_finite() {
                prop_assert!(enclosure.contains(v), "{f}: {v} not in {enclosure:?} at {p:?}");
            }
        }
    }

    #[test]
    fn interval_operations_enclose_on_random_boxes(a in -5.0f64..5.0, w in 0.0f64..4.0, b in -5.0f64..5.0, v in 0.0f64..1.0, n in -4i32..7) {
        let i = Interval::new(a, a + w);
        let j = Interval::new(b, b + 1.0);
        let x = (a + v * w).min(a + w);
        let y = b + v;
        for (r, p) in [
            (i.powi(n), Num::powi(x, n)),
            (i.sin(), x.sin()),
            (i.cos(), x.cos()),
            (i.exp(), x.exp()),
            (i.sqrt(), Num::sqrt(x)),
            (i.mul(j), x * y),
            (i.div(j), x / y),
        ] {
            if p.is_finite() {
                prop_assert!(r.contains(p), "{r:?} misses {p}");
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// The enclosure of the derivative along a ray contains the dual-number derivative at points of
    /// the stretch: the monotonicity shortcut of root isolation rests on it.
    #[test]
    fn slope_enclosure_contains_point_derivatives(
        f in formula(),
        o in proptest::array::uniform3(-2.0f64..2.0),
        d in proptest::array::uniform3(-1.0f64..1.0),
        a in -1.0f64..1.0,
        w in 0.0f64..1.0,
        fr in proptest::collection::vec(0.0f64..=1.0, 6),
    ) {
        use super::slope::Slope;
        let tape = Tape::compile(&parse::parse(&f).unwrap());
        let t = Interval::new(a, a + w);
        let coord = |i: usize| Slope {
            v: Interval::constant(o[i]).add(t.mul(Interval::constant(d[i]))),
            d: Interval::constant(d[i]),
        };
        let s = tape.eval([coord(0), coord(1), coord(2)], &mut Vec::new());
        for u in fr {
            let tt = (a + u * w).min(a + w);
            let p = [0, 1, 2].map(|i| o[i] + tt * d[i]);
            let g = tape.eval([Dual::var(p[0], 0), Dual::var(p[1], 1), Dual::var(p[2], 2)], &mut Vec::new());
            let slope = g.g.dot(DVec3::from(d));
            // The enclosures are rounded outward; the dual numbers and the dot product are
            // rounded to nearest, so they may stray from the exact values they stand for by a
            // few units in the last place of their magnitude (the dot product's terms).
            let near = |i: Interval, x: f64, scale: f64| {
                let tol = 1e-12 * scale;
                i.lo - tol <= x && x <= i.hi + tol
            };
            let slope_scale = (g.g * DVec3::from(d)).abs().element_sum();
            if slope.is_finite() && g.v.is_finite() {
                prop_assert!(near(s.v, g.v, g.v.abs()), "{f}: value {} not in {:?}", g.v, s.v);
                prop_assert!(
                    near(s.d, slope, slope_scale),
                    "{f}: slope {slope} not in {:?} at t = {tt}",
                    s.d
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Any formula on any ray: no panic, hits inside `(0, t_max)` and the box, finite unit normals.
    #[test]
    fn random_formulas_on_random_rays_give_sane_hits(
        f in formula(),
        o in proptest::array::uniform3(-3.0f32..3.0),
        d in proptest::array::uniform3(-1.0f32..1.0),
        t_max in 0.1f32..10.0,
    ) {
        let imp = implicit(&f, 1.0);
        let ray = Ray::new(Vec3::from(o), Vec3::from(d));
        if let Some(h) = imp.intersect(&ray, t_max) {
            prop_assert!(h.t > 0.0 && h.t < t_max, "{h:?}");
            let p = ray.at(h.t);
            prop_assert!(imp.bounds.union(Aabb::new(p, p)).extent().max_element() <= 2.0 + 1e-3 * (1.0 + h.t));
            let si = imp.interaction(&ray, &h);
            prop_assert!(si.n.is_finite() && (si.n.length() - 1.0).abs() < 1e-3, "{f}: {si:?}");
            prop_assert!(si.p_error.is_finite());
        }
    }
}
