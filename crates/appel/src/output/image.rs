//! Writing images: 8-bit sRGB PNG, and linear float32 OpenEXR with optional AOV channels.

use super::write_atomically;
use crate::error::{Error, Result};
use crate::render::cost::CostImage;
use crate::render::Film;
use exr::prelude::*;
use std::path::Path;

/// Which arbitrary output variables go into an EXR beside R, G, B.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Aovs {
    pub depth: bool,
    pub normal: bool,
    pub shape_id: bool,
    pub prim_id: bool,
    pub instance_id: bool,
    /// The variance of each pixel's estimate (`variance.R/G/B`), from the spread of its samples.
    pub variance: bool,
    /// The nodes visited and primitive tests of each pixel's camera ray (`cost.nodes`,
    /// `cost.tests`; see `render::cost`).
    pub cost: bool,
}

impl Aovs {
    pub const NAMES: &'static [&'static str] = &[
        "depth",
        "normal",
        "shapeid",
        "primid",
        "instanceid",
        "variance",
        "cost",
    ];

    /// Parses a comma-separated list such as `depth,normal,primid`. `primid` brings `shapeid` with it,
    /// since a primitive index means nothing without its shape.
    pub fn parse(list: &str) -> std::result::Result<Aovs, String> {
        let mut a = Aovs::default();
        for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            match name {
                "depth" => a.depth = true,
                "normal" => a.normal = true,
                "shapeid" => a.shape_id = true,
                "primid" => {
                    a.prim_id = true;
                    a.shape_id = true;
                }
                "instanceid" => a.instance_id = true,
                "variance" => a.variance = true,
                "cost" => a.cost = true,
                other => {
                    return Err(format!(
                        "unknown AOV `{other}`, expected a comma-separated list of: {}",
                        Self::NAMES.join(", ")
                    ))
                }
            }
        }
        Ok(a)
    }

    pub fn any(&self) -> bool {
        self.depth
            || self.normal
            || self.shape_id
            || self.prim_id
            || self.instance_id
            || self.variance
            || self.cost
    }
}

/// The output formats, chosen by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Exr,
}

impl ImageFormat {
    pub fn from_path(path: &Path) -> Result<ImageFormat> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref()
        {
            Some("png") => Ok(ImageFormat::Png),
            Some("exr") => Ok(ImageFormat::Exr),
            _ => Err(Error::Invalid(format!(
                "{}: unknown image extension, expected .png (8-bit sRGB) or .exr (float RGB and AOVs)",
                path.display()
            ))),
        }
    }
}

/// Writes the film by the format of `path`'s extension. AOVs need EXR.
pub fn write_image(path: &Path, film: &Film, aovs: Aovs) -> Result<()> {
    write_image_with(path, film, aovs, None)
}

/// [`write_image`], with the pixels' costs for the `cost` AOV.
pub fn write_image_with(
    path: &Path,
    film: &Film,
    aovs: Aovs,
    cost: Option<&CostImage>,
) -> Result<()> {
    match ImageFormat::from_path(path)? {
        ImageFormat::Png if !film.channels.is_empty() => Err(Error::Invalid(format!(
            "{}: the integrator's channels ({}, ...) need an .exr output",
            path.display(),
            film.channels[0].name
        ))),
        ImageFormat::Png if aovs.any() => Err(Error::Invalid(format!(
            "{}: AOVs are written as EXR channels; use a .exr output",
            path.display()
        ))),
        ImageFormat::Png => write_png(path, film),
        ImageFormat::Exr => write_exr_with(path, film, aovs, cost),
    }
}

/// The sRGB transfer function (IEC 61966-2-1), clamped to [0, 1], quantized with rounding.
pub fn srgb_encode(linear: f32) -> u8 {
    let c = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// The 8-bit sRGB pixels of the film, row by row.
pub fn to_srgb8(film: &Film) -> Vec<u8> {
    film.rgb
        .iter()
        .flat_map(|c| [srgb_encode(c.x), srgb_encode(c.y), srgb_encode(c.z)])
        .collect()
}

pub fn write_png(path: &Path, film: &Film) -> Result<()> {
    let pixels = to_srgb8(film);
    write_atomically(path, |out| {
        image::write_buffer_with_format(
            out,
            &pixels,
            film.width,
            film.height,
            image::ExtendedColorType::Rgb8,
            image::ImageFormat::Png,
        )
        .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))
    })
}

pub fn write_exr(path: &Path, film: &Film, aovs: Aovs) -> Result<()> {
    write_exr_with(path, film, aovs, None)
}

/// [`write_exr`], with the pixels' costs for the `cost` AOV.
pub fn write_exr_with(
    path: &Path,
    film: &Film,
    aovs: Aovs,
    cost: Option<&CostImage>,
) -> Result<()> {
    let f32s = |f: &dyn Fn(usize) -> f32| -> FlatSamples {
        FlatSamples::F32((0..film.rgb.len()).map(f).collect())
    };
    let mut channels: Vec<AnyChannel<FlatSamples>> = vec![
        AnyChannel::new("R", f32s(&|i| film.rgb[i].x)),
        AnyChannel::new("G", f32s(&|i| film.rgb[i].y)),
        AnyChannel::new("B", f32s(&|i| film.rgb[i].z)),
    ];
    if aovs.depth {
        channels.push(AnyChannel::new(
            "depth",
            FlatSamples::F32(film.depth.clone()),
        ));
    }
    if aovs.normal {
        channels.push(AnyChannel::new("N.X", f32s(&|i| film.normal[i].x)));
        channels.push(AnyChannel::new("N.Y", f32s(&|i| film.normal[i].y)));
        channels.push(AnyChannel::new("N.Z", f32s(&|i| film.normal[i].z)));
    }
    if aovs.shape_id {
        channels.push(AnyChannel::new(
            "shapeid",
            FlatSamples::U32(film.shape_id.clone()),
        ));
    }
    if aovs.prim_id {
        channels.push(AnyChannel::new(
            "primid",
            FlatSamples::U32(film.prim_id.clone()),
        ));
    }
    if aovs.instance_id {
        channels.push(AnyChannel::new(
            "instanceid",
            FlatSamples::U32(film.instance_id.clone()),
        ));
    }
    if aovs.variance {
        if film.variance.len() != film.rgb.len() {
            return Err(Error::Invalid(
                "the variance AOV needs a rendered film (this one has no variance)".into(),
            ));
        }
        channels.push(AnyChannel::new("variance.R", f32s(&|i| film.variance[i].x)));
        channels.push(AnyChannel::new("variance.G", f32s(&|i| film.variance[i].y)));
        channels.push(AnyChannel::new("variance.B", f32s(&|i| film.variance[i].z)));
    }
    if aovs.cost {
        let cost = cost
            .filter(|c| c.nodes.len() == film.rgb.len())
            .ok_or_else(|| {
                Error::Invalid("the cost AOV needs the costs of the film's pixels".into())
            })?;
        channels.push(AnyChannel::new(
            "cost.nodes",
            FlatSamples::F32(cost.nodes.clone()),
        ));
        channels.push(AnyChannel::new(
            "cost.tests",
            FlatSamples::F32(cost.tests.clone()),
        ));
    }
    for c in &film.channels {
        if c.values.len() != film.rgb.len() {
            return Err(Error::Invalid(format!(
                "channel {} has {} values for {} pixels",
                c.name,
                c.values.len(),
                film.rgb.len()
            )));
        }
        channels.push(AnyChannel::new(
            c.name.as_str(),
            FlatSamples::F32(c.values.clone()),
        ));
    }
    for (i, c) in channels.iter().enumerate() {
        if channels[..i].iter().any(|o| o.name == c.name) {
            return Err(Error::Invalid(format!(
                "{}: two channels are named {}",
                path.display(),
                c.name
            )));
        }
    }
    let layer = Layer::new(
        (film.width as usize, film.height as usize),
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    let image = Image::from_layer(layer);
    write_atomically(path, |out| {
        image
            .write()
            .to_buffered(out)
            .map_err(|e| Error::Invalid(format!("{}: {e}", path.display())))
    })
}
