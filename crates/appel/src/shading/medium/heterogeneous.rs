//! Mitsuba's `heterogeneous` medium: extinction `scale * sigma_t(p)` and albedo from volumes,
//! inside the box of its `sigma_t` volume only. Given as absorption and scattering volumes
//! (pbrt-v4's `RGBGridMedium`), `sigma_t` is their sum, built as one volume of the same
//! resolution (trilinear interpolation is linear, so the sum's lookup is the sum of theirs), and
//! the scattering volume is looked up itself rather than as a ratio (interpolating
//! `sigma_s / sigma_t` would not give the interpolated `sigma_s`). Its majorants are local: a
//! coarse grid of bounds over the box ([`MajorantGrid`], pbrt-v4's `MajorantGrid`), whose cells a
//! ray walks so that tracking samples each cell at its own rate. Trilinear interpolation never
//! exceeds the samples it reads, so the bounds hold and null collisions have non-negative density.

use super::majorant_grid::{MajorantGrid, MajorantSegment, Majorants};
use super::volume::VolumeValues;
use super::{MediumPlugin, Phase, Volume};
use crate::math::{Ray, Vec3};

#[derive(Clone, Debug)]
pub struct Heterogeneous {
    pub sigma_t: Volume,
    pub scattering: Scattering,
    pub scale: f32,
    pub phase: Phase,
    /// Bounds of `scale * sigma_t` (any channel) over cells of the volume's unit cube.
    pub majorants: MajorantGrid,
}

/// Where a heterogeneous medium's scattering coefficient comes from.
#[derive(Clone, Debug)]
pub enum Scattering {
    /// The albedo: `sigma_s = sigma_t * albedo(p)`.
    Albedo(Volume),
    /// The scattering coefficient itself (before `scale`).
    Coefficient(Volume),
}

impl From<Volume> for Scattering {
    /// A volume alone is an albedo, Mitsuba's form.
    fn from(albedo: Volume) -> Self {
        Scattering::Albedo(albedo)
    }
}

impl Heterogeneous {
    /// The medium with a majorant grid of [`MajorantGrid::resolution_for`] its grid (one cell
    /// for a constant extinction).
    pub fn new(sigma_t: Volume, scattering: impl Into<Scattering>, scale: f32, phase: Phase) -> Self {
        let resolution = match &sigma_t.values {
            VolumeValues::Grid(g) => MajorantGrid::resolution_for(g),
            VolumeValues::Constant(_) => [1, 1, 1],
        };
        let mut m = Heterogeneous {
            sigma_t,
            scattering: scattering.into(),
            scale,
            phase,
            majorants: MajorantGrid::global(0.0),
        };
        m.set_majorant_resolution(resolution);
        m
    }

    /// Rebuilds the majorants over `resolution` cells (`[1, 1, 1]`: one global majorant, the
    /// largest extinction, as Mitsuba's `volpath` tracks).
    pub fn set_majorant_resolution(&mut self, resolution: [usize; 3]) {
        self.majorants = match &self.sigma_t.values {
            VolumeValues::Grid(g) => MajorantGrid::over(g, resolution, self.scale),
            VolumeValues::Constant(c) => MajorantGrid::global(c.max_element() * self.scale),
        };
    }
}

impl MediumPlugin for Heterogeneous {
    const NAME: &'static str = "heterogeneous";
    const HOMOGENEOUS: bool = false;

    #[inline]
    fn majorants(&self, ray: &Ray, t_max: f32) -> Majorants<'_> {
        let Some((t0, t1)) = self.sigma_t.range(ray, t_max) else {
            return Majorants::One(None);
        };
        if self.majorants.max.len() == 1 {
            return Majorants::One(Some(MajorantSegment {
                t0,
                t1,
                majorant: Vec3::splat(self.majorants.max[0]),
            }));
        }
        Majorants::Grid(self.majorants.walk(&self.sigma_t.to_local, ray, t0, t1))
    }

    #[inline]
    fn coefficients(&self, p: Vec3) -> (Vec3, Vec3) {
        let sigma_t = self.sigma_t.eval(p) * self.scale;
        let sigma_s = match &self.scattering {
            Scattering::Albedo(albedo) => sigma_t * albedo.eval(p),
            // Below the extinction but for rounding: the extinction's grid is this one plus the
            // absorption's.
            Scattering::Coefficient(sigma_s) => (sigma_s.eval(p) * self.scale).min(sigma_t),
        };
        (sigma_t, sigma_s)
    }

    fn phase(&self) -> &Phase {
        &self.phase
    }
}
