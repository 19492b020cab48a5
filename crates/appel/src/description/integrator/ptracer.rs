//! `[render.ptracer]`: the parameter of Mitsuba 3's particle tracer beyond the shared keys of
//! `[render]` (`max_depth`, `rr_depth`, `hide_emitters`).

use super::super::IntegratorTable;
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct PtracerParams {
    /// Batches of `W x H` light paths (samples per pixel) traced in one parallel pass; 0 (the
    /// default): all of them. Mitsuba's `samples_per_pass`: it bounds the memory of a pass's
    /// splats and the granularity of a time limit, never the image.
    #[serde(default)]
    pub samples_per_pass: u32,
}

impl IntegratorTable for PtracerParams {}
