//! What a viewer session renders, and one frame's render as a job for a worker thread.
//!
//! The session hands its stage (the scene, or an animated scene's `Sequence`) to a worker thread
//! for each frame and gets it back with the film, so that the session thread meanwhile reads
//! the page's messages and encodes and sends the previous frame: encoding and sending overlap the
//! next render instead of following it.

use appel::accel::TraversalStats;
use appel::render::{render, Film, RenderOptions, RenderStats};
use appel::scene::{Camera, FrameUpdate, IntegratorKind, Scene, Sequence};
use rayon::prelude::*;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

pub enum Stage {
    Still(Box<Scene>),
    /// An animated scene: moving to another frame refits its structures (`Sequence::advance`).
    Animated(Box<Sequence>),
}

impl Stage {
    pub fn scene(&self) -> &Scene {
        match self {
            Stage::Still(s) => s,
            Stage::Animated(q) => &q.scene,
        }
    }

    fn scene_mut(&mut self) -> &mut Scene {
        match self {
            Stage::Still(s) => s,
            Stage::Animated(q) => &mut q.scene,
        }
    }

    /// The animation frame shown (0 for a still scene).
    pub fn frame(&self) -> u32 {
        match self {
            Stage::Still(_) => 0,
            Stage::Animated(q) => q.frame,
        }
    }

    /// The scene, if it is the one a new session starts from (an animation's first frame).
    pub fn into_initial_scene(self) -> Option<Scene> {
        match self {
            Stage::Still(s) => Some(*s),
            Stage::Animated(q) if q.frame == 0 => Some(q.scene),
            Stage::Animated(_) => None,
        }
    }
}

/// One frame to render: the camera, integrator and seed, and the animation frame to move to
/// first (if it differs from the stage's).
pub struct Job {
    pub stage: Stage,
    pub to_frame: Option<u32>,
    pub camera: Camera,
    pub integrator: IntegratorKind,
    pub seed: u64,
    /// Also compute the traversal-cost heat map (the `cost` AOV).
    pub cost: bool,
    /// Fill the film's AOVs (depth, normal, ids): only when one of them is shown.
    pub aovs: bool,
    /// A preview (shown even if the view changed meanwhile) rather than a still pass (which is
    /// averaged with the others, so only counts if the view is unchanged).
    pub preview: bool,
    /// The session's view generation when the job started: a still pass of an older one is
    /// dropped.
    pub generation: u64,
}

/// A job's frame.
pub struct Rendered {
    /// `None` when cancelled or failed, or (set by the session) when dropped.
    pub film: Option<(Film, RenderStats)>,
    pub cost: Option<Vec<u32>>,
    pub render_time: Duration,
    /// The move to another animation frame, if the job made one; its error, if it failed (the
    /// stage then stays at its frame and nothing is rendered).
    pub update: Option<Result<FrameUpdate, String>>,
    pub preview: bool,
    pub generation: u64,
    pub integrator: IntegratorKind,
    /// The animation frame shown.
    pub anim_frame: u32,
}

impl Job {
    /// Moves to the animation frame, then renders one sample per pixel. `cancel` stops the render
    /// early (the film is then `None`). Gives the stage back with the frame.
    pub fn run(mut self, cancel: &AtomicBool) -> (Stage, Rendered) {
        let update = match (self.to_frame, &mut self.stage) {
            (Some(f), Stage::Animated(q)) => {
                Some(q.advance(f).map_err(|e| format!("frame {f}: {e}")))
            }
            _ => None,
        };
        let (mut film, mut cost, mut render_time) = (None, None, Duration::ZERO);
        if !matches!(update, Some(Err(_))) {
            let scene = self.stage.scene_mut();
            // The scene's own camera and settings come back afterwards: a scene put back for
            // the next session starts from them.
            let own = (scene.camera, scene.settings.clone());
            scene.camera = self.camera;
            scene.settings.spp = 1;
            scene.settings.integrator = self.integrator;
            scene.settings.seed = self.seed;
            let start = Instant::now();
            let options = RenderOptions {
                cancel: Some(cancel),
                skip_aovs: !self.aovs,
                ..Default::default()
            };
            film = render(scene, &options).ok();
            if self.cost && film.is_some() {
                cost = Some(pixel_costs(scene));
            }
            render_time = start.elapsed();
            (scene.camera, scene.settings) = own;
        }
        let rendered = Rendered {
            film,
            cost,
            render_time,
            update,
            preview: self.preview,
            generation: self.generation,
            integrator: self.integrator,
            anim_frame: self.stage.frame(),
        };
        (self.stage, rendered)
    }
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
