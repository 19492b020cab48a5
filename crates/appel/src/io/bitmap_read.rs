//! Reading images as linear float pixels for textures and environment maps: PNG and JPEG (8 and
//! 16 bit, sRGB-decoded unless raw), OpenEXR and Radiance HDR, in grey, grey+alpha, RGB or RGBA.

use crate::error::{Error, Location, Result};
use image::{DynamicImage, ImageFormat};
use std::path::Path;

/// Pixels as f32, row-major with the top row first, `channels` interleaved values per pixel (1 grey,
/// 2 grey+alpha, 3 RGB, 4 RGBA). Colour values are linear; alpha is never gamma-decoded.
#[derive(Clone, Debug, PartialEq)]
pub struct Bitmap {
    pub width: u32,
    pub height: u32,
    pub channels: u8,
    pub data: Vec<f32>,
}

impl Bitmap {
    /// The `channels` values of pixel (x, y), y counted from the top.
    #[inline]
    pub fn pixel(&self, x: u32, y: u32) -> &[f32] {
        let c = self.channels as usize;
        let i = (y as usize * self.width as usize + x as usize) * c;
        &self.data[i..i + c]
    }

    /// Whether the last channel is alpha (grey+alpha or RGBA).
    pub fn has_alpha(&self) -> bool {
        self.channels == 2 || self.channels == 4
    }
}

/// The sRGB transfer function inverted (IEC 61966-2-1): encoded value in [0, 1] to linear.
pub fn srgb_to_linear(v: f32) -> f32 {
    let v = v as f64;
    let l = if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    };
    l as f32
}

/// Reads `path`, recognised by its first bytes. 8- and 16-bit colour values are sRGB-decoded to
/// linear unless `raw` (as Mitsuba's `bitmap` texture does unless its `raw` flag is set); float
/// formats are linear already and `raw` does not change them.
pub fn read_bitmap(path: &Path, raw: bool) -> Result<Bitmap> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    decode_bitmap(&bytes, path, raw)
}

/// [`read_bitmap`] of an image already in memory (embedded in a glTF file, or in a zip archive);
/// `path` names it in errors.
pub fn decode_bitmap(bytes: &[u8], path: &Path, raw: bool) -> Result<Bitmap> {
    let bad = |message: String| Error::input(Location::file(path), message);
    if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
        return read_exr(bytes).map_err(|m| bad(format!("not a readable OpenEXR image: {m}")));
    }
    if super::pfm::is_pfm(bytes) {
        return super::pfm::decode_pfm(bytes)
            .map_err(|m| bad(format!("not a readable PFM image: {m}")));
    }
    let format = if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        ImageFormat::Png
    } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
        ImageFormat::Jpeg
    } else if bytes.starts_with(b"#?") {
        ImageFormat::Hdr
    } else if bytes.starts_with(b"BM") {
        ImageFormat::Bmp
    } else {
        return Err(bad(
            "not an image Appel reads (expected PNG, JPEG, BMP, OpenEXR, Radiance HDR or PFM)"
                .into(),
        ));
    };
    let image = image::load_from_memory_with_format(bytes, format)
        .map_err(|e| bad(format!("not a readable {format:?} image: {e}")))?;
    Ok(from_dynamic(image, !raw))
}

/// Converts decoded pixels to linear floats; `decode_srgb` applies to 8- and 16-bit colour channels.
fn from_dynamic(image: DynamicImage, decode_srgb: bool) -> Bitmap {
    let (width, height) = (image.width(), image.height());
    let (channels, data, integer): (u8, Vec<f32>, bool) = match image {
        DynamicImage::ImageLuma8(b) => (1, unorm8(b.as_raw()), true),
        DynamicImage::ImageLumaA8(b) => (2, unorm8(b.as_raw()), true),
        DynamicImage::ImageRgb8(b) => (3, unorm8(b.as_raw()), true),
        DynamicImage::ImageRgba8(b) => (4, unorm8(b.as_raw()), true),
        DynamicImage::ImageLuma16(b) => (1, unorm16(b.as_raw()), true),
        DynamicImage::ImageLumaA16(b) => (2, unorm16(b.as_raw()), true),
        DynamicImage::ImageRgb16(b) => (3, unorm16(b.as_raw()), true),
        DynamicImage::ImageRgba16(b) => (4, unorm16(b.as_raw()), true),
        DynamicImage::ImageRgb32F(b) => (3, b.into_raw(), false),
        DynamicImage::ImageRgba32F(b) => (4, b.into_raw(), false),
        other => (4, other.into_rgba32f().into_raw(), false),
    };
    let mut bitmap = Bitmap {
        width,
        height,
        channels,
        data,
    };
    if integer && decode_srgb {
        let c = channels as usize;
        let colour = if bitmap.has_alpha() { c - 1 } else { c };
        // The 8-bit case through a table: 256 values instead of one powf per sample.
        let table: Vec<f32> = (0..256).map(|i| srgb_to_linear(i as f32 / 255.0)).collect();
        for px in bitmap.data.chunks_mut(c) {
            for v in &mut px[..colour] {
                let code = *v * 255.0;
                *v = if code == code.round() {
                    table[code as usize]
                } else {
                    srgb_to_linear(*v)
                };
            }
        }
    }
    bitmap
}

fn unorm8(v: &[u8]) -> Vec<f32> {
    v.iter().map(|&x| x as f32 / 255.0).collect()
}

fn unorm16(v: &[u16]) -> Vec<f32> {
    v.iter().map(|&x| x as f32 / 65535.0).collect()
}

/// Samples in one EXR layer above which the file is refused: 2^28 (a 16k x 16k RGBA image), 1 GiB
/// as f32.
const MAX_EXR_SAMPLES: u128 = 1 << 28;

/// The first layer of an EXR file: R, G, B (and A) or Y (and A), or a lone channel of any name
/// read as grey. Channel names may carry a layer prefix (`diffuse.R`).
fn read_exr(bytes: &[u8]) -> std::result::Result<Bitmap, String> {
    use exr::prelude::*;
    // The exr crate allocates a layer's samples as its header declares them, and aborts the
    // process when that fails (found by fuzzing: a header claiming petabytes). Check first.
    let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(bytes), false)
        .map_err(|e| e.to_string())?;
    for header in &meta.headers {
        let samples = header.layer_size.width() as u128
            * header.layer_size.height() as u128
            * header.channels.list.len() as u128;
        if samples > MAX_EXR_SAMPLES {
            return Err(format!(
                "a layer of {} x {} pixels with {} channels is more than Appel reads",
                header.layer_size.width(),
                header.layer_size.height(),
                header.channels.list.len()
            ));
        }
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    let layer = image.layer_data;
    let (width, height) = (layer.size.width(), layer.size.height());
    let channels = &layer.channel_data.list;
    let find = |name: &str| {
        channels.iter().find(|c| {
            let full = c.name.to_string();
            full.rsplit('.')
                .next()
                .unwrap_or("")
                .eq_ignore_ascii_case(name)
        })
    };
    let picked: Vec<&AnyChannel<FlatSamples>> = match (find("R"), find("G"), find("B"), find("Y")) {
        (Some(r), Some(g), Some(b), _) => [Some(r), Some(g), Some(b), find("A")]
            .into_iter()
            .flatten()
            .collect(),
        (_, _, _, Some(y)) => [Some(y), find("A")].into_iter().flatten().collect(),
        _ if channels.len() == 1 => vec![&channels[0]],
        _ => {
            let names: Vec<String> = channels.iter().map(|c| c.name.to_string()).collect();
            return Err(format!(
                "expected channels R, G, B or Y (and A), found {}",
                names.join(", ")
            ));
        }
    };
    let n = width * height;
    let c = picked.len();
    let mut data = vec![0.0f32; n * c];
    for (k, ch) in picked.iter().enumerate() {
        if ch.sample_data.len() != n {
            return Err(format!(
                "channel {} has the wrong number of samples",
                ch.name
            ));
        }
        for (i, v) in ch.sample_data.values_as_f32().enumerate() {
            data[i * c + k] = v;
        }
    }
    let dim = |v: usize| u32::try_from(v).map_err(|_| "image too large".to_string());
    Ok(Bitmap {
        width: dim(width)?,
        height: dim(height)?,
        channels: c as u8,
        data,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &[f32], b: &[f32], tol: f32) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
    }

    #[test]
    fn srgb_decode_by_hand_and_against_mitsuba() {
        // The linear segment below 0.04045 and the 2.4 power above it (IEC 61966-2-1).
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(0.04) - 0.04 / 12.92).abs() < 1e-9);
        assert!((srgb_to_linear(0.5) - 0.214_041_14).abs() < 1e-7);
        assert_eq!(srgb_to_linear(1.0), 1.0);
        let dir = tempfile::tempdir().unwrap();
        // Mitsuba 3.9 reads these as: grey 2x2 (0, 128 / 255, 64) -> 0, 0.215860531, 1,
        // 0.0512694; RGBA (200, 100, 50, 128) -> (0.57758075, 0.12743777, 0.031895995) with alpha
        // left linear and never premultiplied; 16-bit (1000, 30000, 65535) -> (0.0011810388,
        // 0.177014828, 1).
        let grey = dir.path().join("grey.png");
        image::save_buffer(&grey, &[0, 128, 255, 64], 2, 2, image::ColorType::L8).unwrap();
        let b = read_bitmap(&grey, false).unwrap();
        assert_eq!((b.width, b.height, b.channels), (2, 2, 1));
        assert!(
            close(&b.data, &[0.0, 0.215_860_53, 1.0, 0.051_269_4], 1e-6),
            "{:?}",
            b.data
        );
        let rgba = dir.path().join("rgba.png");
        image::save_buffer(
            &rgba,
            &[200, 100, 50, 128, 10, 20, 30, 255],
            2,
            1,
            image::ColorType::Rgba8,
        )
        .unwrap();
        let b = read_bitmap(&rgba, false).unwrap();
        assert_eq!(b.channels, 4);
        assert!(close(
            b.pixel(0, 0),
            &[0.577_580_75, 0.127_437_77, 0.031_895_995, 128.0 / 255.0],
            1e-6
        ));
        let raw = read_bitmap(&rgba, true).unwrap();
        assert!(close(
            raw.pixel(1, 0),
            &[10.0 / 255.0, 20.0 / 255.0, 30.0 / 255.0, 1.0],
            1e-7
        ));
        let rgb16 = dir.path().join("rgb16.png");
        image::ImageBuffer::<image::Rgb<u16>, _>::from_raw(1, 1, vec![1000u16, 30000, 65535])
            .unwrap()
            .save(&rgb16)
            .unwrap();
        let b = read_bitmap(&rgb16, false).unwrap();
        assert!(
            close(&b.data, &[0.001_181_038_8, 0.177_014_83, 1.0], 1e-6),
            "{:?}",
            b.data
        );
        let la = dir.path().join("la.png");
        image::save_buffer(&la, &[255, 51], 1, 1, image::ColorType::La8).unwrap();
        assert!(close(
            &read_bitmap(&la, false).unwrap().data,
            &[1.0, 0.2],
            1e-7
        ));
    }

    #[test]
    fn float_and_lossy_formats() {
        let dir = tempfile::tempdir().unwrap();
        // EXR: linear as stored, RGBA and a lone Y channel.
        let exr_rgba = dir.path().join("rgba.exr");
        exr::prelude::write_rgba_file(&exr_rgba, 3, 2, |x, y| {
            (x as f32, y as f32 * 2.0, 0.25, 0.5)
        })
        .unwrap();
        let b = read_bitmap(&exr_rgba, false).unwrap();
        assert_eq!((b.width, b.height, b.channels), (3, 2, 4));
        assert!(close(b.pixel(2, 1), &[2.0, 2.0, 0.25, 0.5], 0.0));
        let exr_y = dir.path().join("y.exr");
        {
            use exr::prelude::*;
            let samples = FlatSamples::F32(vec![0.5, 1.5, 2.5, 3.5]);
            let channels =
                AnyChannels::sort(SmallVec::from_vec(vec![AnyChannel::new("Y", samples)]));
            let layer = Layer::new(
                (2, 2),
                LayerAttributes::default(),
                Encoding::default(),
                channels,
            );
            Image::from_layer(layer).write().to_file(&exr_y).unwrap();
        }
        let b = read_bitmap(&exr_y, false).unwrap();
        assert_eq!((b.channels, b.data.clone()), (1, vec![0.5, 1.5, 2.5, 3.5]));
        // Radiance HDR: RGBE keeps 8 bits of mantissa.
        let hdr = dir.path().join("sky.hdr");
        let px = [
            image::Rgb([0.5f32, 2.0, 10.0]),
            image::Rgb([0.0, 0.125, 1.0]),
        ];
        let file = std::fs::File::create(&hdr).unwrap();
        image::codecs::hdr::HdrEncoder::new(file)
            .encode(&px, 2, 1)
            .unwrap();
        let b = read_bitmap(&hdr, false).unwrap();
        assert_eq!((b.width, b.height, b.channels), (2, 1, 3));
        assert!(
            close(&b.data, &[0.5, 2.0, 10.0, 0.0, 0.125, 1.0], 0.05),
            "{:?}",
            b.data
        );
        // JPEG: a flat grey 128 decodes near sRGB(128 / 255).
        let jpg = dir.path().join("grey.jpg");
        image::save_buffer(&jpg, &[128u8; 64], 8, 8, image::ColorType::L8).unwrap();
        let b = read_bitmap(&jpg, false).unwrap();
        assert_eq!(b.channels, 1);
        assert!(
            b.data.iter().all(|&v| (v - 0.215_86).abs() < 0.01),
            "{:?}",
            &b.data[..4]
        );
    }

    #[test]
    fn malformed_files_are_errors_naming_them() {
        let dir = tempfile::tempdir().unwrap();
        let png = dir.path().join("cut.png");
        image::save_buffer(&png, &[7u8; 300], 10, 10, image::ColorType::Rgb8).unwrap();
        let bytes = std::fs::read(&png).unwrap();
        std::fs::write(&png, &bytes[..bytes.len() / 2]).unwrap();
        let exr = dir.path().join("garbage.exr");
        let mut junk = vec![0x76, 0x2f, 0x31, 0x01];
        junk.extend((0..200u32).map(|i| (i * 37 % 251) as u8));
        std::fs::write(&exr, &junk).unwrap();
        let txt = dir.path().join("notes.png");
        std::fs::write(&txt, b"not an image at all").unwrap();
        for (path, name) in [
            (&png, "cut.png"),
            (&exr, "garbage.exr"),
            (&txt, "notes.png"),
        ] {
            let err = read_bitmap(path, false).unwrap_err();
            assert!(matches!(err, Error::Input { .. }), "{err}");
            assert!(err.to_string().contains(name), "{err}");
        }
        let missing = dir.path().join("missing.exr");
        let err = read_bitmap(&missing, false).unwrap_err();
        assert!(matches!(err, Error::Io { .. }) && err.to_string().contains("missing.exr"));
    }
}
