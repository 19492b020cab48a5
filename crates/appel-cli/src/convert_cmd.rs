use crate::scene_args::load_scene_with;
use anyhow::{bail, Result};
use appel::geometry::TriangleMesh;
use appel::math::Vec3;
use appel::scene::{SceneHit, ShapeKind, NO_INSTANCE};
use appel::scene_build::SceneOptions;
use std::collections::BTreeMap;
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
    let skip = SceneOptions {
        skip_top_level: true,
        ..Default::default()
    };
    let (scene, _) = load_scene_with(
        Some(&args.input),
        &Default::default(),
        |_| Ok(()),
        skip,
        None,
    )?;
    // One mesh per `[[shape]]`, its triangles in the source file's order, so that a triangle's index
    // in the output is its `[[shape]]`'s offset plus its `primid`. Instances are flattened: one
    // mesh per `[[instance]]` entry, its placements one after the other.
    let g = &scene.geometry;
    let mut by_source: BTreeMap<u32, Vec<(u64, [Vec3; 3])>> = BTreeMap::new();
    for (id, shape) in g.shapes.iter().enumerate() {
        if let ShapeKind::Mesh(m) = shape.kind {
            let mesh = &g.meshes[m as usize];
            for t in 0..mesh.triangle_count() {
                let hit = SceneHit {
                    t: 0.0,
                    shape: id as u32,
                    prim: t as u32,
                    u: 0.0,
                    v: 0.0,
                    instance: NO_INSTANCE,
                };
                let (source, prim) = g.source_ids(&hit);
                by_source
                    .entry(source)
                    .or_default()
                    .push((prim as u64, mesh.vertices(t)));
            }
        }
    }
    let mut placement_in_entry: BTreeMap<u32, u64> = BTreeMap::new();
    for (i, instance) in g.instances.iter().enumerate() {
        let order = placement_in_entry.entry(instance.source).or_default();
        let prototype = &g.prototypes[instance.prototype as usize].geometry;
        for (id, shape) in prototype.shapes.iter().enumerate() {
            let ShapeKind::Mesh(m) = shape.kind else {
                continue;
            };
            let mesh = &prototype.meshes[m as usize];
            for t in 0..mesh.triangle_count() {
                let hit = SceneHit {
                    t: 0.0,
                    shape: id as u32,
                    prim: t as u32,
                    u: 0.0,
                    v: 0.0,
                    instance: i as u32,
                };
                let (source, prim) = g.source_ids(&hit);
                let v = mesh
                    .vertices(t)
                    .map(|p| instance.transform.point_to_world(p));
                by_source
                    .entry(source)
                    .or_default()
                    .push(((*order << 32) | prim as u64, v));
            }
        }
        *order += 1;
    }
    let owned: Vec<(u32, TriangleMesh)> = by_source
        .into_iter()
        .map(|(source, mut tris)| {
            tris.sort_by_key(|(prim, _)| *prim);
            let positions = tris.iter().flat_map(|(_, v)| *v).collect();
            let indices = (0..tris.len() as u32)
                .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
                .collect();
            let mesh = TriangleMesh {
                positions,
                indices,
                ..Default::default()
            };
            (source, mesh)
        })
        .collect();
    let meshes: Vec<(u32, &TriangleMesh)> = owned.iter().map(|(s, m)| (*s, m)).collect();
    if meshes.is_empty() {
        bail!("{}: the scene has no triangles to convert", args.input);
    }
    appel::output::write_ply(&args.output, &meshes)?;
    Ok(())
}
