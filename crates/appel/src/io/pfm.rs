//! Portable float maps (`.pfm`), the format pbrt-v4's scenes keep many environment images in:
//! a text header (`PF` for RGB or `Pf` for grey, the width and height, then a scale whose sign
//! gives the byte order: negative for little-endian), then 32-bit floats row by row from the
//! bottom row up. The `image` crate reads PNM but not PFM, hence this reader.

use super::bitmap_read::Bitmap;

/// Whether `bytes` start as a PFM file.
pub fn is_pfm(bytes: &[u8]) -> bool {
    bytes.len() > 2
        && (bytes.starts_with(b"PF") || bytes.starts_with(b"Pf"))
        && bytes[2].is_ascii_whitespace()
}

/// Decodes a PFM file to a bitmap with its top row first; the header's scale is a byte-order
/// mark only (pbrt-v4 and most writers ignore its magnitude, as this does).
pub fn decode_pfm(bytes: &[u8]) -> Result<Bitmap, String> {
    let channels: u8 = if bytes.starts_with(b"PF") { 3 } else { 1 };
    // Three header tokens after the magic, each ended by one whitespace byte.
    let mut at = 2;
    let mut tokens = Vec::with_capacity(3);
    for _ in 0..3 {
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        let token =
            std::str::from_utf8(&bytes[start..at]).map_err(|_| "a header that is not text")?;
        tokens.push(token.to_string());
    }
    // The single whitespace byte that ends the header.
    at += 1;
    let dimension = |t: &str, what: &str| -> Result<u32, String> {
        t.parse::<u32>()
            .ok()
            .filter(|&v| v > 0)
            .ok_or_else(|| format!("the header's {what} \"{t}\" is not a positive integer"))
    };
    let width = dimension(&tokens[0], "width")?;
    let height = dimension(&tokens[1], "height")?;
    let scale: f32 = tokens[2]
        .parse()
        .ok()
        .filter(|s: &f32| s.is_finite() && *s != 0.0)
        .ok_or_else(|| {
            format!(
                "the header's scale \"{}\" is not a non-zero number",
                tokens[2]
            )
        })?;
    let count = width as u64 * height as u64 * channels as u64;
    let needed = count * 4;
    let available = bytes.len().saturating_sub(at) as u64;
    if available < needed {
        return Err(format!(
            "{width}x{height} pixels need {needed} bytes of data, the file has {available}"
        ));
    }
    let little = scale < 0.0;
    let row = width as usize * channels as usize;
    let mut data = vec![0.0f32; count as usize];
    for (i, chunk) in bytes[at..at + needed as usize].chunks_exact(4).enumerate() {
        let b = [chunk[0], chunk[1], chunk[2], chunk[3]];
        let v = if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        };
        // File rows run bottom to top.
        let (y, x) = (i / row, i % row);
        data[(height as usize - 1 - y) * row + x] = v;
    }
    Ok(Bitmap {
        width,
        height,
        channels,
        data,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(magic: &str, w: u32, h: u32, scale: &str, values: &[f32], little: bool) -> Vec<u8> {
        let mut b = format!("{magic}\n{w} {h}\n{scale}\n").into_bytes();
        for v in values {
            b.extend(if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            });
        }
        b
    }

    #[test]
    fn rows_are_flipped_and_both_byte_orders_read() {
        // 2x2 RGB, bottom row first in the file.
        let values: Vec<f32> = (0..12).map(|i| i as f32 * 0.5).collect();
        for (scale, little) in [("-1.0", true), ("1.0", false)] {
            let b = decode_pfm(&file("PF", 2, 2, scale, &values, little)).unwrap();
            assert_eq!((b.width, b.height, b.channels), (2, 2, 3));
            // The top row is the file's second.
            assert_eq!(b.pixel(0, 0), &values[6..9]);
            assert_eq!(b.pixel(1, 1), &values[3..6]);
        }
        let grey = decode_pfm(&file("Pf", 3, 1, "-1", &[1.0, 2.0, 3.0], true)).unwrap();
        assert_eq!((grey.channels, grey.data.clone()), (1, vec![1.0, 2.0, 3.0]));
        assert!(is_pfm(b"PF\n1 1") && is_pfm(b"Pf 1") && !is_pfm(b"PFX") && !is_pfm(b"P6\n"));
    }

    #[test]
    fn bad_headers_and_short_data_are_errors() {
        let short = decode_pfm(&file("PF", 2, 2, "-1", &[1.0; 11], true)).unwrap_err();
        assert!(
            short.contains("48 bytes") && short.contains("44"),
            "{short}"
        );
        let width = decode_pfm(b"PF\nx 2\n-1\n").unwrap_err();
        assert!(width.contains("width \"x\""), "{width}");
        let scale = decode_pfm(b"PF\n1 1\n0\n\0\0\0\0\0\0\0\0\0\0\0\0").unwrap_err();
        assert!(scale.contains("scale"), "{scale}");
        assert!(decode_pfm(b"PF\n").is_err());
    }
}
