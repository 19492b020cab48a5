//! Extra per-vertex and per-face properties of a PLY file as named mesh attributes, grouped as
//! Mitsuba 3's PLY loader groups them: consecutive properties `P_x P_y P_z (P_w)`, `P_r P_g P_b
//! (P_a)`, `P_0 P_1 ...` or `P_1 P_2 ...` make one attribute `vertex_P` (or `face_P`) of as many
//! channels; `r g b (a)` and `red green blue (alpha)` make `vertex_color` / `face_color`; any other
//! property is an attribute of one channel under its own name. Integer colours are scaled to
//! [0, 1]. Face attributes are repeated for each triangle a polygon is cut into, so that they are
//! indexed by triangle.
//!
//! Read in a second pass over the data, after the main reader has checked its layout.

use super::*;
use crate::description::loaded_mesh::MeshAttribute;

/// The names the main reader takes from the vertex element.
const VERTEX_RESERVED: [&str; 14] = [
    "x",
    "y",
    "z",
    "nx",
    "ny",
    "nz",
    "u",
    "v",
    "s",
    "t",
    "texture_u",
    "texture_v",
    "texture_s",
    "texture_t",
];

const SUFFIXES: [&[&str]; 4] = [
    &["x", "y", "z", "w"],
    &["r", "g", "b", "a"],
    &["0", "1", "2", "3"],
    &["1", "2", "3", "4"],
];

/// One attribute: its name and the indices of its properties in the element.
struct Group {
    name: String,
    props: Vec<usize>,
    /// Integer colour channels, scaled by their type's maximum.
    scale: f64,
}

fn groups(e: &Element, prefix: &str, reserved: &[&str]) -> Vec<Group> {
    let scalars: Vec<(usize, &str, Ty)> = e
        .props
        .iter()
        .enumerate()
        .filter_map(|(i, p)| match p.kind {
            Kind::Scalar(t) if !reserved.contains(&p.name.as_str()) => {
                Some((i, p.name.as_str(), t))
            }
            _ => None,
        })
        .collect();
    let color_scale = |t: Ty| match t {
        Ty::U8 => 1.0 / 255.0,
        Ty::U16 => 1.0 / 65535.0,
        _ => 1.0,
    };
    let mut out = Vec::new();
    let mut k = 0;
    while k < scalars.len() {
        let (i, name, ty) = scalars[k];
        // Bare colour channels.
        for names in [["r", "g", "b", "a"], ["red", "green", "blue", "alpha"]] {
            let run = scalars[k..]
                .iter()
                .zip(names)
                .take_while(|((_, n, _), want)| n == want)
                .count();
            if run >= 3 {
                out.push(Group {
                    name: format!("{prefix}color"),
                    props: scalars[k..k + run].iter().map(|s| s.0).collect(),
                    scale: color_scale(ty),
                });
                k += run;
                break;
            }
        }
        if out.last().is_some_and(|g| g.props[0] == i) {
            continue;
        }
        // `P_suffix` runs.
        let mut grouped = false;
        if let Some((p, _)) = name.rsplit_once('_') {
            for suffixes in SUFFIXES {
                let run = scalars[k..]
                    .iter()
                    .zip(suffixes)
                    .take_while(|((_, n, _), s)| *n == format!("{p}_{s}"))
                    .count();
                if run >= 1 {
                    let is_color = suffixes[0] == "r" || p == "color";
                    out.push(Group {
                        name: format!("{prefix}{p}"),
                        props: scalars[k..k + run].iter().map(|s| s.0).collect(),
                        scale: if is_color { color_scale(ty) } else { 1.0 },
                    });
                    k += run;
                    grouped = true;
                    break;
                }
            }
        }
        if !grouped {
            out.push(Group {
                name: format!("{prefix}{name}"),
                props: vec![i],
                scale: 1.0,
            });
            k += 1;
        }
    }
    out
}

/// The vertex and face attributes of a file whose geometry has been read; `triangles` is the
/// number of triangles the faces were cut into.
pub(super) fn read_attributes(
    data: &[u8],
    path: &Path,
    h: &Header,
    triangles: usize,
) -> Result<Vec<MeshAttribute>> {
    let mut plans: Vec<(usize, Vec<Group>)> = Vec::new();
    for (ei, e) in h.elements.iter().enumerate() {
        let g = match e.name.as_str() {
            "vertex" => groups(e, "vertex_", &VERTEX_RESERVED),
            "face" => groups(e, "face_", &[]),
            _ => continue,
        };
        if !g.is_empty() {
            plans.push((ei, g));
        }
    }
    if plans.is_empty() {
        return Ok(Vec::new());
    }
    let mut out: Vec<MeshAttribute> = Vec::new();
    let mut records = Records::new(data, path, h);
    for (ei, e) in h.elements.iter().enumerate() {
        let plan = plans.iter().find(|(i, _)| *i == ei).map(|(_, g)| g);
        let index = index_prop(e, path)?;
        let per_face = e.name == "face";
        let first = out.len();
        if let Some(plan) = plan {
            for g in plan {
                out.push(MeshAttribute {
                    name: g.name.clone(),
                    per_face,
                    channels: g.props.len(),
                    data: Vec::new(),
                });
            }
        }
        let mut values = vec![0f64; e.props.len()];
        for _ in 0..e.count {
            // The vertex count of the record's polygon, if it has one.
            let mut corners = 0usize;
            for (pi, p) in e.props.iter().enumerate() {
                match p.kind {
                    Kind::Scalar(t) => values[pi] = records.value(t)?,
                    Kind::List { count, item } => {
                        let n = records.list(count, item)?;
                        if Some(pi) == index {
                            corners = n;
                        }
                    }
                }
            }
            let Some(plan) = plan else { continue };
            let copies = if per_face {
                corners.saturating_sub(2)
            } else {
                1
            };
            for (g, a) in plan.iter().zip(&mut out[first..]) {
                for _ in 0..copies {
                    a.data
                        .extend(g.props.iter().map(|&pi| (values[pi] * g.scale) as f32));
                }
            }
        }
    }
    for a in &out {
        let expected = if a.per_face {
            triangles
        } else {
            a.data.len() / a.channels.max(1)
        };
        if a.data.len() != expected * a.channels {
            return Err(Error::input(
                Location::file(path),
                format!("the face attribute `{}` does not match the faces", a.name),
            ));
        }
    }
    Ok(out)
}

/// The values of the data section in order, binary or ascii.
enum Records<'a> {
    Binary(Cursor<'a>, &'a Path),
    Ascii(std::str::SplitAsciiWhitespace<'a>, &'a Path),
}

impl<'a> Records<'a> {
    fn new(data: &'a [u8], path: &'a Path, h: &Header) -> Self {
        match h.format {
            Format::Ascii => {
                // Checked by the main reader: the body is ASCII text.
                let body = std::str::from_utf8(&data[h.data_start..]).unwrap_or("");
                Records::Ascii(body.split_ascii_whitespace(), path)
            }
            _ => Records::Binary(
                Cursor {
                    data,
                    pos: h.data_start,
                    big: h.format == Format::BigEndian,
                },
                path,
            ),
        }
    }

    fn value(&mut self, t: Ty) -> Result<f64> {
        match self {
            Records::Binary(c, path) => c
                .value(t)
                .ok_or_else(|| truncated(path, c.pos, "an attribute")),
            Records::Ascii(tokens, path) => tokens
                .next()
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| Error::input(Location::file(path), "unreadable attribute value")),
        }
    }

    /// Skips a list; returns its length.
    fn list(&mut self, count: Ty, item: Ty) -> Result<usize> {
        let n = self.value(count)?.max(0.0) as usize;
        for _ in 0..n {
            self.value(item)?;
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn properties_group_as_mitsuba_groups_them() {
        let ply = b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty float temp\nelement face 2\nproperty list uchar int vertex_indices\nproperty float color_0\nproperty float color_1\nproperty float color_2\nproperty float weight_0\nend_header\n0 0 0 255 0 51 1.5\n1 0 0 0 255 0 2\n0 1 0 0 0 255 3\n3 0 1 2 0.1 0.2 0.3 0.5\n4 0 1 2 0 0.4 0.5 0.6 0.7\n";
        let path = Path::new("t.ply");
        let m = parse_ply(ply, path).unwrap();
        let a = &m.attributes;
        let names: Vec<&str> = a.iter().map(|a| a.name.as_str()).collect();
        assert_eq!(
            names,
            ["vertex_color", "vertex_temp", "face_color", "face_weight"]
        );
        assert_eq!(a[0].channels, 3);
        assert_eq!(&a[0].data[..3], &[1.0, 0.0, 0.2]);
        assert_eq!(a[1].data, [1.5, 2.0, 3.0]);
        // The quad is two triangles: its values twice.
        assert_eq!(m.parts[0].mesh.triangle_count(), 3);
        assert_eq!(a[2].data, [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.4, 0.5, 0.6]);
        assert_eq!(a[3].data, [0.5, 0.7, 0.7]);
        assert!(a[2].per_face && !a[0].per_face);
    }
}
