//! The scene's emitters for the Monte Carlo integrators: `[[light]]` entries and the surfaces with
//! an `emitter`, the power-based choice among them, and which surface emits as which emitter.

use super::geometry::{Geometry, ShapeKind};
use super::textures::TextureCache;
use crate::description::{Description, FovAxis, LightDesc};
use crate::error::{Error, Location, Result};
use crate::shading::emitter::{
    AreaEmitter, ConstantEnvironment, DirectionalLight, Emitter, EnvMap, LightPicker, PointLight,
    Projector, ShapeSampler, SpotLight, SunPlacement, SunSky, SunSkyParams, SunTime,
};
use crate::shading::texture::Texture;
use glam::{Mat4, Vec2, Vec3};

/// [`SceneEmitters::of_shape`] of a surface that does not emit.
pub const NO_EMITTER: u32 = u32::MAX;

#[derive(Clone, Debug)]
pub struct SceneEmitters {
    pub emitters: Vec<Emitter>,
    /// Chooses an emitter for next-event estimation in proportion to its power.
    pub picker: LightPicker,
    /// The emitter of each top-level surface (by `Geometry::shapes` index), or [`NO_EMITTER`].
    pub of_shape: Vec<u32>,
    /// The infinite emitters (environment), which rays leaving the scene see.
    pub infinite: Vec<u32>,
    /// The delta emitters (points, spots, projectors, directional lights), in order: the lights
    /// of `whitted` and `raycast`, which shade from every one with a shadow ray.
    pub delta: Vec<u32>,
}

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
            let e = match l {
                LightDesc::Point {
                    position,
                    color,
                    intensity,
                } => Emitter::Point(PointLight {
                    position: Vec3::from(*position),
                    intensity: Vec3::from(*color) * *intensity,
                }),
                LightDesc::Directional {
                    direction,
                    color,
                    intensity,
                } => Emitter::Directional(DirectionalLight::new(
                    Vec3::from(*direction).normalize(),
                    Vec3::from(*color) * *intensity,
                )),
                LightDesc::Spot {
                    position,
                    look_at,
                    color,
                    intensity,
                    cutoff_angle,
                    beam_width,
                    texture,
                    up,
                } => Emitter::Spot(SpotLight::new(
                    look_at_frame(*position, *look_at, *up),
                    Vec3::from(*color) * *intensity,
                    *cutoff_angle,
                    beam_width.unwrap_or(0.75 * cutoff_angle),
                    texture.as_ref().map(|t| textures.texture(t)).transpose()?,
                )),
                LightDesc::Projector {
                    position,
                    look_at,
                    up,
                    irradiance,
                    scale,
                    fov,
                    fov_axis,
                } => {
                    let irradiance = textures.texture(irradiance)?;
                    let (w, h) = match &irradiance {
                        Texture::Bitmap(b) => (b.bitmap().width as f32, b.bitmap().height as f32),
                        _ => (1.0, 1.0),
                    };
                    // Mitsuba's default lens when no field of view is given: 50 mm on 36 x 24 mm
                    // film, across the diagonal.
                    let (fov, axis) = match fov {
                        Some(f) => (*f, fov_axis.unwrap_or(FovAxis::X)),
                        None => (
                            2.0 * (36f32.hypot(24.0) / 100.0).atan().to_degrees(),
                            FovAxis::Diagonal,
                        ),
                    };
                    let across = match axis {
                        FovAxis::X => w,
                        FovAxis::Y => h,
                        FovAxis::Diagonal => w.hypot(h),
                        FovAxis::Smaller => w.min(h),
                        FovAxis::Larger => w.max(h),
                    };
                    let tan_half_x = (0.5 * fov.to_radians()).tan() * w / across;
                    Emitter::Projector(Projector::new(
                        look_at_frame(*position, *look_at, *up),
                        irradiance,
                        *scale,
                        tan_half_x,
                        w / h,
                    ))
                }
                LightDesc::Constant { radiance } => {
                    Emitter::Constant(ConstantEnvironment::new(Vec3::from(*radiance)))
                }
                LightDesc::Envmap {
                    file,
                    scale,
                    transform,
                } => {
                    let bitmap = textures.image(file, true)?;
                    let m = transform.as_ref().map_or(Mat4::IDENTITY, |t| t.matrix());
                    Emitter::EnvMap(EnvMap::new(&bitmap, m, *scale).map_err(|e| {
                        Error::input(Location::file(textures.path_of(file)), e.to_string())
                    })?)
                }
                LightDesc::Sunsky {
                    sun_direction,
                    latitude,
                    longitude,
                    timezone,
                    year,
                    month,
                    day,
                    hour,
                    minute,
                    second,
                    turbidity,
                    albedo,
                    sun_scale,
                    sky_scale,
                    sun_aperture,
                    complex_sun,
                    transform,
                } => {
                    // Mitsuba's defaults for the place and time: Tokyo, 2010-07-10 15:00.
                    let sun = match sun_direction {
                        Some(d) => SunPlacement::Direction(Vec3::from(*d)),
                        None => SunPlacement::Time(SunTime {
                            latitude: latitude.unwrap_or(35.6894),
                            longitude: longitude.unwrap_or(139.6917),
                            timezone: timezone.unwrap_or(9.0),
                            year: year.unwrap_or(2010),
                            month: month.unwrap_or(7),
                            day: day.unwrap_or(10),
                            hour: hour.unwrap_or(15.0),
                            minute: minute.unwrap_or(0.0),
                            second: second.unwrap_or(0.0),
                        }),
                    };
                    let params = SunSkyParams {
                        sun,
                        turbidity: *turbidity,
                        albedo: *albedo,
                        sun_scale: *sun_scale,
                        sky_scale: *sky_scale,
                        sun_aperture: *sun_aperture,
                        complex_sun: *complex_sun,
                        to_world: transform.as_ref().map_or(Mat4::IDENTITY, |t| t.matrix()),
                    };
                    // Fails only if the bundled model data do not read.
                    Emitter::SunSky(
                        SunSky::new(&params).map_err(|e| Error::Invalid(format!("sunsky: {e}")))?,
                    )
                }
            };
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
            picker: LightPicker::new(&powers),
            emitters,
            of_shape,
            infinite,
            delta,
        })
    }
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
