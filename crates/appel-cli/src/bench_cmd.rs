use crate::scene_args::{load_scene_with, parse_size, ParamArgs, ViewArgs};
use anyhow::{anyhow, bail, Result};
use appel::accel::AccelKind;
use appel::description::Description;
use appel::format::FormatOptions;
use appel::geometry::TriangleTest;
use appel::scene::SceneOptions;
use appel_bench::{
    bench_pairings, bench_scene, BenchOptions, BenchRays, BenchResult, BenchTarget, BENCH_SCENES,
};
use embree_peer::BuildQuality;

mod animation;
mod frames;

#[derive(clap::Args)]
pub struct BenchArgs {
    /// A generated benchmark scene (uniform, teapot-in-stadium), a built-in scene, a scene file or a
    /// mesh file (framed as `appel render` frames it).
    #[arg(default_value = "teapot-in-stadium")]
    target: String,
    #[arg(long, help = accel_help())]
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
    #[command(flatten)]
    params: ParamArgs,
    /// Builds per structure (the median is reported).
    #[arg(long, default_value_t = 3)]
    builds: usize,
    /// Timed passes over the rays (the median is reported).
    #[arg(long, default_value_t = 3)]
    runs: usize,
    /// Real-time mode: render this scene (built-in name, scene file or mesh file) --frames times at
    /// 1 sample per pixel and report frames per second and rays per frame by kind. A scene whose
    /// integrator is path or direct (a Mitsuba XML file, say) is rendered at --spp instead, and
    /// samples per second are reported.
    #[arg(long, value_name = "SCENE", conflicts_with = "target")]
    scene: Option<String>,
    /// Renders in --scene mode (the median time is reported) [default: 100; path and direct: 3].
    /// Without --scene, with an animated scene file as the target: frames 0 to N-1 of the
    /// animation, with refit and rebuild times, Mrays/s and SAH drift per frame.
    #[arg(long)]
    frames: Option<usize>,
    /// Recursion depth in --scene mode [default: 5; path and direct: the scene's, -1 unlimited].
    #[arg(long, requires = "scene", allow_hyphen_values = true)]
    max_depth: Option<i32>,
    /// Samples per pixel of a path or direct scene in --scene mode [default: the scene's].
    #[arg(long, requires = "scene")]
    spp: Option<u32>,
    /// Also measure Intel Embree 3 (loaded at run time: `libembree3.so.3`, or the file named by
    /// APPEL_EMBREE_LIB) on the same rays, in the same process and thread pools.
    #[arg(long)]
    embree: bool,
    /// Embree's build quality: low, medium (Embree's default) or high.
    #[arg(long, default_value = "medium", requires = "embree")]
    embree_quality: String,
    /// Comma-separated ray-triangle tests to measure Appel with, of watertight and moller, each on
    /// the same rays; with --embree each beside the Embree mode of the same kind: watertight with
    /// Embree's robust mode (RTC_SCENE_FLAG_ROBUST), moller with Embree's default [default: the
    /// target's own; with --embree: watertight,moller].
    #[arg(long)]
    triangle: Option<String>,
    /// Build the BVH with compact leaves (`[render.bvh] compact = true`): primitive ids instead of
    /// vertices.
    #[arg(long)]
    bvh_compact: bool,
    /// Build the BVH over single triangles even where a mesh is made of quads (`[render.bvh]
    /// pairs = false`), to compare.
    #[arg(long)]
    bvh_no_pairs: bool,
    /// Instead of timing, write for each structure a false-colour PNG of the nodes visited or
    /// the primitive tests of each camera ray, to --output.
    #[arg(long, value_parser = ["nodes", "tests"], requires = "output")]
    heatmap: Option<String>,
    /// The --heatmap picture; `{accel}` in the name is replaced by each structure's name.
    #[arg(short, long)]
    output: Option<std::path::PathBuf>,
}

/// `--accel`'s help, naming every registered structure.
fn accel_help() -> String {
    format!(
        "Comma-separated acceleration structures to measure, of {} [default: brute,grid,kdtree,bvh; \
         with --scene: the scene's own]",
        AccelKind::NAMES.join(", ")
    )
}

/// More threads than this is a typo, not a machine.
const MAX_THREADS: usize = 4096;

pub fn run(args: BenchArgs) -> Result<()> {
    let threads = args.threads.unwrap_or(0);
    if threads > MAX_THREADS || args.threads == Some(0) {
        bail!("--threads: expected 1 to {MAX_THREADS}, got {threads}");
    }
    if let Some(scene) = &args.scene {
        return frames::run(scene, &args);
    }
    if let Some(n) = args.frames {
        return animation::run(&args.target, n, &args);
    }
    // Camera rays at 640x480 unless --size says otherwise.
    let (w, h) = match &args.view.size {
        Some(size) => parse_size(size)?,
        None => (640, 480),
    };
    let kinds = parse_accels(args.accel.as_deref().unwrap_or("brute,grid,kdtree,bvh"))?;
    let quality = BuildQuality::from_name(&args.embree_quality).ok_or_else(|| {
        anyhow!(
            "--embree-quality: expected low, medium or high, got `{}`",
            args.embree_quality
        )
    })?;
    let xml = args.params.format_options()?;
    let mut target = load_target(&args.target, args.triangles, w, h, &args.view, &xml)?;
    let tests = match (&args.triangle, args.embree) {
        (Some(list), _) => parse_triangle_tests(list)?,
        (None, true) => TriangleTest::ALL.to_vec(),
        (None, false) => vec![target.geometry.triangle_test],
    };
    target.accel_options.bvh.compact |= args.bvh_compact;
    target.accel_options.bvh.pairs &= !args.bvh_no_pairs;
    if let (Some(what), Some(out)) = (&args.heatmap, &args.output) {
        return heatmaps(&target, &kinds, what, out);
    }
    let options = BenchOptions {
        build_runs: args.builds,
        trace_runs: args.runs,
        threads,
    };
    let rays = BenchRays::new(&target);
    if !args.json {
        println!(
            "{}: {} triangles, {} primitives, {}x{} camera rays, {} incoherent, {} shadow, {} path",
            target.name,
            target.geometry.triangle_count(),
            target.geometry.prims.len(),
            w,
            h,
            rays.incoherent.len(),
            rays.shadow.len(),
            rays.path.len()
        );
        println!(
            "{:<13} {:>9} {:>12} {:>19} {:>19} {:>19} {:>19} {:>13} {:>13}",
            "accel",
            "build ms",
            "bytes",
            "camera 1t/Nt",
            "incoherent 1t/Nt",
            "shadow 1t/Nt",
            "path 1t/Nt",
            "nodes cam/inc",
            "tests cam/inc"
        );
    }
    let mut notes = vec![];
    for &test in &tests {
        let embree = args.embree.then_some(quality);
        let p = bench_pairings(&mut target, &rays, &kinds, test, &options, embree)
            .map_err(|e| anyhow!(e))?;
        if !args.json && tests.len() > 1 {
            println!("-- triangle test: {}", test.name());
        }
        for r in &p.rows {
            print_result(r, args.json)?;
            let tag = row_tag(r, tests.len());
            notes.push(memory_note(&tag, r));
            if let (Some(one), Some(all)) = (r.packet8_mrays_1t, r.packet8_mrays) {
                notes.push(format!(
                    "{tag}: camera rays in packets of 8: {} / {} Mrays/s ({} of {} hits differ from single rays')",
                    rate(one),
                    rate(all),
                    r.packet8_mismatches.unwrap_or(0),
                    r.rays_primary
                ));
            }
        }
        if let Some((r, about)) = &p.embree {
            print_result(r, args.json)?;
            if !args.json {
                for ours in &p.rows {
                    print_ratios(ours);
                }
            }
            notes.push(format!(
                "{about}: camera rays in packets of 8 (rtcIntersect8): {} / {} Mrays/s; \
                 same primitive as Appel's bvh ({}) on {:.4}% of camera and incoherent rays",
                rate(r.packet8_mrays_1t.unwrap_or(0.0)),
                rate(r.packet8_mrays.unwrap_or(0.0)),
                test.name(),
                100.0 * r.agreement.unwrap_or(0.0)
            ));
        }
    }
    if !args.json {
        println!(
            "Mrays/s with 1 thread / {} threads; closest hit for camera, incoherent (one bounce) and path rays \
             (bounces 2 to 4 of diffuse paths), any hit for shadow rays",
            rayon_threads(threads)
        );
        for n in notes {
            println!("{n}");
        }
    }
    Ok(())
}

/// What the structure and its scene take once built, and the process's peak while it was built.
fn memory_note(tag: &str, r: &BenchResult) -> String {
    let mb = |b: f64| b / 1e6;
    let total = (r.bytes + r.scene_bytes) as f64;
    let peak = r.build_peak_rss.map_or(String::new(), |p| {
        format!(
            "; peak resident during the build {:.0} MB, {:.2}x that",
            mb(p as f64),
            p as f64 / total.max(1.0)
        )
    });
    format!(
        "{tag}: memory {:.0} MB ({:.0} MB structure + {:.0} MB meshes and primitive list), {:.1} bytes per triangle{peak}",
        mb(total),
        mb(r.bytes as f64),
        mb(r.scene_bytes as f64),
        r.bytes_per_triangle
    )
}

/// `watertight,moller` to the triangle tests it names.
fn parse_triangle_tests(list: &str) -> Result<Vec<TriangleTest>> {
    list.split(',')
        .map(|n| {
            TriangleTest::from_name(n.trim()).ok_or_else(|| {
                anyhow!(
                    "--triangle: unknown triangle test `{n}`, expected some of: {}",
                    TriangleTest::NAMES.join(", ")
                )
            })
        })
        .collect()
}

/// A row's name in the notes: the structure, and its triangle test when several were measured.
fn row_tag(r: &BenchResult, tests: usize) -> String {
    if tests > 1 {
        format!("{} ({})", r.accel, r.triangle)
    } else {
        r.accel.clone()
    }
}

/// A table row of a structure's ratios to the Embree it was paired with: `x` ratios of the
/// throughputs (above 1: faster than Embree) and of the build time (below 1: faster).
fn print_ratios(r: &BenchResult) {
    let Some(v) = &r.vs_embree else { return };
    let pair = |a: f64, b: f64| format!("{a:.2}x / {b:.2}x");
    let packets = match (v.packet8_1t, v.packet8) {
        (Some(a), Some(b)) => format!("; packets of 8 {}", pair(a, b)),
        _ => String::new(),
    };
    println!(
        "{:<13} {:>8.2}x {:>12} {:>19} {:>19} {:>19} {:>19}   ({} / {}{packets})",
        "  ratio",
        v.build,
        "",
        pair(v.camera_1t, v.camera),
        pair(v.incoherent_1t, v.incoherent),
        pair(v.shadow_1t, v.shadow),
        pair(v.path_1t, v.path),
        r.accel,
        v.peer,
    );
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

fn rayon_threads(threads: usize) -> usize {
    if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads
    }
}

fn print_result(r: &BenchResult, json: bool) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string(r)?);
        return Ok(());
    }
    let pair = |a: f64, b: f64| format!("{} / {}", rate(a), rate(b));
    let counts = |a: f64, b: f64| {
        if r.accel.starts_with("embree") {
            "-".to_string()
        } else {
            format!("{a:.1}/{b:.1}")
        }
    };
    println!(
        "{:<13} {:>9.1} {:>12} {:>19} {:>19} {:>19} {:>19} {:>13} {:>13}",
        r.accel,
        r.build_ms,
        r.bytes,
        pair(r.primary_mrays_1t, r.primary_mrays),
        pair(r.incoherent_mrays_1t, r.incoherent_mrays),
        pair(r.shadow_mrays_1t, r.shadow_mrays),
        pair(r.path_mrays_1t, r.path_mrays),
        counts(r.nodes_per_ray, r.incoherent_nodes_per_ray),
        counts(r.tests_per_ray, r.incoherent_tests_per_ray),
    );
    Ok(())
}

fn load_target(
    name: &str,
    triangles: usize,
    w: u32,
    h: u32,
    view: &ViewArgs,
    xml: &FormatOptions,
) -> Result<BenchTarget> {
    if let Some(mut t) = bench_scene(name, triangles, w, h) {
        if !xml.params.is_empty() {
            bail!("-D sets parameters of a Mitsuba 3 XML scene; `{name}` is a generated one");
        }
        if view.eye.is_some() || view.look_at.is_some() || view.up.is_some() || view.fov.is_some() {
            bail!("the camera of a generated benchmark scene is fixed; --size is the only view flag it takes");
        }
        t.name = name.to_string();
        return Ok(t);
    }
    let adjust = |d: &mut Description| {
        (d.camera.width, d.camera.height) = (w, h);
        view.apply(d)
    };
    // The benchmark builds the top-level structures itself; the scene's own is not built. Meshes
    // declared for instancing keep structures of the scene's kind.
    let skip = SceneOptions {
        skip_top_level: true,
        ..Default::default()
    };
    let (scene, _) = load_scene_with(Some(name), xml, adjust, skip, view.camera).map_err(|e| {
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
        accel_options: scene.settings.accel_options,
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

/// `--heatmap`: one picture of cost per structure over the target's camera rays.
fn heatmaps(
    target: &BenchTarget,
    kinds: &[AccelKind],
    what: &str,
    out: &std::path::Path,
) -> Result<()> {
    let name = out.to_string_lossy();
    if kinds.len() > 1 && !name.contains("{accel}") {
        bail!(
            "--output: several structures need `{{accel}}` in the name, such as heat_{{accel}}.png"
        );
    }
    for &kind in kinds {
        let accel = appel::accel::Accel::build_with(kind, &target.geometry, &target.accel_options);
        let (w, h) = (target.camera.width, target.camera.height);
        let cost = appel::render::cost::CostImage::trace(
            w,
            h,
            |x, y| target.camera.ray(x, y),
            |ray, s| {
                accel.intersect(&target.geometry, ray, f32::INFINITY, s);
            },
        );
        let values = if what == "nodes" {
            &cost.nodes
        } else {
            &cost.tests
        };
        let path = std::path::PathBuf::from(name.replace("{accel}", kind.name()));
        let label = format!("{what} per camera ray");
        appel::output::heatmap::write_heatmap(&path, w, h, values, &label)?;
        let mean = values.iter().map(|&v| v as f64).sum::<f64>() / values.len().max(1) as f64;
        let max = values.iter().copied().fold(0.0f32, f32::max);
        println!(
            "{}: {} {what} per camera ray under {}: mean {mean:.2}, max {max:.0}",
            path.display(),
            target.name,
            kind.name()
        );
    }
    Ok(())
}
