//! The particle tracer (`ptracer`) and the bidirectional path tracer (`bdpt`): the images they
//! estimate are the path tracer's (z-tests of one against the other, pixel by pixel: through a
//! pinhole and a thin lens, in the Cornell box, and in a caustic under a glass ball), and they
//! are bit-identical for any number of threads (and in a window of the image).

use appel::description::{description_from_str, parse::Syntax};
use appel::render::{render, Film, RenderOptions, Window};
use appel::scene::Scene;
use std::path::Path;

#[path = "common/normal.rs"]
mod normal;
use normal::erfc;

fn scene(toml: &str) -> Scene {
    let d = description_from_str(toml, Syntax::Toml, Path::new("light.toml")).unwrap();
    Scene::new(&d, Path::new(".")).unwrap()
}

/// A diffuse floor and back wall, a rough plastic ball and a rough metal ball, lit by an area
/// light facing down, a point light and a spot: every kind of light ray `ptracer` starts, seen
/// directly and after bounces. Nothing is a mirror: a light tracer cannot show what the camera
/// sees through a delta reflection (no connection reaches the camera from a mirror).
fn room(integrator: &str, spp: u32, extra_camera: &str, filter: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 1.2, 4.0]\nlook_at = [0.0, 0.6, 0.0]\nwidth = 32\nheight = 24\n\
         fov = 45\n{extra_camera}\n\
         [render]\nintegrator = \"{integrator}\"\nmax_depth = 5\nspp = {spp}\n\
         filter = {{ type = \"{filter}\" }}\n\n\
         [materials.white]\ntype = \"diffuse\"\nreflectance = [0.7, 0.7, 0.7]\n\
         [materials.red]\ntype = \"roughplastic\"\ndiffuse_reflectance = [0.6, 0.1, 0.1]\n\
         [materials.metal]\ntype = \"roughconductor\"\nalpha = 0.3\n\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"white\"\n\
         transform = {{ scale = [3.0, 3.0, 1.0], rotate = {{ axis = [1.0, 0.0, 0.0], degrees = -90.0 }} }}\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"white\"\n\
         transform = {{ scale = [3.0, 2.0, 1.0], translate = [0.0, 2.0, -1.5] }}\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [-0.5, 0.4, 0.0]\nradius = 0.4\nmaterial = \"red\"\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.6, 0.3, 0.4]\nradius = 0.3\nmaterial = \"metal\"\n\
         [[shape]]\ntype = \"rectangle\"\n\
         transform = {{ scale = [0.4, 0.4, 1.0], rotate = {{ axis = [1.0, 0.0, 0.0], degrees = 90.0 }}, translate = [0.0, 1.8, 0.2] }}\n\
         emitter = {{ radiance = [6.0, 5.0, 4.0] }}\n\
         [[light]]\ntype = \"point\"\nposition = [1.2, 1.0, 1.0]\nintensity = 1.5\n\
         [[light]]\ntype = \"spot\"\nposition = [-1.0, 1.6, 1.0]\nlook_at = [-1.0, 0.0, 0.6]\n\
         intensity = 4.0\ncutoff_angle = 25.0\n"
    )
}

const LENS: &str = "aperture_radius = 0.15\nfocus_distance = 3.5\n";

fn film(toml: &str) -> Film {
    render(&scene(toml), &RenderOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// Each pixel's variance as the largest of its 3x3 neighbourhood's: where a pixel's estimate
/// rests on a few heavy-tailed samples (the edge of an emitter seen by a handful of camera rays),
/// its own spread understates its variance (as in `reference/mod.rs`, after Mitsuba's tests).
fn neighbourhood_variance(f: &Film) -> Vec<[f64; 3]> {
    let (w, h) = (f.width as i64, f.height as i64);
    (0..w * h)
        .map(|k| {
            let (x, y) = (k % w, k / w);
            let mut v = [0.0f64; 3];
            for j in (y - 1).max(0)..=(y + 1).min(h - 1) {
                for i in (x - 1).max(0)..=(x + 1).min(w - 1) {
                    let o = f.variance[(j * w + i) as usize];
                    for c in 0..3 {
                        v[c] = v[c].max(o[c] as f64);
                    }
                }
            }
            v
        })
        .collect()
}

/// The smallest two-sided p-value of the per-pixel, per-channel z-tests of `a` against `b`
/// (two independent estimates, each with its own variance, see [`neighbourhood_variance`],
/// floored at `1e-6`), against the Šidák threshold for a 1% chance of a false failure; and each
/// channel's ratio of the image means with its standard error.
fn agreement(a: &Film, b: &Film) -> (f64, f64, [(f64, f64); 3]) {
    let n = a.rgb.len();
    let (var_a, var_b) = (neighbourhood_variance(a), neighbourhood_variance(b));
    let alpha = 1.0 - 0.99f64.powf(1.0 / (3 * n) as f64);
    let mut min_p = 1.0f64;
    let mut sums = [[0.0f64; 4]; 3];
    for k in 0..n {
        for c in 0..3 {
            let (x, y) = (a.rgb[k][c] as f64, b.rgb[k][c] as f64);
            let (vx, vy) = (var_a[k][c], var_b[k][c]);
            let z = (x - y) / (vx + vy).max(1e-6).sqrt();
            let p = erfc(z.abs() / std::f64::consts::SQRT_2);
            if p < min_p {
                min_p = p;
                if std::env::var_os("APPEL_TEST_VERBOSE").is_some() {
                    eprintln!(
                        "pixel {k} channel {c}: {x} +- {} vs {y} +- {}",
                        vx.sqrt(),
                        vy.sqrt()
                    );
                }
            }
            sums[c][0] += x;
            sums[c][1] += y;
            sums[c][2] += a.variance[k][c] as f64;
            sums[c][3] += b.variance[k][c] as f64;
        }
    }
    let ratios = sums.map(|[x, y, vx, vy]| {
        let r = x / y;
        (r, r * ((vx / (x * x)) + (vy / (y * y))).sqrt())
    });
    (min_p, alpha, ratios)
}

fn assert_agree(what: &str, a: &Film, b: &Film) {
    let (min_p, alpha, ratios) = agreement(a, b);
    eprintln!("{what}: min p {min_p:.3e} (threshold {alpha:.3e}), mean ratios {ratios:?}");
    assert!(min_p >= alpha, "{what}: min p {min_p} < {alpha}");
    for (r, e) in ratios {
        assert!(
            (r - 1.0).abs() <= 4.0 * e + 1e-3,
            "{what}: ratio {r} +- {e}"
        );
    }
}

/// Light tracing and path tracing estimate the same image: pixel by pixel within their noise,
/// through a pinhole and through a thin lens (whose connections sample the aperture). The box
/// filter keeps the pixels' estimates independent. A 3% darker image fails the test.
#[test]
fn ptracer_agrees_with_path() {
    for lens in ["", LENS] {
        let pt = film(&room("ptracer", 512, lens, "box"));
        let path = film(&room("path", 512, lens, "box"));
        assert!(pt.rgb.iter().all(|c| c.is_finite()));
        assert_agree(
            if lens.is_empty() {
                "pinhole"
            } else {
                "thin lens"
            },
            &pt,
            &path,
        );
        if lens.is_empty() {
            let mut darker = pt.clone();
            darker.rgb.iter_mut().for_each(|c| *c *= 0.97);
            let (_, _, ratios) = agreement(&darker, &path);
            assert!(ratios.iter().any(|(r, e)| (r - 1.0).abs() > 4.0 * e + 1e-3));
        }
    }
}

/// The same image, bits and variances, for any number of threads (splats cross the chunks'
/// and pixels' borders through the tent filter), and a window holds the full image's pixels.
#[test]
fn ptracer_images_do_not_depend_on_threads_or_windows() {
    let s = scene(&room("ptracer", 6, LENS, "tent"));
    let at = |threads: usize, window: Option<Window>| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                render(
                    &s,
                    &RenderOptions {
                        window,
                        ..Default::default()
                    },
                )
                .unwrap()
                .0
            })
    };
    let one = at(1, None);
    assert!(one.rgb.iter().filter(|c| c.x > 0.0).count() > 100);
    for threads in [2, 3] {
        let other = at(threads, None);
        assert_eq!(one.rgb, other.rgb, "{threads} threads");
        assert_eq!(one.variance, other.variance, "{threads} threads");
        assert_eq!(one.shape_id, other.shape_id);
    }
    let w = Window {
        x0: 5,
        y0: 3,
        x1: 29,
        y1: 20,
    };
    let part = at(2, Some(w));
    for y in w.y0..w.y1 {
        for x in w.x0..w.x1 {
            let i = part.index(x - w.x0, y - w.y0);
            assert_eq!(part.rgb[i], one.pixel(x, y));
            assert_eq!(part.depth[i], one.depth[one.index(x, y)]);
        }
    }
}

/// An orthographic camera cannot be reached from the lights: an error, not a black image.
#[test]
fn ptracer_refuses_an_orthographic_camera() {
    let toml = room("ptracer", 1, "type = \"orthographic\"\n", "box");
    let e = render(&scene(&toml), &RenderOptions::default()).unwrap_err();
    assert!(e.to_string().contains("perspective camera"), "{e}");
}

/// A glass ball on a diffuse floor under a small spherical light: the caustic below the ball
/// is light that only a light subpath reaches easily (a path tracer finds it when its BSDF
/// samples happen to hit the light through the glass).
fn caustic(integrator: &str, spp: u32) -> String {
    format!(
        "[camera]\neye = [0.0, 1.4, 2.6]\nlook_at = [0.0, 0.3, 0.0]\nwidth = 24\nheight = 16\n\
         fov = 40\n\
         [render]\nintegrator = \"{integrator}\"\nmax_depth = 8\nspp = {spp}\n\
         filter = {{ type = \"box\" }}\n\n\
         [materials.floor]\ntype = \"diffuse\"\nreflectance = [0.7, 0.7, 0.7]\n\
         [materials.glass]\ntype = \"dielectric\"\n\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"floor\"\n\
         transform = {{ scale = [3.0, 3.0, 1.0], rotate = {{ axis = [1.0, 0.0, 0.0], degrees = -90.0 }} }}\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.4, 0.0]\nradius = 0.4\nmaterial = \"glass\"\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.5, 1.9, -0.3]\nradius = 0.15\n\
         emitter = {{ radiance = [40.0, 36.0, 30.0] }}\n"
    )
}

/// Bidirectional and unidirectional path tracing agree on the caustic of a glass ball, pixel by
/// pixel and in the image means.
#[test]
fn bdpt_agrees_with_path_on_a_caustic() {
    let bd = film(&caustic("bdpt", 256));
    let path = film(&caustic("path", 4096));
    assert_agree("caustic", &bd, &path);
}

/// The film of the scene file `rel` in the shared data at `size`, with a box filter, rendered by
/// `integrator` at `spp`.
fn shared_scene(
    rel: &str,
    size: (u32, u32),
    integrator: appel::scene::IntegratorKind,
    spp: u32,
) -> Film {
    let loaded = appel::format::load(&appel_testdata::path(rel), &Default::default()).unwrap();
    let mut d = loaded.description;
    (d.camera.width, d.camera.height) = size;
    d.render.filter = appel::description::FilterDesc::Box { radius: 0.5 };
    d.render.integrator = integrator;
    d.render.spp = spp;
    let scene = Scene::new(&d, &loaded.base_dir).unwrap();
    render(&scene, &RenderOptions::default()).unwrap().0
}

/// Bidirectional and unidirectional path tracing agree on the Cornell box (its Mitsuba file, at
/// 32 x 32 with a box filter).
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn bdpt_agrees_with_path_in_the_cornell_box() {
    use appel::scene::IntegratorKind::{Bdpt, Path};
    let box_at = |integrator, spp| {
        let file = "bitterli-scenes/cornell-box/mitsuba/scene_v3.xml";
        shared_scene(file, (32, 32), integrator, spp)
    };
    assert_agree("Cornell box", &box_at(Bdpt, 128), &box_at(Path, 1024));
}

/// Bidirectional and unidirectional path tracing agree on veach-mis (the pbrt-v4 file as it is,
/// at 48 x 27 with a box filter): four glossy plates reflecting four spherical lights of radii
/// from 0.03 to 0.9.
#[test]
#[cfg_attr(not(shared_data), ignore = "needs ../shared/data")]
fn bdpt_agrees_with_path_on_veach_mis() {
    use appel::scene::IntegratorKind::{Bdpt, Path};
    let plates_at = |integrator, spp| {
        let file = "bitterli-scenes/veach-mis/pbrt/scene-v4.pbrt";
        shared_scene(file, (48, 27), integrator, spp)
    };
    assert_agree("veach-mis", &plates_at(Bdpt, 1024), &plates_at(Path, 8192));
}

/// bdpt's image (its pixel estimates and its splats) is the same for any number of threads.
#[test]
fn bdpt_images_do_not_depend_on_threads() {
    let s = scene(&room("bdpt", 3, LENS, "tent"));
    let at = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(&s, &RenderOptions::default()).unwrap().0)
    };
    let one = at(1);
    assert!(one.rgb.iter().filter(|c| c.x > 0.0).count() > 100);
    let two = at(2);
    assert_eq!(one.rgb, two.rgb);
    assert_eq!(one.variance, two.variance);
}

/// bdpt against path in the room of lights of every kind (area, point, spot), through a thin
/// lens.
#[test]
fn bdpt_agrees_with_path_in_the_room() {
    let bd = film(&room("bdpt", 128, LENS, "box"));
    let path = film(&room("path", 512, LENS, "box"));
    assert_agree("room", &bd, &path);
}

/// An open scene under lights at infinity: the sun and sky (sampled by its image, a sun widened
/// to 5 degrees), over a diffuse ground with a rough plastic ball and a second ball of
/// `material`, with `extra_light`.
fn under_the_sky(integrator: &str, spp: u32, material: &str, extra_light: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 1.2, 3.0]\nlook_at = [0.0, 0.3, 0.0]\nwidth = 24\nheight = 16\n\
         fov = 45\n\
         [render]\nintegrator = \"{integrator}\"\nmax_depth = 6\nspp = {spp}\n\
         filter = {{ type = \"box\" }}\n\n\
         [materials.ground]\ntype = \"diffuse\"\nreflectance = [0.6, 0.6, 0.6]\n\
         [materials.plastic]\ntype = \"roughplastic\"\ndiffuse_reflectance = [0.2, 0.5, 0.3]\n\
         [materials.second]\n{material}\n\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"ground\"\n\
         transform = {{ scale = [4.0, 4.0, 1.0], rotate = {{ axis = [1.0, 0.0, 0.0], degrees = -90.0 }} }}\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.5, 0.4, -0.2]\nradius = 0.4\nmaterial = \"plastic\"\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [-0.4, 0.35, 0.3]\nradius = 0.35\nmaterial = \"second\"\n\
         [[light]]\ntype = \"sunsky\"\nsun_direction = [-0.4, 1.0, 0.5]\nsun_aperture = 5.0\n\
         sun_scale = 0.02\nsky_scale = 0.05\n{extra_light}"
    )
}

/// Bidirectional and unidirectional path tracing agree under lights at infinity: the sky seen
/// directly and after bounces, and the sun's caustic under a glass ball; then with a directional
/// light too, over a rough metal ball (a directional light's caustic through glass is a path a
/// path tracer cannot sample: no BSDF sample reaches a delta direction).
#[test]
fn bdpt_agrees_with_path_under_the_sky() {
    let glass = "type = \"dielectric\"";
    let metal = "type = \"roughconductor\"\nalpha = 0.2";
    let directional =
        "[[light]]\ntype = \"directional\"\ndirection = [0.6, -1.0, -0.3]\nintensity = 0.8\n";
    for (what, material, extra) in [
        ("sky", glass, ""),
        ("sky and a directional light", metal, directional),
    ] {
        let bd = film(&under_the_sky("bdpt", 256, material, extra));
        let path = film(&under_the_sky("path", 4096, material, extra));
        assert_agree(what, &bd, &path);
    }
}

/// A diffuse floor, back wall and ball under a large area light: every strategy can sample
/// every path (no delta lobe, no point light).
fn diffuse_room(images: &str, spp: u32) -> String {
    format!(
        "[camera]\neye = [0.0, 1.0, 3.5]\nlook_at = [0.0, 0.6, 0.0]\nwidth = 20\nheight = 16\n\
         fov = 45\n\
         [render]\nintegrator = \"bdpt\"\nmax_depth = 3\nspp = {spp}\n\
         [render.bdpt]\nstrategy_images = \"{images}\"\n\
         [materials.white]\ntype = \"diffuse\"\nreflectance = [0.7, 0.7, 0.7]\n\
         [materials.red]\ntype = \"diffuse\"\nreflectance = [0.7, 0.2, 0.2]\n\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"white\"\n\
         transform = {{ scale = [3.0, 3.0, 1.0], rotate = {{ axis = [1.0, 0.0, 0.0], degrees = -90.0 }} }}\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"white\"\n\
         transform = {{ scale = [3.0, 2.0, 1.0], translate = [0.0, 2.0, -1.5] }}\n\
         [[shape]]\ntype = \"sphere\"\ncenter = [0.0, 0.5, 0.0]\nradius = 0.5\nmaterial = \"red\"\n\
         [[shape]]\ntype = \"rectangle\"\n\
         transform = {{ scale = [1.0, 1.0, 1.0], rotate = {{ axis = [1.0, 0.0, 0.0], degrees = 90.0 }}, translate = [0.0, 2.2, 0.5] }}\n\
         emitter = {{ radiance = [2.0, 2.0, 2.0] }}\n"
    )
}

/// The sum over the channels named `bdpt_dDD_sSS_tTT.C` of `film` whose name passes `pick`,
/// over all pixels.
fn strategy_sum(film: &Film, c: &str, pick: impl Fn(&str) -> bool) -> f64 {
    film.channels
        .iter()
        .filter(|ch| ch.name.ends_with(&format!(".{c}")) && pick(&ch.name))
        .map(|ch| ch.values.iter().map(|&v| v as f64).sum::<f64>())
        .sum()
}

/// Weighted strategy images (pbrt's `visualizeweights`): one for each strategy of each depth but
/// `(1, 1)`, and together they are the image, pixel by pixel. Unweighted ones
/// (`visualizestrategies`): each strategy of a depth estimates the same light, the depth's
/// share of the weighted images.
#[test]
fn bdpt_strategy_images_are_the_image_split_by_strategy() {
    let weighted = film(&diffuse_room("weighted", 64));
    let names: Vec<&str> = weighted.channels.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names.len(), 3 * 8, "{names:?}");
    assert_eq!(
        &names[..3],
        &[
            "bdpt_d00_s00_t02.R",
            "bdpt_d00_s00_t02.G",
            "bdpt_d00_s00_t02.B"
        ]
    );
    assert!(names.contains(&"bdpt_d02_s03_t01.B"), "{names:?}");
    for (k, rgb) in weighted.rgb.iter().enumerate() {
        for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
            let sum: f32 = weighted
                .channels
                .iter()
                .filter(|ch| ch.name.ends_with(name))
                .map(|ch| ch.values[k])
                .sum();
            assert!(
                (sum - rgb[c]).abs() <= 1e-4 * rgb[c].max(1.0),
                "pixel {k}: {sum} vs {}",
                rgb[c]
            );
        }
    }
    let unweighted = film(&diffuse_room("unweighted", 256));
    for d in 1..=2 {
        let depth = format!("bdpt_d{d:02}_");
        let expected = strategy_sum(&weighted, "G", |n| n.starts_with(&depth));
        for s in 0..=d + 1 {
            let name = format!("{depth}s{s:02}_t{:02}", d + 2 - s);
            let got = strategy_sum(&unweighted, "G", |n| n.starts_with(&name));
            assert!(
                (got / expected - 1.0).abs() < 0.05,
                "{name}: {got} against the depth's {expected}"
            );
        }
    }
}

/// A window of a render with strategy images has the full render's pixels in every channel.
#[test]
fn bdpt_strategy_images_in_a_window_are_the_full_images_cropped() {
    let s = scene(&diffuse_room("weighted", 4));
    let full = render(&s, &RenderOptions::default()).unwrap().0;
    let window = Window {
        x0: 3,
        y0: 5,
        x1: 11,
        y1: 9,
    };
    let part = render(
        &s,
        &RenderOptions {
            window: Some(window),
            ..Default::default()
        },
    )
    .unwrap()
    .0;
    assert_eq!(part.channels.len(), full.channels.len());
    for (p, f) in part.channels.iter().zip(&full.channels) {
        assert_eq!(p.name, f.name);
        for y in window.y0..window.y1 {
            for x in window.x0..window.x1 {
                let i = ((y - window.y0) * (window.x1 - window.x0) + (x - window.x0)) as usize;
                assert_eq!(
                    p.values[i],
                    f.values[full.index(x, y)],
                    "{} at ({x}, {y})",
                    p.name
                );
            }
        }
    }
}

/// A diffuse floor seen from above through a glass pane, lit by a point light above the pane:
/// light, glass, floor, glass, camera, paths no strategy of bdpt samples (a point light cannot
/// be hit, the floor cannot be joined to it or to the camera through the glass).
fn under_glass(integrator: &str, spp: u32, table: &str) -> String {
    format!(
        "[camera]\neye = [0.0, 2.5, 0.8]\nlook_at = [0.0, 0.0, 0.0]\nwidth = 24\nheight = 24\n\
         fov = 40\n\
         [render]\nintegrator = \"{integrator}\"\nmax_depth = 8\nspp = {spp}\n{table}\n\
         [materials.floor]\ntype = \"diffuse\"\nreflectance = [0.7, 0.7, 0.7]\n\
         [materials.glass]\ntype = \"dielectric\"\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"floor\"\n\
         transform = {{ scale = [3.0, 3.0, 1.0], rotate = {{ axis = [1.0, 0.0, 0.0], degrees = -90.0 }} }}\n\
         [[shape]]\ntype = \"cube\"\nmaterial = \"glass\"\n\
         transform = {{ scale = [4.0, 0.05, 4.0], translate = [0.0, 1.0, 0.0] }}\n\
         [[light]]\ntype = \"point\"\nposition = [0.3, 2.0, -0.3]\nintensity = 6.0\n"
    )
}

fn image_mean(f: &Film) -> f64 {
    f.rgb.iter().map(|c| c.y as f64).sum::<f64>() / f.rgb.len() as f64
}

/// pbrt's `regularize`: bdpt alone leaves the floor under the glass black; regularized (the
/// pane roughened past the floor's diffuse bounce) it finds the light, biased but near photon
/// mapping's image mean (measured: 1.001 times it).
#[test]
fn regularized_bdpt_finds_light_through_glass_on_both_sides() {
    let plain = film(&under_glass("bdpt", 16, ""));
    assert_eq!(image_mean(&plain), 0.0);
    let regularized = film(&under_glass(
        "bdpt",
        256,
        "[render.bdpt]\nregularize = true",
    ));
    let photons = film(&under_glass("sppm", 256, "[render.sppm]\nradius = 0.05"));
    let (r, p) = (image_mean(&regularized), image_mean(&photons));
    eprintln!("regularized {r}, sppm {p}");
    assert!(
        (r / p - 1.0).abs() < 0.1,
        "regularized {r} against sppm {p}"
    );
}

/// Regularization changes only BSDFs with a delta lobe or a roughness below 0.3: the diffuse
/// room is the same image, bit for bit.
#[test]
fn regularize_leaves_rough_scenes_alone() {
    let toml = diffuse_room("weighted", 4).replace("strategy_images = \"weighted\"\n", "");
    let plain = film(&toml);
    let regularized = film(&toml.replace("[render.bdpt]\n", "[render.bdpt]\nregularize = true\n"));
    assert!(image_mean(&plain) > 0.0);
    assert_eq!(plain.rgb, regularized.rgb);
}
