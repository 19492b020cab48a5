//! The thin-lens camera against the thin-lens law: out-of-focus points blur into disks of the
//! predicted radius, points on the plane in focus stay sharp, a zero aperture is the pinhole
//! camera bit for bit, and the image does not depend on the number of threads.
//!
//! The law in the camera's own units. Put the lens in the plane `z = 0` with the view along `+z`,
//! the plane in focus at depth `f`, and measure film positions `(u, v)` on the image plane at
//! unit distance (the pinhole ray through `(u, v)` has direction `(u, v, 1)`). A ray from the
//! lens point `L` towards the point `f (u, v, 1)` on the plane in focus reaches depth `d` at the
//! lateral position `L (1 - d/f) + d (u, v)`. It meets a point `P` at depth `d` when
//! `(u, v) = P_xy / d - L (f - d) / (f d)`: as `L` covers the aperture's disk of radius `R`, the
//! point's image covers a disk centred at its pinhole image `P_xy / d` of radius
//! `R |d - f| / (f d)`. With the physical lens law (`c = A |S2 - S1| / S2 * F / (S1 - F)` on film
//! at distance `F S1 / (S1 - F)` from a lens of focal length `F` and aperture diameter `A`),
//! dividing by that film distance gives the same `A |S2 - S1| / (S1 S2)`, with `A = 2R`,
//! `S1 = f`, `S2 = d`. On a film `H` pixels high with vertical field of view `fov`, a unit of
//! the image plane is `H / (2 tan(fov / 2))` pixels.

use appel::description::{description_from_str, parse::Syntax};
use appel::render::{render, Film, RenderOptions};
use appel::scene::Scene;
use std::path::Path;

const SIZE: u32 = 160;
const FOV: f64 = 30.0;
const APERTURE: f64 = 0.25;
const FOCUS: f64 = 5.0;

fn scene(toml: &str) -> Scene {
    let d = description_from_str(toml, Syntax::Toml, Path::new("dof.toml")).unwrap();
    Scene::new(&d, Path::new(".")).unwrap()
}

fn film(toml: &str) -> Film {
    render(&scene(toml), &RenderOptions::default()).unwrap().0
}

/// Pixels per unit of the image plane at unit distance.
fn pixels_per_unit() -> f64 {
    SIZE as f64 / (2.0 * (FOV.to_radians() / 2.0).tan())
}

/// A small emitting sphere: centre, radius.
struct Ball {
    centre: [f64; 3],
    radius: f64,
}

impl Ball {
    /// Its pinhole image's centre in pixels (x right, y down), the eye at the origin looking
    /// down -z with y up.
    fn image_centre(&self) -> (f64, f64) {
        let d = -self.centre[2];
        let k = pixels_per_unit();
        let half = SIZE as f64 / 2.0;
        (half + self.centre[0] / d * k, half - self.centre[1] / d * k)
    }

    /// The radius of its pinhole image in pixels: the tangent of the silhouette's half angle.
    fn image_radius(&self) -> f64 {
        let d = (self.centre.iter().map(|c| c * c).sum::<f64>()).sqrt();
        let r = self.radius;
        r / (d * d - r * r).sqrt() * pixels_per_unit()
    }

    /// The thin-lens circle of confusion's radius in pixels (module comment).
    fn blur_radius(&self, aperture: f64) -> f64 {
        let d = -self.centre[2];
        aperture * (d - FOCUS).abs() / (FOCUS * d) * pixels_per_unit()
    }
}

/// Three small emitters: far behind the plane in focus (left), near in front of it (right), and
/// on it (top).
const BALLS: [Ball; 3] = [
    Ball {
        centre: [-3.0, 0.0, -20.0],
        radius: 0.1,
    },
    Ball {
        centre: [0.375, 0.0, -2.5],
        radius: 0.02,
    },
    Ball {
        centre: [0.0, 0.75, -5.0],
        radius: 0.02,
    },
];

/// The scene file: `lens` is extra `[camera]` keys.
fn balls_scene(lens: &str, spp: u32) -> String {
    let mut s = format!(
        "[camera]\neye = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nfov = {FOV}\n\
         width = {SIZE}\nheight = {SIZE}\n{lens}\n\
         [render]\nintegrator = \"path\"\nmax_depth = 1\nsampler = \"sobol\"\nspp = {spp}\n"
    );
    for b in &BALLS {
        let [x, y, z] = b.centre;
        s += &format!(
            "\n[[shape]]\ntype = \"sphere\"\ncenter = [{x}, {y}, {z}]\nradius = {}\n\
             emitter = {{ radiance = [1.0, 1.0, 1.0] }}\n",
            b.radius
        );
    }
    s
}

fn lens_keys(aperture: f64) -> String {
    format!("aperture_radius = {aperture}\nfocus_distance = {FOCUS}\n")
}

/// What a blurred spot looks like: its brightness-weighted centroid, and the root of twice its
/// mean squared distance from there (the radius of a uniform disk of the same spread), over the
/// square of half-side `reach` pixels around `centre`; and the fraction of its light within
/// `radius` of the centroid.
struct Spot {
    cx: f64,
    cy: f64,
    spread: f64,
    film: Vec<(f64, f64, f64)>,
}

impl Spot {
    fn measure(f: &Film, centre: (f64, f64), reach: f64) -> Spot {
        let mut film = Vec::new();
        for j in 0..f.height {
            for i in 0..f.width {
                let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
                if (x - centre.0).abs() > reach || (y - centre.1).abs() > reach {
                    continue;
                }
                let w = f.rgb[(j * f.width + i) as usize].x as f64;
                film.push((x, y, w));
            }
        }
        let total: f64 = film.iter().map(|p| p.2).sum();
        assert!(total > 0.0, "no light near {centre:?}");
        let cx = film.iter().map(|p| p.0 * p.2).sum::<f64>() / total;
        let cy = film.iter().map(|p| p.1 * p.2).sum::<f64>() / total;
        let r2 = film
            .iter()
            .map(|p| ((p.0 - cx).powi(2) + (p.1 - cy).powi(2)) * p.2)
            .sum::<f64>()
            / total;
        Spot {
            cx,
            cy,
            spread: (2.0 * r2).sqrt(),
            film,
        }
    }

    fn within(&self, radius: f64) -> f64 {
        let total: f64 = self.film.iter().map(|p| p.2).sum();
        let inside: f64 = self
            .film
            .iter()
            .filter(|p| (p.0 - self.cx).hypot(p.1 - self.cy) <= radius)
            .map(|p| p.2)
            .sum();
        inside / total
    }
}

/// The radius of the disk whose convolution with the pinhole image (a disk of radius `a`) has
/// this spread: the mean squared distances of independent offsets add, and a uniform disk of
/// radius `r` has `r^2 / 2`.
fn blur_of(spot: &Spot, a: f64) -> f64 {
    (spot.spread.powi(2) - a * a).max(0.0).sqrt()
}

/// Out-of-focus points blur into uniform disks centred on their pinhole images, of the radius
/// the thin-lens law gives, in front of and behind the plane in focus.
#[test]
fn circles_of_confusion_follow_the_thin_lens_law() {
    let f = film(&balls_scene(&lens_keys(APERTURE), 256));
    for ball in &BALLS[..2] {
        let expected = ball.blur_radius(APERTURE);
        assert!(expected > 10.0, "the test wants a blur of many pixels");
        let (x, y) = ball.image_centre();
        let spot = Spot::measure(&f, (x, y), 35.0);
        let measured = blur_of(&spot, ball.image_radius());
        let inner = spot.within(expected / 2.0);
        let outer = spot.within(expected + ball.image_radius() + 1.0);
        eprintln!(
            "depth {}: blur {measured:.3} px (law {expected:.3}), centroid ({:.2}, {:.2}) for \
             ({x:.2}, {y:.2}), light within r/2 {inner:.3}, within the disk {outer:.4}",
            -ball.centre[2], spot.cx, spot.cy
        );
        assert!(
            (measured - expected).abs() < 0.5,
            "ball at depth {}: blur radius {measured:.2} px, thin-lens law {expected:.2} px",
            -ball.centre[2]
        );
        // Centred on the pinhole image (the lens is symmetric).
        assert!(
            (spot.cx - x).abs() < 0.5 && (spot.cy - y).abs() < 0.5,
            "centroid ({:.2}, {:.2}), pinhole image ({x:.2}, {y:.2})",
            spot.cx,
            spot.cy
        );
        // A uniform disk, not a Gaussian blob of the same spread: a quarter of the light within
        // half the radius, and all of it within the radius plus the pinhole image and a pixel.
        assert!(
            (inner - 0.25).abs() < 0.04,
            "{inner} of the light within r/2"
        );
        assert!(outer > 0.99, "{outer} of the light within the disk");
    }
}

/// A point on the plane in focus images to the same spot as through a pinhole.
#[test]
fn points_on_the_plane_in_focus_stay_sharp() {
    let lens = film(&balls_scene(&lens_keys(APERTURE), 256));
    let pinhole = film(&balls_scene("", 256));
    let ball = &BALLS[2];
    let centre = ball.image_centre();
    let with_lens = Spot::measure(&lens, centre, 12.0);
    let without = Spot::measure(&pinhole, centre, 12.0);
    eprintln!(
        "in focus: spread {:.3} px through the lens, {:.3} px through a pinhole, image radius {:.3}",
        with_lens.spread,
        without.spread,
        ball.image_radius()
    );
    assert!(
        (with_lens.spread - without.spread).abs() < 0.2,
        "spread through the lens {:.3} px, through a pinhole {:.3} px",
        with_lens.spread,
        without.spread
    );
    // And that spot is the pinhole image of the ball, filtered by the pixel box.
    assert!(
        (without.spread - ball.image_radius()).abs() < 0.5,
        "{} against {}",
        without.spread,
        ball.image_radius()
    );
    assert!((with_lens.cx - centre.0).abs() < 0.2 && (with_lens.cy - centre.1).abs() < 0.2);
}

/// A zero aperture draws no lens sample and traces the pinhole's rays: the same bits.
#[test]
fn a_zero_aperture_is_the_pinhole_camera_bit_for_bit() {
    let pinhole = film(&balls_scene("", 16));
    let zero = film(&balls_scene(&lens_keys(0.0), 16));
    assert_eq!(pinhole.rgb, zero.rgb);
    assert_eq!(pinhole.variance, zero.variance);
}

/// Lens samples are a pure function of pixel, sample index and dimension like every other
/// number: one thread or two, the same image.
#[test]
fn blurred_images_do_not_depend_on_the_thread_count() {
    let s = scene(&balls_scene(&lens_keys(APERTURE), 8));
    let at = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(&s, &RenderOptions::default()).unwrap().0)
    };
    let one = at(1);
    assert_eq!(one.rgb, at(2).rgb);
    // And the lens did blur something: the far ball's light spreads far beyond its image.
    let spot = Spot::measure(&one, BALLS[0].image_centre(), 35.0);
    assert!(spot.spread > 8.0, "{}", spot.spread);
}

/// Raycast and Whitted: one sample per pixel is the pinhole image (film and lens centres);
/// more samples sample the lens, so the far ball spreads.
#[test]
fn whitted_samples_the_lens_after_its_first_sample() {
    let whitted = |lens: &str, spp: u32| {
        let toml = balls_scene(lens, spp)
            .replace("integrator = \"path\"", "integrator = \"whitted\"")
            .replace("sampler = \"sobol\"\n", "")
            .replace(
                "emitter = { radiance = [1.0, 1.0, 1.0] }",
                "material = \"white\"",
            );
        film(&format!(
            "{toml}\n[materials.white]\ntype = \"phong\"\ncolor = [1.0, 1.0, 1.0]\nambient = 1.0\n\
             diffuse = 0.0\nspecular = 0.0\n\n[environment]\nbackground = [0.0, 0.0, 0.0]\n\
             ambient = [1.0, 1.0, 1.0]\n"
        ))
    };
    let lens = lens_keys(APERTURE);
    assert_eq!(whitted(&lens, 1).rgb, whitted("", 1).rgb);
    let sharp = Spot::measure(&whitted("", 64), BALLS[0].image_centre(), 35.0);
    let blurred = Spot::measure(&whitted(&lens, 64), BALLS[0].image_centre(), 35.0);
    let expected = BALLS[0].blur_radius(APERTURE);
    let measured = blur_of(&blurred, sharp.spread);
    eprintln!("whitted, 64 spp: blur {measured:.3} px (law {expected:.3})");
    assert!(
        (measured - expected).abs() < 1.5,
        "whitted at 64 spp: blur {measured:.2} px, thin-lens law {expected:.2} px"
    );
}

/// A negative aperture or a plane in focus at or behind the lens is an error at its line.
#[test]
fn bad_lens_values_fail_at_their_line() {
    for (keys, expected) in [
        (
            "aperture_radius = -0.5\n",
            "dof.toml:7:19: camera.aperture_radius: `aperture_radius` must be 0 (a pinhole) or a positive number of scene units, got -0.5",
        ),
        (
            "aperture_radius = 0.5\nfocus_distance = -2.0\n",
            "dof.toml:8:18: camera.focus_distance: `focus_distance` must be a positive distance, got -2",
        ),
    ] {
        let text = balls_scene(keys, 1);
        let e = description_from_str(&text, Syntax::Toml, Path::new("dof.toml"))
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(expected), "expected {expected}\n     got {e}");
    }
}
