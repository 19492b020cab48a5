//! `[render.bdpt]`: the bidirectional path tracer's regularization and debugging images, beyond
//! the shared keys of `[render]` (`max_depth`, `rr_depth`, `hide_emitters`).

use super::super::IntegratorTable;
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, Default, Deserialize, Serialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct BdptParams {
    /// One image per strategy `(s, t)` of each path depth, written beside the render as EXR
    /// channels `bdpt_dDD_sSS_tTT.R/G/B` (pbrt-v4's file names): none by default.
    #[serde(default)]
    pub strategy_images: Option<StrategyImages>,
    /// pbrt-v4's `regularize`: past a subpath's first bounce off a lobe that is not a delta,
    /// every BSDF is roughened (smooth ones to GGX alpha 0.1, alphas below 0.3 doubled, see
    /// `SurfaceBsdf::regularized`), so that paths through specular surfaces on both sides of a
    /// diffuse bounce (a caustic seen through glass, from a point light) can be joined: biased,
    /// the image blurs such light rather than missing it. Off by default.
    #[serde(default)]
    pub regularize: bool,
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
