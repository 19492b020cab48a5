//! PLY (Turk 1994, "The PLY Polygon File Format"): ascii, binary_little_endian and
//! binary_big_endian.
//!
//! Read: the `vertex` element's `x y z` (float or double), optional `nx ny nz`, and optional texture
//! coordinates (`u v`, `s t`, `texture_u texture_v` or `texture_s texture_t`); the `face` element's
//! `vertex_indices` (or `vertex_index`) list. Every other element and property is skipped. Polygons
//! are fan-triangulated, which is exact for convex polygons (the format's common case; scanners emit
//! triangles); faces with fewer than three vertices are skipped.
//!
//! Binary files with the common layout (all-`float` vertices, then faces whose only property is a
//! `uchar`-counted `int` list, little-endian) take a fast path that reads fixed-stride records
//! straight from the memory-mapped file; everything else goes through the general reader.

use crate::description::loaded_mesh::{first_non_finite, LoadedMesh, MeshPart};
use crate::error::{Error, Location, Result};
use crate::geometry::TriangleMesh;
use crate::math::{Vec2, Vec3};
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ty {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Ty {
    fn parse(s: &str) -> Option<Ty> {
        Some(match s {
            "char" | "int8" => Ty::I8,
            "uchar" | "uint8" => Ty::U8,
            "short" | "int16" => Ty::I16,
            "ushort" | "uint16" => Ty::U16,
            "int" | "int32" => Ty::I32,
            "uint" | "uint32" => Ty::U32,
            "float" | "float32" => Ty::F32,
            "double" | "float64" => Ty::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Ty::I8 | Ty::U8 => 1,
            Ty::I16 | Ty::U16 => 2,
            Ty::I32 | Ty::U32 | Ty::F32 => 4,
            Ty::F64 => 8,
        }
    }

    fn is_int(self) -> bool {
        !matches!(self, Ty::F32 | Ty::F64)
    }
}

const TYPE_NAMES: &str =
    "char, uchar, short, ushort, int, uint, float, double (or int8, uint8, ..., float64)";

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Scalar(Ty),
    List { count: Ty, item: Ty },
}

#[derive(Clone, Debug)]
struct Prop {
    name: String,
    kind: Kind,
    /// Its header line, for errors.
    line: usize,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Prop>,
    /// Its header line, for errors.
    line: usize,
}

impl Element {
    /// Bytes of the smallest binary record (lists counted as empty).
    fn min_binary_size(&self) -> u64 {
        self.props
            .iter()
            .map(|p| match p.kind {
                Kind::Scalar(t) => t.size() as u64,
                Kind::List { count, .. } => count.size() as u64,
            })
            .sum()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ascii,
    LittleEndian,
    BigEndian,
}

struct Header {
    format: Format,
    elements: Vec<Element>,
    /// Byte offset of the first data byte.
    data_start: usize,
    /// Number of header lines (ascii data starts on the next line).
    lines: usize,
}

/// Where the vertex properties Appel uses sit in a vertex record.
#[derive(Default)]
struct VertexSlots {
    /// For each property of the vertex element: which of x y z nx ny nz u v it is, if any.
    slot: Vec<Option<usize>>,
    has_normals: bool,
    has_uvs: bool,
}

fn vertex_slots(e: &Element) -> VertexSlots {
    let names: [&[&str]; 8] = [
        &["x"],
        &["y"],
        &["z"],
        &["nx"],
        &["ny"],
        &["nz"],
        &["u", "s", "texture_u", "texture_s"],
        &["v", "t", "texture_v", "texture_t"],
    ];
    let slot: Vec<Option<usize>> = e
        .props
        .iter()
        .map(|p| match p.kind {
            Kind::Scalar(_) => names.iter().position(|n| n.contains(&p.name.as_str())),
            Kind::List { .. } => None,
        })
        .collect();
    let has = |i: usize| slot.contains(&Some(i));
    VertexSlots {
        has_normals: has(3) && has(4) && has(5),
        has_uvs: has(6) && has(7),
        slot,
    }
}

/// Element counts from a PLY header, read without loading the data: what the memory estimate
/// needs before a large file is loaded.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlyCounts {
    pub vertices: u64,
    /// Faces as declared; polygons with more than three corners become several triangles.
    pub faces: u64,
}

/// Reads only the header of a PLY file (the first 64 KiB, decompressed for `.ply.gz`).
pub fn read_ply_counts(path: &Path) -> Result<PlyCounts> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let gz = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    let mut reader: Box<dyn Read> = if gz {
        Box::new(flate2::read::MultiGzDecoder::new(std::io::BufReader::new(
            file,
        )))
    } else {
        Box::new(file)
    };
    let mut head = Vec::new();
    reader
        .by_ref()
        .take(64 * 1024)
        .read_to_end(&mut head)
        .map_err(|e| Error::io(path, e))?;
    let header = parse_header(&head, path)?;
    let count = |name: &str| {
        header
            .elements
            .iter()
            .find(|e| e.name == name)
            .map_or(0, |e| e.count)
    };
    Ok(PlyCounts {
        vertices: count("vertex"),
        faces: count("face"),
    })
}

pub fn parse_ply(data: &[u8], path: &Path) -> Result<LoadedMesh> {
    let header = parse_header(data, path)?;
    let vi = header
        .elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| {
            header_error(
                path,
                header.lines,
                "the PLY header declares no `vertex` element",
            )
        })?;
    let vertex = &header.elements[vi];
    for axis in ["x", "y", "z"] {
        match vertex.props.iter().find(|p| p.name == axis) {
            Some(Prop {
                kind: Kind::Scalar(_),
                ..
            }) => {}
            Some(p) => {
                return Err(header_error(
                    path,
                    p.line,
                    format!("the vertex property `{axis}` is a list; expected a number"),
                ))
            }
            None => {
                return Err(header_error(
                    path,
                    vertex.line,
                    format!("the `vertex` element has no `{axis}` property"),
                ))
            }
        }
    }
    if vertex.count > u32::MAX as u64 {
        return Err(header_error(
            path,
            vertex.line,
            format!(
                "{} vertices: more than the 2^32 - 1 that u32 indices can address",
                vertex.count
            ),
        ));
    }
    for e in &header.elements {
        index_prop(e, path)?;
    }
    let mut out = Output::default();
    match header.format {
        Format::Ascii => read_ascii(data, path, &header, &mut out)?,
        _ => {
            check_binary_sizes(data, path, &header)?;
            if !fast_binary(data, path, &header, &mut out)? {
                read_binary(data, path, &header, &mut out)?;
            }
        }
    }
    let attributes = attributes::read_attributes(data, path, &header, out.indices.len())?;
    let mesh = TriangleMesh {
        positions: out.positions,
        indices: out.indices,
        normals: out.normals,
        uvs: out.uvs,
    };
    Ok(LoadedMesh {
        parts: vec![MeshPart {
            mesh,
            material: None,
            file_triangles: None,
            tangents: None,
        }],
        attributes,
        ..Default::default()
    })
}

#[path = "ply_attributes.rs"]
mod attributes;

#[derive(Default)]
struct Output {
    positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
}

fn header_error(path: &Path, line: usize, msg: impl Into<String>) -> Error {
    Error::input(Location::line(path, line, None), msg)
}

fn parse_header(data: &[u8], path: &Path) -> Result<Header> {
    if !data.starts_with(b"ply") {
        return Err(Error::input(
            Location::byte(path, 0),
            "not a PLY file: it does not start with `ply`",
        ));
    }
    let mut pos = 0usize;
    let mut line_no = 0usize;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some(len) = data[pos..].iter().position(|&b| b == b'\n') else {
            return Err(Error::input(
                Location::byte(path, data.len() as u64),
                "the PLY header never ends: no `end_header` line",
            ));
        };
        let raw = &data[pos..pos + len];
        pos += len + 1;
        line_no += 1;
        let line = std::str::from_utf8(raw)
            .map_err(|_| header_error(path, line_no, "the PLY header is not ASCII text"))?
            .trim();
        let mut words = line.split_ascii_whitespace();
        let keyword = words.next().unwrap_or("");
        let rest: Vec<&str> = words.collect();
        match keyword {
            "ply" if line_no == 1 => {}
            "" | "comment" | "obj_info" => {}
            "format" => {
                format = Some(match rest.first().copied() {
                    Some("ascii") => Format::Ascii,
                    Some("binary_little_endian") => Format::LittleEndian,
                    Some("binary_big_endian") => Format::BigEndian,
                    other => {
                        return Err(header_error(
                            path,
                            line_no,
                            format!(
                                "unknown PLY format `{}`: expected ascii, binary_little_endian or binary_big_endian",
                                other.unwrap_or("")
                            ),
                        ))
                    }
                });
            }
            "element" => {
                let (Some(name), Some(count), 2) = (rest.first(), rest.get(1), rest.len()) else {
                    return Err(header_error(path, line_no, "expected `element NAME COUNT`"));
                };
                let count: u64 = count.parse().map_err(|_| {
                    header_error(
                        path,
                        line_no,
                        format!("element count `{count}` is not a non-negative integer"),
                    )
                })?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    props: vec![],
                    line: line_no,
                });
            }
            "property" => {
                let Some(element) = elements.last_mut() else {
                    return Err(header_error(
                        path,
                        line_no,
                        "`property` before any `element`",
                    ));
                };
                let ty = |s: &str| {
                    Ty::parse(s).ok_or_else(|| {
                        header_error(
                            path,
                            line_no,
                            format!("unknown property type `{s}`: expected one of {TYPE_NAMES}"),
                        )
                    })
                };
                let prop = match rest.as_slice() {
                    ["list", count, item, name] => {
                        let count = ty(count)?;
                        if !count.is_int() {
                            return Err(header_error(
                                path,
                                line_no,
                                format!("the list count type of `{name}` must be an integer type"),
                            ));
                        }
                        Prop {
                            name: name.to_string(),
                            kind: Kind::List {
                                count,
                                item: ty(item)?,
                            },
                            line: line_no,
                        }
                    }
                    [t, name] if *t != "list" => Prop {
                        name: name.to_string(),
                        kind: Kind::Scalar(ty(t)?),
                        line: line_no,
                    },
                    _ => {
                        return Err(header_error(
                            path,
                            line_no,
                            "expected `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`",
                        ))
                    }
                };
                element.props.push(prop);
            }
            "end_header" => break,
            other => {
                return Err(header_error(
                    path,
                    line_no,
                    format!("unknown PLY header keyword `{other}`"),
                ))
            }
        }
    }
    let format =
        format.ok_or_else(|| header_error(path, line_no, "the PLY header has no `format` line"))?;
    Ok(Header {
        format,
        elements,
        data_start: pos,
        lines: line_no,
    })
}

/// Catches headers whose counts promise more records than the file holds before anything is
/// allocated for them.
fn check_binary_sizes(data: &[u8], path: &Path, h: &Header) -> Result<()> {
    let available = (data.len() - h.data_start) as u128;
    let mut need: u128 = 0;
    for e in &h.elements {
        need += e.count as u128 * e.min_binary_size() as u128;
        if need > available {
            return Err(Error::input(
                Location::byte(path, data.len() as u64),
                format!(
                    "the file is too short for its header: {} `{}` records need at least {} bytes up to here, but only {available} bytes follow the header (truncated file, or a header count that is wrong)",
                    e.count, e.name, need
                ),
            ));
        }
    }
    Ok(())
}

fn truncated(path: &Path, pos: usize, what: &str) -> Error {
    Error::input(
        Location::byte(path, pos as u64),
        format!("the file ends in the middle of {what} (truncated file, or a header count that is wrong)"),
    )
}

fn index_error(path: &Path, loc: Location, face: u64, index: i64, nv: usize) -> Error {
    let _ = path;
    Error::input(
        loc,
        format!("face {face}: vertex index {index} is out of range (the file has {nv} vertices)"),
    )
}

fn non_finite_error(loc: Location, vertex: usize, p: Vec3) -> Error {
    Error::input(
        loc,
        format!(
            "vertex {vertex} has a coordinate that is not a finite number: ({}, {}, {})",
            p.x, p.y, p.z
        ),
    )
}

/// In a `tristrips` list, -1 ends one strip and starts the next.
const RESTART: u32 = u32::MAX;

/// The face index list of a `face` or `tristrips` element (checked to be a list of integers), or
/// `None` for other elements.
fn index_prop(e: &Element, path: &Path) -> Result<Option<usize>> {
    if e.name != "face" && e.name != "tristrips" {
        return Ok(None);
    }
    let i = e
        .props
        .iter()
        .position(|p| p.name == "vertex_indices" || p.name == "vertex_index")
        .ok_or_else(|| {
            header_error(
                path,
                e.line,
                format!(
                    "the `{}` element has no `vertex_indices` (or `vertex_index`) property",
                    e.name
                ),
            )
        })?;
    match e.props[i].kind {
        Kind::List { item, .. } if item.is_int() => Ok(Some(i)),
        _ => Err(header_error(
            path,
            e.props[i].line,
            format!(
                "the {} property `{}` must be a list of integers",
                e.name, e.props[i].name
            ),
        )),
    }
}

/// Appends the triangles of triangle strips separated by [`RESTART`]: every three consecutive
/// vertices, with the winding flipped on every other triangle so all face the same way. Triangles
/// with a repeated vertex are the joins writers insert between strips and are dropped.
fn push_strips(indices: &mut Vec<[u32; 3]>, list: &[u32]) {
    for strip in list.split(|&i| i == RESTART) {
        for (k, w) in strip.windows(3).enumerate() {
            let t = if k % 2 == 0 {
                [w[0], w[1], w[2]]
            } else {
                [w[1], w[0], w[2]]
            };
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                indices.push(t);
            }
        }
    }
}

/// Appends the fan triangulation of polygon `poly` (vertex indices already checked).
#[inline]
fn push_fan(indices: &mut Vec<[u32; 3]>, poly: &[u32]) {
    for k in 1..poly.len().saturating_sub(1) {
        indices.push([poly[0], poly[k], poly[k + 1]]);
    }
}

// ---------------------------------------------------------------------------------------------
// Binary

struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
    big: bool,
}

impl Cursor<'_> {
    #[inline]
    fn bytes<const N: usize>(&mut self) -> Option<[u8; N]> {
        let b: [u8; N] = self.data.get(self.pos..self.pos + N)?.try_into().ok()?;
        self.pos += N;
        Some(if self.big {
            let mut r = b;
            r.reverse();
            r
        } else {
            b
        })
    }

    /// Reads one value as f64 (exact for every PLY type).
    #[inline]
    fn value(&mut self, ty: Ty) -> Option<f64> {
        Some(match ty {
            Ty::I8 => i8::from_le_bytes(self.bytes()?) as f64,
            Ty::U8 => u8::from_le_bytes(self.bytes()?) as f64,
            Ty::I16 => i16::from_le_bytes(self.bytes()?) as f64,
            Ty::U16 => u16::from_le_bytes(self.bytes()?) as f64,
            Ty::I32 => i32::from_le_bytes(self.bytes()?) as f64,
            Ty::U32 => u32::from_le_bytes(self.bytes()?) as f64,
            Ty::F32 => f32::from_le_bytes(self.bytes()?) as f64,
            Ty::F64 => f64::from_le_bytes(self.bytes()?),
        })
    }

    fn skip(&mut self, n: usize) -> Option<()> {
        let end = self.pos.checked_add(n)?;
        if end > self.data.len() {
            return None;
        }
        self.pos = end;
        Some(())
    }
}

fn read_binary(data: &[u8], path: &Path, h: &Header, out: &mut Output) -> Result<()> {
    let mut c = Cursor {
        data,
        pos: h.data_start,
        big: h.format == Format::BigEndian,
    };
    let mut nv = 0usize;
    for e in h.elements.iter().filter(|e| !e.props.is_empty()) {
        let what = format!("a `{}` record", e.name);
        match e.name.as_str() {
            "vertex" => {
                let slots = vertex_slots(e);
                let n = e.count as usize;
                out.positions.reserve_exact(n);
                let mut normals = Vec::with_capacity(if slots.has_normals { n } else { 0 });
                let mut uvs = Vec::with_capacity(if slots.has_uvs { n } else { 0 });
                for i in 0..n {
                    let start = c.pos;
                    let mut v = [0f32; 8];
                    for (p, slot) in e.props.iter().zip(&slots.slot) {
                        match p.kind {
                            Kind::Scalar(t) => {
                                let x = c.value(t).ok_or_else(|| truncated(path, c.pos, &what))?;
                                if let Some(s) = slot {
                                    v[*s] = x as f32;
                                }
                            }
                            Kind::List { count, item } => skip_list(&mut c, count, item)
                                .ok_or_else(|| truncated(path, c.pos, &what))?,
                        }
                    }
                    let p = Vec3::new(v[0], v[1], v[2]);
                    if !p.is_finite() {
                        return Err(non_finite_error(Location::byte(path, start as u64), i, p));
                    }
                    out.positions.push(p);
                    if slots.has_normals {
                        normals.push(Vec3::new(v[3], v[4], v[5]));
                    }
                    if slots.has_uvs {
                        uvs.push(Vec2::new(v[6], v[7]));
                    }
                }
                nv = n;
                out.normals = slots.has_normals.then_some(normals);
                out.uvs = slots.has_uvs.then_some(uvs);
            }
            "face" | "tristrips" => {
                let face_index_prop = index_prop(e, path)?;
                let strip = e.name == "tristrips";
                let mut poly: Vec<u32> = Vec::with_capacity(8);
                for f in 0..e.count {
                    for (pi, p) in e.props.iter().enumerate() {
                        match p.kind {
                            Kind::Scalar(t) => {
                                c.skip(t.size())
                                    .ok_or_else(|| truncated(path, c.pos, &what))?;
                            }
                            Kind::List { count, item } if Some(pi) == face_index_prop => {
                                let n = c
                                    .value(count)
                                    .ok_or_else(|| truncated(path, c.pos, &what))?;
                                if n < 0.0 {
                                    return Err(Error::input(
                                        Location::byte(path, (c.pos - count.size()) as u64),
                                        format!("face {f}: negative vertex count {n}"),
                                    ));
                                }
                                poly.clear();
                                for _ in 0..n as usize {
                                    let at = c.pos;
                                    let idx = c
                                        .value(item)
                                        .ok_or_else(|| truncated(path, c.pos, &what))?;
                                    if strip && idx == -1.0 {
                                        poly.push(RESTART);
                                        continue;
                                    }
                                    if idx < 0.0 || idx >= nv as f64 {
                                        return Err(index_error(
                                            path,
                                            Location::byte(path, at as u64),
                                            f,
                                            idx as i64,
                                            nv,
                                        ));
                                    }
                                    poly.push(idx as u32);
                                }
                                if strip {
                                    push_strips(&mut out.indices, &poly);
                                } else {
                                    push_fan(&mut out.indices, &poly);
                                }
                            }
                            Kind::List { count, item } => skip_list(&mut c, count, item)
                                .ok_or_else(|| truncated(path, c.pos, &what))?,
                        }
                    }
                }
            }
            _ => {
                for _ in 0..e.count {
                    for p in &e.props {
                        match p.kind {
                            Kind::Scalar(t) => c.skip(t.size()),
                            Kind::List { count, item } => skip_list(&mut c, count, item),
                        }
                        .ok_or_else(|| truncated(path, c.pos, &what))?;
                    }
                }
            }
        }
    }
    check_trailing(data, path, c.pos)
}

fn skip_list(c: &mut Cursor, count: Ty, item: Ty) -> Option<()> {
    let n = c.value(count)?;
    if n < 0.0 {
        return None;
    }
    c.skip((n as usize).checked_mul(item.size())?)
}

fn check_trailing(data: &[u8], path: &Path, pos: usize) -> Result<()> {
    if pos < data.len() {
        return Err(Error::input(
            Location::byte(path, pos as u64),
            format!(
                "{} bytes of data after the last element: the header's counts do not match the data",
                data.len() - pos
            ),
        ));
    }
    Ok(())
}

/// The fast path for the layout nearly every binary PLY writer uses. Returns `false` (having read
/// nothing) if the file does not have that layout.
fn fast_binary(data: &[u8], path: &Path, h: &Header, out: &mut Output) -> Result<bool> {
    let [vertex, face] = h.elements.as_slice() else {
        return Ok(false);
    };
    let fast_layout = h.format == Format::LittleEndian
        && vertex.name == "vertex"
        && face.name == "face"
        && vertex.props.iter().all(|p| p.kind == Kind::Scalar(Ty::F32))
        && matches!(
            face.props.as_slice(),
            [Prop { name, kind: Kind::List { count: Ty::U8 | Ty::I8, item: Ty::I32 | Ty::U32 }, .. }]
                if name == "vertex_indices" || name == "vertex_index"
        );
    if !fast_layout {
        return Ok(false);
    }
    let slots = vertex_slots(vertex);
    let find = |s: usize| slots.slot.iter().position(|&x| x == Some(s)).unwrap_or(0) * 4;
    let off: [usize; 8] = std::array::from_fn(find);
    let stride = vertex.props.len() * 4;
    let nv = vertex.count as usize;
    // check_binary_sizes guarantees this slice exists.
    let vbytes = &data[h.data_start..h.data_start + nv * stride];
    let f32_at =
        |rec: &[u8], o: usize| f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]);
    out.positions = vbytes
        .chunks_exact(stride)
        .map(|r| Vec3::new(f32_at(r, off[0]), f32_at(r, off[1]), f32_at(r, off[2])))
        .collect();
    if let Some(i) = first_non_finite(&out.positions) {
        return Err(non_finite_error(
            Location::byte(path, (h.data_start + i * stride) as u64),
            i,
            out.positions[i],
        ));
    }
    if slots.has_normals {
        out.normals = Some(
            vbytes
                .chunks_exact(stride)
                .map(|r| Vec3::new(f32_at(r, off[3]), f32_at(r, off[4]), f32_at(r, off[5])))
                .collect(),
        );
    }
    if slots.has_uvs {
        out.uvs = Some(
            vbytes
                .chunks_exact(stride)
                .map(|r| Vec2::new(f32_at(r, off[6]), f32_at(r, off[7])))
                .collect(),
        );
    }

    let signed_count = matches!(face.props[0].kind, Kind::List { count: Ty::I8, .. });
    let nv32 = nv as u32;
    let mut pos = h.data_start + nv * stride;
    let nf = face.count;
    // Each face takes at least one byte, so the count is bounded by the file size (checked above).
    out.indices.reserve(nf as usize);
    let mut poly: Vec<u32> = Vec::new();
    let what = "a `face` record";
    for f in 0..nf {
        let Some(&n) = data.get(pos) else {
            return Err(truncated(path, pos, what));
        };
        let n = if signed_count {
            n as i8 as i32
        } else {
            n as i32
        };
        pos += 1;
        if n == 3 {
            if let Some(rec) = data.get(pos..pos + 12) {
                let a = u32::from_le_bytes([rec[0], rec[1], rec[2], rec[3]]);
                let b = u32::from_le_bytes([rec[4], rec[5], rec[6], rec[7]]);
                let c = u32::from_le_bytes([rec[8], rec[9], rec[10], rec[11]]);
                // Negative i32 indices become huge u32 values, so one comparison rejects both.
                if a >= nv32 || b >= nv32 || c >= nv32 {
                    let k = [a, b, c].iter().position(|&x| x >= nv32).unwrap_or(0);
                    return Err(fast_index_error(
                        path,
                        pos + 4 * k,
                        f,
                        [a, b, c][k],
                        face,
                        nv,
                    ));
                }
                out.indices.push([a, b, c]);
                pos += 12;
                continue;
            }
            return Err(truncated(path, data.len(), what));
        }
        if n < 0 {
            return Err(Error::input(
                Location::byte(path, (pos - 1) as u64),
                format!("face {f}: negative vertex count {n}"),
            ));
        }
        poly.clear();
        for _ in 0..n {
            let Some(rec) = data.get(pos..pos + 4) else {
                return Err(truncated(path, data.len(), what));
            };
            let a = u32::from_le_bytes([rec[0], rec[1], rec[2], rec[3]]);
            if a >= nv32 {
                return Err(fast_index_error(path, pos, f, a, face, nv));
            }
            poly.push(a);
            pos += 4;
        }
        push_fan(&mut out.indices, &poly);
    }
    check_trailing(data, path, pos)?;
    Ok(true)
}

fn fast_index_error(path: &Path, pos: usize, f: u64, raw: u32, face: &Element, nv: usize) -> Error {
    let signed = matches!(face.props[0].kind, Kind::List { item: Ty::I32, .. });
    let index = if signed {
        raw as i32 as i64
    } else {
        raw as i64
    };
    index_error(path, Location::byte(path, pos as u64), f, index, nv)
}

// ---------------------------------------------------------------------------------------------
// ASCII

fn read_ascii(data: &[u8], path: &Path, h: &Header, out: &mut Output) -> Result<()> {
    let body = &data[h.data_start..];
    // Every record is at least one digit and a separator per property: bounds the counts before
    // anything is reserved.
    let mut need: u128 = 0;
    for e in &h.elements {
        need += e.count as u128 * (2 * e.props.len()) as u128;
    }
    if need > body.len() as u128 {
        return Err(Error::input(
            Location::byte(path, data.len() as u64),
            format!(
                "the file is too short for its header: the declared records need at least {need} bytes, but only {} bytes follow the header (truncated file, or a header count that is wrong)",
                body.len()
            ),
        ));
    }
    let mut lines = body
        .split(|&b| b == b'\n')
        .enumerate()
        .filter_map(|(i, l)| {
            let l = l.strip_suffix(b"\r").unwrap_or(l);
            let blank = l.iter().all(|b| b.is_ascii_whitespace());
            (!blank).then_some((h.lines + 1 + i, l))
        });
    let mut nv = 0usize;
    // An element without properties has empty records: nothing to read, however large its count.
    for e in h.elements.iter().filter(|e| !e.props.is_empty()) {
        let slots = (e.name == "vertex").then(|| vertex_slots(e));
        let face_index_prop = index_prop(e, path)?;
        let strip = e.name == "tristrips";
        if e.name == "vertex" {
            out.positions.reserve_exact(e.count as usize);
        }
        let mut normals = vec![];
        let mut uvs = vec![];
        let mut poly: Vec<u32> = vec![];
        for r in 0..e.count {
            let Some((line_no, raw)) = lines.next() else {
                return Err(Error::input(
                    Location::line(path, h.lines + body.split(|&b| b == b'\n').count(), None),
                    format!(
                        "the file ends after {r} of the {} `{}` records the header declares",
                        e.count, e.name
                    ),
                ));
            };
            let loc = || Location::line(path, line_no, None);
            let line = std::str::from_utf8(raw)
                .map_err(|_| Error::input(loc(), "this line is not ASCII text"))?;
            let mut tokens = line.split_ascii_whitespace();
            let mut next = |what: &str| -> Result<f64> {
                let t = tokens.next().ok_or_else(|| {
                    Error::input(
                        loc(),
                        format!("too few values for a `{}` record: missing {what}", e.name),
                    )
                })?;
                t.parse::<f64>().map_err(|_| {
                    Error::input(loc(), format!("`{t}` is not a number (reading {what})"))
                })
            };
            let mut v = [0f32; 8];
            for (pi, p) in e.props.iter().enumerate() {
                match p.kind {
                    Kind::Scalar(_) => {
                        let x = next(&format!("`{}`", p.name))?;
                        if let Some(Some(s)) = slots.as_ref().map(|s| s.slot[pi]) {
                            v[s] = x as f32;
                        }
                    }
                    Kind::List { .. } => {
                        let n = next(&format!("the length of `{}`", p.name))?;
                        if !(n >= 0.0 && n.fract() == 0.0) {
                            return Err(Error::input(
                                loc(),
                                format!("list length {n} is not a non-negative integer"),
                            ));
                        }
                        let is_index = Some(pi) == face_index_prop;
                        poly.clear();
                        for _ in 0..n as u64 {
                            let x = next(&format!("an item of `{}`", p.name))?;
                            if is_index && strip && x == -1.0 {
                                poly.push(RESTART);
                            } else if is_index {
                                if !(x >= 0.0 && x < nv as f64 && x.fract() == 0.0) {
                                    return Err(index_error(path, loc(), r, x as i64, nv));
                                }
                                poly.push(x as u32);
                            }
                        }
                        if is_index && strip {
                            push_strips(&mut out.indices, &poly);
                        } else if is_index {
                            push_fan(&mut out.indices, &poly);
                        }
                    }
                }
            }
            if tokens.next().is_some() {
                return Err(Error::input(
                    loc(),
                    format!("more values than the `{}` element declares", e.name),
                ));
            }
            if let Some(s) = &slots {
                let p = Vec3::new(v[0], v[1], v[2]);
                if !p.is_finite() {
                    return Err(non_finite_error(loc(), r as usize, p));
                }
                out.positions.push(p);
                if s.has_normals {
                    normals.push(Vec3::new(v[3], v[4], v[5]));
                }
                if s.has_uvs {
                    uvs.push(Vec2::new(v[6], v[7]));
                }
            }
        }
        if let Some(s) = &slots {
            nv = e.count as usize;
            out.normals = s.has_normals.then_some(normals);
            out.uvs = s.has_uvs.then_some(uvs);
        }
    }
    if let Some((line_no, _)) = lines.next() {
        return Err(Error::input(
            Location::line(path, line_no, None),
            "more data after the last element: the header's counts do not match the data",
        ));
    }
    Ok(())
}
