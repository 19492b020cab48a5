//! The volumetric path tracer against closed forms and against itself: Beer-Lambert
//! transmittance through an absorbing slab, a white furnace of scattering media, a heterogeneous
//! medium whose grid is constant against the homogeneous medium of the same density, local
//! majorants against one global majorant, and the errors of media that make no sense.

use appel::description::{description_from_str, parse::Syntax, Description};
use appel::render::{render, Film, RenderOptions};
use appel::scene::Scene;
use appel::shading::medium::Medium;
use std::path::Path;

#[path = "common/normal.rs"]
mod normal;
use normal::erfc;

fn description(toml: &str) -> Description {
    description_from_str(toml, Syntax::Toml, Path::new("media.toml"))
        .unwrap_or_else(|e| panic!("{e}"))
}

fn film_in(toml: &str, dir: &Path) -> Film {
    let scene = Scene::new(&description(toml), dir).unwrap_or_else(|e| panic!("{e}"));
    render(&scene, &RenderOptions::default()).unwrap().0
}

fn film(toml: &str) -> Film {
    film_in(toml, Path::new("."))
}

/// The mean over the image and its standard error (from the per-pixel variances).
fn mean_and_error(f: &Film) -> ([f64; 3], [f64; 3]) {
    let n = f.rgb.len() as f64;
    let mut m = [0.0; 3];
    let mut v = [0.0; 3];
    for (c, var) in f.rgb.iter().zip(&f.variance) {
        for k in 0..3 {
            m[k] += c[k] as f64 / n;
            v[k] += var[k] as f64 / (n * n);
        }
    }
    (m, v.map(f64::sqrt))
}

/// Every channel's image mean is `expected` within 4 standard errors (1e-4 for noiseless ones).
fn assert_mean(f: &Film, expected: [f64; 3], what: &str) {
    let (m, e) = mean_and_error(f);
    for k in 0..3 {
        assert!(
            (m[k] - expected[k]).abs() <= 4.0 * e[k] + 1e-4,
            "{what}: mean {m:?} +- {e:?}, expected {expected:?}"
        );
    }
}

/// An orthographic view down -z: every camera ray crosses the slab `0 < z < 1` at right angles
/// on its way to an emitter of radiance 1 at z = -1.
fn slab(sigma_t: &str, spp: u32) -> String {
    format!(
        "[camera]\ntype = \"orthographic\"\neye = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n\
         half_width = 0.5\nwidth = 8\nheight = 8\n\n\
         [render]\nintegrator = \"volpath\"\nmax_depth = -1\nspp = {spp}\n\n\
         [materials.boundary]\ntype = \"null\"\n\n\
         [media.ink]\ntype = \"homogeneous\"\nsigma_t = {sigma_t}\nalbedo = 0.0\n\n\
         [[shape]]\ntype = \"cube\"\nmaterial = \"boundary\"\ninterior = \"ink\"\n\
         transform = {{ scale = [2.0, 2.0, 0.5], translate = [0.0, 0.0, 0.5] }}\n\n\
         [[shape]]\ntype = \"rectangle\"\ntransform = {{ scale = 4.0, translate = [0.0, 0.0, -1.0] }}\n\
         emitter = {{ radiance = 1.0 }}\n"
    )
}

/// Through an absorbing slab of thickness 1 the light is `exp(-sigma_t)` per channel, the
/// channels' extinctions different (one channel samples each path's distances and the others
/// are weighted by their transmittance over its density).
#[test]
fn beer_lambert_through_a_slab() {
    let sigma = [0.5f64, 1.0, 2.0];
    let f = film(&slab("[0.5, 1.0, 2.0]", 256));
    assert_mean(&f, sigma.map(|s| (-s).exp()), "absorbing slab");
    // Without the medium the emitter is seen as it is: the null boundary costs nothing.
    let clear = film(&slab("0.0", 4));
    assert_mean(&clear, [1.0; 3], "clear slab");
}

/// A sphere of medium whose albedo is 1, under a uniform environment: nothing is absorbed, so
/// every path ends in the environment with its weight's expectation unchanged, and the sphere
/// looks exactly like the sky (a white furnace; its extinction differs between channels and its
/// phase function is anisotropic, neither of which may change that).
#[test]
fn a_white_furnace_of_scattering_media() {
    for (medium, what) in [
        (
            "type = \"homogeneous\"\nsigma_t = [2.5, 3.0, 4.0]\nalbedo = 1.0\n\
             phase = { type = \"hg\", g = 0.6 }",
            "homogeneous",
        ),
        (
            "type = \"homogeneous\"\nsigma_a = 0.0\nsigma_s = 1.5\n\
             phase = { type = \"blendphase\", weight = 0.4, phases = [{ type = \"rayleigh\" }, { type = \"hg\", g = -0.7 }] }",
            "sigma_s with a blended phase",
        ),
    ] {
        let f = film(&format!(
            "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nwidth = 12\nheight = 12\n\
             fov = 35\n\n[render]\nintegrator = \"volpath\"\nmax_depth = -1\nspp = 64\n\n\
             [materials.boundary]\ntype = \"null\"\n\n[media.cloud]\n{medium}\n\n\
             [[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\n\
             material = \"boundary\"\ninterior = \"cloud\"\n\n\
             [[light]]\ntype = \"constant\"\nradiance = [0.5, 1.0, 2.0]\n"
        ));
        assert_mean(&f, [0.5, 1.0, 2.0], what);
    }
}

/// The Fresnel reflectance of unpolarised light meeting a dielectric of relative index `eta`
/// from outside at `cos_i`.
fn fresnel(cos_i: f64, eta: f64) -> f64 {
    let sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    let cos_t = (1.0 - sin_t2).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// Shadow rays cross a thin dielectric sheet as Mitsuba's `volpath` does (its transmission is a
/// null lobe): a diffuse floor under a window pane, lit by a directional light at `cos θ = 0.6`
/// and seen straight down through the pane, direct light only. Each crossing passes
/// `T(cos) = (1 - R) / (1 + R)` of the light (the sheet's inter-reflections summed), so the
/// floor's radiance is `T(1) · ρ/π · E cos θ · T(0.6)`.
#[test]
fn shadow_rays_cross_a_thin_dielectric_sheet() {
    let f = film(
        "[camera]\ntype = \"orthographic\"\neye = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n\
         half_width = 0.5\nwidth = 8\nheight = 8\n\n\
         [render]\nintegrator = \"volpath\"\nmax_depth = 2\nspp = 256\n\n\
         [materials.pane]\ntype = \"thindielectric\"\nint_ior = 1.5\next_ior = 1.0\n\n\
         [materials.floor]\ntype = \"diffuse\"\nreflectance = 0.5\n\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"pane\"\n\
         transform = { scale = 10.0, translate = [0.0, 0.0, 1.0] }\n\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"floor\"\ntransform = { scale = 10.0 }\n\n\
         [[light]]\ntype = \"directional\"\ndirection = [0.8, 0.0, -0.6]\nintensity = 2.0\n",
    );
    let t = |cos: f64| {
        let r = fresnel(cos, 1.5);
        (1.0 - r) / (1.0 + r)
    };
    let expected = t(1.0) * 0.5 / std::f64::consts::PI * 2.0 * 0.6 * t(0.6);
    assert_mean(&f, [expected; 3], "floor under a pane");
}

/// Mitsuba's binary grid volume of `values` (x fastest), `channels` per cell.
fn vol_bytes(res: [i32; 3], channels: i32, values: &[f32]) -> Vec<u8> {
    let mut b = b"VOL\x03".to_vec();
    for v in [1, res[0], res[1], res[2], channels] {
        b.extend(v.to_le_bytes());
    }
    for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0].iter().chain(values) {
        b.extend(v.to_le_bytes());
    }
    b
}

fn cube_scene(medium: &str, seed: u32) -> String {
    format!(
        "[camera]\neye = [0.5, 0.8, 3.0]\nlook_at = [0.5, 0.5, 0.5]\nwidth = 10\nheight = 10\nfov = 35\n\n\
         [render]\nintegrator = \"volpath\"\nmax_depth = -1\nspp = 256\nseed = {seed}\n\n\
         [materials.boundary]\ntype = \"null\"\n\n[materials.floor]\ntype = \"diffuse\"\nreflectance = 0.5\n\n\
         [media.m]\n{medium}\n\n\
         [[shape]]\ntype = \"cube\"\nmaterial = \"boundary\"\ninterior = \"m\"\n\
         transform = {{ scale = 0.5, translate = [0.5, 0.5, 0.5] }}\n\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"floor\"\n\
         transform = {{ scale = 3.0, rotate = {{ axis = [1.0, 0.0, 0.0], degrees = -90.0 }}, translate = [0.5, -0.01, 0.5] }}\n\n\
         [[light]]\ntype = \"constant\"\nradiance = [0.3, 0.3, 0.3]\n\n\
         [[light]]\ntype = \"point\"\nposition = [2.0, 3.0, 2.0]\nintensity = 8.0\n"
    )
}

/// A heterogeneous medium over a grid whose channels are constant but different (1, 0.5, 0.25:
/// its one majorant, 1, makes null collisions in two channels) renders as the homogeneous
/// medium of the same extinction, which has none: delta tracking and ratio tracking with null
/// collisions agree with the exact free flights and transmittances, pixel by pixel (a
/// two-sample z-test, Šidák-corrected over the pixels).
#[test]
fn a_constant_grid_renders_as_the_homogeneous_medium() {
    let dir = tempfile::tempdir().unwrap();
    let values: Vec<f32> = (0..4 * 4 * 4).flat_map(|_| [1.0f32, 0.5, 0.25]).collect();
    std::fs::write(dir.path().join("rgb.vol"), vol_bytes([4, 4, 4], 3, &values)).unwrap();
    let grid = film_in(
        &cube_scene(
            "type = \"heterogeneous\"\nscale = 3.0\nalbedo = 0.8\nphase = { type = \"hg\", g = 0.4 }\n\
             sigma_t = { type = \"gridvolume\", file = \"rgb.vol\" }",
            1,
        ),
        dir.path(),
    );
    let homogeneous = film(&cube_scene(
        "type = \"homogeneous\"\nsigma_t = [3.0, 1.5, 0.75]\nalbedo = 0.8\nphase = { type = \"hg\", g = 0.4 }",
        2,
    ));
    assert_same_image(&grid, &homogeneous, "constant grid against homogeneous");
    let m2 = mean_and_error(&homogeneous).0;
    // And the medium is there: the cube is darker than the same scene without it.
    let empty = film(&cube_scene("type = \"homogeneous\"\nsigma_t = 0.0", 3));
    assert!(mean_and_error(&empty).0[2] > m2[2] * 1.05);
}

/// A grid whose one dense block fills a corner and is empty elsewhere renders the same with its
/// local majorants as with one global majorant (Mitsuba's tracking), pixel by pixel and in the
/// mean: the majorant grid changes the cost of tracking, not its expectation.
#[test]
fn local_majorants_render_as_the_global_majorant() {
    let dir = tempfile::tempdir().unwrap();
    let n = 16;
    let values: Vec<f32> = (0..n * n * n)
        .map(|i| {
            let (x, y, z) = (i % n, i / n % n, i / (n * n));
            if x < 5 && y < 6 && z >= 11 {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    std::fs::write(
        dir.path().join("corner.vol"),
        vol_bytes([16, 16, 16], 1, &values),
    )
    .unwrap();
    let medium = "type = \"heterogeneous\"\nscale = 12.0\nalbedo = 0.8\nphase = { type = \"hg\", g = 0.3 }\n\
                  sigma_t = { type = \"gridvolume\", file = \"corner.vol\" }";
    let render_with = |global: bool, seed: u32| {
        let mut scene = Scene::new(&description(&cube_scene(medium, seed)), dir.path())
            .unwrap_or_else(|e| panic!("{e}"));
        let Medium::Heterogeneous(m) = &mut scene.media.media[0] else {
            panic!("a heterogeneous medium");
        };
        assert_eq!(m.majorants.resolution, [4, 4, 4]);
        assert!(m.majorants.max.iter().filter(|&&v| v == 0.0).count() > 32);
        if global {
            m.set_majorant_resolution([1, 1, 1]);
        }
        render(&scene, &RenderOptions::default()).unwrap().0
    };
    let local = render_with(false, 1);
    let global = render_with(true, 2);
    assert_same_image(&local, &global, "local against global majorants");
    // And the medium is there: the cube is darker than the same scene without it.
    let empty = film(&cube_scene("type = \"homogeneous\"\nsigma_t = 0.0", 3));
    let (m_local, e_local) = mean_and_error(&local);
    let m_empty = mean_and_error(&empty).0;
    assert!(
        m_empty[1] - m_local[1] > 6.0 * e_local[1],
        "{m_empty:?} vs {m_local:?}"
    );
}

/// The pixels of two renders agree by a two-sample z-test (Šidák-corrected over the pixels and
/// channels for a 1% overall false-failure rate), and so do their image means.
fn assert_same_image(a: &Film, b: &Film, what: &str) {
    let tests = (3 * a.rgb.len()) as f64;
    let alpha = 1.0 - 0.99f64.powf(1.0 / tests);
    let z_max = inverse_normal_tail(alpha / 2.0);
    for (i, (x, y)) in a.rgb.iter().zip(&b.rgb).enumerate() {
        for k in 0..3 {
            let var = (a.variance[i][k] + b.variance[i][k]) as f64;
            let z = (x[k] - y[k]) as f64 / var.max(1e-10).sqrt();
            assert!(
                z.abs() < z_max,
                "{what}: pixel {i} channel {k}: {x} vs {y} (z = {z})"
            );
        }
    }
    let (m1, e1) = mean_and_error(a);
    let (m2, e2) = mean_and_error(b);
    for k in 0..3 {
        let e = (e1[k] * e1[k] + e2[k] * e2[k]).sqrt();
        assert!(
            (m1[k] - m2[k]).abs() < 4.0 * e,
            "{what}: {m1:?} vs {m2:?} +- {e}"
        );
    }
}

/// A pbrt-v4 scene: a sphere of medium `m` (defined by `medium`, after `WorldBegin`) inside the
/// unit cube, over a diffuse floor, under a grey sky and a point light, rendered by `volpath`.
fn pbrt_film(medium: &str, seed: u32) -> Film {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("media.pbrt");
    std::fs::write(
        &path,
        format!(
            "LookAt 0.5 0.8 3  0.5 0.5 0.5  0 1 0\nCamera \"perspective\" \"float fov\" 35\n\
             Film \"rgb\" \"integer xresolution\" 10 \"integer yresolution\" 10\n\
             Sampler \"independent\" \"integer pixelsamples\" 256 \"integer seed\" {seed}\n\
             Integrator \"volpath\" \"integer maxdepth\" 100\nWorldBegin\n\
             LightSource \"infinite\" \"rgb L\" [0.3 0.3 0.3]\n\
             LightSource \"point\" \"point3 from\" [2 3 2] \"rgb I\" [8 8 8]\n\
             {medium}\n\
             AttributeBegin\nMaterial \"interface\"\nMediumInterface \"m\" \"\"\n\
             Translate 0.5 0.5 0.5\nShape \"sphere\" \"float radius\" 0.45\nAttributeEnd\n\
             Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n\
             Shape \"trianglemesh\" \"integer indices\" [0 1 2 0 2 3]\n\
             \"point3 P\" [-3 -0.01 -3  3 -0.01 -3  3 -0.01 3  -3 -0.01 3]\n"
        ),
    )
    .unwrap();
    let loaded = appel::format::load(&path, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let scene = Scene::new(&loaded.description, dir.path()).unwrap_or_else(|e| panic!("{e}"));
    render(&scene, &RenderOptions::default()).unwrap().0
}

/// pbrt-v4's `rgbgrid` whose cells all hold the same absorption and scattering (different per
/// channel, so the one majorant makes null collisions in two of them) renders as pbrt's
/// `homogeneous` medium of those coefficients, which has none: the absorption and scattering
/// grids, their sum the extinction, tracked with null collisions, agree pixel by pixel with
/// exact free flights.
#[test]
fn a_constant_rgb_grid_renders_as_the_homogeneous_medium() {
    let cells = |rgb: &str| [rgb; 8].join("  ");
    let grid = pbrt_film(
        &format!(
            "MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"integer nx\" 2 \"integer ny\" 2 \
             \"integer nz\" 2 \"point3 p0\" [0 0 0] \"point3 p1\" [1 1 1] \"float scale\" 2 \
             \"float g\" 0.4 \"rgb sigma_a\" [{}] \"rgb sigma_s\" [{}]",
            cells("0.5 0.2 0.1"),
            cells("1 0.5 0.3")
        ),
        1,
    );
    let homogeneous = pbrt_film(
        "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"float scale\" 2 \"float g\" 0.4 \
         \"rgb sigma_a\" [0.5 0.2 0.1] \"rgb sigma_s\" [1 0.5 0.3]",
        2,
    );
    assert_same_image(&grid, &homogeneous, "rgbgrid against homogeneous");
    // And the medium is there: the sphere is darker than the same scene without it.
    let empty = pbrt_film(
        "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"float scale\" 0",
        3,
    );
    assert!(mean_and_error(&empty).0[0] > mean_and_error(&homogeneous).0[0] * 1.05);
}

/// The z beyond which the standard normal's upper tail holds `p` (bisection on erfc).
fn inverse_normal_tail(p: f64) -> f64 {
    let tail = |z: f64| 0.5 * erfc(z / std::f64::consts::SQRT_2);
    let (mut lo, mut hi) = (0.0f64, 40.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if tail(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

fn error_of(toml: &str) -> String {
    match description_from_str(toml, Syntax::Toml, Path::new("media.toml")) {
        Ok(_) => panic!("accepted:\n{toml}"),
        Err(e) => e.to_string(),
    }
}

/// Media that make no sense are errors at their line.
#[test]
fn bad_media_are_errors_at_their_line() {
    let base = "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\n";
    let e = error_of(&format!(
        "{base}[media.fog]\ntype = \"homogeneous\"\nalbedo = 1.5\n"
    ));
    assert!(e.contains("media.toml:6") && e.contains("albedo"), "{e}");
    let e = error_of(&format!(
        "{base}[media.fog]\ntype = \"homogeneous\"\nphase = {{ type = \"hg\", g = 1.0 }}\n"
    ));
    assert!(e.contains("media.toml:6") && e.contains("-1 and 1"), "{e}");
    let e = error_of(&format!("{base}[media.fog]\ntype = \"smoke\"\n"));
    assert!(
        e.contains("media.toml:5") && e.contains("homogeneous"),
        "{e}"
    );
    let e = error_of(&format!(
        "{base}[media.fog]\ntype = \"homogeneous\"\nsigma_a = 1.0\n"
    ));
    assert!(e.contains("sigma_a") && e.contains("together"), "{e}");
    let e = error_of(&format!(
        "{base}[media.fog]\ntype = \"heterogeneous\"\nsigma_a = 1.0\nsigma_s = 2.0\nalbedo = 0.5\n"
    ));
    assert!(
        e.contains("media.toml:8") && e.contains("not `albedo` with `sigma_a`"),
        "{e}"
    );
    let e = error_of(&format!(
        "{base}medium = \"mist\"\n[media.fog]\ntype = \"homogeneous\"\n"
    ));
    assert!(
        e.contains("media.toml:4") && e.contains("unknown medium `mist`"),
        "{e}"
    );
    let e = error_of(&format!(
        "{base}[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\ninterior = \"mist\"\n"
    ));
    assert!(
        e.contains("media.toml:8") && e.contains("unknown medium"),
        "{e}"
    );
}
