//! The render job `raydiance render` runs, called from the library: what it writes and says,
//! and its refusals as typed errors, with nothing written.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use raydiance::graph::IntegratorKind;
use raydiance::job::{Ended, Observer, RenderJob, RenderJobError};
use raydiance::progress::{Progress, Silent};
use raydiance::region::Share;
use raydiance::split::part_file;
use raydiance::split::plan::{Choices, PartChoice};
use raydiance::{RenderRequest, load_with_digest};

const SCENE: &str = "scenes/lab4-direct.scn";

/// Records what a job says; `interrupted` is what it answers when asked.
#[derive(Default)]
struct Record {
    warnings: Mutex<Vec<String>>,
    written: Mutex<Vec<String>>,
    frames: Mutex<Vec<Option<u64>>>,
    interrupted: bool,
}

impl Observer for Record {
    fn frame_starts(&self, total: Option<u64>) -> Result<Box<dyn Progress + '_>, RenderJobError> {
        self.frames.lock().unwrap().push(total);
        Ok(Box::new(Silent))
    }

    fn warning(&self, text: &str) {
        self.warnings.lock().unwrap().push(text.to_string());
    }

    fn written(&self, summary: &str) {
        self.written.lock().unwrap().push(summary.to_string());
    }

    fn interrupted(&self) -> bool {
        self.interrupted
    }
}

/// The lab scene, 8x6 at 4 samples per pixel, into `output`.
fn small_job(output: &Path) -> RenderJob {
    RenderJob {
        scene: PathBuf::from(SCENE),
        output: Some(output.to_path_buf()),
        request: RenderRequest {
            width: Some(8),
            height: Some(6),
            samples: Some(4),
            ..Default::default()
        },
        ppm_res: 1000,
        max_memory: 1.0,
        ..Default::default()
    }
}

fn run(job: &RenderJob, record: &Record) -> Result<Ended, RenderJobError> {
    job.plan(|_| None)?.render(record)
}

#[test]
fn a_share_is_written_as_a_part_whose_header_names_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("part.exr");
    let share = Share::new(1, 2).unwrap();
    let job = RenderJob {
        choices: Choices { part: Some(PartChoice::Share(share)), ..Default::default() },
        ..small_job(&output)
    };
    let record = Record::default();
    assert_eq!(run(&job, &record).unwrap(), Ended::Complete);

    let header = part_file::read_header(&output).unwrap();
    assert_eq!((header.width, header.height), (8, 6));
    assert_eq!(header.region.share, share);
    assert_eq!(header.taken, 2, "half of 4 samples per pixel");
    assert_eq!(header.integrator, "direct", "the scene's integrator");
    let (_, digest) = load_with_digest(Path::new(SCENE), &job.request).unwrap();
    assert_eq!(header.digest, digest.to_string());
    assert_eq!(*record.frames.lock().unwrap(), [Some(8 * 6 * 2)]);
    let written = record.written.lock().unwrap();
    assert_eq!(written.len(), 1);
    assert!(
        written[0].starts_with(&format!("{}: share 1/2 of crop", output.display())),
        "{}",
        written[0]
    );
}

#[test]
fn a_part_of_an_integrator_with_shared_samples_is_refused_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("part.exr");
    let job = RenderJob {
        request: RenderRequest {
            integrator: Some(IntegratorKind::Photon),
            ..small_job(&output).request
        },
        choices: Choices {
            part: Some(PartChoice::Share(Share::new(0, 2).unwrap())),
            ..Default::default()
        },
        ..small_job(&output)
    };
    let record = Record::default();
    let error = run(&job, &record).unwrap_err();
    assert!(matches!(error, RenderJobError::SamplesShared(IntegratorKind::Photon)), "{error:?}");
    assert!(error.to_string().contains("integrator photon"), "{error}");
    assert!(record.frames.lock().unwrap().is_empty(), "no render started");
    assert!(!output.exists(), "nothing written");
}

#[test]
fn a_film_over_the_memory_limit_is_refused_with_its_size() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("image.exr");
    // 8x6 pixels take a few KiB; a millionth of a GiB is about one.
    let job = RenderJob { max_memory: 1e-6, ..small_job(&output) };
    let record = Record::default();
    match run(&job, &record) {
        Err(RenderJobError::FilmTooLarge(film)) => {
            assert_eq!((film.width, film.height), (8, 6));
            assert!(film.needed_bytes > film.max_bytes);
        }
        other => panic!("expected the film refused, got {other:?}"),
    }
    assert!(!output.exists(), "nothing written");
}

#[test]
fn a_run_stopped_before_its_first_frame_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let output = dir.path().join("image.exr");
    let record = Record { interrupted: true, ..Default::default() };
    assert_eq!(run(&small_job(&output), &record).unwrap(), Ended::Interrupted);
    assert!(record.frames.lock().unwrap().is_empty());
    assert!(!output.exists());
}
