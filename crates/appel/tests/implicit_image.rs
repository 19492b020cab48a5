//! The `implicit` built-in scene: the heart, the torus and the sphere appear where they should, with
//! no NaN, no holes and no speckles, at any scene scale.

mod common;
use appel::render::{Film, MISS_ID};
use common::*;

const FLOOR: u32 = 0;
const HEART: u32 = 1;
const SPHERE: u32 = 2;
const TORUS: u32 = 3;

fn id(film: &Film, x: u32, y: u32) -> u32 {
    film.shape_id[film.index(x, y)]
}

/// Pixels whose 8 neighbours all belong to one other shape: a hole in a surface or a speckle on one.
fn isolated_pixels(film: &Film) -> Vec<(u32, u32)> {
    let mut out = vec![];
    for y in 1..film.height - 1 {
        for x in 1..film.width - 1 {
            let n = id(film, x - 1, y - 1);
            let all_same = (0..3)
                .flat_map(|dy| (0..3).map(move |dx| (dx, dy)))
                .filter(|&(dx, dy)| (dx, dy) != (1, 1))
                .all(|(dx, dy)| id(film, x + dx - 1, y + dy - 1) == n);
            if all_same && n != id(film, x, y) {
                out.push((x, y));
            }
        }
    }
    out
}

#[test]
fn implicit_scene_shows_heart_torus_and_sphere_without_holes() {
    let d = with_size(builtin("implicit"), 160, 120);
    let (film, stats, _) = render_description(&d);
    assert!(film.rgb.iter().all(|c| c.is_finite()), "NaN or inf pixels");
    assert!(film.normal.iter().all(|n| n.is_finite()));
    assert!(stats.rays.reflection > 0 && stats.rays.shadow > 0);

    // Sky at the top, floor at the bottom.
    assert_eq!(id(&film, 80, 2), MISS_ID);
    assert_eq!(id(&film, 80, 118), FLOOR);
    // The heart in the middle: its body, and the notch between the lobes at the top is not heart
    // while both lobes beside it are.
    assert_eq!(id(&film, 80, 55), HEART);
    assert_eq!(id(&film, 80, 75), HEART);
    assert_eq!(id(&film, 67, 42), HEART);
    assert_eq!(id(&film, 93, 42), HEART);
    assert_ne!(id(&film, 80, 34), HEART);
    // The mirror sphere on the left, the torus on the right with its hole showing what is behind.
    assert_eq!(id(&film, 24, 62), SPHERE);
    assert_eq!(id(&film, 120, 57), TORUS);
    assert_eq!(id(&film, 147, 57), TORUS);
    let hole = id(&film, 134, 57);
    assert!(
        hole == MISS_ID || hole == FLOOR,
        "torus hole shows shape {hole}"
    );

    let isolated = isolated_pixels(&film);
    assert!(isolated.is_empty(), "holes or speckles at {isolated:?}");
    // The heart is lit: a lit surface without acne has no dark heart pixels facing the light.
    let heart_pixels: Vec<_> = (0..film.height)
        .flat_map(|y| (0..film.width).map(move |x| (x, y)))
        .filter(|&(x, y)| id(&film, x, y) == HEART)
        .collect();
    assert!(heart_pixels.len() > 1500, "{}", heart_pixels.len());
    let n_dark = heart_pixels
        .iter()
        .filter(|&&(x, y)| {
            let n = film.normal[film.index(x, y)];
            // Facing up and towards the light (at +x, +y, +z) but dark: shadow acne.
            n.y > 0.3 && n.x > 0.0 && film.pixel(x, y).x < 0.3
        })
        .count();
    assert_eq!(n_dark, 0, "dark pixels on the lit side of the heart");
}

#[test]
fn implicit_scene_renders_the_same_at_any_scale() {
    let d = with_size(builtin("implicit"), 120, 90);
    let (reference, ..) = render_description(&d);
    for s in [1e-3f32, 1e3] {
        let (scaled, ..) = render_description(&d.scaled(s));
        let differ = reference
            .rgb
            .iter()
            .zip(&scaled.rgb)
            .filter(|(a, b)| (**a - **b).abs().max_element() > 2.0 / 255.0)
            .count();
        // Only silhouette and checker-edge pixels may round differently.
        assert!(
            differ < reference.rgb.len() / 100,
            "scale {s}: {differ} pixels differ"
        );
    }
}

#[test]
fn bad_formula_is_reported_at_its_line_with_the_formula_column() {
    use appel::description::description_from_str;
    use appel::description::parse::Syntax;
    let text = r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]

[[shape]]
type = "implicit"
f = "x^2 + tan(y) - 1"
bounds = [[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]]
"#;
    let e = description_from_str(text, Syntax::Toml, std::path::Path::new("s.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("s.toml:8:"), "{e}");
    assert!(e.contains("column 7 of the formula"), "{e}");
    assert!(e.contains("unknown function `tan`"), "{e}");

    let missing = text.replace("bounds = [[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]]\n", "");
    let e = description_from_str(&missing, Syntax::Toml, std::path::Path::new("s.toml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing field `bounds`"), "{e}");

    let torus = r#"
[camera]
eye = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]

[[shape]]
type = "torus"
center = [0.0, 0.0, 0.0]
major_radius = 1.0
minor_radius = -0.2
"#;
    let e = description_from_str(torus, Syntax::Toml, std::path::Path::new("t.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("t.toml:10:") && e.contains("minor_radius"),
        "{e}"
    );
}
