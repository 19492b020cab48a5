//! Builds the binary BVH of a generated bench scene and prints a hash of its nodes and leaf order,
//! its statistics and SAH cost, and the build time: for checking that a change to the builder
//! leaves the tree bit for bit as it was.
//!
//! `cargo run --release -p appel-bench --example bvh_tree_check -- [scene] [triangles] [builds] [block]`
//! (block 4, the default, is the tree the wide layouts collapse; block 1 the binary layout's).

use appel::accel::{Bvh, BvhOptions};
use std::hash::{Hash, Hasher};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene = args.get(1).map_or("teapot-in-stadium", |s| s.as_str());
    let n: usize = args.get(2).map_or(1_000_000, |s| s.parse().unwrap());
    let builds: usize = args.get(3).map_or(1, |s| s.parse().unwrap());
    // The binary tree the wide layouts collapse is built with blocks of 4: `block 4` gives it.
    let block: usize = args.get(4).map_or(4, |s| s.parse().unwrap());
    let t = appel_bench::bench_scene(scene, n, 16, 16).expect("scene");
    let opts = BvhOptions {
        width: 2,
        block,
        ..BvhOptions::default()
    };
    let mut times = Vec::new();
    let mut bvh = None;
    for _ in 0..builds {
        let t0 = Instant::now();
        let b = Bvh::build_with(&t.geometry, opts);
        times.push(t0.elapsed().as_secs_f64() * 1e3);
        bvh = Some(b);
    }
    let bvh = bvh.unwrap();
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for nd in bvh.nodes() {
        bytemuck::bytes_of(nd).hash(&mut h);
    }
    bvh.indices().hash(&mut h);
    let s = bvh.stats();
    times.sort_by(f64::total_cmp);
    println!(
        "{scene} {n} block {block}: nodes {} leaves {} depth {} sah {:.6} hash {:016x} build ms median {:.1} (threads {})",
        s.nodes,
        s.leaves,
        s.depth,
        s.sah_cost.unwrap_or(0.0),
        h.finish(),
        times[times.len() / 2],
        rayon::current_num_threads()
    );
}
