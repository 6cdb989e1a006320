//! The command line: exit codes, located errors on stderr, no output file on failure.

use std::path::Path;
use std::process::{Command, Output};

fn raydiance(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raydiance")).args(args).output().unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn small(extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = ["--width", "16", "--height", "16", "--samples", "2"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

#[test]
fn render_writes_every_format_and_prints_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["out.exr", "out.ppm", "out.png"] {
        let out = dir.path().join(name);
        let mut args = vec!["render", "scenes/lab4-direct.scn", "-o", out.to_str().unwrap()];
        let extra = small(&[]);
        args.extend(extra.iter().map(String::as_str));
        let output = raydiance(&args);
        assert!(output.status.success(), "{}", stderr(&output));
        assert!(out.exists());
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = std::fs::metadata(&out).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o644, "{name} is readable like any other file");
        }
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(
            stdout.contains("16x16, 2 spp, direct") && stdout.contains("Msamples/s"),
            "{stdout}"
        );
    }
    let ppm = std::fs::read_to_string(dir.path().join("out.ppm")).unwrap();
    assert!(
        ppm.starts_with("P3\n#MAX=") && ppm.contains("\n# out.ppm\n16 16\n10000000\n"),
        "{ppm:.80}"
    );
    let png = image::open(dir.path().join("out.png")).unwrap();
    assert_eq!((png.width(), png.height()), (16, 16));
}

#[test]
fn the_same_seed_gives_the_same_file() {
    // Same file name in different folders: the name is written into the PPM's header.
    let render = |folder: &str, seed: &str| {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join(folder).join("same.ppm");
        std::fs::create_dir(dir.path().join(folder)).unwrap();
        let extra = small(&["--seed", seed]);
        let mut args = vec!["render", "scenes/cornell-area.scn", "-o", out.to_str().unwrap()];
        args.extend(extra.iter().map(String::as_str));
        assert!(raydiance(&args).status.success());
        std::fs::read(out).unwrap()
    };
    assert!(render("a", "5") == render("b", "5"), "same seed, same bytes");
    assert!(render("a", "5") != render("c", "6"), "another seed, another image");
}

#[test]
fn a_bad_scene_fails_with_its_location_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.exr");
    let output =
        raydiance(&["render", "tests/bad_scenes/negative_radius.scn", "-o", out.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    let err = stderr(&output);
    assert!(err.starts_with("tests/bad_scenes/negative_radius.scn:2:30: error:"), "{err}");
    assert!(err.contains("^"), "shows a caret:\n{err}");
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "no temporary left behind");
}

#[test]
fn a_failed_render_leaves_the_previous_file_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("kept.png");
    std::fs::write(&out, b"the previous image").unwrap();
    let output =
        raydiance(&["render", "tests/bad_scenes/missing_camera.scn", "-o", out.to_str().unwrap()]);
    assert!(!output.status.success());
    assert_eq!(std::fs::read(&out).unwrap(), b"the previous image");
}

#[test]
fn unwritable_outputs_fail_before_rendering() {
    let output = raydiance(&["render", "scenes/lab4-direct.scn", "-o", "no/such/folder/out.exr"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("the folder `no/such/folder` does not exist"),
        "{}",
        stderr(&output)
    );
    let output = raydiance(&["render", "scenes/lab4-direct.scn", "-o", "out.tiff"]);
    assert!(stderr(&output).contains("unknown output type"), "{}", stderr(&output));
    assert!(!Path::new("out.tiff").exists());
}

#[test]
fn bad_command_line_values_are_errors_naming_the_value() {
    for (args, message) in [
        (vec!["--samples", "0"], "--samples 0 is out of range"),
        (vec!["--width", "100000"], "--width 100000 is out of range"),
        (vec!["--threads", "0"], "--threads 0 is out of range (1 to 1024)"),
        (vec!["--integrator", "photons"], "unknown integrator `photons`"),
        (vec!["--time", "-3"], "--time -3 must be a positive number"),
        (
            vec!["--time", "1e19"],
            "--time 10000000000000000000 must be a positive number of seconds, at most 1e9",
        ),
    ] {
        let mut all = vec!["render", "scenes/lab4-direct.scn", "-o", "/tmp/raydiance-never.exr"];
        all.extend(args);
        let output = raydiance(&all);
        assert!(!output.status.success());
        assert!(stderr(&output).contains(message), "{message}: {}", stderr(&output));
    }
    assert!(!Path::new("/tmp/raydiance-never.exr").exists());
}

#[test]
fn a_snapshot_of_one_sample_is_refused_before_any_render() {
    let output = raydiance(&["snapshot", "--samples", "1", "no/such/folder"]);
    assert_eq!(output.status.code(), Some(1));
    let message = "error: --samples 1 is out of range (2 to 1000000): a snapshot needs a variance";
    assert_eq!(stderr(&output).trim_end(), message);
}

#[test]
fn check_summarises_or_locates_the_error() {
    let output = raydiance(&["check", "scenes/cornell-specular.scn"]);
    assert!(output.status.success());
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("ok: 256x256, 64 spp, integrator path"), "{stdout}");
    let output = raydiance(&["check", "tests/bad_scenes/unknown_identifier.scn"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("did you mean `White`?"));
}

#[test]
fn tonemap_reproduces_the_spec_example() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("tiny.ppm");
    std::fs::write(&input, "P3\n#MAX=4.5\n# tiny.ppm\n2 1\n255\n255 0 0     51 51 51\n").unwrap();
    for (op, extra, second) in [
        ("clamp", vec![], 230),
        ("equalize", vec![], 51),
        ("equalize-clamp", vec!["--v", "2"], 115),
        ("gamma", vec![], 123),
        ("clamp-gamma", vec![], 243),
    ] {
        let out = dir.path().join(format!("{op}.ppm"));
        let mut args =
            vec!["tonemap", input.to_str().unwrap(), "-o", out.to_str().unwrap(), "--op", op];
        args.extend(extra);
        let output = raydiance(&args);
        assert!(output.status.success(), "{}", stderr(&output));
        let text = std::fs::read_to_string(&out).unwrap();
        let expected =
            format!("P3\n#MAX=1\n# {op}.ppm\n2 1\n255\n255 0 0  {second} {second} {second}\n");
        assert_eq!(text, expected);
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(stdout.contains(&format!("{op}.ppm: 2x1, {op} (")), "one summary line: {stdout}");
        assert!(stdout.contains("largest input value 4.5"), "{stdout}");
    }
}

#[test]
fn tonemap_of_a_malformed_file_says_where_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.png");
    let output = raydiance(&[
        "tonemap",
        "tests/bad_ppm/non_numeric_sample.ppm",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("line 4, column 7: expected a sample value, found `zero`"),
        "{}",
        stderr(&output)
    );
    assert!(!out.exists());
    let output =
        raydiance(&["tonemap", "tests/bad_ppm/wrong_magic.ppm", "-o", "x.png", "--gamma", "0"]);
    assert!(stderr(&output).contains("--gamma 0 must be a positive number"), "{}", stderr(&output));
}

#[test]
fn parameters_without_effect_are_reported() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("unused.scn");
    std::fs::write(
        &scene,
        "camera { location <0, 0, -5>  look_at <0, 0, 0>  focal_distance 4 }
         sphere { 0, 1  material { diffuse rgb 0.5  ior 1.5 } }
         sphere { 2, 1  material { diffuse rgb 0.5  fresnel } }",
    )
    .unwrap();
    let output = raydiance(&["check", scene.to_str().unwrap()]);
    assert!(output.status.success());
    let stdout = String::from_utf8_lossy(&output.stdout);
    for warning in [
        ":1:1: warning: `focal_distance` has no effect without an `aperture`",
        ":2:25: warning: `ior` has no effect without `transmission` or `fresnel`",
        ":3:25: warning: `fresnel` has no effect without `specular` or `transmission`",
    ] {
        assert!(stdout.contains(warning), "{warning}\n{stdout}");
    }
}

/// As POV-Ray does: without `-o`, the scene's name as a PNG in the current folder.
#[test]
fn render_without_an_output_writes_the_scene_name_as_png_here() {
    let dir = tempfile::tempdir().unwrap();
    let scene = std::fs::canonicalize("scenes/lab4-direct.scn").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .current_dir(dir.path())
        .args(["render", scene.to_str().unwrap(), "--width", "8", "--height", "8"])
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", stderr(&output));
    let written: Vec<_> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(written, ["lab4-direct.png"]);
}

/// Every option says what it takes and its default; reviewed as text.
#[test]
fn help_describes_every_option() {
    for command in ["render", "tonemap", "check", "snapshot", "bench", "preview"] {
        let output = raydiance(&[command, "--help"]);
        assert!(output.status.success());
        let help = String::from_utf8_lossy(&output.stdout).into_owned();
        insta::assert_snapshot!(format!("help_{command}"), help);
    }
}

#[test]
fn tonemap_names_only_the_parameters_its_operator_uses() {
    let dir = tempfile::tempdir().unwrap();
    let hdr = dir.path().join("in.ppm");
    std::fs::write(&hdr, "P3\n#MAX=4.5\n2 1\n255\n255 0 0  51 51 51\n").unwrap();
    let out = dir.path().join("out.png");
    for (op, expected) in [
        ("reinhard", "reinhard (white: the largest luminance, exposure 0)"),
        ("clamp-gamma", "clamp-gamma (v 1, gamma 2.2, exposure 0)"),
        ("clamp", "clamp (exposure 0)"),
    ] {
        let output =
            raydiance(&["tonemap", hdr.to_str().unwrap(), "-o", out.to_str().unwrap(), "--op", op]);
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert!(stdout.contains(expected), "{stdout}");
    }
}

#[test]
fn debug_and_warning_print_to_stderr_and_the_check_succeeds() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("messages.scn");
    std::fs::write(
        &scene,
        "camera { location <0, 0, -5>  look_at <0, 0, 0> }\n\
         #debug concat(\"N is \", str(3, 0, 0), \"\\n\")\n\
         #warning \"look here\"\n",
    )
    .unwrap();
    let output = raydiance(&["check", scene.to_str().unwrap()]);
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stderr(&output);
    assert!(text.contains("N is 3\n"), "{text}");
    assert!(text.contains("messages.scn:3:1: warning: look here"), "{text}");
}

/// A scene that cannot emit light, and images that come out black or nearly so, are warned
/// about with what to try; a well-lit render says nothing of the kind.
#[test]
fn dark_scenes_and_black_images_are_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let camera = "settings { resolution 16, 16  samples 2 }\n\
                  camera { location <0, 0, -40>  look_at <0, 0, 0>  angle 5 }\n";
    let ball = "sphere { <0, 0, 0>, 1  material { diffuse rgb 0.8 } }\n";
    let write = |name: &str, text: String| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_string()
    };
    let unlit = write("unlit.scn", format!("{camera}{ball}"));
    let weak =
        write("weak.scn", format!("{camera}{ball}light_source {{ <0, 0, -60> power rgb 1 }}"));
    let lit =
        write("lit.scn", format!("{camera}{ball}light_source {{ <0, 0, -60> power rgb 4000 }}"));
    let out = dir.path().join("out.exr");
    let out = out.to_str().unwrap();

    let check = raydiance(&["check", &unlit]);
    assert!(check.status.success());
    let summary = String::from_utf8_lossy(&check.stdout);
    assert!(summary.contains("warning: the scene emits no light"), "{summary}");
    let render = raydiance(&["render", &unlit, "-o", out]);
    assert!(render.status.success());
    assert!(stderr(&render).contains("warning: the image is black: every pixel is 0"));

    // 1 W/sr at 59 units: radiance 0.8/π/59² ≈ 7e-5 on the ball, 3 of 255 once tone-mapped.
    let render = raydiance(&["render", &weak, "-o", out]);
    assert!(render.status.success());
    let text = stderr(&render);
    assert!(!text.contains("emits no light"), "{text}");
    assert!(text.contains("warning: the image is almost black") && text.contains("1/r²"), "{text}");

    let render = raydiance(&["render", &lit, "-o", out]);
    assert!(render.status.success());
    assert!(!stderr(&render).contains("warning"), "{}", stderr(&render));
}

/// Messages say what was given, not what an internal step met: a negative share or number is a
/// bad value (not clap's "use '-- -1'", which would make it the scene), `scale 1e30` is too
/// large (not "singular"), a folder where no file can be made is named by the output, not by a
/// `.tmpXXXXXX` tried in it, a part given twice is one file (not two parts that overlap), an
/// include found nowhere says where it was looked for, an empty scene is empty (not only
/// missing its camera), and an EXR the decoder cannot read says so before the decoder's words.
#[test]
fn messages_name_what_was_given() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.exr");
    let out = out.to_str().unwrap();
    let output = raydiance(&["render", "scenes/lab4-direct.scn", "-o", out, "--part", "-1/2"]);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("`-1/2` is not a share I/N"), "{}", stderr(&output));

    let scene = dir.path().join("huge.scn");
    let text = "camera { location <0, 0, -3>  look_at <0, 0, 0> }\nsphere { 0, 1 scale 1e30 }\n";
    std::fs::write(&scene, text).unwrap();
    let output = raydiance(&["check", scene.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    let expected = "huge.scn:2:1: error: the transforms of this object scale it beyond what 32-bit";
    assert!(stderr(&output).contains(expected), "{}", stderr(&output));

    let output = raydiance(&["render", "scenes/lab4-direct.scn", "-o", "/proc/out.exr"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).starts_with("error: /proc/out.exr: "), "{}", stderr(&output));
    assert!(!stderr(&output).contains(".tmp"), "{}", stderr(&output));

    for (option, value) in [("--samples", "-3"), ("--seed", "-1"), ("--width", "-8")] {
        let output = raydiance(&["render", "scenes/lab4-direct.scn", "-o", out, option, value]);
        let text = stderr(&output);
        assert!(text.contains(&format!("invalid value '{value}' for '{option}")), "{text}");
        assert!(!text.contains("-- "), "{text}");
    }

    let part = dir.path().join("part.exr");
    let part = part.to_str().unwrap();
    let args = ["render", "scenes/lab4-direct.scn", "-o", part, "--part", "0/2"];
    assert!(raydiance(&[&args[..], &["--width", "4", "--height", "4"]].concat()).status.success());
    let same = format!("{}/./part.exr", dir.path().display());
    let output = raydiance(&["merge", part, &same, "-o", out, "--allow-partial"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr(&output).contains("are the same file"), "{}", stderr(&output));

    let scene = dir.path().join("include.scn");
    std::fs::write(&scene, "#include \"colours.inc\"\n").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["check", scene.to_str().unwrap()])
        .env("RAYDIANCE_INCLUDE_PATH", "/nowhere")
        .output()
        .unwrap();
    let expected = "include.scn:1:1: error: cannot read `colours.inc`: there is no file";
    assert!(stderr(&output).contains(expected), "{}", stderr(&output));
    let expected = "nor in the folders of RAYDIANCE_INCLUDE_PATH (/nowhere)";
    assert!(stderr(&output).contains(expected), "{}", stderr(&output));

    std::fs::write(&scene, "\n").unwrap();
    let output = raydiance(&["check", scene.to_str().unwrap()]);
    assert!(stderr(&output).contains("error: the scene is empty"), "{}", stderr(&output));
    let empty = dir.path().join("empty.exr");
    std::fs::write(&empty, "").unwrap();
    let png = dir.path().join("out.png");
    let output = raydiance(&["tonemap", empty.to_str().unwrap(), "-o", png.to_str().unwrap()]);
    let expected = "empty.exr: not a readable OpenEXR file (";
    assert!(stderr(&output).contains(expected), "{}", stderr(&output));
}
