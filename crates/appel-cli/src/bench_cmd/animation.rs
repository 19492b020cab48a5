//! `appel bench anim.toml --frames N`: frames 0 to N-1 of an animated scene, each reached from
//! the previous by the refit policy of `appel::scene::Sequence`, with per frame the time to
//! refit and to rebuild, the time a build from scratch of the same frame takes, the render's
//! Mrays/s and the SAH cost drift of the refitted trees.

use super::{parse_accels, BenchArgs};
use crate::scene_args::load_description_only;
use anyhow::{bail, Context, Result};
use appel::description::animation::{at_frame, frame_count};
use appel::render::{render, RenderOptions};
use appel::scene::{Scene, Sequence};

/// One frame's figures.
struct FrameFigures {
    scene: String,
    accel: String,
    frame: u32,
    load_ms: f64,
    /// Refitting the structures that were refitted.
    refit_ms: f64,
    /// Building the structures that were rebuilt (the top level over instances, trees the
    /// policy rebuilt, structures that cannot refit).
    rebuild_ms: f64,
    refitted: usize,
    rebuilt: usize,
    rebuilt_by_policy: usize,
    /// Building every structure of the frame from scratch, for comparison.
    scratch_build_ms: f64,
    /// SAH cost after the refit over the cost when last built (the largest over the structures).
    sah_drift: Option<f64>,
    render_ms: f64,
    rays: u64,
    mrays_per_second: f64,
}

pub fn run(target: &str, frames: usize, args: &BenchArgs) -> Result<()> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("cannot start the worker threads")?;
    let xml = args.params.format_options()?;
    let accels: Vec<Option<&str>> = match &args.accel {
        Some(list) => parse_accels(list)?
            .into_iter()
            .map(|k| Some(k.name()))
            .collect(),
        None => vec![None],
    };
    for accel in accels {
        let (d, base_dir) = load_description_only(Some(target), &xml, |d| {
            if let Some(a) = accel {
                d.render.accel = a.to_string();
            }
            args.view.apply(d)
        })?;
        let n = frame_count(&d) as usize;
        if d.animation.is_none() {
            bail!("{target}: --frames without --scene measures an animation, and this scene has no [animation] table");
        }
        if frames == 0 || frames > n {
            bail!("--frames {frames}: the animation has {n} frames");
        }
        let mut seq = pool.install(|| Sequence::new(&d, &base_dir, 0))?;
        let (mut refit, mut rebuild, mut scratch, mut mrays) = (0.0, 0.0, 0.0, 0.0);
        for frame in 0..frames as u32 {
            let update = if frame == 0 {
                None
            } else {
                Some(pool.install(|| seq.advance(frame))?)
            };
            let scratch_build = if frame == 0 {
                seq.scene.timings.build
            } else {
                pool.install(|| Scene::new(&at_frame(&d, frame), &base_dir))?
                    .timings
                    .build
            };
            let (_, stats) = pool.install(|| render(&seq.scene, &RenderOptions::default()))?;
            // Frame 0 is the first build: every structure built from scratch.
            let u = update.unwrap_or_else(|| seq.first_build.clone());
            let f = FrameFigures {
                scene: target.to_string(),
                accel: seq.scene.settings.accel.name().to_string(),
                frame,
                load_ms: u.load.as_secs_f64() * 1e3,
                refit_ms: u.refit.as_secs_f64() * 1e3,
                rebuild_ms: u.rebuild.as_secs_f64() * 1e3,
                refitted: u.refitted,
                rebuilt: u.rebuilt,
                rebuilt_by_policy: u.rebuilt_by_policy,
                scratch_build_ms: scratch_build.as_secs_f64() * 1e3,
                sah_drift: u.sah_drift,
                render_ms: stats.time.as_secs_f64() * 1e3,
                rays: stats.rays.total(),
                mrays_per_second: stats.mrays_per_second(),
            };
            if frame > 0 {
                refit += f.refit_ms;
                rebuild += f.rebuild_ms;
                scratch += f.scratch_build_ms;
            }
            mrays += f.mrays_per_second;
            if args.json {
                let json = serde_json::json!({
                    "scene": f.scene,
                    "accel": f.accel,
                    "frame": f.frame,
                    "load_ms": f.load_ms,
                    "refit_ms": f.refit_ms,
                    "rebuild_ms": f.rebuild_ms,
                    "refitted": f.refitted,
                    "rebuilt": f.rebuilt,
                    "rebuilt_by_policy": f.rebuilt_by_policy,
                    "scratch_build_ms": f.scratch_build_ms,
                    "sah_drift": f.sah_drift,
                    "render_ms": f.render_ms,
                    "rays": f.rays,
                    "mrays_per_second": f.mrays_per_second,
                });
                println!("{json}");
            } else {
                println!(
                    "{} {} frame {:3}: refit {:7.2} ms ({} refitted), rebuild {:7.2} ms ({} rebuilt, {} by policy), \
                     from scratch {:7.2} ms, SAH drift {}, render {:7.1} ms, {:.2} Mrays/s",
                    f.scene,
                    f.accel,
                    f.frame,
                    f.refit_ms,
                    f.refitted,
                    f.rebuild_ms,
                    f.rebuilt,
                    f.rebuilt_by_policy,
                    f.scratch_build_ms,
                    f.sah_drift.map_or("-".into(), |d| format!("{d:.3}")),
                    f.render_ms,
                    f.mrays_per_second
                );
            }
        }
        if !args.json && frames > 1 {
            let k = (frames - 1) as f64;
            println!(
                "mean over frames 1..{frames}: refit {:.2} ms + rebuild {:.2} ms against {:.2} ms from scratch; {:.2} Mrays/s",
                refit / k,
                rebuild / k,
                scratch / k,
                mrays / frames as f64
            );
        }
    }
    Ok(())
}
