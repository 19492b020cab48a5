//! `appel bench --scene NAME --frames N`: frames per second of a whole render, and its rays by kind;
//! for a path or direct scene, samples per second at `--spp`.

use super::{parse_accels, BenchArgs};
use crate::scene_args::load_scene;
use anyhow::{bail, Context, Result};
use appel::description::Description;
use appel_bench::frames::{bench_frames, bench_samples, SampleBench};

/// Real-time frames unless --frames says otherwise.
const FRAMES: usize = 100;
/// Whole Monte Carlo renders are long: a median of three unless --frames says otherwise.
const RUNS: usize = 3;
/// Real-time recursion depth unless --max-depth says otherwise.
const MAX_DEPTH: i32 = 5;

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
    let xml = args.params.format_options()?;
    for accel in accels {
        let (scene, _) = pool.install(|| {
            load_scene(Some(scene_name), &xml, |d| {
                adjust(d, args)?;
                if let Some(a) = accel {
                    d.render.accel = a.to_string();
                }
                args.view.apply(d)
            })
        })?;
        if scene.settings.integrator.is_monte_carlo() {
            let b = bench_samples(&scene, scene_name, args.frames.unwrap_or(RUNS), &pool)?;
            print_samples(&b, args.json)?;
            continue;
        }
        let b = bench_frames(&scene, scene_name, args.frames.unwrap_or(FRAMES), &pool)?;
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

/// Real-time mode renders 1 sample per pixel at a fixed depth; path and direct keep the scene's
/// samples and depth unless --spp and --max-depth say otherwise.
fn adjust(d: &mut Description, args: &BenchArgs) -> Result<()> {
    if args.frames == Some(0) {
        bail!("--frames must be at least 1");
    }
    if d.render.integrator.is_monte_carlo() {
        if let Some(spp) = args.spp {
            if spp == 0 {
                bail!("--spp must be at least 1");
            }
            d.render.spp = spp;
        }
        if let Some(depth) = args.max_depth {
            if depth < -1 {
                bail!("--max-depth: expected -1 (unlimited) or more, got {depth}");
            }
            d.render.max_depth = depth;
        }
        return Ok(());
    }
    if args.spp.is_some() {
        bail!("--spp applies to the path and direct integrators; this scene's renders 1 sample per pixel in real-time mode");
    }
    let depth = args.max_depth.unwrap_or(MAX_DEPTH);
    if depth < 0 {
        bail!("--max-depth: expected 0 or more for this scene's integrator, got {depth}");
    }
    d.render.spp = 1;
    d.render.max_depth = depth;
    Ok(())
}

fn print_samples(b: &SampleBench, json: bool) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string(b)?);
        return Ok(());
    }
    println!(
        "{}: {}, {}x{}, {} spp, max_depth {}, accel {}, {} threads, {} runs: median {:.1} ms, \
         min {:.1} ms, max {:.1} ms; {:.3} Msamples/s",
        b.scene,
        b.integrator,
        b.width,
        b.height,
        b.spp,
        b.max_depth,
        b.accel,
        b.threads,
        b.runs,
        b.render_ms_median,
        b.render_ms_min,
        b.render_ms_max,
        b.msamples_per_second
    );
    println!(
        "rays per render: {} (camera {}, shadow {}, reflection {}, refraction {}), {:.2} per sample, {:.1} Mrays/s",
        b.rays_per_render,
        b.camera_rays,
        b.shadow_rays,
        b.reflection_rays,
        b.refraction_rays,
        b.rays_per_sample,
        b.mrays_per_second
    );
    Ok(())
}
