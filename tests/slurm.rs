//! End to end on a real Slurm started on this machine (`deploy/slurm/local-slurm.sh`): a job
//! array of 4 shares rendered with `--part auto` and the merge job that depends on it make the
//! image of one render; an array of 2 frames times 2 shares makes each frame's. Skipped, with a line saying so, where Slurm is not installed; under CI
//! (`.ci/run` installs it) it must run.

use crate::common;

use std::path::Path;
use std::process::Command;
use std::sync::Mutex;

/// Two local Slurms at once on one machine do not both come up: the tests take turns.
static ONE_SLURM_AT_A_TIME: Mutex<()> = Mutex::new(());

/// Whether Slurm's daemons and client are installed (else the test is skipped, saying so).
fn slurm_installed(test: &str) -> bool {
    let tools = [
        ("slurmctld", "slurmctld"),
        ("slurmd", "slurmd"),
        ("sbatch", "slurm-client"),
        ("munged", "munge"),
    ];
    tools.iter().all(|(tool, package)| common::outside_tool(tool, package, test))
}

fn assert_close(a: &Path, b: &Path) {
    let (a, b) = (raydiance::image::read_hdr(a).unwrap(), raydiance::image::read_hdr(b).unwrap());
    assert_eq!((a.width, a.height), (b.width, b.height));
    for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        let scale = p.abs().max(q.abs()).max_element();
        assert!((*p - *q).abs().max_element() <= 1e-6 * scale, "pixel {i}: {p} and {q}");
    }
}

#[test]
fn a_slurm_array_of_four_shares_and_its_merge_job_make_the_single_render() {
    let test = "a_slurm_array_of_four_shares_and_its_merge_job_make_the_single_render";
    if !slurm_installed(test) {
        return;
    }
    let _turn = ONE_SLURM_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("farm");
    let options = ["--width", "40", "--height", "30", "--samples", "8"];
    let binary = env!("CARGO_BIN_EXE_raydiance");
    let run = Command::new("deploy/slurm/local-slurm.sh")
        .args(["scenes/cornell-area.scn", out.to_str().unwrap(), "4", "--"])
        .args(options)
        .env("RAYDIANCE", binary)
        .output()
        .unwrap();
    let log =
        String::from_utf8_lossy(&run.stdout).into_owned() + &String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "local Slurm run failed:\n{log}");
    assert_eq!(log.matches("raydiance-render JobState=COMPLETED").count(), 4, "{log}");
    assert!(log.contains("raydiance-merge JobState=COMPLETED"), "{log}");
    let single = dir.path().join("single.exr");
    let render = Command::new(binary)
        .args(["render", "scenes/cornell-area.scn", "-o", single.to_str().unwrap()])
        .args(options)
        .output()
        .unwrap();
    assert!(render.status.success());
    assert_close(&out.join("image.exr"), &single);
    // Each task rendered its own share, told by Slurm.
    for task in 0..4 {
        let log = std::fs::read_to_string(out.join(format!("render-{task}.log"))).unwrap();
        assert!(log.contains(&format!("Slurm task {task} of 4: share {task}/4")), "{log}");
    }
}

#[test]
fn a_slurm_array_of_frames_times_shares_merges_each_frame() {
    let test = "a_slurm_array_of_frames_times_shares_merges_each_frame";
    if !slurm_installed(test) {
        return;
    }
    let _turn = ONE_SLURM_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("anim.scn");
    std::fs::write(
        &scene,
        "settings { resolution 32, 24  samples 4  integrator path }
         camera { location <0, 0, -4>  look_at <0, 0, 0>  angle 50 }
         light_source { <0, 2, -2>  power rgb 5 }
         plane { <0, 1, 0>, 1  material { diffuse rgb 0.8 } }
         sphere { <clock * 2 - 1, 0, 0>, 0.5  material { diffuse rgb 0.6 } }",
    )
    .unwrap();
    let out = dir.path().join("farm");
    let binary = env!("CARGO_BIN_EXE_raydiance");
    let run = Command::new("deploy/slurm/local-slurm.sh")
        .args([scene.to_str().unwrap(), out.to_str().unwrap(), "2", "--frames", "0..1"])
        .env("RAYDIANCE", binary)
        .output()
        .unwrap();
    let log =
        String::from_utf8_lossy(&run.stdout).into_owned() + &String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "local Slurm run failed:\n{log}");
    assert_eq!(log.matches("raydiance-render JobState=COMPLETED").count(), 4, "{log}");
    for frame in ["0", "1"] {
        let single = dir.path().join(format!("single-{frame}.exr"));
        let render = Command::new(binary)
            .args(["render", scene.to_str().unwrap(), "-o", single.to_str().unwrap()])
            .args(["--frames", "0..1", "--frame", frame])
            .output()
            .unwrap();
        assert!(render.status.success());
        let single = dir.path().join(format!("single-{frame}{frame}.exr"));
        assert_close(&out.join(format!("frame-000{frame}.exr")), &single);
    }
}
