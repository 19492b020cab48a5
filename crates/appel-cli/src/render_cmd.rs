use crate::scene_args::{load_scene_with, ParamArgs, ViewArgs};
use anyhow::{anyhow, bail, Context, Result};
use appel::description::Description;
use appel::output::heatmap::write_heatmap;
use appel::output::image::{write_image_with, Aovs, ImageFormat};
use appel::render::cost::CostImage;
use appel::render::{render, Film, RenderOptions, RenderStats, Window};
use appel::scene::{LoadStep, Scene, SceneOptions};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::Arc;

#[derive(clap::Args)]
pub struct RenderArgs {
    /// A scene file (.toml, .json, Mitsuba .xml, pbrt .pbrt), a mesh file to view (.ply, .obj,
    /// .gltf, .glb, .ply.gz, .obj.gz, .zip or x.zip:inner.obj), or the name of a built-in scene
    /// (`appel scenes`). Default: whitted.
    pub scene: Option<String>,
    /// Output image: .png (8-bit sRGB) or .exr (linear float RGB, plus AOVs). With --frames, a
    /// name with `{frame}` or `{frame:04}` in it, replaced by each frame's number.
    #[arg(short, long, default_value = "render.png")]
    pub output: PathBuf,
    /// Render frames A to B-1 (`A..B`) or frame K (`K`) of an animated scene (`[animation]`),
    /// refitting the structures from frame to frame.
    #[arg(long, value_name = "A..B")]
    frames: Option<String>,
    /// Instead of rendering, write a false-colour PNG of the nodes visited or the primitive tests
    /// of each pixel's camera ray (through its centre), with a legend and its scale.
    #[arg(long, value_parser = ["nodes", "tests"])]
    heatmap: Option<String>,
    /// AOV channels to add to an EXR: a comma-separated list of depth, normal, shapeid, primid,
    /// instanceid, variance, cost (`cost.nodes` and `cost.tests`: the nodes visited and primitive
    /// tests of each pixel's camera ray).
    #[arg(long, value_name = "LIST")]
    aov: Option<String>,
    /// Worker threads (default: all cores). The image is identical for any count.
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress bar.
    #[arg(short, long)]
    pub quiet: bool,
    /// Print acceleration-structure statistics.
    #[arg(long)]
    stats: bool,
    /// Override render.accel.
    #[arg(long)]
    accel: Option<String>,
    /// Override render.integrator.
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(appel::scene::IntegratorKind::NAMES))]
    integrator: Option<String>,
    /// Override render.spp.
    #[arg(long)]
    spp: Option<u32>,
    /// Stop after the pass of samples during which this many seconds have passed (the image then
    /// has fewer samples per pixel than --spp).
    #[arg(long, value_name = "SECONDS")]
    pub time_limit: Option<f64>,
    /// Render only pixels X0..X1 by Y0..Y1 (end excluded): the image is the window's size and
    /// its pixels are those of the whole render.
    #[arg(long, value_name = "X0,Y0,X1,Y1")]
    pub window: Option<String>,
    /// Override render.max_depth (path and direct: -1 is unlimited).
    #[arg(long, allow_hyphen_values = true)]
    max_depth: Option<i32>,
    #[command(flatten)]
    view: ViewArgs,
    #[command(flatten)]
    pub params: ParamArgs,
}

pub fn run(args: RenderArgs) -> Result<()> {
    let outputs = check_outputs(&args)?;
    if let Some(frames) = &args.frames {
        return crate::render_frames::run(&args, frames, outputs.aovs);
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("cannot start the worker threads")?;
    let interrupt = Interrupt::install();
    let show = !args.quiet && std::io::stderr().is_terminal();
    let (scene, parse_time) = resolve(&args, &pool, &interrupt, show)?;
    interrupt.enter(RENDERING);
    if args.stats {
        print_accel_stats(&scene);
    }
    if let Some(what) = &args.heatmap {
        return write_cost_heatmap(&args.output, what, &pool, &scene);
    }
    let (film, stats) = render_image(&scene, outputs.window, &args, &pool, &interrupt, show)?;
    interrupt.enter(WRITING);
    let cost = outputs
        .aovs
        .cost
        .then(|| pool.install(|| CostImage::of(&scene)));
    if cost.is_some() && outputs.window.is_some() {
        bail!("--aov cost is of the whole image: it does not take --window");
    }
    write_image_with(&args.output, &film, outputs.aovs, cost.as_ref())?;
    print_summary(&args, &scene, &film, &stats, parse_time);
    Ok(())
}

/// What the flags ask to be written, checked before anything is loaded so that a typo fails
/// before a long render.
struct Outputs {
    window: Option<Window>,
    aovs: Aovs,
}

fn check_outputs(args: &RenderArgs) -> Result<Outputs> {
    let format = ImageFormat::from_path(&args.output)?;
    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            bail!(
                "cannot write {}: the folder {} does not exist",
                args.output.display(),
                dir.display()
            );
        }
    }
    if let Some(t) = args.time_limit {
        if !(t.is_finite() && t > 0.0 && t < 1e9) {
            bail!("--time-limit: expected a positive number of seconds, got {t}");
        }
    }
    let window = args.window.as_deref().map(parse_window).transpose()?;
    let aovs = match &args.aov {
        Some(list) => Aovs::parse(list).map_err(|e| anyhow!("--aov: {e}"))?,
        None => Aovs::default(),
    };
    if aovs.any() && format != ImageFormat::Exr {
        bail!("--aov needs an .exr output: AOVs are written as EXR channels");
    }
    if args.heatmap.is_some() && format != ImageFormat::Png {
        bail!("--heatmap writes a .png picture");
    }
    if args.heatmap.is_some() && (aovs.any() || args.frames.is_some()) {
        bail!("--heatmap writes one picture of cost: it takes neither --aov nor --frames");
    }
    Ok(Outputs { window, aovs })
}

/// Ctrl-C: while loading and building nothing has been written, so the process ends at once (a
/// structure build cannot be interrupted half-way, and may take minutes); while rendering, the
/// render stops after the tiles in flight and nothing is written; while the image is being
/// written it finishes (the write is atomic and short).
struct Interrupt {
    cancel: Arc<AtomicBool>,
    phase: Arc<AtomicU8>,
}

impl Interrupt {
    fn install() -> Self {
        let cancel = Arc::new(AtomicBool::new(false));
        let phase = Arc::new(AtomicU8::new(LOADING));
        {
            let (cancel, phase) = (cancel.clone(), phase.clone());
            let _ = ctrlc::set_handler(move || match phase.load(Ordering::SeqCst) {
                LOADING => {
                    eprintln!("\ninterrupted while loading: nothing was written");
                    std::process::exit(130);
                }
                _ => cancel.store(true, Ordering::SeqCst),
            });
        }
        Self { cancel, phase }
    }

    fn enter(&self, phase: u8) {
        self.phase.store(phase, Ordering::SeqCst);
    }
}

/// A progress bar on stderr with `template`, when `show`.
fn progress_bar(show: bool, length: u64, template: &str) -> Option<ProgressBar> {
    show.then(|| {
        let bar = ProgressBar::new(length);
        bar.set_style(
            ProgressStyle::with_template(template)
                .expect("static template")
                .progress_chars("=> "),
        );
        bar
    })
}

/// The scene the arguments name, with their settings, built on `pool` under a progress bar.
fn resolve(
    args: &RenderArgs,
    pool: &rayon::ThreadPool,
    interrupt: &Interrupt,
    show: bool,
) -> Result<(Scene, std::time::Duration)> {
    let xml = args.params.format_options()?;
    let load_bar = progress_bar(
        show,
        1,
        "{spinner} loading [{bar:40}] {pos}/{len} {elapsed} {msg}",
    );
    if let Some(b) = &load_bar {
        b.enable_steady_tick(std::time::Duration::from_millis(200));
    }
    let step = |s: &LoadStep| {
        if let Some(b) = &load_bar {
            b.set_length(s.total);
            b.set_position(s.done);
            b.set_message(s.what.to_string());
        }
    };
    let scene_options = SceneOptions {
        progress: Some(&step),
        cancel: Some(&interrupt.cancel),
        ..Default::default()
    };
    let loaded = pool.install(|| {
        load_scene_with(
            args.scene.as_deref(),
            &xml,
            |d| apply_settings(d, args),
            scene_options,
            args.view.camera,
        )
    });
    if let Some(b) = load_bar {
        b.finish_and_clear();
    }
    loaded
}

fn print_accel_stats(scene: &Scene) {
    let s = scene.accel_stats();
    let layout = match &scene.accel {
        appel::accel::Accel::Bvh(b) => format!(
            " ({}-wide, {} splits)",
            b.width(),
            scene.settings.accel_options.bvh.split.name()
        ),
        _ => String::new(),
    };
    eprintln!(
        "accel {}{layout}: {} primitives, built in {:.3} ms, {} bytes, {} nodes, {} leaves, depth {}{}",
        s.name,
        s.primitives,
        s.build_time.as_secs_f64() * 1e3,
        s.bytes,
        s.nodes,
        s.leaves,
        s.depth,
        s.sah_cost
            .map(|c| format!(", SAH cost {c:.2}"))
            .unwrap_or_default()
    );
}

/// `--heatmap nodes|tests`: a false-colour picture of the camera rays' cost instead of a render.
fn write_cost_heatmap(
    output: &std::path::Path,
    what: &str,
    pool: &rayon::ThreadPool,
    scene: &Scene,
) -> Result<()> {
    let cost = pool.install(|| CostImage::of(scene));
    let values = if what == "nodes" {
        &cost.nodes
    } else {
        &cost.tests
    };
    let label = format!("{what} per camera ray");
    write_heatmap(output, cost.width, cost.height, values, &label)?;
    let mean = values.iter().map(|&v| v as f64).sum::<f64>() / values.len().max(1) as f64;
    let max = values.iter().copied().fold(0.0f32, f32::max);
    println!(
        "{}: {}x{} heatmap of {what} per camera ray under {}: mean {mean:.2}, max {max:.0}",
        output.display(),
        cost.width,
        cost.height,
        scene.settings.accel.name()
    );
    Ok(())
}

/// Renders the scene (or its `window`) on `pool` under a progress bar.
fn render_image(
    scene: &Scene,
    window: Option<Window>,
    args: &RenderArgs,
    pool: &rayon::ThreadPool,
    interrupt: &Interrupt,
    show: bool,
) -> Result<(Film, RenderStats)> {
    if let Some(w) = window {
        w.check(scene.camera.width, scene.camera.height)
            .map_err(|e| anyhow!("--window: {e}"))?;
    }
    let pixels = window.map_or(
        scene.camera.width as u64 * scene.camera.height as u64,
        |w| (w.x1 - w.x0) as u64 * (w.y1 - w.y0) as u64,
    );
    let bar = progress_bar(
        show,
        pixels,
        "{spinner} rendering [{bar:40}] {percent:>3}% {elapsed} (eta {eta})",
    );
    let progress = |done: u64| {
        if let Some(b) = &bar {
            b.set_position(done);
        }
    };
    let options = RenderOptions {
        progress: Some(&progress),
        cancel: Some(&interrupt.cancel),
        time_limit: args.time_limit.map(std::time::Duration::from_secs_f64),
        window,
        skip_aovs: false,
    };
    let rendered = pool.install(|| render(scene, &options));
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    Ok(rendered?)
}

/// The line that says what was written and how long each stage took, and with `--stats` the
/// traversal counts.
fn print_summary(
    args: &RenderArgs,
    scene: &Scene,
    film: &Film,
    stats: &RenderStats,
    parse_time: std::time::Duration,
) {
    let peak = crate::memory::peak_rss_bytes()
        .map(|b| format!(" | peak RSS {:.0} MB", b as f64 / 1e6))
        .unwrap_or_default();
    let r = stats.rays;
    let load = parse_time + scene.timings.load;
    println!(
        "{}: {}x{} | load {:.3}s build {:.3}s render {:.3}s | rays: camera {} shadow {} reflection {} refraction {} | {:.2} Mrays/s{peak}",
        args.output.display(),
        film.width,
        film.height,
        load.as_secs_f64(),
        scene.timings.build.as_secs_f64(),
        stats.time.as_secs_f64(),
        r.camera,
        r.shadow,
        r.reflection,
        r.refraction,
        stats.mrays_per_second()
    );
    if args.stats {
        let t = stats.traversal;
        let per_ray = |x: u64| x as f64 / t.rays.max(1) as f64;
        eprintln!(
            "traversal: {} queries, {:.2} nodes visited and {:.2} primitive tests per query",
            t.rays,
            per_ray(t.nodes_visited),
            per_ray(t.prim_tests)
        );
        if t.instance_queries > 0 {
            let per_query = |x: u64| x as f64 / t.instance_queries as f64;
            eprintln!(
                "inside instances: {} queries of prototypes' structures, {:.2} nodes visited and \
                 {:.2} primitive tests per query",
                t.instance_queries,
                per_query(t.instance_nodes_visited),
                per_query(t.instance_prim_tests)
            );
        }
    }
}

/// `X0,Y0,X1,Y1` in pixels.
fn parse_window(s: &str) -> Result<Window> {
    let v: Vec<u32> = s
        .split(',')
        .map(|x| x.trim().parse::<u32>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| anyhow!("--window: expected X0,Y0,X1,Y1 in pixels, got `{s}`"))?;
    let [x0, y0, x1, y1] = v[..] else {
        bail!("--window: expected four numbers X0,Y0,X1,Y1, got `{s}`");
    };
    Ok(Window { x0, y0, x1, y1 })
}

const LOADING: u8 = 0;
const RENDERING: u8 = 1;
const WRITING: u8 = 2;

/// Applies the flags that override the scene's `[render]` settings and its camera.
pub fn apply_settings(d: &mut Description, a: &RenderArgs) -> Result<()> {
    if let Some(x) = &a.accel {
        d.render.accel = x.clone();
    }
    if let Some(x) = &a.integrator {
        d.render.integrator = appel::scene::IntegratorKind::from_name(x).ok_or_else(|| {
            anyhow!(
                "--integrator: unknown integrator `{x}`, expected one of: {}",
                appel::scene::IntegratorKind::NAMES.join(", ")
            )
        })?;
    }
    if let Some(x) = a.spp {
        d.render.spp = x;
    }
    if let Some(x) = a.max_depth {
        d.render.max_depth = x;
    }
    a.view.apply(d)
}
