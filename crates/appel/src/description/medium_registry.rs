//! The two lists of participating media and phase functions. Everything that enumerates them is
//! generated from these: the description's [`super::MediumDesc`] and [`super::PhaseDesc`] (their
//! `type` names, the names in messages, each variant's checks) and, in `shading/medium`, the
//! runtime `Medium` and `Phase` enums with their per-call match (which check at compile time that
//! each runtime type's `NAME` is its name here).

/// Calls macro `$then!` with every medium as `Variant { name, desc, runtime }`:
/// - `name`: its `type` in `[media.NAME]` and Mitsuba's plugin name;
/// - `desc`: its parameters' struct in `description/medium.rs` (implementing
///   [`super::medium::MediumParams`]);
/// - `runtime`: the type in `shading/medium/` (`module::Type`) implementing `MediumPlugin`.
///
/// Adding a medium is its parameters' struct, its runtime file, one line here, its construction
/// from the description (`shading/medium/build.rs`) and the format mappings that name it.
macro_rules! for_each_medium {
    ($then:ident) => {
        $then! {
            Homogeneous { name: homogeneous, desc: HomogeneousDesc, runtime: homogeneous::Homogeneous },
            Heterogeneous { name: heterogeneous, desc: HeterogeneousDesc, runtime: heterogeneous::Heterogeneous },
        }
    };
}
pub(crate) use for_each_medium;

/// Calls macro `$then!` with every phase function as `Variant { name, desc, runtime }`, as
/// [`for_each_medium!`] does for media (`runtime` implements `PhasePlugin`).
macro_rules! for_each_phase {
    ($then:ident) => {
        $then! {
            Isotropic { name: isotropic, desc: IsotropicDesc, runtime: isotropic::Isotropic },
            Hg { name: hg, desc: HgDesc, runtime: hg::HenyeyGreenstein },
            Rayleigh { name: rayleigh, desc: RayleighDesc, runtime: rayleigh::Rayleigh },
            BlendPhase { name: blendphase, desc: BlendPhaseDesc, runtime: blendphase::BlendPhase },
        }
    };
}
pub(crate) use for_each_phase;
