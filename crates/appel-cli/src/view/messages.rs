//! The viewer's WebSocket protocol, page to server: JSON text messages, each checked before use.
//! Anything else (binary data, bad JSON, an unknown type, a value out of range) is answered with
//! an error message and otherwise ignored.

use serde_json::Value;

/// Largest image the viewer renders, per side (a bound on the memory one message can ask for).
pub const MAX_SIDE: u32 = 4096;
/// Most samples per pixel a still image converges to.
pub const MAX_SPP: u32 = 1 << 16;

#[derive(Clone, Debug, PartialEq)]
pub struct CameraMsg {
    pub eye: [f32; 3],
    pub look_at: [f32; 3],
    pub up: [f32; 3],
    /// Vertical field of view, degrees.
    pub fov: f32,
    /// The camera is still moving: answer with fast previews.
    pub moving: bool,
}

/// Settings the page may change; absent fields stay as they are.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SettingsMsg {
    pub integrator: Option<String>,
    pub preview: Option<String>,
    pub accel: Option<String>,
    pub aov: Option<String>,
    pub spp: Option<u32>,
    pub size: Option<(u32, u32)>,
    pub format: Option<String>,
    /// The preview's resolution divisor while moving (1, 2, 4).
    pub preview_scale: Option<u32>,
    /// The lens's aperture radius in scene units (0: a pinhole).
    pub aperture_radius: Option<f32>,
    /// The distance along the view axis to the plane in focus.
    pub focus_distance: Option<f32>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ClientMsg {
    Camera(CameraMsg),
    Settings(SettingsMsg),
    /// The page has drawn frame N: the server keeps at most two frames unacknowledged, so
    /// frames never queue up behind a slow page.
    Ack(u64),
    /// Play (true) or pause (false) an animated scene.
    Play(bool),
    /// Show frame N of an animated scene (checked against its length by the session, which
    /// knows it).
    Seek(u32),
}

pub const AOVS: &[&str] = &["color", "depth", "normal", "shapeid", "primid", "cost"];
pub const FORMATS: &[&str] = &["jpeg", "png", "raw"];
/// The integrators a preview (shown while the chosen one renders) may use: those that sample
/// nothing, so a preview is quick and final at one sample.
pub fn previews() -> Vec<&'static str> {
    appel::scene::IntegratorKind::ALL
        .iter()
        .filter(|k| !k.is_monte_carlo())
        .map(|k| k.name())
        .collect()
}

pub fn parse(text: &str) -> Result<ClientMsg, String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    let obj = v.as_object().ok_or("expected a JSON object")?;
    match obj.get("type").and_then(Value::as_str) {
        Some("camera") => check_camera(CameraMsg {
            eye: vec3(&v, "eye")?,
            look_at: vec3(&v, "look_at")?,
            up: vec3(&v, "up")?,
            fov: {
                let f = number(&v, "fov")? as f32;
                if !(0.1..=179.0).contains(&f) {
                    return Err(format!("fov: expected 0.1 to 179 degrees, got {f}"));
                }
                f
            },
            moving: v.get("moving").and_then(Value::as_bool).unwrap_or(false),
        })
        .map(ClientMsg::Camera),
        Some("settings") => {
            let mut s = SettingsMsg {
                integrator: name(&v, "integrator", appel::scene::IntegratorKind::NAMES)?,
                preview: name(&v, "preview", &previews())?,
                accel: name(&v, "accel", appel::accel::AccelKind::NAMES)?,
                aov: name(&v, "aov", AOVS)?,
                format: name(&v, "format", FORMATS)?,
                ..Default::default()
            };
            if v.get("spp").is_some() {
                s.spp = Some(int_in(&v, "spp", 1, MAX_SPP)?);
            }
            if v.get("width").is_some() || v.get("height").is_some() {
                s.size = Some((
                    int_in(&v, "width", 8, MAX_SIDE)?,
                    int_in(&v, "height", 8, MAX_SIDE)?,
                ));
            }
            if v.get("preview_scale").is_some() {
                s.preview_scale = Some(int_in(&v, "preview_scale", 1, 8)?);
            }
            if v.get("aperture_radius").is_some() {
                let r = number(&v, "aperture_radius")? as f32;
                if !(r >= 0.0 && r.is_finite()) {
                    return Err(format!("aperture_radius: expected 0 or more, got {r}"));
                }
                s.aperture_radius = Some(r);
            }
            if v.get("focus_distance").is_some() {
                let f = number(&v, "focus_distance")? as f32;
                if !(f > 0.0 && f.is_finite()) {
                    return Err(format!(
                        "focus_distance: expected a positive distance, got {f}"
                    ));
                }
                s.focus_distance = Some(f);
            }
            Ok(ClientMsg::Settings(s))
        }
        Some("ack") => Ok(ClientMsg::Ack(
            v.get("frame")
                .and_then(Value::as_u64)
                .ok_or("ack: expected a frame number")?,
        )),
        Some("play") => Ok(ClientMsg::Play(
            v.get("playing")
                .and_then(Value::as_bool)
                .ok_or("play: expected \"playing\": true or false")?,
        )),
        Some("seek") => Ok(ClientMsg::Seek(
            v.get("frame")
                .and_then(Value::as_u64)
                .and_then(|f| u32::try_from(f).ok())
                .ok_or("seek: expected a frame number (a whole number from 0)")?,
        )),
        Some(t) => Err(format!("unknown message type `{t}`")),
        None => Err("missing \"type\"".into()),
    }
}

fn check_camera(m: CameraMsg) -> Result<CameraMsg, String> {
    let sub = |a: [f32; 3], b: [f32; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let len2 = |a: [f32; 3]| a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
    let d = sub(m.look_at, m.eye);
    if len2(d) < 1e-12 {
        return Err("camera: eye and look_at coincide".into());
    }
    let c = [
        d[1] * m.up[2] - d[2] * m.up[1],
        d[2] * m.up[0] - d[0] * m.up[2],
        d[0] * m.up[1] - d[1] * m.up[0],
    ];
    if len2(c) < 1e-12 * len2(d) * len2(m.up).max(1e-30) {
        return Err("camera: up is parallel to the view direction".into());
    }
    Ok(m)
}

fn number(v: &Value, key: &str) -> Result<f64, String> {
    let x = v
        .get(key)
        .and_then(Value::as_f64)
        .ok_or_else(|| format!("{key}: expected a number"))?;
    if x.is_finite() && x.abs() < 1e9 {
        Ok(x)
    } else {
        Err(format!(
            "{key}: expected a finite number below 1e9, got {x}"
        ))
    }
}

fn vec3(v: &Value, key: &str) -> Result<[f32; 3], String> {
    let a = v
        .get(key)
        .and_then(Value::as_array)
        .filter(|a| a.len() == 3)
        .ok_or_else(|| format!("{key}: expected [x, y, z]"))?;
    let mut out = [0.0; 3];
    for (o, x) in out.iter_mut().zip(a) {
        let x = x
            .as_f64()
            .ok_or_else(|| format!("{key}: expected numbers"))?;
        if !(x.is_finite() && x.abs() < 1e9) {
            return Err(format!("{key}: expected finite numbers below 1e9"));
        }
        *o = x as f32;
    }
    Ok(out)
}

fn int_in(v: &Value, key: &str, lo: u32, hi: u32) -> Result<u32, String> {
    v.get(key)
        .and_then(Value::as_u64)
        .filter(|&x| x >= lo as u64 && x <= hi as u64)
        .map(|x| x as u32)
        .ok_or_else(|| format!("{key}: expected a whole number from {lo} to {hi}"))
}

fn name(v: &Value, key: &str, allowed: &[&str]) -> Result<Option<String>, String> {
    match v.get(key) {
        None => Ok(None),
        Some(x) => match x.as_str() {
            Some(s) if allowed.contains(&s) => Ok(Some(s.to_string())),
            _ => Err(format!("{key}: expected one of {}", allowed.join(", "))),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn well_formed_messages_parse() {
        let m = parse(
            r#"{"type":"camera","eye":[0,1,5],"look_at":[0,0,0],"up":[0,1,0],"fov":40,"moving":true}"#,
        )
        .unwrap();
        assert!(matches!(
            m,
            ClientMsg::Camera(CameraMsg { moving: true, .. })
        ));
        let s =
            parse(r#"{"type":"settings","integrator":"path","width":320,"height":240}"#).unwrap();
        assert_eq!(
            s,
            ClientMsg::Settings(SettingsMsg {
                integrator: Some("path".into()),
                size: Some((320, 240)),
                ..Default::default()
            })
        );
        assert_eq!(
            parse(r#"{"type":"settings","aperture_radius":0.1,"focus_distance":4}"#).unwrap(),
            ClientMsg::Settings(SettingsMsg {
                aperture_radius: Some(0.1),
                focus_distance: Some(4.0),
                ..Default::default()
            })
        );
        assert_eq!(
            parse(r#"{"type":"ack","frame":7}"#).unwrap(),
            ClientMsg::Ack(7)
        );
        assert_eq!(
            parse(r#"{"type":"play","playing":false}"#).unwrap(),
            ClientMsg::Play(false)
        );
        assert_eq!(
            parse(r#"{"type":"seek","frame":12}"#).unwrap(),
            ClientMsg::Seek(12)
        );
    }

    #[test]
    fn malformed_messages_are_refused_with_a_reason() {
        for (text, why) in [
            ("", "not JSON"),
            ("[1,2]", "object"),
            (r#"{"type":"launch"}"#, "unknown"),
            (
                r#"{"type":"camera","eye":[0,0],"look_at":[0,0,1],"up":[0,1,0],"fov":40}"#,
                "eye",
            ),
            (
                r#"{"type":"camera","eye":[0,0,0],"look_at":[0,0,0],"up":[0,1,0],"fov":40}"#,
                "coincide",
            ),
            (
                r#"{"type":"camera","eye":[0,0,0],"look_at":[0,1,0],"up":[0,1,0],"fov":40}"#,
                "parallel",
            ),
            (
                r#"{"type":"camera","eye":[0,0,0],"look_at":[0,0,1],"up":[0,1,0],"fov":1e300}"#,
                "fov",
            ),
            (r#"{"type":"settings","width":100000,"height":10}"#, "width"),
            (r#"{"type":"settings","spp":0}"#, "spp"),
            (
                r#"{"type":"settings","aperture_radius":-1}"#,
                "aperture_radius",
            ),
            (
                r#"{"type":"settings","focus_distance":0}"#,
                "focus_distance",
            ),
            (r#"{"type":"settings","accel":"../../etc/passwd"}"#, "accel"),
            (r#"{"type":"ack"}"#, "frame"),
            (r#"{"type":"play","playing":"yes"}"#, "playing"),
            (r#"{"type":"seek","frame":-1}"#, "seek"),
            (r#"{"type":"seek","frame":2.5}"#, "seek"),
            (r#"{"type":"seek","frame":4294967296}"#, "seek"),
            (r#"{"type":"seek"}"#, "seek"),
        ] {
            let e = parse(text).unwrap_err();
            assert!(e.contains(why), "{text}: {e}");
        }
    }
}
