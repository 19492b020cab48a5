//! The parameters of the integrators that have a `[render.NAME]` table of their own, one file
//! each; the registry (`integrator_registry.rs`) names them.

mod aov;
mod bdpt;
mod ptracer;
mod sppm;

pub use aov::{AovChannel, AovParams, AovType};
pub use bdpt::{BdptParams, StrategyImages};
pub use ptracer::PtracerParams;
pub use sppm::SppmParams;
