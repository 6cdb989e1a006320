//! Robustness: scale invariance (spawned rays clear surfaces at any scale), deep nesting, and
//! interruption with Ctrl-C.

use crate::common;

use common::{max_abs_difference, mean, render_image, scene};

/// Lab 4's scene scaled by `s`: geometry, camera and light positions by s, the light's power
/// by s^2 so that p / r^2, and so the image, stays the same.
fn seed_scene_scaled(s: f64, integrator: &str) -> String {
    format!(
        "#declare S = {s};
         settings {{ resolution 32, 32  samples 4  integrator {integrator}  max_depth 8 }}
         camera {{ origin <0, 0, -3.5> * S  left <-1, 0, 0> * S  up <0, 1, 0> * S  forward <0, 0, 3> * S }}
         light_source {{ <0, 0.5, 0> * S  power rgb S * S }}
         union {{
           plane {{ <1, 0, 0>, 1   material {{ diffuse rgb <0.8, 0.1, 0.1> }} }}
           plane {{ <-1, 0, 0>, 1  material {{ diffuse rgb <0.1, 0.8, 0.1> }} }}
           plane {{ <0, 1, 0>, 1   material {{ diffuse rgb 0.8 }} }}
           plane {{ <0, -1, 0>, 1  material {{ diffuse rgb 0.8 }} }}
           plane {{ <0, 0, -1>, 1  material {{ diffuse rgb 0.8 }} }}
           sphere {{ <-0.5, -0.7, 0.25>, 0.3  material {{ specular rgb 0.9 }} }}
           sphere {{ <0.5, -0.7, -0.25>, 0.3  material {{ transmission rgb 1  ior 1.5  fresnel }} }}
           box {{ <-0.2, -1, -0.7>, <0.1, -0.8, -0.4>  material {{ diffuse rgb 0.5 }} }}
           scale S
         }}"
    )
}

#[test]
fn the_seed_scene_renders_the_same_at_any_scale() {
    let reference = render_image(&scene(&seed_scene_scaled(1.0, "direct")));
    let largest = reference.max_component();
    for s in [1000.0, 0.001] {
        let scaled = render_image(&scene(&seed_scene_scaled(s, "direct")));
        let difference = max_abs_difference(&reference, &scaled);
        assert!(
            difference < 1e-3 * largest,
            "scale {s}: differs by {difference} (largest {largest})"
        );
    }
    // Path tracing takes the same random numbers at every scale; paths may part at a grazing
    // bounce, so the images agree on average.
    let reference = mean(&render_image(&scene(&seed_scene_scaled(1.0, "path"))));
    for s in [1000.0, 0.001] {
        let scaled = mean(&render_image(&scene(&seed_scene_scaled(s, "path"))));
        assert!(
            (scaled - reference).abs().max_element() < 0.01 * reference.max_element(),
            "scale {s}"
        );
    }
}

#[test]
fn nesting_at_the_limit_parses_on_a_small_stack() {
    // Test threads have small stacks; the limit must be safe there.
    let depth = raydiance::lang::MAX_NESTING - 2;
    let text = format!(
        "camera {{ location <0, 0, -5>  look_at <0, 0, 0> }} #declare X = {}1{};",
        "(".repeat(depth),
        ")".repeat(depth)
    );
    let result = std::thread::Builder::new()
        .stack_size(1 << 20)
        .spawn(move || {
            raydiance::lang::parse_scene(std::path::Path::new("deep.scn"), &text).is_ok()
        })
        .unwrap()
        .join()
        .expect("no stack overflow");
    assert!(result);
}

#[test]
fn deep_macro_recursion_runs_on_a_small_stack() {
    // 250 nested calls (under the limit of 256) on a 256 KiB thread stack, then past the limit.
    let scene = |depth: u32| {
        format!(
            "camera {{ location <0, 0, -5>  look_at <0, 0, 0> }}
             #macro Down(N) #if (N > 0) union {{ Down(N - 1) }} #else sphere {{ 0, 1 }} #end #end
             #macro Count(N) #if (N > 0) (1 + Count(N - 1)) #else 0 #end #end
             #declare Depth = Count({depth});
             sphere {{ 0, Depth }}
             Down({depth})"
        )
    };
    let run = |text: String| {
        std::thread::Builder::new()
            .stack_size(256 * 1024)
            .spawn(move || {
                raydiance::lang::parse_scene(std::path::Path::new("deep.scn"), &text)
                    .map(|g| g.objects.len())
                    .map_err(|e| e.to_string())
            })
            .unwrap()
            .join()
            .expect("no stack overflow")
    };
    assert_eq!(run(scene(250)), Ok(2));
    let error = run(scene(300)).unwrap_err();
    assert!(error.contains("macro calls nested more than 256 deep"), "{error}");
}

#[test]
fn a_hundred_thousand_signs_are_an_error_not_a_stack_overflow() {
    let text = format!(
        "camera {{ location <0, 0, -5>  look_at <0, 0, 0> }} #declare X = {}1",
        "- ".repeat(100_000)
    );
    let error = std::thread::Builder::new()
        .stack_size(1 << 20)
        .spawn(move || {
            raydiance::lang::parse_scene(std::path::Path::new("signs.scn"), &text).unwrap_err()
        })
        .unwrap()
        .join()
        .expect("no stack overflow");
    assert!(error.to_string().contains("signs in a row"), "{error}");
}

/// Starts a long render of S4 (`cornell-specular`) to `out` at the given size.
fn long_render(out: &std::path::Path, size: &str) -> std::process::Child {
    std::process::Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["render", "scenes/cornell-specular.scn", "-o", out.to_str().unwrap()])
        .args(["--width", size, "--height", size, "--samples", "1000000"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

fn send(signal: &str, child: &std::process::Child) {
    let sent = std::process::Command::new("kill").args([signal, &child.id().to_string()]).status();
    assert!(sent.unwrap().success());
}

/// Files in `dir` other than `keep`: a temporary file left behind would be one.
fn others(dir: &std::path::Path, keep: &std::path::Path) -> Vec<std::path::PathBuf> {
    let entries = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path());
    entries.filter(|p| p != keep).collect()
}

/// Ctrl-C, SIGTERM and SIGHUP stop a render within a task (the pass under way is dropped, not
/// waited for), write the completed passes and exit with 130.
#[test]
fn a_signal_writes_the_completed_passes_soon_and_exits_non_zero() {
    for signal in ["-INT", "-TERM", "-HUP"] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("interrupted.exr");
        let child = long_render(&out, "256");
        std::thread::sleep(std::time::Duration::from_millis(2500));
        let sent = std::time::Instant::now();
        send(signal, &child);
        let output = child.wait_with_output().unwrap();
        let latency = sent.elapsed().as_secs_f64();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(130), "{signal}: {stderr}");
        assert!(stderr.contains("interrupted: wrote the"), "{signal}: {stderr}");
        assert!(latency < 1.0, "{signal}: exited {latency:.2} s after the signal");
        let samples = raydiance::image::exr::read_samples_per_pixel(&out).unwrap().unwrap();
        assert!(samples > 0 && samples < 1_000_000, "{signal}: {samples}");
        let image = raydiance::image::exr::read(&out).unwrap();
        assert!(image.max_component() > 0.0);
        assert!(others(dir.path(), &out).is_empty(), "{signal}: {:?}", others(dir.path(), &out));
    }
}

/// A second signal ends the process at once, and leaves no file behind.
#[test]
fn a_second_signal_exits_at_once_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.exr");
    let child = long_render(&out, "64");
    std::thread::sleep(std::time::Duration::from_millis(1500));
    send("-TERM", &child);
    send("-TERM", &child);
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(130), "{}", String::from_utf8_lossy(&output.stderr));
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().path()).collect();
    assert!(left.iter().all(|p| p == &out), "{left:?}");
}

#[test]
fn a_time_budget_renders_what_fits() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("budget.exr");
    let start = std::time::Instant::now();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["render", "scenes/cornell-area.scn", "-o", out.to_str().unwrap()])
        .args(["--width", "32", "--height", "32", "--time", "1"])
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(start.elapsed().as_secs_f64() < 10.0, "stopped near its budget of 1 s");
    let samples = raydiance::image::exr::read_samples_per_pixel(&out).unwrap().unwrap();
    assert!(samples >= 16, "used the budget: {samples} spp");
}

/// A budget of samples, as a time budget becomes one: the render takes exactly as many as
/// the budget allows (the last pass shortened), not the largest doubling that fits.
#[test]
fn the_last_pass_is_shortened_to_the_budget() {
    struct Budget {
        pixels: u64,
        samples: u64,
        done: std::sync::atomic::AtomicU64,
    }
    impl raydiance::progress::Progress for Budget {
        fn advance(&self, samples: u64) {
            self.done.fetch_add(samples, std::sync::atomic::Ordering::Relaxed);
        }
        fn pass_limit(&self, _seconds_per_sample: f64) -> Option<u32> {
            let done = self.done.load(std::sync::atomic::Ordering::Relaxed) / self.pixels;
            Some((self.samples - done) as u32)
        }
    }
    let mut s = scene(&seed_scene_scaled(1.0, "path"));
    s.settings.width = 8;
    s.settings.height = 8;
    s.settings.samples = 1000;
    let budget = Budget { pixels: 64, samples: 37, done: Default::default() };
    let (film, stats) = raydiance::render::render(&s, &budget);
    assert_eq!((film.samples, stats.samples_per_pixel), (37, 37));
}

/// A signal before the first pass ends writes nothing: the file of an earlier render stays as
/// it was, and the message says why.
#[test]
fn a_signal_before_the_first_pass_keeps_the_previous_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("keep.png");
    let quick = std::process::Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["render", "scenes/cornell-area.scn", "-o", out.to_str().unwrap()])
        .args(["--width", "16", "--height", "16", "--samples", "4"])
        .output()
        .unwrap();
    assert!(quick.status.success(), "{}", String::from_utf8_lossy(&quick.stderr));
    let before = std::fs::read(&out).unwrap();
    // SPPM's first pass traces 200,000 photons over a 1024 x 1024 film: longer than the wait.
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["render", "scenes/caustic-point.scn", "-o", out.to_str().unwrap()])
        .args(["--width", "1024", "--height", "1024"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1000));
    send("-TERM", &child);
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_ne!(output.status.code(), Some(0), "{stderr}");
    assert!(stderr.contains("interrupted before the first pass"), "{stderr}");
    assert_eq!(std::fs::read(&out).unwrap(), before, "the earlier render is kept");
    assert!(others(dir.path(), &out).is_empty(), "{:?}", others(dir.path(), &out));
}

/// `tonemap` (and `merge`, the same handling) stopped while it writes its output leaves no
/// temporary file: the signal is sent once the temporary file is seen.
#[test]
fn a_signal_while_tone_mapping_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("big.ppm");
    let side = 4096;
    let mut ppm = format!("P6\n{side} {side}\n255\n").into_bytes();
    ppm.extend((0..side * side * 3).map(|i| (i % 251) as u8));
    std::fs::write(&input, ppm).unwrap();
    let out = dir.path().join("out.png");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["tonemap", input.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    let writing = || others(dir.path(), &input).into_iter().any(|p| p != out);
    // What the poll saw, not a second look: the write may end between the two.
    let mut seen = writing();
    while !seen && start.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(2));
        seen = writing();
    }
    assert!(seen, "the temporary output was never seen");
    send("-TERM", &child);
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    let left: Vec<_> = others(dir.path(), &input).into_iter().filter(|p| *p != out).collect();
    assert!(left.is_empty(), "{left:?} left behind; {stderr}");
    // Stopped (130) or, if the signal came as it finished, done (0) with the whole output.
    match output.status.code() {
        Some(130) => assert!(!out.exists()),
        Some(0) => assert!(out.exists()),
        other => panic!("exit {other:?}: {stderr}"),
    }
}
