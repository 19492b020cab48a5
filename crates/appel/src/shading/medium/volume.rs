//! Mitsuba 3's volumes: values over the unit cube `[0, 1]^3` placed in the world by a transform.
//! A `constvolume` is one value; a `gridvolume` holds a `.vol` grid whose samples sit at the
//! centres of the `res` cells along each axis, looked up at `p * res - 1/2` trilinearly (or at
//! the nearest cell) with the indices clamped at the border, as Mitsuba's `grid` plugin does with
//! its clamp wrap mode.

use crate::io::grid_volume::GridVolume;
use crate::math::{Ray, Vec3};
use glam::Mat4;

#[derive(Clone, Debug)]
pub struct Volume {
    /// World to the unit cube.
    pub to_local: Mat4,
    pub values: VolumeValues,
}

#[derive(Clone, Debug)]
pub enum VolumeValues {
    Constant(Vec3),
    Grid(Grid),
}

/// A grid of one or three channels, x fastest.
#[derive(Clone, Debug)]
pub struct Grid {
    pub resolution: [usize; 3],
    /// 1 (grey) or 3 (RGB).
    pub channels: usize,
    pub data: Vec<f32>,
    pub nearest: bool,
}

impl Grid {
    pub fn new(g: GridVolume, nearest: bool) -> Self {
        Grid {
            resolution: g.resolution,
            channels: g.channels,
            data: g.data,
            nearest,
        }
    }

    /// The sample at `i` (x, y, z).
    #[inline]
    pub fn at(&self, i: [usize; 3]) -> Vec3 {
        let [rx, ry, _] = self.resolution;
        let k = ((i[2] * ry + i[1]) * rx + i[0]) * self.channels;
        if self.channels == 1 {
            Vec3::splat(self.data[k])
        } else {
            Vec3::new(self.data[k], self.data[k + 1], self.data[k + 2])
        }
    }

    /// The value of cell `i` of the data (x fastest).
    pub fn cell(&self, i: usize) -> Vec3 {
        let k = i * self.channels;
        if self.channels == 1 {
            Vec3::splat(self.data[k])
        } else {
            Vec3::new(self.data[k], self.data[k + 1], self.data[k + 2])
        }
    }

    /// The value at a point of the unit cube (clamped outside it).
    #[inline]
    pub fn eval(&self, p: Vec3) -> Vec3 {
        let [rx, ry, rz] = self.resolution;
        if self.nearest {
            let clamp = |x: f32, r: usize| ((x * r as f32).max(0.0) as usize).min(r - 1);
            return self.at([clamp(p.x, rx), clamp(p.y, ry), clamp(p.z, rz)]);
        }
        // Per axis: the two samples around `p * res - 1/2` (clamped) and the weight of the
        // second; flat offsets so that the eight reads share their arithmetic.
        let axis = |x: f32, r: usize, stride: usize| {
            let q = x * r as f32 - 0.5;
            let base = q.floor();
            let lo = (base.max(0.0) as usize).min(r - 1);
            let hi = ((base + 1.0).max(0.0) as usize).min(r - 1);
            (lo * stride, hi * stride, q - base)
        };
        let (x0, x1, fx) = axis(p.x, rx, 1);
        let (y0, y1, fy) = axis(p.y, ry, rx);
        let (z0, z1, fz) = axis(p.z, rz, rx * ry);
        let lerp = |a: Vec3, b: Vec3, f: f32| a + (b - a) * f;
        if self.channels == 1 {
            let d = &self.data;
            let lerp = |a: f32, b: f32, f: f32| a + (b - a) * f;
            let row = |y: usize, z: usize| lerp(d[z + y + x0], d[z + y + x1], fx);
            let plane = |z: usize| lerp(row(y0, z), row(y1, z), fy);
            return Vec3::splat(lerp(plane(z0), plane(z1), fz));
        }
        let at = |k: usize| Vec3::new(self.data[3 * k], self.data[3 * k + 1], self.data[3 * k + 2]);
        let row = |y: usize, z: usize| lerp(at(z + y + x0), at(z + y + x1), fx);
        let plane = |z: usize| lerp(row(y0, z), row(y1, z), fy);
        lerp(plane(z0), plane(z1), fz)
    }

    /// The largest value of any channel (a bound on every interpolated value).
    pub fn max(&self) -> f32 {
        self.data.iter().copied().fold(0.0, f32::max)
    }
}

impl Volume {
    /// The value at world point `p`.
    #[inline]
    pub fn eval(&self, p: Vec3) -> Vec3 {
        match &self.values {
            VolumeValues::Constant(c) => *c,
            VolumeValues::Grid(g) => g.eval(self.to_local.transform_point3(p)),
        }
    }

    /// The largest value of any channel anywhere.
    pub fn max(&self) -> f32 {
        match &self.values {
            VolumeValues::Constant(c) => c.max_element(),
            VolumeValues::Grid(g) => g.max(),
        }
    }

    /// Where `ray` is inside the volume's box, within `[0, t_max]` (the ray's own parameter: the
    /// box test runs on the ray carried into the unit cube's space, not renormalised).
    #[inline]
    pub fn range(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32)> {
        let o = self.to_local.transform_point3(ray.origin);
        let d = self.to_local.transform_vector3(ray.dir);
        let (mut t0, mut t1) = (0.0f32, t_max);
        for k in 0..3 {
            let inv = 1.0 / d[k];
            let (a, b) = ((0.0 - o[k]) * inv, (1.0 - o[k]) * inv);
            let (near, far) = if a <= b { (a, b) } else { (b, a) };
            // NaN (a ray in the slab's plane) leaves the interval as it is.
            if near > t0 {
                t0 = near;
            }
            if far < t1 {
                t1 = far;
            }
            if t0 > t1 {
                return None;
            }
        }
        Some((t0, t1))
    }
}
