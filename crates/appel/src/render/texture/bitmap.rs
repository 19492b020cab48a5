//! Mitsuba's `bitmap` texture: uv (0, 0) is the top-left corner of the image (no v flip: the first
//! row stored is v = 0), pixel (x, y) covers [x, x+1]/width by [y, y+1]/height and its value sits at
//! its centre; bilinear lookups blend the four nearest centres, and wrap modes act on whole-pixel
//! indices (Dr.Jit's `Texture::eval`, which Mitsuba's texture calls).

use super::{luminance, transform_uv};
use crate::io::bitmap_read::Bitmap;
use glam::{Mat3, Vec2, Vec3};
use std::sync::Arc;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    #[default]
    Bilinear,
    Nearest,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    #[default]
    Repeat,
    Mirror,
    Clamp,
}

impl Wrap {
    /// Brings a pixel index into [0, n).
    #[inline]
    fn apply(self, i: i64, n: i64) -> usize {
        let j = match self {
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Mirror => {
                // Period 2n: the image, then its reflection (pixel -1 is pixel 0).
                let m = i.rem_euclid(2 * n);
                if m < n {
                    m
                } else {
                    2 * n - 1 - m
                }
            }
        };
        j as usize
    }
}

/// An image on uv. Colour bitmaps (RGB, RGBA) are looked up as RGB and grey ones (Y, YA) as grey;
/// alpha is ignored, as Mitsuba's texture drops it.
///
/// Mitsuba stores 8- and 16-bit sources in half precision (its `format = "auto"`); values here keep
/// the reader's f32, so lookups may differ from Mitsuba's in the fourth significant digit.
#[derive(Clone, Debug)]
pub struct BitmapTexture {
    bitmap: Arc<Bitmap>,
    pub filter: Filter,
    pub wrap: Wrap,
    /// 2D affine map applied to uv before the lookup.
    pub to_uv: Mat3,
    mean: Vec3,
}

impl BitmapTexture {
    /// `bitmap` must have at least one pixel and 1 to 4 channels.
    pub fn new(bitmap: Arc<Bitmap>, filter: Filter, wrap: Wrap, to_uv: Mat3) -> Self {
        assert!(
            bitmap.width > 0 && bitmap.height > 0 && (1..=4).contains(&bitmap.channels),
            "BitmapTexture: empty bitmap or unsupported channel count"
        );
        let mut t = Self {
            bitmap,
            filter,
            wrap,
            to_uv,
            mean: Vec3::ZERO,
        };
        let mut sum = [0.0f64; 3];
        for y in 0..t.bitmap.height {
            for x in 0..t.bitmap.width {
                let v = t.texel(x as usize, y as usize);
                for (s, c) in sum.iter_mut().zip(v.to_array()) {
                    *s += c as f64;
                }
            }
        }
        let n = (t.bitmap.width as f64) * (t.bitmap.height as f64);
        t.mean = Vec3::new(
            (sum[0] / n) as f32,
            (sum[1] / n) as f32,
            (sum[2] / n) as f32,
        );
        t
    }

    pub fn bitmap(&self) -> &Arc<Bitmap> {
        &self.bitmap
    }

    /// Whether the image is grey (one value per pixel, before alpha).
    pub fn is_grey(&self) -> bool {
        self.bitmap.channels <= 2
    }

    /// Pixel (x, y) as RGB (grey repeated).
    #[inline]
    fn texel(&self, x: usize, y: usize) -> Vec3 {
        let c = self.bitmap.channels as usize;
        let i = (y * self.bitmap.width as usize + x) * c;
        let d = &self.bitmap.data[i..];
        if c <= 2 {
            Vec3::splat(d[0])
        } else {
            Vec3::new(d[0], d[1], d[2])
        }
    }

    pub fn eval(&self, uv: Vec2) -> Vec3 {
        let p = transform_uv(&self.to_uv, uv);
        let (w, h) = (self.bitmap.width as i64, self.bitmap.height as i64);
        let (sx, sy) = (p.x * w as f32, p.y * h as f32);
        match self.filter {
            Filter::Nearest => {
                let x = self.wrap.apply(sx.floor() as i64, w);
                let y = self.wrap.apply(sy.floor() as i64, h);
                self.texel(x, y)
            }
            Filter::Bilinear => {
                // Continuous pixel coordinates with the centres at integers.
                let (fx, fy) = (sx - 0.5, sy - 0.5);
                let (x0, y0) = (fx.floor(), fy.floor());
                let (wx, wy) = (fx - x0, fy - y0);
                let (x0, y0) = (x0 as i64, y0 as i64);
                let (xa, xb) = (self.wrap.apply(x0, w), self.wrap.apply(x0 + 1, w));
                let (ya, yb) = (self.wrap.apply(y0, h), self.wrap.apply(y0 + 1, h));
                let top = self.texel(xa, ya) * (1.0 - wx) + self.texel(xb, ya) * wx;
                let bottom = self.texel(xa, yb) * (1.0 - wx) + self.texel(xb, yb) * wx;
                top * (1.0 - wy) + bottom * wy
            }
        }
    }

    /// A grey image's value, a colour image's luminance (Mitsuba's `eval_1`).
    pub fn eval_1(&self, uv: Vec2) -> f32 {
        let v = self.eval(uv);
        if self.is_grey() {
            v.x
        } else {
            luminance(v)
        }
    }

    /// Per-channel mean of the pixels.
    pub fn mean(&self) -> Vec3 {
        self.mean
    }
}
