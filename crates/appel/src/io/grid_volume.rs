//! Mitsuba's binary grid volumes (`.vol`): the bytes `VOL`, version 3, then little-endian i32
//! encoding (1: f32), the x, y and z resolutions and the channel count, six f32 of a bounding box
//! (which Appel does not use), and the values with x varying fastest, then y, then z, channels
//! interleaved. Mitsuba's `sdfgrid` reads single-channel ones.

use crate::error::{Error, Location, Result};
use std::path::Path;

const HEADER: usize = 48;

/// A grid of values, `channels` per sample, x fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct GridVolume {
    pub resolution: [usize; 3],
    pub channels: usize,
    pub data: Vec<f32>,
}

pub fn read_grid_volume(path: &Path) -> Result<GridVolume> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_grid_volume(&bytes, path)
}

pub fn parse_grid_volume(bytes: &[u8], path: &Path) -> Result<GridVolume> {
    let at = |byte: u64, msg: String| Error::input(Location::byte(path, byte), msg);
    if bytes.len() < HEADER {
        return Err(at(
            0,
            format!(
                "not a Mitsuba grid volume: {} bytes, shorter than its {HEADER}-byte header",
                bytes.len()
            ),
        ));
    }
    if &bytes[0..3] != b"VOL" {
        return Err(at(
            0,
            "not a Mitsuba grid volume: it does not start with VOL".into(),
        ));
    }
    if bytes[3] != 3 {
        return Err(at(
            3,
            format!(
                "grid volume version {} is not supported (version 3 is)",
                bytes[3]
            ),
        ));
    }
    let int = |i: usize| i32::from_le_bytes(bytes[i..i + 4].try_into().expect("4 bytes"));
    let encoding = int(4);
    if encoding != 1 {
        return Err(at(
            4,
            format!("grid volume encoding {encoding} is not supported (1, 32-bit floats, is)"),
        ));
    }
    let mut dims = [0usize; 4];
    for (k, d) in dims.iter_mut().enumerate() {
        let v = int(8 + 4 * k);
        if v <= 0 {
            return Err(at(
                8 + 4 * k as u64,
                format!("the resolution and channel count must be positive, got {v}"),
            ));
        }
        *d = v as usize;
    }
    let [x, y, z, channels] = dims;
    let count = (x as u64) * (y as u64) * (z as u64) * (channels as u64);
    let expected = HEADER as u64 + 4 * count;
    if bytes.len() as u64 != expected {
        return Err(at(
            HEADER as u64,
            format!(
                "a {x} x {y} x {z} grid of {channels} channel(s) needs {expected} bytes, the file has {}",
                bytes.len()
            ),
        ));
    }
    let data: Vec<f32> = bytes[HEADER..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().expect("4 bytes")))
        .collect();
    if let Some(i) = data.iter().position(|v| !v.is_finite()) {
        return Err(at(
            HEADER as u64 + 4 * i as u64,
            format!("value {i} is not finite"),
        ));
    }
    Ok(GridVolume {
        resolution: [x, y, z],
        channels,
        data,
    })
}

#[cfg(test)]
pub(crate) fn encode(resolution: [usize; 3], data: &[f32]) -> Vec<u8> {
    let mut out = b"VOL\x03".to_vec();
    out.extend(1i32.to_le_bytes());
    for r in resolution {
        out.extend((r as i32).to_le_bytes());
    }
    out.extend(1i32.to_le_bytes());
    for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0] {
        out.extend(v.to_le_bytes());
    }
    for v in data {
        out.extend(v.to_le_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_what_it_encodes_and_rejects_bad_files() {
        let data: Vec<f32> = (0..24).map(|i| i as f32 - 5.0).collect();
        let bytes = encode([2, 3, 4], &data);
        let p = Path::new("g.vol");
        let g = parse_grid_volume(&bytes, p).unwrap();
        assert_eq!(g.resolution, [2, 3, 4]);
        assert_eq!(g.channels, 1);
        assert_eq!(g.data, data);
        let err = |b: &[u8]| parse_grid_volume(b, p).unwrap_err().to_string();
        assert!(err(&bytes[..20]).contains("shorter"));
        assert!(err(&bytes[..bytes.len() - 4]).contains("needs"));
        let mut bad = bytes.clone();
        bad[0] = b'X';
        assert!(err(&bad).contains("VOL"));
        let mut bad = bytes.clone();
        bad[4] = 2;
        assert!(err(&bad).contains("encoding 2"));
        let mut bad = bytes;
        bad[8..12].copy_from_slice(&(-1i32).to_le_bytes());
        assert!(err(&bad).contains("positive"));
    }
}
