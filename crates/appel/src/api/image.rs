//! Images a front end holds as arrays, written as the command line writes them.

use crate::error::{Error, Result};
use crate::math::Vec3;
use crate::output::image::{to_srgb8, write_image, Aovs};
use crate::render::{Film, MISS_ID};
use std::path::Path;

/// An image's arrays, row by row from the top-left pixel: `rgb` and `normal` three floats a
/// pixel, the others one value a pixel. Absent AOVs are not written.
#[derive(Default)]
pub struct ImageArrays<'a> {
    pub width: u32,
    pub height: u32,
    pub rgb: &'a [f32],
    pub depth: Option<&'a [f32]>,
    pub normal: Option<&'a [f32]>,
    pub shape_id: Option<&'a [u32]>,
    pub prim_id: Option<&'a [u32]>,
    pub instance_id: Option<&'a [u32]>,
    pub variance: Option<&'a [f32]>,
}

fn vec3s(v: &[f32]) -> Vec<Vec3> {
    v.chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect()
}

impl ImageArrays<'_> {
    fn film(&self) -> Result<Film> {
        let n = self.width as usize * self.height as usize;
        let check = |name: &str, len: usize, per: usize| {
            if len != n * per {
                return Err(Error::Invalid(format!(
                    "{name}: {len} values for a {}x{} image",
                    self.width, self.height
                )));
            }
            Ok(())
        };
        check("rgb", self.rgb.len(), 3)?;
        let mut film = Film::new(self.width, self.height);
        film.rgb = vec3s(self.rgb);
        if let Some(d) = self.depth {
            check("depth", d.len(), 1)?;
            film.depth = d.to_vec();
        }
        if let Some(d) = self.normal {
            check("normal", d.len(), 3)?;
            film.normal = vec3s(d);
        }
        for (name, src, dst) in [
            ("shapeid", self.shape_id, &mut film.shape_id),
            ("primid", self.prim_id, &mut film.prim_id),
            ("instanceid", self.instance_id, &mut film.instance_id),
        ] {
            if let Some(ids) = src {
                check(name, ids.len(), 1)?;
                *dst = ids.to_vec();
            } else {
                *dst = vec![MISS_ID; n];
            }
        }
        if let Some(v) = self.variance {
            check("variance", v.len(), 3)?;
            film.variance = vec3s(v);
        }
        Ok(film)
    }

    /// Writes PNG (8-bit sRGB) or EXR (float RGB and the AOVs present) by the extension, atomically.
    pub fn save(&self, path: &Path) -> Result<()> {
        let aovs = Aovs {
            depth: self.depth.is_some(),
            normal: self.normal.is_some(),
            shape_id: self.shape_id.is_some(),
            prim_id: self.prim_id.is_some(),
            instance_id: self.instance_id.is_some(),
            variance: self.variance.is_some(),
        };
        let png = crate::output::image::ImageFormat::from_path(path)?
            == crate::output::image::ImageFormat::Png;
        // A PNG holds the colours only.
        write_image(
            path,
            &self.film()?,
            if png { Aovs::default() } else { aovs },
        )
    }

    /// The 8-bit sRGB PNG file's bytes.
    pub fn png_bytes(&self) -> Result<Vec<u8>> {
        let film = self.film()?;
        let mut out = std::io::Cursor::new(Vec::new());
        image::write_buffer_with_format(
            &mut out,
            &to_srgb8(&film),
            self.width,
            self.height,
            image::ExtendedColorType::Rgb8,
            image::ImageFormat::Png,
        )
        .map_err(|e| Error::Invalid(format!("PNG encoding: {e}")))?;
        Ok(out.into_inner())
    }
}
