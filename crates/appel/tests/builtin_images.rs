//! The built-in scenes under `raycast` and `whitted`, rendered small, against stored references:
//! the lecture's images must keep their look whatever the material system beneath them does.
//!
//! The references (`tests/reference/builtin/NAME-INTEGRATOR.exr`, 80x60, RGB in half floats) were
//! rendered by `appel render NAME --integrator INTEGRATOR --size 80x60 -o DIR/NAME-INTEGRATOR.exr`
//! and converted to half floats by `APPEL_REFERENCE_SOURCE=DIR cargo test --release --test
//! builtin_images -- --ignored`. Half floats round to 11 significant bits, so the bound allows
//! twice that rounding, relative, and no more.

mod common;
use appel::io::bitmap_read::read_bitmap;
use appel::scene::IntegratorKind;
use common::*;
use std::path::{Path, PathBuf};

const WIDTH: u32 = 80;
const HEIGHT: u32 = 60;
const SCENES: [&str; 4] = ["whitted", "mirror-room", "glass-block", "implicit"];
const INTEGRATORS: [(&str, IntegratorKind); 2] = [
    ("raycast", IntegratorKind::Raycast),
    ("whitted", IntegratorKind::Whitted),
];

/// The largest relative difference allowed per channel: two roundings to half precision
/// (2^-11 each).
const RELATIVE_BOUND: f32 = 1.0 / 1024.0;
/// Below half precision's normal range (6.1e-5) its steps are absolute, 2^-24.
const ABSOLUTE_BOUND: f32 = 1.0e-7;

fn reference_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/reference/builtin")
}

#[test]
fn builtin_whitted_images() {
    let mut checked = 0;
    for name in SCENES {
        // Every built-in scene has references: a new one needs its own.
        assert!(appel::scene::builtin::builtin_scene(name).is_some());
        for (integrator, kind) in INTEGRATORS {
            let mut d = with_size(builtin(name), WIDTH, HEIGHT);
            d.render.integrator = kind;
            let (film, _, _) = render_description(&d);
            let path = reference_dir().join(format!("{name}-{integrator}.exr"));
            let reference = read_bitmap(&path, true).unwrap();
            assert_eq!((reference.width, reference.height), (WIDTH, HEIGHT));
            let mut worst = (0.0f32, 0, 0);
            for y in 0..HEIGHT {
                for x in 0..WIDTH {
                    let got = film.pixel(x, y).to_array();
                    let want = reference.pixel(x, y);
                    for c in 0..3 {
                        let diff = (got[c] - want[c]).abs();
                        let allowed = (RELATIVE_BOUND * want[c].abs()).max(ABSOLUTE_BOUND);
                        if diff / allowed > worst.0 {
                            worst = (diff / allowed, x, y);
                        }
                    }
                }
            }
            assert!(
                worst.0 <= 1.0,
                "{name} under {integrator}: pixel ({}, {}) is {:.2}x the bound off the reference",
                worst.1,
                worst.2,
                worst.0
            );
            checked += 1;
        }
    }
    assert_eq!(checked, SCENES.len() * INTEGRATORS.len());
    // The list above is every built-in scene.
    assert_eq!(appel::scene::builtin::BUILTIN_SCENES.len(), SCENES.len());
}

/// Converts full-precision renders in `APPEL_REFERENCE_SOURCE` into the stored half-float
/// references (see the module's documentation).
#[test]
#[ignore = "writes the references from renders named by APPEL_REFERENCE_SOURCE"]
fn write_references() {
    let Ok(source) = std::env::var("APPEL_REFERENCE_SOURCE") else {
        panic!("APPEL_REFERENCE_SOURCE names the folder of the full-precision renders");
    };
    std::fs::create_dir_all(reference_dir()).unwrap();
    for name in SCENES {
        for (integrator, _) in INTEGRATORS {
            let file = format!("{name}-{integrator}.exr");
            let b = read_bitmap(&Path::new(&source).join(&file), true).unwrap();
            assert_eq!((b.width, b.height), (WIDTH, HEIGHT));
            use exr::prelude::*;
            let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                let p = b.pixel(x as u32, y as u32);
                (
                    f16::from_f32(p[0]),
                    f16::from_f32(p[1]),
                    f16::from_f32(p[2]),
                )
            });
            let mut image = Image::from_channels((WIDTH as usize, HEIGHT as usize), channels);
            image.layer_data.encoding = Encoding::SMALL_LOSSLESS;
            image.write().to_file(reference_dir().join(&file)).unwrap();
        }
    }
}
