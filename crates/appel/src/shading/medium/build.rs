//! Runtime media from their descriptions: volumes read (grid files relative to the scene's
//! folder), constants resolved, phase functions built.

use super::volume::{Grid, VolumeValues};
use super::Scattering;
use super::{
    BlendPhase, HenyeyGreenstein, Heterogeneous, Homogeneous, Isotropic, Medium, Phase, Rayleigh,
    Volume,
};
use crate::description::{
    HeterogeneousCoefficients, MediumDesc, PhaseDesc, VolumeDesc, VolumeFilter, VolumeNode,
};
use crate::error::{Error, Result};
use crate::io::grid_volume::{read_grid_volume, GridVolume};
use glam::{Mat4, Vec3};
use std::path::Path;

/// The medium `name` of the description, its files found from `base_dir`.
pub fn build_medium(name: &str, d: &MediumDesc, base_dir: &Path) -> Result<Medium> {
    let at = |e: Error| match e {
        Error::Invalid(m) => Error::Invalid(format!("media.{name}: {m}")),
        e => e,
    };
    Ok(match d {
        MediumDesc::Homogeneous(h) => {
            let (sigma_t, albedo) = h.sigma_t_albedo();
            Medium::Homogeneous(Homogeneous {
                sigma_t: Vec3::from(sigma_t) * h.scale,
                albedo: volume(&albedo, base_dir).map_err(at)?,
                phase: phase(&h.phase),
            })
        }
        MediumDesc::Heterogeneous(h) => {
            let (sigma_t, scattering) = match h.coefficients() {
                HeterogeneousCoefficients::ExtinctionAlbedo { sigma_t, albedo } => (
                    volume(sigma_t, base_dir).map_err(at)?,
                    Scattering::Albedo(volume(albedo, base_dir).map_err(at)?),
                ),
                HeterogeneousCoefficients::AbsorptionScattering { sigma_a, sigma_s } => {
                    let scattering = volume(sigma_s, base_dir).map_err(at)?;
                    let extinction = sum(
                        (sigma_a, &volume(sigma_a, base_dir).map_err(at)?),
                        (sigma_s, &scattering),
                    )
                    .map_err(at)?;
                    (extinction, Scattering::Coefficient(scattering))
                }
            };
            Medium::Heterogeneous(Heterogeneous::new(
                sigma_t,
                scattering,
                h.scale,
                phase(&h.phase),
            ))
        }
    })
}

pub fn phase(d: &PhaseDesc) -> Phase {
    match d {
        PhaseDesc::Isotropic(_) => Phase::Isotropic(Isotropic),
        PhaseDesc::Hg(h) => Phase::Hg(HenyeyGreenstein { g: h.g }),
        PhaseDesc::Rayleigh(_) => Phase::Rayleigh(Rayleigh),
        PhaseDesc::BlendPhase(b) => Phase::BlendPhase(BlendPhase {
            weight: b.weight,
            phases: Box::new([phase(&b.phases[0]), phase(&b.phases[1])]),
        }),
    }
}

fn volume(d: &VolumeDesc, base_dir: &Path) -> Result<Volume> {
    let to_local = d
        .transform()
        .map_or(Mat4::IDENTITY, |t| t.matrix())
        .inverse();
    if !to_local.is_finite() {
        return Err(Error::Invalid(
            "a volume's transform cannot be inverted".into(),
        ));
    }
    let values = match d {
        VolumeDesc::Value(_)
        | VolumeDesc::Rgb(_)
        | VolumeDesc::Volume(VolumeNode::ConstVolume { .. }) => {
            VolumeValues::Constant(Vec3::from(d.constant().expect("a constant")))
        }
        VolumeDesc::Volume(VolumeNode::GridVolume { file, filter, .. }) => {
            let g = read_grid_volume(&base_dir.join(file))?;
            if g.channels != 1 && g.channels != 3 {
                return Err(Error::Invalid(format!(
                    "{file}: a medium's grid has 1 or 3 channels, this one {}",
                    g.channels
                )));
            }
            if let Some(bad) = g.data.iter().find(|v| !(v.is_finite() && **v >= 0.0)) {
                return Err(Error::Invalid(format!(
                    "{file}: a medium's grid holds finite values of at least 0, this one {bad}"
                )));
            }
            VolumeValues::Grid(Grid::new(g, *filter == VolumeFilter::Nearest))
        }
        VolumeDesc::Volume(VolumeNode::Values {
            resolution,
            channels,
            values,
            ..
        }) => VolumeValues::Grid(Grid::new(
            GridVolume {
                resolution: *resolution,
                channels: *channels,
                data: values.clone(),
            },
            false,
        )),
    };
    Ok(Volume { to_local, values })
}

/// The volume of `a + b`: the extinction of absorption and scattering volumes. A plain number
/// (no volume of its own) takes the other's box; otherwise the two share their transform, and
/// two grids their resolution and filter, so that the sum's lookup is the sum of their lookups.
fn sum((da, a): (&VolumeDesc, &Volume), (db, b): (&VolumeDesc, &Volume)) -> Result<Volume> {
    let plain = |d: &VolumeDesc| matches!(d, VolumeDesc::Value(_) | VolumeDesc::Rgb(_));
    let to_local = match (plain(da), plain(db)) {
        (true, _) => b.to_local,
        (false, true) => a.to_local,
        (false, false) if a.to_local == b.to_local => a.to_local,
        (false, false) => {
            return Err(Error::Invalid(
                "sigma_a and sigma_s must share one transform (the medium's box)".into(),
            ))
        }
    };
    let values = match (&a.values, &b.values) {
        (VolumeValues::Constant(x), VolumeValues::Constant(y)) => VolumeValues::Constant(*x + *y),
        (VolumeValues::Constant(c), VolumeValues::Grid(g))
        | (VolumeValues::Grid(g), VolumeValues::Constant(c)) => {
            VolumeValues::Grid(grid_sum(g, |_| *c))
        }
        (VolumeValues::Grid(g), VolumeValues::Grid(h)) => {
            if g.resolution != h.resolution || g.nearest != h.nearest {
                return Err(Error::Invalid(format!(
                    "sigma_a's grid ({:?} cells) and sigma_s's ({:?}) must have the same \
                     resolution and filter",
                    g.resolution, h.resolution
                )));
            }
            VolumeValues::Grid(grid_sum(g, |i| h.cell(i)))
        }
    };
    Ok(Volume { to_local, values })
}

/// `g` plus `other` of each cell (by its index, x fastest); one channel where every sum is
/// grey.
fn grid_sum(g: &Grid, other: impl Fn(usize) -> Vec3) -> Grid {
    let cells = g.resolution.iter().product::<usize>();
    let sums: Vec<Vec3> = (0..cells).map(|i| g.cell(i) + other(i)).collect();
    let grey = sums.iter().all(|v| v.x == v.y && v.y == v.z);
    let data = if grey {
        sums.iter().map(|v| v.x).collect()
    } else {
        sums.iter().flat_map(|v| v.to_array()).collect()
    };
    Grid {
        resolution: g.resolution,
        channels: if grey { 1 } else { 3 },
        data,
        nearest: g.nearest,
    }
}
