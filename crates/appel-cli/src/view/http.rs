//! Just enough HTTP/1.1 for the viewer: one GET per connection, its head read with a size and
//! time bound, answered with `Connection: close`.

use std::io::{Read, Write};
use std::net::TcpStream;

/// Largest request head accepted (request line and headers); longer heads get 431.
pub const MAX_HEAD: usize = 8 * 1024;

#[derive(Debug)]
pub struct Request {
    pub method: String,
    /// The path, without the query.
    pub path: String,
    pub query: String,
    pub headers: Vec<(String, String)>,
}

impl Request {
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|(_, v)| v.as_str())
    }

    /// `key=value` pairs of the query string, percent-decoded (pages encode the commas of
    /// coordinate lists).
    pub fn query_pairs(&self) -> impl Iterator<Item = (String, String)> + '_ {
        self.query
            .split('&')
            .filter(|p| !p.is_empty())
            .map(|p| p.split_once('=').unwrap_or((p, "")))
            .map(|(k, v)| (percent_decode(k), percent_decode(v)))
    }
}

/// `%2C` to `,` and `+` to a space; a malformed escape stays as it is.
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        match b[i] {
            b'%' if i + 2 < b.len() => match (hex(b[i + 1]), hex(b[i + 2])) {
                (Some(h), Some(l)) => {
                    out.push((h * 16 + l) as u8);
                    i += 3;
                    continue;
                }
                _ => out.push(b'%'),
            },
            b'+' => out.push(b' '),
            c => out.push(c),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[derive(Debug, PartialEq)]
pub enum HeadError {
    TooLarge,
    Malformed,
    /// The peer closed or timed out before a full head arrived.
    Gone,
}

/// Reads up to the blank line ending the head. Bytes after it (a request body) are ignored: only
/// GET is served.
pub fn read_head(stream: &mut TcpStream) -> Result<Request, HeadError> {
    let mut buf = Vec::with_capacity(1024);
    let mut chunk = [0u8; 1024];
    loop {
        let n = stream.read(&mut chunk).map_err(|_| HeadError::Gone)?;
        if n == 0 {
            return Err(HeadError::Gone);
        }
        buf.extend_from_slice(&chunk[..n]);
        if let Some(end) = find_end(&buf) {
            return parse_head(&buf[..end]);
        }
        if buf.len() > MAX_HEAD {
            return Err(HeadError::TooLarge);
        }
    }
}

fn find_end(buf: &[u8]) -> Option<usize> {
    buf.windows(4).position(|w| w == b"\r\n\r\n")
}

pub fn parse_head(head: &[u8]) -> Result<Request, HeadError> {
    let text = std::str::from_utf8(head).map_err(|_| HeadError::Malformed)?;
    let mut lines = text.split("\r\n");
    let mut first = lines.next().ok_or(HeadError::Malformed)?.split(' ');
    let (Some(method), Some(target), Some(version), None) =
        (first.next(), first.next(), first.next(), first.next())
    else {
        return Err(HeadError::Malformed);
    };
    if !version.starts_with("HTTP/1.") || !target.starts_with('/') {
        return Err(HeadError::Malformed);
    }
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let mut headers = Vec::new();
    for line in lines {
        let (name, value) = line.split_once(':').ok_or(HeadError::Malformed)?;
        if headers.len() >= 64 {
            return Err(HeadError::TooLarge);
        }
        headers.push((name.trim().to_string(), value.trim().to_string()));
    }
    Ok(Request {
        method: method.to_string(),
        path: path.to_string(),
        query: query.to_string(),
        headers,
    })
}

pub fn respond(stream: &mut TcpStream, status: &str, content_type: &str, body: &[u8]) {
    let head = format!(
        "HTTP/1.1 {status}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\n\
         Cache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n",
        body.len()
    );
    let _ = stream.write_all(head.as_bytes());
    let _ = stream.write_all(body);
    let _ = stream.flush();
}

pub fn error(stream: &mut TcpStream, status: &str) {
    respond(
        stream,
        status,
        "text/plain; charset=utf-8",
        status.as_bytes(),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heads_parse_and_bad_ones_are_refused() {
        let r =
            parse_head(b"GET /api/lecture?n=5&s=grid HTTP/1.1\r\nHost: x\r\nUpgrade: websocket")
                .unwrap();
        assert_eq!(
            (r.method.as_str(), r.path.as_str()),
            ("GET", "/api/lecture")
        );
        let pairs: Vec<(String, String)> = r.query_pairs().collect();
        assert_eq!(
            pairs,
            [("n".into(), "5".into()), ("s".into(), "grid".into())]
        );
        assert_eq!(percent_decode("1%2C2%2c3+x%zz%4"), "1,2,3 x%zz%4");
        assert_eq!(r.header("upgrade"), Some("websocket"));
        for bad in [
            &b"GET / HTTP/1.1 extra"[..],
            b"GET",
            b"GET http://x/ HTTP/1.1",
            b"GET / SPDY/3",
            b"GET / HTTP/1.1\r\nno colon here",
            b"\xff\xfe / HTTP/1.1",
        ] {
            assert_eq!(
                parse_head(bad).unwrap_err(),
                HeadError::Malformed,
                "{bad:?}"
            );
        }
    }
}
