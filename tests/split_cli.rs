//! `render --part/--crop/--frames` and `merge` from the command line: exact merges, every
//! refusal (a message naming the files, a non-zero exit, nothing written), the scheduler's
//! variables, and animation frames.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SCENE: &str = "scenes/lab4-direct.scn";

/// Runs raydiance with no scheduler variables, plus `env`.
fn raydiance(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_raydiance"));
    for name in [
        "SLURM_JOB_ID",
        "SLURM_ARRAY_TASK_ID",
        "SLURM_ARRAY_TASK_MIN",
        "SLURM_ARRAY_TASK_COUNT",
        "SLURM_ARRAY_TASK_STEP",
        "JOB_COMPLETION_INDEX",
    ] {
        command.env_remove(name);
    }
    command.args(args).envs(env.iter().copied()).output().unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Renders `scene` small (24x16, 4 spp) with `extra` options into `out`.
fn render(scene: &str, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["render", scene, "-o", out.to_str().unwrap()];
    for (option, value) in [("--width", "24"), ("--height", "16"), ("--samples", "4")] {
        if !extra.contains(&option) {
            args.extend([option, value]);
        }
    }
    args.extend(extra);
    raydiance(&args, &[])
}

fn rendered(scene: &str, out: &Path, extra: &[&str]) -> PathBuf {
    let output = render(scene, out, extra);
    assert!(output.status.success(), "{}", stderr(&output));
    out.to_path_buf()
}

fn merge(parts: &[&Path], out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(|p| p.to_str().unwrap()));
    args.extend(["-o", out.to_str().unwrap()]);
    args.extend(extra);
    raydiance(&args, &[])
}

fn pixels(path: &Path) -> Vec<glam::Vec3> {
    raydiance::image::read_hdr(path).unwrap().pixels
}

fn assert_close(a: &Path, b: &Path) {
    for (i, (p, q)) in pixels(a).iter().zip(pixels(b)).enumerate() {
        let scale = p.abs().max(q.abs()).max_element();
        assert!((*p - q).abs().max_element() <= 1e-6 * scale, "pixel {i}: {p} and {q}");
    }
}

/// A refused merge: non-zero exit, every named file in the message, no output.
fn assert_refused(output: &Output, out: &Path, names: &[&Path], says: &str) {
    let text = stderr(output);
    assert!(!output.status.success(), "merge must fail: {text}");
    assert!(text.contains(says), "`{says}` in: {text}");
    for name in names {
        assert!(text.contains(&*name.to_string_lossy()), "{} in: {text}", name.display());
    }
    assert!(!out.exists(), "nothing written on a refusal");
}

#[test]
fn shares_and_tiles_from_the_command_line_merge_into_the_single_render() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let single = rendered(SCENE, &d.join("single.exr"), &[]);
    // Three shares of the left tile, the right tile whole.
    let mut parts = vec![rendered(SCENE, &d.join("right.exr"), &["--crop", "10,24,0,16"])];
    for i in 0..3 {
        let share = format!("{i}/3");
        let out = d.join(format!("left-{i}.exr"));
        parts.push(rendered(SCENE, &out, &["--crop", "0,10,0,16", "--part", &share]));
    }
    parts.reverse();
    let refs: Vec<&Path> = parts.iter().map(PathBuf::as_path).collect();
    for name in ["merged.exr", "merged.ppm", "merged.png"] {
        let output = merge(&refs, &d.join(name), &[]);
        assert!(output.status.success(), "{}", stderr(&output));
        assert!(String::from_utf8_lossy(&output.stdout).contains("merged from 4 parts"));
    }
    assert_close(&d.join("merged.exr"), &single);
    // The merged file records what a single render records.
    let spp = raydiance::image::exr::read_samples_per_pixel(&d.join("merged.exr")).unwrap();
    assert_eq!(spp, Some(4));
}

#[test]
fn parts_show_their_merge_data_in_exrheader() {
    let test = "parts_show_their_merge_data_in_exrheader";
    if !common::outside_tool("exrheader", "openexr", test) {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let part = rendered(SCENE, &dir.path().join("p.exr"), &["--part", "1/4", "--crop", "2,20,3,9"]);
    let output = Command::new("exrheader").arg(&part).output().unwrap();
    assert!(output.status.success());
    let text = String::from_utf8_lossy(&output.stdout);
    for expected in [
        "samples, 32-bit unsigned integer",
        "moment2.R, 32-bit floating-point",
        "R, 32-bit floating-point",
        "dataWindow (type box2i): (2 3) - (19 8)",
        "displayWindow (type box2i): (0 0) - (23 15)",
        "raydiance:part (type string): \"1/4\"",
        "raydiance:crop (type string): \"2,20,3,9\"",
        "raydiance:image_size (type string): \"24x16\"",
        "raydiance:render_samples (type int): 4",
        "raydiance:seed (type string): \"0\"",
        "raydiance:digest (type string): \"",
    ] {
        assert!(text.contains(expected), "exrheader shows `{expected}`:\n{text}");
    }
}

#[test]
fn merge_refuses_overlapping_missing_and_foreign_parts() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("out.exr");
    let half = |i: u32, extra: &[&str]| {
        let mut args = vec!["--part"];
        let share = format!("{i}/2");
        args.push(&share);
        args.extend(extra);
        rendered(SCENE, &d.join(format!("half{i}{}.exr", extra.join("").replace(' ', ""))), &args)
    };
    let (a, b) = (half(0, &[]), half(1, &[]));
    // The same file twice (not an overlap of two parts), and a share inside another.
    assert_refused(&merge(&[&a, &b, &a], &out, &[]), &out, &[&a], "are the same file");
    let quarter = rendered(SCENE, &d.join("quarter.exr"), &["--part", "1/4"]);
    assert_refused(&merge(&[&a, &quarter, &b], &out, &[]), &out, &[&a, &quarter], "overlap");
    // Overlapping crops.
    let top = rendered(SCENE, &d.join("top.exr"), &["--crop", "0,24,0,10"]);
    let bottom = rendered(SCENE, &d.join("bottom.exr"), &["--crop", "0,24,8,16"]);
    assert_refused(&merge(&[&top, &bottom], &out, &[]), &out, &[&top, &bottom], "overlap");
    // Missing: a share, and a tile; merge says which and how to render them.
    assert_refused(&merge(&[&b], &out, &[]), &out, &[&b], "--part 0/2");
    assert_refused(&merge(&[&top], &out, &[]), &out, &[], "--crop 0,24,10,16");
    // Other seed, sample count, settings, resolution, scene.
    let seed = half(0, &["--seed", "9"]);
    assert_refused(&merge(&[&seed, &b], &out, &[]), &out, &[&seed, &b], "seeds");
    let spp = half(0, &["--samples", "8"]);
    assert_refused(&merge(&[&spp, &b], &out, &[]), &out, &[&spp, &b], "settings");
    let depth = half(0, &["--max-depth", "3"]);
    assert_refused(&merge(&[&depth, &b], &out, &[]), &out, &[&depth, &b], "scenes or settings");
    let wide = half(0, &["--width", "32"]);
    assert_refused(&merge(&[&wide, &b], &out, &[]), &out, &[&wide, &b], "resolutions");
    let text = std::fs::read_to_string(SCENE).unwrap().replace("0.8", "0.7");
    let other_scene = d.join("other.scn");
    std::fs::write(&other_scene, text).unwrap();
    std::fs::copy("scenes/lab-box.inc", d.join("lab-box.inc")).ok();
    let other = rendered(other_scene.to_str().unwrap(), &d.join("other0.exr"), &["--part", "0/2"]);
    assert_refused(&merge(&[&other, &b], &out, &[]), &out, &[&other, &b], "scenes or settings");
    // A truncated part.
    let bytes = std::fs::read(&a).unwrap();
    let truncated = d.join("truncated.exr");
    std::fs::write(&truncated, &bytes[..bytes.len() * 2 / 3]).unwrap();
    assert_refused(&merge(&[&truncated, &b], &out, &[]), &out, &[&truncated], "error");
    // Not a part: a plain render.
    let plain = rendered(SCENE, &d.join("plain.exr"), &[]);
    assert_refused(&merge(&[&plain], &out, &[]), &out, &[&plain], "not a part");
    // And the good pair merges.
    assert!(merge(&[&b, &a], &out, &[]).status.success());
}

#[test]
fn allow_partial_merges_what_is_there_and_records_the_real_sample_count() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let a = rendered(SCENE, &d.join("a.exr"), &["--part", "0/4"]);
    let out = d.join("partial.exr");
    let output = merge(&[&a], &out, &["--allow-partial"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(stderr(&output).contains("--part 1/4, --part 2/4, --part 3/4"), "{}", stderr(&output));
    assert_eq!(raydiance::image::exr::read_samples_per_pixel(&out).unwrap(), Some(1));
    // The mean of the one share: its part's own RGB.
    assert_eq!(pixels(&out), pixels(&a));
}

#[test]
fn part_auto_takes_the_share_from_slurm_or_kubernetes_and_is_an_error_without_them() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("auto.exr");
    let args = |extra: &[&'static str]| {
        let mut args = vec!["render", SCENE, "-o", out.to_str().unwrap()];
        args.extend(["--width", "24", "--height", "16", "--samples", "4", "--part", "auto"]);
        args.extend(extra.iter().copied());
        args.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let run = |args: &[String], env: &[(&str, &str)]| {
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        raydiance(&refs, env)
    };
    let share_of =
        |path: &Path| raydiance::split::part_file::read_header(path).unwrap().region.share;
    // Slurm: --array=1-4, task 3 is share 2 of 4.
    let slurm = [
        ("SLURM_ARRAY_TASK_ID", "3"),
        ("SLURM_ARRAY_TASK_MIN", "1"),
        ("SLURM_ARRAY_TASK_COUNT", "4"),
    ];
    let output = run(&args(&[]), &slurm);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(share_of(&out).to_string(), "2/4");
    assert!(stderr(&output).contains("Slurm task 2 of 4: share 2/4"), "{}", stderr(&output));
    // Kubernetes: index 5 of --parts 8.
    let output = run(&args(&["--parts", "8"]), &[("JOB_COMPLETION_INDEX", "5")]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(share_of(&out).to_string(), "5/8");
    let output = run(&args(&[]), &[("JOB_COMPLETION_INDEX", "5")]);
    assert!(!output.status.success() && stderr(&output).contains("--parts N"));
    // Neither.
    std::fs::remove_file(&out).unwrap();
    let output = run(&args(&[]), &[]);
    assert!(!output.status.success());
    assert!(stderr(&output).contains("no scheduler task found"), "{}", stderr(&output));
    assert!(!out.exists());
}

#[test]
fn part_files_must_be_openexr_and_shares_valid() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("p.png");
    let output = render(SCENE, &png, &["--part", "0/2"]);
    assert!(!output.status.success() && stderr(&output).contains("name it .exr"));
    let exr = dir.path().join("p.exr");
    for (option, value, says) in [
        ("--part", "2/2", "less than 2"),
        ("--part", "3", "not a share I/N"),
        ("--crop", "0,30,0,4", "outside the 24x16 image"),
        ("--crop", "4,4,0,4", "empty"),
        ("--part", "0/100000", "more shares than the 1536 samples"),
    ] {
        let output = render(SCENE, &exr, &[option, value]);
        assert!(!output.status.success(), "{option} {value}");
        assert!(stderr(&output).contains(says), "{option} {value}: {}", stderr(&output));
        assert!(!exr.exists());
    }
}

/// A scene whose sphere moves with `clock` and whose light follows `frame_number`.
fn animated(position: &str, power: &str) -> String {
    format!(
        "settings {{ resolution 24, 16  samples 2  integrator direct }}
         camera {{ location <0, 0, -4>  look_at <0, 0, 0>  angle 50 }}
         light_source {{ <0, 2, -2>  power rgb {power} }}
         plane {{ <0, 1, 0>, 1  material {{ diffuse rgb 0.8 }} }}
         sphere {{ <{position}, 0, 0>, 0.5  material {{ diffuse rgb 0.6 }} }}"
    )
}

#[test]
fn a_frame_is_the_scene_written_with_its_clock_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = d.join("anim.scn");
    std::fs::write(&scene, animated("clock * 2 - 1", "4 + frame_number")).unwrap();
    let still = d.join("still.scn");
    std::fs::write(&still, animated("0.5 * 2 - 1", "4 + 3")).unwrap();
    let s = scene.to_str().unwrap();
    // Frames 1..5: frame 3 is clock 0.5.
    let frame = rendered(s, &d.join("f.exr"), &["--frames", "1..5", "--frame", "3"]);
    assert_eq!(frame, d.join("f.exr"));
    assert!(d.join("f3.exr").exists() && !d.join("f.exr").exists());
    let expected = rendered(still.to_str().unwrap(), &d.join("still.exr"), &[]);
    assert_eq!(pixels(&d.join("f3.exr")), pixels(&expected));
    // Another clock range moves the sphere: a different image.
    rendered(s, &d.join("g#.exr"), &["--frames", "1..5", "--frame", "3", "--clock", "0..2"]);
    assert_ne!(pixels(&d.join("g3.exr")), pixels(&expected));
    // Without animation options, clock and frame_number are 0.
    let zero = d.join("zero.scn");
    std::fs::write(&zero, animated("0 * 2 - 1", "4 + 0")).unwrap();
    let plain = rendered(s, &d.join("plain.exr"), &[]);
    assert_eq!(pixels(&plain), pixels(&rendered(zero.to_str().unwrap(), &d.join("z.exr"), &[])));
}

#[test]
fn frames_are_named_by_the_hash_pattern_and_combine_with_parts() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = d.join("anim.scn");
    std::fs::write(&scene, animated("clock", "4")).unwrap();
    let s = scene.to_str().unwrap();
    std::fs::create_dir(d.join("anim")).unwrap();
    let output = render(s, &d.join("anim/f###.png"), &["--frames", "8..10"]);
    assert!(output.status.success(), "{}", stderr(&output));
    for n in ["008", "009", "010"] {
        assert!(d.join(format!("anim/f{n}.png")).exists(), "f{n}.png");
    }
    let output = render(s, &d.join("plain.exr"), &["--frames", "8..10", "--frame", "9"]);
    assert!(output.status.success() && d.join("plain09.exr").exists());
    // Frames x parts: both shares of both frames, then one merge a frame.
    for share in ["0/2", "1/2"] {
        let name = format!("p{}-#.exr", &share[..1]);
        rendered(s, &d.join(name), &["--frames", "0..1", "--part", share]);
    }
    for frame in ["0", "1"] {
        rendered(s, &d.join("w#.exr"), &["--frames", "0..1", "--frame", frame]);
        let whole = d.join(format!("w{frame}.exr"));
        let parts = [d.join(format!("p0-{frame}.exr")), d.join(format!("p1-{frame}.exr"))];
        let merged = d.join(format!("m{frame}.exr"));
        let output = merge(&[&parts[0], &parts[1]], &merged, &[]);
        assert!(output.status.success(), "{}", stderr(&output));
        assert_close(&merged, &whole);
    }
    // Shares of different frames do not merge.
    let out = d.join("mixed.exr");
    let (a, b) = (d.join("p0-0.exr"), d.join("p1-1.exr"));
    assert_refused(&merge(&[&a, &b], &out, &[]), &out, &[&a, &b], "frames");
}

#[test]
fn a_part_whose_render_was_stopped_is_named_as_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A time budget ends the render after its first pass: 1 of the 500 samples of the share.
    let options = ["--samples", "1000", "--time", "0.000001"];
    let stopped =
        rendered(SCENE, &d.join("stopped.exr"), &[&["--part", "0/2"][..], &options].concat());
    let done = rendered(SCENE, &d.join("done.exr"), &["--part", "1/2", "--samples", "1000"]);
    let out = d.join("out.exr");
    assert_refused(&merge(&[&stopped, &done], &out, &[]), &out, &[&stopped], "incomplete");
    let output = merge(&[&stopped, &done], &out, &["--allow-partial"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(String::from_utf8_lossy(&output.stdout).contains(", 501 spp,"));
}

#[test]
fn a_signal_during_an_animation_ends_it_after_the_frame_under_way() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("f#.exr");
    let child = Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["render", SCENE, "-o", out.to_str().unwrap(), "--frames", "0..3"])
        .args(["--width", "64", "--height", "64", "--samples", "1000000"])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let sent = Command::new("kill").args(["-TERM", &child.id().to_string()]).status();
    assert!(sent.unwrap().success());
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(130), "{}", stderr(&output));
    assert!(dir.path().join("f0.exr").exists(), "the frame under way is written");
    assert!(!dir.path().join("f1.exr").exists(), "no frame is started after the signal");
}
