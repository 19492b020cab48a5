//! A scene for a bare mesh file (`appel render model.ply`): the camera, lights and background that
//! show the model whole.

use crate::description::{CameraDesc, Description, LightDesc, MeshShapeDesc, ShapeDesc};
use crate::description::{ConstantDesc, DirectionalDesc, PointDesc};
use crate::math::{Aabb, Vec3};

/// The direction from the model's centre to the camera: a diagonal from the front right, above.
const VIEW_DIAGONAL: Vec3 = Vec3::new(1.0, 0.75, 1.25);

/// Camera and lights that frame `bounds`: the camera sits on a diagonal and looks at the box's
/// centre, at the smallest distance where all eight corners of the box project inside the image
/// with a 5% margin (never closer than the bounding sphere's radius, so the camera stays outside). Lighting: a point
/// light beside the camera, scaled so the irradiance at the model is about 1 whatever its size, and
/// a dim directional light from above for the shadowed sides. `fov`, `width` and `height` are kept
/// from `base`, so that command-line overrides of the size feed into the framing.
pub fn frame_model(base: &Description, bounds: Aabb) -> Description {
    let (center, radius) = if bounds.is_empty() || !bounds.extent().is_finite() {
        (Vec3::ZERO, 1.0)
    } else {
        let r = 0.5 * bounds.extent().length();
        (bounds.center(), if r > 0.0 { r } else { 1.0 })
    };
    let cam = &base.camera;
    let half_v = (cam.fov.to_radians() * 0.5).clamp(1e-3, 1.5);
    let aspect = cam.width.max(1) as f32 / cam.height.max(1) as f32;
    let half_h = (half_v.tan() * aspect).atan();
    let up = Vec3::Y;
    let back = VIEW_DIAGONAL.normalize();
    let (fwd, right) = (-back, (-back).cross(up).normalize());
    let cam_up = right.cross(fwd);
    // Corner o (relative to the centre) at camera distance D lies at depth D + o.fwd; it is in view
    // when |o.right| <= tan_h (D + o.fwd) and |o.up| <= tan_v (D + o.fwd).
    let (tan_v, tan_h) = (half_v.tan() / 1.05, half_h.tan() / 1.05);
    let ext = if bounds.is_empty() {
        Vec3::ONE
    } else {
        0.5 * bounds.extent()
    };
    let mut distance = radius * 1.01;
    for i in 0..8 {
        let o = Vec3::new(
            if i & 1 == 0 { -ext.x } else { ext.x },
            if i & 2 == 0 { -ext.y } else { ext.y },
            if i & 4 == 0 { -ext.z } else { ext.z },
        );
        let need_h = o.dot(right).abs() / tan_h - o.dot(fwd);
        let need_v = o.dot(cam_up).abs() / tan_v - o.dot(fwd);
        distance = distance.max(need_h).max(need_v);
    }
    let eye = center + back * distance;
    let mut d = base.clone();
    d.camera = CameraDesc {
        eye: eye.into(),
        look_at: center.into(),
        up: up.into(),
        ..cam.clone()
    };
    // Beside the camera (up and to the left) so that shading shows the shape.
    let right = (center - eye).cross(up).normalize_or_zero();
    let light_pos = eye + (0.3 * up - 0.3 * right) * distance;
    let light_distance = (light_pos - center).length();
    d.lights = vec![
        LightDesc::Point(PointDesc {
            position: light_pos.into(),
            color: [1.0; 3],
            // Irradiance 0.55 at the model's centre: lit faces of an albedo-0.8 surface come out at
            // about 0.5 linear, mid-grey in sRGB, leaving room for the highlights of brighter albedos.
            intensity: 0.55 * light_distance * light_distance,
        }),
        LightDesc::Directional(DirectionalDesc {
            direction: [-0.3, -1.0, -0.2],
            color: [1.0; 3],
            intensity: 0.15,
        }),
    ];
    d.environment.background = [0.15, 0.15, 0.17];
    d
}

/// A scene with one mesh shape, `file` relative to the scene's base folder, not yet framed: the
/// camera looks at the unit cube at the origin until [`frame_model`] is given the real bounds.
/// Samples per pixel of a mesh file with physically based materials, path traced: enough for a
/// clean preview of a textured model.
pub const MODEL_SPP: u32 = 32;

/// Path length for mesh files with physically based materials (a few bounces of indirect light).
pub const MODEL_MAX_DEPTH: i32 = 6;

/// Radiance of the uniform sky around a mesh file with physically based materials and no lights of
/// its own: a white diffuse surface under it alone comes out at this value.
pub const MODEL_SKY: f32 = 0.5;

/// How a loaded mesh file (`base` from [`model_description`]) is viewed: framed automatically, or
/// through the file's camera `camera` (its first by default); lit by the file's lights if it has
/// any, else by the framing's. A file with physically based materials is path traced, as its
/// author meant it to be seen, under a uniform grey sky if it brings no lights (metals show what
/// they reflect: without an environment they would mirror black).
pub fn view_model(
    scene: &crate::scene::Scene,
    base: &Description,
    camera: Option<usize>,
) -> crate::error::Result<Description> {
    use crate::error::Error;
    let files = &scene.from_files;
    let mut framed = frame_model(base, scene.geometry.bounds());
    if files.physically_based {
        framed.render.integrator = crate::scene::IntegratorKind::Path;
        framed.render.spp = MODEL_SPP;
        framed.render.max_depth = MODEL_MAX_DEPTH;
    }
    if !files.lights.is_empty() {
        framed.lights = files.lights.clone();
    } else if files.physically_based {
        framed.lights.push(LightDesc::Constant(ConstantDesc {
            radiance: [MODEL_SKY; 3],
        }));
    }
    let count = files.cameras.len();
    let chosen = match (camera, count) {
        (None, 0) => None,
        (None, _) => Some(0),
        (Some(_), 0) => return Err(Error::Invalid("the file has no cameras".into())),
        (Some(n), _) if n >= count => {
            return Err(Error::Invalid(format!(
                "there is no camera {n}: the file has {count} ({})",
                files
                    .cameras
                    .iter()
                    .enumerate()
                    .map(|(i, c)| format!("{i}: {}", c.name))
                    .collect::<Vec<_>>()
                    .join(", ")
            )))
        }
        (Some(n), _) => Some(n),
    };
    if let Some(c) = chosen.map(|i| &files.cameras[i]) {
        let (width, height) = (framed.camera.width, framed.camera.height);
        framed.camera = CameraDesc {
            width,
            height: c
                .aspect
                .map_or(height, |a| ((width as f32 / a).round() as u32).max(1)),
            ..c.camera.clone()
        };
    }
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
