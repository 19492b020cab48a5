//! The path tracer against closed forms: white furnaces (objects under a uniform environment,
//! and a closed room of emitting, reflecting walls), and its determinism across thread counts
//! and samplers.

use appel::description::Description;
use appel::description::{description_from_str, parse::Syntax};
use appel::render::{render, Film, RenderOptions};
use appel::scene::Scene;
use std::path::Path;

fn scene(toml: &str) -> Scene {
    let d: Description =
        description_from_str(toml, Syntax::Toml, Path::new("furnace.toml")).unwrap();
    Scene::new(&d, Path::new(".")).unwrap()
}

fn film(toml: &str) -> Film {
    render(&scene(toml), &RenderOptions::default()).unwrap().0
}

const CAMERA: &str = "[camera]\neye = [0.0, 0.0, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nwidth = 16\nheight = 16\nfov = 40\n";

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

/// Asserts every channel's image mean is `expected` within 4 standard errors (and a 1e-4 floor
/// for noiseless images).
fn assert_mean(f: &Film, expected: f64, what: &str) {
    let (m, e) = mean_and_error(f);
    for k in 0..3 {
        assert!(
            (m[k] - expected).abs() <= 4.0 * e[k] + 1e-4,
            "{what}: mean {m:?} +- {e:?}, expected {expected}"
        );
    }
}

fn furnace(material: &str, spp: u32) -> Film {
    film(&format!(
        "{CAMERA}[render]\nintegrator = \"path\"\nmax_depth = -1\nrr_depth = 100\nspp = {spp}\n\n\
         [materials.m]\n{material}\n\n[[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\n\
         radius = 1.0\nmaterial = \"m\"\n\n[[light]]\ntype = \"constant\"\nradiance = [1.0, 1.0, 1.0]\n"
    ))
}

/// Lossless surfaces in a uniform environment of radiance 1 look exactly like the environment:
/// whatever path a ray takes, it ends in the environment with its throughput unchanged.
#[test]
fn lossless_surfaces_vanish_in_a_white_furnace() {
    for (what, m) in [
        ("white diffuse", "type = \"diffuse\"\nreflectance = 1.0"),
        ("mirror", "type = \"conductor\"\nmaterial = \"none\""),
        ("glass", "type = \"dielectric\"\nint_ior = \"bk7\""),
        ("thin glass", "type = \"thindielectric\"\nint_ior = 1.5"),
    ] {
        let f = furnace(m, 64);
        for (i, c) in f.rgb.iter().enumerate() {
            // Each pixel, not only the mean: a lossless surface has no pixel darker or brighter.
            let sd = f.variance[i].max_element().sqrt();
            assert!(
                (c.x - 1.0).abs() <= 5.0 * sd + 1e-3,
                "{what}: pixel {i} is {c} +- {sd}"
            );
        }
        assert_mean(&f, 1.0, what);
    }
}

/// A convex Lambertian object sees only the environment: its radiance is its albedo.
#[test]
fn a_grey_convex_object_reflects_its_albedo() {
    let f = furnace("type = \"diffuse\"\nreflectance = 0.5", 64);
    // The image centre lies on the sphere.
    let c = f.pixel(8, 8);
    let sd = f.variance[f.index(8, 8)].x.sqrt();
    assert!((c.x - 0.5).abs() <= 5.0 * sd + 1e-3, "{c} +- {sd}");
    // The corners see the environment.
    assert!((f.pixel(0, 0).x - 1.0).abs() < 1e-6);
}

/// Surfaces without multiple scattering between microfacets, and coated ones, lose energy but
/// never gain it.
#[test]
fn rough_and_coated_surfaces_create_no_energy() {
    for (what, m) in [
        (
            "rough conductor",
            "type = \"roughconductor\"\nmaterial = \"none\"\nalpha = 0.5",
        ),
        (
            "rough glass",
            "type = \"roughdielectric\"\ndistribution = \"ggx\"\nalpha = 0.3",
        ),
        ("plastic", "type = \"plastic\"\ndiffuse_reflectance = 1.0"),
        (
            "rough plastic",
            "type = \"roughplastic\"\ndiffuse_reflectance = 1.0\nalpha = 0.3",
        ),
        (
            "coated diffuse",
            "type = \"coateddiffuse\"\nreflectance = 1.0\nalpha = 0.2",
        ),
        (
            "scattering coat",
            "type = \"coateddiffuse\"\nreflectance = 1.0\nthickness = 0.2\nalbedo = 0.9\ng = 0.5",
        ),
        (
            "coated conductor",
            "type = \"coatedconductor\"\nconductor_material = \"none\"\ninterface_alpha = 0.1\nconductor_alpha = 0.3",
        ),
    ] {
        let f = furnace(m, 64);
        let (mean, err) = mean_and_error(&f);
        for k in 0..3 {
            assert!(mean[k] <= 1.0 + 4.0 * err[k] + 1e-4, "{what}: {mean:?}");
            assert!(mean[k] > 0.5, "{what}: {mean:?} lost too much");
        }
    }
}

/// A closed room whose walls emit `Le` and reflect `rho` diffusely holds the radiance
/// `Le / (1 - rho)` everywhere (the Neumann series of the rendering equation), whether light is
/// found by emitter sampling, by BSDF sampling or by both (MIS).
#[test]
fn a_closed_emitting_room_holds_le_over_one_minus_rho() {
    let room = |integrator: &str, depth: i32| {
        film(&format!(
            "[camera]\neye = [0.0, 0.0, 0.0]\nlook_at = [0.3, 0.2, -1.0]\nwidth = 16\nheight = 16\nfov = 90\n\
             [render]\nintegrator = \"{integrator}\"\nmax_depth = {depth}\nrr_depth = 5\nspp = 64\n\n\
             [materials.wall]\ntype = \"diffuse\"\nreflectance = 0.5\n\n\
             [[shape]]\ntype = \"cube\"\nflip_normals = true\nmaterial = \"wall\"\n\
             transform = {{ scale = 2.0 }}\nemitter = {{ radiance = 0.5 }}\n"
        ))
    };
    assert_mean(&room("path", -1), 1.0, "unlimited depth");
    // Truncated series: depth d sums d terms 0.5 (1 + 0.5 + ... + 0.5^(d-1)).
    assert_mean(&room("path", 1), 0.5, "depth 1");
    assert_mean(&room("path", 3), 0.875, "depth 3");
    assert_mean(&room("direct", 5), 0.75, "direct");
}

fn spheres(sampler: &str) -> String {
    format!(
        "{CAMERA}[render]\nintegrator = \"path\"\nmax_depth = 6\nspp = 8\nsampler = \"{sampler}\"\n\
         filter = {{ type = \"gaussian\" }}\n\n\
         [materials.glass]\ntype = \"dielectric\"\n[materials.red]\ntype = \"roughplastic\"\n\
         diffuse_reflectance = [0.6, 0.1, 0.1]\n\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [-0.6, 0.0, 0.0]\nradius = 0.5\nmaterial = \"glass\"\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.6, 0.0, 0.0]\nradius = 0.5\nmaterial = \"red\"\n\
         [[shape]]\ntype = \"rectangle\"\ntransform = {{ translate = [0.0, 2.0, 0.0], rotate = {{ axis = [1.0, 0.0, 0.0], degrees = 90.0 }} }}\n\
         emitter = {{ radiance = 5.0 }}\n\
         [[light]]\ntype = \"point\"\nposition = [0.0, 1.0, 2.0]\nintensity = 3.0\n"
    )
}

#[test]
fn images_are_identical_for_any_thread_count() {
    for sampler in ["independent", "sobol"] {
        let s = scene(&spheres(sampler));
        let with = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| render(&s, &RenderOptions::default()).unwrap().0)
        };
        let one = with(1);
        let two = with(2);
        let three = with(3);
        assert!(one.rgb.iter().any(|c| c.x > 0.0));
        assert_eq!(one.rgb, two.rgb, "{sampler}");
        assert_eq!(one.variance, two.variance, "{sampler}");
        assert_eq!(one.rgb, three.rgb, "{sampler}");
    }
}

/// Both samplers estimate the same image.
#[test]
fn samplers_agree() {
    let a = film(&spheres("independent").replace("spp = 8", "spp = 64"));
    let b = film(&spheres("sobol").replace("spp = 8", "spp = 64"));
    let (ma, ea) = mean_and_error(&a);
    let (mb, _) = mean_and_error(&b);
    for k in 0..3 {
        assert!(
            (ma[k] - mb[k]).abs() <= 5.0 * ea[k] + 1e-4,
            "{ma:?} {mb:?} +- {ea:?}"
        );
    }
}
