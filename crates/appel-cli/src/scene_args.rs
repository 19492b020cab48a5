//! What every subcommand that reads a scene shares: finding it (a scene file, a mesh file to frame,
//! or a built-in scene), the camera flags, and building it.

use anyhow::{anyhow, bail, Result};
use appel::description::parse::Syntax;
use appel::description::{description_from_str, validate, Description};
use appel::format::FormatOptions;
use appel::io::is_mesh_file;
use appel::scene::builtin::builtin_scene;
use appel::scene::{model_description, view_model, Scene, SceneOptions};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Flags that override the camera of a scene, or the automatic framing of a mesh file.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct ViewArgs {
    /// Override the image size, as WxH.
    #[arg(long, value_name = "WxH")]
    pub size: Option<String>,
    /// Override camera.eye, as x,y,z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub eye: Option<String>,
    /// Override camera.look_at, as x,y,z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub look_at: Option<String>,
    /// Override camera.up, as x,y,z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub up: Option<String>,
    /// Override camera.fov (vertical, degrees).
    #[arg(long)]
    pub fov: Option<f32>,
    /// View a glTF file through its camera N (0-based, in node order); by default its first
    /// camera, or automatic framing if it has none.
    #[arg(long, value_name = "N")]
    pub camera: Option<usize>,
}

impl ViewArgs {
    pub fn apply(&self, d: &mut Description) -> Result<()> {
        if let Some(size) = &self.size {
            (d.camera.width, d.camera.height) = parse_size(size)?;
        }
        if let Some(x) = &self.eye {
            d.camera.eye = parse_vec3("--eye", x)?;
        }
        if let Some(x) = &self.look_at {
            d.camera.look_at = parse_vec3("--look-at", x)?;
        }
        if let Some(x) = &self.up {
            d.camera.up = parse_vec3("--up", x)?;
        }
        if let Some(x) = self.fov {
            d.camera.fov = x;
        }
        Ok(())
    }
}

/// `-D NAME=VALUE`: the parameters of a Mitsuba 3 XML scene.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct ParamArgs {
    /// Set a parameter of a Mitsuba 3 XML scene: `$NAME` in its attributes takes VALUE, over the
    /// file's `<default name="NAME" .../>` (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
}

impl ParamArgs {
    pub fn format_options(&self) -> Result<FormatOptions> {
        let params = self
            .define
            .iter()
            .map(|d| match d.split_once('=') {
                Some((name, value)) if !name.trim().is_empty() => {
                    Ok((name.trim().to_string(), value.to_string()))
                }
                _ => Err(anyhow!(
                    "-D: expected NAME=VALUE, such as -D spp=16, got `{d}`"
                )),
            })
            .collect::<Result<_>>()?;
        Ok(FormatOptions { params })
    }
}

/// Reads a scene (file, mesh file or built-in), lets `adjust` apply command-line overrides, checks the
/// result, and builds it on the current thread pool. A mesh file is framed once its bounds are known,
/// and `adjust` runs again so that camera flags win over the framing. Returns the scene and the time
/// spent reading and checking the scene file.
pub fn load_scene(
    name: Option<&str>,
    xml: &FormatOptions,
    adjust: impl Fn(&mut Description) -> Result<()>,
) -> Result<(Scene, Duration)> {
    load_scene_with(name, xml, adjust, SceneOptions::default(), None)
}

/// [`load_scene`] with progress reports and cancellation while files load and structures build.
/// Before anything large is read, the scene's estimated memory is checked against what is
/// available.
pub fn load_scene_with(
    name: Option<&str>,
    xml: &FormatOptions,
    adjust: impl Fn(&mut Description) -> Result<()>,
    options: SceneOptions,
    camera: Option<usize>,
) -> Result<(Scene, Duration)> {
    let start = Instant::now();
    let (mut description, base_dir, is_model) = read_scene_or_model(name, xml)?;
    adjust(&mut description)?;
    check(&description)?;
    crate::memory::check_memory(&description, &base_dir)?;
    let parse_time = start.elapsed();
    if camera.is_some() && !is_model {
        bail!(
            "--camera picks a camera of a glTF file; `{}` is a scene, whose camera is its own",
            name.unwrap_or("whitted")
        );
    }
    let mut scene = Scene::new_with(&description, &base_dir, options)?;
    for w in &scene.from_files.warnings {
        eprintln!("warning: {w}");
    }
    if is_model {
        let framed = model_view(&scene, &description, camera, &adjust)?;
        scene.set_view(&framed)?;
        scene.settings.integrator = framed.render.integrator;
        scene.settings.spp = framed.render.spp;
        scene.settings.max_depth = framed.render.max_depth;
    }
    Ok((scene, parse_time))
}

/// The description of a scene file or built-in scene (not a mesh file) after `adjust`, checked,
/// and the folder its files are relative to: for animations, which build one scene per frame.
pub fn load_description_only(
    name: Option<&str>,
    xml: &FormatOptions,
    adjust: impl Fn(&mut Description) -> Result<()>,
) -> Result<(Description, PathBuf)> {
    let (mut description, base_dir, is_model) = read_scene_or_model(name, xml)?;
    if is_model {
        bail!(
            "`{}` is a mesh file; an animation is a scene file with `[animation]`",
            name.unwrap_or("whitted")
        );
    }
    adjust(&mut description)?;
    check(&description)?;
    crate::memory::check_memory(&description, &base_dir)?;
    Ok((description, base_dir))
}

/// `A..B` (frames A to B-1) or `K` (frame K alone).
pub fn parse_frames(s: &str) -> Result<std::ops::Range<u32>> {
    let bad = || anyhow!("--frames: expected A..B (frames A to B-1) or one frame K, got `{s}`");
    let range = match s.split_once("..") {
        Some((a, b)) => {
            a.trim().parse::<u32>().map_err(|_| bad())?
                ..b.trim().parse::<u32>().map_err(|_| bad())?
        }
        None => {
            let k = s.trim().parse::<u32>().map_err(|_| bad())?;
            k..k + 1
        }
    };
    if range.is_empty() {
        bail!("--frames: `{s}` holds no frame (the end is excluded)");
    }
    Ok(range)
}

/// The library's view of a mesh file (see `appel::scene::view_model`), then the command line's
/// overrides.
fn model_view(
    scene: &Scene,
    description: &Description,
    camera: Option<usize>,
    adjust: &impl Fn(&mut Description) -> Result<()>,
) -> Result<Description> {
    let mut framed =
        view_model(scene, description, camera).map_err(|e| anyhow!("--camera: {e}"))?;
    adjust(&mut framed)?;
    check(&framed)?;
    Ok(framed)
}

fn check(d: &Description) -> Result<()> {
    validate::validate(d).map_err(|e| anyhow!("after command-line overrides: {}", e.message))
}

/// A scene file, a mesh file (the flag says so: the caller frames it once the bounds are known),
/// or a built-in scene by name. `xml` holds the parameters of a Mitsuba scene, and only of one.
fn read_scene_or_model(
    scene: Option<&str>,
    xml: &FormatOptions,
) -> Result<(Description, PathBuf, bool)> {
    let name = scene.unwrap_or("whitted");
    let path = Path::new(name);
    if !xml.params.is_empty() && !appel::format::find(path).is_some_and(|f| f.takes_params()) {
        bail!("-D sets parameters of a Mitsuba 3 XML scene (.xml); `{name}` is not one");
    }
    if is_mesh_file(path) {
        // An archive's entry (`x.zip:dir/m.obj`) is named relative to the archive's folder.
        let archive = appel::io::assets::archive_path(path);
        let file_path = archive.as_ref().map_or(path, |a| a.archive.as_path());
        let file = file_path
            .file_name()
            .and_then(|f| f.to_str())
            .ok_or_else(|| anyhow!("`{name}`: the file name is not valid UTF-8"))?;
        let file = match archive.as_ref().and_then(|a| a.inner.as_deref()) {
            Some(inner) => format!("{file}:{inner}"),
            None => file.to_string(),
        };
        if !file_path.is_file() {
            bail!("{}: no such mesh file", file_path.display());
        }
        let base_dir = match file_path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        return Ok((model_description(&file), base_dir, true));
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
    let loaded = appel::format::load(path, xml)?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
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
