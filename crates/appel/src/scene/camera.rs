use crate::description::{CameraDesc, CameraKind, FovAxis};
use crate::math::{Ray, Vec3};

/// A pinhole or orthographic camera with Appel's exact pixel convention (README, "Camera"): for
/// pixel column `i` (0 at the left) and row `j` (0 at the top) of a `W x H` image,
/// `u = (2(i+0.5)/W - 1) tan(fov/2) W/H`, `v = (1 - 2(j+0.5)/H) tan(fov/2)` and the direction is
/// `normalize(forward + u right + v true_up)`, `fov` being the vertical field of view. Other
/// `fov_axis` choices become the equivalent vertical `tan(fov/2)`, so that the expression (and its
/// rounding) stays the same. An orthographic camera puts the origin at `eye + u right + v true_up`
/// with `tan(fov/2)` replaced by `half_width H/W`, and looks along `forward`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub kind: CameraKind,
    pub eye: Vec3,
    pub forward: Vec3,
    pub right: Vec3,
    pub true_up: Vec3,
    /// The tangent of half the vertical field of view (orthographic: half the view's height).
    pub tan_half_fov: f32,
    /// Rays start this far along the view axis.
    pub near_clip: f32,
    pub width: u32,
    pub height: u32,
}

impl Camera {
    pub fn new(d: &CameraDesc) -> Self {
        let eye = Vec3::from(d.eye);
        let forward = (Vec3::from(d.look_at) - eye).normalize();
        let right = forward.cross(Vec3::from(d.up)).normalize();
        let true_up = right.cross(forward);
        let (w, h) = (d.width as f32, d.height as f32);
        let tan_half_fov = match d.kind {
            CameraKind::Perspective => {
                let t = (d.fov.to_radians() * 0.5).tan();
                // The axis the field of view spans, in units of the image's height.
                let axis = match d.fov_axis {
                    FovAxis::Y => return Self::with(d, eye, forward, right, true_up, t),
                    FovAxis::X => w,
                    FovAxis::Diagonal => w.hypot(h),
                    FovAxis::Smaller => w.min(h),
                    FovAxis::Larger => w.max(h),
                };
                t * h / axis
            }
            CameraKind::Orthographic => d.half_width.unwrap_or(1.0) * h / w,
        };
        Self::with(d, eye, forward, right, true_up, tan_half_fov)
    }

    fn with(
        d: &CameraDesc,
        eye: Vec3,
        forward: Vec3,
        right: Vec3,
        true_up: Vec3,
        tan_half_fov: f32,
    ) -> Self {
        Self {
            kind: d.kind,
            eye,
            forward,
            right,
            true_up,
            tan_half_fov,
            near_clip: d.near_clip,
            width: d.width,
            height: d.height,
        }
    }

    /// The ray through the continuous film position `(x, y)` in pixels: pixel `(i, j)`'s centre is
    /// `(i + 0.5, j + 0.5)`.
    #[inline(always)]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let (w, h) = (self.width as f32, self.height as f32);
        let t = self.tan_half_fov;
        let u = (2.0 * x / w - 1.0) * t * w / h;
        let v = (1.0 - 2.0 * y / h) * t;
        match self.kind {
            CameraKind::Perspective => {
                let dir = (self.forward + u * self.right + v * self.true_up).normalize();
                if self.near_clip > 0.0 {
                    let o = self.eye + dir * (self.near_clip / dir.dot(self.forward));
                    return Ray::new(o, dir);
                }
                Ray::new(self.eye, dir)
            }
            CameraKind::Orthographic => Ray::new(
                self.eye + u * self.right + v * self.true_up + self.near_clip * self.forward,
                self.forward,
            ),
        }
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
            ..CameraDesc::default()
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

    #[test]
    fn fov_axes_span_their_image_axis() {
        let at = |axis, w, h| {
            let c = Camera::new(&CameraDesc {
                eye: [0.0; 3],
                look_at: [0.0, 0.0, -1.0],
                fov: 60.0,
                fov_axis: axis,
                width: w,
                height: h,
                ..CameraDesc::default()
            });
            // The film's edges, where the rays make half the field of view with the axis.
            let half = |d: Vec3| d.angle_between(c.forward).to_degrees();
            (
                half(c.ray(0.0, h as f32 / 2.0).dir),
                half(c.ray(w as f32 / 2.0, 0.0).dir),
                half(c.ray(0.0, 0.0).dir),
            )
        };
        let close = |a: f32, b: f32| (a - b).abs() < 1e-3;
        let (x, _, _) = at(FovAxis::X, 200, 100);
        assert!(close(x, 30.0), "{x}");
        let (_, y, _) = at(FovAxis::Y, 200, 100);
        assert!(close(y, 30.0), "{y}");
        let (_, _, diag) = at(FovAxis::Diagonal, 200, 100);
        assert!(close(diag, 30.0), "{diag}");
        let (_, small, _) = at(FovAxis::Smaller, 200, 100);
        assert!(close(small, 30.0), "{small}");
        let (large, _, _) = at(FovAxis::Larger, 200, 100);
        assert!(close(large, 30.0), "{large}");
    }

    #[test]
    fn orthographic_rays_are_parallel_and_span_the_half_width() {
        let c = Camera::new(&CameraDesc {
            kind: CameraKind::Orthographic,
            eye: [0.0, 0.0, 5.0],
            look_at: [0.0; 3],
            half_width: Some(2.0),
            width: 40,
            height: 20,
            ..CameraDesc::default()
        });
        let left = c.ray(0.0, 10.0);
        let top = c.ray(20.0, 0.0);
        assert_eq!(left.dir, Vec3::new(0.0, 0.0, -1.0));
        assert!((left.origin - Vec3::new(-2.0, 0.0, 5.0)).length() < 1e-6);
        assert!((top.origin - Vec3::new(0.0, 1.0, 5.0)).length() < 1e-6);
    }
}
