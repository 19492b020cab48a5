//! How a scene that brings only geometry (a bare mesh file), or geometry with its own cameras and
//! lights (a glTF file), is viewed: the camera, lights and background that show the model whole,
//! and the file's own cameras and lights where it has them.

use super::loaded_mesh::FileCamera;
use super::{CameraDesc, Description, IntegratorName, LightDesc};
use super::{ConstantDesc, DirectionalDesc, PointDesc};
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

/// Samples per pixel of a mesh file with physically based materials, path traced: enough for a
/// clean preview of a textured model.
pub const MODEL_SPP: u32 = 32;

/// Path length for mesh files with physically based materials (a few bounces of indirect light).
pub const MODEL_MAX_DEPTH: i32 = 6;

/// Radiance of the uniform sky around a mesh file with physically based materials and no lights of
/// its own: a white diffuse surface under it alone comes out at this value.
pub const MODEL_SKY: f32 = 0.5;

/// What a file brings to its view besides its bounds: its lights and cameras (world space), and
/// whether its materials are physically based.
pub struct FileView<'a> {
    pub lights: &'a [LightDesc],
    pub cameras: &'a [FileCamera],
    pub physically_based: bool,
}

/// How a file's model is viewed: framed automatically, or through the file's camera `camera` (its
/// first by default); lit by the file's lights if it has any, else by the framing's. A file with
/// physically based materials is path traced, as its author meant it to be seen, under a uniform
/// grey sky if it brings no lights (metals show what they reflect: without an environment they
/// would mirror black). An error names a camera the file does not have.
pub fn view_file(
    base: &Description,
    bounds: Aabb,
    file: &FileView,
    camera: Option<usize>,
) -> Result<Description, String> {
    let mut framed = frame_model(base, bounds);
    if file.physically_based {
        framed.render.integrator = IntegratorName::Path;
        framed.render.spp = MODEL_SPP;
        framed.render.max_depth = MODEL_MAX_DEPTH;
    }
    if !file.lights.is_empty() {
        framed.lights = file.lights.to_vec();
    } else if file.physically_based {
        framed.lights.push(LightDesc::Constant(ConstantDesc {
            radiance: [MODEL_SKY; 3],
        }));
    }
    if let Some(c) = pick_camera(file.cameras, camera)? {
        view_through(&mut framed, c);
    }
    Ok(framed)
}

/// The file's camera `camera` (its first by default), or `None` for a file without cameras when
/// none was asked for.
pub fn pick_camera(
    cameras: &[FileCamera],
    camera: Option<usize>,
) -> Result<Option<&FileCamera>, String> {
    let count = cameras.len();
    match (camera, count) {
        (None, 0) => Ok(None),
        (None, _) => Ok(cameras.first()),
        (Some(_), 0) => Err("the file has no cameras".into()),
        (Some(n), _) if n >= count => Err(format!(
            "there is no camera {n}: the file has {count} ({})",
            cameras
                .iter()
                .enumerate()
                .map(|(i, c)| format!("{i}: {}", c.name))
                .collect::<Vec<_>>()
                .join(", ")
        )),
        (Some(n), _) => Ok(cameras.get(n)),
    }
}

/// Views `d` through a file's camera, keeping the image width and deriving the height from the
/// aspect ratio the file asks for, if any.
pub fn view_through(d: &mut Description, c: &FileCamera) {
    let (width, height) = (d.camera.width, d.camera.height);
    d.camera = CameraDesc {
        width,
        height: c
            .aspect
            .map_or(height, |a| ((width as f32 / a).round() as u32).max(1)),
        ..c.camera.clone()
    };
}
