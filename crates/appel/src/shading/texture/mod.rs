//! Textures as Mitsuba 3 evaluates them in its RGB variants: constants, bitmaps and checkerboards,
//! looked up by surface uv.

mod attribute;
mod bitmap;
mod checkerboard;

pub use attribute::{AttributePoint, MeshAttributes};
pub use bitmap::{BitmapTexture, Filter, Wrap};
pub use checkerboard::Checkerboard;

use glam::{Mat3, Vec2, Vec3};

#[derive(Clone, Debug)]
pub enum Texture {
    Constant(Vec3),
    Bitmap(BitmapTexture),
    Checkerboard(Checkerboard),
    /// A mesh's named per-vertex or per-face values (Mitsuba's `mesh_attribute`).
    MeshAttribute(String),
}

/// Where a texture is looked up: texture coordinates, and the mesh attributes of the point where
/// it has them.
#[derive(Clone, Copy, Debug)]
pub struct TexPoint<'a> {
    pub uv: Vec2,
    pub attributes: Option<AttributePoint<'a>>,
}

impl TexPoint<'_> {
    pub fn uv(uv: Vec2) -> Self {
        TexPoint {
            uv,
            attributes: None,
        }
    }
}

/// Luminance of linear sRGB (Rec. 709 primaries, the Y row of the sRGB-to-XYZ matrix), with
/// Mitsuba's coefficients.
pub fn luminance(c: Vec3) -> f32 {
    0.212_671 * c.x + 0.715_160 * c.y + 0.072_169 * c.z
}

/// A channel mean, which is how Mitsuba's constant `rgb` texture answers a float query.
fn channel_mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// Applies a 2D affine map stored as a 3x3 matrix (homogeneous uv).
pub(crate) fn transform_uv(m: &Mat3, uv: Vec2) -> Vec2 {
    m.transform_point2(uv)
}

impl Texture {
    /// The RGB value at `uv` (black for mesh attributes, which need [`Self::eval_at`]).
    pub fn eval(&self, uv: Vec2) -> Vec3 {
        match self {
            Texture::Constant(c) => *c,
            Texture::Bitmap(b) => b.eval(uv),
            Texture::Checkerboard(c) => c.eval(uv),
            Texture::MeshAttribute(_) => Vec3::ZERO,
        }
    }

    /// The RGB value at `p`: a mesh attribute's (one channel as grey), else as [`Self::eval`].
    /// A surface without the attribute is black (scene building checks that meshes have the
    /// attributes their materials read).
    pub fn eval_at(&self, p: &TexPoint) -> Vec3 {
        match self {
            Texture::MeshAttribute(name) => p
                .attributes
                .and_then(|a| a.value(name))
                .unwrap_or(Vec3::ZERO),
            _ => self.eval(p.uv),
        }
    }

    /// [`Self::eval_1`] at `p`: a one-channel attribute's value, a colour attribute's luminance.
    pub fn eval_1_at(&self, p: &TexPoint) -> f32 {
        match self {
            Texture::MeshAttribute(name) => {
                p.attributes.and_then(|a| a.value_1(name)).unwrap_or(0.0)
            }
            _ => self.eval_1(p.uv),
        }
    }

    /// One value at `uv`, as Mitsuba's `eval_1` reads a float parameter (roughness, opacity) from a
    /// texture: a one-channel bitmap's value, a colour bitmap's luminance, and, for constant
    /// colours (also the two of a checkerboard), their channel mean. A checkerboard answers
    /// with its squares swapped, as Mitsuba's does (see [`Checkerboard::eval_1`]).
    pub fn eval_1(&self, uv: Vec2) -> f32 {
        match self {
            Texture::Constant(c) => channel_mean(*c),
            Texture::Bitmap(b) => b.eval_1(uv),
            Texture::Checkerboard(c) => c.eval_1(uv),
            Texture::MeshAttribute(_) => 0.0,
        }
    }

    /// The gradient of [`Self::eval_1`] in (u, v): zero for the piecewise constant textures, as
    /// Mitsuba's constant and checkerboard textures answer.
    pub fn eval_1_grad(&self, uv: Vec2) -> Vec2 {
        match self {
            Texture::Bitmap(b) => b.eval_1_grad(uv),
            Texture::Constant(_) | Texture::Checkerboard(_) | Texture::MeshAttribute(_) => {
                Vec2::ZERO
            }
        }
    }

    /// The average colour over the unit uv square (per channel).
    pub fn mean(&self) -> Vec3 {
        match self {
            Texture::Constant(c) => *c,
            Texture::Bitmap(b) => b.mean(),
            Texture::Checkerboard(c) => 0.5 * (c.color0 + c.color1),
            // Unknown before a surface is hit; a mid grey for the plastics' lobe weights.
            Texture::MeshAttribute(_) => Vec3::splat(0.5),
        }
    }

    pub fn is_constant(&self) -> bool {
        matches!(self, Texture::Constant(_))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_queries_follow_mitsuba() {
        // Mitsuba 3.9 (scalar_rgb): an `rgb` texture of (0.2, 0.5, 0.9) gives eval_1 = 0.53333336
        // (the channel mean); a bitmap of that colour gives 0.46506631 (the luminance).
        let c = Vec3::new(0.2, 0.5, 0.9);
        assert!((Texture::Constant(c).eval_1(Vec2::ZERO) - 0.533_333_36).abs() < 1e-6);
        assert!((luminance(c) - 0.465_066_3).abs() < 1e-6);
        assert!(Texture::Constant(c).is_constant());
        assert_eq!(Texture::Constant(c).mean(), c);
    }
}
