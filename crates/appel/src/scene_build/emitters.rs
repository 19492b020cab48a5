//! Building the scene's emitters: each `[[light]]` and emitting surface becomes an emitter, and the
//! picker weighs them by power.

use super::textures::TextureCache;
use crate::description::{
    Description, FovAxis, LightDesc, ProjectorDesc, SunPlaceDesc, SunSkyDesc,
};
use crate::error::{Error, Location, Result};
use crate::scene::{Geometry, SceneEmitters, ShapeKind, NO_EMITTER};
use crate::shading::emitter::{
    AreaEmitter, ConstantEnvironment, DirectionalLight, Emitter, EnvMap, EqualAreaEnvMap,
    LightPicker, PointLight, Projector, ShapeSampler, SpotLight, SunPlacement, SunSky,
    SunSkyParams,
};
use crate::shading::texture::Texture;
use glam::{Mat4, Vec2, Vec3};

impl SceneEmitters {
    /// `surfaces` are surfaces that emit by their mesh file's material (glTF emission), by
    /// `Geometry::shapes` index.
    pub fn build(
        d: &Description,
        geometry: &Geometry,
        surfaces: &[(u32, Texture)],
        textures: &mut TextureCache,
    ) -> Result<Self> {
        let mut emitters = Vec::new();
        let mut of_shape = vec![NO_EMITTER; geometry.shapes.len()];
        for (shape, radiance) in surfaces {
            let i = *shape as usize;
            if i >= of_shape.len() || of_shape[i] != NO_EMITTER {
                continue;
            }
            if let Some(sampler) = triangles_of(geometry, &[i]) {
                of_shape[i] = emitters.len() as u32;
                emitters.push(Emitter::Area(AreaEmitter::new(radiance.clone(), sampler)));
            }
        }
        for (index, s) in d.shapes.iter().enumerate() {
            let Some(e) = s.emitter() else { continue };
            let radiance = textures.texture(&e.radiance)?;
            // Every surface the `[[shape]]` became (a mesh file may be several) emits as one light.
            let surfaces: Vec<usize> = (0..geometry.shapes.len())
                .filter(|&i| geometry.shapes[i].source.shape == index as u32)
                .collect();
            let sampler = match surfaces.as_slice() {
                [one] => match &geometry.shapes[*one].kind {
                    ShapeKind::Sphere(sphere) => Some(ShapeSampler::Sphere {
                        center: sphere.center,
                        radius: sphere.radius,
                    }),
                    ShapeKind::Cylinder(c) => Some(
                        ShapeSampler::cylinder(c.to_world(), c.flip_normals()).ok_or_else(
                            || {
                                Error::Invalid(format!(
                                    "shape[{index}]: an emitting cylinder must stay circular \
                                     (its transform may rotate, translate and scale, with equal \
                                     scales across the axis)"
                                ))
                            },
                        )?,
                    ),
                    _ => None,
                },
                _ => None,
            };
            let sampler = match sampler {
                Some(s) => s,
                None => triangles_of(geometry, &surfaces).ok_or_else(|| {
                    Error::Invalid(format!(
                        "shape[{index}] has an emitter but no surface area to emit from \
                         (instanced meshes cannot emit)"
                    ))
                })?,
            };
            let id = emitters.len() as u32;
            emitters.push(Emitter::Area(AreaEmitter::new(radiance, sampler)));
            for i in surfaces {
                of_shape[i] = id;
            }
        }
        let mut infinite = Vec::new();
        for l in &d.lights {
            let e = light(l, textures)?;
            if e.is_infinite() {
                infinite.push(emitters.len() as u32);
            }
            emitters.push(e);
        }
        let bounds = geometry.bounds();
        let (center, radius) = if bounds.min.is_finite() && bounds.max.is_finite() {
            let c = (bounds.min + bounds.max) * 0.5;
            (c, (bounds.max - c).length().max(1e-3))
        } else {
            (Vec3::ZERO, 1.0)
        };
        for e in &mut emitters {
            e.set_scene_bounds(center, radius);
        }
        let powers: Vec<f32> = emitters.iter().map(Emitter::power).collect();
        let delta = (0..emitters.len() as u32)
            .filter(|&e| emitters[e as usize].is_delta())
            .collect();
        Ok(Self {
            picker: LightPicker::new(
                &powers,
                &emitters
                    .iter()
                    .map(Emitter::is_infinite)
                    .collect::<Vec<_>>(),
            ),
            emitters,
            of_shape,
            infinite,
            delta,
            sphere: (center, radius),
        })
    }
}

/// The emitter of a `[[light]]`.
fn light(l: &LightDesc, textures: &mut TextureCache) -> Result<Emitter> {
    Ok(match l {
        LightDesc::Point(p) => Emitter::Point(PointLight {
            position: Vec3::from(p.position),
            intensity: Vec3::from(p.color) * p.intensity,
        }),
        LightDesc::Directional(l) => Emitter::Directional(DirectionalLight::new(
            Vec3::from(l.direction).normalize(),
            Vec3::from(l.color) * l.intensity,
        )),
        LightDesc::Spot(s) => Emitter::Spot(SpotLight::new(
            look_at_frame(s.position, s.look_at, s.up),
            Vec3::from(s.color) * s.intensity,
            s.cutoff_angle,
            s.beam_width(),
            s.texture
                .as_ref()
                .map(|t| textures.texture(t))
                .transpose()?,
        )),
        LightDesc::Projector(p) => projector(p, textures)?,
        LightDesc::Constant(c) => {
            Emitter::Constant(ConstantEnvironment::new(Vec3::from(c.radiance)))
        }
        LightDesc::EnvMap(e) => {
            let bitmap = textures.image(&e.file, true)?;
            let m = e.transform.as_ref().map_or(Mat4::IDENTITY, |t| t.matrix());
            Emitter::EnvMap(EnvMap::new(&bitmap, m, e.scale).map_err(|err| {
                Error::input(Location::file(textures.path_of(&e.file)), err.to_string())
            })?)
        }
        LightDesc::EqualAreaEnvMap(e) => {
            let bitmap = textures.image(&e.file, true)?;
            let m = e.transform.as_ref().map_or(Mat4::IDENTITY, |t| t.matrix());
            Emitter::EqualAreaEnvMap(
                EqualAreaEnvMap::new(&bitmap, m, e.scale)
                    .map_err(|err| Error::input(Location::file(textures.path_of(&e.file)), err))?,
            )
        }
        LightDesc::SunSky(s) => sunsky(s)?,
    })
}

fn projector(p: &ProjectorDesc, textures: &mut TextureCache) -> Result<Emitter> {
    let irradiance = textures.texture(&p.irradiance)?;
    let (w, h) = match &irradiance {
        Texture::Bitmap(b) => (b.bitmap().width as f32, b.bitmap().height as f32),
        _ => (1.0, 1.0),
    };
    let (fov, axis) = p.field_of_view();
    let across = match axis {
        FovAxis::X => w,
        FovAxis::Y => h,
        FovAxis::Diagonal => w.hypot(h),
        FovAxis::Smaller => w.min(h),
        FovAxis::Larger => w.max(h),
    };
    let tan_half_x = (0.5 * fov.to_radians()).tan() * w / across;
    Ok(Emitter::Projector(Projector::new(
        look_at_frame(p.position, p.look_at, p.up),
        irradiance,
        p.scale,
        tan_half_x,
        w / h,
    )))
}

fn sunsky(s: &SunSkyDesc) -> Result<Emitter> {
    let sun = match s.sun() {
        SunPlaceDesc::Direction(d) => SunPlacement::Direction(Vec3::from(d)),
        SunPlaceDesc::Time(t) => SunPlacement::Time(t),
    };
    let params = SunSkyParams {
        sun,
        turbidity: s.turbidity,
        albedo: s.albedo,
        sun_scale: s.sun_scale,
        sky_scale: s.sky_scale,
        sun_aperture: s.sun_aperture,
        complex_sun: s.complex_sun,
        to_world: s.transform.as_ref().map_or(Mat4::IDENTITY, |t| t.matrix()),
    };
    // Fails only if the bundled model data do not read.
    Ok(Emitter::SunSky(
        SunSky::new(&params).map_err(|e| Error::Invalid(format!("sunsky: {e}")))?,
    ))
}

/// Mitsuba's `lookat` frame for a light at `position` looking down its local +z toward `look_at`:
/// x = up × z, y = z × x. Without an `up` (or one along the axis), +y, or +x for a vertical axis.
fn look_at_frame(position: [f32; 3], look_at: [f32; 3], up: Option<[f32; 3]>) -> Mat4 {
    let eye = Vec3::from(position);
    let dir = (Vec3::from(look_at) - eye).normalize();
    let up = match up.map(Vec3::from) {
        Some(up) if up.cross(dir).length_squared() > 1e-12 * up.length_squared() => up,
        _ if dir.y.abs() < 0.9 => Vec3::Y,
        _ => Vec3::X,
    };
    let x = up.cross(dir).normalize();
    Mat4::from_cols(
        x.extend(0.0),
        dir.cross(x).extend(0.0),
        dir.extend(0.0),
        eye.extend(1.0),
    )
}

/// The world-space triangles (with uvs where the meshes have them) of these mesh surfaces.
fn triangles_of(geometry: &Geometry, surfaces: &[usize]) -> Option<ShapeSampler> {
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    let mut all_uv = true;
    for &s in surfaces {
        let ShapeKind::Mesh(m) = geometry.shapes[s].kind else {
            return None;
        };
        let mesh = &geometry.meshes[m as usize];
        for (t, tri) in mesh.indices.iter().enumerate() {
            positions.push(mesh.vertices(t));
            match &mesh.uvs {
                Some(uv) => uvs.push(tri.map(|i| uv[i as usize])),
                None => {
                    all_uv = false;
                    uvs.push([Vec2::ZERO; 3]);
                }
            }
        }
    }
    if positions.is_empty() {
        return None;
    }
    Some(if all_uv {
        ShapeSampler::triangles_with_uv(&positions, &uvs)
    } else {
        ShapeSampler::triangles(&positions)
    })
}
