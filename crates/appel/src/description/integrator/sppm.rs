//! `[render.sppm]`: the parameters of stochastic progressive photon mapping (pbrt-v4's `sppm`)
//! beyond the shared keys of `[render]` (`max_depth`; `spp` counts its iterations).

use super::super::IntegratorTable;
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SppmParams {
    /// The initial radius of every pixel's photon gathering disc, in scene units (pbrt's
    /// `radius`, 1 by default). It shrinks with each iteration that finds photons, so it sets
    /// how blurred the first iterations are, not the limit.
    #[serde(default = "default_radius")]
    pub radius: f32,
    /// Photons traced from the lights in each iteration; 0 (the default): one per pixel, as
    /// pbrt's `photonsperiteration` -1.
    #[serde(default)]
    pub photons_per_iteration: u32,
}

fn default_radius() -> f32 {
    1.0
}

impl Default for SppmParams {
    fn default() -> Self {
        SppmParams {
            radius: default_radius(),
            photons_per_iteration: 0,
        }
    }
}

impl IntegratorTable for SppmParams {
    fn check(&self) -> Result<(), (&'static str, String)> {
        if !(self.radius > 0.0 && self.radius.is_finite()) {
            return Err((
                "radius",
                format!(
                    "must be a positive number of scene units, got {}",
                    self.radius
                ),
            ));
        }
        Ok(())
    }
}
