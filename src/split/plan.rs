//! What one `render` command renders: which frames, and of each the share, the crop and the
//! file it goes to. Frames and shares combine: with `--part auto` and `--frames` but no
//! `--frame`, the scheduler's tasks are the frames times their shares, task `t` rendering
//! share `t mod S` of frame `F0 + t / S` (`S` = tasks / frames; one share a frame renders whole
//! frames).

use std::path::{Path, PathBuf};

use super::scheduler::{self, SchedulerError};
use crate::animation::{DEFAULT_CLOCK, Frame, FrameError, Frames};
use crate::region::{Crop, RegionError, Share};

/// The most frames one command plans (each is checked and listed before the first renders).
pub const MAX_FRAMES: u64 = 100_000;

/// `--part`: a share, or the scheduler's task.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartChoice {
    Share(Share),
    Auto,
}

impl std::str::FromStr for PartChoice {
    type Err = RegionError;

    fn from_str(s: &str) -> Result<Self, RegionError> {
        if s == "auto" { Ok(PartChoice::Auto) } else { s.parse().map(PartChoice::Share) }
    }
}

/// The command line's choices of frames and parts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Choices {
    pub part: Option<PartChoice>,
    pub parts: Option<u32>,
    pub crop: Option<Crop>,
    pub frames: Option<(u32, u32)>,
    pub frame: Option<u32>,
    pub clock: Option<(f64, f64)>,
}

/// One render: a frame, the share and crop of it (both `None` for a whole image, else the
/// output is a part file), and the file to write.
#[derive(Debug, Clone, PartialEq)]
pub struct Job {
    pub frame: Frame,
    pub share: Option<Share>,
    pub crop: Option<Crop>,
    pub output: PathBuf,
}

impl Job {
    pub fn is_part(&self) -> bool {
        self.share.is_some() || self.crop.is_some()
    }
}

/// The renders the choices ask for, with a line saying where a scheduler's task came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub jobs: Vec<Job>,
    pub task: Option<String>,
}

/// Choices that do not go together, or a frame or task that is not there.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlanError {
    #[error(
        "error: --parts N goes with --part auto (the count of a Kubernetes Indexed Job's shares)"
    )]
    PartsWithoutAuto,
    #[error("error: --frame F picks one of --frames F0..F1: give both")]
    FrameWithoutFrames,
    #[error("error: --clock C0..C1 goes with --frames F0..F1")]
    ClockWithoutFrames,
    #[error(
        "error: --frames {first}..{last} is {count} frames: one command renders at most \
         {MAX_FRAMES} (split the range over several)"
    )]
    TooManyFrames { first: u32, last: u32, count: u64 },
    #[error("error: {0}")]
    Frame(#[from] FrameError),
    /// The share of a scheduler's task.
    #[error("error: {0}")]
    Share(#[from] RegionError),
    #[error(transparent)]
    Scheduler(#[from] SchedulerError),
}

/// Plans the renders; `var` looks up the environment (for `--part auto`).
pub fn plan(
    choices: &Choices,
    output: &Path,
    var: impl Fn(&str) -> Option<String>,
) -> Result<Plan, PlanError> {
    if choices.parts.is_some() && choices.part != Some(PartChoice::Auto) {
        return Err(PlanError::PartsWithoutAuto);
    }
    let frames = match (choices.frames, choices.frame, choices.clock) {
        (Some((first, last)), _, clock) => {
            Some(Frames { first, last, clock: clock.unwrap_or(DEFAULT_CLOCK) })
        }
        (None, Some(_), _) => {
            return Err(PlanError::FrameWithoutFrames);
        }
        (None, None, Some(_)) => {
            return Err(PlanError::ClockWithoutFrames);
        }
        (None, None, None) => None,
    };
    let numbers: Vec<u32> = match (&frames, choices.frame) {
        (Some(frames), Some(number)) => {
            frames.frame(number)?;
            vec![number]
        }
        (Some(frames), None) => {
            let count = u64::from(frames.last - frames.first) + 1;
            if count > MAX_FRAMES {
                return Err(PlanError::TooManyFrames {
                    first: frames.first,
                    last: frames.last,
                    count,
                });
            }
            (frames.first..=frames.last).collect()
        }
        (None, _) => vec![0],
    };
    let (numbers, share, task) = match choices.part {
        None => (numbers, None, None),
        Some(PartChoice::Share(share)) => (numbers, Some(share), None),
        Some(PartChoice::Auto) => {
            let count = numbers.len() as u32;
            let task = scheduler::task(var, choices.parts, count)?;
            let per_frame = task.count / count;
            let number = numbers[(task.index / per_frame) as usize];
            let share = Share::new(task.index % per_frame, per_frame)?;
            let what = if per_frame == 1 {
                "the whole image".to_string()
            } else {
                format!("share {share}")
            };
            let of_frame =
                if frames.is_some() { format!(" of frame {number}") } else { String::new() };
            let line = format!(
                "{} task {} of {}: {what}{of_frame}",
                task.scheduler, task.index, task.count
            );
            (vec![number], (per_frame > 1).then_some(share), Some(line))
        }
    };
    let jobs = numbers
        .into_iter()
        .map(|number| {
            let (frame, output) = match &frames {
                Some(frames) => (frames.frame(number)?, frames.output(output, number)),
                None => (Frame::default(), output.to_path_buf()),
            };
            Ok(Job { frame, share, crop: choices.crop, output })
        })
        .collect::<Result<Vec<_>, FrameError>>()?;
    Ok(Plan { jobs, task })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn no_scheduler(_: &str) -> Option<String> {
        None
    }

    #[test]
    fn frames_times_shares_under_a_slurm_array() {
        let choices =
            Choices { part: Some(PartChoice::Auto), frames: Some((10, 12)), ..Choices::default() };
        let slurm = |id: u32| {
            move |name: &str| match name {
                "SLURM_ARRAY_TASK_ID" => Some(id.to_string()),
                "SLURM_ARRAY_TASK_MIN" => Some("0".to_string()),
                "SLURM_ARRAY_TASK_COUNT" => Some("12".to_string()),
                _ => None,
            }
        };
        let plan = plan(&choices, Path::new("f##.exr"), slurm(5)).unwrap();
        assert_eq!(
            plan.jobs,
            vec![Job {
                frame: Frame { number: 11, clock: 0.5, step: Some(0.5) },
                share: Some(Share { index: 1, count: 4 }),
                crop: None,
                output: PathBuf::from("f11.exr"),
            }]
        );
        assert_eq!(plan.task.unwrap(), "Slurm task 5 of 12: share 1/4 of frame 11");
    }

    #[test]
    fn one_task_a_frame_renders_whole_frames() {
        let choices = Choices {
            part: Some(PartChoice::Auto),
            parts: Some(1),
            frames: Some((0, 9)),
            ..Choices::default()
        };
        let k8s = |name: &str| (name == "JOB_COMPLETION_INDEX").then(|| "7".to_string());
        let plan = plan(&choices, Path::new("a.png"), k8s).unwrap();
        assert_eq!(plan.jobs[0].output, PathBuf::from("a7.png"));
        assert!(!plan.jobs[0].is_part());
    }

    #[test]
    fn every_frame_of_the_range_without_frame() {
        let choices =
            Choices { frames: Some((1, 3)), clock: Some((2.0, 4.0)), ..Choices::default() };
        let plan = plan(&choices, Path::new("out.exr"), no_scheduler).unwrap();
        let clocks: Vec<f64> = plan.jobs.iter().map(|j| j.frame.clock).collect();
        assert_eq!(clocks, [2.0, 3.0, 4.0]);
        assert_eq!(plan.jobs[2].output, PathBuf::from("out3.exr"));
    }

    #[test]
    fn choices_that_do_not_go_together_are_refused() {
        let refuse = |choices: Choices, says: &str| {
            let error = plan(&choices, Path::new("o.exr"), no_scheduler).unwrap_err().to_string();
            assert!(error.contains(says), "{error}");
        };
        refuse(Choices { frame: Some(1), ..Choices::default() }, "give both");
        refuse(Choices { clock: Some((0.0, 1.0)), ..Choices::default() }, "goes with --frames");
        refuse(Choices { parts: Some(4), ..Choices::default() }, "goes with --part auto");
        refuse(
            Choices { frames: Some((0, 3)), frame: Some(4), ..Choices::default() },
            "not one of",
        );
        refuse(Choices { part: Some(PartChoice::Auto), ..Choices::default() }, "no scheduler task");
    }
}
