//! The accept loop: one thread per connection, at most `max` at once (more get 503 at once),
//! every socket with read and write timeouts so a silent or vanished client cannot hold a
//! thread; Ctrl-C sets a flag that the loop and every session check, and the server waits
//! briefly for the sessions to close their sockets.

use super::{assets, http, lecture_api, session, Shared};
use anyhow::Result;
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use tungstenite::protocol::{Role, WebSocketConfig};
use tungstenite::WebSocket;

/// Largest WebSocket message (and frame) accepted from a page: its messages are small JSON.
pub const MAX_MESSAGE: usize = 64 * 1024;

pub fn serve(listener: TcpListener, shared: Arc<Shared>, max: usize) -> Result<()> {
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst));
    }
    serve_until(listener, shared, max, stop)
}

pub fn serve_until(
    listener: TcpListener,
    shared: Arc<Shared>,
    max: usize,
    stop: Arc<AtomicBool>,
) -> Result<()> {
    listener.set_nonblocking(true)?;
    let active = Arc::new(AtomicUsize::new(0));
    while !stop.load(Ordering::SeqCst) {
        let mut stream = match listener.accept() {
            Ok((s, _)) => s,
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(20));
                continue;
            }
            Err(_) => continue,
        };
        let _ = stream.set_nonblocking(false);
        let _ = stream.set_read_timeout(Some(Duration::from_secs(5)));
        let _ = stream.set_write_timeout(Some(Duration::from_secs(5)));
        let _ = stream.set_nodelay(true);
        if active.fetch_add(1, Ordering::SeqCst) >= max {
            active.fetch_sub(1, Ordering::SeqCst);
            http::error(&mut stream, "503 Service Unavailable");
            continue;
        }
        let (shared, stop, counter) = (shared.clone(), stop.clone(), active.clone());
        let spawned = std::thread::Builder::new()
            .name("appel-view-conn".into())
            .spawn(move || {
                handle(stream, &shared, &stop);
                counter.fetch_sub(1, Ordering::SeqCst);
            });
        if spawned.is_err() {
            // The slot was taken for a thread that never ran.
            active.fetch_sub(1, Ordering::SeqCst);
            eprintln!("warning: could not start a connection thread");
        }
    }
    let deadline = Instant::now() + Duration::from_secs(3);
    while active.load(Ordering::SeqCst) > 0 && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(20));
    }
    Ok(())
}

fn handle(mut stream: TcpStream, shared: &Shared, stop: &AtomicBool) {
    let req = match http::read_head(&mut stream) {
        Ok(r) => r,
        Err(http::HeadError::TooLarge) => {
            return http::error(&mut stream, "431 Request Header Fields Too Large")
        }
        Err(http::HeadError::Malformed) => return http::error(&mut stream, "400 Bad Request"),
        Err(http::HeadError::Gone) => return,
    };
    if req.method != "GET" {
        return http::error(&mut stream, "405 Method Not Allowed");
    }
    let path = match req.path.as_str() {
        "/" if shared.lecture_only => "/lecture.html",
        "/" => "/viewer.html",
        p => p,
    };
    if let Some(a) = assets::find(path) {
        return http::respond(&mut stream, "200 OK", a.content_type, a.body);
    }
    match path {
        "/api/lecture" => match lecture_api::answer(&req) {
            Ok(json) => http::respond(&mut stream, "200 OK", "application/json", json.as_bytes()),
            Err(e) => http::respond(
                &mut stream,
                "400 Bad Request",
                "text/plain; charset=utf-8",
                e.as_bytes(),
            ),
        },
        "/ws" if !shared.lecture_only => websocket(stream, &req, shared, stop),
        _ => http::error(&mut stream, "404 Not Found"),
    }
}

/// The WebSocket handshake (RFC 6455 section 4.2), then the viewer session.
fn websocket(mut stream: TcpStream, req: &http::Request, shared: &Shared, stop: &AtomicBool) {
    let upgrade = req
        .header("upgrade")
        .is_some_and(|u| u.eq_ignore_ascii_case("websocket"));
    let Some(key) = req.header("sec-websocket-key").filter(|_| upgrade) else {
        return http::error(&mut stream, "400 Bad Request");
    };
    let accept = tungstenite::handshake::derive_accept_key(key.as_bytes());
    let head = format!(
        "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
         Sec-WebSocket-Accept: {accept}\r\n\r\n"
    );
    if std::io::Write::write_all(&mut stream, head.as_bytes()).is_err() {
        return;
    }
    let config = WebSocketConfig {
        max_message_size: Some(MAX_MESSAGE),
        max_frame_size: Some(MAX_MESSAGE),
        ..Default::default()
    };
    let mut ws = WebSocket::from_raw_socket(stream, Role::Server, Some(config));
    session::run(&mut ws, shared, stop);
}
