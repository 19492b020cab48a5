//! Every acceleration structure finds the hits Intel Embree finds, on the same rays, in this process:
//! camera rays, incoherent rays and shadow rays on shared real meshes and on the generated benchmark
//! scenes. Embree is loaded at run time; without it a test prints `SKIPPED: <test>: <why>` and
//! passes, unless `APPEL_REQUIRE_EMBREE` is set (as `.ci/run` does after installing it), when it
//! fails. The tests on the shared meshes are ignored where the shared data is absent.

use appel::accel::{Accel, AccelKind, TraversalStats};
use appel::geometry::TriangleTest;
use appel::scene::{frame_model, model_description, Camera, Scene};
use appel_bench::{bench_scene, embree_robust_for, flat_triangles, BenchRays, BenchTarget};
use embree_peer::{BuildQuality, Embree};

fn embree(test: &str) -> Option<Embree> {
    match Embree::load(0) {
        Ok(e) => Some(e),
        Err(e) if std::env::var_os("APPEL_REQUIRE_EMBREE").is_some() => {
            panic!("APPEL_REQUIRE_EMBREE is set but {e}")
        }
        Err(e) => {
            appel_testdata::skip(test, e);
            None
        }
    }
}

fn model(file: &str, w: u32, h: u32) -> BenchTarget {
    let p = appel_testdata::path(&format!("common-3d-test-models/{file}"));
    let mut d = model_description(file);
    (d.camera.width, d.camera.height) = (w, h);
    let scene = Scene::new(&d, p.parent().unwrap()).unwrap();
    let framed = frame_model(&d, scene.geometry.bounds());
    BenchTarget {
        name: file.into(),
        camera: Camera::new(&framed.camera),
        geometry: scene.geometry,
        accel_options: Default::default(),
    }
}

/// Compares every structure with Embree on the target's rays. Embree's default triangle test is not
/// watertight and both round differently, so a few rays in a million may take the neighbouring
/// triangle of an edge; the thresholds are those of `bench/compare_embree.py`.
fn check(embree: &Embree, t: &BenchTarget) {
    let flat = flat_triangles(&t.geometry).unwrap();
    let scene = embree
        .triangle_scene(&flat.positions, &flat.indices, BuildQuality::Medium, false)
        .unwrap();
    let rays = BenchRays::new(t);
    let g = &t.geometry;
    for &name in AccelKind::NAMES.iter().filter(|&&n| n != "brute") {
        let accel = Accel::build(AccelKind::from_name(name).unwrap(), g);
        let mut s = TraversalStats::default();
        let (mut n, mut hit_agree, mut prim_agree, mut t_agree) = (0usize, 0usize, 0usize, 0usize);
        for r in rays.primary.iter().chain(&rays.incoherent) {
            n += 1;
            let ours = accel.intersect(g, r, f32::INFINITY, &mut s);
            let theirs = scene.intersect(r.origin.to_array(), r.dir.to_array(), f32::INFINITY);
            match (ours, theirs) {
                (None, None) => {
                    hit_agree += 1;
                    prim_agree += 1;
                    t_agree += 1;
                }
                (Some(a), Some(b)) => {
                    hit_agree += 1;
                    prim_agree += (a.prim == b.prim) as usize;
                    t_agree += ((a.t - b.t).abs() <= 1e-5 * a.t.max(1.0)) as usize;
                }
                _ => {}
            }
        }
        let shadow_agree = rays
            .shadow
            .iter()
            .filter(|sr| {
                accel.occluded(g, &sr.ray, sr.t_max, &mut s)
                    == scene.occluded(sr.ray.origin.to_array(), sr.ray.dir.to_array(), sr.t_max)
            })
            .count();
        let frac = |k: usize, of: usize| k as f64 / of.max(1) as f64;
        let msg = format!(
            "{} {name}: {n} rays, hit/miss {:.5}, primid {:.5}, t {:.5}, shadow {:.5} of {}",
            t.name,
            frac(hit_agree, n),
            frac(prim_agree, n),
            frac(t_agree, n),
            frac(shadow_agree, rays.shadow.len()),
            rays.shadow.len()
        );
        eprintln!("{msg}");
        assert!(n > 1000 && rays.shadow.len() > 100, "{msg}");
        assert!(frac(hit_agree, n) >= 0.9999, "{msg}");
        assert!(frac(prim_agree, n) >= 0.999, "{msg}");
        assert!(frac(t_agree, n) >= 0.999, "{msg}");
        assert!(frac(shadow_agree, rays.shadow.len()) >= 0.999, "{msg}");
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn every_structure_agrees_with_embree_on_shared_meshes() {
    let Some(embree) = embree("every_structure_agrees_with_embree_on_shared_meshes") else {
        return;
    };
    for file in [
        "stanford-bunny.obj.gz",
        "ogre.obj.gz",
        "fandisk.obj",
        "teapot.obj",
    ] {
        check(&embree, &model(file, 160, 120));
    }
}

#[test]
fn every_structure_agrees_with_embree_on_generated_scenes() {
    let Some(embree) = embree("every_structure_agrees_with_embree_on_generated_scenes") else {
        return;
    };
    for name in ["uniform", "teapot-in-stadium"] {
        let t = bench_scene(name, 20_000, 160, 120).unwrap();
        check(&embree, &t);
    }
}

/// The BVH with each triangle test against the Embree mode `appel bench --embree` pairs it with
/// (watertight with robust, Moller-Trumbore, whose triangles the wide BVH holds as a vertex and two
/// edges, with Embree's default): hit or miss, the primitive, `t` and any-hit answers agree on the
/// same rays, at the thresholds of [`check`].
fn check_pairings(embree: &Embree, mut t: BenchTarget) {
    let flat = flat_triangles(&t.geometry).unwrap();
    let rays = BenchRays::new(&t);
    for test in TriangleTest::ALL {
        t.geometry.triangle_test = test;
        let g = &t.geometry;
        let scene = embree
            .triangle_scene(
                &flat.positions,
                &flat.indices,
                BuildQuality::Medium,
                embree_robust_for(test),
            )
            .unwrap();
        let bvh = Accel::build(AccelKind::Bvh, g);
        let mut s = TraversalStats::default();
        let (mut n, mut hit_agree, mut prim_agree, mut t_agree) = (0usize, 0usize, 0usize, 0usize);
        for r in rays.primary.iter().chain(&rays.incoherent) {
            n += 1;
            let ours = bvh.intersect(g, r, f32::INFINITY, &mut s);
            let theirs = scene.intersect(r.origin.to_array(), r.dir.to_array(), f32::INFINITY);
            hit_agree += (ours.is_some() == theirs.is_some()) as usize;
            match (ours, theirs) {
                (None, None) => {
                    prim_agree += 1;
                    t_agree += 1;
                }
                (Some(a), Some(b)) => {
                    prim_agree += (a.prim == b.prim) as usize;
                    t_agree += ((a.t - b.t).abs() <= 1e-5 * a.t.max(1.0)) as usize;
                }
                _ => {}
            }
        }
        let shadow_agree = rays
            .shadow
            .iter()
            .filter(|sr| {
                bvh.occluded(g, &sr.ray, sr.t_max, &mut s)
                    == scene.occluded(sr.ray.origin.to_array(), sr.ray.dir.to_array(), sr.t_max)
            })
            .count();
        let frac = |k: usize, of: usize| k as f64 / of.max(1) as f64;
        let msg = format!(
            "{} bvh {} against embree (robust {}): {n} rays, hit/miss {:.5}, primid {:.5}, t {:.5}, shadow {:.5}",
            t.name,
            test.name(),
            embree_robust_for(test),
            frac(hit_agree, n),
            frac(prim_agree, n),
            frac(t_agree, n),
            frac(shadow_agree, rays.shadow.len()),
        );
        eprintln!("{msg}");
        assert!(n > 1000 && rays.shadow.len() > 100, "{msg}");
        assert!(frac(hit_agree, n) >= 0.9999, "{msg}");
        assert!(frac(prim_agree, n) >= 0.999, "{msg}");
        assert!(frac(t_agree, n) >= 0.999, "{msg}");
        assert!(frac(shadow_agree, rays.shadow.len()) >= 0.999, "{msg}");
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn both_triangle_tests_agree_with_their_embree_pairing_on_shared_meshes() {
    let test = "both_triangle_tests_agree_with_their_embree_pairing_on_shared_meshes";
    let Some(embree) = embree(test) else { return };
    for file in ["stanford-bunny.obj.gz", "ogre.obj.gz"] {
        check_pairings(&embree, model(file, 160, 120));
    }
}

#[test]
fn both_triangle_tests_agree_with_their_embree_pairing_on_generated_scenes() {
    let test = "both_triangle_tests_agree_with_their_embree_pairing_on_generated_scenes";
    let Some(embree) = embree(test) else { return };
    check_pairings(&embree, bench_scene("uniform", 20_000, 160, 120).unwrap());
    check_pairings(
        &embree,
        bench_scene("teapot-in-stadium", 20_000, 160, 120).unwrap(),
    );
}
