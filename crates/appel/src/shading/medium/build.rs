//! Runtime media from their descriptions: volumes read (grid files relative to the scene's
//! folder), constants resolved, phase functions built.

use super::volume::{Grid, VolumeValues};
use super::{
    BlendPhase, HenyeyGreenstein, Heterogeneous, Homogeneous, Isotropic, Medium, Phase, Rayleigh,
    Volume,
};
use crate::description::{MediumDesc, PhaseDesc, VolumeDesc, VolumeFilter, VolumeNode};
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
        MediumDesc::Heterogeneous(h) => Medium::Heterogeneous(Heterogeneous::new(
            volume(&h.sigma_t, base_dir).map_err(at)?,
            volume(&h.albedo, base_dir).map_err(at)?,
            h.scale,
            phase(&h.phase),
        )),
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
