//! Checks that a parsed [`Description`] makes sense, before anything is built from it. Each problem is
//! reported with the path of the offending value, which the loader turns into a line and column.

use super::param_error::ParamError;
use super::parse::PathSeg;
use super::spectra;
use super::{
    Description, InstanceDesc, IorDesc, KeyframeDesc, LightDesc, MaterialDesc, ShapeDesc,
    TextureDesc, TextureNode, TransformDesc, Vec3f,
};
use crate::accel::AccelKind;

/// The largest image Appel agrees to render: the film holds about 40 bytes per pixel with AOVs, so
/// this is 4 GB.
pub const MAX_PIXELS: u64 = 100_000_000;
pub const MAX_DIMENSION: u32 = 65_536;
pub const MAX_DEPTH: i32 = 1024;
pub const MAX_SPP: u32 = 65_536;
pub const TRIANGLE_TESTS: &[&str] = crate::geometry::TriangleTest::NAMES;

/// A problem and where it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Invalid {
    pub path: Vec<PathSeg>,
    pub message: String,
}

struct Checker {
    path: Vec<PathSeg>,
}

type Check = Result<(), Invalid>;

impl Checker {
    fn fail<T>(&self, key: &str, message: impl Into<String>) -> Result<T, Invalid> {
        let mut path = self.path.clone();
        if !key.is_empty() {
            path.push(PathSeg::Key(key.into()));
        }
        Err(Invalid {
            path,
            message: message.into(),
        })
    }

    fn at<R>(&mut self, seg: PathSeg, f: impl FnOnce(&mut Self) -> R) -> R {
        self.path.push(seg);
        let r = f(self);
        self.path.pop();
        r
    }

    fn finite(&self, key: &str, v: &[f32]) -> Check {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            self.fail(key, format!("`{key}` must be finite, got {v:?}"))
        }
    }

    fn non_negative(&self, key: &str, v: &[f32]) -> Check {
        self.finite(key, v)?;
        if v.iter().all(|&x| x >= 0.0) {
            Ok(())
        } else {
            self.fail(key, format!("`{key}` must not be negative, got {v:?}"))
        }
    }

    fn positive(&self, key: &str, v: f32) -> Check {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            self.fail(key, format!("`{key}` must be a positive number, got {v}"))
        }
    }

    fn non_zero(&self, key: &str, v: Vec3f) -> Check {
        self.finite(key, &v)?;
        if v.iter().any(|&x| x != 0.0) {
            Ok(())
        } else {
            self.fail(key, format!("`{key}` must be a non-zero vector"))
        }
    }

    fn one_of(&self, key: &str, value: &str, options: &[&str]) -> Check {
        if options.contains(&value) {
            Ok(())
        } else {
            self.fail(
                key,
                format!(
                    "unknown {key} `{value}`, expected one of: {}",
                    options.join(", ")
                ),
            )
        }
    }
}

pub fn validate(d: &Description) -> Result<(), Invalid> {
    let mut c = Checker { path: vec![] };
    c.at(key("camera"), |c| camera(c, d))?;
    c.at(key("render"), |c| render(c, d))?;
    c.at(key("environment"), |c| {
        c.non_negative("background", &d.environment.background)?;
        c.non_negative("ambient", &d.environment.ambient)
    })?;
    for (name, m) in &d.materials {
        c.at(key("materials"), |c| {
            c.at(key(name), |c| material(c, d, name, m))
        })?;
    }
    for (name, m) in &d.media {
        c.at(key("media"), |c| c.at(key(name), |c| medium(c, m)))?;
    }
    if let Some(m) = &d.camera.medium {
        c.at(key("camera"), |c| {
            known_name(c, "medium", "medium", m, d.media.keys())
        })?;
    }
    for (i, s) in d.shapes.iter().enumerate() {
        c.at(key("shape"), |c| {
            c.at(PathSeg::Index(i), |c| shape(c, d, s))
        })?;
    }
    if let Some(a) = &d.animation {
        c.at(key("animation"), |c| {
            if !(1..=MAX_FRAMES).contains(&a.frames) {
                return c.fail(
                    "frames",
                    format!(
                        "`frames` must be between 1 and {MAX_FRAMES}, got {}",
                        a.frames
                    ),
                );
            }
            c.positive("fps", a.fps)
        })?;
    }
    for (name, m) in &d.meshes {
        c.at(key("meshes"), |c| {
            c.at(key(name), |c| {
                if m.file.is_empty() == m.triangles.is_empty() {
                    return c.fail(
                        "file",
                        "give `file` (a mesh file) or `triangles`, one of them",
                    );
                }
                for (i, t) in m.triangles.iter().enumerate() {
                    c.at(key("triangles"), |c| {
                        c.at(PathSeg::Index(i), |c| {
                            if t.emitter.is_some() {
                                return c.fail("emitter", "an instanced mesh cannot emit");
                            }
                            shape(c, d, &ShapeDesc::TriangleMesh(t.clone()))
                        })
                    })?;
                }
                file_pattern(c, d, &m.file)?;
                material_name(c, d, m.material.as_deref())
            })
        })?;
    }
    for (i, inst) in d.instances.iter().enumerate() {
        c.at(key("instance"), |c| {
            c.at(PathSeg::Index(i), |c| instance(c, d, inst))
        })?;
    }
    for (i, l) in d.lights.iter().enumerate() {
        c.at(key("light"), |c| c.at(PathSeg::Index(i), |c| light(c, l)))?;
    }
    Ok(())
}

fn medium(c: &mut Checker, m: &super::MediumDesc) -> Check {
    if let Err(e) = m.check() {
        return param_failure(c, e);
    }
    let volumes = match m {
        super::MediumDesc::Homogeneous(h) => h.albedo.iter().map(|a| ("albedo", a)).collect(),
        super::MediumDesc::Heterogeneous(h) => h.volumes().collect::<Vec<_>>(),
    };
    for (k, v) in volumes {
        if let Some(t) = v.transform() {
            c.at(key(k), |c| c.at(key("transform"), |c| transform(c, t)))?;
        }
    }
    Ok(())
}

fn light(c: &mut Checker, l: &LightDesc) -> Check {
    if let Err(e) = l.check() {
        return param_failure(c, e);
    }
    if let Some(t) = l.transform() {
        c.at(key("transform"), |c| transform(c, t))?;
    }
    Ok(())
}

/// A plugin's [`ParamError`] at its key, whose dots name nested tables.
fn param_failure(c: &mut Checker, e: ParamError) -> Check {
    match e.key.rsplit_once('.') {
        Some((table, key)) => {
            let mut segments = table
                .split('.')
                .map(|k| PathSeg::Key(k.into()))
                .collect::<Vec<_>>();
            let depth = segments.len();
            c.path.append(&mut segments);
            let failure = c.fail(key, e.message);
            c.path.truncate(c.path.len() - depth);
            failure
        }
        None => c.fail(e.key, e.message),
    }
}

fn material(c: &mut Checker, d: &Description, name: &str, m: &MaterialDesc) -> Check {
    for (k, t) in m.textures() {
        texture(c, k, t)?;
    }
    for (k, ior) in m.iors() {
        index_of_refraction(c, k, ior)?;
    }
    if let Err(e) = m.check_bsdf() {
        return param_failure(c, e);
    }
    for (k, r) in match m {
        MaterialDesc::TwoSided(t) => vec![("front", Some(&t.front)), ("back", t.back.as_ref())],
        MaterialDesc::Mask(mask) => vec![("material", Some(&mask.material))],
        MaterialDesc::NormalMap(x) => vec![("material", Some(&x.material))],
        MaterialDesc::BumpMap(x) => vec![("material", Some(&x.material))],
        MaterialDesc::Blend(x) => vec![
            ("materials", Some(&x.materials[0])),
            ("materials", Some(&x.materials[1])),
        ],
        _ => vec![],
    } {
        let Some(r) = r else { continue };
        known_name(c, k, "material", r, d.materials.keys())?;
        if r == name {
            return c.fail(k, format!("material `{name}` cannot wrap itself"));
        }
    }
    if let MaterialDesc::Blend(x) = m {
        for r in &x.materials {
            if d.materials
                .get(r)
                .is_some_and(|inner| !inner.references().is_empty())
            {
                return c.fail(
                    "materials",
                    format!("a blend mixes plain materials; `{r}` wraps others"),
                );
            }
        }
    }
    // Wrapping chains end: a material reaches no material twice.
    let is_map =
        |m: &MaterialDesc| matches!(m, MaterialDesc::NormalMap(_) | MaterialDesc::BumpMap(_));
    let mut seen = vec![name];
    let mut frontier = m.references();
    while let Some(next) = frontier.pop() {
        if seen.contains(&next) {
            return c.fail(
                "",
                format!("material `{name}` wraps itself through `{next}`"),
            );
        }
        seen.push(next);
        if let Some(inner) = d.materials.get(next) {
            // One perturbed frame per surface: the material layer composes one.
            if is_map(m) && is_map(inner) {
                return c.fail(
                    "material",
                    format!(
                        "normal and bump maps cannot wrap one another (`{name}` wraps `{next}`)"
                    ),
                );
            }
            frontier.extend(inner.references());
        }
    }
    Ok(())
}

/// A positive number, or a name Appel has an index of refraction for.
fn index_of_refraction(c: &Checker, k: &str, ior: &IorDesc) -> Check {
    match ior {
        IorDesc::Value(v) if v.is_finite() && *v > 0.0 => Ok(()),
        IorDesc::Value(v) => c.fail(
            k,
            format!("`{k}`, an index of refraction, must be positive, got {v}"),
        ),
        IorDesc::Named(n) if spectra::ior(n).is_some() => Ok(()),
        IorDesc::Named(n) => c.fail(
            k,
            format!(
                "unknown index of refraction `{n}`, expected a number or one of: {}",
                spectra::IOR_NAMES.join(", ")
            ),
        ),
    }
}

/// The texture at key `k`: a number or colour not negative, or a texture node that makes sense.
fn texture(c: &mut Checker, k: &str, t: &TextureDesc) -> Check {
    match t {
        TextureDesc::Value(v) => c.non_negative(k, &[*v]),
        TextureDesc::Rgb(v) => c.non_negative(k, v),
        TextureDesc::Texture(node) => c.at(key(k), |c| texture_node(c, node)),
    }
}

fn texture_node(c: &mut Checker, t: &TextureNode) -> Check {
    match t {
        TextureNode::Bitmap { file, to_uv, .. } => {
            if file.is_empty() {
                return c.fail("file", "`file` must name an image file");
            }
            if let Some(m) = to_uv {
                c.finite("to_uv", m.as_flattened())?;
            }
            Ok(())
        }
        TextureNode::MeshAttribute { name } => {
            if name.is_empty() {
                return c.fail("name", "`name` must name a mesh attribute");
            }
            Ok(())
        }
        TextureNode::Checkerboard {
            color0,
            color1,
            to_uv,
        } => {
            c.non_negative("color0", color0)?;
            c.non_negative("color1", color1)?;
            if let Some(m) = to_uv {
                c.finite("to_uv", m.as_flattened())?;
            }
            Ok(())
        }
    }
}

fn key(k: &str) -> PathSeg {
    PathSeg::Key(k.to_string())
}

fn camera(c: &mut Checker, d: &Description) -> Check {
    let cam = &d.camera;
    c.finite("eye", &cam.eye)?;
    c.finite("look_at", &cam.look_at)?;
    c.non_zero("up", cam.up)?;
    let eye = glam::Vec3::from(cam.eye);
    let forward = glam::Vec3::from(cam.look_at) - eye;
    if forward.length_squared() == 0.0 || !forward.is_finite() {
        return c.fail("look_at", "`look_at` must differ from `eye`");
    }
    let up = glam::Vec3::from(cam.up);
    let sine = forward.normalize().cross(up.normalize()).length();
    // Also catches NaN.
    if sine.is_nan() || sine <= 1e-6 {
        return c.fail(
            "up",
            "`up` is parallel to the viewing direction (look_at - eye): the camera's roll is undefined",
        );
    }
    if !(cam.fov > 0.0 && cam.fov < 180.0) {
        return c.fail(
            "fov",
            format!(
                "`fov` is the vertical field of view in degrees and must lie in (0, 180), got {}",
                cam.fov
            ),
        );
    }
    if !(cam.aperture_radius >= 0.0 && cam.aperture_radius.is_finite()) {
        return c.fail(
            "aperture_radius",
            format!(
                "`aperture_radius` must be 0 (a pinhole) or a positive number of scene units, got {}",
                cam.aperture_radius
            ),
        );
    }
    if let Some(f) = cam.focus_distance {
        if !(f > 0.0 && f.is_finite()) {
            return c.fail(
                "focus_distance",
                format!("`focus_distance` must be a positive distance, got {f}"),
            );
        }
    }
    for (k, v) in [("width", cam.width), ("height", cam.height)] {
        if v == 0 || v > MAX_DIMENSION {
            return c.fail(
                k,
                format!("`{k}` must be between 1 and {MAX_DIMENSION} pixels, got {v}"),
            );
        }
    }
    let pixels = cam.width as u64 * cam.height as u64;
    if pixels > MAX_PIXELS {
        return c.fail(
            "width",
            format!(
                "{} x {} is {pixels} pixels, which needs about {:.1} GB of film; the limit is {MAX_PIXELS} pixels",
                cam.width,
                cam.height,
                pixels as f64 * 40.0 / 1e9
            ),
        );
    }
    Ok(())
}

fn render(c: &mut Checker, d: &Description) -> Check {
    let r = &d.render;
    if AccelKind::from_name(&r.accel).is_none() {
        c.one_of("accel", &r.accel, AccelKind::NAMES)?;
    }
    c.one_of("triangle", &r.triangle, TRIANGLE_TESTS)?;
    let min_depth = if r.integrator.is_monte_carlo() { -1 } else { 0 };
    if !(min_depth..=MAX_DEPTH).contains(&r.max_depth) {
        return c.fail(
            "max_depth",
            format!(
                "`max_depth` must be between {min_depth} and {MAX_DEPTH}{}, got {}",
                if min_depth < 0 {
                    " (-1: unlimited)"
                } else {
                    ""
                },
                r.max_depth
            ),
        );
    }
    match r.filter {
        super::FilterDesc::Box { radius } | super::FilterDesc::Tent { radius } => {
            c.at(key("filter"), |c| c.positive("radius", radius))?
        }
        super::FilterDesc::Gaussian { stddev } => {
            c.at(key("filter"), |c| c.positive("stddev", stddev))?
        }
    }
    if r.spp == 0 || r.spp > MAX_SPP {
        return c.fail(
            "spp",
            format!("`spp` must be between 1 and {MAX_SPP}, got {}", r.spp),
        );
    }
    if let Err((table, bad)) = r.check_accel_options() {
        return c.at(key(table), |c| c.fail(bad.key, bad.message));
    }
    if let Err((table, k, message)) = r.check_integrator_params() {
        return c.at(key(table), |c| c.fail(k, message));
    }
    Ok(())
}

/// `name` must be a key of `names`; the message lists the keys.
fn known_name<'a>(
    c: &Checker,
    k: &str,
    what: &str,
    name: &str,
    mut names: impl Iterator<Item = &'a String>,
) -> Check {
    let known: Vec<&str> = names.by_ref().map(|k| k.as_str()).collect();
    if known.contains(&name) {
        return Ok(());
    }
    c.fail(
        k,
        format!(
            "unknown {what} `{name}`; the scene defines: {}",
            if known.is_empty() {
                "none".to_string()
            } else {
                known.join(", ")
            }
        ),
    )
}

fn material_name(c: &Checker, d: &Description, m: Option<&str>) -> Check {
    match m {
        Some(m) => known_name(c, "material", "material", m, d.materials.keys()),
        None => Ok(()),
    }
}

fn instance(c: &mut Checker, d: &Description, i: &InstanceDesc) -> Check {
    known_name(c, "mesh", "mesh", &i.mesh, d.meshes.keys())?;
    if !i.keyframes.is_empty() && i.placements.is_some() {
        return c.fail(
            "keyframes",
            "an instance takes `keyframes` or `placements`, not both",
        );
    }
    keyframes(c, &i.keyframes, &i.transform)?;
    if let Some(t) = &i.transform {
        if i.placements.is_some() {
            return c.fail(
                "placements",
                "an instance takes `transform` or `placements`, not both",
            );
        }
        c.at(key("transform"), |c| transform(c, t))?;
    }
    if i.placements.as_deref() == Some("") {
        return c.fail("placements", "`placements` must name a placement list file");
    }
    Ok(())
}

fn shape(c: &mut Checker, d: &Description, s: &ShapeDesc) -> Check {
    material_name(c, d, s.material())?;
    let (interior, exterior) = s.media();
    for (k, m) in [("interior", interior), ("exterior", exterior)] {
        if let Some(m) = m {
            known_name(c, k, "medium", m, d.media.keys())?;
        }
    }
    let placed = |c: &mut Checker, t: &Option<TransformDesc>| match t {
        Some(t) => c.at(key("transform"), |c| transform(c, t)),
        None => Ok(()),
    };
    match s {
        ShapeDesc::Sphere(s) => {
            c.finite("center", &s.center)?;
            c.positive("radius", s.radius)?;
            if let Some(rows) = &s.mitsuba_uv {
                c.finite("mitsuba_uv", rows.as_flattened())?;
                for r in rows {
                    c.non_zero("mitsuba_uv", *r)?;
                }
            }
        }
        ShapeDesc::Plane(p) => {
            c.finite("point", &p.point)?;
            c.non_zero("normal", p.normal)?;
            if let Some(size) = p.size {
                c.positive("size", size[0])?;
                c.positive("size", size[1])?;
            }
        }
        ShapeDesc::Triangle(t) => c.finite("vertices", t.vertices.as_flattened())?,
        ShapeDesc::Implicit(i) => {
            let b = i.bounds;
            c.finite("bounds", b.as_flattened())?;
            if (0..3).any(|k| b[0][k] >= b[1][k]) {
                return c.fail(
                    "bounds",
                    format!(
                        "`bounds` is [[xmin, ymin, zmin], [xmax, ymax, zmax]] with each min below its max, got {b:?}"
                    ),
                );
            }
            if let Err(e) = crate::geometry::implicit::parse::parse(&i.f) {
                return c.fail("f", format!("in the formula `{}`, {e}", i.f));
            }
            placed(c, &i.transform)?;
        }
        ShapeDesc::Torus(t) => {
            c.finite("center", &t.center)?;
            c.positive("major_radius", t.major_radius)?;
            c.positive("minor_radius", t.minor_radius)?;
            if let Some(a) = t.axis {
                c.non_zero("axis", a)?;
            }
        }
        ShapeDesc::Mesh(m) => {
            if m.file.is_empty() {
                return c.fail("file", "`file` must name a mesh file");
            }
            file_pattern(c, d, &m.file)?;
            if m.face_normals && m.smooth_normals {
                return c.fail(
                    "smooth_normals",
                    "`smooth_normals` and `face_normals` contradict each other: choose one",
                );
            }
            placed(c, &m.transform)?;
            keyframes(c, &m.keyframes, &m.transform)?;
        }
        ShapeDesc::Rectangle(b) | ShapeDesc::Cube(b) | ShapeDesc::Disk(b) => {
            placed(c, &b.transform)?;
            keyframes(c, &b.keyframes, &b.transform)?;
        }
        ShapeDesc::Cylinder(cy) => {
            c.finite("p0", &cy.p0)?;
            c.finite("p1", &cy.p1)?;
            c.positive("radius", cy.radius)?;
            if cy.p0 == cy.p1 {
                return c.fail(
                    "p1",
                    "`p1` must differ from `p0`: the cylinder has no length",
                );
            }
            placed(c, &cy.transform)?
        }
        ShapeDesc::SdfGrid(g) => {
            if g.file.is_empty() {
                return c.fail("file", "`file` must name a grid volume (.vol)");
            }
            placed(c, &g.transform)?
        }
        ShapeDesc::TriangleMesh(m) => {
            // Named by index rather than printed whole: the arrays may be long.
            let all_finite =
                |key: &str, v: &[f32], per: usize| match v.iter().position(|x| !x.is_finite()) {
                    Some(i) => c.fail(key, format!("`{key}[{}]` is not finite", i / per)),
                    None => Ok(()),
                };
            all_finite("positions", m.positions.as_flattened(), 3)?;
            let n = m.positions.len();
            if let Some(bad) = m.indices.iter().flatten().find(|&&i| i as usize >= n) {
                return c.fail(
                    "indices",
                    format!("index {bad} is out of range: the mesh has {n} positions"),
                );
            }
            if let Some(normals) = &m.normals {
                all_finite("normals", normals.as_flattened(), 3)?;
                if normals.len() != n {
                    return c.fail(
                        "normals",
                        format!("{} normals for {n} positions", normals.len()),
                    );
                }
            }
            if let Some(uvs) = &m.uvs {
                all_finite("uvs", uvs.as_flattened(), 2)?;
                if uvs.len() != n {
                    return c.fail("uvs", format!("{} uvs for {n} positions", uvs.len()));
                }
            }
            placed(c, &m.transform)?;
        }
    }
    if let Some(e) = s.emitter() {
        c.at(key("emitter"), |c| texture(c, "radiance", &e.radiance))?;
    }
    Ok(())
}

/// The most frames `[animation]` may have.
pub const MAX_FRAMES: u32 = 1_000_000;

/// Keys in increasing time, each a valid transform, instead of (not beside) `transform`.
fn keyframes(c: &mut Checker, keys: &[KeyframeDesc], fixed: &Option<TransformDesc>) -> Check {
    if keys.is_empty() {
        return Ok(());
    }
    if fixed.is_some() {
        return c.fail("keyframes", "give `transform` or `keyframes`, not both");
    }
    c.at(key("keyframes"), |c| {
        for (i, k) in keys.iter().enumerate() {
            c.at(PathSeg::Index(i), |c| {
                c.finite("time", &[k.time])?;
                if i > 0 && k.time <= keys[i - 1].time {
                    return c.fail(
                        "time",
                        format!(
                            "keyframe times must increase, but {} follows {}",
                            k.time,
                            keys[i - 1].time
                        ),
                    );
                }
                c.at(key("transform"), |c| transform(c, &k.transform))
            })?;
        }
        Ok(())
    })
}

/// A file name with `{frame...}` fields needs `[animation]`, and well-formed fields.
fn file_pattern(c: &mut Checker, d: &Description, file: &str) -> Check {
    if !super::animation::is_pattern(file) {
        return Ok(());
    }
    if d.animation.is_none() {
        return c.fail(
            "file",
            "a file name with `{frame}` needs an `[animation]` table saying how many frames",
        );
    }
    super::animation::check_pattern(file).or_else(|m| c.fail("file", m))
}

fn transform(c: &mut Checker, t: &TransformDesc) -> Check {
    if let Some(m) = &t.matrix {
        if t.translate.is_some() || t.rotate.is_some() || t.scale.is_some() {
            return c.fail(
                "matrix",
                "a transform is a `matrix` or translate/rotate/scale, not both",
            );
        }
        c.finite("matrix", m.as_flattened())?;
        if m[3] != [0.0, 0.0, 0.0, 1.0] {
            return c.fail(
                "matrix",
                "the matrix's last row must be [0, 0, 0, 1] (no projective transforms)",
            );
        }
    }
    if let Some(tr) = t.translate {
        c.finite("translate", &tr)?;
    }
    if let Some(r) = &t.rotate {
        c.at(key("rotate"), |c| {
            c.non_zero("axis", r.axis)?;
            c.finite("degrees", &[r.degrees])
        })?;
    }
    if let Some(sc) = t.scale {
        let axes = sc.axes();
        c.finite("scale", &axes)?;
        if axes.contains(&0.0) {
            return c.fail(
                "scale",
                "`scale` must not be zero: it would flatten the mesh",
            );
        }
    }
    // Finite pieces can still make a matrix f32 cannot invert (a scale of 1e-30).
    if crate::geometry::InstanceTransform::new(t.matrix()).is_none() {
        return c.fail(
            "",
            "the transform is not invertible in single precision (a scale too small or too large)",
        );
    }
    Ok(())
}

/// Checks that every mesh and placement file the description names exists, relative to `base_dir`.
pub fn files(d: &Description, base_dir: &std::path::Path) -> Result<(), Invalid> {
    // A file name per frame: every frame's file must be there.
    if super::animation::is_animated(d) {
        for frame in 0..super::animation::frame_count(d) {
            files(&super::animation::at_frame(d, frame), base_dir)?;
        }
        return Ok(());
    }
    let exists = |f: &str, what: &str, path: Vec<PathSeg>| {
        let p = base_dir.join(f);
        if p.is_file() || (what == "mesh file" && super::archive_path::mesh_source_exists(&p)) {
            Ok(())
        } else {
            Err(Invalid {
                path,
                message: format!("the {what} `{}` does not exist", p.display()),
            })
        }
    };
    for (name, m) in d.meshes.iter().filter(|(_, m)| !m.file.is_empty()) {
        exists(
            &m.file,
            "mesh file",
            vec![key("meshes"), key(name), key("file")],
        )?;
    }
    for (i, inst) in d.instances.iter().enumerate() {
        if let Some(f) = &inst.placements {
            let path = vec![key("instance"), PathSeg::Index(i), key("placements")];
            exists(f, "placement list", path)?;
        }
    }
    for (i, s) in d.shapes.iter().enumerate() {
        if let ShapeDesc::SdfGrid(g) = s {
            exists(
                &g.file,
                "grid volume",
                vec![key("shape"), PathSeg::Index(i), key("file")],
            )?;
        }
        if let ShapeDesc::Mesh(m) = s {
            let p = base_dir.join(&m.file);
            if !super::archive_path::mesh_source_exists(&p) {
                return Err(Invalid {
                    path: vec![key("shape"), PathSeg::Index(i), key("file")],
                    message: format!("the mesh file `{}` does not exist", p.display()),
                });
            }
        }
    }
    Ok(())
}
