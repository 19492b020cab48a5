//! From a film to the bytes of one WebSocket frame: the chosen AOV mapped to 8-bit colour, then
//! encoded as JPEG, PNG or raw RGBA. The binary message is a 16-byte header (`APF1`, width,
//! height, format code, little-endian u32s) followed by the encoded image.

use super::srgb8;
use appel::math::Vec3;
use appel::render::{Film, MISS_ID};
use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{ExtendedColorType, ImageEncoder};
use rayon::prelude::*;

/// The AOV as 8-bit RGB, row-major. `rgb` is the accumulated radiance (the film's own for one
/// pass); `cost` the per-pixel traversal work for the `cost` heat map.
pub fn to_rgb8(aov: &str, film: &Film, rgb: &[Vec3], cost: Option<&[u32]>) -> Vec<u8> {
    let n = film.width as usize * film.height as usize;
    let mut out = Vec::with_capacity(n * 3);
    // A frame rendered for colour, before the view switched to an AOV, has none: it shows its
    // colour until the next frame brings them.
    let without_aovs =
        film.depth.len() < n && matches!(aov, "depth" | "normal" | "shapeid" | "primid");
    let aov = if without_aovs { "color" } else { aov };
    match aov {
        "depth" => {
            // Near is bright: the visible depth range maps to 1..0.2, misses are black.
            let finite = film.depth.iter().copied().filter(|d| d.is_finite());
            let (lo, hi) = finite.fold((f32::INFINITY, 0.0f32), |(a, b), d| (a.min(d), b.max(d)));
            for &d in &film.depth {
                let v = if d.is_finite() {
                    1.0 - 0.8 * (d - lo) / (hi - lo).max(1e-12)
                } else {
                    0.0
                };
                let g = (v * 255.0) as u8;
                out.extend_from_slice(&[g, g, g]);
            }
        }
        "normal" => {
            for nrm in &film.normal {
                for c in [nrm.x, nrm.y, nrm.z] {
                    out.push(((c * 0.5 + 0.5).clamp(0.0, 1.0) * 255.0) as u8);
                }
            }
        }
        "shapeid" | "primid" => {
            let ids = if aov == "shapeid" {
                &film.shape_id
            } else {
                &film.prim_id
            };
            for &id in ids {
                out.extend_from_slice(&id_colour(id));
            }
        }
        "cost" => {
            let cost = cost.unwrap_or(&[]);
            let hi = cost.iter().copied().max().unwrap_or(1).max(1) as f32;
            for &c in cost {
                out.extend_from_slice(&heat(c as f32 / hi));
            }
            out.resize(n * 3, 0);
        }
        _ => {
            // Rows in parallel: the conversion is a few milliseconds of a frame's budget.
            let table = srgb8::table();
            out.resize(rgb.len() * 3, 0);
            const CHUNK: usize = 4096;
            out.par_chunks_mut(3 * CHUNK)
                .zip(rgb.par_chunks(CHUNK))
                .for_each(|(o, c)| {
                    for (o, c) in o.chunks_exact_mut(3).zip(c) {
                        o[0] = table.encode(c.x);
                        o[1] = table.encode(c.y);
                        o[2] = table.encode(c.z);
                    }
                });
        }
    }
    out
}

/// A distinct, stable colour per id (a multiplicative hash); misses are black.
fn id_colour(id: u32) -> [u8; 3] {
    if id == MISS_ID {
        return [0, 0, 0];
    }
    let h = id.wrapping_mul(0x9E37_79B1).rotate_left(7) ^ 0x5bd1_e995;
    [
        64 + (h & 0xBF) as u8,
        64 + ((h >> 8) & 0xBF) as u8,
        64 + ((h >> 16) & 0xBF) as u8,
    ]
}

/// Black, blue, red, yellow, white as t goes 0 to 1.
fn heat(t: f32) -> [u8; 3] {
    let t = t.clamp(0.0, 1.0);
    let r = (3.0 * t - 0.75).clamp(0.0, 1.0);
    let g = (3.0 * t - 1.75).clamp(0.0, 1.0);
    let b = if t < 0.33 {
        3.0 * t
    } else {
        (1.0 - 3.0 * (t - 0.33)).max(0.0) + (3.0 * t - 2.0).max(0.0)
    };
    [
        (r * 255.0) as u8,
        (g * 255.0) as u8,
        (b.min(1.0) * 255.0) as u8,
    ]
}

pub const FORMAT_JPEG: u32 = 0;
pub const FORMAT_PNG: u32 = 1;
pub const FORMAT_RAW: u32 = 2;

pub fn format_code(name: &str) -> u32 {
    match name {
        "png" => FORMAT_PNG,
        "raw" => FORMAT_RAW,
        _ => FORMAT_JPEG,
    }
}

pub fn format_name(code: u32) -> &'static str {
    match code {
        FORMAT_PNG => "png",
        FORMAT_RAW => "raw",
        _ => "jpeg",
    }
}

/// The format frames start in: on loopback, where bytes cost a copy, raw RGBA, which costs the
/// least to make and to draw (docs/performance.md, "The viewer in a browser"); over a network
/// JPEG, whose frames are about 30x smaller.
pub fn default_format(peer_is_loopback: bool) -> u32 {
    if peer_is_loopback {
        FORMAT_RAW
    } else {
        FORMAT_JPEG
    }
}

/// The binary message of one frame.
pub fn encode(rgb8: &[u8], width: u32, height: u32, format: u32) -> Vec<u8> {
    let mut out = Vec::with_capacity(16 + rgb8.len() / 4);
    out.extend_from_slice(b"APF1");
    for x in [width, height, format] {
        out.extend_from_slice(&x.to_le_bytes());
    }
    match format {
        FORMAT_PNG => {
            PngEncoder::new_with_quality(&mut out, CompressionType::Fast, FilterType::Sub)
                .write_image(rgb8, width, height, ExtendedColorType::Rgb8)
                .expect("encoding to memory")
        }
        FORMAT_RAW => {
            // RGBA, so the page copies it straight into an ImageData.
            for p in rgb8.chunks_exact(3) {
                out.extend_from_slice(&[p[0], p[1], p[2], 255]);
            }
        }
        // `jpeg-encoder`: its colour conversion and DCT run in SIMD, where the `image` crate's
        // encoder is scalar (docs/performance.md). Sides are at most
        // `messages::MAX_SIDE`, within its u16.
        _ => jpeg_encoder::Encoder::new(&mut out, 85)
            .encode(
                rgb8,
                width as u16,
                height as u16,
                jpeg_encoder::ColorType::Rgb,
            )
            .expect("encoding to memory"),
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_format_decodes_to_the_image_it_encoded() {
        let (w, h) = (24u32, 10u32);
        let rgb8: Vec<u8> = (0..w * h * 3).map(|i| (i * 7 % 256) as u8).collect();
        let png = encode(&rgb8, w, h, FORMAT_PNG);
        assert_eq!(&png[..4], b"APF1");
        assert_eq!(u32::from_le_bytes(png[4..8].try_into().unwrap()), w);
        let back = image::load_from_memory(&png[16..]).unwrap().to_rgb8();
        assert_eq!(back.into_raw(), rgb8);
        let raw = encode(&rgb8, w, h, FORMAT_RAW);
        assert_eq!(raw.len(), 16 + (w * h * 4) as usize);
        assert_eq!(&raw[16..20], &[rgb8[0], rgb8[1], rgb8[2], 255]);
        // A flat image survives JPEG within a few levels.
        let flat = vec![120u8; (w * h * 3) as usize];
        let jpeg = encode(&flat, w, h, FORMAT_JPEG);
        let back = image::load_from_memory(&jpeg[16..]).unwrap().to_rgb8();
        assert!(back.into_raw().iter().all(|&v| v.abs_diff(120) <= 3));
    }

    #[test]
    fn a_film_without_aovs_shows_its_colour_for_any_aov() {
        let mut film = Film::new(4, 3);
        film.rgb = vec![Vec3::new(1.0, 0.0, 1.0); 12];
        let colour = to_rgb8("color", &film, &film.rgb, None);
        assert_eq!(&colour[..3], &[255, 0, 255]);
        // With AOVs the depth view differs from the colour...
        assert_ne!(to_rgb8("depth", &film, &film.rgb, None), colour);
        // ...without them (a frame rendered for colour), every AOV view is the colour.
        film.depth.clear();
        film.normal.clear();
        film.shape_id.clear();
        film.prim_id.clear();
        film.instance_id.clear();
        for aov in ["depth", "normal", "shapeid", "primid"] {
            let out = to_rgb8(aov, &film, &film.rgb, None);
            assert_eq!(out.len(), 4 * 3 * 3);
            assert_eq!(out, colour, "{aov}");
        }
    }

    #[test]
    fn heat_map_runs_from_black_to_white() {
        assert_eq!(heat(0.0), [0, 0, 0]);
        assert_eq!(heat(1.0), [255, 255, 255]);
    }
}
