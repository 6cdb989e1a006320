//! The preview's HTTP side: the page (embedded in the binary), the event stream of what it
//! shows, the picture as PNG and EXR (and its denoised view, only when the preview denoises),
//! and the tone mapping the page chooses. Nothing else is served: no path reaches the file
//! system.

use std::io::Write;
use std::net::SocketAddr;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use tiny_http::{Header, Method, Request, Response};

use crate::OutputFormat;
use crate::image::{Image, RenderInfo};
use crate::tonemap::{Operator, ToneMap, ToneMapError};

use super::shown::Shown;

const PAGE: &str = include_str!("page.html");
const SCRIPT: &str = include_str!("page.js");
const STYLE: &str = include_str!("page.css");
/// The page's choice between the pass as rendered and its denoised view, and the save of the
/// latter: only in the page of a preview that denoises.
const DENOISED_VIEW: &str = include_str!("denoised-view.html");

/// How long an event stream waits for a change before it sends a comment: a closed page is
/// noticed then, and its thread ends.
const KEEP_ALIVE: Duration = Duration::from_secs(10);

/// The most event streams open at once, each a thread: pages of the preview open in tabs (a
/// client opening thousands is refused, not given thousands of threads).
pub const MAX_STREAMS: usize = 64;

/// What the server serves, and to whom.
pub struct Site {
    /// The page, with the scene's name.
    page: String,
    /// Whether the preview denoises its passes: only then are the denoised view's paths served.
    denoising: bool,
    /// The `Host` a request must name when the preview listens on loopback only: another one is
    /// a page of another site that had its name resolve to this machine (DNS rebinding), which
    /// must not read the scene's errors. `None`: listening for other machines, any name.
    hosts: Option<[String; 2]>,
    streams: AtomicUsize,
}

impl Site {
    pub fn new(scene: &Path, address: SocketAddr, denoising: bool) -> Site {
        let hosts = address
            .ip()
            .is_loopback()
            .then(|| [address.to_string(), format!("localhost:{}", address.port())]);
        Site { page: page(scene, denoising), denoising, hosts, streams: AtomicUsize::new(0) }
    }

    fn admits(&self, request: &Request) -> bool {
        let Some(hosts) = &self.hosts else { return true };
        let host = request.headers().iter().find(|h| h.field.equiv("Host"));
        host.is_some_and(|h| {
            hosts.iter().any(|allowed| h.value.as_str().eq_ignore_ascii_case(allowed))
        })
    }
}

/// Answers one request.
pub fn respond(request: Request, shown: &Shown, site: &Site) {
    if !site.admits(&request) {
        let refused = text("this preview answers to its own address only\n".into(), "text/plain");
        let _ = request.respond(refused.with_status_code(403));
        return;
    }
    let url = request.url().to_string();
    let (path, query) = url.split_once('?').unwrap_or((&url, ""));
    // A failed answer is the client's going away: nothing to do about it.
    let _ = match (request.method(), path) {
        (Method::Get, "/") => request.respond(text(site.page.clone(), "text/html; charset=utf-8")),
        (Method::Get, "/page.js") => request.respond(text(SCRIPT.into(), "text/javascript")),
        (Method::Get, "/page.css") => request.respond(text(STYLE.into(), "text/css")),
        (Method::Get, "/events") => {
            if site.streams.fetch_add(1, Ordering::SeqCst) < MAX_STREAMS {
                let streamed = stream(request, shown);
                site.streams.fetch_sub(1, Ordering::SeqCst);
                streamed
            } else {
                site.streams.fetch_sub(1, Ordering::SeqCst);
                let busy = format!("more than {MAX_STREAMS} pages are open\n");
                request.respond(text(busy, "text/plain").with_status_code(503))
            }
        }
        (Method::Get, "/image.png") => match shown.png() {
            Some(png) => request.respond(bytes(png, "image/png")),
            None => request.respond(not_found()),
        },
        (Method::Get, "/denoised.png") if site.denoising => match shown.denoised_png() {
            Some(png) => request.respond(bytes(png, "image/png")),
            None => request.respond(not_found()),
        },
        // Copied out, so that passes are not held up while the file is written.
        (Method::Get, "/image.exr") => {
            let render = shown.with_picture(|p| (p.image.clone(), p.info.clone()));
            respond_exr(request, render)
        }
        (Method::Get, "/denoised.exr") if site.denoising => {
            let denoised = shown
                .with_picture(|p| p.denoised.as_ref().map(|d| (d.image.clone(), d.info.clone())));
            respond_exr(request, denoised.flatten())
        }
        (Method::Post, "/tonemap") => match tone_map(query) {
            Ok(tone_map) => {
                shown.set_tone_map(tone_map);
                request.respond(text(String::new(), "text/plain").with_status_code(204))
            }
            Err(e) => request.respond(text(e.to_string(), "text/plain").with_status_code(400)),
        },
        _ => request.respond(not_found()),
    };
}

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name, value).expect("the header names and values here are ASCII")
}

fn text(body: String, kind: &str) -> Response<std::io::Cursor<Vec<u8>>> {
    bytes(body.into_bytes(), kind)
}

fn bytes(body: Vec<u8>, kind: &str) -> Response<std::io::Cursor<Vec<u8>>> {
    Response::from_data(body)
        .with_header(header("Content-Type", kind))
        .with_header(header("Cache-Control", "no-store"))
}

fn not_found() -> Response<std::io::Cursor<Vec<u8>>> {
    text("not found\n".into(), "text/plain").with_status_code(404)
}

/// The page, with the scene's name, the tone-mapping operators and, when the preview denoises,
/// the choice of the denoised view.
fn page(scene: &Path, denoising: bool) -> String {
    let name = |p: Option<&std::ffi::OsStr>| escape(&p.unwrap_or_default().to_string_lossy());
    let operators: String =
        Operator::ALL.iter().map(|op| format!(r#"<option value="{op}">{op}</option>"#)).collect();
    PAGE.replace("{{denoised-view}}", if denoising { DENOISED_VIEW } else { "" })
        .replace("{{scene}}", &name(scene.file_name()))
        .replace("{{stem}}", &name(scene.file_stem()))
        .replace("{{operators}}", &operators)
}

/// Text made safe to put in HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace('\'', "&#39;")
}

/// Server-Sent Events: the state now, then each change, until the page goes.
fn stream(request: Request, shown: &Shown) -> std::io::Result<()> {
    let mut writer = request.into_writer();
    writer.write_all(
        b"HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nCache-Control: no-store\r\n\
          Connection: close\r\n\r\n",
    )?;
    let mut seen = 0;
    loop {
        match shown.events_after(seen, KEEP_ALIVE) {
            Some((version, events)) => {
                seen = version;
                writer.write_all(events.as_bytes())?;
            }
            None => writer.write_all(b": waiting for a change\n\n")?,
        }
        writer.flush()?;
    }
}

/// An image as an OpenEXR file, with its render's metadata; 404 before there is one.
fn respond_exr(request: Request, image: Option<(Image, RenderInfo)>) -> std::io::Result<()> {
    let Some((image, info)) = image else { return request.respond(not_found()) };
    let write = || {
        let folder = tempfile::tempdir().map_err(|e| e.to_string())?;
        let path = folder.path().join("preview.exr");
        crate::write_image(&path, &OutputFormat::Exr, &image, None, &info)
            .map_err(|e| e.to_string())?;
        std::fs::read(&path).map_err(|e| e.to_string())
    };
    match write() {
        Ok(exr) => request.respond(bytes(exr, "image/x-exr")),
        Err(message) => request.respond(text(message, "text/plain").with_status_code(500)),
    }
}

/// A tone mapping the page cannot ask for.
#[derive(Debug, thiserror::Error)]
enum ToneMapQueryError {
    #[error(transparent)]
    ToneMap(#[from] ToneMapError),
    #[error("exposure `{0}` is not a number")]
    Exposure(String),
    #[error("unknown tone-mapping parameter `{0}`")]
    Unknown(String),
}

/// The tone mapping `op=NAME&exposure=EV` asks for.
fn tone_map(query: &str) -> Result<ToneMap, ToneMapQueryError> {
    let mut tone_map = ToneMap::default();
    for pair in query.split('&').filter(|pair| !pair.is_empty()) {
        match pair.split_once('=') {
            Some(("op", name)) => tone_map.op = name.parse()?,
            Some(("exposure", ev)) => {
                tone_map.exposure =
                    ev.parse().map_err(|_| ToneMapQueryError::Exposure(ev.to_string()))?;
            }
            _ => return Err(ToneMapQueryError::Unknown(pair.to_string())),
        }
    }
    tone_map.validate()?;
    Ok(tone_map)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_names_the_scene_escaped_and_offers_every_operator() {
        for denoising in [false, true] {
            let page = page(Path::new("dir/<b>.scn"), denoising);
            assert!(page.contains("<h1>&lt;b&gt;.scn</h1>"), "{page}");
            assert!(!page.contains("{{"));
            for op in Operator::ALL {
                assert!(page.contains(&format!(r#"<option value="{op}">"#)), "{op}");
            }
            // The denoised view's choice only where there is one; its save is named after the
            // scene too.
            assert_eq!(page.contains(r#"name="view""#), denoising);
            assert_eq!(page.contains(r#"download="&lt;b&gt;-denoised.exr""#), denoising);
        }
    }

    #[test]
    fn tone_maps_are_read_from_the_query_and_bad_ones_named() {
        let aces = tone_map("op=aces&exposure=-1.5").unwrap();
        assert_eq!((aces.op, aces.exposure), (Operator::Aces, -1.5));
        assert_eq!(tone_map("").unwrap(), ToneMap::default());
        assert!(tone_map("op=sepia").unwrap_err().to_string().contains("sepia"));
        assert!(tone_map("exposure=bright").unwrap_err().to_string().contains("bright"));
        assert!(tone_map("exposure=inf").is_err());
        assert!(tone_map("white=2").unwrap_err().to_string().contains("white=2"));
    }
}
