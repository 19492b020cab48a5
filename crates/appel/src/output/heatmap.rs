//! False-colour pictures of per-pixel values (the cost of each camera ray), as a PNG with a
//! legend below the picture: the colour bar from 0 to the largest value, its scale written at
//! both ends and the middle, and what is shown. The text uses a built-in 3x5 pixel font, so the
//! picture needs no font files.

use super::write_atomically;
use crate::error::{Error, Result};
use std::path::Path;

/// Legend height in pixels below the picture.
const LEGEND: u32 = 36;
/// Font pixels per glyph pixel.
const SCALE: u32 = 2;

/// Writes `values` (row by row, `width` by `height`) as a heatmap PNG with a legend naming
/// `what`. The scale runs linearly from 0 to the largest value.
pub fn write_heatmap(
    path: &Path,
    width: u32,
    height: u32,
    values: &[f32],
    what: &str,
) -> Result<()> {
    assert_eq!(values.len(), width as usize * height as usize);
    let max = values.iter().copied().fold(0.0f32, f32::max);
    let h = height + LEGEND;
    let mut img = vec![255u8; width as usize * h as usize * 3];
    let mut put = |x: u32, y: u32, c: [u8; 3]| {
        if x < width && y < h {
            let i = 3 * (y as usize * width as usize + x as usize);
            img[i..i + 3].copy_from_slice(&c);
        }
    };
    for y in 0..height {
        for x in 0..width {
            let v = values[(y * width + x) as usize];
            put(x, y, colour(if max > 0.0 { v / max } else { 0.0 }));
        }
    }
    // The colour bar, with a margin either side for the labels.
    let margin = 8;
    let bar = width.saturating_sub(2 * margin).max(1);
    for x in 0..bar {
        let c = colour(x as f32 / (bar - 1).max(1) as f32);
        for y in height + 4..height + 14 {
            put(margin + x, y, c);
        }
    }
    let text_y = height + 18;
    let mut text = |s: &str, x: u32| {
        for (k, ch) in s.chars().enumerate() {
            let g = glyph(ch);
            for (row, bits) in g.iter().enumerate() {
                for col in 0..3 {
                    if bits >> (2 - col) & 1 == 1 {
                        for dy in 0..SCALE {
                            for dx in 0..SCALE {
                                put(
                                    x + (4 * k as u32 + col) * SCALE + dx,
                                    text_y + row as u32 * SCALE + dy,
                                    [0, 0, 0],
                                );
                            }
                        }
                    }
                }
            }
        }
    };
    let label_width = |s: &str| 4 * SCALE * s.chars().count() as u32;
    let number = |v: f32| {
        if max >= 10.0 {
            format!("{:.0}", v)
        } else {
            format!("{:.1}", v)
        }
    };
    text("0", margin);
    let mid = number(max / 2.0);
    text(
        &mid,
        (margin + bar / 2).saturating_sub(label_width(&mid) / 2),
    );
    let top = number(max);
    text(&top, (margin + bar).saturating_sub(label_width(&top)));
    // What is shown, between the first label and the middle one.
    text(what, margin + bar / 4 - label_width(what).min(bar / 4) / 2);
    write_atomically(path, |out| {
        image::write_buffer_with_format(
            out,
            &img,
            width,
            h,
            image::ExtendedColorType::Rgb8,
            image::ImageFormat::Png,
        )
        .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))
    })
}

/// A dark-to-bright ramp through purple, red and orange to pale yellow (control points chosen by
/// eye to resemble the "inferno" map of matplotlib): brightness grows with the value, so it
/// reads in grey too.
pub fn colour(f: f32) -> [u8; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [0.0, 0.0, 4.0],
        [87.0, 16.0, 110.0],
        [188.0, 55.0, 84.0],
        [249.0, 142.0, 9.0],
        [252.0, 255.0, 164.0],
    ];
    let f = if f.is_nan() { 0.0 } else { f.clamp(0.0, 1.0) } * 4.0;
    let k = (f as usize).min(3);
    let t = f - k as f32;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    [0, 1, 2].map(|i| (a[i] + (b[i] - a[i]) * t).round() as u8)
}

/// Rows of a 3x5 glyph, the high bit the left column; unknown characters are blank.
fn glyph(c: char) -> [u8; 5] {
    match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '.' => [0, 0, 0, 0, 2],
        'a' => [0, 3, 5, 5, 3],
        'c' => [0, 3, 4, 4, 3],
        'd' => [1, 3, 5, 5, 3],
        'e' => [3, 5, 7, 4, 3],
        'm' => [0, 6, 7, 5, 5],
        'n' => [0, 6, 5, 5, 5],
        'o' => [0, 2, 5, 5, 2],
        'p' => [0, 6, 5, 6, 4],
        'r' => [0, 5, 6, 4, 4],
        's' => [0, 3, 6, 3, 6],
        't' => [2, 7, 2, 2, 3],
        'y' => [0, 5, 5, 3, 6],
        _ => [0; 5],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ramp_grows_brighter_and_ends_at_its_stops() {
        assert_eq!(colour(0.0), [0, 0, 4]);
        assert_eq!(colour(1.0), [252, 255, 164]);
        let luma = |c: [u8; 3]| 0.2126 * c[0] as f32 + 0.7152 * c[1] as f32 + 0.0722 * c[2] as f32;
        for k in 0..100 {
            assert!(luma(colour(k as f32 / 100.0)) < luma(colour((k + 1) as f32 / 100.0)));
        }
    }

    #[test]
    fn a_heatmap_is_the_picture_over_its_legend() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("h.png");
        let values: Vec<f32> = (0..64 * 16).map(|i| (i % 64) as f32).collect();
        write_heatmap(&path, 64, 16, &values, "nodes").unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (64, 16 + LEGEND));
        assert_eq!(img.get_pixel(0, 0).0, colour(0.0));
        assert_eq!(img.get_pixel(63, 5).0, colour(1.0));
        // The legend holds black text.
        let text = (16..16 + LEGEND)
            .flat_map(|y| (0..64).map(move |x| (x, y)))
            .filter(|&(x, y)| img.get_pixel(x, y).0 == [0, 0, 0])
            .count();
        assert!(text > 20, "{text}");
    }
}
