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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::{HeterogeneousDesc, TransformDesc};
    use crate::shading::chi2::Pcg32;

    fn values(resolution: [usize; 3], channels: usize, rng: &mut Pcg32) -> VolumeDesc {
        let n = resolution.iter().product::<usize>() * channels;
        VolumeDesc::Volume(VolumeNode::Values {
            resolution,
            channels,
            values: (0..n).map(|_| rng.next_f32()).collect(),
            transform: Some(TransformDesc {
                scale: Some(crate::description::ScaleDesc::Uniform(2.0)),
                ..TransformDesc::default()
            }),
        })
    }

    /// Absorption and scattering grids: the extinction is the sum of their lookups and the
    /// scattering its own lookup, both times `scale`, everywhere in the box (cells' centres,
    /// between them and past the border), and the majorant bounds the extinction.
    #[test]
    fn absorption_and_scattering_grids_add_up_to_the_extinction() {
        let mut rng = Pcg32::new(7, 3);
        for (a, s) in [
            (
                values([3, 2, 4], 3, &mut rng),
                values([3, 2, 4], 1, &mut rng),
            ),
            (
                VolumeDesc::Rgb([0.2, 0.1, 0.0]),
                values([2, 5, 3], 3, &mut rng),
            ),
            (values([4, 1, 2], 1, &mut rng), VolumeDesc::Value(0.5)),
        ] {
            let d = MediumDesc::Heterogeneous(HeterogeneousDesc {
                sigma_a: Some(Box::new(a.clone())),
                sigma_s: Some(Box::new(s.clone())),
                scale: 1.5,
                ..HeterogeneousDesc::default()
            });
            d.check().unwrap();
            let m = build_medium("m", &d, Path::new(".")).unwrap();
            let (va, vs) = (
                volume(&a, Path::new(".")).unwrap(),
                volume(&s, Path::new(".")).unwrap(),
            );
            for _ in 0..2000 {
                let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.4 - 0.2;
                let (sigma_t, sigma_s) = m.coefficients(p);
                let want_s = vs.eval(p) * 1.5;
                let want_t = va.eval(p) * 1.5 + want_s;
                assert!(
                    (sigma_t - want_t).abs().max_element() < 1e-5,
                    "{sigma_t} {want_t}"
                );
                assert!(
                    (sigma_s - want_s).abs().max_element() < 1e-5,
                    "{sigma_s} {want_s}"
                );
                // The majorant of the segment holding `p`, along a ray through it, bounds it.
                let ray = crate::math::Ray::new(p - Vec3::X * 5.0, Vec3::X);
                if let Some(seg) = m.majorants(&ray, 10.0).find(|s| s.t0 <= 5.0 && 5.0 <= s.t1) {
                    assert!(
                        (sigma_t - seg.majorant * (1.0 + 1e-6)).max_element() <= 0.0,
                        "{sigma_t} {:?}",
                        seg.majorant
                    );
                }
            }
            // The box is the grid's, [0, 2]^3: the segments cover [1, 3] along this ray.
            let ray = crate::math::Ray::new(Vec3::new(-1.0, 1.0, 1.0), Vec3::X);
            let segments: Vec<_> = m.majorants(&ray, 10.0).collect();
            let (t0, t1) = (segments[0].t0, segments.last().unwrap().t1);
            assert!(
                (t0 - 1.0).abs() < 1e-5 && (t1 - 3.0).abs() < 1e-5,
                "{t0} {t1}"
            );
        }
        let mut rng = Pcg32::new(1, 1);
        let d = MediumDesc::Heterogeneous(HeterogeneousDesc {
            sigma_a: Some(Box::new(values([2, 2, 2], 1, &mut rng))),
            sigma_s: Some(Box::new(values([2, 2, 3], 1, &mut rng))),
            ..HeterogeneousDesc::default()
        });
        let e = build_medium("m", &d, Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("media.m") && e.contains("same resolution"),
            "{e}"
        );
    }
}
