//! Builds each acceleration structure over a generated mesh and times closest-hit queries.
//!
//! `cargo run --release -p appel --example accel_bench -- [levels] [rays] [runs] [names]`
//!
//! The mesh is an icosphere subdivided `levels` times (20 * 4^levels triangles; 8 gives 1.31M) with
//! bumps pushed along the normal, so triangles vary in size and orientation. Two ray sets: camera
//! rays (a pinhole at distance 3, pixels in scanline order: coherent, like primary rays) and random
//! rays (origins on a sphere of radius 3 aimed at random points within radius 0.8: incoherent, like
//! bounces). Each figure is the median of `runs` runs, on 1 and then on 2 threads. All structures
//! must return the same `t` for every ray.

use appel::accel::{Accel, AccelKind, MeshPrimitives, TraversalStats};
use appel::geometry::TriangleMesh;
use appel::math::{Ray, Vec3};
use rayon::prelude::*;
use std::time::Instant;

fn icosphere(levels: u32) -> TriangleMesh {
    let mut m = appel::geometry::procedural::icosphere(levels);
    for p in &mut m.positions {
        let bump = 1.0 + 0.15 * (7.0 * p.x).sin() * (9.0 * p.y).sin() * (5.0 * p.z).cos();
        *p *= bump;
    }
    m
}

struct Rng(u32);

impl Rng {
    fn f(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        (self.0 >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0
    }

    fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.f(), self.f(), self.f());
            if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
                return v;
            }
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Closest hits of `rays` in parallel chunks; returns the summed statistics and each ray's `t`.
fn trace(
    accel: &Accel,
    prims: &MeshPrimitives,
    rays: &[Ray],
) -> (TraversalStats, Vec<Option<f32>>) {
    rays.par_chunks(1024)
        .map(|chunk| {
            let mut s = TraversalStats::default();
            let ts: Vec<Option<f32>> = chunk
                .iter()
                .map(|r| {
                    accel
                        .intersect(prims, r, f32::INFINITY, &mut s)
                        .map(|h| h.t)
                })
                .collect();
            (s, ts)
        })
        .reduce(
            || (TraversalStats::default(), Vec::new()),
            |(mut a, mut x), (b, y)| {
                a.merge(&b);
                x.extend(y);
                (a, x)
            },
        )
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let levels: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(8);
    let nrays: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(300_000);
    let runs: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(3);
    let names: Vec<&str> = args
        .get(4)
        .map(|s| s.split(',').collect())
        .unwrap_or(vec!["bvh", "grid", "kdtree"]);
    let mesh = icosphere(levels);
    let prims = MeshPrimitives::new(&mesh);
    let side = (nrays as f64).sqrt() as usize;
    let eye = Vec3::new(0.3, 0.4, 3.0);
    let camera: Vec<Ray> = (0..side * side)
        .map(|k| {
            let (x, y) = ((k % side) as f32, (k / side) as f32);
            let s = 2.4 / side as f32;
            let p = Vec3::new(-1.2 + x * s, 1.2 - y * s, 0.0);
            Ray::new(eye, (p - eye).normalize())
        })
        .collect();
    let mut rng = Rng(0x9E37_79B9);
    let random: Vec<Ray> = (0..nrays)
        .map(|_| {
            let o = rng.unit().normalize() * 3.0;
            let target = rng.unit() * 0.8;
            Ray::new(o, (target - o).normalize())
        })
        .collect();
    println!(
        "{} triangles, {} camera rays and {} random rays, median of {runs} runs",
        mesh.triangle_count(),
        camera.len(),
        random.len()
    );
    let mut reference: [Option<Vec<Option<f32>>>; 2] = [None, None];
    for name in names {
        let kind = AccelKind::from_name(name).expect("accel name");
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut builds = Vec::new();
            let mut accel: Option<Accel> = None;
            for _ in 0..runs {
                // Free the previous build first, so that only one is in memory at a time.
                drop(accel.take());
                let t = Instant::now();
                accel = Some(pool.install(|| Accel::build(kind, &prims)));
                builds.push(t.elapsed().as_secs_f64());
            }
            let accel = accel.expect("at least one run");
            let st = accel.stats();
            println!(
                "{name:7} threads {threads}: build {:8.1} ms | {} bytes, {} nodes, {} leaves, depth {}",
                median(builds) * 1e3,
                st.bytes,
                st.nodes,
                st.leaves,
                st.depth,
            );
            for (set, (label, rays)) in [("camera", &camera), ("random", &random)]
                .into_iter()
                .enumerate()
            {
                let mut traces = Vec::new();
                let mut stats = TraversalStats::default();
                let mut found = Vec::new();
                for _ in 0..runs {
                    let t = Instant::now();
                    (stats, found) = pool.install(|| trace(&accel, &prims, rays));
                    traces.push(t.elapsed().as_secs_f64());
                }
                match &reference[set] {
                    None => reference[set] = Some(found),
                    Some(r) => assert!(r == &found, "{name} disagrees with the first structure"),
                }
                let t = median(traces);
                println!(
                    "        {label} rays: {:7.1} ms = {:6.2} Mrays/s | per ray: {:.1} nodes, {:.1} prim tests",
                    t * 1e3,
                    rays.len() as f64 / t / 1e6,
                    stats.nodes_visited as f64 / stats.rays as f64,
                    stats.prim_tests as f64 / stats.rays as f64,
                );
            }
        }
    }
}
