//! One viewer's WebSocket session: it owns a scene, answers camera moves with fast previews
//! (lower resolution, raycast or Whitted, one sample) and, once the camera is still, refines the
//! image with passes of one sample of the chosen integrator, each with its own seed, averaged
//! (each pass is an independent estimate of the pixel, so their mean converges like one render
//! with as many samples).
//!
//! Flow control: a frame is sent only once the page has acknowledged the previous one, so frames
//! never queue in the socket and the page always gets the newest view.

use super::frame;
use super::messages::{self, CameraMsg, ClientMsg};
use super::Shared;
use appel::accel::TraversalStats;
use appel::math::Vec3;
use appel::render::{render, RenderOptions};
use appel::scene::description::CameraKind;
use appel::scene::{IntegratorKind, Scene, SceneOptions};
use rayon::prelude::*;
use serde_json::json;
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use tungstenite::{Error as WsError, Message, WebSocket};

/// With no camera message for this long, a moving camera is taken to be still.
const STILL_AFTER: Duration = Duration::from_millis(250);

struct View {
    scene: Scene,
    accel: String,
    integrator: IntegratorKind,
    preview: IntegratorKind,
    preview_scale: u32,
    aov: String,
    format: u32,
    spp: u32,
    width: u32,
    height: u32,
    camera: appel::scene::Camera,
    moving: bool,
    last_move: Instant,
    /// Radiance summed over the still passes so far, and their count.
    sum: Vec<Vec3>,
    passes: u32,
    base_seed: u64,
}

pub fn run(ws: &mut WebSocket<TcpStream>, shared: &Shared, stop: &AtomicBool) {
    let Some(scene) = take_scene(shared) else {
        let _ = send_json(ws, &json!({"type": "error", "message": "no scene to view"}));
        return;
    };
    let c = scene.camera;
    let mut view = View {
        accel: scene.settings.accel.name().to_string(),
        integrator: scene.settings.integrator,
        preview: IntegratorKind::Whitted,
        preview_scale: 2,
        aov: "color".into(),
        format: frame::FORMAT_JPEG,
        spp: scene.settings.spp.max(1),
        width: c.width,
        height: c.height,
        camera: c,
        moving: false,
        last_move: Instant::now(),
        sum: Vec::new(),
        passes: 0,
        base_seed: scene.settings.seed,
        scene,
    };
    let _ = send_json(ws, &hello(&view));
    let _ = send_json(ws, &scene_info(&view));
    let mut next_frame = 0u64;
    let mut awaiting: Option<u64> = None;
    loop {
        if stop.load(Ordering::SeqCst) {
            let _ = ws.close(None);
            let _ = ws.flush();
            break;
        }
        let idle = awaiting.is_some() || (!view.moving && view.passes >= view.spp);
        match read_messages(ws, idle) {
            Err(()) => break,
            Ok(msgs) => {
                for m in msgs {
                    match m {
                        Ok(ClientMsg::Ack(id)) => {
                            if awaiting == Some(id) {
                                awaiting = None;
                            }
                        }
                        Ok(ClientMsg::Camera(cm)) => set_camera(&mut view, &cm),
                        Ok(ClientMsg::Settings(s)) => {
                            if let Err(e) = apply_settings(&mut view, s, shared) {
                                let _ = send_json(ws, &json!({"type": "error", "message": e}));
                            } else {
                                let _ = send_json(ws, &scene_info(&view));
                            }
                        }
                        Err(e) => {
                            if send_json(ws, &json!({"type": "error", "message": e})).is_err() {
                                return put_back(shared, view.scene);
                            }
                        }
                    }
                }
            }
        }
        if view.moving && view.last_move.elapsed() > STILL_AFTER {
            view.moving = false;
        }
        if awaiting.is_some() || (!view.moving && view.passes >= view.spp) {
            continue;
        }
        let Some((bytes, info)) = render_frame(&mut view, next_frame, stop) else {
            continue;
        };
        if send_json(ws, &info).is_err() || ws.send(Message::Binary(bytes)).is_err() {
            break;
        }
        awaiting = Some(next_frame);
        next_frame += 1;
    }
    put_back(shared, view.scene);
}

/// The shared scene if no other session holds it, else a new one built from the description.
fn take_scene(shared: &Shared) -> Option<Scene> {
    if let Some(s) = shared.scene.lock().ok()?.take() {
        return Some(s);
    }
    let d = shared.description.as_ref()?;
    let mut s = Scene::new_with(d, &shared.base_dir, SceneOptions::default()).ok()?;
    s.camera = shared.camera?;
    Some(s)
}

fn put_back(shared: &Shared, scene: Scene) {
    if let Ok(mut slot) = shared.scene.lock() {
        if slot.is_none() {
            *slot = Some(scene);
        }
    }
}

/// Reads what the page sent. Idle, it waits up to 50 ms for a first message; busy, it only
/// drains what has arrived. `Err` when the connection is gone or unusable.
fn read_messages(
    ws: &mut WebSocket<TcpStream>,
    idle: bool,
) -> Result<Vec<Result<ClientMsg, String>>, ()> {
    let mut out = Vec::new();
    let mut wait = if idle { 50 } else { 1 };
    loop {
        if ws
            .get_mut()
            .set_read_timeout(Some(Duration::from_millis(wait)))
            .is_err()
        {
            return Err(());
        }
        match ws.read() {
            Ok(Message::Text(t)) => out.push(messages::parse(&t)),
            Ok(Message::Binary(_)) => out.push(Err("binary messages are not accepted".into())),
            Ok(Message::Close(_)) => {
                let _ = ws.flush();
                return Err(());
            }
            Ok(_) => {}
            Err(WsError::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                return Ok(out)
            }
            // Oversized or malformed frames, a closed or reset connection: end the session.
            Err(_) => return Err(()),
        }
        wait = 1;
        if out.len() > 256 {
            return Ok(out);
        }
    }
}

fn set_camera(view: &mut View, m: &CameraMsg) {
    let eye = Vec3::from(m.eye);
    let forward = (Vec3::from(m.look_at) - eye).normalize();
    let right = forward.cross(Vec3::from(m.up)).normalize();
    let c = &mut view.camera;
    c.eye = eye;
    c.forward = forward;
    c.right = right;
    c.true_up = right.cross(forward);
    if c.kind == CameraKind::Perspective {
        c.tan_half_fov = (m.fov.to_radians() * 0.5).tan();
    }
    view.moving = m.moving;
    view.last_move = Instant::now();
    restart(view);
}

fn restart(view: &mut View) {
    view.passes = 0;
    view.sum.clear();
}

fn apply_settings(
    view: &mut View,
    s: messages::SettingsMsg,
    shared: &Shared,
) -> Result<(), String> {
    if let Some(name) = s.accel.filter(|a| *a != view.accel) {
        let d = shared
            .description
            .as_ref()
            .ok_or("this scene cannot be rebuilt")?;
        let mut d = d.clone();
        d.render.accel = name.clone();
        let mut scene = Scene::new_with(&d, &shared.base_dir, SceneOptions::default())
            .map_err(|e| format!("accel {name}: {e}"))?;
        scene.camera = view.scene.camera;
        view.scene = scene;
        view.accel = name;
    }
    if let Some(x) = s.integrator {
        view.integrator = IntegratorKind::from_name(&x).expect("checked by the parser");
    }
    if let Some(x) = s.preview {
        view.preview = IntegratorKind::from_name(&x).expect("checked by the parser");
    }
    if let Some(x) = s.aov {
        view.aov = x;
    }
    if let Some(x) = s.format {
        view.format = frame::format_code(&x);
    }
    if let Some(x) = s.spp {
        view.spp = x;
    }
    if let Some(x) = s.preview_scale {
        view.preview_scale = x;
    }
    if let Some((w, h)) = s.size {
        view.width = w;
        view.height = h;
    }
    restart(view);
    Ok(())
}

/// Renders the next frame (a preview while moving, else the next still pass) and encodes it.
fn render_frame(
    view: &mut View,
    id: u64,
    stop: &AtomicBool,
) -> Option<(Vec<u8>, serde_json::Value)> {
    let preview = view.moving;
    let scale = if preview { view.preview_scale } else { 1 };
    let (w, h) = ((view.width / scale).max(8), (view.height / scale).max(8));
    let mut camera = view.camera;
    camera.width = w;
    camera.height = h;
    let scene = &mut view.scene;
    scene.camera = camera;
    scene.settings.spp = 1;
    if preview {
        scene.settings.integrator = view.preview;
        scene.settings.seed = view.base_seed;
    } else {
        scene.settings.integrator = view.integrator;
        scene.settings.seed = view.base_seed.wrapping_add(view.passes as u64);
    }
    let start = Instant::now();
    let options = RenderOptions {
        cancel: Some(stop),
        ..Default::default()
    };
    let (film, stats) = render(scene, &options).ok()?;
    let cost = (view.aov == "cost").then(|| pixel_costs(scene));
    let render_time = start.elapsed();
    let rgb: Vec<Vec3> = if preview {
        film.rgb.clone()
    } else {
        if view.sum.len() != film.rgb.len() {
            view.sum = vec![Vec3::ZERO; film.rgb.len()];
        }
        for (s, c) in view.sum.iter_mut().zip(&film.rgb) {
            *s += *c;
        }
        view.passes += 1;
        let k = 1.0 / view.passes as f32;
        view.sum.iter().map(|s| *s * k).collect()
    };
    let encode_start = Instant::now();
    let rgb8 = frame::to_rgb8(&view.aov, &film, &rgb, cost.as_deref());
    let bytes = frame::encode(&rgb8, w, h, view.format);
    let info = json!({
        "type": "frame",
        "id": id,
        "width": w,
        "height": h,
        "preview": preview,
        "spp": if preview { 1 } else { view.passes },
        "target_spp": view.spp,
        "render_ms": render_time.as_secs_f64() * 1e3,
        "encode_ms": encode_start.elapsed().as_secs_f64() * 1e3,
        "bytes": bytes.len(),
        "rays": stats.rays.total(),
        "mrays_per_s": stats.mrays_per_second(),
        "integrator": integrator_name(scene.settings.integrator),
    });
    Some((bytes, info))
}

/// Nodes visited plus primitives tested by each pixel's camera ray: the traversal-cost heat map.
fn pixel_costs(scene: &Scene) -> Vec<u32> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    (0..h)
        .into_par_iter()
        .flat_map_iter(|j| {
            (0..w).map(move |i| {
                let mut st = TraversalStats::default();
                let ray = scene.camera.pixel_ray(i, j);
                scene.intersect(&ray, f32::INFINITY, &mut st);
                (st.nodes_visited + st.prim_tests) as u32
            })
        })
        .collect()
}

fn hello(view: &View) -> serde_json::Value {
    let c = &view.camera;
    let b = view.scene.geometry.bounds();
    let centre = (b.min + b.max) * 0.5;
    // Orbit around the point of the view axis nearest the scene's centre (at least a little
    // ahead of the eye), so the first drag turns the scene about itself.
    let ahead = (centre - c.eye)
        .dot(c.forward)
        .max(1e-3 * (b.max - b.min).length().max(1.0));
    let target = c.eye + c.forward * ahead;
    json!({
        "type": "hello",
        "eye": [c.eye.x, c.eye.y, c.eye.z],
        "look_at": [target.x, target.y, target.z],
        "up": [c.true_up.x, c.true_up.y, c.true_up.z],
        "fov": 2.0 * c.tan_half_fov.atan().to_degrees(),
        "width": view.width,
        "height": view.height,
        "spp": view.spp,
        "integrator": integrator_name(view.integrator),
        "accel": view.accel,
        "integrators": IntegratorKind::NAMES,
        "previews": messages::PREVIEWS,
        "accels": appel::accel::AccelKind::NAMES,
        "aovs": messages::AOVS,
        "formats": messages::FORMATS,
        "scene_size": (b.max - b.min).length(),
    })
}

fn scene_info(view: &View) -> serde_json::Value {
    let s = view.scene.accel_stats();
    json!({
        "type": "scene",
        "accel": view.accel,
        "build_ms": s.build_time.as_secs_f64() * 1e3,
        "accel_bytes": s.bytes,
        "primitives": s.primitives,
        "peak_rss_bytes": crate::memory::peak_rss_bytes(),
    })
}

/// Sends a JSON message; `Err` when the connection is gone (the reason does not matter).
fn send_json(ws: &mut WebSocket<TcpStream>, v: &serde_json::Value) -> Result<(), ()> {
    ws.send(Message::Text(v.to_string())).map_err(|_| ())
}

fn integrator_name(k: IntegratorKind) -> &'static str {
    match k {
        IntegratorKind::Raycast => "raycast",
        IntegratorKind::Whitted => "whitted",
        IntegratorKind::Path => "path",
        IntegratorKind::Direct => "direct",
    }
}
