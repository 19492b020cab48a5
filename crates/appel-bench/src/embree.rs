//! Embree on the same rays as Appel's structures, in the same process and the same thread pools:
//! the peer issue 4 and issue 6 measure against. Embree is loaded at run time (`embree-peer`).

use super::{median, pools, throughput, BenchOptions, BenchRays, BenchResult, BenchTarget};
use appel::accel::{Accel, AccelKind, TraversalStats};
use appel::math::Ray;
use appel::scene::{Geometry, ShapeKind};
use embree_peer::{BuildQuality, Embree, EmbreeHit, TriangleScene};

#[derive(Clone, Copy, Debug)]
pub struct EmbreeBenchOptions {
    pub quality: BuildQuality,
    /// `RTC_SCENE_FLAG_ROBUST`: Embree's watertight mode. Off by default, Embree's fastest setting.
    pub robust: bool,
}

/// A scene's triangles as one flat mesh, the form Embree takes.
pub struct FlatTriangles {
    pub positions: Vec<[f32; 3]>,
    pub indices: Vec<[u32; 3]>,
}

/// The scene's triangles as one mesh whose triangle `k` is the geometry's primitive `k`, or an error
/// naming what Embree would not see.
pub fn flat_triangles(g: &Geometry) -> Result<FlatTriangles, String> {
    let mut positions = Vec::new();
    let mut indices = Vec::with_capacity(g.prims.len());
    let mut mesh_base: Vec<Option<u32>> = vec![None; g.meshes.len()];
    for p in g.prims.iter() {
        let shape = &g.shapes[p.shape as usize];
        let ShapeKind::Mesh(m) = shape.kind else {
            return Err(format!(
                "the Embree comparison takes triangles only; shape {} is not a mesh",
                shape.source.shape
            ));
        };
        let mesh = &g.meshes[m as usize];
        let base = *mesh_base[m as usize].get_or_insert_with(|| {
            let base = positions.len() as u32;
            positions.extend(mesh.positions.iter().map(|v| v.to_array()));
            base
        });
        let [a, b, c] = mesh.indices[p.index as usize];
        indices.push([base + a, base + b, base + c]);
    }
    Ok(FlatTriangles { positions, indices })
}

fn ray_arrays(r: &Ray) -> ([f32; 3], [f32; 3]) {
    (r.origin.to_array(), r.dir.to_array())
}

/// Measures Embree on the target's rays: build time (`rtcCommitScene`, median of the build runs),
/// the bytes Embree's memory monitor counts, `rtcIntersect1` on camera and incoherent rays,
/// `rtcOccluded1` on shadow rays, and `rtcIntersect8` on camera rays in packets of eight
/// consecutive pixels. Also reports how often Embree's hit is the same primitive as Appel's BVH's.
pub fn bench_embree(
    target: &BenchTarget,
    rays: &BenchRays,
    o: &BenchOptions,
    e: &EmbreeBenchOptions,
) -> Result<(BenchResult, String), String> {
    let g = &target.geometry;
    let FlatTriangles { positions, indices } = flat_triangles(g)?;
    let embree = Embree::load(o.threads).map_err(|e| e.to_string())?;
    let mut builds = vec![];
    let mut scene: Option<TriangleScene> = None;
    for _ in 0..o.build_runs.max(1) {
        drop(scene.take());
        let s = embree
            .triangle_scene(&positions, &indices, e.quality, e.robust)
            .map_err(|e| e.to_string())?;
        builds.push(s.build_time.as_secs_f64() * 1e3);
        scene = Some(s);
    }
    let scene = scene.expect("at least one build");
    let (one, all) = pools(o.threads);
    let runs = o.trace_runs;
    let closest = |r: &Ray| {
        let (org, dir) = ray_arrays(r);
        scene.intersect(org, dir, f32::INFINITY).is_some() as usize
    };
    let any = |s: &super::ShadowRay| {
        let (org, dir) = ray_arrays(&s.ray);
        scene.occluded(org, dir, s.t_max) as usize
    };
    let packets: Vec<Vec<([f32; 3], [f32; 3])>> = rays
        .primary
        .chunks(8)
        .map(|c| c.iter().map(ray_arrays).collect())
        .collect();
    let packet8 = |p: &Vec<([f32; 3], [f32; 3])>| {
        let mut out = [None; 8];
        scene.intersect8(p, &mut out);
        out.iter().filter(|h| h.is_some()).count()
    };
    let agreement = agreement(g, &scene, rays);
    let result = BenchResult {
        accel: if e.robust { "embree-robust" } else { "embree" }.to_string(),
        scene: target.name.clone(),
        triangle: if e.robust { "watertight" } else { "moller" }.to_string(),
        triangles: g.triangle_count(),
        primitives: g.prims.len(),
        build_ms: median(builds),
        bytes: scene.bytes,
        // The flat arrays Embree shares (it keeps no copy of them).
        scene_bytes: std::mem::size_of_val(positions.as_slice())
            + std::mem::size_of_val(indices.as_slice()),
        bytes_per_triangle: (scene.bytes
            + std::mem::size_of_val(positions.as_slice())
            + std::mem::size_of_val(indices.as_slice())) as f64
            / g.triangle_count().max(1) as f64,
        // Appel's own scene shares the process: a peak would not be Embree's alone.
        build_peak_rss: None,
        depth: 0,
        primary_mrays: throughput(&all, &rays.primary, 1, runs, closest),
        incoherent_mrays: throughput(&all, &rays.incoherent, 1, runs, closest),
        primary_mrays_1t: throughput(&one, &rays.primary, 1, runs, closest),
        incoherent_mrays_1t: throughput(&one, &rays.incoherent, 1, runs, closest),
        shadow_mrays: throughput(&all, &rays.shadow, 1, runs, any),
        shadow_mrays_1t: throughput(&one, &rays.shadow, 1, runs, any),
        path_mrays: throughput(&all, &rays.path, 1, runs, closest),
        path_mrays_1t: throughput(&one, &rays.path, 1, runs, closest),
        // Packets of eight, but the last may be short: count the rays, not 8 per packet.
        packet8_mrays: Some(
            throughput(&all, &packets, 8, runs, packet8) * rays.primary.len() as f64
                / (8 * packets.len()).max(1) as f64,
        ),
        packet8_mrays_1t: Some(
            throughput(&one, &packets, 8, runs, packet8) * rays.primary.len() as f64
                / (8 * packets.len()).max(1) as f64,
        ),
        packet8_mismatches: None,
        agreement: Some(agreement),
        threads: all.current_num_threads(),
        rays_primary: rays.primary.len(),
        rays_incoherent: rays.incoherent.len(),
        rays_shadow: rays.shadow.len(),
        rays_path: rays.path.len(),
        nodes_per_ray: 0.0,
        tests_per_ray: 0.0,
        incoherent_nodes_per_ray: 0.0,
        incoherent_tests_per_ray: 0.0,
        vs_embree: None,
    };
    let about = format!(
        "Embree {} ({} build quality{}, native 8-wide packets: {})",
        embree.version(),
        format!("{:?}", e.quality).to_lowercase(),
        if e.robust { ", robust" } else { "" },
        if embree.native_ray8() { "yes" } else { "no" }
    );
    Ok((result, about))
}

/// Fraction of camera and incoherent rays on which Embree's closest hit is the same primitive as
/// the BVH's, or both miss.
fn agreement(g: &Geometry, scene: &TriangleScene, rays: &BenchRays) -> f64 {
    let bvh = Accel::build(AccelKind::Bvh, g);
    let all = || rays.primary.iter().chain(&rays.incoherent);
    let same = all()
        .filter(|r| {
            let mut stats = TraversalStats::default();
            let ours = bvh
                .intersect(g, r, f32::INFINITY, &mut stats)
                .map(|h| h.prim);
            let (org, dir) = ray_arrays(r);
            let theirs = scene
                .intersect(org, dir, f32::INFINITY)
                .map(|h: EmbreeHit| h.prim);
            ours == theirs
        })
        .count();
    same as f64 / all().count().max(1) as f64
}
