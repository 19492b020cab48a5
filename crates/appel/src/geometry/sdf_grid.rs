//! Mitsuba 3's `sdfgrid`: a signed distance function sampled on an `nx x ny x nz` grid spanning
//! `[0, 1]^3` in its own space (sample `(i, j, k)` at `(i / (nx - 1), j / (ny - 1), k / (nz - 1))`),
//! interpolated trilinearly inside each voxel; the surface is its zero set, placed by an affine
//! `to_world`. A ray walks the voxels it crosses (Amanatides and Woo 1987) and, in each voxel whose
//! corners change sign, solves the cubic the trilinear function becomes along the ray (Marmitt et
//! al. 2004, "Fast and accurate ray-voxel intersection techniques for iso-surface ray tracing";
//! Hansson-Söderlund et al. 2022, "Ray tracing of signed distance function grids", JCGT 11(3)).
//! The surface has no texture coordinates (uv = 0) and cannot emit, as in Mitsuba.

use super::{ObjectTransform, PrimHit, SurfaceInteraction};
use crate::math::{gamma, Aabb, Ray, Vec2, Vec3};
use glam::{DMat4, DVec3, Mat4};

/// How shading normals are computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SdfNormals {
    /// The gradient of the voxel's trilinear function: continuous inside a voxel, not across.
    Analytic,
    /// Hansson-Söderlund et al.'s blend of the eight voxels around the nearest grid vertex,
    /// continuous across voxels (Mitsuba's default).
    Smooth,
}

#[derive(Clone, Debug)]
pub struct SdfGrid {
    /// Samples per axis (at least 2).
    n: [usize; 3],
    values: Vec<f32>,
    /// Voxels whose corners take both signs (or touch zero), x fastest, `(n - 1)` per axis.
    occupied: Vec<bool>,
    transform: ObjectTransform,
    to_object: DMat4,
    normals: SdfNormals,
}

impl SdfGrid {
    /// `values` has `n[0] * n[1] * n[2]` samples, x fastest. `Err` with a reason when the grid is
    /// too small, has no surface, or the transform cannot be inverted.
    pub fn new(
        n: [usize; 3],
        values: Vec<f32>,
        to_world: Mat4,
        normals: SdfNormals,
    ) -> Result<Self, String> {
        if n.iter().any(|&k| k < 2) {
            return Err(format!(
                "the grid needs 2 samples per axis at least, has {n:?}"
            ));
        }
        if values.len() != n[0] * n[1] * n[2] {
            return Err("the grid's value count does not match its resolution".into());
        }
        let transform = ObjectTransform::new(to_world)
            .ok_or_else(|| "the transform is not invertible".to_string())?;
        let to_object = to_world.as_dmat4().inverse();
        let mut grid = Self {
            n,
            values,
            occupied: Vec::new(),
            transform,
            to_object,
            normals,
        };
        let v = grid.voxels();
        let mut occupied = vec![false; v[0] * v[1] * v[2]];
        let mut any = false;
        for z in 0..v[2] {
            for y in 0..v[1] {
                for x in 0..v[0] {
                    let c = grid.corners([x, y, z]);
                    let o = c.iter().any(|&f| f >= 0.0) && c.iter().any(|&f| f <= 0.0);
                    occupied[(z * v[1] + y) * v[0] + x] = o;
                    any |= o;
                }
            }
        }
        if !any {
            return Err("the grid has no surface: its values never change sign".into());
        }
        grid.occupied = occupied;
        Ok(grid)
    }

    fn voxels(&self) -> [usize; 3] {
        self.n.map(|k| k - 1)
    }

    fn sample(&self, i: [i64; 3]) -> f64 {
        let c = |a: usize| i[a].clamp(0, self.n[a] as i64 - 1) as usize;
        self.values[(c(2) * self.n[1] + c(1)) * self.n[0] + c(0)] as f64
    }

    /// The voxel's corner values, indexed x + 2y + 4z.
    fn corners(&self, v: [usize; 3]) -> [f64; 8] {
        std::array::from_fn(|i| {
            self.sample([
                (v[0] + (i & 1)) as i64,
                (v[1] + ((i >> 1) & 1)) as i64,
                (v[2] + (i >> 2)) as i64,
            ])
        })
    }

    fn resolution(&self) -> DVec3 {
        DVec3::new(
            (self.n[0] - 1) as f64,
            (self.n[1] - 1) as f64,
            (self.n[2] - 1) as f64,
        )
    }

    pub fn bounds(&self) -> Aabb {
        let b = self
            .transform
            .bounds_to_world(Aabb::new(Vec3::ZERO, Vec3::ONE));
        let pad = (b.max - b.min).abs().max(b.min.abs().max(b.max.abs())) * (4.0 * f32::EPSILON);
        Aabb::new(b.min - pad, b.max + pad)
    }

    /// The nearest zero of the interpolated function along the ray in `(0, t_max)`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<PrimHit> {
        let res = self.resolution();
        // Grid coordinates: voxel v spans [v, v + 1] on each axis. `t` is the world ray's.
        let o = self.to_object.transform_point3(ray.origin.as_dvec3()) * res;
        let d = self.to_object.transform_vector3(ray.dir.as_dvec3()) * res;
        let (mut t_lo, mut t_hi) = (0.0f64, t_max as f64);
        for a in 0..3 {
            if d[a] == 0.0 {
                if o[a] < 0.0 || o[a] > res[a] {
                    return None;
                }
                continue;
            }
            let (t0, t1) = ((0.0 - o[a]) / d[a], (res[a] - o[a]) / d[a]);
            t_lo = t_lo.max(t0.min(t1));
            t_hi = t_hi.min(t0.max(t1));
        }
        if t_lo.partial_cmp(&t_hi).is_none_or(|o| o.is_gt()) {
            return None;
        }
        let p = o + t_lo * d;
        let mut v = [0i64; 3];
        let mut step = [0i64; 3];
        let mut t_next = [f64::INFINITY; 3];
        let mut t_delta = [f64::INFINITY; 3];
        for a in 0..3 {
            v[a] = (p[a].floor() as i64).clamp(0, res[a] as i64 - 1);
            if d[a] > 0.0 {
                step[a] = 1;
                t_next[a] = (v[a] as f64 + 1.0 - o[a]) / d[a];
                t_delta[a] = 1.0 / d[a];
            } else if d[a] < 0.0 {
                step[a] = -1;
                t_next[a] = (v[a] as f64 - o[a]) / d[a];
                t_delta[a] = -1.0 / d[a];
            }
        }
        let voxels = self.voxels();
        loop {
            let vi = [v[0] as usize, v[1] as usize, v[2] as usize];
            if self.occupied[(vi[2] * voxels[1] + vi[1]) * voxels[0] + vi[0]] {
                if let Some(t) = self.voxel_root(vi, o, d, t_lo, t_hi) {
                    let t32 = t as f32;
                    if t32 > 0.0 && t32 < t_max {
                        return Some(PrimHit {
                            t: t32,
                            // What f32 drops of t, for the interaction's point.
                            u: (t - t32 as f64) as f32,
                            v: 0.0,
                            sub: 0,
                        });
                    }
                }
            }
            let a = if t_next[0] < t_next[1] {
                if t_next[0] < t_next[2] {
                    0
                } else {
                    2
                }
            } else if t_next[1] < t_next[2] {
                1
            } else {
                2
            };
            if t_next[a] > t_hi {
                return None;
            }
            v[a] += step[a];
            if v[a] < 0 || v[a] >= voxels[a] as i64 {
                return None;
            }
            t_next[a] += t_delta[a];
        }
    }

    /// The first root in the part of `[t_lo, t_hi]` inside voxel `v` (grid-space ray `o + t d`).
    fn voxel_root(&self, v: [usize; 3], o: DVec3, d: DVec3, t_lo: f64, t_hi: f64) -> Option<f64> {
        let base = DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64);
        let ol = o - base;
        // The ray's span inside the voxel, and the faces it enters and leaves by.
        let (mut ta, mut tb) = (t_lo, t_hi);
        let (mut enter, mut leave) = (None, None);
        for a in 0..3 {
            if d[a] == 0.0 {
                if ol[a] < 0.0 || ol[a] > 1.0 {
                    return None;
                }
                continue;
            }
            let (t0, t1) = ((0.0 - ol[a]) / d[a], (1.0 - ol[a]) / d[a]);
            let (near, far) = (t0.min(t1), t0.max(t1));
            if near >= ta {
                ta = near;
                enter = Some(a);
            }
            if far <= tb {
                tb = far;
                leave = Some(a);
            }
        }
        if ta.partial_cmp(&tb).is_none_or(|o| o.is_gt()) {
            return None;
        }
        let c = self.corners(v);
        // The function where the ray crosses a face is evaluated on that face exactly (its
        // coordinate across the face set to 0 or 1): two voxels sharing the face then agree on
        // the sign there, and a surface passing through the face is found by one of them.
        let on_face = |t: f64, face: Option<usize>, entering: bool| -> f64 {
            let mut p = ol + t * d;
            if let Some(a) = face {
                p[a] = if (d[a] > 0.0) == entering { 0.0 } else { 1.0 };
            }
            trilinear(&c, p.clamp(DVec3::ZERO, DVec3::ONE))
        };
        let fa = on_face(ta, enter, true);
        let fb = on_face(tb, leave, false);
        // The trilinear function along the ray: c3 s^3 + c2 s^2 + c1 s + c0 with s = t - ta.
        let p = ol + ta * d;
        let coeffs = cubic_along(&c, p, d);
        let f = |s: f64| ((coeffs[3] * s + coeffs[2]) * s + coeffs[1]) * s + coeffs[0];
        let df = |s: f64| (3.0 * coeffs[3] * s + 2.0 * coeffs[2]) * s + coeffs[1];
        let len = tb - ta;
        // Monotonic pieces between the roots of the derivative.
        let mut cuts = vec![0.0];
        for r in quadratic_roots(3.0 * coeffs[3], 2.0 * coeffs[2], coeffs[1]) {
            if r > 0.0 && r < len {
                cuts.push(r);
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.push(len);
        for w in cuts.windows(2) {
            let (mut lo, mut hi) = (w[0], w[1]);
            let mut f_lo = if lo == 0.0 { fa } else { f(lo) };
            let f_hi = if hi == len { fb } else { f(hi) };
            if f_lo * f_hi > 0.0 {
                continue;
            }
            if f_lo == 0.0 {
                return Some(ta + lo);
            }
            // Newton's method kept inside the bracket, bisecting when a step leaves it.
            let mut s = lo + (hi - lo) * (f_lo / (f_lo - f_hi));
            if !(s >= lo && s <= hi) {
                s = 0.5 * (lo + hi);
            }
            for _ in 0..60 {
                let fs = f(s);
                if fs == 0.0 {
                    break;
                }
                if (fs > 0.0) == (f_lo > 0.0) {
                    lo = s;
                    f_lo = fs;
                } else {
                    hi = s;
                }
                let next = s - fs / df(s);
                let next = if next > lo && next < hi {
                    next
                } else {
                    0.5 * (lo + hi)
                };
                let done = (next - s).abs() <= 1e-12 * len.max(1e-300);
                s = next;
                if done || hi - lo <= 1e-14 * len {
                    break;
                }
            }
            return Some(ta + s);
        }
        None
    }

    pub fn interaction(&self, ray: &Ray, hit: &PrimHit) -> SurfaceInteraction {
        let res = self.resolution();
        let t = hit.t as f64 + hit.u as f64;
        let local = self.to_object.transform_point3(ray.origin.as_dvec3())
            + t * self.to_object.transform_vector3(ray.dir.as_dvec3());
        let g = (local * res).clamp(DVec3::ZERO, res);
        let voxel: [usize; 3] = std::array::from_fn(|a| (g[a].floor() as usize).min(self.n[a] - 2));
        let c = self.corners(voxel);
        let w = g - DVec3::new(voxel[0] as f64, voxel[1] as f64, voxel[2] as f64);
        let gradient = trilinear_gradient(&c, w) * res;
        let n = gradient.normalize_or(DVec3::Z).as_vec3();
        let ns = match self.normals {
            SdfNormals::Analytic => n,
            SdfNormals::Smooth => self.smooth_normal(g).as_vec3().normalize_or(n),
        };
        let p = local.as_vec3();
        // The point is not projected onto the surface: its error is the solve's tolerance (far
        // below rounding) and the rounding of o + t d, a few ulps of the coordinates involved.
        let reach = self
            .to_object
            .transform_point3(ray.origin.as_dvec3())
            .abs()
            .as_vec3();
        let si = SurfaceInteraction {
            p,
            p_error: gamma(7) * (p.abs() + reach) + Vec3::splat(1e-6),
            n,
            ns,
            uv: Vec2::ZERO,
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            tangent: None,
        };
        self.transform.interaction_to_world(&si)
    }

    /// Hansson-Söderlund et al.'s smooth normal at grid point `g` (grid coordinates): the
    /// gradients of the eight voxels around the nearest grid vertex, each the differences of the
    /// interpolated function between the voxel's two faces along each axis (at `g`'s position
    /// across that axis), normalized and blended trilinearly by `g`'s position among the voxels'
    /// centres. Voxels beyond the grid's lower faces get no weight; beyond its upper faces their
    /// differences vanish (the samples are clamped), as in Mitsuba.
    fn smooth_normal(&self, g: DVec3) -> DVec3 {
        let res = self.resolution();
        let nearest = g.round();
        let lower: [i64; 3] = std::array::from_fn(|a| nearest[a] as i64 - 1);
        let mut blend = g - nearest + DVec3::splat(0.5);
        let cell: [i64; 3] =
            std::array::from_fn(|a| (g[a].floor() as i64).clamp(0, self.n[a] as i64 - 2));
        let frac = DVec3::new(
            g.x - cell[0] as f64,
            g.y - cell[1] as f64,
            g.z - cell[2] as f64,
        );
        // The function on the grid plane of index q across axis a, at g's position along the
        // other two axes.
        let plane = |a: usize, q: i64| -> f64 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let mut f = [0.0; 4];
            for (i, fi) in f.iter_mut().enumerate() {
                let mut idx = [0i64; 3];
                idx[a] = q;
                idx[b] = cell[b] + (i & 1) as i64;
                idx[c] = cell[c] + (i >> 1) as i64;
                *fi = self.sample(idx);
            }
            let lerp = |x: f64, y: f64, t: f64| x + (y - x) * t;
            lerp(
                lerp(f[0], f[1], frac[b]),
                lerp(f[2], f[3], frac[b]),
                frac[c],
            )
        };
        // Differences across the lower and the upper voxel along each axis.
        let mut diff = [[0.0; 3]; 2];
        for a in 0..3 {
            for (side, d) in diff.iter_mut().enumerate() {
                let q = lower[a] + side as i64;
                d[a] = (plane(a, q + 1) - plane(a, q)) * res[a];
            }
        }
        for a in 0..3 {
            if lower[a] < 0 {
                blend[a] = 1.0;
            }
        }
        let mut sum = DVec3::ZERO;
        for i in 0..8 {
            let hi = [i & 1 != 0, i & 2 != 0, i & 4 != 0];
            if (0..3).any(|a| !hi[a] && lower[a] < 0) {
                continue;
            }
            let grad = DVec3::from_array(std::array::from_fn(|a| diff[hi[a] as usize][a]));
            let weight: f64 = (0..3)
                .map(|a| if hi[a] { blend[a] } else { 1.0 - blend[a] })
                .product();
            sum += weight * grad.normalize_or_zero();
        }
        sum
    }
}

/// Trilinear interpolation of corner values `c` (x + 2y + 4z) at `p` in the unit cube.
fn trilinear(c: &[f64; 8], p: DVec3) -> f64 {
    let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
    let x00 = lerp(c[0], c[1], p.x);
    let x10 = lerp(c[2], c[3], p.x);
    let x01 = lerp(c[4], c[5], p.x);
    let x11 = lerp(c[6], c[7], p.x);
    lerp(lerp(x00, x10, p.y), lerp(x01, x11, p.y), p.z)
}

fn trilinear_gradient(c: &[f64; 8], p: DVec3) -> DVec3 {
    let bilerp = |f: [f64; 4], u: f64, v: f64| {
        let a = f[0] + (f[1] - f[0]) * u;
        let b = f[2] + (f[3] - f[2]) * u;
        a + (b - a) * v
    };
    DVec3::new(
        bilerp(
            [c[1] - c[0], c[3] - c[2], c[5] - c[4], c[7] - c[6]],
            p.y,
            p.z,
        ),
        bilerp(
            [c[2] - c[0], c[3] - c[1], c[6] - c[4], c[7] - c[5]],
            p.x,
            p.z,
        ),
        bilerp(
            [c[4] - c[0], c[5] - c[1], c[6] - c[2], c[7] - c[3]],
            p.x,
            p.y,
        ),
    )
}

/// The coefficients `[c0, c1, c2, c3]` of the trilinear function along `p + s d`. Written as
/// `f = k0 + k1 x + k2 y + k4 z + k3 xy + k5 xz + k6 yz + k7 xyz`, each product of linear
/// functions of `s` expands into its powers.
fn cubic_along(c: &[f64; 8], p: DVec3, d: DVec3) -> [f64; 4] {
    let k0 = c[0];
    let k1 = c[1] - c[0];
    let k2 = c[2] - c[0];
    let k4 = c[4] - c[0];
    let k3 = c[3] - c[2] - c[1] + c[0];
    let k5 = c[5] - c[4] - c[1] + c[0];
    let k6 = c[6] - c[4] - c[2] + c[0];
    let k7 = c[7] - c[6] - c[5] - c[3] + c[4] + c[2] + c[1] - c[0];
    // Linear factors (a + b s) multiplied as polynomials.
    let mul = |x: [f64; 4], a: f64, b: f64| {
        [
            x[0] * a,
            x[1] * a + x[0] * b,
            x[2] * a + x[1] * b,
            x[3] * a + x[2] * b,
        ]
    };
    let one = [1.0, 0.0, 0.0, 0.0];
    let x = mul(one, p.x, d.x);
    let y = mul(one, p.y, d.y);
    let xy = mul(x, p.y, d.y);
    let xz = mul(x, p.z, d.z);
    let yz = mul(y, p.z, d.z);
    let xyz = mul(xy, p.z, d.z);
    let z = mul(one, p.z, d.z);
    std::array::from_fn(|i| {
        k0 * one[i]
            + k1 * x[i]
            + k2 * y[i]
            + k4 * z[i]
            + k3 * xy[i]
            + k5 * xz[i]
            + k6 * yz[i]
            + k7 * xyz[i]
    })
}

/// Real roots of `a s^2 + b s + c` (a linear or constant one when `a` vanishes).
fn quadratic_roots(a: f64, b: f64, c: f64) -> Vec<f64> {
    if a == 0.0 {
        return if b != 0.0 { vec![-c / b] } else { vec![] };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return vec![];
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let mut r = vec![q / a];
    if q != 0.0 {
        r.push(c / q);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere of radius 0.3 about the grid's centre, sampled exactly.
    fn sphere_grid(n: usize, normals: SdfNormals) -> SdfGrid {
        let mut values = Vec::with_capacity(n * n * n);
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let p = DVec3::new(i as f64, j as f64, k as f64) / (n - 1) as f64;
                    values.push(((p - DVec3::splat(0.5)).length() - 0.3) as f32);
                }
            }
        }
        SdfGrid::new([n, n, n], values, Mat4::IDENTITY, normals).unwrap()
    }

    #[test]
    fn the_cubic_is_the_trilinear_function_along_the_ray() {
        let c = [0.3, -0.2, 0.5, 0.1, -0.7, 0.4, 0.2, -0.1];
        let p = DVec3::new(0.1, 0.7, 0.3);
        let d = DVec3::new(0.4, -0.5, 0.6);
        let k = cubic_along(&c, p, d);
        for s in [0.0, 0.3, 0.9] {
            let poly = ((k[3] * s + k[2]) * s + k[1]) * s + k[0];
            assert!((poly - trilinear(&c, p + s * d)).abs() < 1e-12);
        }
        // The gradient against central differences.
        let g = trilinear_gradient(&c, p);
        let h = 1e-6;
        for a in 0..3 {
            let mut e = DVec3::ZERO;
            e[a] = h;
            let fd = (trilinear(&c, p + e) - trilinear(&c, p - e)) / (2.0 * h);
            assert!((fd - g[a]).abs() < 1e-6);
        }
    }

    /// Rays at a sampled sphere hit within a fraction of a voxel of the sphere, where the
    /// interpolated function vanishes, with normals close to the sphere's; rays beside it miss.
    #[test]
    fn a_sampled_sphere_is_hit_where_it_is() {
        for normals in [SdfNormals::Analytic, SdfNormals::Smooth] {
            let g = sphere_grid(33, normals);
            let mut hits = 0;
            for i in 0..40 {
                for j in 0..40 {
                    let target = Vec3::new(0.5, i as f32 / 39.0, j as f32 / 39.0);
                    let o = Vec3::new(-2.0, 0.5, 0.5);
                    let ray = Ray::new(o, target - o);
                    let dist = (target - Vec3::new(0.5, 0.5, 0.5)).length();
                    let h = g.intersect(&ray, f32::INFINITY);
                    // The line's distance from the centre decides, away from the silhouette.
                    let ray_dist = {
                        let c = Vec3::splat(0.5) - o;
                        let dir = ray.dir.normalize();
                        (c - c.dot(dir) * dir).length()
                    };
                    if ray_dist < 0.28 {
                        let h = h.expect("a ray through the sphere hits it");
                        hits += 1;
                        let si = g.interaction(&ray, &h);
                        let r = (si.p - Vec3::splat(0.5)).length();
                        assert!((r - 0.3).abs() < 2e-3, "{r}");
                        let radial = (si.p - Vec3::splat(0.5)).normalize();
                        assert!(si.n.dot(radial) > 0.99 && si.ns.dot(radial) > 0.99);
                    } else if ray_dist > 0.32 {
                        assert!(h.is_none(), "{dist}");
                    }
                }
            }
            assert!(hits > 200);
        }
    }

    /// Leaving the surface along its normal finds nothing more than the far side of the sphere.
    #[test]
    fn rays_leaving_the_surface_do_not_hit_it_again_at_once() {
        let g = sphere_grid(17, SdfNormals::Smooth);
        let ray = Ray::new(Vec3::new(-1.0, 0.52, 0.47), Vec3::X);
        let h = g.intersect(&ray, f32::INFINITY).unwrap();
        let si = g.interaction(&ray, &h);
        let out = Ray::new(
            crate::math::offset_ray_origin(si.p, si.p_error, si.n, si.n),
            si.n,
        );
        assert!(g.intersect(&out, f32::INFINITY).is_none());
        let inward = Ray::new(
            crate::math::offset_ray_origin(si.p, si.p_error, si.n, -si.n),
            -si.n,
        );
        let far = g.intersect(&inward, f32::INFINITY).unwrap();
        assert!(far.t > 0.5, "{}", far.t);
    }

    #[test]
    fn grids_without_a_surface_are_rejected() {
        let e = SdfGrid::new([2, 2, 2], vec![1.0; 8], Mat4::IDENTITY, SdfNormals::Smooth);
        assert!(e.unwrap_err().contains("no surface"));
        let e = SdfGrid::new([1, 2, 2], vec![1.0; 4], Mat4::IDENTITY, SdfNormals::Smooth);
        assert!(e.is_err());
    }
}
