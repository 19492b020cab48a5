//! Appel against Embree like for like: each of Appel's ray-triangle tests measured beside the
//! Embree mode whose test is of the same kind, on the same rays, in the same process and thread
//! pools. Appel's watertight test (Woop, Benthin & Wald 2013) goes with Embree's robust mode
//! (`RTC_SCENE_FLAG_ROBUST`, watertight too); Appel's Moller-Trumbore test with Embree's default
//! (Moller-Trumbore on precomputed edges, not watertight).

use super::{
    bench_accel, bench_embree, BenchOptions, BenchRays, BenchResult, BenchTarget,
    EmbreeBenchOptions, PeerRatios,
};
use appel::accel::AccelKind;
use appel::geometry::TriangleTest;
use embree_peer::BuildQuality;

/// One triangle test's figures: Appel's structures (each with its ratios to Embree when Embree was
/// measured), then Embree's row in the paired mode and a line saying which Embree it was.
pub struct Pairing {
    pub test: TriangleTest,
    pub rows: Vec<BenchResult>,
    pub embree: Option<(BenchResult, String)>,
}

/// Whether Embree's robust mode is the one paired with `test`.
pub fn embree_robust_for(test: TriangleTest) -> bool {
    test == TriangleTest::Watertight
}

/// Measures `kinds` with the target's meshes tested by `test` (restored afterwards), and with
/// `embree` (a build quality) Embree in the mode paired with `test`, on `rays`, which stay the
/// same for every test so that the two pairings' figures compare too.
pub fn bench_pairings(
    target: &mut BenchTarget,
    rays: &BenchRays,
    kinds: &[AccelKind],
    test: TriangleTest,
    o: &BenchOptions,
    embree: Option<BuildQuality>,
) -> Result<Pairing, String> {
    let own = std::mem::replace(&mut target.geometry.triangle_test, test);
    let measured = pairing(target, rays, kinds, test, o, embree);
    target.geometry.triangle_test = own;
    measured
}

fn pairing(
    target: &BenchTarget,
    rays: &BenchRays,
    kinds: &[AccelKind],
    test: TriangleTest,
    o: &BenchOptions,
    embree: Option<BuildQuality>,
) -> Result<Pairing, String> {
    let mut rows: Vec<BenchResult> = kinds
        .iter()
        .map(|&k| bench_accel(target, rays, k, o))
        .collect();
    let embree = match embree {
        Some(quality) => {
            let e = EmbreeBenchOptions {
                quality,
                robust: embree_robust_for(test),
            };
            let (peer, about) = bench_embree(target, rays, o, &e)?;
            for r in &mut rows {
                r.vs_embree = Some(PeerRatios::of(r, &peer));
            }
            Some((peer, about))
        }
        None => None,
    };
    Ok(Pairing { test, rows, embree })
}
