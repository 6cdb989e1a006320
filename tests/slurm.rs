//! End to end on a real Slurm started on this machine (`deploy/slurm/local-slurm.sh`): a job
//! array of 4 shares rendered with `--part auto` and the merge job that depends on it make the
//! image of one render. Skipped, with a line saying so, where Slurm is not installed; under CI
//! (`.ci/run` installs it) it must run.

mod common;

use std::process::Command;

#[test]
fn a_slurm_array_of_four_shares_and_its_merge_job_make_the_single_render() {
    let test = "a_slurm_array_of_four_shares_and_its_merge_job_make_the_single_render";
    for (tool, package) in [
        ("slurmctld", "slurmctld"),
        ("slurmd", "slurmd"),
        ("sbatch", "slurm-client"),
        ("munged", "munge"),
    ] {
        if !common::outside_tool(tool, package, test) {
            return;
        }
    }
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
    let merged = raydiance::image::read_hdr(&out.join("image.exr")).unwrap();
    let single = raydiance::image::read_hdr(&single).unwrap();
    assert_eq!((merged.width, merged.height), (40, 30));
    for (i, (a, b)) in merged.pixels.iter().zip(&single.pixels).enumerate() {
        let scale = a.abs().max(b.abs()).max_element();
        assert!((*a - *b).abs().max_element() <= 1e-6 * scale, "pixel {i}: {a} and {b}");
    }
    // Each task rendered its own share, told by Slurm.
    for task in 0..4 {
        let log = std::fs::read_to_string(out.join(format!("render-{task}.log"))).unwrap();
        assert!(log.contains(&format!("Slurm task {task} of 4: share {task}/4")), "{log}");
    }
}
