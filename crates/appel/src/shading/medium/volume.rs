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

    #[inline]
    fn at(&self, i: [usize; 3]) -> Vec3 {
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
        let res = self.resolution.map(|r| r as f32);
        let clamp = |x: f32, r: usize| (x.max(0.0) as usize).min(r - 1);
        if self.nearest {
            let i = [0, 1, 2].map(|k| clamp((p[k] * res[k]).floor(), self.resolution[k]));
            return self.at(i);
        }
        let q = [0, 1, 2].map(|k| p[k] * res[k] - 0.5);
        let base = q.map(f32::floor);
        let f = [0, 1, 2].map(|k| q[k] - base[k]);
        let lo = [0, 1, 2].map(|k| clamp(base[k], self.resolution[k]));
        let hi = [0, 1, 2].map(|k| clamp(base[k] + 1.0, self.resolution[k]));
        let mut v = Vec3::ZERO;
        for corner in 0..8 {
            let pick = |k: usize| corner >> k & 1 == 1;
            let i = [0, 1, 2].map(|k| if pick(k) { hi[k] } else { lo[k] });
            let w: f32 = (0..3)
                .map(|k| if pick(k) { f[k] } else { 1.0 - f[k] })
                .product();
            if w > 0.0 {
                v += self.at(i) * w;
            }
        }
        v
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
