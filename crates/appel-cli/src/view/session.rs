//! One viewer's WebSocket session: it owns a scene, answers camera moves with fast previews
//! (lower resolution, raycast or Whitted, one sample) and, once the camera is still, refines the
//! image with passes of one sample of the chosen integrator, each with its own seed, averaged
//! (each pass is an independent estimate of the pixel, so their mean converges like one render
//! with as many samples). An animated scene plays as previews, stepping one animation frame per
//! rendered frame and at most at the animation's frame rate (slower if rendering is slower), its
//! structures refitted from frame to frame (`Sequence::advance`); paused, its frame converges
//! like a still scene.
//!
//! Pipelining: each frame renders on a worker thread (`stage.rs`) while this thread reads the
//! page's messages and encodes and sends the frame before. Flow control: at most
//! [`MAX_IN_FLIGHT`] frames are rendering, encoding or sent but not yet acknowledged as drawn by
//! the page, so the page decodes frame k while frame k+1 renders, and frames never queue in the
//! socket behind a slow page.

use super::frame;
use super::messages::{self, CameraMsg, ClientMsg};
use super::stage::{Job, Rendered, Stage};
use super::Shared;
use appel::description::animation::{frame_count, is_animated};
use appel::description::CameraKind;
use appel::math::Vec3;
use appel::scene::{IntegratorKind, Scene};
use appel::scene_build::{FrameUpdate, SceneOptions, Sequence};
use serde_json::json;
use std::collections::VecDeque;
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::{Scope, ScopedJoinHandle};
use std::time::{Duration, Instant};
use tungstenite::{Error as WsError, Message, WebSocket};

/// With no camera message for this long, a moving camera is taken to be still.
const STILL_AFTER: Duration = Duration::from_millis(250);
/// Frames rendering, encoding or awaiting the page's acknowledgement at once: two lets the
/// server render one frame while the page decodes the other.
const MAX_IN_FLIGHT: usize = 2;

struct View {
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
    /// Still passes started since the view last changed (some may still be rendering).
    started: u32,
    base_seed: u64,
    /// Counts the view's changes: a still pass started before the last change is dropped.
    generation: u64,
    animation: Option<Playback>,
}

/// An animated scene's playback.
struct Playback {
    frames: u32,
    fps: f32,
    /// The animation frame to show: the stage's own, unless the page asked for another.
    frame: u32,
    playing: bool,
    /// When playing last stepped to the next frame: it steps at most `fps` times a second.
    last_step: Instant,
}

impl Playback {
    /// How long until playing may step to the next frame (zero if it may now).
    fn step_due_in(&self) -> Duration {
        Duration::from_secs_f32(1.0 / self.fps.max(1e-3)).saturating_sub(self.last_step.elapsed())
    }
}

impl View {
    /// Whether there is a frame to render: a preview while the camera moves or the animation
    /// plays, else the still passes not yet started.
    fn has_work(&self) -> bool {
        let step_due = self
            .animation
            .as_ref()
            .is_some_and(|a| a.playing && a.step_due_in().is_zero());
        self.moving || step_due || (!self.playing() && self.started < self.spp)
    }

    fn playing(&self) -> bool {
        self.animation.as_ref().is_some_and(|a| a.playing)
    }
}

/// The session's connection and the frames it has sent and not yet had acknowledged.
struct Link<'w> {
    ws: &'w mut WebSocket<TcpStream>,
    unacked: VecDeque<u64>,
    next_id: u64,
}

pub fn run(ws: &mut WebSocket<TcpStream>, shared: &Shared, stop: &AtomicBool) {
    let Some(stage) = take_stage(shared) else {
        let _ = send_json(ws, &json!({"type": "error", "message": "no scene to view"}));
        return;
    };
    let scene = stage.scene();
    let c = scene.camera;
    let animation = match &stage {
        Stage::Animated(_) => shared.description.as_ref().map(|d| Playback {
            frames: frame_count(d),
            fps: d.animation.as_ref().map_or(24.0, |a| a.fps),
            frame: 0,
            playing: false,
            last_step: Instant::now(),
        }),
        Stage::Still(_) => None,
    };
    let mut view = View {
        accel: scene.settings.accel.name().to_string(),
        integrator: scene.settings.integrator,
        preview: IntegratorKind::Whitted,
        preview_scale: 2,
        aov: "color".into(),
        format: frame::default_format(ws.get_ref().peer_addr().is_ok_and(|a| a.ip().is_loopback())),
        spp: scene.settings.spp.max(1),
        width: c.width,
        height: c.height,
        camera: c,
        moving: false,
        last_move: Instant::now(),
        sum: Vec::new(),
        passes: 0,
        started: 0,
        base_seed: scene.settings.seed,
        generation: 0,
        animation,
    };
    let mut link = Link {
        ws,
        unacked: VecDeque::new(),
        next_id: 0,
    };
    let _ = send_json(link.ws, &hello(&view, scene));
    let _ = send_json(link.ws, &scene_info(&view, scene));
    let abort = AtomicBool::new(false);
    let stage =
        std::thread::scope(|s| serve_frames(&mut link, &mut view, stage, shared, stop, &abort, s));
    if let Some(scene) = stage.into_initial_scene() {
        put_back(shared, scene);
    }
}

/// The session's loop: reads messages, starts a frame's job whenever one may be in flight,
/// sends finished frames; returns the stage once the page leaves or the server stops.
fn serve_frames<'s>(
    link: &mut Link,
    view: &mut View,
    stage: Stage,
    shared: &Shared,
    stop: &AtomicBool,
    abort: &'s AtomicBool,
    scope: &'s Scope<'s, '_>,
) -> Stage {
    let mut idle = Some(stage);
    let mut job: Option<ScopedJoinHandle<'s, (Stage, Rendered)>> = None;
    let mut job_is_preview = false;
    'session: loop {
        if stop.load(Ordering::SeqCst) {
            abort.store(true, Ordering::SeqCst);
            let _ = link.ws.close(None);
            let _ = link.ws.flush();
            break;
        }
        let can_start = job.is_none() && link.unacked.len() < MAX_IN_FLIGHT && view.has_work();
        let wait = match (&job, can_start) {
            (Some(_), _) => 2,
            (None, true) => 1,
            // Idle: until the next animation step, if playing, else 50 ms.
            (None, false) => view
                .animation
                .as_ref()
                .filter(|a| a.playing)
                .map_or(50, |a| a.step_due_in().as_millis().clamp(1, 50) as u64),
        };
        let Ok(msgs) = read_messages(link.ws, wait) else {
            break;
        };
        for m in msgs {
            let generation = view.generation;
            let outcome = match m {
                Ok(ClientMsg::Ack(id)) => {
                    while link.unacked.front().is_some_and(|&f| f <= id) {
                        link.unacked.pop_front();
                    }
                    Ok(())
                }
                Ok(ClientMsg::Camera(cm)) => {
                    set_camera(view, &cm);
                    Ok(())
                }
                Ok(ClientMsg::Settings(s)) => {
                    // A new structure needs the stage back from the job.
                    if s.accel.as_ref().is_some_and(|a| *a != view.accel) {
                        if let Some(h) = job.take() {
                            let (stage, out) = join(h);
                            idle = Some(stage);
                            if finish(link, view, out).is_err() {
                                break 'session;
                            }
                        }
                    }
                    apply_settings(view, s, idle.as_mut(), shared).map(|()| {
                        if let Some(stage) = &idle {
                            let _ = send_json(link.ws, &scene_info(view, stage.scene()));
                        }
                    })
                }
                Ok(ClientMsg::Play(playing)) => play(view, playing),
                Ok(ClientMsg::Seek(f)) => seek(view, f),
                Err(e) => Err(e),
            };
            if let Err(e) = outcome {
                if send_json(link.ws, &json!({"type": "error", "message": e})).is_err() {
                    break 'session;
                }
            }
            if view.generation != generation && job.is_some() && !job_is_preview {
                // A still pass of the old view would be dropped: stop it early. (A preview is
                // shown, however old: while the camera moves, every preview is.)
                abort.store(true, Ordering::SeqCst);
            }
        }
        if view.moving && view.last_move.elapsed() > STILL_AFTER {
            view.moving = false;
            restart(view);
        }
        let mut finished = None;
        match job.take() {
            Some(h) if h.is_finished() => {
                let (stage, mut out) = join(h);
                idle = Some(stage);
                if absorb(link, view, &mut out).is_err() {
                    break;
                }
                finished = Some(out);
            }
            running => job = running,
        }
        // The finished frame counts as in flight until it is sent; the next job starts before
        // it is encoded, so that encoding overlaps the render.
        let in_flight = link.unacked.len() + finished.is_some() as usize;
        if job.is_none() && in_flight < MAX_IN_FLIGHT && view.has_work() {
            if let Some(stage) = idle.take() {
                abort.store(false, Ordering::SeqCst);
                let next = next_job(view, stage);
                job_is_preview = next.preview;
                job = Some(scope.spawn(move || next.run(abort)));
            }
        }
        if let Some(out) = finished {
            if send_frame(link, view, out).is_err() {
                break;
            }
        }
    }
    abort.store(true, Ordering::SeqCst);
    match job {
        Some(h) => join(h).0,
        None => idle.expect("no job holds the stage"),
    }
}

fn join(h: ScopedJoinHandle<'_, (Stage, Rendered)>) -> (Stage, Rendered) {
    h.join().unwrap_or_else(|p| std::panic::resume_unwind(p))
}

/// A frame's job: a preview while the camera moves or the animation plays (which steps to the
/// next animation frame), else the next still pass.
fn next_job(view: &mut View, stage: Stage) -> Job {
    let preview = view.moving || view.playing();
    let to_frame = view.animation.as_mut().and_then(|a| {
        let at = stage.frame();
        if a.playing && a.frame == at && a.step_due_in().is_zero() {
            a.frame = (at + 1) % a.frames;
            a.last_step = Instant::now();
        }
        (a.frame != at).then_some(a.frame)
    });
    let scale = if preview { view.preview_scale } else { 1 };
    let mut camera = view.camera;
    camera.width = (view.width / scale).max(8);
    camera.height = (view.height / scale).max(8);
    let seed = if preview {
        view.base_seed
    } else {
        view.started += 1;
        view.base_seed.wrapping_add(view.started as u64 - 1)
    };
    Job {
        stage,
        to_frame,
        camera,
        integrator: if preview {
            view.preview
        } else {
            view.integrator
        },
        seed,
        cost: view.aov == "cost",
        aovs: !matches!(view.aov.as_str(), "color" | "cost"),
        preview,
        generation: view.generation,
    }
}

/// Takes a finished job's frame into the view: reports a failed move to another animation frame
/// (and pauses), adds a still pass to the sum, or drops it if the view changed since it started.
fn absorb(link: &mut Link, view: &mut View, out: &mut Rendered) -> Result<(), ()> {
    if let Some(Err(e)) = &out.update {
        if let Some(a) = view.animation.as_mut() {
            a.playing = false;
            a.frame = out.anim_frame;
        }
        send_json(link.ws, &json!({"type": "error", "message": e}))?;
    }
    if out.preview {
        return Ok(());
    }
    match &out.film {
        Some((film, _)) if out.generation == view.generation => {
            if view.sum.len() != film.rgb.len() {
                view.sum = vec![Vec3::ZERO; film.rgb.len()];
            }
            for (s, c) in view.sum.iter_mut().zip(&film.rgb) {
                *s += *c;
            }
            view.passes += 1;
        }
        _ => out.film = None,
    }
    Ok(())
}

/// [`absorb`], then [`send_frame`].
fn finish(link: &mut Link, view: &mut View, mut out: Rendered) -> Result<(), ()> {
    absorb(link, view, &mut out)?;
    send_frame(link, view, out)
}

/// Encodes and sends a frame (its info, then its image); nothing for a dropped one.
fn send_frame(link: &mut Link, view: &View, out: Rendered) -> Result<(), ()> {
    let Some((film, stats)) = &out.film else {
        return Ok(());
    };
    let encode_start = Instant::now();
    let averaged: Vec<Vec3>;
    let rgb = if out.preview {
        &film.rgb
    } else {
        let k = 1.0 / view.passes.max(1) as f32;
        averaged = view.sum.iter().map(|s| *s * k).collect();
        &averaged
    };
    let rgb8 = frame::to_rgb8(&view.aov, film, rgb, out.cost.as_deref());
    let bytes = frame::encode(&rgb8, film.width, film.height, view.format);
    let id = link.next_id;
    let step = out.update.as_ref().and_then(|u| u.as_ref().ok());
    let info = json!({
        "type": "frame",
        "id": id,
        "width": film.width,
        "height": film.height,
        "preview": out.preview,
        "spp": if out.preview { 1 } else { view.passes },
        "target_spp": view.spp,
        "render_ms": out.render_time.as_secs_f64() * 1e3,
        "encode_ms": encode_start.elapsed().as_secs_f64() * 1e3,
        "bytes": bytes.len(),
        "rays": stats.rays.total(),
        "mrays_per_s": stats.mrays_per_second(),
        "integrator": out.integrator.name(),
        "anim_frame": out.anim_frame,
        "playing": view.playing(),
        "step": step.map(step_info),
    });
    send_json(link.ws, &info)?;
    link.ws.send(Message::Binary(bytes)).map_err(|_| ())?;
    link.unacked.push_back(id);
    link.next_id += 1;
    Ok(())
}

/// What moving to an animation frame cost, for the page's panel.
fn step_info(u: &FrameUpdate) -> serde_json::Value {
    json!({
        "frame": u.frame,
        "load_ms": u.load.as_secs_f64() * 1e3,
        "refit_ms": u.refit.as_secs_f64() * 1e3,
        "rebuild_ms": u.rebuild.as_secs_f64() * 1e3,
        "refitted": u.refitted,
        "rebuilt": u.rebuilt,
    })
}

fn play(view: &mut View, playing: bool) -> Result<(), String> {
    let a = view
        .animation
        .as_mut()
        .ok_or("play: this scene is not animated")?;
    if a.playing != playing {
        a.playing = playing;
        restart(view);
    }
    Ok(())
}

fn seek(view: &mut View, frame: u32) -> Result<(), String> {
    let a = view
        .animation
        .as_mut()
        .ok_or("seek: this scene is not animated")?;
    if frame >= a.frames {
        return Err(format!(
            "seek: frame {frame} is past the animation's last frame, {}",
            a.frames - 1
        ));
    }
    a.frame = frame;
    restart(view);
    Ok(())
}

/// The shared scene if no other session holds it, else a new one built from the description;
/// for an animated scene, its sequence at the first frame.
fn take_stage(shared: &Shared) -> Option<Stage> {
    let scene = take_scene(shared)?;
    match &shared.description {
        Some(d) if is_animated(d) && frame_count(d) > 1 => {
            match Sequence::from_scene(d, &shared.base_dir, 0, scene) {
                Ok(q) => Some(Stage::Animated(Box::new(q))),
                Err(_) => None,
            }
        }
        _ => Some(Stage::Still(Box::new(scene))),
    }
}

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

/// Reads what the page sent: waits up to `wait_ms` for a first message, then drains what has
/// arrived. `Err` when the connection is gone or unusable.
fn read_messages(
    ws: &mut WebSocket<TcpStream>,
    wait_ms: u64,
) -> Result<Vec<Result<ClientMsg, String>>, ()> {
    let mut out = Vec::new();
    let mut wait = wait_ms;
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

/// The view changed: the still passes start over.
fn restart(view: &mut View) {
    view.passes = 0;
    view.started = 0;
    view.sum.clear();
    view.generation += 1;
}

fn apply_settings(
    view: &mut View,
    s: messages::SettingsMsg,
    stage: Option<&mut Stage>,
    shared: &Shared,
) -> Result<(), String> {
    if let Some(name) = s.accel.filter(|a| *a != view.accel) {
        let stage = stage.expect("the caller takes the stage back for a new structure");
        let d = shared
            .description
            .as_ref()
            .ok_or("this scene cannot be rebuilt")?;
        let mut d = d.clone();
        d.render.accel = name.clone();
        let fail = |e: appel::error::Error| format!("accel {name}: {e}");
        *stage = match stage {
            Stage::Still(_) => Stage::Still(Box::new(
                Scene::new_with(&d, &shared.base_dir, SceneOptions::default()).map_err(fail)?,
            )),
            Stage::Animated(q) => Stage::Animated(Box::new(
                Sequence::new(&d, &shared.base_dir, q.frame).map_err(fail)?,
            )),
        };
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
    if let Some(r) = s.aperture_radius {
        view.camera.lens_radius = r;
    }
    if let Some(f) = s.focus_distance {
        view.camera.focus_distance = f;
    }
    restart(view);
    Ok(())
}

fn hello(view: &View, scene: &Scene) -> serde_json::Value {
    let c = &view.camera;
    let b = scene.geometry.bounds();
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
        "aperture_radius": shortest(c.lens_radius),
        "focus_distance": shortest(c.focus_distance),
        "width": view.width,
        "height": view.height,
        "spp": view.spp,
        "integrator": view.integrator.name(),
        "accel": view.accel,
        "integrators": IntegratorKind::NAMES,
        "previews": messages::previews(),
        "accels": appel::accel::AccelKind::NAMES,
        "aovs": messages::AOVS,
        "formats": messages::FORMATS,
        "format": frame::format_name(view.format),
        "scene_size": (b.max - b.min).length(),
        "frames": view.animation.as_ref().map_or(1, |a| a.frames),
        "fps": view.animation.as_ref().map(|a| a.fps),
    })
}

/// `x` as the f64 of its shortest decimal form, so that the page's fields show 0.3, not the f32's
/// exact 0.30000001192092896.
fn shortest(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(x as f64)
}

fn scene_info(view: &View, scene: &Scene) -> serde_json::Value {
    let s = scene.accel_stats();
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
