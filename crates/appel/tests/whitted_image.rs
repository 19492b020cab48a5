//! The Whitted scene, checked by what a correct image must show rather than against a stored copy.

mod common;
use appel::math::{Ray, Vec3};
use appel::render::MISS_ID;
use common::*;

const FLOOR: u32 = 0;
const MIRROR: u32 = 1;
const GLASS: u32 = 2;

fn is_warm(c: Vec3) -> bool {
    // Red and yellow squares: red clearly above blue.
    c.x > 1.5 * c.z && c.x > 0.05
}

fn is_sky(c: Vec3) -> bool {
    c.z > 1.2 * c.x
}

/// Pixels of one shape, with their rows normalized to the shape's own vertical extent (0 top, 1 bottom).
fn pixels_of(film: &appel::render::Film, shape: u32) -> Vec<(f32, Vec3)> {
    let rows: Vec<u32> = (0..film.height)
        .filter(|&y| (0..film.width).any(|x| film.shape_id[film.index(x, y)] == shape))
        .collect();
    let (top, bottom) = (*rows.first().unwrap() as f32, *rows.last().unwrap() as f32);
    let mut out = vec![];
    for y in 0..film.height {
        for x in 0..film.width {
            if film.shape_id[film.index(x, y)] == shape {
                out.push(((y as f32 - top) / (bottom - top), film.pixel(x, y)));
            }
        }
    }
    out
}

fn fraction(p: &[(f32, Vec3)], band: std::ops::Range<f32>, pred: fn(Vec3) -> bool) -> f32 {
    let in_band: Vec<_> = p.iter().filter(|(r, _)| band.contains(r)).collect();
    in_band.iter().filter(|(_, c)| pred(*c)).count() as f32 / in_band.len().max(1) as f32
}

#[test]
fn whitted_scene_shows_reflection_refraction_and_shadows() {
    let d = with_size(builtin("whitted"), 200, 150);
    let (film, stats, scene) = render_description(&d);
    assert!(film.rgb.iter().all(|c| c.is_finite()));
    assert!(stats.rays.reflection > 0 && stats.rays.refraction > 0 && stats.rays.shadow > 0);

    // Sky above, floor below, both spheres in view.
    assert_eq!(film.shape_id[film.index(100, 0)], MISS_ID);
    assert_eq!(film.shape_id[film.index(100, 149)], FLOOR);
    let mirror = pixels_of(&film, MIRROR);
    let glass = pixels_of(&film, GLASS);
    assert!(mirror.len() > 500 && glass.len() > 500);

    // The mirror reflects the checkerboard in its lower part and the sky in its upper part.
    assert!(
        fraction(&mirror, 0.75..1.01, is_warm) > 0.6,
        "mirror's lower part shows no checkerboard"
    );
    assert!(
        fraction(&mirror, 0.0..0.25, is_sky) > 0.6,
        "mirror's upper part shows no sky"
    );

    // The glass sphere inverts: the floor appears in its upper part, the sky in its lower part.
    assert!(
        fraction(&glass, 0.1..0.4, is_warm) > 0.6,
        "no inverted checkerboard in the glass"
    );
    assert!(
        fraction(&glass, 0.7..0.95, is_sky) > 0.4,
        "no inverted sky in the glass"
    );

    // Shadows: floor points whose segment to the light crosses a sphere (decided analytically, not by
    // the renderer) are much darker than lit floor points of the same colour.
    let light = Vec3::new(4.0, 8.0, 6.0);
    let spheres = [
        (Vec3::new(-1.1, 1.1, -1.8), 1.1f32),
        (Vec3::new(0.7, 1.0, 1.2), 0.8),
    ];
    let blocked = |p: Vec3| {
        spheres.iter().any(|&(c, r)| {
            let d = light - p;
            let t = ((c - p).dot(d) / d.length_squared()).clamp(0.0, 1.0);
            (p + t * d - c).length() < r * 0.97
        })
    };
    let clearly_lit = |p: Vec3| {
        spheres.iter().all(|&(c, r)| {
            let d = light - p;
            let t = ((c - p).dot(d) / d.length_squared()).clamp(0.0, 1.0);
            (p + t * d - c).length() > r * 1.03
        })
    };
    let (mut shadow, mut lit) = (vec![], vec![]);
    for y in 0..film.height {
        for x in 0..film.width {
            let i = film.index(x, y);
            if film.shape_id[i] != FLOOR {
                continue;
            }
            let ray: Ray = scene.camera.pixel_ray(x, y);
            let p = ray.at(film.depth[i]);
            let c = film.rgb[i];
            // Compare red squares only (green channel low), so albedo does not confound.
            if c.y > 0.5 * c.x {
                continue;
            }
            if blocked(p) {
                shadow.push(luminance(c));
            } else if clearly_lit(p) {
                lit.push(luminance(c));
            }
        }
    }
    assert!(shadow.len() > 50 && lit.len() > 50);
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    assert!(
        mean(&shadow) < 0.4 * mean(&lit),
        "shadowed floor {} is not much darker than lit floor {}",
        mean(&shadow),
        mean(&lit)
    );
}

#[test]
fn raycast_casts_no_secondary_rays_and_shows_opaque_glass() {
    let mut d = with_size(builtin("whitted"), 80, 60);
    d.render.integrator = appel::scene::IntegratorKind::Raycast;
    let (film, stats, _) = render_description(&d);
    assert_eq!(stats.rays.reflection + stats.rays.refraction, 0);
    assert_eq!(stats.rays.camera, 80 * 60);
    // One shadow ray per light at most, per camera ray.
    assert!(stats.rays.shadow <= stats.rays.camera);
    assert!(film.rgb.iter().all(|c| c.is_finite()));
}

fn scene_from_toml(text: &str) -> appel::description::Description {
    appel::description::description_from_str(
        text,
        appel::description::parse::Syntax::Toml,
        std::path::Path::new("test.toml"),
    )
    .unwrap()
}

/// A floor seen from above under `light`, rendered by Whitted at 64x64 (the floor fills the
/// image: x and z from -2 to 2).
fn floor_under(material: &str, light: &str) -> appel::render::Film {
    let text = format!(
        r#"
[camera]
eye = [0.0, 4.0, 0.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 0.0, -1.0]
fov = 53.13
width = 64
height = 64
[render]
integrator = "whitted"
[environment]
ambient = [0.0, 0.0, 0.0]
[materials.floor]
{material}
[[shape]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "floor"
[[light]]
{light}
"#
    );
    render_description(&scene_from_toml(&text)).0
}

/// Whitted's lights are the scene's emitters: a spot light lights its cone only, as under `path`.
#[test]
fn whitted_lights_with_the_emitters_spot_cone() {
    let film = floor_under(
        "type = \"diffuse\"\nreflectance = 0.5",
        "type = \"spot\"\nposition = [0.0, 2.0, 0.0]\nlook_at = [0.0, 0.0, 0.0]\n\
         intensity = 10.0\ncutoff_angle = 20.0\nbeam_width = 20.0",
    );
    // The cone of half-angle 20 degrees meets the floor in a disc of radius 2 tan 20 = 0.73, 12
    // pixels across from the centre; the diffuse response at the centre is 0.5 * 10 / 4 (cosine 1).
    let centre = film.pixel(32, 32);
    assert!((centre.x - 0.5 * 10.0 / 4.0).abs() < 0.02, "{centre}");
    let outside = film.pixel(32, 32 + 20);
    assert_eq!(outside, appel::math::Vec3::ZERO);
}

/// A physically based material's Whitted response reads its textures at the point: a diffuse
/// checkerboard shows both of its colours under Whitted.
#[test]
fn whitted_reads_textures_of_physically_based_materials() {
    let film = floor_under(
        "type = \"diffuse\"\nreflectance = { type = \"checkerboard\", color0 = [1.0, 0.0, 0.0], \
         color1 = [0.0, 0.0, 1.0] }",
        "type = \"directional\"\ndirection = [0.0, -1.0, 0.0]\nintensity = 1.0",
    );
    let (mut red, mut blue) = (0, 0);
    for y in 0..64 {
        for x in 0..64 {
            let c = film.pixel(x, y);
            red += (c.x > 0.9 && c.z == 0.0) as u32;
            blue += (c.z > 0.9 && c.x == 0.0) as u32;
        }
    }
    assert!(red > 500 && blue > 500, "red {red}, blue {blue}");
}
