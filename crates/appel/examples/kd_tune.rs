//! Tuning the kd-tree: `cargo run --release -p appel --example kd_tune -- MESH [ISECT_COST EMPTY_BONUS MAX_PRIMS DEPTH_ADD]...`
//! builds the kd-tree over a mesh file with each option set (and the BVH for reference) and prints
//! build time, bytes, and 1-thread Mrays/s on the camera, incoherent and shadow rays of `appel bench`.

use appel::accel::{Accel, AccelKind, KdOptions, KdTree, TraversalStats};
use appel::bench::{throughput, BenchRays, BenchTarget};
use appel::scene::{frame_model, model_description, Scene};
use std::path::Path;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = Path::new(&args[0]);
    let d = model_description(path.file_name().unwrap().to_str().unwrap());
    let mut scene = Scene::new(&d, path.parent().unwrap()).expect("scene");
    let framed = frame_model(&d, scene.geometry.bounds());
    scene.set_view(&framed);
    let target = BenchTarget {
        name: args[0].clone(),
        geometry: scene.geometry,
        camera: scene.camera,
        accel_options: Default::default(),
    };
    let rays = BenchRays::new(&target);
    let g = &target.geometry;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let n = g.prims.len() as f64;
    if std::env::var_os("KD_PROFILE").is_some() {
        // One pass of each ray kind through the default kd-tree, for callgrind.
        let kd = Accel::build(AccelKind::KdTree, g);
        let mut t = TraversalStats::default();
        let mut hits = 0;
        for r in rays.primary.iter().chain(&rays.incoherent) {
            hits += kd.intersect(g, r, f32::INFINITY, &mut t).is_some() as usize;
        }
        for s in &rays.shadow {
            hits += kd.occluded(g, &s.ray, s.t_max, &mut t) as usize;
        }
        println!("{hits} hits");
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
