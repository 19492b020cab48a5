//! Textures from their descriptions, each image file read once however many materials use it.

use crate::description::{TextureDesc, TextureFilter, TextureNode, TextureWrap};
use crate::error::Result;
use crate::io::bitmap_read::{read_bitmap, Bitmap};
use crate::shading::texture::{BitmapTexture, Checkerboard, Filter, Texture, Wrap};
use glam::{Mat3, Vec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub struct TextureCache<'a> {
    base_dir: &'a Path,
    images: HashMap<(PathBuf, bool), Arc<Bitmap>>,
}

impl<'a> TextureCache<'a> {
    pub fn new(base_dir: &'a Path) -> Self {
        Self {
            base_dir,
            images: HashMap::new(),
        }
    }

    pub fn texture(&mut self, d: &TextureDesc) -> Result<Texture> {
        Ok(match d {
            TextureDesc::Value(v) => Texture::Constant(Vec3::splat(*v)),
            TextureDesc::Rgb(c) => Texture::Constant(Vec3::from(*c)),
            TextureDesc::Texture(TextureNode::Bitmap {
                file,
                filter,
                wrap,
                raw,
                to_uv,
            }) => {
                let bitmap = self.image(file, *raw)?;
                let filter = match filter {
                    TextureFilter::Bilinear => Filter::Bilinear,
                    TextureFilter::Nearest => Filter::Nearest,
                };
                let wrap = match wrap {
                    TextureWrap::Repeat => Wrap::Repeat,
                    TextureWrap::Mirror => Wrap::Mirror,
                    TextureWrap::Clamp => Wrap::Clamp,
                };
                Texture::Bitmap(BitmapTexture::new(bitmap, filter, wrap, uv_matrix(to_uv)))
            }
            TextureDesc::Texture(TextureNode::MeshAttribute { name }) => {
                Texture::MeshAttribute(name.clone())
            }
            TextureDesc::Texture(TextureNode::Checkerboard {
                color0,
                color1,
                to_uv,
            }) => Texture::Checkerboard(Checkerboard {
                color0: Vec3::from(*color0),
                color1: Vec3::from(*color1),
                to_uv: uv_matrix(to_uv),
            }),
        })
    }

    pub fn path_of(&self, file: &str) -> PathBuf {
        self.base_dir.join(file)
    }

    /// An image file relative to the scene's folder, read once per decoding.
    pub fn image(&mut self, file: &str, raw: bool) -> Result<Arc<Bitmap>> {
        let path = self.base_dir.join(file);
        if let Some(b) = self.images.get(&(path.clone(), raw)) {
            return Ok(b.clone());
        }
        let b = Arc::new(read_bitmap(&path, raw)?);
        self.images.insert((path, raw), b.clone());
        Ok(b)
    }
}

/// A row-major 3x3 matrix acting on (u, v, 1).
fn uv_matrix(m: &Option<[[f32; 3]; 3]>) -> Mat3 {
    m.map_or(Mat3::IDENTITY, |m| Mat3::from_cols_array_2d(&m).transpose())
}

impl crate::shading::bsdf::TextureSource for TextureCache<'_> {
    fn texture(&mut self, d: &TextureDesc) -> Result<Texture> {
        TextureCache::texture(self, d)
    }
}
