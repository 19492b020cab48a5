//! The pages' files, compiled into the binary: the server answers only these paths, so no
//! request can name a file on disk.

pub struct Asset {
    pub path: &'static str,
    pub content_type: &'static str,
    pub body: &'static [u8],
}

const HTML: &str = "text/html; charset=utf-8";
const JS: &str = "text/javascript; charset=utf-8";
const CSS: &str = "text/css; charset=utf-8";

pub const ASSETS: &[Asset] = &[
    Asset {
        path: "/viewer.html",
        content_type: HTML,
        body: include_bytes!("assets/viewer.html"),
    },
    Asset {
        path: "/viewer.js",
        content_type: JS,
        body: include_bytes!("assets/viewer.js"),
    },
    Asset {
        path: "/lecture.html",
        content_type: HTML,
        body: include_bytes!("assets/lecture.html"),
    },
    Asset {
        path: "/lecture.js",
        content_type: JS,
        body: include_bytes!("assets/lecture.js"),
    },
    Asset {
        path: "/style.css",
        content_type: CSS,
        body: include_bytes!("assets/style.css"),
    },
];

pub fn find(path: &str) -> Option<&'static Asset> {
    ASSETS.iter().find(|a| a.path == path)
}
