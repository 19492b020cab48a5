//! A rectangle of the image to render alone: the pixels of a window are exactly the full render's,
//! so a render cut into windows (on other threads, processes or machines) reassembles bit for bit.

use crate::error::{Error, Result};

/// Pixels `x0..x1` by `y0..y1` of the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Window {
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// An error unless the window is a non-empty part of a `width` by `height` image.
    pub fn check(&self, width: u32, height: u32) -> Result<()> {
        if self.x0 < self.x1 && self.y0 < self.y1 && self.x1 <= width && self.y1 <= height {
            return Ok(());
        }
        Err(Error::Invalid(format!(
            "window {}..{} x {}..{} is not a non-empty part of the {width}x{height} image",
            self.x0, self.x1, self.y0, self.y1
        )))
    }

    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    pub fn pixel_count(&self) -> u64 {
        self.width() as u64 * self.height() as u64
    }
}
