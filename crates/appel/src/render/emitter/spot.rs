//! Mitsuba's `spot` emitter: a point light whose intensity is full inside `beam_width` of its axis,
//! falls linearly in angle to zero at `cutoff_angle`, optionally modulated by a texture projected
//! through the cone.

use super::EmitterSample;
use crate::render::texture::Texture;
use glam::{Mat4, Vec2, Vec3};
use std::f32::consts::PI;

#[derive(Clone, Debug)]
pub struct SpotLight {
    /// Light-to-world transform: the spot sits at the origin looking down +z.
    to_world: Mat4,
    from_world: Mat4,
    position: Vec3,
    pub intensity: Vec3,
    /// Projected through the cone: uv (0.5, 0.5) on the axis, the cone's edge at 0 and 1.
    pub texture: Option<Texture>,
    cutoff: f32,
    beam: f32,
    cos_cutoff: f32,
    cos_beam: f32,
    /// tan(cutoff): the half-width of the texture's projection plane at z = 1.
    uv_factor: f32,
}

impl SpotLight {
    /// Angles in degrees; Mitsuba's defaults are a cutoff of 20 and a beam width of 3/4 of it (see
    /// [`SpotLight::with_defaults`]). A beam width above the cutoff is clamped to it.
    pub fn new(
        to_world: Mat4,
        intensity: Vec3,
        cutoff_deg: f32,
        beam_width_deg: f32,
        texture: Option<Texture>,
    ) -> Self {
        let cutoff = cutoff_deg.to_radians();
        let beam = beam_width_deg.to_radians().min(cutoff);
        Self {
            to_world,
            from_world: to_world.inverse(),
            position: to_world.transform_point3(Vec3::ZERO),
            intensity,
            texture,
            cutoff,
            beam,
            cos_cutoff: cutoff.cos(),
            cos_beam: beam.cos(),
            uv_factor: cutoff.tan(),
        }
    }

    pub fn with_defaults(to_world: Mat4, intensity: Vec3) -> Self {
        Self::new(to_world, intensity, 20.0, 15.0, None)
    }

    pub fn to_world(&self) -> &Mat4 {
        &self.to_world
    }

    /// 1 inside the beam, (cutoff - θ) / (cutoff - beam) in the transition, 0 outside the cutoff.
    fn falloff(&self, local: Vec3) -> f32 {
        let cos_theta = local.normalize().z;
        if cos_theta <= self.cos_cutoff {
            0.0
        } else if cos_theta >= self.cos_beam {
            1.0
        } else {
            (self.cutoff - cos_theta.acos()) / (self.cutoff - self.beam)
        }
    }

    /// Intensity toward local direction `local` (away from the light).
    fn intensity_toward(&self, local: Vec3) -> Vec3 {
        let f = self.falloff(local);
        if f <= 0.0 {
            return Vec3::ZERO;
        }
        let mut i = self.intensity * f;
        if let Some(t) = &self.texture {
            let uv = Vec2::new(
                0.5 + 0.5 * local.x / (local.z * self.uv_factor),
                0.5 + 0.5 * local.y / (local.z * self.uv_factor),
            );
            i *= t.eval(uv);
        }
        i
    }

    pub fn sample_li(&self, p: Vec3) -> Option<EmitterSample> {
        let to = self.position - p;
        let dist2 = to.length_squared();
        if !(dist2 > 0.0) {
            return None;
        }
        let dist = dist2.sqrt();
        let wi = to / dist;
        let local = self.from_world.transform_vector3(-wi);
        let i = self.intensity_toward(local);
        if i == Vec3::ZERO {
            return None;
        }
        Some(EmitterSample {
            wi,
            dist,
            weight: i / dist2,
            pdf: 1.0,
            delta: true,
        })
    }

    /// Φ = I ∫ falloff dω = 2π I (1 + (sin b - sin c) / (c - b)) for beam b < cutoff c (the linear
    /// ramp integrated against sin θ), 2π I (1 - cos c) when they are equal; a texture scales it
    /// by its mean.
    pub fn power(&self) -> Vec3 {
        let (b, c) = (self.beam, self.cutoff);
        let solid_angle = if c - b > 1e-6 {
            2.0 * PI * (1.0 + (b.sin() - c.sin()) / (c - b))
        } else {
            2.0 * PI * (1.0 - c.cos())
        };
        let tex = self.texture.as_ref().map_or(Vec3::ONE, Texture::mean);
        self.intensity * tex * solid_angle
    }
}
