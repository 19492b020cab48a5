use crate::scene_args::load_scene;
use anyhow::{bail, Result};
use appel::scene::ShapeKind;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct ConvertArgs {
    /// A scene file, built-in scene or mesh file.
    input: String,
    /// Output: a binary PLY holding every triangle of the scene, transforms applied, in Appel's order.
    #[arg(short, long)]
    output: PathBuf,
}

pub fn run(args: ConvertArgs) -> Result<()> {
    if !args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ply"))
    {
        bail!(
            "{}: convert writes binary PLY; use a .ply output",
            args.output.display()
        );
    }
    let (scene, _) = load_scene(Some(&args.input), |d| {
        d.render.accel = "brute".into();
        Ok(())
    })?;
    let meshes: Vec<_> = scene
        .geometry
        .shapes
        .iter()
        .enumerate()
        .filter_map(|(id, s)| match s.kind {
            ShapeKind::Mesh(m) => Some((id as u32, &scene.geometry.meshes[m as usize])),
            _ => None,
        })
        .collect();
    if meshes.is_empty() {
        bail!("{}: the scene has no triangles to convert", args.input);
    }
    appel::io::write_ply(&args.output, &meshes)?;
    Ok(())
}
