//! Points on the shapes that carry area lights, sampled by area or, for a sphere seen from outside,
//! by the solid angle it covers. Built from plain world-space data, independent of the intersection
//! code; the conventions (parameterisation, normals, uv) are Mitsuba 3's shapes'.

use super::distribution::Distribution1D;
use super::warp::{square_to_sphere, square_to_triangle};
use crate::shading::bsdf::warp::square_to_uniform_disk_concentric;
use glam::{Mat3, Mat4, Vec2, Vec3};
use std::f32::consts::PI;

/// A sampled point of a shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapePoint {
    pub point: Vec3,
    /// Unit normal on the emitting side.
    pub normal: Vec3,
    pub uv: Vec2,
}

/// A shape point sampled as seen from a reference point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionSample {
    pub shape: ShapePoint,
    /// Unit direction from the reference point toward the shape point.
    pub wi: Vec3,
    pub dist: f32,
    /// Solid-angle density at the reference point.
    pub pdf: f32,
}

/// A triangle mesh in world space, with the area distribution over its triangles.
#[derive(Clone, Debug)]
pub struct TriangleSet {
    positions: Vec<[Vec3; 3]>,
    /// Each triangle's unit geometric normal, computed once: every light sample needs it, and a
    /// cross product and a square root per sample would repeat the same work.
    normals: Vec<Vec3>,
    uvs: Option<Vec<[Vec2; 3]>>,
    by_area: Distribution1D,
    area: f32,
}

#[derive(Clone, Debug)]
pub enum ShapeSampler {
    Triangles(TriangleSet),
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// Mitsuba's `rectangle`: [-1, 1]² at z = 0 with normal +z, mapped by `to_world`.
    Rectangle {
        to_world: Mat4,
    },
    /// Mitsuba's `disk`: the unit disk at z = 0 with normal +z, mapped by `to_world`.
    Disk {
        to_world: Mat4,
    },
    /// Mitsuba's `cylinder`: the tube x² + y² = 1, 0 <= z <= 1 mapped by `to_world`, which keeps
    /// it circular (see [`ShapeSampler::cylinder`]); normals away from the axis unless `flip`.
    Cylinder {
        to_world: Mat4,
        flip: bool,
        area: f32,
    },
}

/// Below this sin² of the cone's half-angle (about 1.5 degrees), 1 - cos θmax loses all precision
/// in f32 and its Taylor expansion sin²θmax / 2 is used instead (pbrt-v4 section 6.2.4).
const SMALL_CONE_SIN2: f32 = 0.000_685_23;

impl TriangleSet {
    pub fn triangle_count(&self) -> usize {
        self.positions.len()
    }
}

impl ShapeSampler {
    /// A cylinder sampled uniformly by area as Mitsuba samples it (the angle from the second
    /// number, the height from the first). Uniform in (angle, height) is uniform by area only
    /// while the tube stays circular: `None` unless the transform's x and y columns are
    /// perpendicular and of equal length, and the axis perpendicular to both.
    pub fn cylinder(to_world: Mat4, flip: bool) -> Option<Self> {
        let lin = Mat3::from_mat4(to_world);
        let (x, y, z) = (lin.x_axis, lin.y_axis, lin.z_axis);
        let r = x.length();
        let len = z.length();
        let tol = 1e-4;
        let circular = r > 0.0
            && len > 0.0
            && ((y.length() - r).abs() <= tol * r)
            && x.dot(y).abs() <= tol * r * r
            && x.dot(z).abs() <= tol * r * len
            && y.dot(z).abs() <= tol * r * len;
        circular.then_some(ShapeSampler::Cylinder {
            to_world,
            flip,
            area: 2.0 * PI * r * len,
        })
    }

    /// A mesh of world-space triangles without texture coordinates: a point's uv is then its
    /// barycentrics (b1, b2), as in Mitsuba's meshes without uvs.
    pub fn triangles(positions: &[[Vec3; 3]]) -> Self {
        Self::build_triangles(positions.to_vec(), None)
    }

    /// A mesh of world-space triangles with one uv per vertex, for textured radiance.
    pub fn triangles_with_uv(positions: &[[Vec3; 3]], uvs: &[[Vec2; 3]]) -> Self {
        assert_eq!(positions.len(), uvs.len(), "one uv triple per triangle");
        Self::build_triangles(positions.to_vec(), Some(uvs.to_vec()))
    }

    fn build_triangles(positions: Vec<[Vec3; 3]>, uvs: Option<Vec<[Vec2; 3]>>) -> Self {
        let areas: Vec<f32> = positions
            .iter()
            .map(|[a, b, c]| 0.5 * (*b - *a).cross(*c - *a).length())
            .collect();
        let area = areas.iter().map(|&a| a as f64).sum::<f64>() as f32;
        let normals = positions.iter().map(|&t| triangle_normal(t)).collect();
        ShapeSampler::Triangles(TriangleSet {
            positions,
            normals,
            uvs,
            by_area: Distribution1D::new(&areas),
            area,
        })
    }

    /// Surface area.
    pub fn area(&self) -> f32 {
        match self {
            ShapeSampler::Triangles(t) => t.area,
            ShapeSampler::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            ShapeSampler::Rectangle { to_world } => 4.0 * frame_of(to_world).2,
            ShapeSampler::Disk { to_world } => PI * frame_of(to_world).2,
            ShapeSampler::Cylinder { area, .. } => *area,
        }
    }

    /// A point uniformly distributed by area: (point, unit normal, uv, density per unit area).
    pub fn sample_area(&self, u: Vec2) -> (Vec3, Vec3, Vec2, f32) {
        let s = self.sample_point(u);
        let area = self.area();
        let pdf = if area > 0.0 { 1.0 / area } else { 0.0 };
        (s.point, s.normal, s.uv, pdf)
    }

    fn sample_point(&self, u: Vec2) -> ShapePoint {
        match self {
            ShapeSampler::Triangles(t) => {
                // The first coordinate picks the triangle and is then reused inside it
                // (Mitsuba's `sample_reuse`).
                let (i, _, ux) = t.by_area.sample_discrete(u.x);
                let [a, b, c] = t.positions[i];
                let bary = square_to_triangle(Vec2::new(ux, u.y));
                let b0 = 1.0 - bary.x - bary.y;
                let uv = match &t.uvs {
                    Some(uvs) => {
                        let [ua, ub, uc] = uvs[i];
                        b0 * ua + bary.x * ub + bary.y * uc
                    }
                    None => bary,
                };
                ShapePoint {
                    point: b0 * a + bary.x * b + bary.y * c,
                    normal: t.normals[i],
                    uv,
                }
            }
            ShapeSampler::Sphere { center, radius } => {
                let n = square_to_sphere(u);
                ShapePoint {
                    point: *center + *radius * n,
                    normal: n,
                    uv: sphere_uv(n),
                }
            }
            ShapeSampler::Rectangle { to_world } => {
                let local = Vec3::new(2.0 * u.x - 1.0, 2.0 * u.y - 1.0, 0.0);
                ShapePoint {
                    point: to_world.transform_point3(local),
                    normal: frame_of(to_world).1,
                    uv: u,
                }
            }
            ShapeSampler::Disk { to_world } => {
                let d = square_to_uniform_disk_concentric(u);
                let mut phi = d.y.atan2(d.x);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                ShapePoint {
                    point: to_world.transform_point3(d.extend(0.0)),
                    normal: frame_of(to_world).1,
                    // Mitsuba's disk parameterisation: (radius, azimuth / 2π).
                    uv: Vec2::new(d.length(), phi / (2.0 * PI)),
                }
            }
            ShapeSampler::Cylinder { to_world, flip, .. } => {
                let phi = 2.0 * PI * u.y;
                let (sin, cos) = phi.sin_cos();
                let outward = to_world
                    .transform_vector3(Vec3::new(cos, sin, 0.0))
                    .normalize();
                ShapePoint {
                    point: to_world.transform_point3(Vec3::new(cos, sin, u.x)),
                    normal: if *flip { -outward } else { outward },
                    // Mitsuba's cylinder parameterisation: (azimuth / 2π, height).
                    uv: Vec2::new(u.y, u.x),
                }
            }
        }
    }

    /// A point of the shape as seen from `p`, with its solid-angle density at `p`; `None` when the
    /// point is degenerate (on `p`, or seen exactly edge-on).
    pub fn sample_direction(&self, p: Vec3, u: Vec2) -> Option<DirectionSample> {
        if let ShapeSampler::Sphere { center, radius } = *self {
            if let Some(cone) = SphereCone::new(p, center, radius) {
                return cone.sample(u);
            }
        }
        let s = self.sample_point(u);
        let to = s.point - p;
        let dist2 = to.length_squared();
        let dist = dist2.sqrt();
        let wi = to / dist;
        let cos = wi.dot(s.normal).abs();
        let area = self.area();
        if !(dist > 0.0 && cos > 0.0 && area > 0.0) {
            return None;
        }
        Some(DirectionSample {
            shape: s,
            wi,
            dist,
            pdf: dist2 / (cos * area),
        })
    }

    /// The solid-angle density with which [`sample_direction`](Self::sample_direction) from `p`
    /// returns direction `wi`, which reaches the shape at `point` with unit normal `normal`.
    pub fn pdf_direction(&self, p: Vec3, wi: Vec3, point: Vec3, normal: Vec3) -> f32 {
        if let ShapeSampler::Sphere { center, radius } = *self {
            if let Some(cone) = SphereCone::new(p, center, radius) {
                return cone.pdf();
            }
        }
        let dist2 = (point - p).length_squared();
        let cos = wi.dot(normal).abs();
        let area = self.area();
        if cos > 0.0 && area > 0.0 {
            dist2 / (cos * area)
        } else {
            0.0
        }
    }
}

/// The unit normal of triangle `(a, b, c)` by the right-hand rule (zero if degenerate).
fn triangle_normal([a, b, c]: [Vec3; 3]) -> Vec3 {
    (b - a).cross(c - a).normalize_or_zero()
}

/// Mitsuba's sphere parameterisation of a unit normal: (azimuth / 2π, polar angle / π).
fn sphere_uv(n: Vec3) -> Vec2 {
    let mut phi = n.y.atan2(n.x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    Vec2::new(phi / (2.0 * PI), n.z.clamp(-1.0, 1.0).acos() / PI)
}

/// The affine map's linear part, its unit normal (the inverse transpose applied to +z, as normals
/// transform) and the area scale of its xy plane.
fn frame_of(m: &Mat4) -> (Mat3, Vec3, f32) {
    let lin = Mat3::from_mat4(*m);
    let n = lin.inverse().transpose() * Vec3::Z;
    let scale = (lin * Vec3::X).cross(lin * Vec3::Y).length();
    (lin, n.normalize_or_zero(), scale)
}

/// The cone of directions from a point outside a sphere toward it.
struct SphereCone {
    p: Vec3,
    center: Vec3,
    radius: f32,
    /// Unit axis from the sphere's centre toward the reference point.
    axis: Vec3,
    sin2_max: f32,
    /// 1 - cos θmax, computed stably.
    one_minus_cos_max: f32,
}

impl SphereCone {
    /// `None` when `p` is inside the sphere (or on it), where the sphere is sampled by area.
    fn new(p: Vec3, center: Vec3, radius: f32) -> Option<Self> {
        let offset = p - center;
        let d2 = offset.length_squared();
        if d2 <= radius * radius {
            return None;
        }
        let dist_center = d2.sqrt();
        let sin2_max = radius * radius / d2;
        let one_minus_cos_max = if sin2_max < SMALL_CONE_SIN2 {
            0.5 * sin2_max
        } else {
            1.0 - (1.0 - sin2_max).max(0.0).sqrt()
        };
        Some(Self {
            p,
            center,
            radius,
            axis: offset / dist_center,
            sin2_max,
            one_minus_cos_max,
        })
    }

    fn pdf(&self) -> f32 {
        1.0 / (2.0 * PI * self.one_minus_cos_max)
    }

    /// A direction uniform in the cone, and the nearer point where it meets the sphere, found not by
    /// intersecting a ray but through the angle α at the sphere's centre (pbrt-v4 section 6.2.4):
    /// exact for distant, small spheres too.
    fn sample(&self, u: Vec2) -> Option<DirectionSample> {
        let sin2_theta = if self.sin2_max < SMALL_CONE_SIN2 {
            self.sin2_max * u.x
        } else {
            let cos_theta = 1.0 - u.x * self.one_minus_cos_max;
            (1.0 - cos_theta * cos_theta).max(0.0)
        };
        let cos_theta = (1.0 - sin2_theta).max(0.0).sqrt();
        let sin_max = self.sin2_max.sqrt();
        // The law of sines in the triangle (p, centre, hit point) gives the angle at the centre.
        let cos_alpha =
            sin2_theta / sin_max + cos_theta * (1.0 - sin2_theta / self.sin2_max).max(0.0).sqrt();
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let (t1, t2) = crate::math::orthonormal_basis(self.axis);
        let normal =
            (cos_alpha * self.axis + sin_alpha * (phi.cos() * t1 + phi.sin() * t2)).normalize();
        let point = self.center + self.radius * normal;
        let to = point - self.p;
        let dist = to.length();
        if dist.is_nan() || dist <= 0.0 {
            return None;
        }
        Some(DirectionSample {
            shape: ShapePoint {
                point,
                normal,
                uv: sphere_uv(normal),
            },
            wi: to / dist,
            dist,
            pdf: self.pdf(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::chi2_sphere::{assert_fits, Spec};
    use super::*;

    /// The shape sampler's directions from `p` against its own density, over the cap about the
    /// direction toward `target` that holds the shape.
    fn check(name: &str, s: &ShapeSampler, p: Vec3, target: Vec3, cos_min: f64) {
        let spec = Spec::cap(target - p, cos_min, 200_000);
        // The density of a direction is the sampler's pdf at the point where it reaches the shape.
        assert_fits(
            name,
            &spec,
            |u| s.sample_direction(p, u).map(|d| d.wi),
            |wi| density(s, p, wi),
            1.0,
            0.01,
        );
    }

    /// The density of sampling direction `wi` from `p`: the pdf at the nearest hit, except for a
    /// mesh, where a ray may cross several triangles that can each be sampled, and the densities
    /// add (pdf_direction itself answers for the visible one, which is what shading needs).
    fn density(s: &ShapeSampler, p: Vec3, wi: Vec3) -> f32 {
        let ShapeSampler::Triangles(set) = s else {
            return hit(s, p, wi).map_or(0.0, |(x, n)| s.pdf_direction(p, wi, x, n));
        };
        set.positions
            .iter()
            .filter_map(|tri| {
                let one = ShapeSampler::Triangles(TriangleSet {
                    positions: vec![*tri],
                    normals: vec![triangle_normal(*tri)],
                    uvs: None,
                    by_area: Distribution1D::new(&[1.0]),
                    area: set.area,
                });
                hit(&one, p, wi).map(|(x, n)| s.pdf_direction(p, wi, x, n))
            })
            .sum()
    }

    /// The nearest hit of the ray p + t wi with the shape, and the normal there (a test's
    /// stand-in for the scene's intersection code).
    fn hit(s: &ShapeSampler, p: Vec3, wi: Vec3) -> Option<(Vec3, Vec3)> {
        match s {
            ShapeSampler::Sphere { center, radius } => {
                let oc = p - *center;
                let b = oc.dot(wi);
                let c = oc.length_squared() - radius * radius;
                let disc = b * b - c;
                if disc < 0.0 {
                    return None;
                }
                let sq = disc.sqrt();
                let t = if -b - sq > 0.0 { -b - sq } else { -b + sq };
                (t > 0.0).then(|| {
                    let x = p + t * wi;
                    (x, (x - *center).normalize())
                })
            }
            ShapeSampler::Rectangle { to_world } | ShapeSampler::Disk { to_world } => {
                let inv = to_world.inverse();
                let (o, d) = (inv.transform_point3(p), inv.transform_vector3(wi));
                let t = -o.z / d.z;
                let l = o + t * d;
                let inside = match s {
                    ShapeSampler::Rectangle { .. } => l.x.abs() <= 1.0 && l.y.abs() <= 1.0,
                    _ => l.x * l.x + l.y * l.y <= 1.0,
                };
                (t > 0.0 && inside).then(|| (p + t * wi, frame_of(to_world).1))
            }
            ShapeSampler::Cylinder { to_world, flip, .. } => {
                let c = crate::geometry::Cylinder::new(*to_world, *flip).unwrap();
                let ray = crate::math::Ray::new(p, wi);
                let h = c.intersect(&ray, f32::INFINITY)?;
                let si = c.interaction(&ray, &h);
                Some((si.p, si.n))
            }
            ShapeSampler::Triangles(set) => {
                let mut best: Option<(f32, Vec3, Vec3)> = None;
                for &[a, b, c] in &set.positions {
                    let (e1, e2) = (b - a, c - a);
                    let pv = wi.cross(e2);
                    let det = e1.dot(pv);
                    if det.abs() < 1e-12 {
                        continue;
                    }
                    let tv = p - a;
                    let u = tv.dot(pv) / det;
                    let qv = tv.cross(e1);
                    let v = wi.dot(qv) / det;
                    let t = e2.dot(qv) / det;
                    if u >= 0.0
                        && v >= 0.0
                        && u + v <= 1.0
                        && t > 0.0
                        && best.is_none_or(|b| t < b.0)
                    {
                        best = Some((t, p + t * wi, e1.cross(e2).normalize()));
                    }
                }
                best.map(|(_, x, n)| (x, n))
            }
        }
    }

    fn small_mesh() -> ShapeSampler {
        // A bent strip of three triangles of different sizes and orientations, one of zero area.
        let a = Vec3::new(-1.0, 0.0, 0.0);
        let b = Vec3::new(0.0, 0.0, 0.2);
        let c = Vec3::new(-0.5, 1.0, 0.0);
        let d = Vec3::new(1.0, 0.5, 0.8);
        ShapeSampler::triangles(&[
            [a, b, c],
            [b, d, c],
            [a, a, b],
            [b, Vec3::new(0.6, -0.7, 0.3), d],
        ])
    }

    #[test]
    fn sphere_from_outside_samples_the_visible_cap() {
        let s = ShapeSampler::Sphere {
            center: Vec3::new(0.5, -0.2, 3.0),
            radius: 1.2,
        };
        let p = Vec3::new(0.1, 0.3, -0.4);
        // The cone's half-angle: sin θmax = r / d.
        let d = (Vec3::new(0.5, -0.2, 3.0) - p).length();
        let cos_max = (1.0 - (1.2 / d).powi(2)).sqrt() as f64;
        check(
            "sphere outside",
            &s,
            p,
            Vec3::new(0.5, -0.2, 3.0),
            cos_max - 0.01,
        );
        // Sampled points lie on the sphere, facing p.
        let ds = s.sample_direction(p, Vec2::new(0.3, 0.8)).unwrap();
        assert!(((ds.shape.point - Vec3::new(0.5, -0.2, 3.0)).length() - 1.2).abs() < 1e-5);
        assert!(ds.wi.dot(ds.shape.normal) < 0.0);
        assert!((ds.shape.point - (p + ds.dist * ds.wi)).length() < 1e-5);
    }

    #[test]
    fn far_small_sphere_keeps_its_cone() {
        // θmax of 0.06 degrees: the Taylor branch. Density is exact, samples hit the sphere.
        let s = ShapeSampler::Sphere {
            center: Vec3::new(0.0, 0.0, 1000.0),
            radius: 1.0,
        };
        let pdf = s.pdf_direction(Vec3::ZERO, Vec3::Z, Vec3::ZERO, Vec3::ZERO);
        let expect = 1.0 / (2.0 * PI * (1.0 - (1.0f64 - 1e-6).sqrt()) as f32);
        assert!((pdf / expect - 1.0).abs() < 1e-4, "{pdf} vs {expect}");
        for k in 0..16 {
            let u = Vec2::new((k as f32 + 0.5) / 16.0, (k * 7 % 16) as f32 / 16.0);
            let ds = s.sample_direction(Vec3::ZERO, u).unwrap();
            assert!((ds.shape.point.distance(Vec3::new(0.0, 0.0, 1000.0)) - 1.0).abs() < 1e-3);
        }
    }

    /// Directions toward a cylinder follow its density, checked from inside the tube, where each
    /// direction meets the wall at most once (from outside, a direction crossing both walls has
    /// two points that can be sampled, which `hit` would not add up).
    #[test]
    fn cylinder_samples_follow_their_density() {
        let to_world = Mat4::from_scale_rotation_translation(
            Vec3::new(1.5, 1.5, 2.0),
            glam::Quat::from_axis_angle(Vec3::new(0.3, 1.0, 0.2).normalize(), 0.7),
            Vec3::new(0.2, -0.4, 0.5),
        );
        let s = ShapeSampler::cylinder(to_world, true).unwrap();
        assert!((s.area() - 2.0 * PI * 1.5 * 2.0).abs() < 1e-4);
        // Inside the tube at mid-height: every direction meets it once, and with flipped normals
        // (facing the axis) every sampled point faces the reference point.
        let p = to_world.transform_point3(Vec3::new(0.2, -0.1, 0.5));
        let outcome = crate::shading::chi2::Chi2Test::new(Default::default()).run(
            |_, u| s.sample_direction(p, u).map(|d| d.wi),
            |wi| density(&s, p, wi),
        );
        assert!(outcome.passed, "{outcome}");
        assert!((outcome.pdf_integral - 1.0).abs() < 2e-3, "{outcome}");
        let ds = s.sample_direction(p, Vec2::new(0.3, 0.8)).unwrap();
        assert!(ds.wi.dot(ds.shape.normal) < 0.0);
        assert!((ds.shape.uv - Vec2::new(0.8, 0.3)).length() < 1e-6);
        // A sheared or elliptic tube cannot be sampled uniformly this way.
        assert!(
            ShapeSampler::cylinder(Mat4::from_scale(Vec3::new(1.0, 2.0, 1.0)), false).is_none()
        );
    }

    #[test]
    fn sphere_from_inside_samples_by_area() {
        let s = ShapeSampler::Sphere {
            center: Vec3::new(0.2, 0.0, 0.1),
            radius: 2.0,
        };
        let p = Vec3::new(0.9, -0.5, 0.4);
        let outcome = crate::shading::chi2::Chi2Test::new(Default::default()).run(
            |_, u| s.sample_direction(p, u).map(|d| d.wi),
            |wi| density(&s, p, wi),
        );
        assert!(outcome.passed, "{outcome}");
        assert!((outcome.pdf_integral - 1.0).abs() < 1e-3, "{outcome}");
    }

    #[test]
    fn triangles_rectangle_and_disk_sample_by_area() {
        let mesh = small_mesh();
        check(
            "triangles",
            &mesh,
            Vec3::new(0.2, 0.3, 2.0),
            Vec3::new(0.0, 0.3, 0.3),
            0.3,
        );
        let rect = ShapeSampler::Rectangle {
            to_world: Mat4::from_scale_rotation_translation(
                Vec3::new(0.5, 1.5, 1.0),
                glam::Quat::from_rotation_x(0.4),
                Vec3::new(0.0, 0.0, 2.0),
            ),
        };
        check(
            "rectangle",
            &rect,
            Vec3::new(0.3, 0.1, 0.0),
            Vec3::new(0.0, 0.0, 2.0),
            0.3,
        );
        let disk = ShapeSampler::Disk {
            to_world: Mat4::from_scale_rotation_translation(
                Vec3::splat(0.8),
                glam::Quat::from_rotation_y(-0.7),
                Vec3::new(1.0, 0.0, 1.5),
            ),
        };
        check(
            "disk",
            &disk,
            Vec3::new(-0.2, 0.1, 0.0),
            Vec3::new(1.0, 0.0, 1.5),
            0.88,
        );
    }

    #[test]
    fn areas_normals_and_uvs_follow_mitsuba() {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 3.0, 1.0),
            glam::Quat::IDENTITY,
            Vec3::new(1.0, 0.0, 0.0),
        );
        let rect = ShapeSampler::Rectangle { to_world: m };
        assert!((rect.area() - 24.0).abs() < 1e-5);
        // Mitsuba 3.9: a unit rectangle's sample_position at (0.3, 0.8) is (-0.4, 0.6, 0), uv
        // (0.3, 0.8), normal +z, pdf 0.25; a unit disk's is (-0.3, 0.519615, 0), uv
        // (0.6, 0.333333), pdf 1/π.
        let unit = ShapeSampler::Rectangle {
            to_world: Mat4::IDENTITY,
        };
        let (p, n, uv, pdf) = unit.sample_area(Vec2::new(0.3, 0.8));
        assert!(p.distance(Vec3::new(-0.4, 0.6, 0.0)) < 1e-6 && n == Vec3::Z);
        assert!(uv.distance(Vec2::new(0.3, 0.8)) < 1e-6 && (pdf - 0.25).abs() < 1e-7);
        let disk = ShapeSampler::Disk {
            to_world: Mat4::IDENTITY,
        };
        let (p, n, uv, pdf) = disk.sample_area(Vec2::new(0.3, 0.8));
        assert!(p.distance(Vec3::new(-0.3, 0.519_615, 0.0)) < 1e-5 && n == Vec3::Z);
        assert!(uv.distance(Vec2::new(0.6, 0.333_333)) < 1e-5);
        assert!((pdf - 1.0 / PI).abs() < 1e-6);
        // Mitsuba's sphere uv at direction (0.303046, -0.505076, 0.808122) is (0.83601, 0.200484).
        let uv = sphere_uv(Vec3::new(0.303_046, -0.505_076, 0.808_122));
        assert!(uv.distance(Vec2::new(0.836_01, 0.200_484)) < 1e-5, "{uv}");
        // A mirroring transform keeps the transformed +z normal (as Mitsuba transforms normals).
        let flip = ShapeSampler::Rectangle {
            to_world: Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
        };
        assert!(flip.sample_area(Vec2::splat(0.5)).1.distance(Vec3::Z) < 1e-6);
        // Triangles: total area, geometric normal, interpolated uvs.
        let tri = [[Vec3::ZERO, Vec3::X * 2.0, Vec3::Y]];
        let uvs = [[Vec2::ZERO, Vec2::X, Vec2::Y]];
        let t = ShapeSampler::triangles_with_uv(&tri, &uvs);
        assert_eq!(t.area(), 1.0);
        let (p, n, uv, pdf) = t.sample_area(Vec2::new(0.36, 0.5));
        assert_eq!(n, Vec3::Z);
        assert!(p.distance(Vec3::new(2.0 * uv.x, uv.y, 0.0)) < 1e-6 && pdf == 1.0);
    }
}
