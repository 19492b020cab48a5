use crate::description::{CameraDesc, CameraKind, FovAxis};
use crate::math::{Ray, Vec2, Vec3};
use crate::shading::bsdf::warp::square_to_uniform_disk_concentric;

/// A pinhole or orthographic camera with Appel's exact pixel convention (README, "Camera"): for
/// pixel column `i` (0 at the left) and row `j` (0 at the top) of a `W x H` image,
/// `u = (2(i+0.5)/W - 1) tan(fov/2) W/H`, `v = (1 - 2(j+0.5)/H) tan(fov/2)` and the direction is
/// `normalize(forward + u right + v true_up)`, `fov` being the vertical field of view. Other
/// `fov_axis` choices become the equivalent vertical `tan(fov/2)`, so that the expression (and its
/// rounding) stays the same. An orthographic camera puts the origin at `eye + u right + v true_up`
/// with `tan(fov/2)` replaced by `half_width H/W`, and looks along `forward`.
///
/// With an aperture (`lens_radius > 0`) either kind is a thin lens (pbrt-v4 section 5.2.3,
/// Mitsuba 3's `thinlens`): [`Camera::ray_through_lens`] starts the ray at a point of the lens
/// disk, in the plane through `eye` facing `forward`, and aims it at the point where the pinhole
/// ray meets the plane in focus, `focus_distance` along the view axis.
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
    /// The radius of the lens's aperture in scene units: 0 is a pinhole.
    pub lens_radius: f32,
    /// The distance along the view axis from the lens to the plane in focus.
    pub focus_distance: f32,
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
            lens_radius: d.aperture_radius,
            focus_distance: d.focus_distance(),
            width: d.width,
            height: d.height,
        }
    }

    /// The ray through the continuous film position `(x, y)` in pixels: pixel `(i, j)`'s centre is
    /// `(i + 0.5, j + 0.5)`.
    #[inline(always)]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let (u, v) = self.film_uv(x, y);
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

    /// The film position `(x, y)` in pixels as `(u, v)`, the coordinates along `right` and
    /// `true_up` on the image plane at unit distance (orthographic: scene units across the view
    /// rectangle at `eye`).
    #[inline(always)]
    fn film_uv(&self, x: f32, y: f32) -> (f32, f32) {
        let (w, h) = (self.width as f32, self.height as f32);
        let t = self.tan_half_fov;
        let u = (2.0 * x / w - 1.0) * t * w / h;
        let v = (1.0 - 2.0 * y / h) * t;
        (u, v)
    }

    /// Whether the camera has a lens of non-zero aperture, whose rays need a lens sample.
    #[inline(always)]
    pub fn has_lens(&self) -> bool {
        self.lens_radius > 0.0
    }

    /// The ray through film position `(x, y)` from the lens point that `lens` (uniform in
    /// `[0, 1)^2`) picks by Shirley and Chiu's concentric map, as pbrt-v4 (section 5.2.3) and
    /// Mitsuba's `thinlens` sample it. It is aimed at the point where the pinhole ray through
    /// `(x, y)` meets the plane in focus, so that everything on that plane is sharp and a point
    /// at another depth `d` blurs into a disk of radius `R |d - f| / (f d)` on the image plane at
    /// unit distance (`R` the lens radius, `f` the focus distance). The lens centre,
    /// `lens = (0.5, 0.5)`, gives [`Camera::ray`] exactly.
    #[inline]
    pub fn ray_through_lens(&self, x: f32, y: f32, lens: Vec2) -> Ray {
        let p = square_to_uniform_disk_concentric(lens) * self.lens_radius;
        if p == Vec2::ZERO {
            return self.ray(x, y);
        }
        let (u, v) = self.film_uv(x, y);
        let offset = p.x * self.right + p.y * self.true_up;
        let f = self.focus_distance;
        let (start, dir) = match self.kind {
            CameraKind::Perspective => {
                // The pinhole ray's unnormalised direction has a `forward` component of 1, so
                // `f` times it reaches the plane in focus.
                let focus = f * (self.forward + u * self.right + v * self.true_up);
                (self.eye + offset, (focus - offset).normalize())
            }
            CameraKind::Orthographic => {
                let film = self.eye + u * self.right + v * self.true_up;
                (film + offset, (f * self.forward - offset).normalize())
            }
        };
        // The near plane is `near_clip` ahead of the lens along the view axis, as in Mitsuba.
        let origin = if self.near_clip > 0.0 {
            start + dir * (self.near_clip / dir.dot(self.forward))
        } else {
            start
        };
        Ray::new(origin, dir)
    }

    /// The area of the film on the image plane at unit distance (perspective), `2 tan(fov/2) W/H`
    /// by `2 tan(fov/2)`: the normalisation of the camera's importance.
    fn film_area(&self) -> f32 {
        let t = self.tan_half_fov;
        4.0 * t * t * self.width as f32 / self.height as f32
    }

    /// The film position (in pixels) of the direction `w` (not necessarily unit) that leaves the
    /// lens at `lens_offset` from the eye (zero for a pinhole), or `None` outside the film: the
    /// inverse of [`Self::ray_through_lens`], through the point where the ray meets the plane in
    /// focus (for a pinhole, through the image plane).
    fn film_position(&self, lens_offset: Vec3, w: Vec3) -> Option<Vec2> {
        let z = w.dot(self.forward);
        if z.is_nan() || z <= 0.0 {
            return None;
        }
        let (u, v) = if lens_offset == Vec3::ZERO {
            (w.dot(self.right) / z, w.dot(self.true_up) / z)
        } else {
            let f = self.focus_distance;
            let q = lens_offset + (f / z) * w;
            (q.dot(self.right) / f, q.dot(self.true_up) / f)
        };
        let (wf, hf) = (self.width as f32, self.height as f32);
        let t = self.tan_half_fov;
        let x = (u * hf / (t * wf) + 1.0) * 0.5 * wf;
        let y = (1.0 - v / t) * 0.5 * hf;
        ((0.0..wf).contains(&x) && (0.0..hf).contains(&y)).then_some(Vec2::new(x, y))
    }

    /// A point of the lens for `u` (the eye for a pinhole), as an offset from the eye.
    fn lens_offset(&self, u: Vec2) -> Vec3 {
        if !self.has_lens() {
            return Vec3::ZERO;
        }
        let d = square_to_uniform_disk_concentric(u) * self.lens_radius;
        d.x * self.right + d.y * self.true_up
    }

    /// The connection of scene point `p` to the camera, for light tracing (pbrt-v4's
    /// `PerspectiveCamera::SampleWi`, Mitsuba 3's `sample_direction` of `perspective` and
    /// `thinlens`): a lens point from `u_lens` (uniform over the aperture), the film position the
    /// ray from it through `p` reaches, and the weight `We cos θ / pdf` by which a quantity arriving
    /// at the lens along that ray is splatted. The importance `We = 1 / (A A_lens cos⁴ θ)` (`A`
    /// the film's area at unit distance) makes the film the average of radiance over its area;
    /// the density of the direction at `p` is `d² / (cos θ A_lens)`, so the weight is
    /// `1 / (A cos³ θ d²)`, whatever the aperture. `None` for a point outside the view, nearer
    /// than the near plane, or for an orthographic camera (whose directions form a delta
    /// distribution no point can be connected through).
    pub fn connect(&self, p: Vec3, u_lens: Vec2) -> Option<CameraConnection> {
        if self.kind != CameraKind::Perspective {
            return None;
        }
        let offset = self.lens_offset(u_lens);
        let lens = self.eye + offset;
        let v = p - lens;
        let z = v.dot(self.forward);
        if !(z > 0.0 && z >= self.near_clip) {
            return None;
        }
        let pos = self.film_position(offset, v)?;
        let dist = v.length();
        let cos = z / dist;
        Some(CameraConnection {
            pos,
            lens,
            wi: -v / dist,
            dist,
            weight: 1.0 / (self.film_area() * cos * cos * cos * dist * dist),
        })
    }

    /// The density by solid angle with which camera rays from lens point `lens` leave along
    /// unit `w`, as a film position uniform over the film makes them: `1 / (A cos³ θ)` inside
    /// the view, zero outside (pbrt-v4's `PDF_We`, without the lens's density).
    pub fn pdf_direction(&self, lens: Vec3, w: Vec3) -> f32 {
        if self.kind != CameraKind::Perspective {
            return 0.0;
        }
        if self.film_position(lens - self.eye, w).is_none() {
            return 0.0;
        }
        let cos = w.dot(self.forward);
        1.0 / (self.film_area() * cos * cos * cos)
    }

    /// [`Self::connect`] for a light at infinity seen along unit direction `w`: the lens point,
    /// the film position and `We cos θ = 1 / (A cos³ θ)` (the density of `w` is the light's).
    pub fn connect_direction(&self, w: Vec3, u_lens: Vec2) -> Option<CameraConnection> {
        if self.kind != CameraKind::Perspective {
            return None;
        }
        let offset = self.lens_offset(u_lens);
        let pos = self.film_position(offset, w)?;
        let cos = w.dot(self.forward);
        Some(CameraConnection {
            pos,
            lens: self.eye + offset,
            wi: -w,
            dist: f32::INFINITY,
            weight: 1.0 / (self.film_area() * cos * cos * cos),
        })
    }

    /// The ray through the centre of pixel `(i, j)`.
    pub fn pixel_ray(&self, i: u32, j: u32) -> Ray {
        self.ray(i as f32 + 0.5, j as f32 + 0.5)
    }
}

/// A scene point connected to the camera: see [`Camera::connect`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraConnection {
    /// The film position in pixels.
    pub pos: Vec2,
    /// The point of the lens (the eye for a pinhole).
    pub lens: Vec3,
    /// Unit direction from the scene point toward `lens`.
    pub wi: Vec3,
    /// Distance from the scene point to `lens` (infinite for a direction).
    pub dist: f32,
    /// `We cos θ / pdf`: see [`Camera::connect`].
    pub weight: f32,
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

    /// Every lens ray through a film position meets the pinhole ray on the plane in focus;
    /// the lens's centre gives the pinhole ray itself; lens points cover the aperture.
    #[test]
    fn lens_rays_meet_on_the_plane_in_focus() {
        for kind in [CameraKind::Perspective, CameraKind::Orthographic] {
            let c = Camera::new(&CameraDesc {
                kind,
                eye: [1.0, 2.0, 3.0],
                look_at: [2.0, 1.0, -1.0],
                up: [0.0, 1.0, 0.0],
                fov: 50.0,
                half_width: Some(2.0),
                near_clip: 0.5,
                aperture_radius: 0.3,
                focus_distance: Some(4.0),
                width: 40,
                height: 30,
                ..CameraDesc::default()
            });
            assert!(c.has_lens());
            for (x, y) in [(20.0, 15.0), (0.0, 0.0), (33.3, 7.1)] {
                let pinhole = c.ray(x, y);
                assert_eq!(c.ray_through_lens(x, y, Vec2::splat(0.5)), pinhole);
                // Where the pinhole ray crosses the plane in focus.
                let t =
                    (4.0 - (pinhole.origin - c.eye).dot(c.forward)) / pinhole.dir.dot(c.forward);
                let focus = pinhole.origin + t * pinhole.dir;
                let mut farthest = 0.0f32;
                for (i, j) in (0..8).flat_map(|i| (0..8).map(move |j| (i, j))) {
                    let u = Vec2::new((i as f32 + 0.5) / 8.0, (j as f32 + 0.5) / 8.0);
                    let r = c.ray_through_lens(x, y, u);
                    assert!((r.dir.length() - 1.0).abs() < 1e-6);
                    // It starts on the near plane...
                    let depth = (r.origin - c.eye).dot(c.forward);
                    assert!(
                        (depth - 0.5).abs() < 1e-5,
                        "{kind:?}: near plane at {depth}"
                    );
                    // ...from a point of the lens disk...
                    let lens = r.origin - r.dir * (depth / r.dir.dot(c.forward));
                    let off = lens
                        - if kind == CameraKind::Perspective {
                            c.eye
                        } else {
                            pinhole.origin - 0.5 * c.forward
                        };
                    assert!(off.dot(c.forward).abs() < 1e-5 && off.length() <= 0.3 + 1e-5);
                    farthest = farthest.max(off.length());
                    // ...through the pinhole ray's point on the plane in focus.
                    let s = (4.0 - depth) / r.dir.dot(c.forward);
                    let miss = (r.origin + s * r.dir - focus).length();
                    assert!(miss < 1e-5, "{kind:?} ({x}, {y}): {miss}");
                }
                assert!(farthest > 0.25, "{farthest}");
            }
        }
    }

    #[test]
    fn no_aperture_is_no_lens_and_focus_defaults_to_the_target() {
        let d = CameraDesc {
            eye: [0.0, 0.0, 5.0],
            look_at: [0.0, 3.0, 1.0],
            ..CameraDesc::default()
        };
        let c = Camera::new(&d);
        assert!(!c.has_lens());
        assert_eq!(c.focus_distance, 5.0);
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
