//! Wavefront OBJ with MTL materials.
//!
//! Hand-written rather than `tobj`: tobj fan-triangulates polygons (wrong for concave ones, which
//! must be ear-clipped in the polygon's plane), reports errors without line numbers, and turns
//! non-UTF-8 input into a bare I/O error. OBJ is small enough that a direct reader is clearer.
//!
//! Read: `v` (x y z; a `w` or vertex colours after them are ignored), `vn`, `vt` (u [v]), `f` with
//! `v`, `v/vt`, `v//vn`, `v/vt/vn` references (1-based; negative ones count back from the last
//! vertex defined so far), `usemtl`, `mtllib`. `g`, `o`, `s`, `l`, `p` and unknown statements are
//! ignored (groups and objects do not split the mesh). Triangles are grouped into one part per
//! material, in the order materials first appear; `primid` is the triangle's index inside its part,
//! in file order. A `mtllib` that cannot be found is ignored (its materials fall back to the scene's
//! default), since OBJ files are often shared without their MTL.

use super::assets::Assets;
use crate::description::loaded_mesh::{
    AlphaMode, FileImage, FileMaterial, FileTexture, LoadedMesh, MeshPart,
};
use crate::description::texture_lookup::{Filter, Wrap};
use crate::error::{Error, Location, Result};
use crate::geometry::TriangleMesh;
use crate::math::{Vec2, Vec3};
use glam::Mat3;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where MTL files and textures come from: the file system next to the OBJ, a zip archive, or
/// nowhere (tests, fuzzing).
pub trait MtlSource {
    /// The MTL file `name` referenced by `obj`, with the path to name in errors, or `None` if absent.
    fn read(&self, obj: &Path, name: &str) -> Option<(PathBuf, Vec<u8>)>;

    /// The texture `name` an MTL file of `obj` refers to: its path for messages, and its bytes or
    /// why they cannot be read.
    fn texture(&self, obj: &Path, name: &str) -> (PathBuf, std::result::Result<Vec<u8>, String>) {
        let path = obj.parent().unwrap_or(Path::new(".")).join(name);
        (path, Err(format!("`{name}` cannot be read here")))
    }
}

impl MtlSource for Assets {
    fn read(&self, _: &Path, name: &str) -> Option<(PathBuf, Vec<u8>)> {
        Assets::read(self, name).ok().map(|b| (self.name(name), b))
    }

    fn texture(&self, _: &Path, name: &str) -> (PathBuf, std::result::Result<Vec<u8>, String>) {
        (self.name(name), Assets::read(self, name))
    }
}

/// Reads MTL files relative to the OBJ file's folder.
pub struct FsMtl;

impl MtlSource for FsMtl {
    fn read(&self, obj: &Path, name: &str) -> Option<(PathBuf, Vec<u8>)> {
        let path = obj.parent().unwrap_or(Path::new(".")).join(name);
        std::fs::read(&path).ok().map(|b| (path, b))
    }

    fn texture(&self, obj: &Path, name: &str) -> (PathBuf, std::result::Result<Vec<u8>, String>) {
        Assets::beside(obj).texture(obj, name)
    }
}

/// No MTL files at all.
pub struct NoMtl;

impl MtlSource for NoMtl {
    fn read(&self, _: &Path, _: &str) -> Option<(PathBuf, Vec<u8>)> {
        None
    }
}

/// Above this many vertices a polygon is fan-triangulated: ear clipping costs O(n^3) in the worst
/// case, and real polygons are far smaller; the cap keeps hostile input from taking hours.
const MAX_EAR_CLIP: usize = 1024;

const NONE: u32 = u32::MAX;

#[derive(Default)]
struct PartBuilder {
    material: Option<u32>,
    /// Index in the file's triangle order of each triangle of the part.
    file_triangles: Vec<u32>,
    /// (position, uv, normal) indices of the file -> vertex of this part.
    map: HashMap<[u32; 3], u32>,
    mesh: TriangleMesh,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    all_normals: bool,
    all_uvs: bool,
}

impl PartBuilder {
    fn vertex(&mut self, key: [u32; 3], v: &[Vec3], vt: &[Vec2], vn: &[Vec3]) -> u32 {
        if let Some(&i) = self.map.get(&key) {
            return i;
        }
        let i = self.mesh.positions.len() as u32;
        self.mesh.positions.push(v[key[0] as usize]);
        match key[1] {
            NONE => {
                self.all_uvs = false;
                self.uvs.push(Vec2::ZERO);
            }
            t => self.uvs.push(vt[t as usize]),
        }
        match key[2] {
            NONE => {
                self.all_normals = false;
                self.normals.push(Vec3::ZERO);
            }
            n => self.normals.push(vn[n as usize]),
        }
        self.map.insert(key, i);
        i
    }
}

fn line_error(path: &Path, line: usize, msg: impl Into<String>) -> Error {
    Error::input(Location::line(path, line, None), msg)
}

/// The lines of a text file with 1-based numbers, comments removed; a line that is not UTF-8 is
/// an error naming it.
fn text_lines<'a>(
    data: &'a [u8],
    path: &'a Path,
) -> impl Iterator<Item = Result<(usize, &'a str)>> + 'a {
    data.split(|&b| b == b'\n')
        .enumerate()
        .map(move |(i, raw)| {
            let line = std::str::from_utf8(raw).map_err(|e| {
                line_error(
                    path,
                    i + 1,
                    format!(
                        "this line is not valid UTF-8 text (bad byte at column {})",
                        e.valid_up_to() + 1
                    ),
                )
            })?;
            let line = line.split('#').next().unwrap_or("").trim();
            Ok((i + 1, line))
        })
}

fn numbers<const N: usize>(
    words: &[&str],
    min: usize,
    path: &Path,
    line: usize,
    what: &str,
) -> Result<[f32; N]> {
    if words.len() < min {
        return Err(line_error(
            path,
            line,
            format!("`{what}` needs at least {min} numbers, got {}", words.len()),
        ));
    }
    let mut out = [0f32; N];
    for (o, w) in out.iter_mut().zip(words) {
        *o = w
            .parse::<f32>()
            .map_err(|_| line_error(path, line, format!("`{w}` is not a number")))?;
        if !o.is_finite() {
            return Err(line_error(
                path,
                line,
                format!("`{what}` has a value that is not a finite number: `{w}`"),
            ));
        }
    }
    Ok(out)
}

pub fn parse_obj(data: &[u8], path: &Path, mtl: &dyn MtlSource) -> Result<LoadedMesh> {
    let mut v: Vec<Vec3> = vec![];
    let mut vt: Vec<Vec2> = vec![];
    let mut vn: Vec<Vec3> = vec![];
    let mut materials: Vec<FileMaterial> = vec![];
    let mut images: Vec<FileImage> = vec![];
    let mut image_ids: HashMap<PathBuf, u32> = HashMap::new();
    let mut material_ids: HashMap<String, u32> = HashMap::new();
    let mut parts: Vec<PartBuilder> = vec![];
    let mut part_of: HashMap<Option<u32>, usize> = HashMap::new();
    let mut current: Option<u32> = None;
    let mut face: Vec<[u32; 3]> = vec![];
    let mut corners: Vec<u32> = vec![];
    let mut tris: Vec<[usize; 3]> = vec![];
    let mut triangles_so_far = 0u32;
    for item in text_lines(data, path) {
        let (line, text) = item?;
        let mut words = text.split_ascii_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let args: Vec<&str> = words.collect();
        match keyword {
            "v" => v.push(numbers::<3>(&args, 3, path, line, "v")?.into()),
            "vn" => vn.push(numbers::<3>(&args, 3, path, line, "vn")?.into()),
            // OBJ's v grows upwards from the image's bottom row; Appel's textures (as Mitsuba's and
            // glTF's) put v = 0 at the top row, so v is flipped here, as Mitsuba's OBJ reader does.
            "vt" => {
                let [u, v] = numbers::<2>(&args, 1, path, line, "vt")?;
                vt.push(Vec2::new(u, 1.0 - v));
            }
            "f" => {
                if args.len() < 3 {
                    return Err(line_error(
                        path,
                        line,
                        format!("a face needs at least 3 vertices, got {}", args.len()),
                    ));
                }
                face.clear();
                for a in &args {
                    face.push(parse_ref(a, [v.len(), vt.len(), vn.len()], path, line)?);
                }
                let pi = *part_of.entry(current).or_insert_with(|| {
                    parts.push(PartBuilder {
                        material: current,
                        all_normals: true,
                        all_uvs: true,
                        ..Default::default()
                    });
                    parts.len() - 1
                });
                let part = &mut parts[pi];
                if part.mesh.positions.len() + face.len() > u32::MAX as usize - 1 {
                    return Err(line_error(
                        path,
                        line,
                        "more than 2^32 - 2 vertices in one mesh",
                    ));
                }
                corners.clear();
                for &key in &face {
                    corners.push(part.vertex(key, &v, &vt, &vn));
                }
                let points: Vec<Vec3> = face.iter().map(|k| v[k[0] as usize]).collect();
                tris.clear();
                triangulate(&points, &mut tris);
                part.mesh
                    .indices
                    .extend(tris.iter().map(|t| t.map(|k| corners[k])));
                let n = tris.len() as u32;
                part.file_triangles
                    .extend(triangles_so_far..triangles_so_far + n);
                triangles_so_far += n;
            }
            "usemtl" => {
                let name = args.join(" ");
                current = material_ids.get(&name).copied();
            }
            "mtllib" => {
                for name in &args {
                    if let Some((mtl_path, bytes)) = mtl.read(path, name) {
                        let (mut found, maps) = parse_mtl_with_maps(&bytes, &mtl_path)?;
                        // The MTL's image names -> the file's images, each read once.
                        let ids: Vec<u32> = maps
                            .iter()
                            .map(|m| {
                                let (name, bytes) = mtl.texture(path, m);
                                *image_ids.entry(name.clone()).or_insert_with(|| {
                                    images.push(FileImage {
                                        name,
                                        bytes: bytes.map(Arc::new),
                                    });
                                    images.len() as u32 - 1
                                })
                            })
                            .collect();
                        for m in &mut found {
                            for t in [
                                &mut m.diffuse_map,
                                &mut m.specular_map,
                                &mut m.shininess_map,
                                &mut m.opacity_map,
                            ]
                            .into_iter()
                            .flatten()
                            .chain(m.normal_map.as_mut().map(|t| &mut t.0))
                            .chain(m.bump_map.as_mut().map(|t| &mut t.0))
                            {
                                t.image = ids[t.image as usize];
                            }
                        }
                        for m in found {
                            material_ids.insert(m.name.clone(), materials.len() as u32);
                            materials.push(m);
                        }
                    }
                }
            }
            _ => {}
        }
    }
    let single = parts.len() == 1;
    let parts = parts
        .into_iter()
        .map(|mut p| {
            p.mesh.normals = p.all_normals.then_some(p.normals);
            p.mesh.uvs = p.all_uvs.then_some(p.uvs);
            MeshPart {
                mesh: p.mesh,
                material: p.material,
                file_triangles: (!single).then_some(p.file_triangles),
                tangents: None,
            }
        })
        .collect();
    let warnings = crate::description::loaded_mesh::unreadable_images(&images);
    Ok(LoadedMesh {
        parts,
        materials,
        images,
        warnings,
        ..Default::default()
    })
}

/// `v`, `v/vt`, `v//vn` or `v/vt/vn` -> 0-based indices (`NONE` where absent).
fn parse_ref(word: &str, counts: [usize; 3], path: &Path, line: usize) -> Result<[u32; 3]> {
    let mut out = [NONE; 3];
    let names = ["vertex", "texture coordinate", "normal"];
    let fields: Vec<&str> = word.split('/').collect();
    if fields.len() > 3 || fields[0].is_empty() {
        return Err(line_error(
            path,
            line,
            format!("`{word}` is not a face vertex: expected v, v/vt, v//vn or v/vt/vn"),
        ));
    }
    for (k, f) in fields.iter().enumerate() {
        if f.is_empty() {
            continue;
        }
        let i: i64 = f.parse().map_err(|_| {
            line_error(
                path,
                line,
                format!("`{f}` in `{word}` is not an integer index"),
            )
        })?;
        let n = counts[k] as i64;
        let resolved = if i > 0 { i - 1 } else { n + i };
        if i == 0 || resolved < 0 || resolved >= n {
            return Err(line_error(
                path,
                line,
                format!(
                    "{} index {i} in `{word}` is out of range: {n} {}s are defined before this line",
                    names[k], names[k]
                ),
            ));
        }
        out[k] = resolved as u32;
    }
    Ok(out)
}

/// Triangulates a planar polygon given by its corner positions into `out` (corner indices, in the
/// polygon's winding). Ear clipping (Meisters 1975) in the plane of the polygon's Newell normal, so a
/// concave polygon yields only triangles inside it. Falls back to a fan for degenerate or
/// self-intersecting polygons where no ear is found, and above [`MAX_EAR_CLIP`] corners.
pub fn triangulate(points: &[Vec3], out: &mut Vec<[usize; 3]>) {
    let n = points.len();
    if n < 3 {
        return;
    }
    let fan = |from: &[usize], out: &mut Vec<[usize; 3]>| {
        for k in 1..from.len() - 1 {
            out.push([from[0], from[k], from[k + 1]]);
        }
    };
    let all: Vec<usize> = (0..n).collect();
    if n == 3 || n > MAX_EAR_CLIP {
        fan(&all, out);
        return;
    }
    // Newell's method: robust normal of a possibly non-convex, slightly non-planar polygon.
    let mut normal = Vec3::ZERO;
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        normal += Vec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    let an = normal.abs();
    if an.max_element().is_nan() || an.max_element() <= 0.0 {
        fan(&all, out);
        return;
    }
    // Project by dropping the normal's dominant axis; choose the remaining axes so the polygon is
    // counter-clockwise in 2D.
    let (ax, ay) = if an.x >= an.y && an.x >= an.z {
        if normal.x > 0.0 {
            (1, 2)
        } else {
            (2, 1)
        }
    } else if an.y >= an.z {
        if normal.y > 0.0 {
            (2, 0)
        } else {
            (0, 2)
        }
    } else if normal.z > 0.0 {
        (0, 1)
    } else {
        (1, 0)
    };
    let p2: Vec<Vec2> = points.iter().map(|p| Vec2::new(p[ax], p[ay])).collect();
    let cross = |o: Vec2, a: Vec2, b: Vec2| (a - o).perp_dot(b - o);
    let mut ring = all;
    while ring.len() > 3 {
        let m = ring.len();
        let mut clipped = false;
        // The search starts at the ring's second corner, so that a convex polygon is clipped
        // into the fan from its first corner, `(0, k, k + 1)`: a quad's two halves are then
        // `(p0, p1, p2)` and `(p0, p2, p3)`, the pair the wide BVH stores as one quad.
        for i in (1..m).chain([0]) {
            let (ip, ic, inx) = (ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]);
            let (a, b, c) = (p2[ip], p2[ic], p2[inx]);
            if cross(a, b, c).is_nan() || cross(a, b, c) <= 0.0 {
                continue; // reflex or degenerate corner: not an ear
            }
            let blocked = ring.iter().any(|&j| {
                if j == ip || j == ic || j == inx {
                    return false;
                }
                let p = p2[j];
                if p == a || p == b || p == c {
                    return false;
                }
                cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0
            });
            if !blocked {
                out.push([ip, ic, inx]);
                ring.remove(i);
                clipped = true;
                break;
            }
        }
        if !clipped {
            fan(&ring, out);
            return;
        }
    }
    out.push([ring[0], ring[1], ring[2]]);
}

/// MTL: `newmtl`, `Kd`, `Ks`, `Ns`, `Ni`, `d` (and `Tr = 1 - d`); other statements are ignored.
/// Texture maps are read by [`parse_mtl_with_maps`].
pub fn parse_mtl(data: &[u8], path: &Path) -> Result<Vec<FileMaterial>> {
    parse_mtl_with_maps(data, path).map(|(m, _)| m)
}

/// [`parse_mtl`], with `map_Kd`, `map_Ks`, `map_Ns`, `map_d`, `bump`/`map_bump` and `norm`: their
/// [`FileTexture::image`] index the returned list of image names (as written, relative to the
/// MTL's folder). Options `-o` and `-s` (uv offset and scale), `-clamp` and `-bm` (bump strength)
/// are read; the others are skipped with their values.
pub fn parse_mtl_with_maps(data: &[u8], path: &Path) -> Result<(Vec<FileMaterial>, Vec<String>)> {
    let mut out: Vec<FileMaterial> = vec![];
    let mut names: Vec<String> = vec![];
    for item in text_lines(data, path) {
        let (line, text) = item?;
        let mut words = text.split_ascii_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let args: Vec<&str> = words.collect();
        if keyword == "newmtl" {
            out.push(FileMaterial {
                name: args.join(" "),
                ..Default::default()
            });
            continue;
        }
        let known = [
            "Kd", "Ks", "Ns", "Ni", "d", "Tr", "map_Kd", "map_Ks", "map_Ns", "map_d", "bump",
            "map_bump", "map_Bump", "norm",
        ];
        if !known.contains(&keyword) {
            continue;
        }
        let Some(m) = out.last_mut() else {
            return Err(line_error(
                path,
                line,
                format!("`{keyword}` before any `newmtl`"),
            ));
        };
        if keyword.starts_with("map_") || keyword == "bump" || keyword == "norm" {
            let (file, texture, strength) = texture_statement(&args, path, line, keyword)?;
            let image = match names.iter().position(|n| *n == file) {
                Some(i) => i,
                None => {
                    names.push(file);
                    names.len() - 1
                }
            } as u32;
            let t = FileTexture { image, ..texture };
            match keyword {
                "map_Kd" => m.diffuse_map = Some(t),
                "map_Ks" => m.specular_map = Some(t),
                "map_Ns" => m.shininess_map = Some(t),
                "map_d" => {
                    m.opacity_map = Some(t);
                    m.alpha = AlphaMode::Blend;
                }
                "norm" => m.normal_map = Some((t, strength)),
                _ => m.bump_map = Some((t, strength)),
            }
            continue;
        }
        match keyword {
            "Kd" | "Ks" => {
                let c = numbers::<3>(&args, 1, path, line, keyword)?;
                // A single value means grey.
                let c = if args.len() < 3 { [c[0]; 3] } else { c };
                if keyword == "Kd" {
                    m.diffuse = c;
                } else {
                    m.specular = c;
                }
            }
            "Ns" => m.shininess = numbers::<1>(&args, 1, path, line, keyword)?[0].max(0.0),
            "Ni" => {
                let ior = numbers::<1>(&args, 1, path, line, keyword)?[0];
                // Ni 0 is common in exported files and means "unset".
                m.ior = if ior > 0.0 { ior } else { 1.5 };
            }
            "d" => m.opacity = numbers::<1>(&args, 1, path, line, keyword)?[0].clamp(0.0, 1.0),
            _ => m.opacity = 1.0 - numbers::<1>(&args, 1, path, line, keyword)?[0].clamp(0.0, 1.0),
        }
        if m.opacity < 1.0 {
            m.alpha = AlphaMode::Blend;
        }
    }
    Ok((out, names))
}

/// `map_Kd [options] file`: the file name (which may hold spaces), the lookup and the `-bm`
/// strength (1 by default).
fn texture_statement(
    args: &[&str],
    path: &Path,
    line: usize,
    keyword: &str,
) -> Result<(String, FileTexture, f32)> {
    let mut offset = [0.0f32; 2];
    let mut scale = [1.0f32; 2];
    let mut wrap = Wrap::Repeat;
    let mut strength = 1.0;
    let mut i = 0;
    let is_number = |w: &str| w.parse::<f32>().is_ok();
    while i < args.len() && args[i].starts_with('-') && args[i].len() > 1 && !is_number(args[i]) {
        let option = args[i];
        i += 1;
        // Up to three numbers for -o -s -t; one value for the rest; two for -mm.
        let values = match option {
            "-o" | "-s" | "-t" => {
                let mut n = 0;
                while n < 3 && i + n < args.len() - 1 && is_number(args[i + n]) {
                    n += 1;
                }
                n
            }
            "-mm" => 2,
            _ => 1,
        };
        if i + values > args.len() {
            return Err(line_error(
                path,
                line,
                format!("`{keyword}`: option `{option}` needs a value"),
            ));
        }
        let v = &args[i..i + values];
        let num = |k: usize| -> Result<f32> {
            let x = v.get(k).map_or(Ok(f32::NAN), |w| w.parse::<f32>());
            match x {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(line_error(
                    path,
                    line,
                    format!("`{keyword}`: option `{option}` needs a number"),
                )),
            }
        };
        match option {
            "-o" if values > 0 => {
                offset[0] = num(0)?;
                offset[1] = if values > 1 { num(1)? } else { 0.0 };
            }
            "-s" if values > 0 => {
                scale[0] = num(0)?;
                scale[1] = if values > 1 { num(1)? } else { 1.0 };
            }
            "-clamp" => {
                wrap = if v[0] == "on" {
                    Wrap::Clamp
                } else {
                    Wrap::Repeat
                }
            }
            "-bm" => strength = num(0)?,
            _ => {}
        }
        i += values;
    }
    if i >= args.len() {
        return Err(line_error(
            path,
            line,
            format!("`{keyword}` needs a file name"),
        ));
    }
    // -o and -s act on OBJ's uv, whose v this reader flips (v' = 1 - v): in flipped coordinates
    // u -> s_u u + o_u and v' -> s_v v' + (1 - s_v - o_v).
    let to_uv = Mat3::from_cols_array_2d(&[
        [scale[0], 0.0, 0.0],
        [0.0, scale[1], 0.0],
        [offset[0], 1.0 - scale[1] - offset[1], 1.0],
    ]);
    let texture = FileTexture {
        image: 0,
        uv_set: 0,
        wrap,
        filter: Filter::Bilinear,
        to_uv,
    };
    Ok((args[i..].join(" "), texture, strength))
}
