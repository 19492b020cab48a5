//! Mitsuba's `bitmap` texture: uv (0, 0) is the top-left corner of the image (no v flip: the first
//! row stored is v = 0), pixel (x, y) covers [x, x+1]/width by [y, y+1]/height and its value sits at
//! its centre; bilinear lookups blend the four nearest centres, and wrap modes act on whole-pixel
//! indices (Dr.Jit's `Texture::eval`, which Mitsuba's texture calls).

use super::{luminance, transform_uv};
pub use crate::description::texture_lookup::{Filter, Wrap};
use crate::io::bitmap_read::Bitmap;
use glam::{Mat3, Vec2, Vec3};
use std::sync::Arc;

/// Brings a pixel index into [0, n) as `wrap` says.
#[inline]
fn wrap_index(wrap: Wrap, i: i64, n: i64) -> usize {
    let j = match wrap {
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
                let x = wrap_index(self.wrap, sx.floor() as i64, w);
                let y = wrap_index(self.wrap, sy.floor() as i64, h);
                self.texel(x, y)
            }
            Filter::Bilinear => {
                // Continuous pixel coordinates with the centres at integers.
                let (fx, fy) = (sx - 0.5, sy - 0.5);
                let (x0, y0) = (fx.floor(), fy.floor());
                let (wx, wy) = (fx - x0, fy - y0);
                let (x0, y0) = (x0 as i64, y0 as i64);
                let (xa, xb) = (
                    wrap_index(self.wrap, x0, w),
                    wrap_index(self.wrap, x0 + 1, w),
                );
                let (ya, yb) = (
                    wrap_index(self.wrap, y0, h),
                    wrap_index(self.wrap, y0 + 1, h),
                );
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

    /// The gradient of [`Self::eval_1`] with respect to (u, v) (Mitsuba's `eval_1_grad`, which
    /// `bumpmap` reads): the derivative of the bilinear blend of the four texels' float values
    /// (a grey value or the luminance) inside the cell, times the resolution, carried back through
    /// `to_uv` by its transpose. Piecewise constant lookups have no gradient.
    pub fn eval_1_grad(&self, uv: Vec2) -> Vec2 {
        if self.filter == Filter::Nearest {
            return Vec2::ZERO;
        }
        let p = transform_uv(&self.to_uv, uv);
        let (w, h) = (self.bitmap.width as i64, self.bitmap.height as i64);
        let (fx, fy) = (p.x * w as f32 - 0.5, p.y * h as f32 - 0.5);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (wx, wy) = (fx - x0, fy - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let (xa, xb) = (
            wrap_index(self.wrap, x0, w),
            wrap_index(self.wrap, x0 + 1, w),
        );
        let (ya, yb) = (
            wrap_index(self.wrap, y0, h),
            wrap_index(self.wrap, y0 + 1, h),
        );
        let value = |x, y| {
            let c = self.texel(x, y);
            if self.is_grey() {
                c.x
            } else {
                luminance(c)
            }
        };
        let (f00, f10, f01, f11) = (value(xa, ya), value(xb, ya), value(xa, yb), value(xb, yb));
        // Per pixel of x and y...
        let dx = (1.0 - wy) * (f10 - f00) + wy * (f11 - f01);
        let dy = (1.0 - wx) * (f01 - f00) + wx * (f11 - f10);
        // ...then per unit of the transformed uv, and through the map's linear part.
        let d = Vec2::new(dx * w as f32, dy * h as f32);
        let m = self.to_uv;
        Vec2::new(
            m.x_axis.x * d.x + m.x_axis.y * d.y,
            m.y_axis.x * d.x + m.y_axis.y * d.y,
        )
    }

    /// Per-channel mean of the pixels.
    pub fn mean(&self) -> Vec3 {
        self.mean
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::bitmap_read::read_bitmap;
    use std::path::Path;

    /// The 3x2 sRGB test image: rows (10,20,30) (200,100,50) (255,0,128) and (0,255,64)
    /// (90,90,90) (30,180,240), written as an 8-bit RGB PNG.
    fn write_rgb_png(path: &Path) {
        let px: [u8; 18] = [
            10, 20, 30, 200, 100, 50, 255, 0, 128, 0, 255, 64, 90, 90, 90, 30, 180, 240,
        ];
        image::save_buffer(path, &px, 3, 2, image::ColorType::Rgb8).unwrap();
    }

    fn texture(path: &Path, raw: bool, filter: Filter, wrap: Wrap, to_uv: Mat3) -> BitmapTexture {
        BitmapTexture::new(
            Arc::new(read_bitmap(path, raw).unwrap()),
            filter,
            wrap,
            to_uv,
        )
    }

    fn assert_close(got: Vec3, want: [f32; 3], what: &str) {
        let w = Vec3::from_array(want);
        assert!((got - w).abs().max_element() < 2e-6, "{what}: {got} vs {w}");
    }

    const UVS: [(f32, f32); 5] = [
        (0.1, 0.2),
        (0.5, 0.5),
        (0.95, 0.9),
        (-0.3, 1.4),
        (1.7, -0.2),
    ];

    #[test]
    fn filters_and_wrap_modes_match_mitsuba() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rgb.png");
        write_rgb_png(&path);
        // Mitsuba 3.9 `bitmap` (format "variant", so stored in f32) at UVS, for each filter and
        // wrap mode.
        let expect: [(Filter, Wrap, [[f32; 3]; 5]); 6] = [
            (
                Filter::Bilinear,
                Wrap::Repeat,
                [
                    [0.182_445_03, 0.094_164_94, 0.069_731_57],
                    [0.339_911_28, 0.114_839_79, 0.067_068_905],
                    [0.201_226, 0.453_401_6, 0.452_489_05],
                    [0.596_328_6, 0.130_105_6, 0.268_707_28],
                    [0.126_921_13, 0.288_366_7, 0.521_572_9],
                ],
            ),
            (
                Filter::Bilinear,
                Wrap::Mirror,
                [
                    [0.003_035_27, 0.006_995_4, 0.012_983_06],
                    [0.339_911_28, 0.114_839_79, 0.067_068_905],
                    [0.012_983_059, 0.456_411_18, 0.871_366_9],
                    [0.098_483_76, 0.465_179_38, 0.056_325_346],
                    [0.232_853_25, 0.055_172_306, 0.020_548_226],
                ],
            ),
            (
                Filter::Bilinear,
                Wrap::Clamp,
                [
                    [0.003_035_27, 0.006_995_4, 0.012_983_06],
                    [0.339_911_28, 0.114_839_79, 0.067_068_905],
                    [0.012_983_059, 0.456_411_18, 0.871_366_9],
                    [0.0, 1.0, 0.051_269_43],
                    [1.0, 0.0, 0.215_860_44],
                ],
            ),
            (
                Filter::Nearest,
                Wrap::Repeat,
                [
                    [0.003_035_27, 0.006_995_4, 0.012_983_06],
                    [0.102_241_81, 0.102_241_81, 0.102_241_81],
                    [0.012_983_06, 0.456_411_18, 0.871_366_9],
                    [1.0, 0.0, 0.215_860_43],
                    [0.012_983_06, 0.456_411_18, 0.871_366_9],
                ],
            ),
            (
                Filter::Nearest,
                Wrap::Mirror,
                [
                    [0.003_035_27, 0.006_995_4, 0.012_983_06],
                    [0.102_241_81, 0.102_241_81, 0.102_241_81],
                    [0.012_983_06, 0.456_411_18, 0.871_366_9],
                    [0.0, 1.0, 0.051_269_434],
                    [0.003_035_27, 0.006_995_4, 0.012_983_06],
                ],
            ),
            (
                Filter::Nearest,
                Wrap::Clamp,
                [
                    [0.003_035_27, 0.006_995_4, 0.012_983_06],
                    [0.102_241_81, 0.102_241_81, 0.102_241_81],
                    [0.012_983_06, 0.456_411_18, 0.871_366_9],
                    [0.0, 1.0, 0.051_269_434],
                    [1.0, 0.0, 0.215_860_43],
                ],
            ),
        ];
        for (filter, wrap, values) in expect {
            let t = texture(&path, false, filter, wrap, Mat3::IDENTITY);
            for ((u, v), want) in UVS.iter().zip(values) {
                assert_close(
                    t.eval(Vec2::new(*u, *v)),
                    want,
                    &format!("{filter:?} {wrap:?} ({u}, {v})"),
                );
            }
        }
        // raw: no sRGB decode.
        let raw = texture(&path, true, Filter::Bilinear, Wrap::Repeat, Mat3::IDENTITY);
        assert_close(
            raw.eval(Vec2::new(0.1, 0.2)),
            [0.210_588_2, 0.150_588_26, 0.213_960_8],
            "raw",
        );
        assert_close(
            raw.eval(Vec2::new(0.5, 0.5)),
            [0.568_627_5, 0.372_549_06, 0.274_509_82],
            "raw",
        );
        // to_uv = translate(0.25, -0.1) * scale(2, 0.5), as Mitsuba's 4x4 to_uv applies it.
        let m =
            Mat3::from_translation(Vec2::new(0.25, -0.1)) * Mat3::from_scale(Vec2::new(2.0, 0.5));
        let t = texture(&path, false, Filter::Bilinear, Wrap::Repeat, m);
        let want = [
            [0.289_152_24, 0.173_138_5, 0.061_827_507],
            [0.122_449_405, 0.184_796_89, 0.026_971_54],
            [0.042_436_406, 0.199_880_63, 0.036_956_31],
        ];
        for ((u, v), w) in UVS.iter().zip(want) {
            assert_close(t.eval(Vec2::new(*u, *v)), w, "to_uv");
        }
        // Mitsuba's mean is the luminance of the pixels' mean (0.277377576, from f16 storage).
        let mean = texture(&path, false, Filter::Bilinear, Wrap::Repeat, Mat3::IDENTITY).mean();
        assert!((crate::shading::texture::luminance(mean) - 0.277_377_58).abs() < 2e-4);
    }

    #[test]
    fn bilinear_weights_by_hand() {
        // A 2x2 grey image of values 0, 1 / 2, 3: at uv (0.5, 0.5) all four pixel centres are half
        // a pixel away, so the mean 1.5; at a pixel centre, that pixel.
        let bitmap = Bitmap {
            width: 2,
            height: 2,
            channels: 1,
            data: vec![0.0, 1.0, 2.0, 3.0],
        };
        let t = BitmapTexture::new(
            Arc::new(bitmap),
            Filter::Bilinear,
            Wrap::Clamp,
            Mat3::IDENTITY,
        );
        assert_eq!(t.eval_1(Vec2::new(0.5, 0.5)), 1.5);
        assert_eq!(t.eval_1(Vec2::new(0.75, 0.25)), 1.0);
        // A quarter of the way from the centre of (0, 1) to that of (1, 1): 2 + 0.25.
        assert_eq!(t.eval_1(Vec2::new(0.375, 0.75)), 2.25);
        assert_eq!(t.eval(Vec2::new(0.25, 0.75)), Vec3::splat(2.0));
        assert_eq!(t.mean(), Vec3::splat(1.5));
        // Mirror: pixel indices -1 and 2 reflect onto 0 and 1; repeat wraps them across.
        let m = BitmapTexture {
            wrap: Wrap::Mirror,
            filter: Filter::Nearest,
            ..t.clone()
        };
        assert_eq!(m.eval_1(Vec2::new(-0.25, 0.25)), 0.0);
        assert_eq!(m.eval_1(Vec2::new(1.25, 0.25)), 1.0);
        assert_eq!(m.eval_1(Vec2::new(-0.75, 0.25)), 1.0);
        let r = BitmapTexture {
            wrap: Wrap::Repeat,
            filter: Filter::Nearest,
            ..t
        };
        assert_eq!(r.eval_1(Vec2::new(-0.25, 0.25)), 1.0);
        assert_eq!(r.eval_1(Vec2::new(1.25, -0.25)), 2.0);
    }

    /// The gradient is the derivative of `eval_1`: central differences inside a cell, through a
    /// uv map that scales, shears and translates.
    #[test]
    fn gradient_is_the_derivative_of_the_lookup() {
        let bitmap = Bitmap {
            width: 3,
            height: 2,
            channels: 3,
            data: vec![
                0.1, 0.7, 0.2, 0.9, 0.3, 0.4, 0.5, 0.5, 0.1, 0.0, 0.2, 0.8, 0.6, 0.6, 0.6, 1.0,
                0.0, 0.3,
            ],
        };
        let m = Mat3::from_cols_array_2d(&[[1.5, 0.3, 0.0], [-0.2, 0.8, 0.0], [0.1, 0.25, 1.0]]);
        let t = BitmapTexture::new(Arc::new(bitmap), Filter::Bilinear, Wrap::Repeat, m);
        let h = 1e-3;
        for uv in [
            Vec2::new(0.31, 0.42),
            Vec2::new(-0.7, 1.33),
            Vec2::new(0.9, 0.05),
        ] {
            let g = t.eval_1_grad(uv);
            let du = (t.eval_1(uv + Vec2::X * h) - t.eval_1(uv - Vec2::X * h)) / (2.0 * h);
            let dv = (t.eval_1(uv + Vec2::Y * h) - t.eval_1(uv - Vec2::Y * h)) / (2.0 * h);
            assert!(
                (g - Vec2::new(du, dv)).length() < 2e-3 * (1.0 + g.length()),
                "{uv}: {g} vs {du}, {dv}"
            );
        }
        let nearest = BitmapTexture {
            filter: Filter::Nearest,
            ..t
        };
        assert_eq!(nearest.eval_1_grad(Vec2::new(0.31, 0.42)), Vec2::ZERO);
    }
}
