//! Animation (`docs/language.md`, Animation): the frames of `--frames F0..F1`, the `clock` of each,
//! and the name of each frame's output file.

use std::path::{Path, PathBuf};

/// The values a scene sees of its frame: `clock`, `frame_number`, and POV-Ray's `clock_on` and
/// `clock_delta`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub number: u32,
    pub clock: f64,
    /// The clock's step from one frame to the next when the frame is one of an animation
    /// (`--frames`); `None` for a still image.
    pub step: Option<f64>,
}

impl Default for Frame {
    /// Without animation options `clock` is 0 and `frame_number` 0.
    fn default() -> Self {
        Frame { number: 0, clock: 0.0, step: None }
    }
}

/// `--frames F0..F1` with `--clock C0..C1`: `clock` runs linearly from C0 at F0 to C1 at F1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frames {
    pub first: u32,
    pub last: u32,
    pub clock: (f64, f64),
}

/// `clock` from 0 at the first frame to 1 at the last, as POV-Ray's default.
pub const DEFAULT_CLOCK: (f64, f64) = (0.0, 1.0);

/// A frame outside `--frames`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("--frame {number} is not one of --frames {first}..{last}")]
pub struct FrameError {
    pub number: u32,
    pub first: u32,
    pub last: u32,
}

impl Frames {
    pub fn count(&self) -> u32 {
        self.last - self.first + 1
    }

    /// Frame `number`, which must be one of these.
    pub fn frame(&self, number: u32) -> Result<Frame, FrameError> {
        if !(self.first..=self.last).contains(&number) {
            return Err(FrameError { number, first: self.first, last: self.last });
        }
        let (c0, c1) = self.clock;
        let (clock, step) = match self.last - self.first {
            0 => (c0, 0.0),
            intervals => {
                let share = f64::from(number - self.first) / f64::from(intervals);
                (c0 + (c1 - c0) * share, (c1 - c0) / f64::from(intervals))
            }
        };
        Ok(Frame { number, clock, step: Some(step) })
    }

    /// The name of frame `number`'s file: each run of `#` in the file name (not its folder)
    /// becomes the number, zero-padded to the run's length; without one, the number is
    /// appended before the extension, zero-padded to the digits of the last frame (POV-Ray's
    /// habit: `anim.png` gives `anim07.png` of frames 0..10).
    pub fn output(&self, pattern: &Path, number: u32) -> PathBuf {
        let name =
            pattern.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let renamed = if name.contains('#') {
            replace_runs(&name, number)
        } else {
            let digits = self.last.to_string().len();
            match name.rfind('.').filter(|&dot| dot > 0) {
                Some(dot) => format!("{}{number:0digits$}{}", &name[..dot], &name[dot..]),
                None => format!("{name}{number:0digits$}"),
            }
        };
        pattern.with_file_name(renamed)
    }
}

/// `name` with each run of `#` replaced by `number`, zero-padded to the run's length.
fn replace_runs(name: &str, number: u32) -> String {
    let mut out = String::with_capacity(name.len() + 8);
    let mut run = 0;
    for c in name.chars().chain(std::iter::once('\0')) {
        if c == '#' {
            run += 1;
            continue;
        }
        if run > 0 {
            out.push_str(&format!("{number:0run$}"));
            run = 0;
        }
        if c != '\0' {
            out.push(c);
        }
    }
    out
}

/// A `--frames` or `--clock` value that is not a range of frames or clock values.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RangeError {
    #[error("{option} `{text}` is not a range A..B (e.g. 0..99)")]
    NotARange { option: &'static str, text: String },
    #[error("--frames `{0}`: the first frame must not come after the last")]
    FramesBackwards(String),
    #[error("--clock `{0}`: the values must be finite numbers")]
    ClockNotFinite(String),
}

/// Parses `A..B` of two values of type `T`, given to `option`.
fn parse_range<T: std::str::FromStr>(s: &str, option: &'static str) -> Result<(T, T), RangeError> {
    let parse = |t: &str| t.trim().parse::<T>().ok();
    s.split_once("..")
        .and_then(|(a, b)| Some((parse(a)?, parse(b)?)))
        .ok_or_else(|| RangeError::NotARange { option, text: s.to_string() })
}

/// `--frames F0..F1` (whole numbers, F0 <= F1).
pub fn parse_frames(s: &str) -> Result<(u32, u32), RangeError> {
    match parse_range(s, "--frames")? {
        (a, b) if a <= b => Ok((a, b)),
        _ => Err(RangeError::FramesBackwards(s.to_string())),
    }
}

/// `--clock C0..C1` (finite numbers; the clock may run backwards).
pub fn parse_clock(s: &str) -> Result<(f64, f64), RangeError> {
    let (a, b): (f64, f64) = parse_range(s, "--clock")?;
    if a.is_finite() && b.is_finite() {
        Ok((a, b))
    } else {
        Err(RangeError::ClockNotFinite(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clock_runs_linearly_from_the_first_frame_to_the_last() {
        let frames = Frames { first: 10, last: 14, clock: DEFAULT_CLOCK };
        assert_eq!(frames.frame(10).unwrap().clock, 0.0);
        assert_eq!(frames.frame(12).unwrap().clock, 0.5);
        assert_eq!(frames.frame(14).unwrap(), Frame { number: 14, clock: 1.0, step: Some(0.25) });
        assert!(frames.frame(15).unwrap_err().to_string().contains("not one of --frames 10..14"));
        let one = Frames { first: 3, last: 3, clock: (2.0, 5.0) };
        assert_eq!(one.frame(3).unwrap().clock, 2.0);
        let backwards = Frames { first: 0, last: 2, clock: (1.0, -1.0) };
        assert_eq!(backwards.frame(1).unwrap().clock, 0.0);
    }

    #[test]
    fn output_names_take_the_frame_number() {
        let frames = Frames { first: 0, last: 120, clock: DEFAULT_CLOCK };
        let name = |pattern: &str, n| frames.output(Path::new(pattern), n);
        assert_eq!(name("anim/f####.exr", 7), PathBuf::from("anim/f0007.exr"));
        assert_eq!(name("a#b##.png", 7), PathBuf::from("a7b07.png"));
        assert_eq!(name("f##.exr", 120), PathBuf::from("f120.exr"));
        assert_eq!(name("out.exr", 7), PathBuf::from("out007.exr"));
        assert_eq!(name("dir.v2/out", 7), PathBuf::from("dir.v2/out007"));
        assert_eq!(name("##/out.exr", 7), PathBuf::from("##/out007.exr"), "not in the folder");
    }

    #[test]
    fn ranges_parse_and_refuse_with_reasons() {
        assert_eq!(parse_frames("0..99"), Ok((0, 99)));
        assert!(parse_frames("5..1").unwrap_err().to_string().contains("must not come after"));
        assert!(parse_frames("0-99").unwrap_err().to_string().contains("not a range"));
        assert_eq!(parse_clock("-1..0.5"), Ok((-1.0, 0.5)));
        assert!(parse_clock("0..inf").unwrap_err().to_string().contains("finite"));
    }
}
