//! What every subcommand that reads a scene shares: finding it (a scene file, a mesh file to frame,
//! or a built-in scene), the camera flags, and building it.

use anyhow::{anyhow, bail, Result};
use appel::api::{build_resolved, resolve_description, RequestNames, ResolvedScene, SceneRequest};
use appel::description::Description;
use appel::format::FormatOptions;
use appel::scene::Scene;
use appel::scene_build::SceneOptions;
use std::path::PathBuf;
use std::time::Duration;

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
    /// Override camera.aperture_radius: a thin lens of this radius in scene units (0: a pinhole).
    #[arg(long, value_name = "R")]
    pub aperture_radius: Option<f32>,
    /// Override camera.focus_distance: the distance along the view axis to the plane in focus.
    #[arg(long, value_name = "D")]
    pub focus_distance: Option<f32>,
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
        if let Some(x) = self.aperture_radius {
            d.camera.aperture_radius = x;
        }
        if let Some(x) = self.focus_distance {
            d.camera.focus_distance = Some(x);
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

/// Reads a scene (file, mesh file or built-in; `appel::api::resolve_scene`), lets `adjust` apply
/// command-line overrides, checks the result, and builds it on the current thread pool. A mesh
/// file is framed once its bounds are known, and `adjust` runs again so that camera flags win over
/// the framing. Returns the scene and the time spent reading and checking the scene file.
pub fn load_scene(
    name: Option<&str>,
    xml: &FormatOptions,
    adjust: impl Fn(&mut Description) -> Result<()>,
) -> Result<(Scene, Duration)> {
    load_scene_with(name, xml, adjust, SceneOptions::default(), None)
}

/// [`load_scene`] with progress reports and cancellation while files load and structures build,
/// and a glTF file's `camera`. Before anything large is read, the scene's estimated memory is
/// checked against what is available.
pub fn load_scene_with(
    name: Option<&str>,
    xml: &FormatOptions,
    adjust: impl Fn(&mut Description) -> Result<()>,
    options: SceneOptions,
    camera: Option<usize>,
) -> Result<(Scene, Duration)> {
    let request = scene_request(name, xml, camera, &adjust);
    let mut resolved = resolve(&request)?;
    let scene = build_resolved(&request, &mut resolved, options)?;
    for w in &scene.from_files.warnings {
        eprintln!("warning: {w}");
    }
    Ok((scene, resolved.parse_time))
}

/// The description of a scene file or built-in scene (not a mesh file) after `adjust`, checked,
/// and the folder its files are relative to: for animations, which build one scene per frame.
pub fn load_description_only(
    name: Option<&str>,
    xml: &FormatOptions,
    adjust: impl Fn(&mut Description) -> Result<()>,
) -> Result<(Description, PathBuf)> {
    let name = name.unwrap_or(DEFAULT_SCENE);
    if appel::api::is_model(name) {
        bail!("`{name}` is a mesh file; an animation is a scene file with `[animation]`");
    }
    let resolved = resolve(&scene_request(Some(name), xml, None, &adjust))?;
    Ok((resolved.description, resolved.base_dir))
}

/// The scene `appel render` shows when none is named.
pub const DEFAULT_SCENE: &str = "whitted";

/// What the command line asks of `appel::api::resolve_scene`, in the flags' terms.
fn scene_request<'a>(
    name: Option<&'a str>,
    xml: &FormatOptions,
    camera: Option<usize>,
    adjust: &'a dyn Fn(&mut Description) -> Result<()>,
) -> SceneRequest<'a, anyhow::Error> {
    SceneRequest {
        name: name.unwrap_or(DEFAULT_SCENE),
        params: xml.clone(),
        camera,
        overrides: adjust,
        names: RequestNames {
            overrides: "command-line overrides",
            camera: "--camera",
            params: "-D parameters",
        },
    }
}

/// Reads and checks the scene, prints the reader's warnings, and checks its estimated memory.
fn resolve(request: &SceneRequest<'_, anyhow::Error>) -> Result<ResolvedScene> {
    let resolved = resolve_description(request)?;
    for w in &resolved.warnings {
        eprintln!("warning: {w}");
    }
    crate::memory::check_memory(&resolved.description, &resolved.base_dir)?;
    Ok(resolved)
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
