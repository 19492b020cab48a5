//! The measurement behind `appel bench`: for each acceleration structure, build time and memory, and
//! closest-hit throughput on the scene's camera rays and on incoherent rays, with one thread and with
//! all of them; and the same figures for Embree on the same rays ([`embree`]); and frames per
//! second of whole renders ([`frames`]).

mod embree;
pub mod frames;
mod pairing;
mod path_rays;
pub mod rss;
pub use embree::{bench_embree, flat_triangles, EmbreeBenchOptions, FlatTriangles};
pub use pairing::{bench_pairings, embree_robust_for, Pairing};
pub use path_rays::path_rays;

use appel::accel::{Accel, AccelKind, AccelOptions, TraversalStats};
use appel::description::CameraDesc;
use appel::geometry::procedural::{scattered_triangles, teapot_in_stadium, SplitMix64};
use appel::geometry::TriangleMesh;
use appel::math::{offset_ray_origin, orthonormal_basis, Aabb, Ray, Vec3};
use appel::scene::{Camera, Geometry};
use rayon::prelude::*;
use std::time::Instant;

/// What is measured: geometry and the camera whose rays are cast.
pub struct BenchTarget {
    pub name: String,
    pub geometry: Geometry,
    pub camera: Camera,
    /// The structures' build parameters (a scene file's `[render.bvh]` and the like).
    pub accel_options: AccelOptions,
}

/// Generated benchmark scenes.
pub const BENCH_SCENES: &[(&str, &str)] = &[
    (
        "uniform",
        "small triangles spread evenly through a cube: the grid's best case",
    ),
    (
        "teapot-in-stadium",
        "a dense small mesh in the middle of a huge sparse one: the grid's worst case",
    ),
];

/// Builds a generated benchmark scene with about `triangles` triangles.
pub fn bench_scene(name: &str, triangles: usize, width: u32, height: u32) -> Option<BenchTarget> {
    let (mesh, eye, look_at): (TriangleMesh, Vec3, Vec3) = match name {
        "uniform" => {
            let n = triangles.max(1);
            // Triangles about as large as the spacing between them.
            let size = 2.0 / (n as f32).cbrt();
            let mesh = scattered_triangles(n, Vec3::splat(-1.0), Vec3::splat(1.0), size, 7);
            (mesh, Vec3::new(0.3, 0.4, 3.5), Vec3::ZERO)
        }
        "teapot-in-stadium" => (
            teapot_in_stadium(triangles),
            Vec3::new(2.5, 2.2, 3.5),
            Vec3::Y,
        ),
        _ => return None,
    };
    let mut geometry = Geometry::default();
    geometry.push_mesh(mesh, 0);
    let camera = Camera::new(&CameraDesc {
        eye: eye.into(),
        look_at: look_at.into(),
        up: [0.0, 1.0, 0.0],
        fov: 45.0,
        width,
        height,
        ..CameraDesc::default()
    });
    Some(BenchTarget {
        name: name.to_string(),
        geometry,
        camera,
        accel_options: AccelOptions::default(),
    })
}

/// One structure's figures.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchResult {
    pub accel: String,
    pub scene: String,
    /// The ray-triangle test: `watertight` or `moller` (Embree's robust mode is watertight, its
    /// default Moller-Trumbore).
    pub triangle: String,
    pub triangles: usize,
    pub primitives: usize,
    /// Median build time over the build runs.
    pub build_ms: f64,
    pub bytes: usize,
    /// Bytes of what the structure is built over: the scene's meshes and primitive list
    /// ([`Geometry::bytes`]). With `bytes`, the scene's final size.
    pub scene_bytes: usize,
    /// `(bytes + scene_bytes) / triangles`.
    pub bytes_per_triangle: f64,
    /// The process's peak resident memory during the first build (scene, structure, the builder's
    /// scratch and the benchmark's rays), where the system reports it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub build_peak_rss: Option<u64>,
    pub depth: usize,
    /// Closest-hit Mrays/s on camera rays, with all `threads`.
    pub primary_mrays: f64,
    /// Closest-hit Mrays/s on incoherent rays, with all `threads`.
    pub incoherent_mrays: f64,
    pub primary_mrays_1t: f64,
    pub incoherent_mrays_1t: f64,
    /// Any-hit Mrays/s on shadow rays (camera hit to a point light), with all `threads` and with one.
    pub shadow_mrays: f64,
    pub shadow_mrays_1t: f64,
    /// Closest-hit Mrays/s on the rays of a diffuse path's deeper bounces ([`path_rays`]), with all
    /// `threads` and with one.
    pub path_mrays: f64,
    pub path_mrays_1t: f64,
    /// Camera rays traced as packets of eight (a peer's packet mode), all `threads` and one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub packet8_mrays: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub packet8_mrays_1t: Option<f64>,
    /// Fraction of camera and incoherent rays on which a peer reports the same primitive as Appel's
    /// BVH (or a miss for both).
    /// Camera rays whose packet hit is not the single-ray hit (BVH only; 0 unless two primitives
    /// are hit at exactly the same distance).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub packet8_mismatches: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub agreement: Option<f64>,
    pub threads: usize,
    pub rays_primary: usize,
    pub rays_incoherent: usize,
    pub rays_shadow: usize,
    pub rays_path: usize,
    /// Mean nodes (or cells) visited and primitive tests per camera ray.
    pub nodes_per_ray: f64,
    pub tests_per_ray: f64,
    /// The same means for the incoherent rays.
    pub incoherent_nodes_per_ray: f64,
    pub incoherent_tests_per_ray: f64,
    /// This structure against Embree with the same triangle test, measured beside it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vs_embree: Option<PeerRatios>,
}

/// One structure over a peer measured on the same rays in the same run: throughput ratios (above 1:
/// the structure is faster) and the build time's ratio (below 1: the structure builds faster).
#[derive(Clone, Debug, serde::Serialize)]
pub struct PeerRatios {
    /// The peer's row (`accel` of its [`BenchResult`]).
    pub peer: String,
    pub camera_1t: f64,
    pub incoherent_1t: f64,
    pub shadow_1t: f64,
    pub camera: f64,
    pub incoherent: f64,
    pub shadow: f64,
    pub path_1t: f64,
    pub path: f64,
    /// Camera-ray packets of eight against the peer's (BVH only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub packet8_1t: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub packet8: Option<f64>,
    pub build: f64,
}

impl PeerRatios {
    pub fn of(ours: &BenchResult, peer: &BenchResult) -> Self {
        let r = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
        let opt = |a: Option<f64>, b: Option<f64>| Some(r(a?, b?));
        Self {
            peer: peer.accel.clone(),
            camera_1t: r(ours.primary_mrays_1t, peer.primary_mrays_1t),
            incoherent_1t: r(ours.incoherent_mrays_1t, peer.incoherent_mrays_1t),
            shadow_1t: r(ours.shadow_mrays_1t, peer.shadow_mrays_1t),
            camera: r(ours.primary_mrays, peer.primary_mrays),
            incoherent: r(ours.incoherent_mrays, peer.incoherent_mrays),
            shadow: r(ours.shadow_mrays, peer.shadow_mrays),
            path_1t: r(ours.path_mrays_1t, peer.path_mrays_1t),
            path: r(ours.path_mrays, peer.path_mrays),
            packet8_1t: opt(ours.packet8_mrays_1t, peer.packet8_mrays_1t),
            packet8: opt(ours.packet8_mrays, peer.packet8_mrays),
            build: r(ours.build_ms, peer.build_ms),
        }
    }
}

pub struct BenchOptions {
    pub build_runs: usize,
    pub trace_runs: usize,
    pub threads: usize,
}

/// Camera rays of every pixel centre, in the exact convention.
pub fn camera_rays(camera: &Camera) -> Vec<Ray> {
    (0..camera.height)
        .flat_map(|j| (0..camera.width).map(move |i| camera.pixel_ray(i, j)))
        .collect()
}

/// From each camera hit, one ray in a uniformly random direction on the hemisphere of the geometric
/// normal facing the camera (fixed seed), leaving from the error-bound offset of the hit point.
pub fn incoherent_rays(target: &BenchTarget, accel: &Accel, primary: &[Ray]) -> Vec<Ray> {
    let g = &target.geometry;
    let mut rng = SplitMix64(0x5eed);
    let mut out = Vec::with_capacity(primary.len());
    let mut stats = TraversalStats::default();
    for ray in primary {
        let Some(hit) = accel.intersect(g, ray, f32::INFINITY, &mut stats) else {
            continue;
        };
        let hit = g.scene_hit(hit);
        let si = g.interaction(ray, &hit);
        let n = if si.n.dot(ray.dir) > 0.0 { -si.n } else { si.n };
        let (z, phi) = (rng.next_f32(), std::f32::consts::TAU * rng.next_f32());
        let r = (1.0 - z * z).max(0.0).sqrt();
        let (s, t) = orthonormal_basis(n);
        let dir = (r * phi.cos() * s + r * phi.sin() * t + z * n).normalize();
        out.push(Ray::new(
            offset_ray_origin(si.p, si.p_error, si.n, dir),
            dir,
        ));
    }
    out
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Mrays/s of `trace` over `items` (rays, or packets of `rays_per_item` rays) in the given pool
/// (median of `runs`). `trace` returns how many hits it found, so that no work can be optimised away.
pub fn throughput<T: Sync>(
    pool: &rayon::ThreadPool,
    items: &[T],
    rays_per_item: usize,
    runs: usize,
    trace: impl Fn(&T) -> usize + Sync,
) -> f64 {
    if items.is_empty() {
        return 0.0;
    }
    let times: Vec<f64> = (0..runs.max(1))
        .map(|_| {
            let start = Instant::now();
            let hits: usize = pool.install(|| {
                items
                    .par_chunks((1024 / rays_per_item).max(1))
                    .map(|chunk| chunk.iter().map(&trace).sum::<usize>())
                    .sum()
            });
            std::hint::black_box(hits);
            start.elapsed().as_secs_f64()
        })
        .collect();
    (items.len() * rays_per_item) as f64 / median(times) / 1e6
}

/// A shadow ray: any hit with `t` in `(0, t_max)`.
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay {
    pub ray: Ray,
    pub t_max: f32,
}

/// The rays every structure is measured on: the same for all, so their figures compare.
pub struct BenchRays {
    pub primary: Vec<Ray>,
    pub incoherent: Vec<Ray>,
    pub shadow: Vec<ShadowRay>,
    pub path: Vec<Ray>,
}

impl BenchRays {
    /// Camera rays, and the incoherent, shadow and path rays that leave their hits, found with the
    /// default structure.
    pub fn new(target: &BenchTarget) -> Self {
        let accel = Accel::build(AccelKind::default(), &target.geometry);
        let primary = camera_rays(&target.camera);
        let incoherent = incoherent_rays(target, &accel, &primary);
        let shadow = shadow_rays(target, &accel, &primary);
        let path = path_rays(target, &accel, &primary);
        Self {
            primary,
            incoherent,
            shadow,
            path,
        }
    }
}

/// Where the benchmark's point light sits: above the scene and off to one side, two bounding-box
/// diagonals from its centre, so that shadow rays are long and not axis-aligned.
fn bench_light(bounds: &Aabb) -> Vec3 {
    let d = (bounds.max - bounds.min).length().max(1e-3);
    bounds.center() + Vec3::new(0.6, 1.6, 0.8).normalize() * 2.0 * d
}

/// From each camera hit, one shadow ray toward [`bench_light`], ending at the light.
pub fn shadow_rays(target: &BenchTarget, accel: &Accel, primary: &[Ray]) -> Vec<ShadowRay> {
    let g = &target.geometry;
    let light = bench_light(&g.bounds());
    let mut stats = TraversalStats::default();
    primary
        .iter()
        .filter_map(|ray| {
            let hit = accel.intersect(g, ray, f32::INFINITY, &mut stats)?;
            let si = g.interaction(ray, &g.scene_hit(hit));
            let to_light = light - si.p;
            let dir = to_light.normalize();
            let origin = offset_ray_origin(si.p, si.p_error, si.n, dir);
            let t_max = (light - origin).length();
            Some(ShadowRay {
                ray: Ray::new(origin, dir),
                t_max,
            })
        })
        .collect()
}

/// Measures one structure on the target.
pub fn bench_accel(
    target: &BenchTarget,
    rays: &BenchRays,
    kind: AccelKind,
    o: &BenchOptions,
) -> BenchResult {
    let g = &target.geometry;
    let mut builds = vec![];
    let mut accel = None;
    let mut build_peak_rss = None;
    for run in 0..o.build_runs.max(1) {
        // The first build's peak: later ones run while the structure before them is held.
        let measure_peak = run == 0 && rss::reset_peak();
        let start = Instant::now();
        let a = Accel::build_with(kind, g, &target.accel_options);
        builds.push(start.elapsed().as_secs_f64() * 1e3);
        if measure_peak {
            build_peak_rss = rss::peak_bytes();
        }
        accel = Some(a);
    }
    let accel = accel.expect("at least one build");
    let stats = accel.stats();
    // A structure that needs thousands of tests per ray (brute force; a grid with a dense mesh in one
    // cell) is measured on an evenly strided subset of the rays, so every benchmark finishes in
    // seconds; the rate is per ray, so it stays comparable. The subset keeps each timed pass under
    // about 1e8 primitive tests.
    let probe_stride = (rays.primary.len() / 2000).max(1);
    let mut probe = TraversalStats::default();
    for r in rays.primary.iter().step_by(probe_stride) {
        accel.intersect(g, r, f32::INFINITY, &mut probe);
    }
    let tests_per_ray = probe.prim_tests as f64 / probe.rays.max(1) as f64;
    let budget = (1e8 / tests_per_ray.max(1.0)).max(200.0) as usize;
    let subset = |rays: &[Ray]| -> Vec<Ray> {
        let stride = rays.len().div_ceil(budget).max(1);
        rays.iter().step_by(stride).copied().collect()
    };
    let primary = subset(&rays.primary);
    let incoherent = subset(&rays.incoherent);
    let path = subset(&rays.path);
    let shadow: Vec<ShadowRay> = {
        let stride = rays.shadow.len().div_ceil(budget).max(1);
        rays.shadow.iter().step_by(stride).copied().collect()
    };
    let trace_runs = if primary.len() < rays.primary.len() {
        1
    } else {
        o.trace_runs
    };
    let count = |rays: &[Ray]| {
        let mut t = TraversalStats::default();
        for r in rays {
            accel.intersect(g, r, f32::INFINITY, &mut t);
        }
        let per_ray = |x: u64| x as f64 / t.rays.max(1) as f64;
        (per_ray(t.nodes_visited), per_ray(t.prim_tests))
    };
    let (nodes_per_ray, tests_per_ray) = count(&primary);
    let (incoherent_nodes_per_ray, incoherent_tests_per_ray) = count(&incoherent);
    let (one, all) = pools(o.threads);
    let closest = |r: &Ray| {
        let mut stats = TraversalStats::default();
        accel.intersect(g, r, f32::INFINITY, &mut stats).is_some() as usize
    };
    let any = |s: &ShadowRay| {
        let mut stats = TraversalStats::default();
        accel.occluded(g, &s.ray, s.t_max, &mut stats) as usize
    };
    // Packets of eight consecutive pixels, as Embree's `rtcIntersect8` is measured; only the BVH
    // has a packet path (every other structure would just loop over single rays).
    let packets: Vec<&[Ray]> = primary.chunks(appel::accel::bvh::PACKET).collect();
    let packet = |p: &&[Ray]| {
        let mut out = [None; appel::accel::bvh::PACKET];
        let mut stats = TraversalStats::default();
        accel.intersect_packet(g, p, f32::INFINITY, &mut out, &mut stats);
        out.iter().filter(|h| h.is_some()).count()
    };
    let is_bvh = matches!(accel, Accel::Bvh(_));
    let packet_rate = |pool: &rayon::ThreadPool| {
        is_bvh.then(|| {
            throughput(
                pool,
                &packets,
                appel::accel::bvh::PACKET,
                trace_runs,
                packet,
            ) * primary.len() as f64
                / (appel::accel::bvh::PACKET * packets.len()).max(1) as f64
        })
    };
    let mismatches = is_bvh.then(|| {
        let mut stats = TraversalStats::default();
        packets
            .iter()
            .map(|p| {
                let mut out = [None; appel::accel::bvh::PACKET];
                accel.intersect_packet(g, p, f32::INFINITY, &mut out, &mut stats);
                p.iter()
                    .zip(out)
                    .filter(|(r, h)| accel.intersect(g, r, f32::INFINITY, &mut stats) != *h)
                    .count()
            })
            .sum()
    });
    let runs = trace_runs;
    BenchResult {
        accel: kind.name().to_string(),
        scene: target.name.clone(),
        triangle: g.triangle_test.name().to_string(),
        triangles: g.triangle_count(),
        primitives: g.prims.len(),
        build_ms: median(builds),
        bytes: stats.bytes,
        scene_bytes: g.bytes(),
        bytes_per_triangle: (stats.bytes + g.bytes()) as f64 / g.triangle_count().max(1) as f64,
        build_peak_rss,
        depth: stats.depth,
        primary_mrays: throughput(&all, &primary, 1, runs, closest),
        incoherent_mrays: throughput(&all, &incoherent, 1, runs, closest),
        primary_mrays_1t: throughput(&one, &primary, 1, runs, closest),
        incoherent_mrays_1t: throughput(&one, &incoherent, 1, runs, closest),
        shadow_mrays: throughput(&all, &shadow, 1, runs, any),
        shadow_mrays_1t: throughput(&one, &shadow, 1, runs, any),
        path_mrays: throughput(&all, &path, 1, runs, closest),
        path_mrays_1t: throughput(&one, &path, 1, runs, closest),
        packet8_mrays: packet_rate(&all),
        packet8_mrays_1t: packet_rate(&one),
        packet8_mismatches: mismatches,
        agreement: None,
        threads: all.current_num_threads(),
        rays_primary: primary.len(),
        rays_incoherent: incoherent.len(),
        rays_shadow: shadow.len(),
        rays_path: path.len(),
        nodes_per_ray,
        tests_per_ray,
        incoherent_nodes_per_ray,
        incoherent_tests_per_ray,
        vs_embree: None,
    }
}

/// A one-thread pool and a pool of `threads` (0: all cores).
pub(crate) fn pools(threads: usize) -> (rayon::ThreadPool, rayon::ThreadPool) {
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("a thread pool of a valid size")
    };
    (pool(1), pool(threads))
}
