//! Acceleration structures in whole renders: every built-in scene gives the same image, depth,
//! normals and ids with every structure and BVH layout, and the scene file's `[render.bvh]`,
//! `[render.grid]` and `[render.kdtree]` tables reach the structure that is built.

use appel::accel::{
    Accel, AccelKind, BspOptions, BvhOptions, BvhSplit, GridOptions, OctreeOptions,
};
use appel::description::description_from_str;
use appel::description::parse::Syntax;
use appel::description::Description;
use appel::render::{render, Film, RenderOptions};
use appel::scene::builtin::builtin_scene;
use appel::scene::Scene;
use std::path::Path;

fn builtin(name: &str, width: u32, height: u32) -> Description {
    let text = builtin_scene(name).unwrap();
    let mut d = description_from_str(text, Syntax::Toml, Path::new("builtin.toml")).unwrap();
    (d.camera.width, d.camera.height) = (width, height);
    d
}

fn film(d: &Description) -> (Film, Scene) {
    let scene = Scene::new(d, Path::new(".")).unwrap();
    let (film, _) = render(&scene, &RenderOptions::default()).unwrap();
    (film, scene)
}

#[test]
fn every_structure_renders_the_built_in_scenes_identically() {
    for name in ["whitted", "mirror-room", "glass-block", "implicit"] {
        let size = if name == "implicit" {
            (40, 30)
        } else {
            (96, 72)
        };
        let mut d = builtin(name, size.0, size.1);
        d.render.accel = "brute".into();
        let (want, _) = film(&d);
        let mut variants: Vec<(String, Description)> = ["grid", "kdtree", "bvh", "octree", "bsp"]
            .iter()
            .map(|&a| {
                let mut v = d.clone();
                v.render.accel = a.into();
                (a.to_string(), v)
            })
            .collect();
        for width in [2, 4] {
            let mut v = d.clone();
            v.render.accel = "bvh".into();
            v.render.bvh = Some(BvhOptions {
                width,
                ..Default::default()
            });
            variants.push((format!("bvh width {width}"), v));
        }
        for (label, v) in variants {
            let (got, _) = film(&v);
            assert!(got.rgb == want.rgb, "{name} with {label}: colours differ");
            assert!(
                got.depth
                    .iter()
                    .zip(&want.depth)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "{name} with {label}: depth differs"
            );
            assert!(
                got.normal == want.normal,
                "{name} with {label}: normals differ"
            );
            assert!(
                got.shape_id == want.shape_id && got.prim_id == want.prim_id,
                "{name} with {label}: ids differ"
            );
        }
    }
}

#[test]
fn scene_tables_set_the_structure_parameters() {
    let mut d = builtin("glass-block", 8, 8);
    d.render.accel = "bvh".into();
    d.render.bvh = Some(BvhOptions {
        width: 4,
        split: BvhSplit::Median,
        max_leaf: 2,
        ..Default::default()
    });
    let scene = Scene::new(&d, Path::new(".")).unwrap();
    let Accel::Bvh(b) = &scene.accel else {
        panic!("not a BVH")
    };
    assert_eq!(b.width(), 4);
    assert_eq!(scene.settings.accel_options.bvh.max_leaf, 2);
    assert_eq!(scene.settings.accel_options.bvh.split, BvhSplit::Median);

    // The grid's cell count follows `density`.
    let cells = |density: Option<f32>| {
        let mut d = builtin("glass-block", 8, 8);
        d.render.accel = AccelKind::Grid.name().into();
        d.render.grid = density.map(|density| GridOptions {
            density,
            ..Default::default()
        });
        Scene::new(&d, Path::new(".")).unwrap().accel.stats().nodes
    };
    let (sparse, default, dense) = (cells(Some(1.0)), cells(None), cells(Some(200.0)));
    assert!(
        sparse < default && default < dense,
        "{sparse} {default} {dense}"
    );

    // The octree's and the BSP's depth limits hold, and without them the trees are deeper.
    let octree = |max_depth| {
        let mut d = builtin("mirror-room", 8, 8);
        d.render.accel = "octree".into();
        d.render.octree = Some(OctreeOptions {
            max_prims: 1,
            max_depth,
        });
        Scene::new(&d, Path::new(".")).unwrap().accel.stats()
    };
    let (flat, deep) = (octree(0), octree(16));
    assert_eq!((flat.depth, flat.nodes, flat.leaves), (0, 0, 1));
    assert!(deep.depth > 1, "{deep:?}");
    let bsp = |max_depth| {
        let mut d = builtin("mirror-room", 8, 8);
        d.render.accel = "bsp".into();
        // Leaf tests costed high, so that the SAH splits the room's few large primitives.
        d.render.bsp = Some(BspOptions {
            max_prims: 1,
            max_depth,
            intersect_cost: 100.0,
            ..Default::default()
        });
        Scene::new(&d, Path::new(".")).unwrap().accel.stats()
    };
    let (shallow, deep) = (bsp(Some(1)), bsp(None));
    assert!(shallow.depth <= 1, "{shallow:?}");
    assert!(deep.depth > 1, "{deep:?}");
}

/// With one sample per pixel the renderer traces camera rays in packets of eight wherever the
/// 8-wide BVH has more than one leaf: forcing one primitive per leaf makes it do so on the built-in
/// scenes, and the film (colours, depth, normals, ids) is brute force's, bit for bit. A width of 100
/// leaves tiles of 4 columns at the right edge: short packets.
#[test]
fn camera_ray_packets_render_what_single_rays_render() {
    for name in ["whitted", "mirror-room", "glass-block"] {
        let mut d = builtin(name, 100, 72);
        d.render.spp = 1;
        d.render.accel = "brute".into();
        let (want, _) = film(&d);
        d.render.accel = "bvh".into();
        d.render.bvh = Some(BvhOptions {
            max_leaf: 1,
            ..Default::default()
        });
        let (got, scene) = film(&d);
        // Packets need AVX2; elsewhere this checks the ray-by-ray fallback.
        #[cfg(target_arch = "x86_64")]
        let packets = std::arch::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        let packets = false;
        assert_eq!(scene.accel.has_packets(), packets, "{name}");
        assert!(got.rgb == want.rgb, "{name}: colours differ");
        assert!(
            got.depth
                .iter()
                .zip(&want.depth)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "{name}: depth differs"
        );
        assert!(got.normal == want.normal, "{name}: normals differ");
        assert!(
            got.shape_id == want.shape_id && got.prim_id == want.prim_id,
            "{name}: ids differ"
        );
    }
}
