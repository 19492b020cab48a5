//! Packets and streams of rays answer what single rays answer: `Primitives::intersect_all_packet`
//! for every pattern of active lanes, and `Scene::intersect_stream` / `Scene::occluded_stream`,
//! closest and any hit, with their traversal counts, on a real mesh and on the built-in Whitted
//! scene (a leaf of spheres and a rectangle, tested in SIMD lanes).

use appel::accel::{Hit, Primitives, TraversalStats, LEAF_PACKET};
use appel::description::description_from_str;
use appel::description::parse::Syntax;
use appel::math::{Ray, Vec3};
use appel::scene::builtin::builtin_scene;
use appel::scene::Scene;
use appel::scene_build::{frame_model, model_description};
use std::path::Path;

/// xorshift32 in `[-1, 1)`.
fn rng(mut seed: u32) -> impl FnMut() -> f32 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed as f32 / u32::MAX as f32 * 2.0 - 1.0
    }
}

/// Rays from around `centre` (within `reach`), half of them aimed at points near it so that
/// many hit, the others in any direction; every fifth has a zero-length direction component mix.
fn random_rays(n: usize, centre: Vec3, reach: f32, seed: u32) -> Vec<Ray> {
    let mut r = rng(seed);
    let mut v = move || Vec3::new(r(), r(), r());
    (0..n)
        .map(|k| {
            let origin = centre + v() * reach;
            let dir = if k % 2 == 0 {
                centre + v() * (0.3 * reach) - origin
            } else {
                v()
            };
            Ray::new(origin, dir)
        })
        .collect()
}

/// Limits per lane: unbounded, and distances that cut some hits off.
fn limits(k: usize) -> [f32; LEAF_PACKET] {
    std::array::from_fn(|lane| match (k + lane) % 4 {
        0 => f32::INFINITY,
        1 => 0.8,
        2 => 3.0,
        _ => 7.5,
    })
}

fn key(h: Option<Hit>) -> Option<(u32, u32)> {
    h.map(|h| (h.prim, h.t.to_bits()))
}

/// `intersect_all_packet` of `prims` against `intersect_all` lane by lane, for all 16 patterns
/// of active lanes: closest hits (primitive and `t` bit for bit, and the narrowed `t_max`), any-hit
/// answers, and inactive lanes left as they were. Returns how many lanes hit.
fn packets_match_single_rays<P: Primitives>(prims: &P, rays: &[Ray]) -> usize {
    let sentinel = Some(Hit {
        prim: 12345,
        t: -1.0,
        u: 0.0,
        v: 0.0,
        sub: 0,
    });
    let mut hits = 0;
    for (k, chunk) in rays.chunks_exact(LEAF_PACKET).enumerate() {
        let packet: [Ray; LEAF_PACKET] = chunk.try_into().unwrap();
        let limit = limits(k);
        let mut stats = TraversalStats::default();
        let single: Vec<(Option<Hit>, f32, bool)> = (0..LEAF_PACKET)
            .map(|lane| {
                let mut t = limit[lane];
                let closest = prims.intersect_all::<false>(&packet[lane], &mut t, &mut stats);
                let mut t_any = limit[lane];
                let any = prims.intersect_all::<true>(&packet[lane], &mut t_any, &mut stats);
                (closest, t, any.is_some())
            })
            .collect();
        for mask in 0..16u32 {
            let mut t_max = limit;
            let mut out = [sentinel; LEAF_PACKET];
            prims.intersect_all_packet::<false>(&packet, mask, &mut t_max, &mut out, &mut stats);
            let mut t_any = limit;
            let mut any = [sentinel; LEAF_PACKET];
            prims.intersect_all_packet::<true>(&packet, mask, &mut t_any, &mut any, &mut stats);
            for lane in 0..LEAF_PACKET {
                let (closest, t, occluded) = single[lane];
                if mask & (1 << lane) == 0 {
                    assert_eq!(out[lane], sentinel, "ray {k} lane {lane} mask {mask:04b}");
                    assert_eq!(any[lane], sentinel, "ray {k} lane {lane} mask {mask:04b}");
                    assert_eq!(t_max[lane], limit[lane]);
                    continue;
                }
                let at = format!("packet {k} lane {lane} mask {mask:04b}");
                assert_eq!(key(out[lane]), key(closest), "{at}");
                assert_eq!(t_max[lane].to_bits(), t.to_bits(), "{at}");
                assert_eq!(any[lane].is_some(), occluded, "{at}");
                if mask == 15 {
                    hits += closest.is_some() as usize;
                }
            }
        }
    }
    hits
}

/// The scene's streams against its single-ray queries, with equal traversal counts.
fn streams_match_single_rays(scene: &Scene, rays: &[Ray]) {
    let t_max: Vec<f32> = (0..rays.len()).map(|k| limits(k)[0]).collect();
    // Lengths that leave a partial last packet.
    for n in [rays.len(), rays.len() - 3, 1] {
        let (rays, t_max) = (&rays[..n], &t_max[..n]);
        let (mut stream, mut single) = (TraversalStats::default(), TraversalStats::default());
        let mut out = vec![None; n];
        scene.intersect_stream(rays, f32::INFINITY, &mut out, &mut stream);
        let mut occluded = vec![false; n];
        scene.occluded_stream(rays, t_max, &mut occluded, &mut stream);
        for (i, ray) in rays.iter().enumerate() {
            assert_eq!(
                out[i],
                scene.intersect(ray, f32::INFINITY, &mut single),
                "ray {i}"
            );
            assert_eq!(
                occluded[i],
                scene.occluded(ray, t_max[i], &mut single),
                "ray {i}"
            );
        }
        assert_eq!(stream, single);
    }
}

#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn packets_and_streams_on_a_real_mesh_answer_as_single_rays() {
    let p = appel_testdata::path("common-3d-test-models/spot.obj");
    let d = model_description("spot.obj");
    let mut scene = Scene::new(&d, p.parent().unwrap()).unwrap();
    let framed = frame_model(&d, scene.geometry.bounds());
    scene.set_view(&framed).unwrap();
    let b = scene.geometry.bounds();
    let (centre, reach) = (b.center(), b.extent().max_element());
    let rays = random_rays(48, centre, reach, 7);
    let hits = packets_match_single_rays(&scene.geometry, &rays);
    assert!(hits > 6 && hits < 42, "{hits} of 48 rays hit");
    let mut rays = random_rays(2000, centre, reach, 8);
    // Camera rays too: the coherent case.
    rays.extend((0..200).map(|i| {
        scene
            .camera
            .ray((i % 20) as f32 * 3.1, (i / 20) as f32 * 4.7)
    }));
    streams_match_single_rays(&scene, &rays);
}

#[test]
fn packets_and_streams_on_the_whitted_scene_answer_as_single_rays() {
    let text = builtin_scene("whitted").unwrap();
    let d = description_from_str(text, Syntax::Toml, Path::new("whitted")).unwrap();
    let scene = Scene::new(&d, Path::new(".")).unwrap();
    let centre = Vec3::new(0.0, 1.0, 0.0);
    let mut rays = random_rays(4000, centre, 4.0, 3);
    // Rays leaving the surfaces they start on, to both sides, as reflected, refracted and shadow
    // rays do; and camera rays.
    let mut stats = TraversalStats::default();
    for (i, ray) in rays.clone().iter().enumerate() {
        if let Some(h) = scene.intersect(ray, f32::INFINITY, &mut stats) {
            let si = scene.geometry.interaction(ray, &h);
            let w = if i % 2 == 0 { si.n } else { -si.n } + 0.5 * ray.dir;
            let origin = appel::math::offset_ray_origin(si.p, si.p_error, si.n, w);
            rays.push(Ray::new(origin, w));
        }
    }
    rays.extend((0..400).map(|i| {
        scene
            .camera
            .ray((i % 20) as f32 * 31.9, (i / 20) as f32 * 23.9)
    }));
    let hits = packets_match_single_rays(&scene.geometry, &rays);
    assert!(hits > rays.len() / 5, "{hits} of {} rays hit", rays.len());
    streams_match_single_rays(&scene, &rays);
}
