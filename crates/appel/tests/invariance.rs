//! Properties every render must have: scale invariance (no scene epsilon), thread-count determinism,
//! and exact camera-convention AOVs.

mod common;
use appel::math::Vec3;
use appel::render::MISS_ID;
use common::*;

fn compare(a: &appel::render::Film, b: &appel::render::Film) -> (f32, f32) {
    let diffs: Vec<f32> = a
        .rgb
        .iter()
        .zip(&b.rgb)
        .map(|(x, y)| (*x - *y).abs().max_element())
        .collect();
    let mean = diffs.iter().sum::<f32>() / diffs.len() as f32;
    let bad = diffs.iter().filter(|&&d| d > 2.0 / 255.0).count() as f32 / diffs.len() as f32;
    (mean, bad)
}

#[test]
fn scenes_render_the_same_at_any_scale() {
    for name in ["whitted", "glass-block", "mirror-room"] {
        let d = with_size(builtin(name), 120, 90);
        let (reference, ..) = render_description(&d);
        for s in [1e-3f32, 1e4] {
            let (scaled, ..) = render_description(&d.scaled(s));
            let (mean, bad) = compare(&reference, &scaled);
            // Differences come only from rounding at silhouettes and square edges, never from acne.
            assert!(
                mean < 2e-3 && bad < 0.01,
                "{name} at scale {s}: mean difference {mean}, {:.2}% of pixels differ",
                bad * 100.0
            );
        }
    }
}

#[test]
fn image_is_bit_identical_for_any_thread_count() {
    let mut d = with_size(builtin("whitted"), 97, 61);
    d.render.spp = 3;
    let scene = appel::scene::Scene::new(&d, std::path::Path::new(".")).unwrap();
    let render_on = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                appel::render::render(&scene, &Default::default())
                    .unwrap()
                    .0
            })
    };
    let one = render_on(1);
    for threads in [2, 3, 8] {
        assert!(one == render_on(threads), "{threads} threads differ from 1");
    }
}

#[test]
fn depth_normal_and_ids_follow_the_camera_convention() {
    let text = r#"
        [camera]
        eye = [0.0, 0.0, 10.0]
        look_at = [0.0, 0.0, 0.0]
        fov = 30.0
        width = 41
        height = 31

        [[shape]]
        type = "plane"
        point = [0.0, 0.0, -5.0]
        normal = [0.0, 0.0, 1.0]
        size = [4.0, 4.0]

        [[shape]]
        type = "sphere"
        center = [0.0, 0.0, 0.0]
        radius = 1.5
    "#;
    let d = appel::description::description_from_str(
        text,
        appel::description::parse::Syntax::Toml,
        std::path::Path::new("t.toml"),
    )
    .unwrap();
    let (film, _, scene) = render_description(&d);
    // Centre pixel: the sphere, 8.5 away, facing the camera, shape 1.
    let c = film.index(20, 15);
    assert!((film.depth[c] - 8.5).abs() < 1e-5);
    assert!((film.normal[c] - Vec3::Z).length() < 1e-5);
    assert_eq!((film.shape_id[c], film.prim_id[c]), (1, 0));
    // Every pixel's depth is the analytic distance along its convention ray.
    for y in 0..31 {
        for x in 0..41 {
            let i = film.index(x, y);
            let ray = scene.camera.pixel_ray(x, y);
            let o = ray.origin;
            let dir = ray.dir;
            let b = o.dot(dir);
            let disc = b * b - (o.length_squared() - 1.5 * 1.5);
            let sphere_t = (disc >= 0.0).then(|| -b - disc.sqrt());
            let plane_t = (-5.0 - o.z) / dir.z;
            let on_plane = o + plane_t * dir;
            let plane_t = (on_plane.x.abs() <= 2.0 && on_plane.y.abs() <= 2.0).then_some(plane_t);
            match (sphere_t, plane_t) {
                (Some(t), _) => {
                    assert_eq!(film.shape_id[i], 1);
                    assert!((film.depth[i] - t).abs() < 1e-4 * t, "({x},{y})");
                }
                (None, Some(t)) => {
                    assert_eq!(film.shape_id[i], 0);
                    assert!((film.depth[i] - t).abs() < 1e-4 * t);
                    assert!((film.normal[i] - Vec3::Z).length() < 1e-6);
                }
                (None, None) => {
                    assert_eq!(film.shape_id[i], MISS_ID);
                    assert_eq!(film.prim_id[i], MISS_ID);
                    assert_eq!(film.depth[i], f32::INFINITY);
                    assert_eq!(film.normal[i], Vec3::ZERO);
                }
            }
        }
    }
}
