use anyhow::{bail, Result};
use appel::geometry::procedural::append;
use appel::geometry::TriangleMesh;
use appel::io::load_mesh;
use appel::io::points::read_points_csv;
use appel::query::InsideTester;
use std::io::Write;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct InsideArgs {
    /// A closed mesh (.ply, .obj, .gltf, .glb, .ply.gz, .obj.gz).
    mesh: PathBuf,
    /// Points, one `x,y,z` per line.
    points: PathBuf,
    /// Print a JSON array of booleans instead of one `inside`/`outside` per line.
    #[arg(long)]
    json: bool,
}

pub fn run(args: InsideArgs) -> Result<()> {
    let loaded = load_mesh(&args.mesh)?.flattened();
    let mut mesh = TriangleMesh::default();
    for part in &loaded.parts {
        append(&mut mesh, &part.mesh);
    }
    if mesh.triangle_count() == 0 {
        bail!("{}: the mesh has no triangles", args.mesh.display());
    }
    let points = read_points_csv(&args.points)?;
    let answers = InsideTester::new(&mesh).classify(&points);
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    if args.json {
        writeln!(out, "{}", serde_json::to_string(&answers)?)?;
    } else {
        for inside in answers {
            writeln!(out, "{}", if inside { "inside" } else { "outside" })?;
        }
    }
    Ok(())
}
