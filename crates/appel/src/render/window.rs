//! A rectangle of the image to render alone: the pixels of a window are exactly the full render's,
//! so a render cut into windows (on other threads, processes or machines) reassembles bit for bit.

use crate::error::{Error, Result};

/// Pixels `x0..x1` by `y0..y1` of the full image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Window {
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// The window of `options`, or the whole `width` x `height` image; an empty window, or one
    /// reaching outside the image, is an error.
    pub fn resolve(window: Option<Window>, width: u32, height: u32) -> Result<Window> {
        let w = window.unwrap_or(Window {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        });
        if w.x0 >= w.x1 || w.y0 >= w.y1 || w.x1 > width || w.y1 > height {
            return Err(Error::Invalid(format!(
                "render window x {}..{}, y {}..{} is empty or outside the {width}x{height} image",
                w.x0, w.x1, w.y0, w.y1
            )));
        }
        Ok(w)
    }

    /// Whether the rectangle `x0..x1` by `y0..y1` (which may reach outside the image) overlaps it.
    pub fn overlaps(&self, x0: i32, y0: i32, x1: i32, y1: i32) -> bool {
        x0 < self.x1 as i32 && y0 < self.y1 as i32 && x1 > self.x0 as i32 && y1 > self.y0 as i32
    }
}
