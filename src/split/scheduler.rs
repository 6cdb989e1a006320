//! `--part auto`: the task of the scheduler that started the process. Slurm job arrays give
//! task `SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN` (divided by `SLURM_ARRAY_TASK_STEP` when
//! the array has a step) of `SLURM_ARRAY_TASK_COUNT`, so `--array=1-16` works as `0-15`;
//! Kubernetes Indexed Jobs give task `JOB_COMPLETION_INDEX`, the count being `--parts N` times
//! the frames.

/// Why `--part auto` found no task of its own.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SchedulerError {
    #[error("error: --part auto: {name}={value:?} is not a whole number")]
    NotANumber { name: String, value: String },
    #[error(
        "error: --part auto: both SLURM_ARRAY_TASK_ID (Slurm) and JOB_COMPLETION_INDEX \
         (Kubernetes) are set: cannot tell which scheduler started this process; give --part I/N \
         instead"
    )]
    BothSchedulers,
    #[error("error: --part auto: SLURM_ARRAY_TASK_ID is set but {0} is not")]
    SlurmVariableMissing(String),
    #[error(
        "error: --part auto: Slurm array task {id} is not one of {count} tasks from {min} by \
         {step} (the array must be a range such as --array=0-{last})",
        last = count.saturating_sub(1)
    )]
    NotInArray { id: u32, count: u32, min: u32, step: u32 },
    #[error(
        "error: --part auto: JOB_COMPLETION_INDEX is set (a Kubernetes Indexed Job) but the \
         number of shares is not: give --parts N (the Job's completions, divided by the frames)"
    )]
    PartsMissing,
    #[error("error: --parts times --frames is too large")]
    TooManyTasks,
    #[error(
        "error: --part auto: JOB_COMPLETION_INDEX {index} is not less than the {count} tasks of \
         --parts {parts} (times {frames} frames)"
    )]
    IndexOutOfRange { index: u32, count: u32, parts: u32, frames: u32 },
    #[error(
        "error: --part auto: no scheduler task found: neither a Slurm job array \
         (SLURM_ARRAY_TASK_ID{unset}) nor a Kubernetes Indexed Job (JOB_COMPLETION_INDEX) \
         started this process; give --part I/N instead",
        unset = if *slurm_job {
            " is unset: this Slurm job is not an array, submit it with --array"
        } else {
            ""
        }
    )]
    NoTask { slurm_job: bool },
    #[error(
        "error: --part auto: the Slurm array has {count} tasks, not {frames} frames times {shares}",
        shares = parts.map_or("a whole number of shares".to_string(), |p| format!("--parts {p}"))
    )]
    ArrayCount { count: u32, frames: u32, parts: Option<u32> },
}

/// Task `index` of `count` tasks, and who said so.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Task {
    pub index: u32,
    pub count: u32,
    pub scheduler: &'static str,
}

/// The task from the environment (`var` looks a variable up), for `parts` shares of each frame
/// (`--parts`, needed with Kubernetes) of `frames` frames.
pub fn task(
    var: impl Fn(&str) -> Option<String>,
    parts: Option<u32>,
    frames: u32,
) -> Result<Task, SchedulerError> {
    let number = |name: &str| -> Result<Option<u32>, SchedulerError> {
        match var(name) {
            None => Ok(None),
            Some(v) => v
                .trim()
                .parse()
                .map(Some)
                .map_err(|_| SchedulerError::NotANumber { name: name.to_string(), value: v }),
        }
    };
    let slurm = number("SLURM_ARRAY_TASK_ID")?;
    let kubernetes = number("JOB_COMPLETION_INDEX")?;
    match (slurm, kubernetes) {
        (Some(_), Some(_)) => Err(SchedulerError::BothSchedulers),
        (Some(id), None) => {
            let need = |name: &str| {
                number(name)?.ok_or_else(|| SchedulerError::SlurmVariableMissing(name.to_string()))
            };
            let (min, count) = (need("SLURM_ARRAY_TASK_MIN")?, need("SLURM_ARRAY_TASK_COUNT")?);
            let step = number("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1).max(1);
            let offset = id.checked_sub(min).filter(|o| o % step == 0);
            match offset.map(|o| o / step).filter(|&index| index < count) {
                Some(index) => {
                    check_count(Task { index, count, scheduler: "Slurm" }, parts, frames)
                }
                None => Err(SchedulerError::NotInArray { id, count, min, step }),
            }
        }
        (None, Some(index)) => {
            let Some(parts) = parts else {
                return Err(SchedulerError::PartsMissing);
            };
            let count = parts.checked_mul(frames).ok_or(SchedulerError::TooManyTasks)?;
            if index >= count {
                return Err(SchedulerError::IndexOutOfRange { index, count, parts, frames });
            }
            Ok(Task { index, count, scheduler: "Kubernetes" })
        }
        (None, None) => Err(SchedulerError::NoTask { slurm_job: var("SLURM_JOB_ID").is_some() }),
    }
}

/// A Slurm array's count must be a multiple of the frames, and of `--parts` when given.
fn check_count(task: Task, parts: Option<u32>, frames: u32) -> Result<Task, SchedulerError> {
    let per_frame = task.count / frames;
    if !task.count.is_multiple_of(frames) || parts.is_some_and(|p| p != per_frame) {
        return Err(SchedulerError::ArrayCount { count: task.count, frames, parts });
    }
    Ok(task)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(vars: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> + use<> {
        let vars: Vec<(String, String)> =
            vars.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
        move |name| vars.iter().find(|(k, _)| k == name).map(|(_, v)| v.clone())
    }

    #[test]
    fn slurm_arrays_count_from_their_first_task() {
        let array = |id: &str| {
            env(&[
                ("SLURM_ARRAY_TASK_ID", id),
                ("SLURM_ARRAY_TASK_MIN", "1"),
                ("SLURM_ARRAY_TASK_COUNT", "16"),
            ])
        };
        assert_eq!(task(array("1"), None, 1).unwrap().index, 0);
        assert_eq!(
            task(array("16"), None, 1).unwrap(),
            Task { index: 15, count: 16, scheduler: "Slurm" }
        );
        assert!(
            task(array("17"), None, 1).unwrap_err().to_string().contains("not one of 16 tasks")
        );
        assert!(task(array("x"), None, 1).unwrap_err().to_string().contains("not a whole number"));
        assert!(task(array("3"), None, 3).unwrap_err().to_string().contains("not 3 frames"));
        assert!(
            task(array("3"), Some(8), 1)
                .unwrap_err()
                .to_string()
                .contains("not 1 frames times --parts 8")
        );
        let stepped = env(&[
            ("SLURM_ARRAY_TASK_ID", "6"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
        ]);
        assert_eq!(task(stepped, None, 1).unwrap().index, 3);
    }

    #[test]
    fn kubernetes_needs_the_count() {
        let indexed = env(&[("JOB_COMPLETION_INDEX", "5")]);
        assert_eq!(task(&indexed, Some(8), 1).unwrap().index, 5);
        assert_eq!(task(&indexed, Some(2), 3).unwrap().count, 6);
        assert!(task(&indexed, None, 1).unwrap_err().to_string().contains("give --parts N"));
        assert!(
            task(&indexed, Some(4), 1).unwrap_err().to_string().contains("not less than the 4")
        );
    }

    #[test]
    fn without_a_scheduler_it_is_an_error_that_says_so() {
        assert!(
            task(env(&[]), None, 1).unwrap_err().to_string().contains("no scheduler task found")
        );
        let plain = env(&[("SLURM_JOB_ID", "7")]);
        assert!(task(plain, None, 1).unwrap_err().to_string().contains("not an array"));
        let both = env(&[("SLURM_ARRAY_TASK_ID", "0"), ("JOB_COMPLETION_INDEX", "0")]);
        assert!(task(both, Some(2), 1).unwrap_err().to_string().contains("both"));
    }
}
