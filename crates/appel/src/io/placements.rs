//! Placement lists for `[[instance]]` entries with many placements: one placement per line, the
//! first three rows of its 4x4 affine matrix as twelve numbers, row by row
//! (`m00 m01 m02 tx  m10 m11 m12 ty  m20 m21 m22 tz`), separated by spaces, tabs or commas.
//! Blank lines and `#` comments are skipped. Text, so that a generator's output can be read and
//! diffed; the numbers round-trip exactly when written with Rust's shortest representation.

use crate::error::{Error, Location, Result};
use glam::{Mat4, Vec4};
use std::path::Path;

/// One placement and the line it came from (1-based), for error messages about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub to_world: Mat4,
    pub line: usize,
}

pub fn read_placements(path: &Path) -> Result<Vec<Placement>> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        Error::input(
            Location::byte(path, e.valid_up_to() as u64),
            "the placement list is not UTF-8 text",
        )
    })?;
    parse_placements(text, path)
}

/// Parses placement-list text; `origin` names it in error messages.
pub fn parse_placements(text: &str, origin: &Path) -> Result<Vec<Placement>> {
    let mut out = Vec::with_capacity(text.len() / 100);
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("");
        let mut m = [0.0f32; 12];
        let mut n = 0;
        for field in line.split([',', ' ', '\t']).filter(|f| !f.is_empty()) {
            let column = field.as_ptr() as usize - raw.as_ptr() as usize + 1;
            let at = || Location::line(origin, i + 1, Some(column));
            if n == 12 {
                return Err(Error::input(
                    at(),
                    "more than twelve numbers: a placement is the three rows of a 3x4 matrix",
                ));
            }
            m[n] = match field.parse::<f32>() {
                Ok(x) if x.is_finite() => x,
                _ => {
                    return Err(Error::input(
                        at(),
                        format!("expected a finite number, got `{field}`"),
                    ))
                }
            };
            n += 1;
        }
        if n == 0 {
            continue;
        }
        if n != 12 {
            return Err(Error::input(
                Location::line(origin, i + 1, None),
                format!("expected twelve numbers (three rows of a 3x4 matrix), got {n}"),
            ));
        }
        let to_world = Mat4::from_cols(
            Vec4::new(m[0], m[4], m[8], 0.0),
            Vec4::new(m[1], m[5], m[9], 0.0),
            Vec4::new(m[2], m[6], m[10], 0.0),
            Vec4::new(m[3], m[7], m[11], 1.0),
        );
        out.push(Placement {
            to_world,
            line: i + 1,
        });
    }
    Ok(out)
}

/// One line of a placement list for `m` (its first three rows), in the shortest form that reads
/// back exactly.
pub fn placement_line(m: &Mat4) -> String {
    let mut s = String::with_capacity(120);
    for r in 0..3 {
        let row = m.row(r);
        for x in [row.x, row.y, row.z, row.w] {
            if !s.is_empty() {
                s.push(' ');
            }
            s.push_str(&format!("{x}"));
        }
    }
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Quat, Vec3};

    #[test]
    fn lines_round_trip_exactly() {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(0.3, 1.7, 2.0),
            Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.77),
            Vec3::new(-1e4, 3.25, 1e-3),
        );
        let text = format!(
            "# header\n\n{}{}",
            placement_line(&m),
            placement_line(&Mat4::IDENTITY)
        );
        let p = parse_placements(&text, Path::new("p.txt")).unwrap();
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].to_world, m);
        assert_eq!(p[0].line, 3);
        assert_eq!(p[1].to_world, Mat4::IDENTITY);
        let commas = "1,0,0,5, 0,1,0,6, 0,0,1,7 # moved\n";
        let q = parse_placements(commas, Path::new("p.txt")).unwrap();
        assert_eq!(q[0].to_world.w_axis, glam::Vec4::new(5.0, 6.0, 7.0, 1.0));
    }

    #[test]
    fn bad_lines_name_their_line_and_column() {
        for (bad, expected) in [
            (
                "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n",
                "p.txt:2: expected twelve",
            ),
            (
                "1 0 0 0 0 1 0 x 0 0 1 0\n",
                "p.txt:1:15: expected a finite number, got `x`",
            ),
            (
                "\n1 0 0 0 0 1 0 0 0 0 1 inf\n",
                "p.txt:2:23: expected a finite",
            ),
            (
                "1 0 0 0 0 1 0 0 0 0 1 0 1\n",
                "p.txt:1:25: more than twelve",
            ),
        ] {
            let e = parse_placements(bad, Path::new("p.txt"))
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(expected), "{e}");
        }
    }
}
