use anyhow::{anyhow, bail, Context, Result};
use appel::io::image::{write_image, Aovs, ImageFormat};
use appel::io::is_mesh_file;
use appel::render::{render, RenderOptions};
use appel::scene::builtin::builtin_scene;
use appel::scene::parse::Syntax;
use appel::scene::{
    description_from_str, frame_model, load_description, model_description, validate, Description,
    Scene,
};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

#[derive(clap::Args)]
pub struct RenderArgs {
    /// A scene file (.toml or .json), a mesh file to view (.ply, .obj, .gltf, .glb, .ply.gz, .obj.gz),
    /// or the name of a built-in scene (`appel scenes`). Default: whitted.
    scene: Option<String>,
    /// Output image: .png (8-bit sRGB) or .exr (linear float RGB, plus AOVs).
    #[arg(short, long, default_value = "render.png")]
    output: PathBuf,
    /// AOV channels to add to an EXR: a comma-separated list of depth, normal, shapeid, primid.
    #[arg(long, value_name = "LIST")]
    aov: Option<String>,
    /// Worker threads (default: all cores). The image is identical for any count.
    #[arg(long)]
    threads: Option<usize>,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
    /// Print acceleration-structure statistics.
    #[arg(long)]
    stats: bool,
    /// Override render.accel.
    #[arg(long)]
    accel: Option<String>,
    /// Override render.integrator (raycast or whitted).
    #[arg(long)]
    integrator: Option<String>,
    /// Override render.spp.
    #[arg(long)]
    spp: Option<u32>,
    /// Override render.max_depth.
    #[arg(long)]
    max_depth: Option<u32>,
    /// Override the image size, as WxH.
    #[arg(long, value_name = "WxH")]
    size: Option<String>,
    /// Override camera.eye, as x,y,z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    eye: Option<String>,
    /// Override camera.look_at, as x,y,z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    look_at: Option<String>,
    /// Override camera.up, as x,y,z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    up: Option<String>,
    /// Override camera.fov (vertical, degrees).
    #[arg(long)]
    fov: Option<f32>,
}

pub fn run(args: RenderArgs) -> Result<()> {
    let start = Instant::now();
    // Check the output name first, so a typo fails before a long render.
    ImageFormat::from_path(&args.output)?;
    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        if !dir.is_dir() {
            bail!(
                "cannot write {}: the folder {} does not exist",
                args.output.display(),
                dir.display()
            );
        }
    }
    let aovs = match &args.aov {
        Some(list) => Aovs::parse(list).map_err(|e| anyhow!("--aov: {e}"))?,
        None => Aovs::default(),
    };
    if aovs.any() && ImageFormat::from_path(&args.output)? != ImageFormat::Exr {
        bail!("--aov needs an .exr output: AOVs are written as EXR channels");
    }
    let (mut description, base_dir, is_model) = read_scene_or_model(args.scene.as_deref())?;
    apply_overrides(&mut description, &args)?;
    validate::validate(&description)
        .map_err(|e| anyhow!("after command-line overrides: {}", e.message))?;
    let parse_time = start.elapsed();

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .context("cannot start the worker threads")?;
    let mut scene = pool.install(|| Scene::new(&description, &base_dir))?;
    if is_model {
        // A bare mesh file: frame it now that its bounds are known; camera flags still win.
        let mut framed = frame_model(&description, scene.geometry.bounds());
        apply_overrides(&mut framed, &args)?;
        validate::validate(&framed)
            .map_err(|e| anyhow!("after command-line overrides: {}", e.message))?;
        scene.set_view(&framed);
    }
    if args.stats {
        let s = scene.accel_stats();
        eprintln!(
            "accel {}: {} primitives, built in {:.3} ms, {} bytes, {} nodes, {} leaves, depth {}{}",
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

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // Ctrl-C stops the render at the next tile; nothing is written.
        let _ = ctrlc::set_handler(move || cancel.store(true, Ordering::Relaxed));
    }
    let pixels = scene.camera.width as u64 * scene.camera.height as u64;
    let bar = (!args.quiet && std::io::stderr().is_terminal()).then(|| {
        let bar = ProgressBar::new(pixels);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} rendering [{bar:40}] {percent:>3}% {elapsed} (eta {eta})",
            )
            .expect("static template")
            .progress_chars("=> "),
        );
        bar
    });
    let progress = |done: u64| {
        if let Some(b) = &bar {
            b.set_position(done);
        }
    };
    let options = RenderOptions {
        progress: Some(&progress),
        cancel: Some(&cancel),
    };
    let (film, stats) = pool.install(|| render(&scene, &options))?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    write_image(&args.output, &film, aovs)?;

    let r = stats.rays;
    let load = parse_time + scene.timings.load;
    println!(
        "{}: {}x{} | load {:.3}s build {:.3}s render {:.3}s | rays: camera {} shadow {} reflection {} refraction {} | {:.2} Mrays/s",
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
    }
    Ok(())
}

/// A scene file, or a built-in scene by name. A mesh file gives an unframed one-mesh scene.
pub fn read_scene(scene: Option<&str>) -> Result<(Description, PathBuf)> {
    read_scene_or_model(scene).map(|(d, base, _)| (d, base))
}

/// A scene file, a mesh file (the flag says so: the caller frames it once the bounds are known),
/// or a built-in scene by name.
fn read_scene_or_model(scene: Option<&str>) -> Result<(Description, PathBuf, bool)> {
    let name = scene.unwrap_or("whitted");
    let path = Path::new(name);
    if is_mesh_file(path) {
        let file = path
            .file_name()
            .and_then(|f| f.to_str())
            .ok_or_else(|| anyhow!("`{name}`: the file name is not valid UTF-8"))?;
        if !path.is_file() {
            bail!("{name}: no such mesh file");
        }
        let base_dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        return Ok((model_description(file), base_dir, true));
    }
    if Syntax::from_path(path).is_none() && !path.exists() {
        if let Some(text) = builtin_scene(name) {
            let origin = PathBuf::from(format!("<built-in scene {name}>"));
            return Ok((
                description_from_str(text, Syntax::Toml, &origin)?,
                PathBuf::from("."),
                false,
            ));
        }
        bail!(
            "`{name}` is neither a scene file nor a built-in scene (built-in: {})",
            appel::scene::builtin::BUILTIN_SCENES
                .iter()
                .map(|s| s.0)
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let loaded = load_description(path)?;
    Ok((loaded.description, loaded.base_dir, false))
}

/// `640x480` to `(640, 480)`.
pub fn parse_size(size: &str) -> Result<(u32, u32)> {
    size.split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)))
        .ok_or_else(|| anyhow!("--size: expected WIDTHxHEIGHT such as 640x480, got `{size}`"))
}

fn parse_vec3(flag: &str, s: &str) -> Result<[f32; 3]> {
    let parts: Vec<&str> = s.split(',').collect();
    let v: Vec<f32> = parts
        .iter()
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| anyhow!("{flag}: expected three numbers as x,y,z, got `{s}`"))?;
    v.try_into()
        .map_err(|_| anyhow!("{flag}: expected three numbers as x,y,z, got `{s}`"))
}

fn apply_overrides(d: &mut Description, a: &RenderArgs) -> Result<()> {
    if let Some(x) = &a.accel {
        d.render.accel = x.clone();
    }
    if let Some(x) = &a.integrator {
        d.render.integrator = x.clone();
    }
    if let Some(x) = a.spp {
        d.render.spp = x;
    }
    if let Some(x) = a.max_depth {
        d.render.max_depth = x;
    }
    if let Some(size) = &a.size {
        let (w, h) = size
            .split_once(['x', 'X'])
            .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)))
            .ok_or_else(|| {
                anyhow!("--size: expected WIDTHxHEIGHT such as 640x480, got `{size}`")
            })?;
        d.camera.width = w;
        d.camera.height = h;
    }
    if let Some(x) = &a.eye {
        d.camera.eye = parse_vec3("--eye", x)?;
    }
    if let Some(x) = &a.look_at {
        d.camera.look_at = parse_vec3("--look-at", x)?;
    }
    if let Some(x) = &a.up {
        d.camera.up = parse_vec3("--up", x)?;
    }
    if let Some(x) = a.fov {
        d.camera.fov = x;
    }
    Ok(())
}
