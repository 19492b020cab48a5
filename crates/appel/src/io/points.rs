//! Point lists for geometry queries: one `x,y,z` per line (blank lines and `#` comments skipped).

use crate::error::{Error, Location, Result};
use crate::math::Vec3;
use std::path::Path;

pub fn read_points_csv(path: &Path) -> Result<Vec<Vec3>> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        Error::input(
            Location::byte(path, e.valid_up_to() as u64),
            "the point list is not UTF-8 text",
        )
    })?;
    parse_points_csv(text, path)
}

/// Parses point-list text; `origin` names it in error messages.
pub fn parse_points_csv(text: &str, origin: &Path) -> Result<Vec<Vec3>> {
    let mut points = vec![];
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line
            .split([',', ' ', '\t', ';'])
            .filter(|f| !f.is_empty())
            .collect();
        let values: Option<Vec<f32>> = fields.iter().map(|f| f.parse().ok()).collect();
        match values.as_deref() {
            Some(&[x, y, z]) if x.is_finite() && y.is_finite() && z.is_finite() => {
                points.push(Vec3::new(x, y, z))
            }
            _ => {
                return Err(Error::input(
                    Location::line(origin, i + 1, None),
                    format!("expected a point as three finite numbers `x,y,z`, got `{line}`"),
                ))
            }
        }
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_points_skipping_blanks_and_comments() {
        let p = parse_points_csv(
            "# header\n1,2,3\n\n 4 5 6 # trailing\n-1e-3,0,7\n",
            Path::new("p.csv"),
        )
        .unwrap();
        assert_eq!(
            p,
            vec![
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::new(4.0, 5.0, 6.0),
                Vec3::new(-1e-3, 0.0, 7.0)
            ]
        );
    }

    #[test]
    fn bad_lines_are_reported_with_their_number() {
        for bad in [
            "1,2,3\n1,2\n",
            "1,2,3\n1,2,x\n",
            "1,2,3\nnan,0,0\n",
            "1,2,3\n1,2,3,4\n",
        ] {
            let e = parse_points_csv(bad, Path::new("p.csv"))
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("p.csv:2: expected a point"), "{e}");
        }
    }
}
