//! `appel gen`: writes a large reproducible scene (issue 5) into a folder.

use anyhow::{bail, Context, Result};
use appel_gen::{city_scene, cloth_scene, ecosystem, GenOptions};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

#[derive(clap::Args)]
pub struct GenArgs {
    /// Which scene: `ecosystem` (a terrain and 20 instanced plant species: 20M unique, over 10^9
    /// instanced triangles), `city` (one mesh of 10M triangles, no instancing) or `cloth` (an
    /// animation: a waving flag, one PLY per frame, and a flock of keyframed instanced birds).
    #[arg(value_parser = ["ecosystem", "city", "cloth"])]
    scene: String,
    /// The folder to write into (created if missing): the scene file, binary PLY meshes and, for the
    /// ecosystem, placement lists.
    #[arg(short, long)]
    output: PathBuf,
    /// The same seed gives the same bytes.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Multiplies the number of plants placed (ecosystem).
    #[arg(long, default_value_t = 1.0)]
    density: f64,
    /// Multiplies every mesh's triangle count: 1 is the full scene, 0.001 a quick small one.
    #[arg(long, default_value_t = 1.0)]
    detail: f64,
    /// Print nothing but errors.
    #[arg(short, long)]
    quiet: bool,
}

pub fn run(args: GenArgs) -> Result<()> {
    for (flag, v) in [("--density", args.density), ("--detail", args.detail)] {
        if !(v.is_finite() && v > 0.0 && v <= 100.0) {
            bail!("{flag} must be a number in (0, 100], got {v}");
        }
    }
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: cannot create the folder", args.output.display()))?;
    let options = GenOptions {
        seed: args.seed,
        density: args.density,
        detail: args.detail,
    };
    let start = Instant::now();
    let quiet = args.quiet;
    // Ctrl-C stops at the next step: the file being written is finished (files are written whole
    // or not at all) and the scene file, written last, is not.
    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        let _ = ctrlc::set_handler(move || cancel.store(true, Ordering::SeqCst));
    }
    let step = |m: &str| -> appel::Result<()> {
        if cancel.load(Ordering::SeqCst) {
            return Err(appel::Error::Cancelled);
        }
        if !quiet {
            eprintln!("[{:6.1} s] {m}", start.elapsed().as_secs_f64());
        }
        Ok(())
    };
    let report = match args.scene.as_str() {
        "ecosystem" => ecosystem(&args.output, &options, &step),
        "cloth" => cloth_scene(&args.output, &options, &step),
        _ => city_scene(&args.output, &options, &step),
    };
    let report = match report {
        Err(appel::Error::Cancelled) => bail!(
            "interrupted: the files written so far in {} are whole, but the scene file was not written",
            args.output.display()
        ),
        r => r?,
    };
    println!(
        "{}: {} unique triangles, {} instanced triangles, {} instances, {} files, {:.1} s",
        args.output.join(&report.files[0]).display(),
        report.unique_triangles,
        report.instanced_triangles,
        report.instances,
        report.files.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
