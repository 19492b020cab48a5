//! Renders compared with reference images statistically, as Mitsuba's own render tests do: a
//! per-pixel z-test with the render's own variance and a Šidák-corrected threshold, and the
//! per-channel ratio of the image means.

use appel::description::Description;
use appel::io::bitmap_read::read_bitmap;
use appel::render::{render, Film, RenderOptions};
use appel::scene::Scene;
use std::path::{Path, PathBuf};

#[path = "../common/normal.rs"]
mod normal;
use normal::erfc;

/// The path of `rel` in the shared data (tests calling it are marked as needing the data).
pub fn shared(rel: &str) -> PathBuf {
    appel_testdata::path(rel)
}

/// How a render compares with its reference.
#[derive(Debug)]
pub struct Comparison {
    /// The smallest two-sided p-value of the per-pixel, per-channel z-tests.
    pub min_p: f64,
    /// The Šidák-corrected per-test threshold for a 1% chance of a false failure.
    pub alpha: f64,
    /// Where the smallest p-value is: (x, y, channel), ours, reference, our standard deviation
    /// (printed by the failures' messages).
    #[allow(dead_code)]
    pub worst: (u32, u32, usize, f32, f32, f32),
    /// Per channel: our mean / the reference's, and that ratio's allowed deviation from 1 (1%
    /// plus three standard deviations of our mean).
    pub mean_ratio: [f64; 3],
    pub ratio_tolerance: [f64; 3],
}

impl Comparison {
    pub fn passes(&self) -> bool {
        self.min_p >= self.alpha
            && (0..3).all(|c| (self.mean_ratio[c] - 1.0).abs() <= self.ratio_tolerance[c])
    }
}

pub struct Setup {
    pub spp: u32,
    /// Compare means over blocks of this many pixels square (1: pixel by pixel), so that a large
    /// reference is tested at full resolution with few samples per pixel.
    pub block: u32,
}

/// An image and its per-pixel variance of the estimate, averaged over blocks.
pub struct Averaged {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[f32; 3]>,
    pub variance: Vec<[f32; 3]>,
    /// Samples behind each value.
    pub samples: u32,
}

pub fn render_xml(scene: &Path, setup: &Setup) -> Averaged {
    render_xml_with(scene, setup, |_| {})
}

/// [`render_xml`] with the description changed by `adjust` first (a smaller film, another filter).
pub fn render_xml_with(
    scene: &Path,
    setup: &Setup,
    adjust: impl FnOnce(&mut Description),
) -> Averaged {
    render_xml_with_params(scene, setup, &[], adjust)
}

/// [`render_xml_with`] with Mitsuba `-D name=value` parameters.
pub fn render_xml_with_params(
    scene: &Path,
    setup: &Setup,
    params: &[(&str, &str)],
    adjust: impl FnOnce(&mut Description),
) -> Averaged {
    let options = appel::format::FormatOptions {
        params: params
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
    };
    let loaded = appel::format::load(scene, &options).unwrap_or_else(|e| panic!("{e}"));
    render_loaded(loaded, setup, adjust)
}

/// Renders a scene read by any reader, its description changed by `adjust` first.
pub fn render_loaded(
    loaded: appel::format::LoadedDescription,
    setup: &Setup,
    adjust: impl FnOnce(&mut Description),
) -> Averaged {
    let mut d = loaded.description;
    d.render.spp = setup.spp;
    adjust(&mut d);
    let scene = Scene::new(&d, &loaded.base_dir).unwrap_or_else(|e| panic!("{e}"));
    let film = render(&scene, &RenderOptions::default()).unwrap().0;
    let filter = appel::render::filter::Filter::new(&d.render.filter);
    average(&film, setup.block, setup.spp, correlation(&filter))
}

/// How much a filter wider than the pixel makes the sum of its pixels' variances understate the
/// variance of a block mean: each sample counts in several pixels. Per axis, with support `2r`
/// and weights `w`, a pixel's estimate has the variance of `2r mean(w)^2 / mean(w^2)` fewer
/// samples than the block it sits in; the filter is separable, so the factor is squared (2.25 for
/// Mitsuba's tent, 1 for the box).
fn correlation(f: &appel::render::filter::Filter) -> f64 {
    let r = f.radius() as f64;
    let n = 10_000;
    let (mut m1, mut m2) = (0.0f64, 0.0f64);
    for k in 0..n {
        let x = -r + (k as f64 + 0.5) / n as f64 * 2.0 * r;
        let w = f.eval(x as f32) as f64;
        m1 += w / n as f64;
        m2 += w * w / n as f64;
    }
    let per_axis = 2.0 * r * m1 * m1 / m2;
    per_axis * per_axis
}

/// Block means of the film; the variance of a mean of `b^2` pixels is the sum of theirs over
/// `b^4`, times the filter's `correlation` where blocks are larger than a pixel.
fn average(film: &Film, b: u32, spp: u32, correlation: f64) -> Averaged {
    let correlation = if b > 1 { correlation } else { 1.0 };
    assert!(film.width.is_multiple_of(b) && film.height.is_multiple_of(b));
    assert_eq!(
        film.variance.len(),
        film.rgb.len(),
        "the render has no variance"
    );
    let (w, h) = (film.width / b, film.height / b);
    let mut rgb = vec![[0.0f32; 3]; (w * h) as usize];
    let mut variance = vec![[0.0f32; 3]; (w * h) as usize];
    let n = (b * b) as f64;
    for y in 0..h {
        for x in 0..w {
            let (mut s, mut v) = ([0.0f64; 3], [0.0f64; 3]);
            for j in 0..b {
                for i in 0..b {
                    let k = film.index(x * b + i, y * b + j);
                    for c in 0..3 {
                        s[c] += film.rgb[k][c] as f64;
                        v[c] += film.variance[k][c] as f64;
                    }
                }
            }
            rgb[(y * w + x) as usize] = s.map(|s| (s / n) as f32);
            variance[(y * w + x) as usize] = v.map(|v| (v * correlation / (n * n)) as f32);
        }
    }
    Averaged {
        width: w,
        height: h,
        rgb,
        variance,
        samples: spp * b * b,
    }
}

/// The reference's RGB, averaged down by whole blocks to `w x h`.
pub fn reference(path: &Path, w: u32, h: u32) -> Vec<[f32; 3]> {
    let b = read_bitmap(path, true).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        b.width.is_multiple_of(w) && b.height.is_multiple_of(h),
        "{}x{} does not divide into {w}x{h}",
        b.width,
        b.height
    );
    let (fx, fy) = (b.width / w, b.height / h);
    let mut out = vec![[0.0f32; 3]; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let mut s = [0.0f64; 3];
            for j in 0..fy {
                for i in 0..fx {
                    let p = b.pixel(x * fx + i, y * fy + j);
                    for c in 0..3 {
                        s[c] += p[c.min(p.len() - 1)] as f64;
                    }
                }
            }
            let n = (fx * fy) as f64;
            out[(y * w + x) as usize] = s.map(|v| (v / n) as f32);
        }
    }
    out
}

/// The standard normal's two-sided tail probability `P(|Z| > z)`, through `erfc`.
fn two_sided_p(z: f64) -> f64 {
    erfc(z.abs() / std::f64::consts::SQRT_2)
}

/// Compares `film` with `reference`. A pixel's variance is estimated from its own samples, and
/// where those are few or heavy-tailed (a caustic seen by a handful of samples, a silhouette
/// whose samples all missed) that estimate is far too small: each pixel's variance is therefore
/// taken as the largest of its 3x3 neighbourhood, and the per-sample variance is floored at 1e-4
/// as in Mitsuba's own render tests.
pub fn compare(film: &Averaged, reference: &[[f32; 3]]) -> Comparison {
    compare_within(film, reference, &vec![[0.0; 3]; reference.len()])
}

/// How far each value of a reference averaged over `block`-pixel squares (at `w` blocks a row) may
/// lie from the average of the true image over the block because of the reference's own
/// reconstruction filter, Mitsuba's and Tungsten's tent of radius one pixel: across an edge
/// between blocks the tent moves at most the light of a sixth of a pixel row (the mass of a step
/// convolved with the tent beyond the step, `∫₀¹ (1 - x)² / 2 dx`), so a block's average moves by
/// at most the contrast to a neighbouring block over `6 block`. A render at the reduced resolution
/// with a box filter has no such blur: without this allowance the sharp edge of a visible emitter
/// fails the z-test against a perfect reference.
pub fn tent_blur_allowance(reference: &[[f32; 3]], w: usize, block: u32) -> Vec<[f32; 3]> {
    let h = reference.len() / w;
    (0..reference.len())
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let neighbours = [
                (x > 0).then(|| i - 1),
                (x + 1 < w).then_some(i + 1),
                (y > 0).then(|| i - w),
                (y + 1 < h).then_some(i + w),
            ];
            std::array::from_fn(|c| {
                let contrast = neighbours
                    .iter()
                    .flatten()
                    .map(|&j| (reference[j][c] - reference[i][c]).abs())
                    .fold(0.0f32, f32::max);
                contrast / (6 * block) as f32
            })
        })
        .collect()
}

/// [`compare`], where each reference value may be off by up to `allowance` (a known, bounded
/// difference that is not noise) before the z-test counts the rest.
pub fn compare_within(
    film: &Averaged,
    reference: &[[f32; 3]],
    allowance: &[[f32; 3]],
) -> Comparison {
    let n = film.rgb.len();
    assert_eq!(n, reference.len());
    let samples = film.samples as f64;
    let (w, h) = (film.width as i64, film.height as i64);
    let neighbourhood_max = |i: usize, c: usize| {
        let (x, y) = (i as i64 % w, i as i64 / w);
        let mut m = 0.0f32;
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (nx, ny) = (x + dx, y + dy);
                if (0..w).contains(&nx) && (0..h).contains(&ny) {
                    m = m.max(film.variance[(ny * w + nx) as usize][c]);
                }
            }
        }
        m
    };
    let tests = (3 * n) as f64;
    let alpha = 1.0 - (1.0 - 0.01f64).powf(1.0 / tests);
    let mut min_p = 1.0f64;
    let mut worst = (0, 0, 0, 0.0, 0.0, 0.0);
    let mut sum = [0.0f64; 3];
    let mut sum_ref = [0.0f64; 3];
    let mut sum_var = [0.0f64; 3];
    for (i, reference) in reference.iter().enumerate() {
        let ours = film.rgb[i];
        let var = film.variance[i];
        for c in 0..3 {
            let r = reference[c] as f64;
            let o = ours[c] as f64;
            let v = (neighbourhood_max(i, c) as f64 * samples).max(1e-4) / samples;
            let excess = ((o - r).abs() - allowance[i][c] as f64).max(0.0);
            let p = two_sided_p(excess / v.sqrt());
            if p < min_p {
                min_p = p;
                let (x, y) = (i as u32 % film.width, i as u32 / film.width);
                worst = (x, y, c, o as f32, r as f32, var[c].sqrt());
            }
            sum[c] += o;
            sum_ref[c] += r;
            sum_var[c] += var[c] as f64;
        }
    }
    let mean_ratio = std::array::from_fn(|c| sum[c] / sum_ref[c]);
    let ratio_tolerance = std::array::from_fn(|c| 0.01 + 3.0 * sum_var[c].sqrt() / sum_ref[c]);
    Comparison {
        min_p,
        alpha,
        worst,
        mean_ratio,
        ratio_tolerance,
    }
}

/// With `APPEL_REFERENCE_PNG=<folder>` set, writes `<name>.png`: ours, the reference, and their
/// difference magnified 4x (grey is zero), each pixel drawn 4x4, sRGB, so that a failing
/// comparison can be looked at.
pub fn save_side_by_side(name: &str, film: &Averaged, reference: &[[f32; 3]]) {
    let Ok(dir) = std::env::var("APPEL_REFERENCE_PNG") else {
        return;
    };
    let (w, h, s) = (film.width, film.height, 4u32);
    let srgb = |v: f32| {
        let v = v.clamp(0.0, 1.0);
        let e = if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (e * 255.0).round() as u8
    };
    let mut img = image::RgbImage::new(3 * w * s, h * s);
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let ours = film.rgb[i];
            let r = reference[i];
            let diff: [f32; 3] = std::array::from_fn(|c| 0.5 + 4.0 * (ours[c] - r[c]));
            for (k, p) in [ours, r, diff].into_iter().enumerate() {
                let px = image::Rgb(p.map(|v| {
                    if k == 2 {
                        (v.clamp(0.0, 1.0) * 255.0) as u8
                    } else {
                        srgb(v)
                    }
                }));
                for dy in 0..s {
                    for dx in 0..s {
                        img.put_pixel(k as u32 * w * s + x * s + dx, y * s + dy, px);
                    }
                }
            }
        }
    }
    let path = std::path::Path::new(&dir).join(format!("{name}.png"));
    img.save(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}
