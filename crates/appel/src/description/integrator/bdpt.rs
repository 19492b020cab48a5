//! `[render.bdpt]`: the debugging images of the bidirectional path tracer beyond the shared keys
//! of `[render]` (`max_depth`, `rr_depth`, `hide_emitters`).

use super::super::IntegratorTable;
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct BdptParams {
    /// One image per strategy `(s, t)` of each path depth, written beside the render as EXR
    /// channels `bdpt_dDD_sSS_tTT.R/G/B` (pbrt-v4's file names): none by default.
    #[serde(default)]
    pub strategy_images: Option<StrategyImages>,
}

/// What each strategy's image holds (pbrt-v4's `visualizestrategies` and `visualizeweights`).
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum StrategyImages {
    /// The strategy's own estimate of the light of its depth, before multiple importance
    /// sampling weighs it (each image alone converges to that light; where the strategy cannot
    /// sample a path, it is missing).
    Unweighted,
    /// The strategy's weighted contribution: the images of a depth sum to that depth's share of
    /// the render, and show which strategy carries which light.
    Weighted,
}

impl IntegratorTable for BdptParams {}
