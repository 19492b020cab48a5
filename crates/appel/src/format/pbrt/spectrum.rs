//! pbrt's spectrum-valued parameters as linear sRGB: `rgb` values as they are, `spectrum` as
//! (wavelength, value) pairs, a named spectrum or a `.spd` file, and `blackbody` temperatures.
//! pbrt-v4 renders spectrally; Appel, like Mitsuba's RGB variants, integrates each spectrum to a
//! colour once (`pairs_to_rgb`).

use super::params::{Param, ParamType};
use crate::error::Result;
use crate::format::mitsuba::spectrum::{pairs_to_rgb, SpectrumUse};
use std::path::Path;

/// What a spectrum describes, which decides how it becomes a colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Use {
    /// A reflectance: clamped to [0, 1].
    Albedo,
    /// An index of refraction or absorption.
    Unbounded,
    /// Emitted light. pbrt-v4 divides an emission spectrum by its luminance (so that `scale` is
    /// in nits), except that an `rgb` value keeps its own: it stands for the colour under the
    /// colour space's illuminant, normalised to one nit (pbrt-v4's `RGBIlluminantSpectrum` and
    /// `SpectrumToPhotometric`).
    Illuminant,
}

/// The colour of a spectrum-valued parameter (`rgb`, `spectrum` or `blackbody`); `base_dir`
/// resolves `.spd` files.
pub fn rgb_of(p: &Param, use_: Use, base_dir: &Path) -> Result<[f32; 3]> {
    let rgb = match p.ty {
        ParamType::Rgb => {
            let v = p.numbers();
            if v.len() != 3 {
                return Err(p.error(format!("\"rgb {}\" takes three numbers", p.name)));
            }
            if use_ != Use::Unbounded && v.iter().any(|x| *x < 0.0) {
                return Err(p.error(format!("\"rgb {}\" must not be negative", p.name)));
            }
            let rgb = [v[0], v[1], v[2]];
            if use_ == Use::Albedo && rgb.iter().any(|x| *x > 1.0) {
                return Err(p.error(format!(
                    "\"rgb {}\" is a reflectance and must lie in [0, 1]",
                    p.name
                )));
            }
            rgb
        }
        ParamType::Spectrum => {
            let pairs = match p.strings().first() {
                Some(name) => named_or_file(p, name, base_dir)?,
                None => numbers_to_pairs(p)?,
            };
            let pairs = match pairs {
                Spectrum::Rgb(rgb) => return Ok(rgb.map(|x| x as f32)),
                Spectrum::Pairs(pairs) => pairs,
            };
            let rgb = pairs_to_rgb(
                &pairs,
                match use_ {
                    Use::Albedo => SpectrumUse::Reflectance,
                    Use::Unbounded => SpectrumUse::Unbounded,
                    Use::Illuminant => SpectrumUse::Emission,
                },
            );
            if use_ == Use::Illuminant {
                per_nit(p, rgb)?
            } else {
                rgb
            }
        }
        ParamType::Blackbody => {
            if use_ != Use::Illuminant {
                return Err(p.error(format!(
                    "\"blackbody {}\": a blackbody describes emitted light only",
                    p.name
                )));
            }
            let t = p.numbers()[0];
            if p.numbers().len() != 1 || t <= 0.0 {
                return Err(p.error("a blackbody takes one positive temperature in kelvin"));
            }
            per_nit(p, pairs_to_rgb(&planck(t), SpectrumUse::Emission))?
        }
        other => {
            return Err(p.error(format!(
                "\"{}\" must be rgb, spectrum or blackbody, not {}",
                p.name,
                other.name()
            )))
        }
    };
    Ok(rgb.map(|x| x as f32))
}

/// Scales an emitted colour to luminance 1.
fn per_nit(p: &Param, rgb: [f64; 3]) -> Result<[f64; 3]> {
    let y = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
    if y.is_nan() || y <= 0.0 {
        return Err(p.error(format!("\"{}\" emits no visible light", p.name)));
    }
    Ok(rgb.map(|x| x / y))
}

/// Planck's law sampled every 5 nm over the visible range (the scale does not matter: emission
/// spectra are normalised to one nit).
fn planck(t: f64) -> Vec<(f64, f64)> {
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    (0..=94)
        .map(|i| {
            let nm = 360.0 + 5.0 * i as f64;
            let l = nm * 1e-9;
            let b = 2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * t)).exp() - 1.0));
            (nm, b * 1e-12)
        })
        .collect()
}

enum Spectrum {
    /// A named spectrum whose colour Appel already knows.
    Rgb([f64; 3]),
    Pairs(Vec<(f64, f64)>),
}

fn numbers_to_pairs(p: &Param) -> Result<Spectrum> {
    let v = p.numbers();
    let pairs: Vec<(f64, f64)> = v.chunks_exact(2).map(|c| (c[0], c[1])).collect();
    check_pairs(p, &pairs)?;
    Ok(Spectrum::Pairs(pairs))
}

fn check_pairs(p: &Param, pairs: &[(f64, f64)]) -> Result<()> {
    if pairs.len() < 2 || pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(p.error(format!(
            "\"spectrum {}\": give at least two (wavelength, value) pairs with increasing \
             wavelengths",
            p.name
        )));
    }
    Ok(())
}

/// pbrt's named spectra that Appel has (its conductors' `metal-X-eta`/`metal-X-k`, and BK7
/// glass), or a file of (wavelength, value) pairs.
fn named_or_file(p: &Param, name: &str, base_dir: &Path) -> Result<Spectrum> {
    if let Some(rest) = name.strip_prefix("metal-") {
        let (metal, part) = rest
            .rsplit_once('-')
            .ok_or_else(|| p.error(format!("unknown named spectrum \"{name}\"")))?;
        let (eta, k) = crate::description::spectra::conductor(metal).ok_or_else(|| {
            p.error(format!(
                "named spectrum \"{name}\": Appel has no data for the metal \"{metal}\""
            ))
        })?;
        let v = match part {
            "eta" => eta,
            "k" => k,
            _ => return Err(p.error(format!("unknown named spectrum \"{name}\""))),
        };
        return Ok(Spectrum::Rgb([v.x as f64, v.y as f64, v.z as f64]));
    }
    if name == "glass-BK7" {
        let eta = crate::description::spectra::ior("bk7").expect("a known IOR") as f64;
        return Ok(Spectrum::Rgb([eta; 3]));
    }
    if !name.ends_with(".spd") {
        return Err(p.error(format!(
            "named spectrum \"{name}\" is not one Appel has (metal-<name>-eta and -k for its \
             conductors, glass-BK7), nor a .spd file"
        )));
    }
    let path = base_dir.join(name);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        p.error(format!(
            "cannot read the spectrum file \"{}\": {e}",
            path.display()
        ))
    })?;
    let mut numbers = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        for w in line.split_whitespace() {
            numbers.push(super::params::parse_number(w).ok_or_else(|| {
                p.error(format!(
                    "{}:{}: bad number \"{w}\" in the spectrum file",
                    path.display(),
                    i + 1
                ))
            })?);
        }
    }
    if numbers.len() % 2 != 0 {
        return Err(p.error(format!(
            "{}: a spectrum file holds (wavelength, value) pairs; it has an odd count of numbers",
            path.display()
        )));
    }
    let pairs: Vec<(f64, f64)> = numbers.chunks_exact(2).map(|c| (c[0], c[1])).collect();
    check_pairs(p, &pairs)?;
    Ok(Spectrum::Pairs(pairs))
}
