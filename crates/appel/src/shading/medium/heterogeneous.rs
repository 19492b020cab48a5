//! Mitsuba's `heterogeneous` medium: extinction `scale * sigma_t(p)` and albedo from volumes,
//! inside the box of its `sigma_t` volume only. Its majorants are local: a coarse grid of bounds
//! over the box ([`MajorantGrid`], pbrt-v4's `MajorantGrid`), whose cells a ray walks so that
//! tracking samples each cell at its own rate. Trilinear interpolation never exceeds the samples
//! it reads, so the bounds hold and null collisions have non-negative density.

use super::majorant_grid::{MajorantGrid, MajorantSegment, Majorants};
use super::volume::VolumeValues;
use super::{MediumPlugin, Phase, Volume};
use crate::math::{Ray, Vec3};

#[derive(Clone, Debug)]
pub struct Heterogeneous {
    pub sigma_t: Volume,
    pub albedo: Volume,
    pub scale: f32,
    pub phase: Phase,
    /// Bounds of `scale * sigma_t` (any channel) over cells of the volume's unit cube.
    pub majorants: MajorantGrid,
}

impl Heterogeneous {
    /// The medium with a majorant grid of [`MajorantGrid::resolution_for`] its grid (one cell
    /// for a constant extinction).
    pub fn new(sigma_t: Volume, albedo: Volume, scale: f32, phase: Phase) -> Self {
        let resolution = match &sigma_t.values {
            VolumeValues::Grid(g) => MajorantGrid::resolution_for(g),
            VolumeValues::Constant(_) => [1, 1, 1],
        };
        let mut m = Heterogeneous {
            sigma_t,
            albedo,
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
        (sigma_t, sigma_t * self.albedo.eval(p))
    }

    fn phase(&self) -> &Phase {
        &self.phase
    }
}
