//! Points on the shapes that carry area lights, sampled by area or, for a sphere seen from outside,
//! by the solid angle it covers. Built from plain world-space data, independent of the intersection
//! code; the conventions (parameterisation, normals, uv) are Mitsuba 3's shapes'.

use super::distribution::Distribution1D;
use super::warp::{square_to_disk_concentric, square_to_sphere, square_to_triangle};
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
        ShapeSampler::Triangles(TriangleSet {
            positions,
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
                    normal: (b - a).cross(c - a).normalize_or_zero(),
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
                let d = square_to_disk_concentric(u);
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
        if !(dist > 0.0) {
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
