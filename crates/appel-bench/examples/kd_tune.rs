//! Tuning the kd-tree: `cargo run --release -p appel-bench --example kd_tune -- MESH [ISECT_COST EMPTY_BONUS MAX_PRIMS DEPTH_ADD MAX_BAD]...`
//! (MESH may also name a built-in benchmark scene, of `KD_TRIANGLES` triangles)
//! builds the kd-tree over a mesh file with each option set (and the BVH for reference) and prints
//! build time, bytes, and 1-thread Mrays/s on the camera, incoherent and shadow rays of `appel bench`.
//! `KD_RACE=1`: builds every structure first, then times them in alternation (best of 7 passes) and
//! prints the BVH / kd-tree ratios. `KD_PROFILE=camera|incoherent|shadow|none`: one pass of that kind (or none)
//! through the kd-tree of the first option set (or the default; the BVH with `KD_BVH=1`), for
//! `valgrind --tool=callgrind` or `--tool=cachegrind --branch-sim=yes`.

use appel::accel::{Accel, AccelKind, KdOptions, KdTree, TraversalStats};
use appel::scene::{frame_model, model_description, Scene};
use appel_bench::{bench_scene, throughput, BenchRays, BenchTarget};
use std::path::Path;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // A built-in benchmark scene (`uniform`, `teapot-in-stadium`; `KD_TRIANGLES`, default 10^6)
    // or a mesh file.
    let triangles = std::env::var("KD_TRIANGLES").map_or(1_000_000, |v| v.parse().unwrap());
    let target = bench_scene(&args[0], triangles, 640, 480).unwrap_or_else(|| {
        let path = Path::new(&args[0]);
        let d = model_description(path.file_name().unwrap().to_str().unwrap());
        let mut scene = Scene::new(&d, path.parent().unwrap()).expect("scene");
        let framed = frame_model(&d, scene.geometry.bounds());
        scene.set_view(&framed).expect("framing lights");
        BenchTarget {
            name: args[0].clone(),
            geometry: scene.geometry,
            camera: scene.camera,
            accel_options: Default::default(),
        }
    });
    let rays = BenchRays::new(&target);
    let g = &target.geometry;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let n = g.prims.len() as f64;
    if std::env::var_os("KD_PROFILE").is_some() {
        // One pass of each ray kind through the default kd-tree, for callgrind.
        let kd = match args.get(1..6) {
            Some(v) => {
                let v: Vec<f32> = v.iter().map(|s| s.parse().unwrap()).collect();
                Accel::KdTree(KdTree::build_with(
                    g,
                    KdOptions {
                        intersect_cost: v[0],
                        empty_bonus: v[1],
                        max_prims: v[2] as usize,
                        max_depth: Some((v[3] as f64 + 1.3 * n.log2()).round() as usize),
                        max_bad: v[4] as u32,
                        ..KdOptions::default()
                    },
                ))
            }
            None => Accel::build(AccelKind::KdTree, g),
        };
        let mut t = TraversalStats::default();
        let mut hits = 0;
        let mut traced = 0;
        // KD_PROFILE=camera|incoherent|shadow traces only that kind (callgrind per kind).
        let kind = std::env::var("KD_PROFILE").unwrap();
        let bvh = Accel::build(AccelKind::Bvh, g);
        let accel = if std::env::var_os("KD_BVH").is_some() {
            &bvh
        } else {
            &kd
        };
        if kind == "none" {
            // The build and ray generation alone: subtracted from the other kinds' totals.
        } else if kind != "shadow" {
            let rs = if kind == "camera" {
                &rays.primary
            } else {
                &rays.incoherent
            };
            traced = rs.len();
            for r in rs {
                hits += accel.intersect(g, r, f32::INFINITY, &mut t).is_some() as usize;
            }
        } else {
            traced = rays.shadow.len();
            for s in &rays.shadow {
                hits += accel.occluded(g, &s.ray, s.t_max, &mut t) as usize;
            }
        }
        println!("{hits} hits of {traced} rays");
        return;
    }
    let mut sets: Vec<Option<KdOptions>> = vec![None];
    for chunk in args[1..].chunks(5) {
        let v: Vec<f32> = chunk.iter().map(|s| s.parse().unwrap()).collect();
        sets.push(Some(KdOptions {
            intersect_cost: v[0],
            empty_bonus: v[1],
            max_prims: v[2] as usize,
            max_depth: Some((v[3] as f64 + 1.3 * n.log2()).round() as usize),
            max_bad: v[4] as u32,
            ..KdOptions::default()
        }));
    }
    if std::env::var_os("KD_RACE").is_some() {
        // Every structure built first, then timed in alternation, best pass of each kept: the
        // least disturbed pass on a shared machine, and the same load for every structure.
        let accels: Vec<(String, Accel)> = sets
            .iter()
            .map(|set| match set {
                None => ("bvh".to_string(), Accel::build(AccelKind::Bvh, g)),
                Some(o) => (
                    format!(
                        "kd {:?}",
                        (o.intersect_cost, o.empty_bonus, o.max_prims, o.max_bad)
                    ),
                    Accel::KdTree(KdTree::build_with(g, *o)),
                ),
            })
            .collect();
        let mut best = vec![[0.0f64; 3]; accels.len()];
        for _ in 0..7 {
            for (k, (_, accel)) in accels.iter().enumerate() {
                let cam = throughput(&pool, &rays.primary, 1, 1, |r| {
                    accel
                        .intersect(g, r, f32::INFINITY, &mut TraversalStats::default())
                        .is_some() as usize
                });
                let inc = throughput(&pool, &rays.incoherent, 1, 1, |r| {
                    accel
                        .intersect(g, r, f32::INFINITY, &mut TraversalStats::default())
                        .is_some() as usize
                });
                let sh = throughput(&pool, &rays.shadow, 1, 1, |s| {
                    accel.occluded(g, &s.ray, s.t_max, &mut TraversalStats::default()) as usize
                });
                for (b, v) in best[k].iter_mut().zip([cam, inc, sh]) {
                    *b = b.max(v);
                }
            }
        }
        for (k, (name, accel)) in accels.iter().enumerate() {
            let [c, i, s] = best[k];
            let [bc, bi, bs] = best[0];
            let mut t = TraversalStats::default();
            for r in &rays.incoherent {
                accel.intersect(g, r, f32::INFINITY, &mut t);
            }
            let mut ts = TraversalStats::default();
            for s in &rays.shadow {
                accel.occluded(g, &s.ray, s.t_max, &mut ts);
            }
            let st = accel.stats();
            println!(
                "{name:<32} {:>10} B d{:2} inc n/t {:5.1} {:5.1} shadow n/t {:5.1} {:5.1}  cam {c:6.2} inc {i:6.3} shadow {s:6.3}  bvh/this {:.2} {:.2} {:.2}",
                st.bytes,
                st.depth,
                t.nodes_visited as f64 / t.rays as f64,
                t.prim_tests as f64 / t.rays as f64,
                ts.nodes_visited as f64 / ts.rays as f64,
                ts.prim_tests as f64 / ts.rays as f64,
                bc / c,
                bi / i,
                bs / s
            );
        }
        return;
    }
    for set in sets {
        let start = Instant::now();
        let (name, accel) = match set {
            None => ("bvh".to_string(), Accel::build(AccelKind::Bvh, g)),
            Some(o) => (
                format!(
                    "kd {:?}",
                    (
                        o.intersect_cost,
                        o.empty_bonus,
                        o.max_prims,
                        o.max_depth,
                        o.max_bad
                    )
                ),
                Accel::KdTree(KdTree::build_with(g, o)),
            ),
        };
        let build = start.elapsed().as_secs_f64() * 1e3;
        let cam = throughput(&pool, &rays.primary, 1, 3, |r| {
            accel
                .intersect(g, r, f32::INFINITY, &mut TraversalStats::default())
                .is_some() as usize
        });
        let inc = throughput(&pool, &rays.incoherent, 1, 3, |r| {
            accel
                .intersect(g, r, f32::INFINITY, &mut TraversalStats::default())
                .is_some() as usize
        });
        let sh = throughput(&pool, &rays.shadow, 1, 3, |s| {
            accel.occluded(g, &s.ray, s.t_max, &mut TraversalStats::default()) as usize
        });
        let st = accel.stats();
        println!(
            "  nodes {} leaves {} depth {}",
            st.nodes, st.leaves, st.depth
        );
        let mut t = TraversalStats::default();
        for r in &rays.incoherent {
            accel.intersect(g, r, f32::INFINITY, &mut t);
        }
        println!(
            "{name:<40} build {build:7.1} ms {:>10} B  cam {cam:5.2} inc {inc:5.3} shadow {sh:5.3} Mrays/s  inc nodes {:.1} tests {:.1}",
            accel.stats().bytes,
            t.nodes_visited as f64 / t.rays as f64,
            t.prim_tests as f64 / t.rays as f64
        );
    }
}
