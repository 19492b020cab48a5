//! Rendering an animation frame after frame: each frame's geometry is loaded afresh (its own
//! keyframed transforms and mesh files), and the previous frame's structures are refitted to it
//! rather than built again, where that is possible and the refitted tree is still good.
//!
//! The policy, per structure:
//! - the top level over instances is always rebuilt: it has one primitive per instance, so it is
//!   cheap, and instances move freely, which refitting handles worst;
//! - a BVH over triangles (the top level of a scene without instances, or a declared mesh's) whose
//!   primitives are the same in number is refitted (`Bvh::refit`); if its SAH cost then exceeds
//!   [`REBUILD_FACTOR`] times its cost when it was last built, it is rebuilt instead;
//! - a declared mesh whose vertices did not move keeps its structure untouched;
//! - any other structure (grid, kd-tree, octree, BSP, or a mesh whose triangle count changed) is
//!   rebuilt.
//!
//! Since a frame's geometry never depends on the frames before it, a frame reached through
//! refits holds the same triangles as the frame built alone; only the trees' shapes differ, and
//! every structure returns the closest hit, so the images agree (tested in
//! `crates/appel-gen/tests/animation.rs`).

use super::{Description, Scene, SceneOptions};
use crate::accel::{Accel, Brute};
use crate::description::animation::{at_frame, frame_count};
use crate::error::{Error, Result};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A refitted BVH is rebuilt once its SAH cost exceeds its cost when built by this factor. Wald,
/// Boulos and Shirley (2007) rebuild when the refitted cost has grown "significantly"; 1.5 keeps
/// the traversal cost within about that factor of a fresh tree's while, on a deforming surface
/// (the waving cloth of `appel gen cloth`), a rebuild comes only every few dozen frames.
pub const REBUILD_FACTOR: f64 = 1.5;

/// An animated scene at one of its frames, with what its structures cost when last built.
pub struct Sequence {
    description: Description,
    base_dir: PathBuf,
    pub scene: Scene,
    pub frame: u32,
    /// What building the first frame did, in the terms [`Self::advance`] reports: its files
    /// loaded and every structure (the top level and each declared mesh's) built from scratch.
    pub first_build: FrameUpdate,
    /// SAH cost when last built of the top level (index 0) and of each declared mesh's structure,
    /// where the structure can be refitted.
    built_cost: Vec<Option<f64>>,
}

/// What moving to a frame did.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct FrameUpdate {
    pub frame: u32,
    /// Reading the frame's files and making its geometry.
    pub load: Duration,
    /// Refitting structures.
    pub refit: Duration,
    /// Building structures (from scratch).
    pub rebuild: Duration,
    /// Structures refitted, and kept after the refit.
    pub refitted: usize,
    /// Structures built from scratch: the top level over instances, other kinds than the BVH,
    /// and trees whose refit drifted past [`REBUILD_FACTOR`].
    pub rebuilt: usize,
    /// Of them, BVHs rebuilt because their refit drifted past [`REBUILD_FACTOR`].
    pub rebuilt_by_policy: usize,
    /// The largest ratio, over the refitted structures, of the SAH cost after the refit to the
    /// cost when last built (before any rebuild the policy then made); `None` if none was refitted.
    pub sah_drift: Option<f64>,
}

impl Sequence {
    /// The scene of animated description `d` at `frame`, its structures built from scratch.
    pub fn new(d: &Description, base_dir: &Path, frame: u32) -> Result<Self> {
        check_frame(d, frame)?;
        let scene = Scene::new(&at_frame(d, frame), base_dir)?;
        Self::from_scene(d, base_dir, frame, scene)
    }

    /// The sequence at `frame` from its scene already built from `at_frame(d, frame)` with its
    /// structures (as `Scene::new` builds it), so that a caller holding that scene need not
    /// build it again.
    pub fn from_scene(d: &Description, base_dir: &Path, frame: u32, scene: Scene) -> Result<Self> {
        check_frame(d, frame)?;
        let mut built_cost = vec![scene.accel.current_sah_cost()];
        built_cost.extend(
            scene
                .geometry
                .prototypes
                .iter()
                .map(|p| p.accel.current_sah_cost()),
        );
        let first_build = FrameUpdate {
            frame,
            load: scene.timings.load,
            rebuild: scene.timings.build,
            rebuilt: built_cost.len(),
            ..Default::default()
        };
        Ok(Self {
            description: d.clone(),
            base_dir: base_dir.to_path_buf(),
            scene,
            frame,
            first_build,
            built_cost,
        })
    }

    /// Moves to `frame`: loads its geometry and refits or rebuilds each structure by the policy
    /// above.
    pub fn advance(&mut self, frame: u32) -> Result<FrameUpdate> {
        check_frame(&self.description, frame)?;
        let start = Instant::now();
        let options = SceneOptions {
            skip_structures: true,
            ..Default::default()
        };
        let mut next =
            Scene::new_with(&at_frame(&self.description, frame), &self.base_dir, options)?;
        let mut u = FrameUpdate {
            frame,
            load: start.elapsed(),
            ..Default::default()
        };
        let kind = next.settings.accel;
        let opts = next.settings.accel_options;
        let mut built_cost = vec![None; next.geometry.prototypes.len() + 1];
        // The declared meshes' structures.
        for (k, p) in next.geometry.prototypes.iter_mut().enumerate() {
            let old = self.scene.geometry.prototypes.get_mut(k);
            let unmoved = old.as_ref().is_some_and(|o| {
                o.geometry.meshes.len() == p.geometry.meshes.len()
                    && o.geometry
                        .meshes
                        .iter()
                        .zip(&p.geometry.meshes)
                        .all(|(a, b)| a.positions == b.positions && a.indices == b.indices)
            });
            let previous = old
                .filter(|o| o.geometry.prims.len() == p.geometry.prims.len())
                .map(|o| std::mem::replace(&mut o.accel, Accel::Brute(Brute::default())));
            let (accel, cost) = if unmoved {
                let a = previous.expect("an unmoved mesh had a structure");
                (a, self.built_cost[k + 1])
            } else {
                update(
                    previous,
                    self.built_cost[k + 1],
                    &p.geometry,
                    &mut u,
                    || Accel::build_with(kind, &p.geometry, &opts),
                )
            };
            p.accel = accel;
            built_cost[k + 1] = cost;
        }
        // The top level: over instances it is always rebuilt.
        let previous = (next.geometry.instances.is_empty()
            && next.geometry.prims.len() == self.scene.geometry.prims.len())
        .then(|| std::mem::replace(&mut self.scene.accel, Accel::Brute(Brute::default())));
        let (accel, cost) = update(previous, self.built_cost[0], &next.geometry, &mut u, || {
            Accel::build_with(kind, &next.geometry, &opts)
        });
        next.accel = accel;
        built_cost[0] = cost;
        next.timings.build = u.refit + u.rebuild;
        next.timings.load = u.load;
        self.scene = next;
        self.frame = frame;
        self.built_cost = built_cost;
        Ok(u)
    }
}

/// Refits `previous` (if any) to `prims` under the policy, or builds anew with `build`; returns
/// the structure and its cost when last built.
fn update<P: crate::accel::Primitives>(
    previous: Option<Accel>,
    built_cost: Option<f64>,
    prims: &P,
    u: &mut FrameUpdate,
    build: impl FnOnce() -> Accel,
) -> (Accel, Option<f64>) {
    if let (Some(mut accel), Some(built)) = (previous, built_cost) {
        let start = Instant::now();
        let refitted = accel.refit(prims);
        u.refit += start.elapsed();
        if let Some(cost) = refitted {
            let drift = if built > 0.0 { cost / built } else { 1.0 };
            u.sah_drift = Some(u.sah_drift.map_or(drift, |d: f64| d.max(drift)));
            if drift <= REBUILD_FACTOR {
                u.refitted += 1;
                return (accel, Some(built));
            }
            u.rebuilt_by_policy += 1;
        }
    }
    let start = Instant::now();
    let accel = build();
    u.rebuild += start.elapsed();
    u.rebuilt += 1;
    let cost = accel.current_sah_cost();
    (accel, cost)
}

fn check_frame(d: &Description, frame: u32) -> Result<()> {
    let n = frame_count(d);
    if frame >= n {
        return Err(Error::Invalid(format!(
            "frame {frame} is past the animation's last frame, {}",
            n - 1
        )));
    }
    Ok(())
}
