//! Hostile input cannot take the machine: special files, huge sizes and counts are refused
//! before any work, under a memory cap and a time limit set here, so that a regression fails the
//! test instead of exhausting the machine. Outputs are never mangled or put in the wrong place.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The most address space a run here may take.
const MEMORY_CAP: &str = "--as=2147483648";

/// Runs raydiance with `args` under the memory cap; fails the test if it takes longer than
/// `seconds` (and then kills it).
fn limited(args: &[&str], seconds: u64) -> Output {
    limited_to(MEMORY_CAP, args, seconds)
}

/// `limited` under another address-space cap (prlimit's `--as=BYTES`).
fn limited_to(memory_cap: &str, args: &[&str], seconds: u64) -> Output {
    let mut child = Command::new("prlimit")
        .args([memory_cap, "--", env!("CARGO_BIN_EXE_raydiance")])
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("prlimit (util-linux) runs the command");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(seconds) {
            child.kill().unwrap();
            panic!("{args:?} ran longer than {seconds} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// A clean refusal: exit status 1 (not a panic's 101, not a signal), the message on stderr.
fn assert_refused(output: &Output, expected: &str) {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains(expected), "expected `{expected}` in:\n{stderr}");
}

const SMALL_SCENE: &str = "camera { location <0, 0, -3>  look_at <0, 0, 0> }
light_source { <0, 2, -2>  power rgb 5 }
sphere { <0, 0, 0>, 1  material { diffuse rgb 0.5 } }
";

fn write_scene(dir: &Path, name: &str, extra: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, format!("{SMALL_SCENE}{extra}")).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn a_film_too_large_for_memory_is_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.scn", "");
    let out = dir.path().join("out.exr");
    let args = ["render", &scene, "-o", out.to_str().unwrap(), "--width", "65536"];
    let output = limited(&[&args[..], &["--height", "65536"]].concat(), 10);
    assert_refused(&output, "a 65536x65536 film needs 384.0 GiB");
    assert!(!out.exists());
    // The bound is an option: a small one refuses a small film.
    let args = ["render", &scene, "-o", out.to_str().unwrap(), "--max-memory", "0.00001"];
    assert_refused(&limited(&args, 10), "more than --max-memory 0.0 GiB allows");
}

#[test]
fn counts_beyond_reason_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.scn", "");
    let out = dir.path().join("out.exr");
    let output =
        limited(&["render", &scene, "-o", out.to_str().unwrap(), "--threads", "100000"], 10);
    assert_refused(&output, "--threads 100000 is out of range (1 to 1024)");
    let output = limited(&["bench", &scene, "--repeats", "1000000000000"], 10);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "a command-line error:\n{stderr}");
    assert!(stderr.contains("1000000000000"), "{stderr}");
}

/// FIFOs, devices and folders named as meshes, images and tone-mapping inputs: an error that
/// names them, at once (a FIFO opened for reading would wait for a writer for ever).
#[test]
fn special_files_are_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = |name: &str| {
        let path = dir.path().join(name);
        assert!(Command::new("mkfifo").arg(&path).status().unwrap().success());
        path
    };
    let device = |name: &str| {
        let path = dir.path().join(name);
        std::os::unix::fs::symlink("/dev/urandom", &path).unwrap();
        path
    };
    let out = dir.path().join("out.png");
    let out = out.to_str().unwrap();
    for (mesh, kind) in [(fifo("pipe.ply"), "a FIFO"), (device("random.ply"), "a device")] {
        let name = mesh.file_name().unwrap().to_str().unwrap();
        let scene = write_scene(dir.path(), "mesh.scn", &format!("mesh {{ \"{name}\" }}"));
        let output = limited(&["render", &scene, "-o", out], 10);
        assert_refused(&output, &format!("{name}: cannot read: not a regular file ({kind})"));
    }
    for (image, kind) in [(fifo("pipe.png"), "a FIFO"), (device("random.png"), "a device")] {
        let name = image.file_name().unwrap().to_str().unwrap();
        let texture = format!("box {{ -1, 1  material {{ diffuse image_map {{ \"{name}\" }} }} }}");
        let scene = write_scene(dir.path(), "image.scn", &texture);
        let output = limited(&["render", &scene, "-o", out], 10);
        assert_refused(&output, &format!("{name}: not a regular file ({kind})"));
    }
    for (input, kind) in [(fifo("pipe.ppm"), "a FIFO"), (device("random.exr"), "a device")] {
        let output = limited(&["tonemap", input.to_str().unwrap(), "-o", out], 10);
        assert_refused(&output, &format!("{}: not a regular file ({kind})", input.display()));
    }
    let folder = dir.path().join("folder.ppm");
    std::fs::create_dir(&folder).unwrap();
    let output = limited(&["tonemap", folder.to_str().unwrap(), "-o", out], 10);
    assert_refused(&output, "not a regular file (a folder)");
    assert!(!Path::new(out).exists());
}

/// CRC-32 (ISO-HDLC), for a PNG chunk written by hand.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &byte in bytes {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 { (crc >> 1) ^ 0xedb8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

/// A PNG of 65 bytes that declares 15000 x 11000 pixels: refused from its header,
/// before anything is decoded.
#[test]
fn an_image_declaring_too_many_texels_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let mut header = b"IHDR".to_vec();
    header.extend(15000u32.to_be_bytes());
    header.extend(11000u32.to_be_bytes());
    header.extend([8, 2, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    // An empty zlib stream for the pixels: a decoder would find them missing only later.
    let data = [b"IDAT".as_slice(), &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01]].concat();
    for chunk in [header, data, b"IEND".to_vec()] {
        png.extend((chunk.len() as u32 - 4).to_be_bytes());
        png.extend(&chunk);
        png.extend(crc32(&chunk).to_be_bytes());
    }
    std::fs::write(dir.path().join("huge.png"), png).unwrap();
    let texture = "box { -1, 1  material { diffuse image_map { \"huge.png\" } } }";
    let scene = write_scene(dir.path(), "s.scn", texture);
    let out = dir.path().join("out.png");
    let output = limited(&["render", &scene, "-o", out.to_str().unwrap()], 10);
    assert_refused(&output, "15000 x 11000 texels, more than raydiance reads in one image");
}

/// A binary PPM whose header declares 18000 x 18000 pixels, in a sparse file of the size that
/// needs: refused from the header's pixel count (as an EXR's), before samples are allocated.
#[test]
fn a_ppm_declaring_too_many_pixels_is_refused_from_its_header() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.ppm");
    let header = b"P6\n18000 18000\n255\n";
    let file = std::fs::File::create(&path).unwrap();
    std::io::Write::write_all(&mut &file, header).unwrap();
    file.set_len(header.len() as u64 + 18000 * 18000 * 3).unwrap();
    let out = dir.path().join("out.png");
    // Under a cap smaller than the file: refused from the header, before the rest is read.
    let args = ["tonemap", path.to_str().unwrap(), "-o", out.to_str().unwrap()];
    let output = limited_to("--as=536870912", &args, 20);
    let expected = "the image is 18000 x 18000 pixels, more than raydiance reads (33554432)";
    assert_refused(&output, expected);
    assert!(!out.exists());
}

/// Reading a P3 PPM is linear in its size: a 512 x 512 HDR PPM as `render` writes it (1.6
/// million numbers) tone-maps in seconds (46 s when every token counted the lines before it).
#[test]
fn a_large_plain_ppm_tone_maps_in_linear_time() {
    let dir = tempfile::tempdir().unwrap();
    let hdr = dir.path().join("big.ppm");
    let pixels: String =
        (0..512 * 512).map(|i| format!("{} {} {}\n", i % 7, i % 1000, 9)).collect();
    std::fs::write(&hdr, format!("P3\n#MAX=12.5\n512 512\n1000\n{pixels}")).unwrap();
    let out = dir.path().join("out.png");
    let output = limited(&["tonemap", hdr.to_str().unwrap(), "-o", out.to_str().unwrap()], 20);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
}

#[test]
fn non_finite_pixels_take_no_part_in_tone_mapping() {
    use glam::Vec3;
    use raydiance::tonemap::{Operator, ToneMap, tonemap};
    let mut image = raydiance::image::Image::new(4, 1);
    image.pixels = vec![Vec3::splat(0.5), Vec3::splat(2.0), Vec3::INFINITY, Vec3::NAN];
    for op in [Operator::Equalize, Operator::Gamma, Operator::Reinhard] {
        let display = tonemap(&image, &ToneMap { op, ..Default::default() });
        assert!(display[0].x > 0.0 && display[1].x > display[0].x, "{op}: {display:?}");
        assert_eq!(display[2], display[1], "{op}: +inf stands for the largest finite value");
        assert_eq!(display[3], Vec3::ZERO, "{op}: NaN is black");
    }
    assert_eq!(raydiance::tonemap::non_finite_pixels(&image), 2);
}

#[test]
fn outputs_are_never_mangled_or_misplaced() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.scn", "");
    let small = ["--width", "8", "--height", "8", "--samples", "2"];
    // A name that would end the PPM's comment line and forge a header.
    let forged = dir.path().join("x\n#MAX=1000\n#.ppm");
    let output =
        limited(&[&["render", &scene, "-o", forged.to_str().unwrap()], &small[..]].concat(), 20);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let bytes = std::fs::read(&forged).unwrap();
    let text = String::from_utf8_lossy(&bytes);
    assert_eq!(text.lines().nth(2), Some("# x\\n#MAX=1000\\n#.ppm"), "{text}");
    let image = raydiance::image::ppm::parse(&bytes).unwrap();
    let max_line = text.lines().nth(1).unwrap();
    assert_eq!(max_line, format!("#MAX={}", image.max_component()), "the real MAX decodes");

    // Tone mapping a file onto itself would replace the HDR input.
    let before = std::fs::read(&forged).unwrap();
    let output =
        limited(&["tonemap", forged.to_str().unwrap(), "-o", forged.to_str().unwrap()], 10);
    assert_refused(&output, "is the input; tone mapping would replace it");
    assert_eq!(std::fs::read(&forged).unwrap(), before);

    // A folder in the output's place is refused before rendering.
    let folder = dir.path().join("taken.exr");
    std::fs::create_dir(&folder).unwrap();
    let start = Instant::now();
    let args = ["render", &scene, "-o", folder.to_str().unwrap(), "--samples", "100000"];
    assert_refused(&limited(&args, 10), "is a folder, not a file to write");
    assert!(start.elapsed() < Duration::from_secs(5), "refused before rendering");

    // A replaced file keeps its read and write permissions, never setuid or setgid.
    use std::os::unix::fs::PermissionsExt;
    let replaced = dir.path().join("replaced.png");
    std::fs::write(&replaced, b"old").unwrap();
    std::fs::set_permissions(&replaced, std::fs::Permissions::from_mode(0o6755)).unwrap();
    let output =
        limited(&[&["render", &scene, "-o", replaced.to_str().unwrap()], &small[..]].concat(), 20);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let mode = std::fs::metadata(&replaced).unwrap().permissions().mode() & 0o7777;
    assert_eq!(mode, 0o755, "{mode:o}");
}

/// `raydiance check scene | head -0`: the summary cannot be written, and that is no panic.
#[test]
fn a_closed_stdout_is_no_panic() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.scn", "");
    let mut child = Command::new(env!("CARGO_BIN_EXE_raydiance"))
        .args(["check", &scene])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// Writes scene text to `dir/NAME`; `check` and `render` both refuse it, naming `expected`.
fn assert_scene_refused(dir: &Path, name: &str, text: &str, expected: &str) {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let (scene, out) = (path.to_str().unwrap(), dir.join("out.exr"));
    assert_refused(&limited(&["check", scene], 20), expected);
    assert_refused(&limited(&["render", scene, "-o", out.to_str().unwrap()], 20), expected);
    assert!(!out.exists());
}

/// A few lines that stand for 2^26 objects or texture nodes are refused from their counts,
/// before anything is expanded.
#[test]
fn expansion_bombs_are_refused_before_they_expand() {
    let dir = tempfile::tempdir().unwrap();
    let mut objects = String::from("#declare O0 = sphere { 0, 1 }\n");
    for i in 1..=26 {
        objects += &format!(
            "#declare O{i} = union {{ object {{ O{} }} object {{ O{} }} }}\n",
            i - 1,
            i - 1
        );
    }
    objects += "object { O26 }\n";
    let text = format!("{SMALL_SCENE}{objects}");
    assert_scene_refused(dir.path(), "objects.scn", &text, "the scene has 67108865 primitives");

    let mut textures = String::from("#declare T0 = checker { rgb 1, rgb 0 }\n");
    for i in 1..=26 {
        textures += &format!("#declare T{i} = mix {{ T{}, T{}, rgb 0.5 }}\n", i - 1, i - 1);
    }
    let text = format!("{SMALL_SCENE}{textures}");
    assert_scene_refused(dir.path(), "textures.scn", &text, "at most 65536 nodes nested 64 deep");

    let chain = "#declare T = mix { T, rgb 0, rgb 0.5 }\n".repeat(10_000);
    let text = format!("{SMALL_SCENE}#declare T = rgb 1\n{chain}");
    assert_scene_refused(dir.path(), "chain.scn", &text, "nested 65 deep");
}

/// A loop that never ends, making a union of a hundred spheres on each turn, is stopped by the
/// count of objects made (at 2^22, some half a gigabyte) long before its loop turns run out.
#[test]
fn a_loop_making_objects_is_stopped_by_their_count() {
    let dir = tempfile::tempdir().unwrap();
    let spheres: String = (0..100).map(|k| format!("sphere {{ <I, {k}, 0>, 1 }} ")).collect();
    let text = format!(
        "{SMALL_SCENE}#declare I = 0;\n#while (1) union {{ {spheres}}} #declare I = I + 1; #end\n"
    );
    let path = dir.path().join("loop.scn");
    std::fs::write(&path, text).unwrap();
    let refused = limited(&["check", path.to_str().unwrap()], 120);
    assert_refused(&refused, &format!("more than {} objects", raydiance::lang::MAX_OBJECTS_MADE));
}

/// 31 files, each including the next twice, would read 2^31 files.
#[test]
fn an_include_bomb_is_refused_by_its_count() {
    let dir = tempfile::tempdir().unwrap();
    for i in 0..31 {
        let next = format!("#include \"f{}.inc\"\n", i + 1);
        std::fs::write(dir.path().join(format!("f{i}.inc")), next.repeat(2)).unwrap();
    }
    std::fs::write(dir.path().join("f31.inc"), "").unwrap();
    let text = format!("{SMALL_SCENE}#include \"f0.inc\"\n");
    assert_scene_refused(dir.path(), "includes.scn", &text, "more than 10000 files included");
    let text = format!("{SMALL_SCENE}#include \"/dev/zero\"\n");
    assert_scene_refused(dir.path(), "zero.scn", &text, "not a regular file (a device)");
    let fifo = dir.path().join("pipe.scn");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    assert_refused(&limited(&["check", fifo.to_str().unwrap()], 10), "not a regular file (a FIFO)");
}

/// Positions come from a line index and error excerpts are clipped around the column: a scene
/// of a megabyte on one line checks in time linear in its size, and an error in it, or at a
/// 30,000-character name, is a few lines long. Control characters in names are shown escaped.
#[test]
fn long_lines_and_names_give_short_errors_in_linear_time() {
    let dir = tempfile::tempdir().unwrap();
    let spheres: Vec<String> =
        (0..40_000).map(|i| format!("sphere {{ <{}, 0, 0>, 0.1 }}", i % 100)).collect();
    let one_line =
        format!("camera {{ location <0, 0, -5>  look_at <0, 0, 0> }} {}", spheres.join(" "));
    let path = dir.path().join("one_line.scn");
    std::fs::write(&path, &one_line).unwrap();
    let output = limited(&["check", path.to_str().unwrap()], 20);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));

    std::fs::write(&path, format!("{one_line} sphere {{ <0, 0, 0> 0.1 }}")).unwrap();
    let output = limited(&["check", path.to_str().unwrap()], 20);
    assert_refused(&output, "is a `,` missing?");
    assert!(output.stderr.len() < 2000, "{} bytes of error", output.stderr.len());

    let name = "x".repeat(30_000);
    let text = format!("sphere {{ 0, {name} }}");
    let output = limited(&["check", &write_scene(dir.path(), "name.scn", &text)], 20);
    assert_refused(&output, "unknown identifier `xxxx");
    assert!(output.stderr.len() < 2000, "{} bytes of error", output.stderr.len());

    let text = "mesh { \"bell\u{7}\u{1b}[31m.ply\" }";
    let output = limited(&["check", &write_scene(dir.path(), "escape.scn", text)], 20);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!stderr.contains('\u{1b}') && !stderr.contains('\u{7}'), "{stderr:?}");
    assert!(stderr.contains("bell\\u{7}\\u{1b}[31m.ply"), "{stderr}");
}

/// Numbers finite in the language's f64 but not in the renderer's f32 (or that vanish there)
/// are located errors, not black images or missing objects.
#[test]
fn numbers_beyond_f32_are_located_errors() {
    let dir = tempfile::tempdir().unwrap();
    for (object, expected) in [
        ("sphere { <1e39, 0, 0>, 1 }", "1e39 is too large"),
        ("sphere { 0, 1e-50 }", "1e-50 is too small"),
        ("light_source { <0, 1, 0>  power rgb 1e39 }", "1e39 is too large"),
        ("plane { <0, 1, 0>, -1e40 }", "-1e40 is too large"),
    ] {
        let output = limited(&["check", &write_scene(dir.path(), "n.scn", object)], 10);
        assert_refused(&output, expected);
        assert!(String::from_utf8_lossy(&output.stderr).contains("n.scn:4:"), "{object}");
    }
    let camera = "camera { origin <0, 0, -3e39>  left <1, 0, 0>  up <0, 1, 0>  forward <0, 0, 1> }";
    let path = dir.path().join("camera.scn");
    std::fs::write(&path, camera).unwrap();
    let output = limited(&["check", path.to_str().unwrap()], 10);
    assert_refused(&output, "camera.scn:1:10: error: -3e39 is too large");
}

/// The language's work is budgeted: a macro calling itself twice, which would make 2^41 calls,
/// is stopped by the count of macro calls, at the call.
#[test]
fn an_exponential_macro_is_stopped_by_the_count_of_calls() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("{SMALL_SCENE}#macro F(N) #if (N > 0) F(N-1) F(N-1) #end #end\nF(40)\n");
    let start = Instant::now();
    let expected = format!("more than {} macro calls", raydiance::lang::MAX_MACRO_CALLS);
    assert_scene_refused(dir.path(), "macro.scn", &text, &expected);
    // Both runs (debug build) in well under the 2^41 calls' weeks.
    assert!(start.elapsed() < Duration::from_secs(30), "{:?}", start.elapsed());
}

/// Strings are bounded where `concat` makes them, and appending to a variable takes time linear
/// in the length made: 200,000 appends of 5 bytes stay far from the quadratic 10^11 bytes copied.
#[test]
fn strings_are_bounded_and_appends_linear() {
    let dir = tempfile::tempdir().unwrap();
    let doubling = "#declare S = \"x\";\n#for (I, 1, 40) #declare S = concat(S, S); #end\n";
    let text = format!("{SMALL_SCENE}{doubling}");
    let expected = "double.scn:5:30: error: a string of 2097152 bytes: at most 1048576 are allowed";
    assert_scene_refused(dir.path(), "double.scn", &text, expected);
    let appends =
        "#declare S = \"\";\n#for (I, 1, 200000) #declare S = concat(S, \"abcde\"); #end\n";
    let path = dir.path().join("append.scn");
    std::fs::write(&path, format!("{SMALL_SCENE}{appends}")).unwrap();
    let output = limited(&["check", path.to_str().unwrap()], 30);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
}

/// A mesh whose bad token is 20 MB long, with escape sequences: the error quotes a clipped,
/// escaped excerpt of it.
#[test]
fn a_huge_token_in_a_mesh_is_quoted_short_and_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let token = format!("\u{1b}[31m{}", "9".repeat(20 << 20));
    let ply = format!(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         {token} 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
    );
    std::fs::write(dir.path().join("huge.ply"), ply).unwrap();
    let output =
        limited(&["check", &write_scene(dir.path(), "m.scn", "mesh { \"huge.ply\" }")], 20);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{}", &stderr[..stderr.len().min(500)]);
    assert!(output.stderr.len() < 2000, "{} bytes of error", output.stderr.len());
    assert!(!stderr.contains('\u{1b}'), "{stderr:?}");
}

/// Arrays are held in shared chunks and counted scene-wide: declaring a 10-million-element array
/// a thousand times, or writing into a copy of one, copies a chunk, not the array; a loop of
/// copies written into is stopped by the count of elements made or copied.
#[test]
fn arrays_are_counted_scene_wide_and_written_without_a_whole_copy() {
    let dir = tempfile::tempdir().unwrap();
    let redeclared = "#for (I, 0, 999) #declare A = array[9999999]; #end\n\
                      #declare A[5] = -1;\n#declare B = A;\n\
                      #for (I, 0, 99) #declare B[I * 99991 + 5] = I; #end\n\
                      #if (B[99 * 99991 + 5] != 99) #error \"the write is lost\" #end\n\
                      #if (A[5] != -1) #error \"the copy's write reached A\" #end\n";
    let path = dir.path().join("arrays.scn");
    std::fs::write(&path, format!("{SMALL_SCENE}{redeclared}")).unwrap();
    let output = limited(&["check", path.to_str().unwrap()], 30);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));

    let copies = "#declare A = array[9999999];\n\
                  #for (I, 0, 9999998, 1024) #declare B = A; #declare B[I] = 1; #end\n";
    let expected = format!(
        "arrays.scn:5:53: error: more than {} array elements made or copied",
        raydiance::lang::MAX_ARRAY_ELEMENTS_MADE
    );
    assert_scene_refused(dir.path(), "arrays.scn", &format!("{SMALL_SCENE}{copies}"), &expected);
}

/// Suggestions for an unknown name compare only names of about its length, and none for a name
/// longer than a name is written: ten 40,000-character names and an unknown one are an error at
/// once.
#[test]
fn suggestions_for_long_names_are_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let declares: String =
        (0..10).map(|i| format!("#declare {}{i} = 1;\n", "n".repeat(40_000))).collect();
    let text = format!("{declares}sphere {{ 0, {}x }}\n", "n".repeat(40_000));
    let start = Instant::now();
    let output = limited(&["check", &write_scene(dir.path(), "names.scn", &text)], 20);
    assert_refused(&output, "unknown identifier `nnnn");
    assert!(start.elapsed() < Duration::from_secs(5), "{:?}", start.elapsed());
}

/// Writes a part file as `render --part` would, with a header and means made up here: a
/// `width` x `height` image, its crop `crop`, share `share` of `samples` samples per pixel, each
/// pixel's one sample `mean`.
fn forged_part(path: &Path, size: (u32, u32), crop: &str, share: &str, samples: u32, mean: f64) {
    use raydiance::region::{Crop, Region};
    let crop: Crop = crop.parse().unwrap();
    let mut film = raydiance::film::Film::new(crop.width() as usize, crop.height() as usize);
    film.samples = 1;
    film.sum.iter_mut().for_each(|s| *s = glam::DVec3::splat(mean));
    let header = raydiance::split::part_file::PartHeader {
        path: path.to_path_buf(),
        width: size.0,
        height: size.1,
        region: Region { crop, share: share.parse().unwrap(), samples },
        taken: 1,
        seed: 0,
        integrator: "path".to_string(),
        max_depth: 8,
        digest: "forged".to_string(),
        frame: raydiance::animation::Frame::default(),
        seconds: 1.0,
        aovs: Default::default(),
    };
    raydiance::split::part_file::write(path, &film, &header).unwrap();
}

/// `merge` believes no size a part's header states: one past 65,536 a side is refused, and a
/// 65536 x 65536 image, allowed, is refused from its memory before anything is allocated.
#[test]
fn merge_bounds_the_image_size_and_memory_from_the_headers() {
    let dir = tempfile::tempdir().unwrap();
    let (part, out) = (dir.path().join("part.exr"), dir.path().join("out.exr"));
    let merge = |partial: &[&str]| {
        let args = ["merge", part.to_str().unwrap(), "-o", out.to_str().unwrap()];
        limited(&[&args[..], partial].concat(), 20)
    };
    forged_part(&part, (100_000, 1), "0,1,0,1", "0/1", 1, 0.5);
    assert_refused(&merge(&[]), "its header has no valid raydiance:image_size");
    forged_part(&part, (65536, 65536), "0,1,0,1", "0/1", 1, 0.5);
    assert_refused(&merge(&["--allow-partial"]), "merging a 65536x65536 image needs 220.0 GiB");
    assert!(!out.exists());
}

/// One share of 10^8 merged alone: the missing ones are counted, not listed one by one.
#[test]
fn merge_counts_missing_shares_without_listing_them() {
    let dir = tempfile::tempdir().unwrap();
    let (part, out) = (dir.path().join("part.exr"), dir.path().join("out.exr"));
    forged_part(&part, (1, 1), "0,1,0,1", "0/100000000", 100_000_000, 0.5);
    let args = ["merge", part.to_str().unwrap(), "-o", out.to_str().unwrap(), "--allow-partial"];
    let output = limited(&args, 20);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("--part 8/100000000 and 99999991 more"), "{stderr}");
    assert!(stderr.len() < 2000, "{} bytes", stderr.len());
}

/// Missing work in many tiles is listed in a few lines: a share missing in each of 40 tiles
/// (each line once listed every file of its tile, and there was a line for each).
#[test]
fn merge_lists_a_few_pieces_of_missing_work() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec!["merge".to_string()];
    for x in 0..40 {
        let part = dir.path().join(format!("part{x}.exr"));
        forged_part(&part, (40, 1), &format!("{x},{},0,1", x + 1), "0/2", 2, 0.5);
        args.push(part.to_str().unwrap().to_string());
    }
    let out = dir.path().join("out.exr");
    args.extend(["-o".to_string(), out.to_str().unwrap().to_string()]);
    let output = limited(&args.iter().map(String::as_str).collect::<Vec<_>>(), 20);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("and 32 more pieces of missing work"), "{stderr}");
    assert_eq!(stderr.matches("missing shares of crop").count(), 8, "{stderr}");
}

/// A part whose means are not finite, or negative, is damaged: refused, never merged into the
/// image; an integrator that does not render parts is refused with its name escaped.
#[test]
fn merge_refuses_damaged_means_and_forged_integrators() {
    let dir = tempfile::tempdir().unwrap();
    let (part, out) = (dir.path().join("part.exr"), dir.path().join("out.exr"));
    let args = ["merge", part.to_str().unwrap(), "-o", out.to_str().unwrap()];
    for (mean, shown) in [(f64::NAN, "NaN"), (f64::INFINITY, "inf"), (-1.0, "-1")] {
        forged_part(&part, (2, 2), "0,2,0,2", "0/1", 1, mean);
        assert_refused(&limited(&args, 20), &format!("holds the mean [{shown}, {shown}, {shown}]"));
        assert!(!out.exists());
    }
    forged_part(&part, (2, 2), "0,2,0,2", "0/1", 1, 0.5);
    let bytes = std::fs::read(&part).unwrap();
    let at = bytes.windows(4).position(|w| w == b"path").unwrap();
    let mut forged = bytes.clone();
    forged[at..at + 4].copy_from_slice(b"\x1b[1m");
    std::fs::write(&part, forged).unwrap();
    let output = limited(&args, 20);
    assert_refused(&output, "raydiance:integrator `\\u{1b}[1m` is not one that renders parts");
    assert!(!output.stderr.contains(&0x1b));
}

/// Snapshots are small renders: a `--size` or a stored size past 2^22 pixels is refused before
/// anything renders; a scene named `NAME.new.scn`, whose snapshot would be the new render of
/// `NAME.scn` beside it, is refused rather than compared with the wrong image.
#[test]
fn snapshot_sizes_are_bounded_and_names_cannot_collide() {
    use raydiance::snapshot::{self, Estimate, MAX_SNAPSHOT_PIXELS};
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.scn", "");
    let output = limited(&["snapshot", &scene, "--size", "65536x65536"], 20);
    let expected =
        format!("65536x65536: more pixels than a snapshot may have ({MAX_SNAPSHOT_PIXELS})");
    assert_refused(&output, &expected);

    let (width, height) = (2048, 2049);
    let pixels = vec![glam::Vec3::ONE; width * height];
    let stored =
        Estimate { width, height, mean: pixels.clone(), variance: pixels, samples_per_pixel: 64 };
    std::fs::create_dir(dir.path().join("__snapshots__")).unwrap();
    snapshot::write(&dir.path().join("__snapshots__/s.exr"), &stored).unwrap();
    let start = Instant::now();
    assert_refused(&limited(&["snapshot", &scene], 20), "2048x2049: more pixels than a snapshot");
    assert!(start.elapsed() < Duration::from_secs(10), "{:?}", start.elapsed());

    let folder = dir.path().join("scenes");
    std::fs::create_dir(&folder).unwrap();
    write_scene(&folder, "foo.scn", "");
    write_scene(&folder, "foo.new.scn", "");
    let output = limited(&["snapshot", folder.to_str().unwrap()], 60);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("foo.new.scn: a scene named NAME.new.scn cannot be snapshotted"));
    // foo.scn's new render is written; nothing was written as foo.new.scn's.
    assert!(folder.join("__snapshots__/foo.new.exr").exists());
    assert!(!folder.join("__snapshots__/foo.new.new.exr").exists());
}

/// `--frames` is bounded when planned: four billion frames are refused at once, not listed.
#[test]
fn a_range_of_frames_beyond_reason_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.scn", "");
    let out = dir.path().join("f#.exr");
    let args = ["render", &scene, "-o", out.to_str().unwrap(), "--frames", "0..4294967295"];
    let output = limited(&args, 10);
    assert_refused(&output, "--frames 0..4294967295 is 4294967296 frames: one command renders");
    let args = ["render", "missing.scn", "-o", out.to_str().unwrap(), "--frames", "0..99999"];
    assert_refused(&limited(&args, 20), "cannot read `missing.scn`");
}

/// 20 MB of binary PLY faces of 255 vertices stand for 20 million triangles: refused while the
/// faces are read, at the face that passes 2^24 triangles.
#[test]
fn a_mesh_of_too_many_triangles_is_refused_while_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let mut ply = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
                    property float y\nproperty float z\nelement face 80000\n\
                    property list uchar uchar vertex_indices\nend_header\n"
        .to_vec();
    for corner in [[0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        corner.iter().for_each(|c| ply.extend(c.to_le_bytes()));
    }
    for _ in 0..80_000 {
        ply.push(255);
        ply.extend((0..255).map(|i| (i % 3) as u8));
    }
    std::fs::write(dir.path().join("fans.ply"), ply).unwrap();
    let scene = write_scene(dir.path(), "m.scn", "mesh { \"fans.ply\" }");
    let limit = raydiance::mesh::MAX_TRIANGLES;
    let face = limit / 253;
    let expected = format!("face {face}: the mesh has more than {limit} triangles");
    assert_refused(&limited(&["check", &scene], 20), &expected);
}

/// A ray meeting a CSG object is tested against every operand: more than 1,024 are refused
/// (a difference of 10^5 spheres rendered 3000 times slower than their union).
#[test]
fn csg_of_too_many_operands_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let holes = "#for (I, 1, 100000) sphere { <I / 100000, 0, 0>, 0.01 } #end";
    let text = format!("{SMALL_SCENE}difference {{ box {{ -1, 1 }} {holes} }}\n");
    let expected = format!(
        "csg.scn:4:1: error: a difference of 100001 operands: at most {} are allowed",
        raydiance::lang::MAX_CSG_OPERANDS
    );
    assert_scene_refused(dir.path(), "csg.scn", &text, &expected);
}

/// What would silently render nothing is an error: a CSG object of no operands, a mesh whose
/// every triangle has no area.
#[test]
fn empty_csg_and_all_degenerate_meshes_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("{SMALL_SCENE}intersection {{ }}\n");
    assert_scene_refused(dir.path(), "e.scn", &text, "e.scn:4:1: error: an intersection of no");
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nelement face 2\nproperty list uchar int vertex_indices\n\
               end_header\n0 0 0\n1 1 1\n2 2 2\n3 0 1 2\n3 2 1 0\n";
    std::fs::write(dir.path().join("line.ply"), ply).unwrap();
    let text = format!("{SMALL_SCENE}mesh {{ \"line.ply\" }}\n");
    let expected = "all 2 triangles of the mesh are degenerate";
    assert_scene_refused(dir.path(), "m.scn", &text, expected);
}

/// A stored snapshot whose variance no render gives (1e30, more than its mean squared) is refused
/// as damaged instead of matching any render.
#[test]
fn a_snapshot_of_impossible_variance_is_refused() {
    use raydiance::snapshot::{self, Estimate};
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "s.scn", "");
    let stored = Estimate {
        width: 8,
        height: 8,
        mean: vec![glam::Vec3::splat(0.5); 64],
        variance: vec![glam::Vec3::splat(1e30); 64],
        samples_per_pixel: 64,
    };
    std::fs::create_dir(dir.path().join("__snapshots__")).unwrap();
    snapshot::write(&dir.path().join("__snapshots__/s.exr"), &stored).unwrap();
    let output = limited(&["snapshot", &scene], 20);
    assert_refused(&output, "pixel 0's variance 1e30 is more than the square of its mean 5e-1");
}

/// The lab's open box with a point light, and `settings` (issue 31's photon mapping cases).
fn lab_scene(dir: &Path, name: &str, settings: &str) -> String {
    let lab = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/lab-box.inc");
    let text = format!(
        "#include \"{}\"\nlight_source {{ <0, 0.5, 0>  power rgb 1 }}\nsettings {{ {settings} }}\n",
        lab.display()
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn photon_maps_too_large_for_memory_are_refused_before_tracing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.exr");
    // A closed room of white walls keeps every photon to max_depth bounces: 1024 stored each.
    let room = dir.path().join("room.scn");
    std::fs::write(
        &room,
        "camera { location <0, 0, -0.9>  look_at <0, 0, 0> }
light_source { <0, 0.5, 0>  power rgb 10 }
box { <-1, -1, -1>, <1, 1, 1>  material { diffuse rgb 1 } }
settings { integrator photon  max_depth 1024 }
",
    )
    .unwrap();
    let output = limited(&["render", room.to_str().unwrap(), "-o", out.to_str().unwrap()], 10);
    assert_refused(&output, "`photons` 1000000 with `max_depth` 1024 may store 1024000000 photons");
    assert!(String::from_utf8_lossy(&output.stderr).contains("68.7 GiB"));
    // The most photons a pass may emit, at the default depth.
    let most = lab_scene(dir.path(), "most.scn", "integrator photon  photons 20000000");
    let output = limited(&["render", &most, "-o", out.to_str().unwrap()], 10);
    assert_refused(&output, "`photons` 20000000 with `max_depth` 32 may store 640000000 photons");
    assert!(!out.exists());
}

#[test]
fn sppm_memory_does_not_grow_with_the_gather_radius() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.exr");
    // A radius of 5 in a box 2 wide holds every pixel's visible point in every photon's reach.
    // The grid's memory is set by the visible points and the cells their discs cover, not by the
    // photons, so a tenth of the default photons tests it as well in a tenth of the time.
    for radius in ["0.5", "5"] {
        let settings = format!("integrator sppm  photons 20000  photon_radius {radius}");
        let scene = lab_scene(dir.path(), "lab.scn", &settings);
        let args = ["render", &scene, "-o", out.to_str().unwrap(), "--samples", "1"];
        let output = limited(&[&args[..], &["--width", "32", "--height", "32"]].concat(), 300);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(0), "photon_radius {radius}: {stderr}");
        let warned = stderr.contains(&format!("warning: photon_radius {radius} is large"));
        assert!(warned, "photon_radius {radius}: {stderr}");
    }
    // The documented radius draws no warning, and a bound too small refuses by the image.
    let scene = lab_scene(dir.path(), "lab.scn", "integrator sppm");
    let args = ["render", &scene, "-o", out.to_str().unwrap(), "--samples", "1"];
    let output = limited(&[&args[..], &["--width", "32", "--height", "32"]].concat(), 300);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("photon_radius"), "{stderr}");
    let output = limited(&[&args[..], &["--max-memory", "0.01"]].concat(), 10);
    assert_refused(&output, "error: sppm: a 256x256 image needs");
}

/// A sphere flattened by `scale <1, s, 1>`, seen from above, is a disc of radius 1 (its quadric
/// is solved in f64 from the ray's point nearest its centre: in f32 from the camera, |o|^2 - 1
/// lost the disc, a noisy banded square at s = 0.001, nothing at 1e-12); flatter than a 32-bit
/// matrix inverts, it is a located error.
#[test]
fn a_sphere_flattened_by_a_strong_scale_is_a_disc() {
    let dir = tempfile::tempdir().unwrap();
    let (size, half_extent) = (48, 1.25);
    let scene = |scale: &str| {
        format!(
            "settings {{ resolution {size}, {size}  samples 4 }}
camera {{ origin <0, 5, 0>  left <-{half_extent}, 0, 0>  up <0, 0, {half_extent}>  forward <0, -5, 0> }}
sphere {{ 0, 1 scale <1, {scale}, 1>  material {{ emission rgb 1 }} }}
"
        )
    };
    for scale in ["0.001", "1e-6", "1e-12"] {
        let path = dir.path().join("disc.scn");
        std::fs::write(&path, scene(scale)).unwrap();
        let out = dir.path().join("disc.exr");
        let output = limited(&["render", path.to_str().unwrap(), "-o", out.to_str().unwrap()], 60);
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
        let image = raydiance::image::exr::read(&out).unwrap();
        let pixel = 2.0 * half_extent / size as f32;
        let mut inside = 0;
        for y in 0..size {
            for x in 0..size {
                let at = |i: usize| (i as f32 + 0.5) * pixel - half_extent;
                let radius = at(x).hypot(at(y));
                // Away from the rim by more than half a pixel's diagonal: all or nothing.
                if (radius - 1.0).abs() > 0.75 * pixel {
                    let expected = if radius < 1.0 { 1.0 } else { 0.0 };
                    let value = image.pixels[y * size + x].x;
                    assert_eq!(value, expected, "scale {scale}: pixel ({x}, {y}) at r {radius}");
                    inside += usize::from(radius < 1.0);
                }
            }
        }
        assert!(inside > 1000, "scale {scale}: {inside} pixels inside the disc");
    }
    let path = dir.path().join("flat.scn");
    std::fs::write(&path, scene("1e-13")).unwrap();
    let output = limited(&["check", path.to_str().unwrap()], 10);
    assert_refused(&output, "flat.scn:3:1: error: the transforms of this object are singular");
}

/// Scene names that are not UTF-8 keep their own snapshots (two names differing in a byte that
/// is not UTF-8 became one name by the replacement character: each compared with the other's
/// image); a linked scene is snapshotted as the file it names, and a snapshot linked to no file
/// is an error naming it, not a scene without a snapshot.
#[test]
fn snapshot_names_are_taken_byte_for_byte_and_links_followed() {
    use std::ffi::OsStr;
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("scenes");
    std::fs::create_dir(&folder).unwrap();
    let scene = |brightness: &str| {
        format!(
            "settings {{ resolution 8, 8 }}
camera {{ location <0, 0, -3>  look_at <0, 0, 0> }}
sphere {{ 0, 1  material {{ emission rgb {brightness} }} }}
"
        )
    };
    for (byte, brightness) in [(0xfe, "1"), (0xff, "3")] {
        let name = [b'a', byte, b'.', b's', b'c', b'n'];
        std::fs::write(folder.join(OsStr::from_bytes(&name)), scene(brightness)).unwrap();
    }
    let linked = dir.path().join("elsewhere.scn");
    std::fs::write(&linked, scene("2")).unwrap();
    std::os::unix::fs::symlink(&linked, folder.join("link.scn")).unwrap();
    let snapshot = |more: &[&str]| {
        let args = [&["snapshot", folder.to_str().unwrap(), "--samples", "4"][..], more].concat();
        limited(&args, 60)
    };
    assert_eq!(snapshot(&[]).status.code(), Some(1), "new snapshots");
    assert!(snapshot(&["--accept"]).status.success());
    for name in [&b"a\xfe.exr"[..], b"a\xff.exr", b"link.exr"] {
        let stored = folder.join("__snapshots__").join(OsStr::from_bytes(name));
        assert!(stored.exists(), "{}", stored.display());
    }
    let output = snapshot(&[]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "each scene matches its own snapshot: {stdout}");
    assert!(stdout.contains("3 scenes: 3 match"), "the linked scene is one: {stdout}");

    let missing = folder.join("__snapshots__/link.exr");
    std::fs::remove_file(&missing).unwrap();
    std::os::unix::fs::symlink(dir.path().join("nowhere.exr"), &missing).unwrap();
    let output = limited(&["snapshot", folder.join("link.scn").to_str().unwrap()], 60);
    assert_refused(&output, "link.exr");
}

/// Renders `solid` lit by one light, seen from a corner, with the deterministic `direct`
/// integrator; returns the pixels.
fn render_solid(dir: &Path, solid: &str) -> Vec<glam::Vec3> {
    let path = dir.join("solid.scn");
    let text = format!(
        "settings {{ resolution 64, 48  samples 4  integrator direct }}
camera {{ location <3, 2.5, -4>  look_at <0, 0, 0>  angle 50 }}
light_source {{ <5, 6, -7>  power rgb 300 }}
{solid}
"
    );
    std::fs::write(&path, text).unwrap();
    let out = dir.join("solid.exr");
    let output = limited(&["render", path.to_str().unwrap(), "-o", out.to_str().unwrap()], 60);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    raydiance::image::exr::read(&out).unwrap().pixels
}

/// CSG whose operands share faces renders as the solid it makes: a box less a box that shares
/// five of its faces (which showed those faces whole), an intersection of boxes sharing faces,
/// a merge of two boxes touching along a face, a box less a larger box sharing one face.
#[test]
fn csg_of_coincident_surfaces_is_the_solid_it_makes() {
    let dir = tempfile::tempdir().unwrap();
    let material = "material { diffuse rgb 0.7 }";
    let expected =
        render_solid(dir.path(), &format!("box {{ <-1, -1, 0>, <1, 1, 1>  {material} }}"));
    assert!(expected.iter().filter(|p| p.x > 0.0).count() > 500, "the box is in view");
    for solid in [
        "difference { box { -1, 1 }  box { <-1, -1, -1>, <1, 1, 0> }",
        "intersection { box { -1, 1 }  box { <-1, -1, 0>, <1, 1, 1> }",
        "merge { box { <-1, -1, 0>, <1, 1, 0.5> }  box { <-1, -1, 0.5>, <1, 1, 1> }",
        "difference { box { <-1, -1, -1>, <1, 1, 1> }  box { <-2, -2, -2>, <2, 2, 0> }",
    ] {
        let pixels = render_solid(dir.path(), &format!("{solid}  {material} }}"));
        let differing: Vec<_> = pixels
            .iter()
            .zip(&expected)
            .enumerate()
            .filter(|(_, (p, e))| (**p - **e).abs().max_element() > 1e-3)
            .collect();
        // A sample within rounding of an edge may see either face there (one pixel of the
        // first here, by one of its four samples); the faces shown whole were 840 pixels.
        assert!(pixels.iter().all(|p| p.is_finite()), "{solid}");
        assert!(differing.len() <= 2, "{solid}: {differing:?}");
    }
}
