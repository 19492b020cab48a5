//! Measures binary PLY load speed: writes a 10-million-triangle grid to a temporary PLY (once) and
//! times `load_mesh` on it.
//!
//! `cargo run --release -p appel --example ply_load_speed [PATH] [TRIANGLES]`
//! (default `appel-grid-10m.ply` in the system temporary folder, 10 000 000 triangles).

use appel::geometry::TriangleMesh;
use appel::io::load_mesh;
use appel::math::Vec3;
use appel::output::write_ply;
use std::path::PathBuf;
use std::time::Instant;

/// An n x n grid of quads on a gently curved sheet: 2 n^2 triangles sharing (n+1)^2 vertices, like a
/// scanned surface.
fn grid(n: u32) -> TriangleMesh {
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
            positions.push(Vec3::new(x, 0.1 * (6.0 * x).sin() * (4.0 * z).cos(), z));
        }
    }
    let mut indices = Vec::with_capacity(2 * (n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let (b, c, d) = (a + 1, a + n + 1, a + n + 2);
            indices.push([a, c, b]);
            indices.push([b, c, d]);
        }
    }
    TriangleMesh {
        positions,
        indices,
        normals: None,
        uvs: None,
    }
}

fn main() -> appel::Result<()> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("appel-grid-10m.ply"));
    let triangles: u64 = args
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000_000);
    if !path.exists() {
        let n = ((triangles as f64 / 2.0).sqrt().ceil()) as u32;
        let mesh = grid(n);
        eprintln!(
            "writing {} triangles to {}",
            mesh.triangle_count(),
            path.display()
        );
        write_ply(&path, &[(0, &mesh)])?;
    }
    let bytes = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    for run in 0..3 {
        let start = Instant::now();
        let mesh = load_mesh(&path)?;
        let secs = start.elapsed().as_secs_f64();
        let t = mesh.triangle_count();
        println!(
            "run {run}: {t} triangles, {:.1} MB in {:.3} s: {:.1} M triangles/s, {:.0} MB/s",
            bytes as f64 / 1e6,
            secs,
            t as f64 / secs / 1e6,
            bytes as f64 / secs / 1e6
        );
    }
    Ok(())
}
