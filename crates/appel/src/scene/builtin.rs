//! Scenes that ship with Appel, as scene files a user can print (`appel scenes --write NAME`) and edit.

/// `(name, what it shows, scene file text)`.
pub const BUILTIN_SCENES: &[(&str, &str, &str)] = &[
    (
        "whitted",
        "Whitted 1980: mirror and glass spheres over a checkerboard (the default)",
        include_str!("../../scenes/whitted.toml"),
    ),
    (
        "mirror-room",
        "two facing mirrors repeating a sphere down an endless corridor",
        include_str!("../../scenes/mirror-room.toml"),
    ),
    (
        "glass-block",
        "total internal reflection in a glass block made of triangles",
        include_str!("../../scenes/glass-block.toml"),
    ),
    (
        "implicit",
        "a heart, a torus and a mirror sphere as implicit surfaces, by interval root isolation",
        include_str!("../../scenes/implicit.toml"),
    ),
];

/// The text of a built-in scene.
pub fn builtin_scene(name: &str) -> Option<&'static str> {
    BUILTIN_SCENES
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|(_, _, text)| *text)
}
