//! Participating media against Mitsuba 3.9.1: small scenes of each medium and phase function
//! (`tests/reference/media/*.xml`), rendered by Appel from the XML and compared with Mitsuba's
//! `volpath` images of them (`scripts/media_references.py` regenerates the references and the
//! cloud's grid) by the per-pixel z-test and mean ratios of `reference/mod.rs`.

#[allow(dead_code)] // the shared helpers include the shared-data lookups this file does not use
mod reference;

use reference::{compare, reference, render_xml, save_side_by_side, Setup};
use std::path::PathBuf;

fn media(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/reference/media")
        .join(file)
}

fn check(name: &str, spp: u32, block: u32) {
    let scene = media(&format!("{name}.xml"));
    let film = render_xml(&scene, &Setup { spp, block });
    let r = reference(&media(&format!("{name}.exr")), film.width, film.height);
    let c = compare(&film, &r);
    save_side_by_side(name, &film, &r);
    eprintln!("{name}: {c:?}");
    assert!(c.passes(), "{name}: {c:?}");
}

/// A homogeneous sphere behind a null boundary, its extinction different in each channel, with
/// a forward Henyey-Greenstein phase function.
#[test]
fn homogeneous_sphere() {
    check("homogeneous_sphere", 1024, 1);
}

/// A heterogeneous cloud from a grid, scattering backward (g < 0), under a sky and a light.
#[test]
fn hg_cloud() {
    check("hg_cloud", 1024, 1);
}

/// The camera inside an unbounded fog with Rayleigh and Henyey-Greenstein blended.
#[test]
fn camera_in_fog() {
    check("camera_in_fog", 1024, 1);
}

/// A dielectric sphere holding a scattering medium: refraction between two media. The room is
/// lit through the glass by caustics that only BSDF sampling finds, rare and bright at this
/// sample count (a pixel's own variance estimate misses them), so values are compared as means
/// of 4x4 pixels.
#[test]
fn dielectric_medium() {
    check("dielectric_medium", 1024, 4);
}

/// A spot light inside a box of isotropic fog: the beam lit by single scattering, the rest of
/// the fog and the floor's pool of light through the null walls.
#[test]
fn spot_in_fog() {
    check("spot_in_fog", 1024, 1);
}

/// The comparison can fail: the cloud rendered 3% too dark is rejected.
#[test]
fn a_biased_medium_is_rejected() {
    let film = render_xml(
        &media("hg_cloud.xml"),
        &Setup {
            spp: 1024,
            block: 1,
        },
    );
    let r = reference(&media("hg_cloud.exr"), film.width, film.height);
    let brighter: Vec<[f32; 3]> = r.iter().map(|p| p.map(|c| c * 1.03)).collect();
    assert!(!compare(&film, &brighter).passes());
}
