use crate::scene_args::{load_scene, parse_size, ViewArgs};
use anyhow::{anyhow, bail, Result};
use appel::accel::AccelKind;
use appel::bench::{bench_accel, bench_scene, BenchOptions, BenchRays, BenchTarget, BENCH_SCENES};
use appel::scene::Description;

mod frames;

#[derive(clap::Args)]
pub struct BenchArgs {
    /// A generated benchmark scene (uniform, teapot-in-stadium), a built-in scene, a scene file or a
    /// mesh file (framed as `appel render` frames it).
    #[arg(default_value = "teapot-in-stadium")]
    target: String,
    /// Comma-separated acceleration structures to measure [default: brute,grid,kdtree,bvh; with
    /// --scene: the scene's own].
    #[arg(long)]
    accel: Option<String>,
    /// Threads for the multi-threaded figures (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Print one JSON object per structure instead of a table.
    #[arg(long)]
    json: bool,
    /// Triangle count of the generated benchmark scenes.
    #[arg(long, default_value_t = 100_000)]
    triangles: usize,
    #[command(flatten)]
    view: ViewArgs,
    /// Builds per structure (the median is reported).
    #[arg(long, default_value_t = 3)]
    builds: usize,
    /// Timed passes over the rays (the median is reported).
    #[arg(long, default_value_t = 3)]
    runs: usize,
    /// Real-time mode: render this scene (built-in name, scene file or mesh file) --frames times at
    /// 1 sample per pixel and report frames per second and rays per frame by kind.
    #[arg(long, value_name = "SCENE", conflicts_with = "target")]
    scene: Option<String>,
    /// Frames to render in real-time mode (the median frame time is reported).
    #[arg(long, default_value_t = 100, requires = "scene")]
    frames: usize,
    /// Recursion depth in real-time mode.
    #[arg(long, default_value_t = 5, requires = "scene")]
    max_depth: u32,
}

pub fn run(args: BenchArgs) -> Result<()> {
    if let Some(scene) = &args.scene {
        return frames::run(scene, &args);
    }
    // Camera rays at 640x480 unless --size says otherwise.
    let (w, h) = match &args.view.size {
        Some(size) => parse_size(size)?,
        None => (640, 480),
    };
    let kinds = parse_accels(args.accel.as_deref().unwrap_or("brute,grid,kdtree,bvh"))?;
    let target = load_target(&args.target, args.triangles, w, h, &args.view)?;
    let options = BenchOptions {
        build_runs: args.builds,
        trace_runs: args.runs,
        threads: args.threads.unwrap_or(0),
    };
    let rays = BenchRays::new(&target);
    if !args.json {
        println!(
            "{}: {} triangles, {} primitives, {}x{} camera rays",
            target.name,
            target.geometry.triangle_count(),
            target.geometry.prims.len(),
            w,
            h
        );
        println!(
            "{:<8} {:>10} {:>12} {:>6} {:>22} {:>22} {:>15} {:>15}",
            "accel",
            "build ms",
            "bytes",
            "depth",
            "camera Mrays/s 1t/Nt",
            "incoherent 1t/Nt",
            "nodes/ray cam/inc",
            "tests/ray cam/inc"
        );
    }
    for kind in kinds {
        let r = bench_accel(&target, &rays, kind, &options);
        if args.json {
            println!("{}", serde_json::to_string(&r)?);
        } else {
            println!(
                "{:<8} {:>10.1} {:>12} {:>6} {:>10} / {:<9} {:>10} / {:<9} {:>7.1}/{:<7.1} {:>7.1}/{:<7.1}",
                r.accel,
                r.build_ms,
                r.bytes,
                r.depth,
                rate(r.primary_mrays_1t),
                rate(r.primary_mrays),
                rate(r.incoherent_mrays_1t),
                rate(r.incoherent_mrays),
                r.nodes_per_ray,
                r.incoherent_nodes_per_ray,
                r.tests_per_ray,
                r.incoherent_tests_per_ray
            );
        }
    }
    Ok(())
}

/// `bvh,kdtree` to the structures it names.
fn parse_accels(list: &str) -> Result<Vec<AccelKind>> {
    list.split(',')
        .map(|n| {
            AccelKind::from_name(n.trim()).ok_or_else(|| {
                anyhow!(
                    "--accel: unknown structure `{n}`, expected some of: {}",
                    AccelKind::NAMES.join(", ")
                )
            })
        })
        .collect()
}

fn load_target(
    name: &str,
    triangles: usize,
    w: u32,
    h: u32,
    view: &ViewArgs,
) -> Result<BenchTarget> {
    if let Some(mut t) = bench_scene(name, triangles, w, h) {
        if view.eye.is_some() || view.look_at.is_some() || view.up.is_some() || view.fov.is_some() {
            bail!("the camera of a generated benchmark scene is fixed; --size is the only view flag it takes");
        }
        t.name = name.to_string();
        return Ok(t);
    }
    let adjust = |d: &mut Description| {
        // The structures are built by the benchmark itself; the scene's own choice is not measured.
        d.render.accel = "brute".into();
        (d.camera.width, d.camera.height) = (w, h);
        view.apply(d)
    };
    let (scene, _) = load_scene(Some(name), adjust).map_err(|e| {
        anyhow!(
            "{e:#}\n(generated benchmark scenes: {})",
            BENCH_SCENES
                .iter()
                .map(|s| s.0)
                .collect::<Vec<_>>()
                .join(", ")
        )
    })?;
    Ok(BenchTarget {
        name: name.to_string(),
        geometry: scene.geometry,
        camera: scene.camera,
    })
}

/// Three significant digits, so brute force's 0.00123 Mrays/s does not print as zero.
fn rate(mrays: f64) -> String {
    if mrays >= 100.0 {
        format!("{mrays:.0}")
    } else if mrays >= 1.0 {
        format!("{mrays:.2}")
    } else {
        format!("{mrays:.2e}")
    }
}
