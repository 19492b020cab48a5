//! Animated scenes: a description with `[animation]`, keyframed transforms and mesh files named
//! per frame (`file = "wave_{frame:04}.ply"`) stands for one plain description per frame.
//! [`at_frame`] makes that description; everything downstream (the scene, its structures, the
//! render) sees only plain descriptions, so a frame rendered alone and the same frame reached
//! through a sequence start from the very same input.

use super::{Description, KeyframeDesc, ShapeDesc, TransformDesc};
use glam::{Mat4, Quat, Vec3};

/// Frames in the description's sequence (1 without `[animation]`).
pub fn frame_count(d: &Description) -> u32 {
    d.animation.as_ref().map_or(1, |a| a.frames)
}

/// The time of frame `frame`, in seconds.
pub fn time_of(d: &Description, frame: u32) -> f32 {
    d.animation.as_ref().map_or(0.0, |a| frame as f32 / a.fps)
}

/// Whether anything in the description changes from frame to frame.
pub fn is_animated(d: &Description) -> bool {
    d.instances.iter().any(|i| !i.keyframes.is_empty())
        || d.meshes.values().any(|m| is_pattern(&m.file))
        || d.shapes.iter().any(|s| match s {
            ShapeDesc::Mesh(m) => !m.keyframes.is_empty() || is_pattern(&m.file),
            ShapeDesc::Rectangle(b) | ShapeDesc::Cube(b) | ShapeDesc::Disk(b) => {
                !b.keyframes.is_empty()
            }
            _ => false,
        })
}

/// The plain description of frame `frame`: keyframes replaced by the transform at the frame's
/// time, file name patterns by the frame's file names.
pub fn at_frame(d: &Description, frame: u32) -> Description {
    let time = time_of(d, frame);
    let mut out = d.clone();
    let settle = |keys: &mut Vec<KeyframeDesc>, transform: &mut Option<TransformDesc>| {
        if !keys.is_empty() {
            *transform = Some(matrix_desc(transform_at(keys, time)));
            keys.clear();
        }
    };
    for i in &mut out.instances {
        settle(&mut i.keyframes, &mut i.transform);
    }
    for m in out.meshes.values_mut() {
        m.file = frame_file(&m.file, frame);
    }
    for s in &mut out.shapes {
        match s {
            ShapeDesc::Mesh(m) => {
                settle(&mut m.keyframes, &mut m.transform);
                m.file = frame_file(&m.file, frame);
            }
            ShapeDesc::Rectangle(b) | ShapeDesc::Cube(b) | ShapeDesc::Disk(b) => {
                settle(&mut b.keyframes, &mut b.transform)
            }
            _ => {}
        }
    }
    out
}

/// Whether a file name holds a `{frame...}` field.
pub fn is_pattern(file: &str) -> bool {
    file.contains("{frame")
}

/// `pattern` with each `{frame}` replaced by the frame number and each `{frame:0N}` by the
/// number padded with zeros to `N` digits. A field of any other form stays as written; the
/// validator reports it ([`check_pattern`]).
pub fn frame_file(pattern: &str, frame: u32) -> String {
    let mut out = String::new();
    let mut rest = pattern;
    while let Some(at) = rest.find("{frame") {
        out.push_str(&rest[..at]);
        let field = &rest[at..];
        let Some(end) = field.find('}') else {
            out.push_str(field);
            return out;
        };
        match field_width(&field[..=end]) {
            Some(w) => out.push_str(&format!("{frame:0w$}")),
            None => out.push_str(&field[..=end]),
        }
        rest = &field[end + 1..];
    }
    out.push_str(rest);
    out
}

/// Checks the `{frame...}` fields of a file name.
pub fn check_pattern(pattern: &str) -> Result<(), String> {
    let mut rest = pattern;
    while let Some(at) = rest.find("{frame") {
        let field = &rest[at..];
        let end = field
            .find('}')
            .ok_or_else(|| format!("`{field}`: a `{{frame` field must end with `}}`"))?;
        if field_width(&field[..=end]).is_none() {
            return Err(format!(
                "`{}`: expected `{{frame}}` or `{{frame:0N}}` (N digits, zero-padded)",
                &field[..=end]
            ));
        }
        rest = &field[end + 1..];
    }
    Ok(())
}

/// The width of a `{frame}` (0: no padding) or `{frame:0N}` field.
fn field_width(field: &str) -> Option<usize> {
    match field {
        "{frame}" => Some(0),
        _ => {
            let digits = field.strip_prefix("{frame:0")?.strip_suffix('}')?;
            digits.parse::<usize>().ok().filter(|&w| w <= 12)
        }
    }
}

/// The transform of keys `keys` (in increasing time) at `time`: between two keys their
/// translations and scales are interpolated linearly and their rotations by slerp (Shoemake
/// 1985), the shorter way round; before the first key and after the last the object rests there.
pub fn transform_at(keys: &[KeyframeDesc], time: f32) -> Mat4 {
    let first = &keys[0];
    let last = &keys[keys.len() - 1];
    if time <= first.time {
        return first.transform.matrix();
    }
    if time >= last.time {
        return last.transform.matrix();
    }
    let k = keys.partition_point(|key| key.time <= time) - 1;
    let (a, b) = (&keys[k], &keys[k + 1]);
    let f = (time - a.time) / (b.time - a.time);
    let (sa, ra, ta) = parts(&a.transform);
    let (sb, rb, tb) = parts(&b.transform);
    Mat4::from_scale_rotation_translation(sa.lerp(sb, f), ra.slerp(rb, f), ta.lerp(tb, f))
}

/// Scale, rotation and translation of a transform: as written for translate/rotate/scale, by
/// decomposing a `matrix` (which is then taken to be of that form: a shear is lost).
fn parts(t: &TransformDesc) -> (Vec3, Quat, Vec3) {
    if t.matrix.is_some() {
        return t.matrix().to_scale_rotation_translation();
    }
    let s = Vec3::from(t.scale.map_or([1.0; 3], |s| s.axes()));
    let r = t.rotate.as_ref().map_or(Quat::IDENTITY, |r| {
        Quat::from_axis_angle(Vec3::from(r.axis).normalize(), r.degrees.to_radians())
    });
    (s, r, Vec3::from(t.translate.unwrap_or([0.0; 3])))
}

/// A transform given as its matrix.
fn matrix_desc(m: Mat4) -> TransformDesc {
    TransformDesc {
        matrix: Some(m.transpose().to_cols_array_2d()),
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::RotateDesc;

    fn key(time: f32, x: f32, degrees: f32, scale: f32) -> KeyframeDesc {
        KeyframeDesc {
            time,
            transform: TransformDesc {
                translate: Some([x, 0.0, 0.0]),
                rotate: Some(RotateDesc {
                    axis: [0.0, 0.0, 1.0],
                    degrees,
                }),
                scale: Some(crate::description::ScaleDesc::Uniform(scale)),
                matrix: None,
            },
        }
    }

    #[test]
    fn keys_interpolate_by_parts_and_rest_outside() {
        let keys = [key(1.0, 0.0, 0.0, 1.0), key(3.0, 4.0, 90.0, 3.0)];
        // Half-way: translation 2, rotation 45 degrees (slerp, not a blend of matrices, which
        // would shrink the rotated axes by cos 45), scale 2.
        let m = transform_at(&keys, 2.0);
        let p = m.transform_point3(Vec3::X);
        let h = std::f32::consts::FRAC_1_SQRT_2 * 2.0;
        assert!((p - Vec3::new(2.0 + h, h, 0.0)).length() < 1e-5, "{p}");
        assert_eq!(transform_at(&keys, 0.0), keys[0].transform.matrix());
        assert_eq!(transform_at(&keys, 9.0), keys[1].transform.matrix());
        // A key given as a matrix decomposes to the same parts.
        let as_matrix = [
            keys[0].clone(),
            KeyframeDesc {
                time: 3.0,
                transform: matrix_desc(keys[1].transform.matrix()),
            },
        ];
        let q = transform_at(&as_matrix, 2.0).transform_point3(Vec3::X);
        assert!((q - p).length() < 1e-5, "{q} vs {p}");
    }

    #[test]
    fn frame_fields_are_replaced_and_checked() {
        assert_eq!(frame_file("wave_{frame:04}.ply", 7), "wave_0007.ply");
        assert_eq!(frame_file("a{frame}b{frame:02}", 123), "a123b123");
        assert_eq!(frame_file("plain.ply", 3), "plain.ply");
        assert!(check_pattern("wave_{frame:04}.ply").is_ok());
        assert!(check_pattern("wave_{frame:4}.ply").is_err());
        assert!(check_pattern("wave_{frame.ply").is_err());
        assert!(check_pattern("wave_{frames}.ply").is_err());
    }
}
