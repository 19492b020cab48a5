//! Reporting progress while a scene loads and builds, and stopping when asked: large scenes spend
//! most of their time here, before the first pixel.

use crate::error::{Error, Result};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// One finished step: a mesh file read or an acceleration structure built.
#[derive(Clone, Copy, Debug)]
pub struct LoadStep<'a> {
    pub done: u64,
    pub total: u64,
    /// What was just done, such as `read oak-wood.ply`, or what is starting, such as
    /// `building the top-level structure`.
    pub what: &'a str,
}

/// How to build a scene, beyond what its description says.
#[derive(Clone, Copy, Default)]
pub struct SceneOptions<'a> {
    /// Called after each step, from any thread.
    pub progress: Option<&'a (dyn Fn(&LoadStep) + Sync)>,
    /// When set, building stops at the next step and returns [`Error::Cancelled`].
    pub cancel: Option<&'a AtomicBool>,
    /// Leave the scene's top-level structure unbuilt (brute force, which costs nothing to build):
    /// for tools that build their own over the geometry, such as `appel bench`. The declared
    /// meshes' structures are still built, of the scene's kind.
    pub skip_top_level: bool,
    /// Leave every structure unbuilt (brute force), the declared meshes' too: for an animation,
    /// which refits the previous frame's structures to the new geometry instead.
    pub skip_structures: bool,
}

/// Counts steps and forwards them.
pub(super) struct Steps<'a> {
    options: SceneOptions<'a>,
    done: AtomicU64,
    total: u64,
}

impl<'a> Steps<'a> {
    pub fn new(options: SceneOptions<'a>, total: u64) -> Self {
        Self {
            options,
            done: AtomicU64::new(0),
            total,
        }
    }

    /// Records a finished step; fails if the build was cancelled.
    pub fn step(&self, what: &str) -> Result<()> {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(p) = self.options.progress {
            p(&LoadStep {
                done,
                total: self.total,
                what,
            });
        }
        self.check()
    }

    /// Announces a long step before it starts (the count stays), so a progress display does not
    /// show the previous step while this one runs.
    pub fn begin(&self, what: &str) {
        if let Some(p) = self.options.progress {
            p(&LoadStep {
                done: self.done.load(Ordering::Relaxed),
                total: self.total,
                what,
            });
        }
    }

    pub fn check(&self) -> Result<()> {
        match self.options.cancel {
            Some(c) if c.load(Ordering::Relaxed) => Err(Error::Cancelled),
            _ => Ok(()),
        }
    }
}
