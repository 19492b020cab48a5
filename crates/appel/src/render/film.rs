use super::film_block::{FilmBlock, PixelSums};
use crate::math::Vec3;

/// Primitive and shape ids of pixels whose camera ray hit nothing.
pub const MISS_ID: u32 = u32::MAX;

/// The rendered image and its arbitrary output variables, in row-major order from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    /// Linear RGB radiance.
    pub rgb: Vec<Vec3>,
    /// Distance along the unit camera ray to the first hit; +inf on a miss. This and the other
    /// AOVs are empty in a film rendered with [`super::RenderOptions::skip_aovs`].
    pub depth: Vec<f32>,
    /// Unit world-space shading normal at the first hit; zero on a miss.
    pub normal: Vec<Vec3>,
    pub shape_id: Vec<u32>,
    pub prim_id: Vec<u32>,
    /// The instance hit (`[[instance]]` placements in file order); [`MISS_ID`] for misses and for
    /// surfaces that are not instanced.
    pub instance_id: Vec<u32>,
    /// The variance of each pixel's estimate, per channel, from the spread of its samples (zero
    /// at one sample per pixel; empty in films not rendered, such as [`Film::new`]'s).
    pub variance: Vec<Vec3>,
    /// Further named image channels an integrator computed (the `aov` integrator's), each of
    /// one value per pixel in row order; empty for most integrators.
    pub channels: Vec<Channel>,
}

/// One named channel of a film beside its RGB (an EXR channel name such as `dd.y.T`).
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    pub name: String,
    pub values: Vec<f32>,
}

/// What the camera ray of one pixel saw first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelAov {
    pub depth: f32,
    pub normal: Vec3,
    pub shape_id: u32,
    pub prim_id: u32,
    pub instance_id: u32,
}

impl PixelAov {
    pub const MISS: PixelAov = PixelAov {
        depth: f32::INFINITY,
        normal: Vec3::ZERO,
        shape_id: MISS_ID,
        prim_id: MISS_ID,
        instance_id: MISS_ID,
    };
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            rgb: vec![Vec3::ZERO; n],
            depth: vec![f32::INFINITY; n],
            normal: vec![Vec3::ZERO; n],
            shape_id: vec![MISS_ID; n],
            prim_id: vec![MISS_ID; n],
            instance_id: vec![MISS_ID; n],
            variance: vec![],
            channels: vec![],
        }
    }

    /// The film of a block of weighted sums: each pixel the weighted mean of its samples, with
    /// the variance of that mean; `aovs` in the block's row order.
    pub(crate) fn from_sums(sums: &FilmBlock, aovs: &[PixelAov]) -> Self {
        Self::from_pixels(
            sums.width,
            sums.height,
            sums.sums.iter().map(PixelSums::mean).collect(),
            sums.sums.iter().map(PixelSums::variance_of_mean).collect(),
            aovs,
        )
    }

    /// The film of pixels whose means and variances are known; all in row order (`aovs` empty
    /// for a film without them).
    pub(crate) fn from_pixels(
        width: u32,
        height: u32,
        rgb: Vec<Vec3>,
        variance: Vec<Vec3>,
        aovs: &[PixelAov],
    ) -> Self {
        debug_assert!(aovs.is_empty() || rgb.len() == aovs.len());
        debug_assert_eq!(variance.len(), rgb.len());
        Self {
            width,
            height,
            rgb,
            depth: aovs.iter().map(|a| a.depth).collect(),
            normal: aovs.iter().map(|a| a.normal).collect(),
            shape_id: aovs.iter().map(|a| a.shape_id).collect(),
            prim_id: aovs.iter().map(|a| a.prim_id).collect(),
            instance_id: aovs.iter().map(|a| a.instance_id).collect(),
            variance,
            channels: vec![],
        }
    }

    /// The pixels of `window` of this full-image film (RGB and variance), with `aovs` (the
    /// window's, in row order, or empty).
    pub(crate) fn crop(&self, window: super::Window, aovs: &[PixelAov]) -> Film {
        let (mut rgb, mut variance) = (Vec::new(), Vec::new());
        for y in window.y0..window.y1 {
            let (a, b) = (self.index(window.x0, y), self.index(window.x1 - 1, y) + 1);
            rgb.extend_from_slice(&self.rgb[a..b]);
            variance.extend_from_slice(&self.variance[a..b]);
        }
        Film::from_pixels(window.width(), window.height(), rgb, variance, aovs)
    }

    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    pub fn set(&mut self, x: u32, y: u32, rgb: Vec3, aov: PixelAov) {
        let i = self.index(x, y);
        self.rgb[i] = rgb;
        self.depth[i] = aov.depth;
        self.normal[i] = aov.normal;
        self.shape_id[i] = aov.shape_id;
        self.prim_id[i] = aov.prim_id;
        self.instance_id[i] = aov.instance_id;
    }

    pub fn pixel(&self, x: u32, y: u32) -> Vec3 {
        self.rgb[self.index(x, y)]
    }
}
