//! `appel view`: a local web server for an interactive viewer of a scene (frames streamed over a
//! WebSocket while the camera moves or an animation plays, then refined progressively), and for
//! the lecture's 2D illustrations of acceleration structures (`--lecture`), computed by the
//! `appel-lecture2d` crate and drawn by the page.
//!
//! Safety: the server binds to loopback unless `--host` says otherwise, serves only the assets
//! compiled into the binary, its frames and the 2D API (never a file by path), bounds request
//! heads and WebSocket messages, caps the number of connections, and stops on Ctrl-C.

mod assets;
mod frame;
mod http;
mod lecture_api;
mod messages;
mod server;
mod session;
mod srgb8;
mod stage;

use crate::scene_args::{load_scene, ParamArgs, ViewArgs as CameraArgs};
use anyhow::{bail, Result};
use appel::description::Description;
use appel::scene::Scene;
use std::net::{IpAddr, Ipv4Addr};

#[derive(clap::Args)]
pub struct ViewArgs {
    /// A scene file, a mesh file or a built-in scene (as for `appel render`). Default: whitted.
    scene: Option<String>,
    /// Serve the lecture's 2D illustrations (uniform grid, quadtree, kd-tree, BSP, BVH) instead
    /// of a scene.
    #[arg(long)]
    lecture: bool,
    /// Port to listen on (default: a free one).
    #[arg(long, default_value_t = 0)]
    port: u16,
    /// Address to bind. Anything other than loopback exposes the viewer to the network.
    #[arg(long, default_value = "127.0.0.1")]
    host: IpAddr,
    /// Open the page in the default browser.
    #[arg(long)]
    open: bool,
    /// Most connections served at once; more are refused with 503.
    #[arg(long, default_value_t = 16)]
    max_connections: usize,
    /// Override render.accel.
    #[arg(long)]
    accel: Option<String>,
    /// Override render.integrator.
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(appel::scene::IntegratorKind::NAMES))]
    integrator: Option<String>,
    /// Override render.spp: the samples per pixel the still image converges to.
    #[arg(long)]
    spp: Option<u32>,
    #[command(flatten)]
    view: CameraArgs,
    #[command(flatten)]
    params: ParamArgs,
}

/// What every connection shares: the scene's description (each viewer session builds its own
/// scene from it, so sessions can pick structures independently) and the first built scene.
pub struct Shared {
    pub lecture_only: bool,
    pub description: Option<Description>,
    pub base_dir: std::path::PathBuf,
    /// The scene built at start, lent to one session at a time (others build their own).
    pub scene: std::sync::Mutex<Option<Scene>>,
    /// The camera of the scene built at start (a framed mesh file's is decided after the build).
    pub camera: Option<appel::scene::Camera>,
}

pub fn run(args: ViewArgs) -> Result<()> {
    if !args.host.is_loopback() {
        eprintln!(
            "warning: --host {}: the viewer is reachable from the network; it has no \
             authentication",
            args.host
        );
    }
    if args.max_connections == 0 {
        bail!("--max-connections: expected at least 1");
    }
    let shared = if args.lecture {
        Shared {
            lecture_only: true,
            description: None,
            base_dir: ".".into(),
            scene: std::sync::Mutex::new(None),
            camera: None,
        }
    } else {
        load_shared(&args)?
    };
    let listener = std::net::TcpListener::bind((args.host, args.port))
        .map_err(|e| anyhow::anyhow!("cannot listen on {}:{}: {e}", args.host, args.port))?;
    let addr = listener.local_addr()?;
    let host = if addr.ip() == IpAddr::V4(Ipv4Addr::UNSPECIFIED) {
        IpAddr::V4(Ipv4Addr::LOCALHOST)
    } else {
        addr.ip()
    };
    let url = format!("http://{host}:{}/", addr.port());
    println!("appel view: serving {url} (Ctrl-C to stop)");
    if args.open {
        if let Err(e) = std::process::Command::new("xdg-open").arg(&url).spawn() {
            eprintln!("warning: --open: could not start a browser ({e}); open {url} by hand");
        }
    }
    server::serve(listener, std::sync::Arc::new(shared), args.max_connections)?;
    println!("appel view: stopped");
    Ok(())
}

/// Reads and builds the scene once (so errors show before the server starts), keeping the
/// description the sessions rebuild from when the structure changes.
fn load_shared(args: &ViewArgs) -> Result<Shared> {
    let xml = args.params.format_options()?;
    let kept = std::sync::Mutex::new(None::<Description>);
    let (scene, _) = load_scene(args.scene.as_deref(), &xml, |d| {
        if let Some(x) = &args.accel {
            d.render.accel = x.clone();
        }
        if let Some(x) = &args.integrator {
            d.render.integrator = appel::scene::IntegratorKind::from_name(x).ok_or_else(|| {
                anyhow::anyhow!(
                    "--integrator: unknown integrator `{x}`, expected one of: {}",
                    appel::scene::IntegratorKind::NAMES.join(", ")
                )
            })?;
        }
        if let Some(x) = args.spp {
            d.render.spp = x;
        }
        args.view.apply(d)?;
        *kept.lock().expect("not poisoned") = Some(d.clone());
        Ok(())
    })?;
    let description = kept.into_inner().expect("not poisoned");
    Ok(Shared {
        lecture_only: false,
        description,
        base_dir: scene_base_dir(args.scene.as_deref()),
        camera: Some(scene.camera),
        scene: std::sync::Mutex::new(Some(scene)),
    })
}

fn scene_base_dir(scene: Option<&str>) -> std::path::PathBuf {
    match scene.map(std::path::Path::new).and_then(|p| p.parent()) {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => ".".into(),
    }
}
