//! `appel view` as a server: it serves its pages and nothing from disk, refuses malformed and
//! oversized requests and WebSocket messages without falling over, caps connections, survives a
//! client vanishing mid-frame, streams frames, plays animations, and stops on Ctrl-C.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use tungstenite::{Message, WebSocket};

struct Server {
    child: Child,
    addr: String,
}

impl Server {
    fn start(args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_appel"))
            .arg("view")
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("appel runs");
        let mut line = String::new();
        BufReader::new(child.stdout.as_mut().unwrap())
            .read_line(&mut line)
            .unwrap();
        let url = line
            .split_whitespace()
            .find(|w| w.starts_with("http://"))
            .unwrap_or_else(|| panic!("no URL in {line:?}"));
        let addr = url
            .trim_start_matches("http://")
            .trim_end_matches('/')
            .to_string();
        assert!(addr.starts_with("127.0.0.1:"), "binds loopback: {addr}");
        Server { child, addr }
    }

    fn get(&self, raw: &[u8]) -> String {
        let mut s = TcpStream::connect(&self.addr).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
        let _ = s.write_all(raw);
        let mut out = Vec::new();
        let _ = s.read_to_end(&mut out);
        String::from_utf8_lossy(&out).into_owned()
    }

    fn ws(&self) -> WebSocket<TcpStream> {
        let s = TcpStream::connect(&self.addr).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
        let (ws, _) = tungstenite::client(format!("ws://{}/ws", self.addr), s).expect("handshake");
        ws
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn status(response: &str) -> &str {
    response.lines().next().unwrap_or("")
}

/// Reads until a text message of type `kind`, returning it (binary frames are counted, frames
/// passed over are acknowledged).
fn until(ws: &mut WebSocket<TcpStream>, kind: &str, binaries: &mut usize) -> serde_json::Value {
    loop {
        match ws.read().expect("server still talking") {
            Message::Text(t) => {
                let v: serde_json::Value = serde_json::from_str(&t).unwrap();
                if v["type"] == kind {
                    return v;
                }
                if v["type"] == "frame" {
                    // Skipped frames are acknowledged, so the server goes on sending.
                    let ack = format!(r#"{{"type":"ack","frame":{}}}"#, v["id"]);
                    let _ = ws.send(Message::Text(ack));
                }
            }
            Message::Binary(b) => {
                assert_eq!(&b[..4], b"APF1");
                *binaries += 1;
            }
            _ => {}
        }
    }
}

/// Reads one frame (its info then its image), acknowledges it, returns the info and image.
fn frame(ws: &mut WebSocket<TcpStream>) -> (serde_json::Value, Vec<u8>) {
    let mut n = 0;
    let info = until(ws, "frame", &mut n);
    loop {
        if let Message::Binary(b) = ws.read().unwrap() {
            ws.send(Message::Text(format!(
                r#"{{"type":"ack","frame":{}}}"#,
                info["id"]
            )))
            .unwrap();
            return (info, b);
        }
    }
}

#[test]
fn serves_only_its_own_assets_and_refuses_bad_requests() {
    let s = Server::start(&["whitted", "--size", "64x48"]);
    let page = s.get(b"GET / HTTP/1.1\r\nHost: x\r\n\r\n");
    assert_eq!(status(&page), "HTTP/1.1 200 OK");
    assert!(page.contains("viewer.js"));
    assert!(status(&s.get(b"GET /viewer.js HTTP/1.1\r\n\r\n")).contains("200"));
    for path in [
        "/Cargo.toml",
        "/../Cargo.toml",
        "/%2e%2e/Cargo.toml",
        "/etc/passwd",
        "/assets/viewer.js",
    ] {
        let r = s.get(format!("GET {path} HTTP/1.1\r\n\r\n").as_bytes());
        assert_eq!(status(&r), "HTTP/1.1 404 Not Found", "{path}");
    }
    assert!(status(&s.get(b"POST / HTTP/1.1\r\n\r\n")).contains("405"));
    assert!(status(&s.get(b"GARBAGE\r\n\r\n")).contains("400"));
    let huge = format!("GET / HTTP/1.1\r\nX-Pad: {}\r\n\r\n", "a".repeat(20_000));
    assert!(status(&s.get(huge.as_bytes())).contains("431"));
    // A WebSocket request without the handshake's key.
    assert!(status(&s.get(b"GET /ws HTTP/1.1\r\nUpgrade: websocket\r\n\r\n")).contains("400"));
    // Still serving.
    assert!(status(&s.get(b"GET / HTTP/1.1\r\n\r\n")).contains("200"));
}

#[test]
fn streams_frames_that_refine_and_follow_the_camera() {
    let s = Server::start(&["whitted", "--size", "64x48", "--spp", "3"]);
    let mut ws = s.ws();
    let mut n = 0;
    let hello = until(&mut ws, "hello", &mut n);
    assert_eq!(hello["width"], 64);
    assert_eq!(hello["format"], "raw", "raw RGBA on loopback");
    let (first, img) = frame(&mut ws);
    assert_eq!(first["preview"], false);
    let word = |img: &[u8], k: usize| u32::from_le_bytes(img[4 * k..4 * k + 4].try_into().unwrap());
    assert_eq!((word(&img, 1), word(&img, 2), word(&img, 3)), (64, 48, 2));
    assert_eq!(img.len(), 16 + 64 * 48 * 4);
    assert!(img[16..].chunks(4).all(|p| p[3] == 255));
    let (second, _) = frame(&mut ws);
    assert_eq!(second["spp"], 2);
    // JPEG frames decode to the stated size.
    ws.send(Message::Text(
        r#"{"type":"settings","format":"jpeg"}"#.into(),
    ))
    .unwrap();
    let jpeg = loop {
        let (info, img) = frame(&mut ws);
        if word(&img, 3) == 0 && info["preview"] == false {
            break img;
        }
    };
    let decoded = image::load_from_memory(&jpeg[16..]).unwrap().to_rgb8();
    assert_eq!(decoded.dimensions(), (64, 48));
    // A moving camera gets a half-resolution preview.
    ws.send(Message::Text(
        r#"{"type":"camera","eye":[0,2,9],"look_at":[0,1,0],"up":[0,1,0],"fov":45,"moving":true}"#
            .into(),
    ))
    .unwrap();
    let preview = loop {
        let (info, img) = frame(&mut ws);
        if info["preview"] == true {
            break img;
        }
    };
    assert_eq!(u32::from_le_bytes(preview[4..8].try_into().unwrap()), 32);
    // PNG frames decode losslessly to the stated size.
    ws.send(Message::Text(
        r#"{"type":"settings","format":"png","aov":"normal"}"#.into(),
    ))
    .unwrap();
    let png = loop {
        let (info, img) = frame(&mut ws);
        if u32::from_le_bytes(img[12..16].try_into().unwrap()) == 1 && info["preview"] == false {
            break img;
        }
    };
    let decoded = image::load_from_memory(&png[16..]).unwrap().to_rgb8();
    assert_eq!(decoded.dimensions(), (64, 48));
}

#[test]
fn malformed_websocket_messages_get_errors_and_the_session_goes_on() {
    let s = Server::start(&["whitted", "--size", "32x24", "--spp", "1"]);
    let mut ws = s.ws();
    let mut n = 0;
    until(&mut ws, "hello", &mut n);
    for bad in [
        "not json",
        r#"{"type":"camera","eye":[1e400,0,0]}"#,
        r#"{"type":"settings","width":999999,"height":1}"#,
        r#"{"type":"settings","accel":"/etc/passwd"}"#,
        r#"{"no":"type"}"#,
        // Not an animated scene.
        r#"{"type":"play","playing":true}"#,
        r#"{"type":"seek","frame":0}"#,
    ] {
        ws.send(Message::Text(bad.into())).unwrap();
        let e = until(&mut ws, "error", &mut n);
        assert!(e["message"].as_str().unwrap().len() > 3);
    }
    ws.send(Message::Binary(vec![1, 2, 3])).unwrap();
    until(&mut ws, "error", &mut n);
    // A valid change still works afterwards.
    ws.send(Message::Text(
        r#"{"type":"settings","integrator":"raycast","spp":2}"#.into(),
    ))
    .unwrap();
    let (info, _) = frame(&mut ws);
    assert_eq!(info["integrator"], "raycast");
    // An oversized message ends that connection only.
    let _ = ws.send(Message::Text("x".repeat(200_000)));
    let closed = (0..100).any(|_| ws.read().is_err());
    assert!(closed);
    let mut again = s.ws();
    until(&mut again, "hello", &mut n);
}

#[test]
fn connection_flood_is_capped_and_the_server_recovers() {
    let s = Server::start(&["whitted", "--size", "32x24", "--max-connections", "4"]);
    // Idle connections that never send a request hold their slots.
    let idle: Vec<TcpStream> = (0..4)
        .map(|_| TcpStream::connect(&s.addr).unwrap())
        .collect();
    std::thread::sleep(Duration::from_millis(300));
    let refused = s.get(b"GET / HTTP/1.1\r\n\r\n");
    assert!(status(&refused).contains("503"), "{refused}");
    drop(idle);
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        let r = s.get(b"GET / HTTP/1.1\r\n\r\n");
        if status(&r).contains("200") {
            break;
        }
        assert!(Instant::now() < deadline, "server did not recover: {r}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn a_client_vanishing_mid_frame_leaves_the_server_serving() {
    let s = Server::start(&["whitted", "--size", "32x24"]);
    for _ in 0..3 {
        let mut ws = s.ws();
        let mut n = 0;
        until(&mut ws, "hello", &mut n);
        // Large frames, then the socket is dropped while one is on its way.
        ws.send(Message::Text(
            r#"{"type":"settings","width":1600,"height":1200,"format":"raw"}"#.into(),
        ))
        .unwrap();
        until(&mut ws, "frame", &mut n);
        drop(ws);
    }
    let mut ws = s.ws();
    ws.send(Message::Text(
        r#"{"type":"settings","width":32,"height":24}"#.into(),
    ))
    .unwrap();
    let (_, img) = frame(&mut ws);
    assert_eq!(&img[..4], b"APF1");
}

#[test]
fn ctrl_c_stops_the_server_cleanly() {
    let mut s = Server::start(&["--lecture"]);
    let page = s.get(b"GET / HTTP/1.1\r\n\r\n");
    assert!(page.contains("lecture.js"));
    let api =
        s.get(b"GET /api/lecture?scene=figures&structure=bvh-sah&ray=5,5,95,90 HTTP/1.1\r\n\r\n");
    assert!(status(&api).contains("200"));
    let body = &api[api.find("\r\n\r\n").unwrap() + 4..];
    let v: serde_json::Value = serde_json::from_str(body).unwrap();
    assert!(!v["steps"].as_array().unwrap().is_empty());
    assert_eq!(v["trace"]["hit"], v["brute_force_hit"]);
    let bad = s.get(b"GET /api/lecture?n=100000 HTTP/1.1\r\n\r\n");
    assert!(status(&bad).contains("400"));
    let _idle = TcpStream::connect(&s.addr).unwrap();
    unsafe { libc::kill(s.child.id() as i32, libc::SIGINT) };
    let start = Instant::now();
    let code = loop {
        if let Some(c) = s.child.try_wait().unwrap() {
            break c;
        }
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "still running after Ctrl-C"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    assert!(code.success(), "{code:?}");
}

/// `appel gen cloth` at a small size: 48 frames of a waving flag and keyframed birds.
fn small_cloth() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_appel"))
        .args(["gen", "cloth", "--detail", "0.01", "--quiet", "-o"])
        .arg(dir.path())
        .status()
        .unwrap();
    assert!(status.success());
    dir
}

#[test]
fn an_animation_plays_by_refitting_pauses_and_refuses_bad_frame_selections() {
    let dir = small_cloth();
    let scene = dir.path().join("cloth.toml");
    let s = Server::start(&[scene.to_str().unwrap(), "--size", "48x36", "--spp", "2"]);
    let mut ws = s.ws();
    let mut n = 0;
    let hello = until(&mut ws, "hello", &mut n);
    assert_eq!(hello["frames"], 48);
    // Paused at first: still passes of frame 0.
    let (first, _) = frame(&mut ws);
    assert_eq!(
        (first["anim_frame"].as_u64(), first["preview"].as_bool()),
        (Some(0), Some(false))
    );
    for bad in [
        r#"{"type":"seek","frame":48}"#,
        r#"{"type":"seek","frame":-1}"#,
        r#"{"type":"seek","frame":"3"}"#,
        r#"{"type":"seek"}"#,
        r#"{"type":"play"}"#,
    ] {
        ws.send(Message::Text(bad.into())).unwrap();
        let e = until(&mut ws, "error", &mut n);
        let text = e["message"].as_str().unwrap();
        assert!(
            text.contains("seek") || text.contains("play"),
            "{bad}: {text}"
        );
    }
    // Playing: previews of successive frames, each reached by refitting the flag's BVH.
    ws.send(Message::Text(r#"{"type":"play","playing":true}"#.into()))
        .unwrap();
    let mut shown = Vec::new();
    while shown.len() < 6 {
        let (info, _) = frame(&mut ws);
        if info["preview"] == true {
            let step = &info["step"];
            assert_eq!(step["frame"], info["anim_frame"]);
            assert!(step["refitted"].as_u64().unwrap() >= 1, "{step}");
            assert!(step["refit_ms"].as_f64().unwrap() >= 0.0);
            shown.push(info["anim_frame"].as_u64().unwrap());
        }
    }
    assert!(
        shown.windows(2).all(|w| w[1] == (w[0] + 1) % 48),
        "{shown:?}"
    );
    // Paused: the frame stays and converges.
    ws.send(Message::Text(r#"{"type":"play","playing":false}"#.into()))
        .unwrap();
    let mut stills = Vec::new();
    while stills
        .last()
        .is_none_or(|i: &serde_json::Value| i["spp"] != 2)
    {
        let (info, _) = frame(&mut ws);
        if info["preview"] == false {
            stills.push(info);
        }
    }
    let paused_at = stills[0]["anim_frame"].as_u64().unwrap();
    assert!(stills
        .iter()
        .all(|i| i["anim_frame"] == paused_at && i["playing"] == false));
    // Paused on the frame playing reached, a few frames past the last one read.
    assert!(
        (paused_at + 48 - shown[5]) % 48 <= 8,
        "{paused_at} after {shown:?}"
    );
    // Seeking shows the frame asked for, and an image that differs from frame 0's.
    ws.send(Message::Text(r#"{"type":"seek","frame":20}"#.into()))
        .unwrap();
    let (at20, img20) = loop {
        let (info, img) = frame(&mut ws);
        if info["anim_frame"] == 20 && info["spp"] == 2 {
            break (info, img);
        }
    };
    assert_eq!(at20["preview"], false);
    ws.send(Message::Text(r#"{"type":"seek","frame":0}"#.into()))
        .unwrap();
    let img0 = loop {
        let (info, img) = frame(&mut ws);
        if info["anim_frame"] == 0 && info["spp"] == 2 {
            break img;
        }
    };
    assert_ne!(img0, img20);
}
