use super::description::CameraDesc;
use crate::math::{Ray, Vec3};

/// A pinhole camera with Appel's exact pixel convention (README, "Camera"): for pixel column `i` (0 at
/// the left) and row `j` (0 at the top) of a `W x H` image,
/// `u = (2(i+0.5)/W - 1) tan(fov/2) W/H`, `v = (1 - 2(j+0.5)/H) tan(fov/2)` and the direction is
/// `normalize(forward + u right + v true_up)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub forward: Vec3,
    pub right: Vec3,
    pub true_up: Vec3,
    pub tan_half_fov: f32,
    pub width: u32,
    pub height: u32,
}

impl Camera {
    pub fn new(d: &CameraDesc) -> Self {
        let eye = Vec3::from(d.eye);
        let forward = (Vec3::from(d.look_at) - eye).normalize();
        let right = forward.cross(Vec3::from(d.up)).normalize();
        let true_up = right.cross(forward);
        Self {
            eye,
            forward,
            right,
            true_up,
            tan_half_fov: (d.fov.to_radians() * 0.5).tan(),
            width: d.width,
            height: d.height,
        }
    }

    /// The ray through the continuous film position `(x, y)` in pixels: pixel `(i, j)`'s centre is
    /// `(i + 0.5, j + 0.5)`.
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let (w, h) = (self.width as f32, self.height as f32);
        let t = self.tan_half_fov;
        let u = (2.0 * x / w - 1.0) * t * w / h;
        let v = (1.0 - 2.0 * y / h) * t;
        Ray::new(
            self.eye,
            (self.forward + u * self.right + v * self.true_up).normalize(),
        )
    }

    /// The ray through the centre of pixel `(i, j)`.
    pub fn pixel_ray(&self, i: u32, j: u32) -> Ray {
        self.ray(i as f32 + 0.5, j as f32 + 0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(w: u32, h: u32) -> Camera {
        Camera::new(&CameraDesc {
            eye: [0.0, 1.0, 5.0],
            look_at: [0.0, 1.0, 0.0],
            up: [0.0, 1.0, 0.0],
            fov: 90.0,
            width: w,
            height: h,
        })
    }

    #[test]
    fn centre_ray_looks_at_the_target() {
        // With an odd size the middle pixel's centre is the image centre.
        let d = cam(3, 3).pixel_ray(1, 1).dir;
        assert!((d - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
    }

    #[test]
    fn corner_rays_follow_the_convention() {
        let c = cam(4, 2);
        let t = (45.0f32).to_radians().tan();
        // Top-left pixel: u = (2*0.5/4 - 1) * t * 2, v = (1 - 2*0.5/2) * t.
        let (u, v) = ((0.25 - 1.0) * t * 2.0, 0.5 * t);
        let expected = (Vec3::new(0.0, 0.0, -1.0) + u * Vec3::X + v * Vec3::Y).normalize();
        assert!((c.pixel_ray(0, 0).dir - expected).length() < 1e-6);
        // Bottom-right is its mirror image.
        let br = c.pixel_ray(3, 1).dir;
        assert!((br - Vec3::new(-expected.x, -expected.y, expected.z)).length() < 1e-6);
        // Right is +x when looking down -z with y up; top is +y.
        assert!(c.right.x > 0.99 && c.true_up.y > 0.99);
    }
}
