//! What every acceleration structure provides, so that one registry (`registry.rs`) can list it
//! once and the renderer, the scene files, validation and the benchmark all find it there.

use super::{AccelStats, Hit, Primitives, TraversalStats};
use crate::math::Ray;
use serde::{de::DeserializeOwned, Serialize};
use std::fmt::Debug;

/// An acceleration structure: built once over a set of [`Primitives`], then asked closest-hit and
/// any-hit questions about rays. [`super::Accel`] holds one of each registered kind in an enum and
/// matches once per ray, so these calls are static and inline into the traversal.
pub trait Structure: Clone + Debug + Send + Sync + Sized {
    /// The name `render.accel`, `--accel` and the options table `[render.NAME]` use; the registry
    /// checks at compile time that it is the name of the structure's module.
    const NAME: &'static str;

    /// Build parameters: the keys of `[render.NAME]` (a key a file leaves out keeps
    /// [`Default`]'s value; an unknown key is an error at its line).
    type Options: Copy + Default + Debug + PartialEq + Serialize + DeserializeOwned;

    /// Checks options read from a scene file before anything is built: the key at fault and why.
    fn check_options(options: &Self::Options) -> Result<(), BadOption> {
        let _ = options;
        Ok(())
    }

    fn build<P: Primitives>(prims: &P, options: &Self::Options) -> Self;

    /// The closest hit with `t` in `(0, t_max)`.
    fn intersect<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> Option<Hit>;

    /// Whether there is any hit with `t` in `(0, t_max)` (a shadow ray).
    fn occluded<P: Primitives>(
        &self,
        prims: &P,
        ray: &Ray,
        t_max: f32,
        stats: &mut TraversalStats,
    ) -> bool;

    /// What the structure costs: build time, bytes, nodes.
    fn stats(&self) -> AccelStats;

    /// `Some(n)` when the structure is a single leaf of `n` primitives that are all called back
    /// (none a gathered triangle), so that each query is [`Primitives::intersect_all`] (when `n` is
    /// every primitive) counted as one ray and `n` tests: a caller may then ask it directly, past
    /// the structure's layers, and get the same hits. `None` (the default) otherwise.
    fn single_leaf(&self) -> Option<usize> {
        None
    }

    /// Whether [`Self::intersect_packet`] traces packets together rather than ray by ray.
    fn has_packets(&self) -> bool {
        false
    }

    /// Closest hits of several rays, `out[i]` for `rays[i]`: the hits of [`Self::intersect`] on
    /// each. The default goes ray by ray.
    fn intersect_packet<P: Primitives>(
        &self,
        prims: &P,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<Hit>],
        stats: &mut TraversalStats,
    ) {
        for (ray, o) in rays.iter().zip(out.iter_mut()) {
            *o = self.intersect(prims, ray, t_max, stats);
        }
    }

    /// Fits the structure to `prims` after they moved (same count, same ids) and returns its SAH
    /// cost afterwards; `None` (the default) for a structure whose cells or planes the build fixed,
    /// which must be built again.
    fn refit<P: Primitives>(&mut self, prims: &P) -> Option<f64> {
        let _ = prims;
        None
    }

    /// The SAH cost of a refittable structure as it stands.
    fn current_sah_cost(&self) -> Option<f64> {
        None
    }
}

/// An option value that makes no sense, found by [`Structure::check_options`].
#[derive(Clone, Debug, PartialEq)]
pub struct BadOption {
    /// The key in `[render.NAME]`.
    pub key: &'static str,
    pub message: String,
}

impl BadOption {
    pub fn new(key: &'static str, message: impl Into<String>) -> Self {
        Self {
            key,
            message: message.into(),
        }
    }

    /// `Err` unless `lo <= value <= hi`.
    pub fn check_range<T: PartialOrd + std::fmt::Display>(
        key: &'static str,
        value: T,
        lo: T,
        hi: T,
    ) -> Result<(), BadOption> {
        if lo <= value && value <= hi {
            Ok(())
        } else {
            Err(Self::new(
                key,
                format!("`{key}` must be between {lo} and {hi}, got {value}"),
            ))
        }
    }

    /// `Err` unless `value` is finite and not negative.
    pub fn check_non_negative(key: &'static str, value: f32) -> Result<(), BadOption> {
        if value.is_finite() && value >= 0.0 {
            Ok(())
        } else {
            Err(Self::new(
                key,
                format!("`{key}` must be a finite number, not negative, got {value}"),
            ))
        }
    }

    /// `Err` unless `value` is finite and positive.
    pub fn check_positive(key: &'static str, value: f32) -> Result<(), BadOption> {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(Self::new(
                key,
                format!("`{key}` must be a positive number, got {value}"),
            ))
        }
    }
}

/// The options of a structure that has none: `[render.NAME]` may be given, empty.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct NoOptions {}

/// Byte-wise string equality usable in constants: the registry's check that each structure's
/// [`Structure::NAME`] is its module's (and so its `[render.NAME]` table's) name.
pub const fn same_name(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    let mut i = 0;
    while i < a.len() {
        if a[i] != b[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// The query methods of a [`Structure`] impl whose type answers them with inherent methods of the
/// same names (each structure keeps its traversal in its own folder); written once here so that
/// every impl forwards them alike, inlined so the per-ray match in [`super::Accel`] stays static.
macro_rules! forward_queries {
    ($ty:ty) => {
        #[inline]
        fn intersect<P: $crate::accel::Primitives>(
            &self,
            prims: &P,
            ray: &$crate::math::Ray,
            t_max: f32,
            stats: &mut $crate::accel::TraversalStats,
        ) -> Option<$crate::accel::Hit> {
            <$ty>::intersect(self, prims, ray, t_max, stats)
        }

        #[inline]
        fn occluded<P: $crate::accel::Primitives>(
            &self,
            prims: &P,
            ray: &$crate::math::Ray,
            t_max: f32,
            stats: &mut $crate::accel::TraversalStats,
        ) -> bool {
            <$ty>::occluded(self, prims, ray, t_max, stats)
        }

        fn stats(&self) -> $crate::accel::AccelStats {
            <$ty>::stats(self)
        }
    };
}
pub(crate) use forward_queries;
