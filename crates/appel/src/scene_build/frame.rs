//! A scene for a bare mesh file (`appel render model.ply`): one mesh shape, viewed as
//! [`crate::description::framing`] says once the built scene's bounds are known.

pub use crate::description::framing::frame_model;
use crate::description::framing::{view_file, FileView};
use crate::description::{CameraDesc, Description, MeshShapeDesc, ShapeDesc};
use crate::math::{Aabb, Vec3};

/// How a loaded mesh file (`base` from [`model_description`]) is viewed: see
/// [`view_file`], with the bounds, lights, cameras and materials the built scene holds.
pub fn view_model(
    scene: &crate::scene::Scene,
    base: &Description,
    camera: Option<usize>,
) -> crate::error::Result<Description> {
    use crate::error::Error;
    let files = &scene.from_files;
    let file = FileView {
        lights: &files.lights,
        cameras: &files.cameras,
        physically_based: files.physically_based,
    };
    let framed = view_file(base, scene.geometry.bounds(), &file, camera).map_err(Error::Invalid)?;
    // A view that does not validate comes from the file (a camera or light whose values make no
    // sense, bounds too large to frame): say so at the file rather than as a bad setting.
    crate::description::validate::validate(&framed).map_err(|invalid| {
        let file = base
            .shapes
            .iter()
            .find_map(|s| match s {
                ShapeDesc::Mesh(m) => Some(m.file.clone()),
                _ => None,
            })
            .unwrap_or_default();
        Error::input(
            crate::error::Location::file(file),
            format!("the model cannot be viewed: {}", invalid.message),
        )
    })?;
    Ok(framed)
}

/// A scene with one mesh shape, `file` relative to the scene's base folder, not yet framed: the
/// camera looks at the unit cube at the origin until [`frame_model`] is given the real bounds.
pub fn model_description(file: &str) -> Description {
    let base = Description {
        camera: CameraDesc {
            eye: [0.0, 0.0, 5.0],
            look_at: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            fov: 45.0,
            width: 640,
            height: 480,
            ..CameraDesc::default()
        },
        render: Default::default(),
        environment: Default::default(),
        materials: Default::default(),
        meshes: Default::default(),
        instances: vec![],
        shapes: vec![ShapeDesc::Mesh(MeshShapeDesc {
            file: file.into(),
            ..Default::default()
        })],
        lights: vec![],
        media: Default::default(),
        animation: None,
    };
    frame_model(&base, Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;

    /// Every corner of the box must project inside the image, and the box must fill a good part of
    /// it (the framing is tight, not just safe).
    #[test]
    fn framed_box_is_inside_the_image_and_fills_it() {
        for (min, max, w, h) in [
            (Vec3::new(-1.0, -2.0, 0.5), Vec3::new(3.0, 0.0, 0.7), 64, 48),
            (
                Vec3::new(100.0, 0.0, 0.0),
                Vec3::new(100.001, 0.002, 0.001),
                48,
                64,
            ),
        ] {
            let mut base = model_description("x.ply");
            base.camera.width = w;
            base.camera.height = h;
            let d = frame_model(&base, Aabb::new(min, max));
            let cam = Camera::new(&d.camera);
            let eye = Vec3::from(d.camera.eye);
            let forward = (Vec3::from(d.camera.look_at) - eye).normalize();
            let right = forward.cross(Vec3::Y).normalize();
            let up = right.cross(forward);
            let tan_v = (d.camera.fov.to_radians() / 2.0).tan();
            let tan_h = tan_v * w as f32 / h as f32;
            let mut max_ndc: f32 = 0.0;
            for i in 0..8 {
                let c = Vec3::new(
                    if i & 1 == 0 { min.x } else { max.x },
                    if i & 2 == 0 { min.y } else { max.y },
                    if i & 4 == 0 { min.z } else { max.z },
                );
                let v = c - eye;
                let z = v.dot(forward);
                assert!(z > 0.0);
                let x = v.dot(right) / z / tan_h;
                let y = v.dot(up) / z / tan_v;
                max_ndc = max_ndc.max(x.abs()).max(y.abs());
            }
            assert!(max_ndc < 1.0, "corner outside the image: {max_ndc}");
            assert!(max_ndc > 0.4, "model too small in frame: {max_ndc}");
            let _ = cam;
        }
    }
}
