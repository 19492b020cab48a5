//! `appel bench --scene NAME --frames N`: frames per second of a whole render, and its rays by kind.

use super::{parse_accels, BenchArgs};
use crate::scene_args::load_scene;
use anyhow::{Context, Result};
use appel::bench_frames::bench_frames;

pub fn run(scene_name: &str, args: &BenchArgs) -> Result<()> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("cannot start the worker threads")?;
    // The scene's own structure, or each one --accel lists.
    let accels: Vec<Option<&str>> = match &args.accel {
        Some(list) => parse_accels(list)?
            .into_iter()
            .map(|k| Some(k.name()))
            .collect(),
        None => vec![None],
    };
    for accel in accels {
        let (scene, _) = pool.install(|| {
            load_scene(Some(scene_name), |d| {
                d.render.spp = 1;
                d.render.max_depth = args.max_depth as i32;
                if let Some(a) = accel {
                    d.render.accel = a.to_string();
                }
                args.view.apply(d)
            })
        })?;
        let b = bench_frames(&scene, scene_name, args.frames, &pool)?;
        if args.json {
            println!("{}", serde_json::to_string(&b)?);
        } else {
            println!(
                "{}: {}x{}, {} spp, max_depth {}, accel {}, {} threads, {} frames: median {:.2} ms \
                 ({:.1} fps), min {:.2} ms, max {:.2} ms",
                b.scene,
                b.width,
                b.height,
                b.spp,
                b.max_depth,
                b.accel,
                b.threads,
                b.frames,
                b.frame_ms_median,
                b.fps,
                b.frame_ms_min,
                b.frame_ms_max
            );
            println!(
                "rays per frame: {} (camera {}, shadow {}, reflection {}, refraction {}), {:.1} Mrays/s",
                b.rays_per_frame,
                b.camera_rays,
                b.shadow_rays,
                b.reflection_rays,
                b.refraction_rays,
                b.mrays_per_second
            );
        }
    }
    Ok(())
}
