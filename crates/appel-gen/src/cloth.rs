//! `appel gen cloth`: an animated scene. A flag waves on a pole (one PLY mesh per frame, the same
//! triangles moving: the BVH refits it) while a flock of instanced birds circles it (keyframed
//! instances: the top level over them is rebuilt each frame).

use super::{GenOptions, GenReport};
use appel::error::Result;
use appel::geometry::TriangleMesh;
use appel::math::Vec3;
use std::f32::consts::TAU;
use std::fmt::Write as _;
use std::path::Path;

/// Frames written (two seconds at 24 frames per second: one period of the wave).
pub const FRAMES: u32 = 48;
const FPS: f32 = 24.0;
/// Birds in the flock.
const BIRDS: usize = 24;

/// The flag at `time` seconds: an `n` by `n` sheet of quads over x in [0, 3], y in [1, 3],
/// pinned along x = 0, displaced in z by a travelling wave whose amplitude grows away from the
/// pole. Each quad is `(p0, p1, p2), (p0, p2, p3)`, the fan order the BVH pairs.
pub fn flag(n: u32, time: f32) -> TriangleMesh {
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            let phase = TAU * (1.5 * u - time / 2.0) + 0.8 * v;
            let z = 0.35 * u * phase.sin() + 0.05 * u * (3.0 * phase + 2.0 * v).sin();
            positions.push(Vec3::new(3.0 * u, 1.0 + 2.0 * v - 0.1 * u * u, z));
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut indices = Vec::with_capacity(2 * (n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let (p0, p1, p2, p3) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            indices.push([p0, p1, p2]);
            indices.push([p0, p2, p3]);
        }
    }
    TriangleMesh {
        positions,
        indices,
        normals: None,
        uvs: None,
    }
}

/// A bird of a few triangles: a body and two raised wings, its beak along +x.
fn bird() -> TriangleMesh {
    let p = [
        Vec3::new(0.25, 0.0, 0.0),    // beak
        Vec3::new(-0.2, 0.04, 0.0),   // back
        Vec3::new(-0.2, -0.04, 0.0),  // belly
        Vec3::new(-0.3, 0.0, 0.0),    // tail
        Vec3::new(-0.05, 0.12, 0.3),  // left wing tip
        Vec3::new(-0.05, 0.12, -0.3), // right wing tip
        Vec3::new(0.05, 0.0, 0.0),    // wing root
    ];
    let indices = vec![
        [0, 1, 2],
        [1, 3, 2],
        [6, 1, 4],
        [6, 5, 1],
        [6, 4, 2],
        [6, 2, 5],
    ];
    TriangleMesh {
        positions: p.to_vec(),
        indices,
        normals: None,
        uvs: None,
    }
}

/// Writes the flag's frames, the bird and `cloth.toml` into `dir`. `detail` scales the flag's
/// triangle count (about 33,000 at 1); `step` as for the other generators.
pub fn cloth_scene(
    dir: &Path,
    options: &GenOptions,
    step: &dyn Fn(&str) -> Result<()>,
) -> Result<GenReport> {
    let n = ((128.0 * options.detail.sqrt()).round() as u32).clamp(2, 4096);
    let mut files = vec!["cloth.toml".to_string(), "bird.ply".to_string()];
    let mut report = GenReport::default();
    step(&format!("writing {FRAMES} frames of a {n}x{n} flag"))?;
    for frame in 0..FRAMES {
        let mesh = flag(n, frame as f32 / FPS);
        let name = format!("wave_{frame:04}.ply");
        appel::output::write_ply(&dir.join(&name), &[(0, &mesh)])?;
        report.unique_triangles += mesh.triangle_count() as u64;
        files.push(name);
    }
    let b = bird();
    appel::output::write_ply(&dir.join("bird.ply"), &[(0, &b)])?;
    report.unique_triangles += b.triangle_count() as u64;
    report.instances = BIRDS as u64 + 1;
    report.instanced_triangles = (2 * n * n) as u64 + (BIRDS * b.triangle_count()) as u64;
    let mut scene = format!(
        r#"# `appel gen cloth --detail {detail}`: a flag waving on a pole ({FRAMES} PLY frames of the same
# {tris} triangles) and a flock of {BIRDS} instanced birds on keyframed circles.
# Render: appel render cloth.toml --frames 0..{FRAMES} -o out_{{frame:04}}.png
[animation]
frames = {FRAMES}
fps = {FPS:.1}

[camera]
eye = [6.5, 3.2, 8.0]
look_at = [1.5, 1.8, 0.0]
fov = 45.0
width = 640
height = 480

[render]
integrator = "whitted"
max_depth = 3

[environment]
background = [0.55, 0.7, 0.9]
ambient = [0.35, 0.4, 0.5]

[materials.flag]
color = [0.8, 0.15, 0.1]
ambient = 0.3
diffuse = 0.8
specular = 0.2
shininess = 30.0

[materials.bird]
color = [0.15, 0.15, 0.2]
ambient = 0.4
diffuse = 0.7

[materials.ground]
color = [0.45, 0.55, 0.35]
ambient = 0.4
diffuse = 0.7

[meshes.flag]
file = "wave_{{frame:04}}.ply"
material = "flag"

[meshes.bird]
file = "bird.ply"
material = "bird"

[[instance]]
mesh = "flag"

[[shape]]
type = "cube"
material = "ground"
transform = {{ translate = [-0.04, 1.6, 0.0], scale = [0.04, 1.6, 0.04] }}

[[shape]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "ground"

[[light]]
type = "point"
position = [5.0, 8.0, 6.0]
intensity = 60.0
"#,
        detail = options.detail,
        tris = 2 * n * n,
    );
    // Each bird circles the pole once in the animation's two seconds, at its own radius, height
    // and phase, keyed every quarter turn (slerp turns it between the keys).
    let duration = FRAMES as f32 / FPS;
    let mut seed = options.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut random = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    for _ in 0..BIRDS {
        let radius = 2.5 + 2.0 * random();
        let height = 3.0 + 1.5 * random();
        let phase = random();
        let _ = writeln!(scene, "\n[[instance]]\nmesh = \"bird\"\nkeyframes = [");
        for k in 0..=8 {
            let time = duration * k as f32 / 8.0;
            let angle = TAU * (phase + k as f32 / 8.0);
            let (x, z) = (1.5 + radius * angle.cos(), radius * angle.sin());
            // Heading along the circle (counter-clockwise seen from above): the beak (+x) turned
            // about y to the tangent.
            let heading = -(angle + TAU / 4.0).to_degrees();
            let _ = writeln!(
                scene,
                "  {{ time = {time:.4}, transform = {{ translate = [{x:.4}, {h:.4}, {z:.4}], \
                 rotate = {{ axis = [0.0, 1.0, 0.0], degrees = {heading:.3} }}, scale = 1.5 }} }},",
                h = height + 0.3 * (TAU * 2.0 * k as f32 / 8.0).sin(),
            );
        }
        scene.push_str("]\n");
    }
    step("writing cloth.toml")?;
    appel::output::write_atomically(&dir.join("cloth.toml"), |out| {
        use std::io::Write;
        out.write_all(scene.as_bytes())
            .map_err(|e| appel::error::Error::io(dir.join("cloth.toml"), e))
    })?;
    report.files = files;
    Ok(report)
}
