//! `appel render anim.toml --frames A..B -o out_{frame:04}.png`: renders frames A to B-1 of an
//! animated scene, each written to the output name with `{frame...}` replaced by its number. The
//! structures of one frame are refitted to the next (`appel::scene::Sequence`).

use crate::render_cmd::RenderArgs;
use crate::scene_args::{load_description_only, parse_frames};
use anyhow::{anyhow, bail, Context, Result};
use appel::description::animation::{check_pattern, frame_count, frame_file, is_pattern};
use appel::output::image::{write_image_with, Aovs};
use appel::render::cost::CostImage;
use appel::render::{render, RenderOptions};
use appel::scene::Sequence;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;

pub fn run(args: &RenderArgs, frames: &str, aovs: Aovs) -> Result<()> {
    let range = parse_frames(frames)?;
    let output = args.output.to_string_lossy().into_owned();
    if range.len() > 1 && !is_pattern(&output) {
        bail!(
            "-o {output}: several frames need a name with `{{frame}}` or `{{frame:04}}` in it, \
             such as out_{{frame:04}}.png"
        );
    }
    check_pattern(&output).map_err(|e| anyhow!("-o: {e}"))?;
    if args.window.is_some() || args.time_limit.is_some() {
        bail!("--frames renders whole frames: --window and --time-limit are for single images");
    }
    let xml = args.params.format_options()?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("cannot start the worker threads")?;
    let (d, base_dir) = load_description_only(args.scene.as_deref(), &xml, |d| {
        crate::render_cmd::apply_settings(d, args)
    })?;
    let n = frame_count(&d);
    if range.end > n {
        bail!(
            "--frames {frames}: the scene has {n} frames (0 to {}){}",
            n - 1,
            if d.animation.is_none() {
                "; it has no [animation] table"
            } else {
                ""
            }
        );
    }
    let pixels = d.camera.width as u64 * d.camera.height as u64;
    let bar = (!args.quiet && std::io::stderr().is_terminal())
        .then(|| frames_bar(range.len() as u64 * pixels));
    let say = |what: String| {
        if let Some(b) = &bar {
            b.set_message(what);
        }
    };
    say(format!("frame {}: loading", range.start));
    let mut sequence = pool.install(|| Sequence::new(&d, &base_dir, range.start))?;
    for (done_frames, frame) in range.clone().enumerate() {
        let update = if frame == sequence.frame {
            None
        } else {
            say(format!("frame {frame}: loading"));
            Some(pool.install(|| sequence.advance(frame))?)
        };
        say(format!("frame {frame}"));
        let before = done_frames as u64 * pixels;
        let progress = |done: u64| {
            if let Some(b) = &bar {
                b.set_position(before + done);
            }
        };
        let options = RenderOptions {
            progress: Some(&progress),
            ..Default::default()
        };
        let scene = &sequence.scene;
        let (film, stats) = pool.install(|| render(scene, &options))?;
        let path = std::path::PathBuf::from(frame_file(&output, frame));
        let cost = aovs.cost.then(|| pool.install(|| CostImage::of(scene)));
        write_image_with(&path, &film, aovs, cost.as_ref())?;
        let structures = match &update {
            None => format!(
                "load {:.3}s build {:.3}s",
                scene.timings.load.as_secs_f64(),
                scene.timings.build.as_secs_f64()
            ),
            Some(u) => format!(
                "load {:.3}s refit {:.1} ms ({} refitted) rebuild {:.1} ms ({} rebuilt){}",
                u.load.as_secs_f64(),
                u.refit.as_secs_f64() * 1e3,
                u.refitted,
                u.rebuild.as_secs_f64() * 1e3,
                u.rebuilt,
                u.sah_drift
                    .map(|d| format!(", SAH drift {d:.3}"))
                    .unwrap_or_default()
            ),
        };
        let line = format!(
            "{}: frame {frame} | {structures} | render {:.3}s | {:.2} Mrays/s",
            path.display(),
            stats.time.as_secs_f64(),
            stats.mrays_per_second()
        );
        // Printed above the bar, which stays at the bottom of the terminal.
        match &bar {
            Some(b) => b.suspend(|| println!("{line}")),
            None => println!("{line}"),
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    Ok(())
}

/// A bar over the pixels of all the frames, with the frame at work as its message.
fn frames_bar(pixels: u64) -> ProgressBar {
    let bar = ProgressBar::new(pixels);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} rendering [{bar:40}] {percent:>3}% {elapsed} (eta {eta}) {msg}",
        )
        .expect("static template")
        .progress_chars("=> "),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}
