//! pbrt's scene-wide options (before `WorldBegin`): `Camera`, `Film`, `Sampler`, `PixelFilter`
//! and `Integrator`, with pbrt-v4's defaults, as Appel's camera and `[render]`.

use super::parser::Directive;
use super::tokenizer::Loc;
use crate::description::{
    BdptParams, CameraDesc, CameraKind, FilterDesc, FovAxis, IntegratorName, RenderDesc,
    SamplerName, SppmParams, StrategyImages,
};
use crate::error::Result;
use glam::{DMat4, DVec3};

#[derive(Default)]
pub(super) struct SceneOptions {
    camera: Option<Camera>,
    resolution: Option<(u32, u32)>,
    sampler: Option<(SamplerName, u32, u64)>,
    filter: Option<FilterDesc>,
    /// Mitsuba's `max_depth` (pbrt's `maxdepth` plus one).
    max_depth: Option<i32>,
    /// Whether the `Integrator` renders media (`volpath`, pbrt-v4's default, and
    /// `simplevolpath`); `None` before an `Integrator`.
    volumetric: Option<bool>,
    /// The integrator `Integrator` names where Appel has it (`bdpt`, `lightpath`, `sppm`); path
    /// otherwise.
    integrator: Option<IntegratorName>,
    /// `sppm`'s `radius` and `photonsperiteration`.
    sppm: Option<SppmParams>,
    /// `bdpt`'s `visualizestrategies` and `visualizeweights`.
    bdpt: Option<BdptParams>,
}

struct Camera {
    kind: CameraKind,
    /// Degrees, across the shorter image axis (perspective).
    fov: f64,
    /// `lensradius` and `focaldistance`, in camera space.
    lens_radius: f64,
    focal_distance: f64,
    camera_to_world: DMat4,
    loc: Loc,
}

impl SceneOptions {
    pub fn camera(&mut self, d: &Directive, ctm: DMat4) -> Result<()> {
        if self.camera.is_some() {
            return Err(d.loc.error("a scene has one Camera"));
        }
        let p = &d.params;
        let kind = match d.strings[0].as_str() {
            "perspective" => CameraKind::Perspective,
            "orthographic" => CameraKind::Orthographic,
            other => {
                return Err(d.loc.error(format!(
                    "unsupported camera \"{other}\" (supported: perspective, orthographic)"
                )))
            }
        };
        let fov = if kind == CameraKind::Perspective {
            p.float_or("fov", 90.0)?
        } else {
            90.0
        };
        if !(fov > 0.0 && fov < 180.0) {
            let at = p.get("fov").map_or(&d.loc, |p| &p.loc);
            return Err(at.error(format!("the field of view must be in (0, 180), got {fov}")));
        }
        // pbrt-v4's thin lens (section 5.2.3), on both projective cameras, with its defaults.
        let lens_radius = p.float_or("lensradius", 0.0)?;
        if !(lens_radius >= 0.0 && lens_radius.is_finite()) {
            let at = &p.get("lensradius").expect("read").loc;
            return Err(at.error(format!(
                "\"lensradius\" must be 0 (a pinhole) or positive, got {lens_radius}"
            )));
        }
        let focal_distance = p.float_or("focaldistance", 1e6)?;
        if !(focal_distance > 0.0 && focal_distance.is_finite()) {
            let at = &p.get("focaldistance").expect("read").loc;
            return Err(at.error(format!(
                "\"focaldistance\" must be a positive distance, got {focal_distance}"
            )));
        }
        for unsupported in ["screenwindow", "frameaspectratio"] {
            if let Some(q) = p.get(unsupported) {
                return Err(q.error(format!("\"{unsupported}\" is not supported")));
            }
        }
        // Motion blur's shutter interval does not matter to a static scene.
        p.ignore("shutteropen");
        p.ignore("shutterclose");
        self.camera = Some(Camera {
            kind,
            fov,
            lens_radius,
            focal_distance,
            camera_to_world: ctm.inverse(),
            loc: d.loc.clone(),
        });
        Ok(())
    }

    pub fn film(&mut self, d: &Directive) -> Result<()> {
        if self.resolution.is_some() {
            return Err(d.loc.error("a scene has one Film"));
        }
        if d.strings[0] != "rgb" {
            return Err(d.loc.error(format!(
                "unsupported film \"{}\" (supported: rgb)",
                d.strings[0]
            )));
        }
        let p = &d.params;
        let res = |name: &str, default: i64| -> Result<u32> {
            let v = p.int(name)?.unwrap_or(default);
            if !(1..=65536).contains(&v) {
                let at = &p.get(name).expect("read").loc;
                return Err(at.error(format!("\"{name}\" must be in 1..=65536, got {v}")));
            }
            Ok(v as u32)
        };
        self.resolution = Some((res("xresolution", 1280)?, res("yresolution", 720)?));
        // Where pbrt would write the image: Appel's `-o` decides that.
        p.ignore("filename");
        p.ignore("savefp16");
        // The physical film size only matters to pbrt's "realistic" camera.
        p.ignore("diagonal");
        for unsupported in [
            "cropwindow",
            "pixelbounds",
            "iso",
            "exposuretime",
            "whitebalance",
            "sensor",
            "maxcomponentvalue",
        ] {
            if let Some(q) = p.get(unsupported) {
                return Err(q.error(format!(
                    "the film's \"{unsupported}\" is not supported (Appel's film records the \
                     radiance as it is)"
                )));
            }
        }
        Ok(())
    }

    pub fn sampler(&mut self, d: &Directive) -> Result<()> {
        let name = match d.strings[0].as_str() {
            "independent" => SamplerName::Independent,
            // Appel's low-discrepancy sampler stands for pbrt's.
            "sobol" | "zsobol" | "paddedsobol" | "halton" | "pmj02bn" | "stratified" => {
                SamplerName::Sobol
            }
            other => {
                return Err(d.loc.error(format!(
                    "unsupported sampler \"{other}\" (supported: independent, sobol, zsobol, \
                     paddedsobol, halton, pmj02bn, stratified)"
                )))
            }
        };
        let p = &d.params;
        let spp = if d.strings[0] == "stratified" {
            let xs = p.int("xsamples")?.unwrap_or(4);
            let ys = p.int("ysamples")?.unwrap_or(4);
            p.ignore("jitter");
            xs * ys
        } else {
            p.int("pixelsamples")?.unwrap_or(16)
        };
        if !(1..=1 << 20).contains(&spp) {
            return Err(d
                .loc
                .error(format!("samples per pixel must be in 1..=2^20, got {spp}")));
        }
        let seed = p.int("seed")?.unwrap_or(0).max(0) as u64;
        p.ignore("randomization");
        self.sampler = Some((name, spp as u32, seed));
        Ok(())
    }

    /// pbrt-v4's filters and their default radii; a filter whose x and y radii differ is not
    /// Appel's.
    pub fn filter(&mut self, d: &Directive) -> Result<()> {
        let p = &d.params;
        let radius = |default: f64| -> Result<f32> {
            let x = p.float_or("xradius", default)?;
            let y = p.float_or("yradius", default)?;
            if x != y || x <= 0.0 {
                return Err(d.loc.error(format!(
                    "the filter's radii must be equal and positive, got {x} and {y}"
                )));
            }
            Ok(x as f32)
        };
        self.filter = Some(match d.strings[0].as_str() {
            "box" => FilterDesc::Box {
                radius: radius(0.5)?,
            },
            "triangle" => FilterDesc::Tent {
                radius: radius(2.0)?,
            },
            // pbrt's Gaussian (sigma 0.5, radius 1.5, its value at the radius subtracted) is
            // rendered with Appel's (the same sigma, cut at four of them).
            "gaussian" => {
                radius(1.5)?;
                FilterDesc::Gaussian {
                    stddev: p.float_or("sigma", 0.5)? as f32,
                }
            }
            other => {
                return Err(d.loc.error(format!(
                    "unsupported pixel filter \"{other}\" (supported: box, triangle, gaussian)"
                )))
            }
        });
        Ok(())
    }

    /// `Integrator`: `bdpt` is Appel's bidirectional path tracer, `lightpath` its particle
    /// tracer (`ptracer`) and `sppm` its photon mapping; pbrt's other estimators of the light
    /// transport equation (Metropolis, the simple path tracers) converge to the image the path
    /// tracer converges to (Veach 1997, ch. 8-11), so they are rendered with it and a warning
    /// says so; an integrator that computes something else (ambient occlusion, AOVs) is an
    /// error.
    pub fn integrator(&mut self, d: &Directive, warnings: &mut Vec<String>) -> Result<()> {
        self.volumetric = Some(matches!(d.strings[0].as_str(), "volpath" | "simplevolpath"));
        match d.strings[0].as_str() {
            "path" | "volpath" => {}
            "bdpt" => {
                self.integrator = Some(IntegratorName::Bdpt);
                // The images of each strategy, which pbrt writes as files beside the render and
                // Appel as channels of its EXR.
                let p = &d.params;
                let mut strategy_images = None;
                for (name, images) in [
                    ("visualizestrategies", StrategyImages::Unweighted),
                    ("visualizeweights", StrategyImages::Weighted),
                ] {
                    if p.bool_or(name, false)? {
                        if strategy_images.is_some() {
                            let at = &p.get(name).expect("read").loc;
                            return Err(at.error(
                                "\"visualizestrategies\" and \"visualizeweights\" are both set: \
                                 Appel writes one kind of strategy image, choose one",
                            ));
                        }
                        strategy_images = Some(images);
                    }
                }
                self.bdpt = Some(BdptParams {
                    strategy_images,
                    regularize: p.bool_or("regularize", false)?,
                });
            }
            "lightpath" => self.integrator = Some(IntegratorName::Ptracer),
            "sppm" => {
                self.integrator = Some(IntegratorName::Sppm);
                let p = &d.params;
                let radius = p.float_or("radius", 1.0)?;
                if !(radius > 0.0 && radius.is_finite()) {
                    let at = p.get("radius").map_or(&d.loc, |p| &p.loc);
                    return Err(at.error(format!("radius must be positive, got {radius}")));
                }
                let photons = p.int("photonsperiteration")?.unwrap_or(-1);
                if photons == 0 || photons < -1 || photons > u32::MAX as i64 {
                    let at = p.get("photonsperiteration").map_or(&d.loc, |p| &p.loc);
                    return Err(at.error(format!(
                        "photonsperiteration must be positive, or -1 for one per pixel, got \
                         {photons}"
                    )));
                }
                // The photons' own sequence follows from the scene's seed.
                p.ignore("seed");
                self.sppm = Some(SppmParams {
                    radius: radius as f32,
                    photons_per_iteration: photons.max(0) as u32,
                });
            }
            same @ ("mlt" | "simplepath" | "randomwalk" | "simplevolpath") => {
                warnings.push(format!(
                    "{}: Integrator \"{same}\" is rendered with Appel's path tracer: it converges \
                 to the same image, with other noise",
                    d.loc.describe()
                ))
            }
            other => {
                return Err(d.loc.error(format!(
                    "unsupported integrator \"{other}\" (supported: path, volpath, bdpt, \
                     lightpath, sppm; mlt, simplepath, randomwalk and simplevolpath are rendered \
                     as path)"
                )))
            }
        }
        let p = &d.params;
        let depth = p.int("maxdepth")?.unwrap_or(5);
        if depth < 0 || depth > i32::MAX as i64 - 1 {
            return Err(d
                .loc
                .error(format!("maxdepth must be at least 0, got {depth}")));
        }
        // pbrt counts bounces: maxdepth 0 sees emitters only, 1 adds direct light. Mitsuba (and
        // Appel) count path vertices: 1 sees emitters, 2 adds direct light.
        self.max_depth = Some(depth as i32 + 1);
        // Which light a path samples and how changes the noise, not the image.
        p.ignore("lightsampler");
        p.ignore("samplelights");
        p.ignore("samplebsdf");
        // pbrt's path tracers regularize too; Appel's only in `bdpt`.
        if self.integrator != Some(IntegratorName::Bdpt) && p.bool_or("regularize", false)? {
            let at = &p.get("regularize").expect("read").loc;
            return Err(at.error("\"regularize\" (a biased roughening) is supported by bdpt only"));
        }
        Ok(())
    }

    /// Whether the scene's integrator renders media (pbrt-v4's default, `volpath`, does).
    pub fn volumetric(&self) -> bool {
        self.volumetric.unwrap_or(true)
    }

    fn camera_to_world(&self) -> DMat4 {
        self.camera
            .as_ref()
            .map_or(DMat4::IDENTITY, |c| c.camera_to_world)
    }

    /// The mirror that makes the camera's frame right-handed in the description (see
    /// `convert`'s module comment).
    pub fn world_mirror(&self) -> DMat4 {
        if self.camera_to_world().determinant() > 0.0 {
            DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0))
        } else {
            DMat4::IDENTITY
        }
    }

    pub fn finish(&self, mirror: &DMat4) -> Result<(CameraDesc, RenderDesc)> {
        let m = *mirror * self.camera_to_world();
        let eye = m.transform_point3(DVec3::ZERO);
        let forward = m.transform_vector3(DVec3::Z);
        let up = m.transform_vector3(DVec3::Y);
        if forward.length_squared() == 0.0 || up.cross(forward).length_squared() == 0.0 {
            let loc = self.camera.as_ref().map(|c| c.loc.clone());
            let message = "the camera transform flattens the view";
            return Err(match loc {
                Some(l) => l.error(message),
                None => crate::error::Error::Invalid(message.into()),
            });
        }
        let f32s = |v: DVec3| [v.x as f32, v.y as f32, v.z as f32];
        let (width, height) = self.resolution.unwrap_or((1280, 720));
        let (kind, fov) = self
            .camera
            .as_ref()
            .map_or((CameraKind::Perspective, 90.0), |c| (c.kind, c.fov));
        // The lens lies in camera space: its radius and focal distance scale with the camera
        // transform's axes (a mirror keeps them).
        let (aperture_radius, focus_distance) = match &self.camera {
            Some(c) if c.lens_radius > 0.0 => (
                (c.lens_radius * m.transform_vector3(DVec3::X).length()) as f32,
                Some((c.focal_distance * forward.length()) as f32),
            ),
            _ => (0.0, None),
        };
        // pbrt's orthographic screen window spans [-1, 1] across the shorter axis.
        let aspect = width as f64 / height as f64;
        let half_width = (kind == CameraKind::Orthographic)
            .then(|| (aspect.max(1.0) * m.transform_vector3(DVec3::X).length()) as f32);
        let camera = CameraDesc {
            medium: None,
            kind,
            eye: f32s(eye),
            look_at: f32s(eye + forward.normalize()),
            up: f32s(up.normalize()),
            fov: fov as f32,
            fov_axis: FovAxis::Smaller,
            half_width,
            near_clip: 0.0,
            aperture_radius,
            focus_distance,
            width,
            height,
        };
        let (sampler, spp, seed) = self.sampler.unwrap_or((SamplerName::Sobol, 16, 0));
        let render = RenderDesc {
            integrator: self.integrator.unwrap_or(IntegratorName::Path),
            max_depth: self.max_depth.unwrap_or(6),
            spp,
            sampler: Some(sampler),
            seed,
            filter: self.filter.unwrap_or(FilterDesc::Gaussian { stddev: 0.5 }),
            sppm: self.sppm,
            bdpt: self.bdpt,
            ..RenderDesc::default()
        };
        Ok((camera, render))
    }
}
