//! Animated scenes: a frame reached by refitting the previous frames' structures renders
//! bit-identically to the same frame built alone, for the refitted declared mesh (the flag of
//! `appel gen cloth`, under a rebuilt top level over keyframed instances), for a refitted top
//! level (the flag as a `[[shape]]`), and for structures that are rebuilt every frame.

use appel::description::animation::at_frame;
use appel::description::Description;
use appel::render::{render, Film, RenderOptions};
use appel::scene::{Scene, Sequence};
use appel_gen::{cloth_scene, GenOptions};
use std::path::Path;

fn image(scene: &Scene) -> Film {
    render(scene, &RenderOptions::default()).unwrap().0
}

/// The film's colours and first-hit ids, as bits.
fn bits(f: &Film) -> (Vec<[u32; 3]>, Vec<u32>, Vec<u32>, Vec<u32>) {
    (
        f.rgb
            .iter()
            .map(|c| c.to_array().map(f32::to_bits))
            .collect(),
        f.shape_id.clone(),
        f.prim_id.clone(),
        f.instance_id.clone(),
    )
}

/// The generated cloth scene, small, in `dir`; `edit` rewrites its text.
fn cloth(dir: &Path, edit: impl Fn(String) -> String) -> Description {
    let options = GenOptions {
        detail: 0.1,
        ..Default::default()
    };
    cloth_scene(dir, &options, &|_| Ok(())).unwrap();
    let path = dir.join("cloth.toml");
    let text = edit(std::fs::read_to_string(&path).unwrap());
    std::fs::write(&path, text).unwrap();
    let mut d = appel::format::load(&path, &Default::default())
        .unwrap()
        .description;
    d.camera.width = 96;
    d.camera.height = 72;
    d
}

/// Steps a sequence through `frames` and checks each against the frame built alone; returns the
/// structures refitted over the steps.
fn sequence_matches_frames_alone(d: &Description, dir: &Path, frames: &[u32]) -> usize {
    let mut seq = Sequence::new(d, dir, frames[0]).unwrap();
    let mut refitted = 0;
    for &k in frames {
        if k != seq.frame {
            let u = seq.advance(k).unwrap();
            refitted += u.refitted;
        }
        let alone = Scene::new(&at_frame(d, k), dir).unwrap();
        let (a, b) = (image(&seq.scene), image(&alone));
        let hit = b.shape_id.iter().filter(|&&s| s != u32::MAX).count();
        assert!(
            hit > 1000,
            "frame {k}: the flag and ground fill the view ({hit})"
        );
        assert!(bits(&a) == bits(&b), "frame {k} differs after refits");
    }
    refitted
}

#[test]
fn refitted_frames_are_bit_identical_to_frames_built_alone() {
    let dir = tempfile::tempdir().unwrap();
    let d = cloth(dir.path(), |t| t);
    // Frames in order, then a jump: the flag's structure is refitted at each step.
    let refitted = sequence_matches_frames_alone(&d, dir.path(), &[0, 1, 2, 3, 9, 30]);
    assert!(refitted >= 5, "{refitted} refits");
    // The frames differ (the flag waves, the birds fly): the check is not of one image.
    let (f0, f9) = (
        image(&Scene::new(&at_frame(&d, 0), dir.path()).unwrap()),
        image(&Scene::new(&at_frame(&d, 9), dir.path()).unwrap()),
    );
    assert!(bits(&f0) != bits(&f9));
}

#[test]
fn a_refitted_top_level_gives_the_frames_built_alone() {
    let dir = tempfile::tempdir().unwrap();
    // The flag as a `[[shape]]` and no birds: its triangles sit in the top level, which refits.
    let d = cloth(dir.path(), |t| {
        let t = t.replace(
            "[[instance]]\nmesh = \"flag\"\n",
            "[[shape]]\ntype = \"mesh\"\nfile = \"wave_{frame:04}.ply\"\nmaterial = \"flag\"\n",
        );
        t[..t.find("\n[[instance]]\nmesh = \"bird\"").unwrap()].to_string()
    });
    assert!(d.instances.is_empty());
    let refitted = sequence_matches_frames_alone(&d, dir.path(), &[4, 5, 6, 20]);
    assert!(refitted >= 2, "{refitted} refits");
}

#[test]
fn structures_rebuilt_each_frame_give_the_frames_built_alone() {
    let dir = tempfile::tempdir().unwrap();
    let mut d = cloth(dir.path(), |t| t);
    d.render.accel = "kdtree".into();
    let mut seq = Sequence::new(&d, dir.path(), 0).unwrap();
    let u = seq.advance(7).unwrap();
    assert_eq!((u.refitted, u.sah_drift), (0, None));
    assert_eq!(u.rebuilt, 2, "the flag's kd-tree and the top level");
    let alone = Scene::new(&at_frame(&d, 7), dir.path()).unwrap();
    assert!(bits(&image(&seq.scene)) == bits(&image(&alone)));
}

/// The first frame is a build: it reports every structure built from scratch (the flag's and the
/// top level's; the bird is a declared mesh too) and the time the scene's build took, as
/// `appel bench --frames --json` prints for frame 0.
#[test]
fn the_first_frame_reports_its_structures_built() {
    let dir = tempfile::tempdir().unwrap();
    let d = cloth(dir.path(), |t| t);
    let seq = Sequence::new(&d, dir.path(), 3).unwrap();
    let u = &seq.first_build;
    let declared = seq.scene.geometry.prototypes.len();
    assert!(declared >= 1);
    assert_eq!(u.frame, 3);
    assert_eq!(u.rebuilt, declared + 1);
    assert_eq!((u.refitted, u.rebuilt_by_policy, u.sah_drift), (0, 0, None));
    assert_eq!(u.rebuild, seq.scene.timings.build);
    assert!(u.rebuild > std::time::Duration::ZERO);
}
