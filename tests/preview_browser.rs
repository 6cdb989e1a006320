//! `raydiance preview` in a real browser: headless Chromium driven over WebDriver (JSON over
//! HTTP). The image appears and refines, changes when the scene is saved, an error shows its
//! line and column while the image stays, and the image returns when the error is fixed.
//! Skipped, with a line saying so, where Chromium or its driver is not installed; under CI
//! (`.ci/run` installs them) it must run.

use crate::common;

use std::net::TcpListener;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::preview::{PATIENCE, Preview, small_scene};
use serde_json::{Value, json};

/// A headless Chromium under chromedriver, ended (by process id) when dropped.
struct Browser {
    driver: Child,
    session: String,
}

impl Browser {
    fn start() -> Browser {
        // A free port for the driver: taken, then let go.
        let port = TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
        let driver = Command::new("chromedriver")
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut browser = Browser { driver, session: format!("http://127.0.0.1:{port}/session") };
        let start = Instant::now();
        while ureq::get(format!("http://127.0.0.1:{port}/status")).call().is_err() {
            assert!(start.elapsed() < PATIENCE, "chromedriver did not start");
            std::thread::sleep(Duration::from_millis(50));
        }
        // Root cannot use Chromium's sandbox; headless needs no GPU.
        let args = ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"];
        let capabilities = json!({ "capabilities": { "alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": { "args": args }
        }}});
        let session = browser.send("", &capabilities);
        let id = session["sessionId"].as_str().expect("a WebDriver session").to_string();
        browser.session = format!("{}/{id}", browser.session);
        browser
    }

    /// POSTs a WebDriver command; its `value`.
    fn send(&self, command: &str, body: &Value) -> Value {
        let mut response = ureq::post(format!("{}{command}", self.session))
            .content_type("application/json")
            .send(body.to_string())
            .unwrap_or_else(|e| panic!("WebDriver {command}: {e}"));
        let text = response.body_mut().read_to_string().unwrap();
        serde_json::from_str::<Value>(&text).unwrap()["value"].clone()
    }

    fn open(&self, url: &str) {
        self.send("/url", &json!({ "url": url }));
    }

    /// Runs `script` in the page; what it returns.
    fn run(&self, script: &str) -> Value {
        self.send("/execute/sync", &json!({ "script": script, "args": [] }))
    }

    /// What the page shows: the picture's mean colour (drawn on a canvas), its samples per
    /// pixel and render, and the error pane.
    fn page(&self) -> Value {
        self.run(
            r#"
            const $ = (id) => document.getElementById(id);
            const img = $("picture");
            let mean = null;
            if (!img.hidden && img.complete && img.naturalWidth > 0) {
              const canvas = document.createElement("canvas");
              canvas.width = img.naturalWidth;
              canvas.height = img.naturalHeight;
              const context = canvas.getContext("2d");
              context.drawImage(img, 0, 0);
              const data = context.getImageData(0, 0, canvas.width, canvas.height).data;
              mean = [0, 0, 0];
              for (let i = 0; i < data.length; i += 4) {
                for (let c = 0; c < 3; c++) mean[c] += data[i + c] / (data.length / 4);
              }
            }
            return {
              mean,
              spp: parseInt($("spp").textContent),
              render: parseInt($("render").textContent),
              error: $("error").hidden ? null : $("error-text").textContent,
            };
            "#,
        )
    }

    /// Polls the page until `done` holds; the page then.
    fn wait_for(&self, what: &str, done: impl Fn(&Value) -> bool) -> Value {
        let start = Instant::now();
        loop {
            let page = self.page();
            if done(&page) {
                return page;
            }
            assert!(start.elapsed() < PATIENCE, "the page never showed {what}: {page}");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = ureq::delete(&self.session).call();
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

fn spp(page: &Value) -> u64 {
    page["spp"].as_u64().unwrap_or(0)
}

fn render(page: &Value) -> u64 {
    page["render"].as_u64().unwrap_or(0)
}

fn red_minus_blue(page: &Value) -> f64 {
    page["mean"][0].as_f64().unwrap() - page["mean"][2].as_f64().unwrap()
}

#[test]
fn the_page_refines_follows_saves_and_shows_errors_beside_the_last_image() {
    let test = "the_page_refines_follows_saves_and_shows_errors_beside_the_last_image";
    if !(common::outside_tool("chromium", "chromium", test)
        && common::outside_tool("chromedriver", "chromium-driver", test))
    {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // As many samples as a scene may ask: the render must still be refining when the browser
    // first looks (a fast machine finished 1024 before Chromium had started).
    let scene = small_scene(dir.path(), raydiance::MAX_SAMPLES);
    let good = std::fs::read_to_string(&scene).unwrap();
    let preview = Preview::start(&scene, &["--listen", "127.0.0.1:0"]);
    let browser = Browser::start();
    browser.open(&preview.url);

    // The image appears, then refines.
    let first = browser.wait_for("an image", |page| !page["mean"].is_null());
    let refined = browser.wait_for("more samples", |page| spp(page) > spp(&first));
    assert!(refined["error"].is_null(), "{refined}");

    // The blue sphere made red: a new render, a redder image.
    let red = good.replace("material { Blue }", "material { diffuse rgb <0.9, 0.05, 0.05> }");
    std::fs::write(&scene, red).unwrap();
    let edited = browser
        .wait_for("the edit", |page| render(page) > render(&refined) && !page["mean"].is_null());
    assert!(red_minus_blue(&edited) > red_minus_blue(&refined) + 1.0, "{refined} then {edited}");

    // A brace dropped on line 3: the error's place, the image kept beside it.
    let broken = good.replace("object { CeilingLight }", "object { CeilingLight");
    std::fs::write(&scene, broken).unwrap();
    let failed = browser.wait_for("the error", |page| page["error"].is_string());
    let error = failed["error"].as_str().unwrap();
    assert!(error.contains("scene.scn:4:1: error"), "{error}");
    assert!(error.contains("4 | sphere") && error.contains("  | ^"), "the caret: {error}");
    assert!(!failed["mean"].is_null(), "the last image stays: {failed}");

    // Fixed: the error goes and the image of the fixed scene comes.
    std::fs::write(&scene, &good).unwrap();
    let fixed = browser.wait_for("the fix", |page| {
        page["error"].is_null() && render(page) > render(&failed) && !page["mean"].is_null()
    });
    assert!(red_minus_blue(&fixed) < red_minus_blue(&edited) - 1.0, "{edited} then {fixed}");
}
