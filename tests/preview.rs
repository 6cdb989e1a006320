//! `raydiance preview` without a browser: the event stream announces each pass, a save of the
//! scene or of a file it includes starts the render again, an error is announced with its place
//! beside the last picture, nothing outside the page is served, and only this machine is
//! listened on unless asked. (`preview_browser.rs` drives the page in a real browser.)

use crate::common;

use std::io::{BufRead, BufReader};
use std::net::{SocketAddr, TcpStream, UdpSocket};
use std::os::unix::fs::PermissionsExt;
use std::sync::Mutex;

use common::preview::{Preview, picture, small_scene};
use raydiance::film::Film;
use raydiance::progress::Progress;

/// Each finished pass's samples per pixel, as a progress hears them.
#[derive(Default)]
struct Passes(Mutex<Vec<u32>>);

impl Progress for Passes {
    fn advance(&self, _: u64) {}

    fn pass_done(&self, film: &Film) {
        assert_eq!(film.image().pixels.len(), film.width * film.height);
        self.0.lock().unwrap().push(film.samples);
    }
}

#[test]
fn every_integrator_reports_its_passes_as_their_samples_double() {
    for (integrator, samples, passes) in [
        ("path", 12, vec![1, 2, 4, 8, 12]),
        ("direct", 3, vec![1, 2, 3]),
        ("photon", 2, vec![1, 2]),
        // sppm's iterations are reported at the same doubling counts.
        ("sppm", 5, vec![1, 2, 4]),
    ] {
        let scene = common::scene(&format!(
            "settings {{ resolution 4, 3  samples {samples}  integrator {integrator} \
             photons 1000 }}\nlight_source {{ <0, 0.5, 0>  power rgb 1 }}\n{}",
            common::LAB_BOX
        ));
        let heard = Passes::default();
        raydiance::render::render(&scene, &heard);
        assert_eq!(*heard.0.lock().unwrap(), passes, "{integrator}");
    }
}

#[test]
fn the_event_stream_announces_each_pass_up_to_the_scene_s_samples() {
    let dir = tempfile::tempdir().unwrap();
    let preview = Preview::start(&small_scene(dir.path(), 16), &["--listen", "127.0.0.1:0"]);
    let states = preview.events().until(|state| picture(state) == Some((16, 1)));
    let mut spp: Vec<u64> = states.iter().filter_map(|e| picture(&e.json())).map(|p| p.0).collect();
    // A pass's denoised view, when built with `denoise`, is a state of the same pass.
    spp.dedup();
    // The stream sends the latest state: a pass done before it opened may be skipped.
    assert!(spp.windows(2).all(|w| w[1] == w[0] * 2), "{spp:?}");
    let last = states.last().unwrap().json();
    assert_eq!((&last["picture"]["width"], &last["picture"]["target"]), (&32.into(), &16.into()));
    assert_eq!(last["error"], false);
    // The image saved is the last pass's.
    let (status, exr) = preview.get("/image.exr");
    assert_eq!(status, 200);
    let image = raydiance::image::exr::read_bytes(&exr).unwrap();
    assert_eq!((image.width, image.height), (32, 32));
    let (status, png) = preview.get("/image.png");
    assert_eq!((status, &png[1..4]), (200, &b"PNG"[..]));
    // A denoised view only from a raydiance built with `denoise` (tests/denoise.rs).
    assert_eq!(last["denoising"], cfg!(feature = "denoise"));
    if !cfg!(feature = "denoise") {
        assert_eq!(last["picture"]["denoised"], false);
        assert_eq!(preview.get("/denoised.png").0, 404);
        assert_eq!(preview.get("/denoised.exr").0, 404);
    }
}

#[test]
fn a_pov_scene_is_previewed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("ball.pov");
    std::fs::write(
        &scene,
        "camera { location <0, 0, -4> look_at <0, 0, 0> }\n\
         light_source { <2, 4, -3> color rgb 1 }\n\
         sphere { 0, 1 pigment { color rgb <1, 0.5, 0.2> } }\n",
    )
    .unwrap();
    let args = ["--listen", "127.0.0.1:0"];
    let preview = Preview::start(&scene, &args);
    let states = preview.events().until(|state| picture(state).is_some());
    let state = states.last().unwrap().json();
    assert_eq!(state["error"], false, "{states:#?}");
    // POV-Ray's default image size.
    assert_eq!(state["picture"]["width"], 320);
}

#[test]
fn a_save_of_an_included_file_renders_the_scene_again() {
    let dir = tempfile::tempdir().unwrap();
    let preview = Preview::start(&small_scene(dir.path(), 4), &["--listen", "127.0.0.1:0"]);
    let mut events = preview.events();
    events.until(|state| picture(state) == Some((4, 1)));
    let before = preview.get("/image.png").1;
    let include = dir.path().join("lab-box.inc");
    let text = std::fs::read_to_string(&include).unwrap();
    std::fs::write(&include, text.replace("0.2, 0.4, 0.8", "0.9, 0.1, 0.1")).unwrap();
    events.until(|state| picture(state) == Some((4, 2)));
    assert_ne!(preview.get("/image.png").1, before, "the blue sphere turned red");
}

#[test]
fn an_error_is_announced_with_its_place_and_the_last_picture_is_kept_until_it_is_fixed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = small_scene(dir.path(), 2);
    let preview = Preview::start(&scene, &["--listen", "127.0.0.1:0"]);
    let mut events = preview.events();
    events.until(|state| picture(state) == Some((2, 1)));
    let good = std::fs::read_to_string(&scene).unwrap();
    // Line 3 is the light: its brace dropped.
    std::fs::write(&scene, good.replace("object { CeilingLight }", "object { CeilingLight"))
        .unwrap();
    let seen = events.until(|state| state["error"] == true);
    let error = &seen.iter().rev().find(|e| e.name == "scene-error").unwrap().data;
    let expected = raydiance::load(&scene, &Default::default()).err().unwrap().to_string();
    assert_eq!(*error, expected, "the terminal's text");
    assert!(error.contains("scene.scn:4:1: error"), "{error}");
    assert!(error.contains("\n  |"), "the caret's lines: {error}");
    let state = seen.last().unwrap().json();
    assert_eq!(picture(&state), Some((2, 1)), "the last good picture stays");
    assert_eq!(preview.get("/image.png").0, 200);
    std::fs::write(&scene, good).unwrap();
    let fixed = events.until(|state| picture(state).is_some_and(|(_, render)| render > 2));
    assert_eq!(fixed.last().unwrap().json()["error"], false);
}

#[test]
fn nothing_but_the_page_is_served() {
    let dir = tempfile::tempdir().unwrap();
    let preview = Preview::start(&small_scene(dir.path(), 1), &["--listen", "127.0.0.1:0"]);
    let (status, page) = preview.get("/");
    assert_eq!(status, 200);
    let page = String::from_utf8(page).unwrap();
    assert!(page.contains("<h1>scene.scn</h1>") && page.contains("/page.js"), "{page}");
    // The choice of a denoised view only in the page of a preview that denoises
    // (tests/denoise.rs).
    assert_eq!(page.contains(r#"name="view""#), cfg!(feature = "denoise"), "{page}");
    for (path, text) in [("/page.js", "EventSource"), ("/page.css", "body")] {
        let (status, body) = preview.get(path);
        assert_eq!(status, 200, "{path}");
        assert!(String::from_utf8(body).unwrap().contains(text), "{path}");
    }
    for path in [
        "/../Cargo.toml",
        "/%2e%2e/Cargo.toml",
        "/Cargo.toml",
        "/src/main.rs",
        "/page.html",
        "//etc/passwd",
        "/scene.scn",
        "/lab-box.inc",
    ] {
        let (status, body) = preview.get(path);
        assert_eq!(status, 404, "{path}");
        assert_eq!(body, b"not found\n", "{path}");
    }
    // The tone mapping is only set, never read from a path, and bad values are refused.
    assert_eq!(common::preview::request(preview.address, "GET", "/tonemap?op=aces").0, 404);
    assert_eq!(common::preview::request(preview.address, "POST", "/tonemap?op=x").0, 400);
    assert_eq!(common::preview::request(preview.address, "POST", "/tonemap?op=aces").0, 204);
}

#[test]
fn a_page_of_another_site_is_refused_even_on_this_machine() {
    let dir = tempfile::tempdir().unwrap();
    let preview = Preview::start(&small_scene(dir.path(), 1), &["--listen", "127.0.0.1:0"]);
    let port = preview.address.port();
    let to = |host: &str| common::preview::request_to(preview.address, host, "GET", "/").0;
    assert_eq!(to(&format!("localhost:{port}")), 200);
    assert_eq!(to(&format!("127.0.0.1:{port}")), 200);
    // A name of another site made to resolve to 127.0.0.1 (DNS rebinding).
    assert_eq!(to(&format!("attacker.example:{port}")), 403);
    assert_eq!(to("127.0.0.1:1"), 403);
    // Asked to listen for other machines, any name is theirs.
    let everywhere = Preview::start(&small_scene(dir.path(), 1), &["--listen", "0.0.0.0:0"]);
    let host = format!("attacker.example:{}", everywhere.address.port());
    let (status, _) = common::preview::request_to(everywhere.address, &host, "GET", "/");
    assert_eq!(status, 200);
}

#[test]
fn a_missing_scene_or_a_taken_address_is_an_error_before_serving() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.scn");
    let stderr = Preview::try_start(&missing, &["--listen", "127.0.0.1:0"]).err().unwrap();
    assert!(stderr.contains("missing.scn") && stderr.contains("error"), "{stderr}");
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let taken = listener.local_addr().unwrap();
    let scene = small_scene(dir.path(), 1);
    let stderr = Preview::try_start(&scene, &["--listen", &taken.to_string()]).err().unwrap();
    assert!(stderr.contains(&format!("error: cannot listen on {taken}")), "{stderr}");
}

#[test]
fn event_streams_past_the_most_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let preview = Preview::start(&small_scene(dir.path(), 1), &["--listen", "127.0.0.1:0"]);
    let open: Vec<_> = (0..raydiance::preview::MAX_STREAMS).map(|_| preview.events()).collect();
    assert_eq!(common::preview::status(preview.address, "/events"), 503);
    drop(open);
    // A closed page's stream ends at its next write (a state, or the keep-alive comment).
    let start = std::time::Instant::now();
    while common::preview::status(preview.address, "/events") != 200 {
        assert!(start.elapsed() < common::preview::PATIENCE, "the streams never closed");
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
}

#[test]
fn the_tone_mapping_chosen_in_the_page_is_applied_to_the_picture() {
    let dir = tempfile::tempdir().unwrap();
    let preview = Preview::start(&small_scene(dir.path(), 2), &["--listen", "127.0.0.1:0"]);
    let mut events = preview.events();
    events.until(|state| picture(state) == Some((2, 1)));
    let (_, before) = preview.get("/image.png");
    let (status, _) =
        common::preview::request(preview.address, "POST", "/tonemap?op=aces&exposure=2");
    assert_eq!(status, 204);
    let state = events.until(|state| state["operator"] == "aces");
    assert_eq!(state.last().unwrap().json()["exposure"], 2.0);
    let (_, after) = preview.get("/image.png");
    assert_ne!(before, after);
    // Tone mapping is the page's, not the render's: the saved image is the same linear one.
    let exr = raydiance::image::exr::read_bytes(&preview.get("/image.exr").1).unwrap();
    let rendered = dir.path().join("rendered.exr");
    let scene = dir.path().join("scene.scn");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["render", scene.to_str().unwrap(), "-o", rendered.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert_eq!(exr.pixels, raydiance::image::read_hdr(&rendered).unwrap().pixels);
}

#[test]
fn open_hands_the_page_s_address_to_the_desktop() {
    let dir = tempfile::tempdir().unwrap();
    let opened = dir.path().join("opened");
    let opener = dir.path().join("xdg-open");
    std::fs::write(&opener, format!("#!/bin/sh\necho \"$1\" > {}\n", opened.display())).unwrap();
    std::fs::set_permissions(&opener, std::fs::Permissions::from_mode(0o755)).unwrap();
    let path = format!("{}:{}", dir.path().display(), std::env::var("PATH").unwrap_or_default());
    let scene = small_scene(dir.path(), 1);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["preview", scene.to_str().unwrap(), "--listen", "127.0.0.1:0", "--open"])
        .env("PATH", path)
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let start = std::time::Instant::now();
    while std::fs::read_to_string(&opened).map_or(true, |text| text.is_empty()) {
        assert!(start.elapsed() < common::preview::PATIENCE, "xdg-open was not run");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    let url = std::fs::read_to_string(&opened).unwrap();
    assert!(url.starts_with("http://127.0.0.1:") && line.contains(url.trim()), "{url} / {line}");
}

/// An address of this machine other than loopback (the one it would reach the network by), if
/// it has one.
fn outside_address() -> Option<std::net::IpAddr> {
    let socket = UdpSocket::bind("0.0.0.0:0").ok()?;
    // Connecting a UDP socket sends nothing: it only picks the route.
    socket.connect("192.0.2.1:9").ok()?;
    Some(socket.local_addr().ok()?.ip()).filter(|ip| !ip.is_loopback() && !ip.is_unspecified())
}

fn reachable(address: SocketAddr) -> bool {
    TcpStream::connect_timeout(&address, std::time::Duration::from_secs(2)).is_ok()
}

#[test]
fn only_this_machine_is_listened_on_unless_asked() {
    let dir = tempfile::tempdir().unwrap();
    let scene = small_scene(dir.path(), 1);
    // The default address.
    match Preview::try_start(&scene, &[]) {
        Ok(preview) => {
            assert_eq!(preview.address, raydiance::preview::DEFAULT_LISTEN.parse().unwrap());
            assert!(reachable(preview.address));
            if let Some(ip) = outside_address() {
                assert!(!reachable(SocketAddr::new(ip, preview.address.port())), "{ip}");
            }
        }
        // Its port taken by another program: what it tried is still said.
        Err(stderr) => assert!(stderr.contains("cannot listen on 127.0.0.1:"), "{stderr}"),
    }
    assert!(raydiance::preview::DEFAULT_LISTEN.parse::<SocketAddr>().unwrap().ip().is_loopback());
    // Asked for every address: it says so, and the page is seen from outside.
    let everywhere = Preview::start(&scene, &["--listen", "0.0.0.0:0"]);
    if let Some(ip) = outside_address() {
        assert!(reachable(SocketAddr::new(ip, everywhere.address.port())), "{ip}");
    }
}
