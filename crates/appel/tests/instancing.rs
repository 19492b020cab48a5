//! Instancing: an instanced mesh is the same surface as the mesh with its transform baked in - same
//! image, same AOVs (plus `instanceid`), same hits on random rays - and stays free of shadow acne at
//! any scale.

mod common;
use appel::accel::TraversalStats;
use appel::description::parse::Syntax;
use appel::description::{description_from_str, Description};
use appel::geometry::procedural::{append, cube, icosphere, SplitMix64};
use appel::geometry::TriangleMesh;
use appel::math::{Ray, Vec3};
use appel::render::MISS_ID;
use appel::scene::{Scene, NO_INSTANCE};
use common::*;
use std::path::Path;

/// A lopsided test mesh (a sphere with a cube stuck to it) so that a wrong rotation shows.
fn lopsided() -> TriangleMesh {
    let mut m = icosphere(3);
    let mut c = cube();
    for p in &mut c.positions {
        *p = *p * 0.4 + Vec3::new(0.9, 0.3, 0.0);
    }
    append(&mut m, &c);
    m
}

fn write_mesh(dir: &Path) {
    let m = lopsided();
    appel::output::write_ply(&dir.join("m.ply"), &[(0, &m)]).unwrap();
}

const HEADER: &str = r#"
[camera]
eye = [0.0, 2.0, 9.0]
look_at = [0.0, 0.3, 0.0]
fov = 35.0
width = 96
height = 72

[materials.mirror]
color = [0.2, 0.2, 0.2]
reflection = 0.6

[[shape]]
type = "plane"
point = [0.0, -1.2, 0.0]
normal = [0.0, 1.0, 0.0]
material = "mirror"

[[light]]
type = "point"
position = [4.0, 8.0, 6.0]
intensity = 120.0
"#;

const TRANSFORM: &str =
    "{ translate = [0.5, 0.2, -0.3], rotate = { axis = [1.0, 2.0, 0.5], degrees = 37.0 }, scale = [1.3, 0.8, 1.1] }";

fn scene_text(instanced: bool) -> String {
    if instanced {
        format!(
            "{HEADER}\n[meshes.lump]\nfile = \"m.ply\"\n\n[[instance]]\nmesh = \"lump\"\ntransform = {TRANSFORM}\n"
        )
    } else {
        format!("{HEADER}\n[[shape]]\ntype = \"mesh\"\nfile = \"m.ply\"\ntransform = {TRANSFORM}\n")
    }
}

fn parse(text: &str) -> Description {
    description_from_str(text, Syntax::Toml, Path::new("t.toml")).unwrap()
}

#[test]
fn an_instance_renders_like_the_mesh_with_its_transform_baked_in() {
    let dir = tempfile::tempdir().unwrap();
    write_mesh(dir.path());
    let render = |instanced| {
        let scene = Scene::new(&parse(&scene_text(instanced)), dir.path()).unwrap();
        appel::render::render(&scene, &Default::default())
            .unwrap()
            .0
    };
    let (baked, inst) = (render(false), render(true));
    let n = baked.rgb.len();
    let mut hits = 0;
    let mut same_prim = 0;
    let mut rgb_off = 0;
    for i in 0..n {
        // The plane is shape 0; the mesh is shape 1 as a `[[shape]]` and as the first `[[instance]]`.
        assert_eq!(baked.instance_id[i], MISS_ID);
        if baked.shape_id[i] == 1 {
            hits += 1;
            if inst.shape_id[i] == 1 && inst.prim_id[i] == baked.prim_id[i] {
                same_prim += 1;
                assert_eq!(inst.instance_id[i], 0);
                assert!((inst.depth[i] - baked.depth[i]).abs() < 1e-4 * baked.depth[i]);
                assert!((inst.normal[i] - baked.normal[i]).length() < 1e-4);
            }
        } else {
            assert_eq!(inst.instance_id[i], MISS_ID);
        }
        if (inst.rgb[i] - baked.rgb[i]).abs().max_element() > 2.0 / 255.0 {
            rgb_off += 1;
        }
    }
    assert!(hits > n / 20, "the mesh covers {hits} of {n} pixels");
    // Transforming the ray instead of the vertices rounds differently: only a ray through an edge
    // may pick the neighbouring triangle.
    assert!(same_prim * 100 >= hits * 99, "{same_prim} of {hits}");
    assert!(rgb_off * 100 <= n, "{rgb_off} of {n} pixels differ");
}

/// Random transforms: rotation about a random axis, non-uniform scale, translation.
/// `--stats` counts the work inside instances apart: every query that tests the instance (the
/// scene structure's only primitive) runs one query of the prototype's structure, whose nodes and
/// triangle tests are counted; the same mesh as a plain shape has no instance queries.
#[test]
fn work_inside_instances_is_counted_apart() {
    let dir = tempfile::tempdir().unwrap();
    write_mesh(dir.path());
    let traversal = |instanced| {
        let scene = Scene::new(&parse(&scene_text(instanced)), dir.path()).unwrap();
        appel::render::render(&scene, &Default::default())
            .unwrap()
            .1
            .traversal
    };
    let (baked, inst) = (traversal(false), traversal(true));
    assert_eq!(baked.instance_queries, 0);
    assert_eq!(baked.instance_prim_tests, 0);
    assert!(inst.instance_queries > 0);
    assert_eq!(inst.instance_queries, inst.prim_tests);
    assert!(inst.instance_nodes_visited > 0 && inst.instance_prim_tests > 0);
    // The prototype's structure is the baked mesh's structure (in object space): the same order of
    // work per ray.
    let per = |n: u64, q: u64| n as f64 / q as f64;
    let (a, b) = (
        per(inst.instance_prim_tests, inst.instance_queries),
        per(baked.prim_tests, baked.rays),
    );
    assert!(a > 0.25 * b && a < 4.0 * b, "{a} against {b}");
}

fn random_transform(rng: &mut SplitMix64) -> glam::Mat4 {
    let axis = (rng.in_box(Vec3::splat(-1.0), Vec3::splat(1.0)) + Vec3::splat(1e-3)).normalize();
    glam::Mat4::from_scale_rotation_translation(
        rng.in_box(Vec3::splat(0.3), Vec3::splat(2.0)),
        glam::Quat::from_axis_angle(axis, rng.next_f32() * std::f32::consts::TAU),
        rng.in_box(Vec3::splat(-6.0), Vec3::splat(6.0)),
    )
}

#[test]
fn hits_agree_with_a_flattened_copy_on_random_rays() {
    let dir = tempfile::tempdir().unwrap();
    write_mesh(dir.path());
    let mut rng = SplitMix64(7);
    let transforms: Vec<glam::Mat4> = (0..40).map(|_| random_transform(&mut rng)).collect();
    let lines: String = transforms
        .iter()
        .map(appel::io::placements::placement_line)
        .collect();
    std::fs::write(dir.path().join("p.txt"), lines).unwrap();
    let base = "[camera]\neye = [0.0, 0.0, 30.0]\nlook_at = [0.0, 0.0, 0.0]\n";
    let instanced = parse(&format!(
        "{base}[meshes.lump]\nfile = \"m.ply\"\n[[instance]]\nmesh = \"lump\"\nplacements = \"p.txt\"\n"
    ));
    let scene = Scene::new(&instanced, dir.path()).unwrap();
    assert_eq!(scene.geometry.instances.len(), 40);
    let per = lopsided().triangle_count();
    assert_eq!(scene.geometry.triangle_count(), per);
    assert_eq!(scene.geometry.instanced_triangle_count(), 40 * per as u64);
    // The flattened copy: every placement's triangles transformed and written as one mesh.
    let mut flat = TriangleMesh::default();
    for m in &transforms {
        let mut copy = lopsided();
        for p in &mut copy.positions {
            *p = m.transform_point3(*p);
        }
        append(&mut flat, &copy);
    }
    appel::output::write_ply(&dir.path().join("flat.ply"), &[(0, &flat)]).unwrap();
    let flat_scene = Scene::new(
        &parse(&format!(
            "{base}[[shape]]\ntype = \"mesh\"\nfile = \"flat.ply\"\n"
        )),
        dir.path(),
    )
    .unwrap();
    let mut s = TraversalStats::default();
    let (mut both, mut agree, mut hit_miss, mut occluded_agree) = (0, 0, 0, 0);
    let rays = 20_000;
    for k in 0..rays {
        let origin = rng.in_box(Vec3::splat(-12.0), Vec3::splat(12.0));
        // Half the rays aim at a random instance's centre, so most of them hit something.
        let target = if k % 2 == 0 {
            transforms[k % 40].transform_point3(Vec3::ZERO)
        } else {
            rng.in_box(Vec3::splat(-8.0), Vec3::splat(8.0))
        };
        let ray = Ray::new(origin, (target - origin).normalize());
        let a = scene.intersect(&ray, f32::INFINITY, &mut s);
        let b = flat_scene.intersect(&ray, f32::INFINITY, &mut s);
        if a.is_some() == b.is_some() {
            hit_miss += 1;
        }
        if let (Some(a), Some(b)) = (a, b) {
            both += 1;
            let (_, prim) = scene.geometry.source_ids(&a);
            let (_, flat_prim) = flat_scene.geometry.source_ids(&b);
            assert_ne!(a.instance, NO_INSTANCE);
            let same = flat_prim as usize == a.instance as usize * per + prim as usize;
            if same {
                agree += 1;
                assert!(
                    (a.t - b.t).abs() <= 1e-4 * b.t.max(1.0),
                    "{} vs {}",
                    a.t,
                    b.t
                );
            }
        }
        let t_max = rng.next_f32() * 20.0;
        if scene.occluded(&ray, t_max, &mut s) == flat_scene.occluded(&ray, t_max, &mut s) {
            occluded_agree += 1;
        }
    }
    assert!(both > rays / 3, "only {both} rays hit");
    // Rounding differs between moving the ray and moving the triangles: only rays grazing an edge
    // may disagree.
    assert!(agree * 1000 >= both * 998, "{agree} of {both} agree");
    assert!(hit_miss * 1000 >= rays * 999, "{hit_miss} of {rays}");
    assert!(
        occluded_agree * 1000 >= rays * 999,
        "{occluded_agree} of {rays}"
    );
}

/// Every structure, as the scene's top level over 40 placements (primitives known only by their
/// bounds and their own any-hit query) and inside the placed mesh, returns the BVH's hits (the
/// structures' agreement with brute force is tested in `accel_agreement`) exactly. Brute force
/// itself, through 40 instances of 1,292 triangles, would take most of this test's time.
#[test]
fn every_structure_finds_the_same_instance_hits() {
    let dir = tempfile::tempdir().unwrap();
    write_mesh(dir.path());
    let mut rng = SplitMix64(11);
    let lines: String = (0..40)
        .map(|_| appel::io::placements::placement_line(&random_transform(&mut rng)))
        .collect();
    std::fs::write(dir.path().join("p.txt"), lines).unwrap();
    let scene = |accel: &str| {
        let text = format!(
            "[camera]\neye = [0.0, 0.0, 30.0]\nlook_at = [0.0, 0.0, 0.0]\n[render]\naccel = \"{accel}\"\n\
             [meshes.lump]\nfile = \"m.ply\"\n[[instance]]\nmesh = \"lump\"\nplacements = \"p.txt\"\n"
        );
        Scene::new(&parse(&text), dir.path()).unwrap()
    };
    let bvh = scene("bvh");
    let rays: Vec<(Ray, f32)> = (0..3000)
        .map(|_| {
            let o = rng.in_box(Vec3::splat(-12.0), Vec3::splat(12.0));
            let target = rng.in_box(Vec3::splat(-6.0), Vec3::splat(6.0));
            (Ray::new(o, (target - o).normalize()), rng.next_f32() * 20.0)
        })
        .collect();
    let mut s = TraversalStats::default();
    let want: Vec<(Option<f32>, bool)> = rays
        .iter()
        .map(|(ray, t_max)| {
            let h = bvh.intersect(ray, f32::INFINITY, &mut s);
            (h.map(|h| h.t), bvh.occluded(ray, *t_max, &mut s))
        })
        .collect();
    assert!(want.iter().filter(|w| w.0.is_some()).count() > 300);
    for &name in appel::accel::AccelKind::NAMES
        .iter()
        .filter(|&&n| n != "brute" && n != "bvh")
    {
        let other = scene(name);
        for ((ray, t_max), &(t, occluded)) in rays.iter().zip(&want) {
            let got = other.intersect(ray, f32::INFINITY, &mut s);
            assert_eq!(got.map(|h| h.t), t, "{name} {ray:?}");
            assert_eq!(
                other.occluded(ray, *t_max, &mut s),
                occluded,
                "{name} {ray:?} {t_max}"
            );
        }
    }
}

fn compare(a: &appel::render::Film, b: &appel::render::Film) -> (f32, f32) {
    let diffs: Vec<f32> = a
        .rgb
        .iter()
        .zip(&b.rgb)
        .map(|(x, y)| (*x - *y).abs().max_element())
        .collect();
    let mean = diffs.iter().sum::<f32>() / diffs.len() as f32;
    let bad = diffs.iter().filter(|&&d| d > 2.0 / 255.0).count() as f32 / diffs.len() as f32;
    (mean, bad)
}

#[test]
fn a_rotated_scaled_instance_renders_the_same_at_any_scale() {
    let dir = tempfile::tempdir().unwrap();
    write_mesh(dir.path());
    let d = parse(&scene_text(true));
    let render = |d: &Description| {
        let scene = Scene::new(d, dir.path()).unwrap();
        appel::render::render(&scene, &Default::default())
            .unwrap()
            .0
    };
    let reference = render(&d);
    // Shadow acne would darken lit pixels of the instance: check that most of it is lit.
    let lit = (0..reference.rgb.len())
        .filter(|&i| reference.shape_id[i] == 1 && luminance(reference.rgb[i]) > 0.3)
        .count();
    let on = reference.shape_id.iter().filter(|&&s| s == 1).count();
    assert!(lit * 2 > on, "{lit} of {on} instance pixels lit");
    for s in [1e-3f32, 1e4] {
        let scaled = render(&d.scaled(s));
        let (mean, bad) = compare(&reference, &scaled);
        assert!(
            mean < 2e-3 && bad < 0.01,
            "scale {s}: mean difference {mean}, {:.2}% of pixels differ",
            bad * 100.0
        );
    }
}

#[test]
fn instanceid_numbers_placements_in_file_order() {
    let dir = tempfile::tempdir().unwrap();
    write_mesh(dir.path());
    // Five placements along x: one inline, then four from a list; seen from the front, left to
    // right. A `[[shape]]` sphere after them keeps its own id and reports no instance.
    let list: String = (1..5)
        .map(|k| {
            let t = glam::Mat4::from_translation(Vec3::new(-6.0 + 3.0 * k as f32, 0.0, 0.0));
            appel::io::placements::placement_line(&t)
        })
        .collect();
    std::fs::write(dir.path().join("row.txt"), format!("# four\n{list}")).unwrap();
    let text = r#"
        [camera]
        eye = [0.0, 0.0, 30.0]
        look_at = [0.0, 0.0, 0.0]
        fov = 40.0
        width = 200
        height = 60

        [meshes.lump]
        file = "m.ply"

        [[shape]]
        type = "sphere"
        center = [0.0, 5.0, 0.0]
        radius = 1.0

        [[instance]]
        mesh = "lump"
        transform = { translate = [-6.0, 0.0, 0.0] }

        [[instance]]
        mesh = "lump"
        placements = "row.txt"
    "#;
    let scene = Scene::new(&parse(text), dir.path()).unwrap();
    let (film, _) = appel::render::render(&scene, &Default::default()).unwrap();
    let mut seen = vec![];
    let y = 30;
    for x in 0..film.width {
        let i = film.index(x, y);
        let id = film.instance_id[i];
        if id != MISS_ID && seen.last() != Some(&id) {
            seen.push(id);
            // Entry 0 is `[[shape]]` 0 (the sphere); the instance entries are shapes 1 and 2.
            assert_eq!(film.shape_id[i], if id == 0 { 1 } else { 2 });
        }
    }
    assert_eq!(seen, vec![0, 1, 2, 3, 4]);
    let top = film.index(100, 16);
    assert_eq!(
        (film.shape_id[top], film.instance_id[top]),
        (0, MISS_ID),
        "the sphere"
    );
}

#[test]
fn many_instances_share_one_copy_of_the_mesh() {
    // A million placements of a 5,120-triangle mesh: five billion triangles as rendered (60 GB as
    // a flat mesh, more than this machine has), one copy stored.
    let dir = tempfile::tempdir().unwrap();
    appel::output::write_ply(&dir.path().join("s.ply"), &[(0, &icosphere(4))]).unwrap();
    let mut list = String::new();
    for i in 0..1_000_000u32 {
        let (x, z) = ((i % 1000) as f32, (i / 1000) as f32);
        let m = glam::Mat4::from_scale_rotation_translation(
            Vec3::splat(0.4),
            glam::Quat::IDENTITY,
            Vec3::new(x - 500.0, 0.0, -z),
        );
        list.push_str(&appel::io::placements::placement_line(&m));
    }
    std::fs::write(dir.path().join("grid.txt"), list).unwrap();
    let text = r#"
        [camera]
        eye = [0.0, 20.0, 30.0]
        look_at = [0.0, 0.0, -100.0]
        width = 64
        height = 48
        [meshes.ball]
        file = "s.ply"
        [[instance]]
        mesh = "ball"
        placements = "grid.txt"
        [[light]]
        type = "directional"
        direction = [-1.0, -2.0, -1.0]
    "#;
    let scene = Scene::new(&parse(text), dir.path()).unwrap();
    assert_eq!(scene.geometry.triangle_count(), 5120);
    assert_eq!(scene.geometry.instanced_triangle_count(), 5_120_000_000);
    assert_eq!(scene.geometry.prims.len(), 1_000_000);
    let (film, _) = appel::render::render(&scene, &Default::default()).unwrap();
    let ids: std::collections::HashSet<u32> = film.instance_id.iter().copied().collect();
    assert!(ids.len() > 50, "{} distinct instances seen", ids.len());
}

#[test]
fn bad_instance_entries_are_located() {
    let dir = tempfile::tempdir().unwrap();
    write_mesh(dir.path());
    let head = "[camera]\neye = [0.0, 0.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n\n[meshes.lump]\nfile = \"m.ply\"\n\n";
    let err = |body: &str| {
        let path = dir.path().join("s.toml");
        std::fs::write(&path, format!("{head}{body}")).unwrap();
        match appel::format::load(&path, &Default::default())
            .and_then(|l| Scene::new(&l.description, &l.base_dir))
        {
            Ok(_) => panic!("accepted: {body}"),
            Err(e) => e.to_string().replace(&dir.path().display().to_string(), ""),
        }
    };
    let e = err("[[instance]]\nmesh = \"lumpy\"\n");
    assert!(
        e.starts_with(
            "/s.toml:9:8: instance[0].mesh: unknown mesh `lumpy`; the scene defines: lump"
        ),
        "{e}"
    );
    let e = err("[[instance]]\nmesh = \"lump\"\ntransform = { scale = [1.0, 0.0, 1.0] }\n");
    assert!(
        e.starts_with("/s.toml:10:23: instance[0].transform.scale: `scale` must not be zero"),
        "{e}"
    );
    let e = err("[[instance]]\nmesh = \"lump\"\ntransform = { scale = 1e-30 }\n");
    assert!(
        e.starts_with("/s.toml:10:13: instance[0].transform: the transform is not invertible"),
        "{e}"
    );
    let e = err("[[instance]]\nmesh = \"lump\"\ntransform = { translate = [0.0, 1.0] }\n");
    assert!(e.starts_with("/s.toml:10:"), "{e}");
    let e = err("[[instance]]\nmesh = \"lump\"\nplacement = \"p.txt\"\n");
    assert!(
        e.starts_with("/s.toml:10:1: unknown field `placement`"),
        "{e}"
    );
    let e = err("[[instance]]\nmesh = \"lump\"\nplacements = \"nowhere.txt\"\n");
    assert!(
        e.starts_with("/s.toml:10:14: instance[0].placements: the placement list"),
        "{e}"
    );
    std::fs::write(
        dir.path().join("p.txt"),
        "1 0 0 0 0 1 0 0 0 0 1 0\n0 0 0 0 0 0 0 0 0 0 0 0\n",
    )
    .unwrap();
    let e = err("[[instance]]\nmesh = \"lump\"\nplacements = \"p.txt\"\n");
    assert!(
        e.starts_with("/p.txt:2: the placement's matrix is not invertible"),
        "{e}"
    );
    std::fs::write(
        dir.path().join("far.txt"),
        "1 0 0 3.4028234e38 0 1 0 0 0 0 1 0\n",
    )
    .unwrap();
    let e = err("[[instance]]\nmesh = \"lump\"\nplacements = \"far.txt\"\n");
    assert!(
        e.starts_with("/far.txt:1: the placement moves the mesh beyond the range of f32"),
        "{e}"
    );
    let e = err("[meshes.other]\nfile = \"missing.ply\"\n");
    assert!(
        e.starts_with("/s.toml:9:8: meshes.other.file: the mesh file"),
        "{e}"
    );
}
