//! Source locations and located errors, shared by the language front end and scene building.

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

/// A source file as read, kept so that any later error can quote its line, with an index of its
/// lines so that a position is found in time independent of the file's size.
#[derive(PartialEq, Eq)]
pub struct SourceFile {
    pub path: PathBuf,
    pub text: String,
    /// The byte offset where each line starts, and whether the line is ASCII (so that a
    /// column, counted in characters, is its byte offset in the line).
    line_starts: Vec<usize>,
    ascii_lines: Vec<bool>,
}

impl SourceFile {
    pub fn new(path: PathBuf, text: String) -> SourceFile {
        let line_starts: Vec<usize> =
            std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
        let ascii_lines = line_starts
            .iter()
            .enumerate()
            .map(|(i, &start)| {
                let end = line_starts.get(i + 1).copied().unwrap_or(text.len());
                text.as_bytes()[start..end].is_ascii()
            })
            .collect();
        SourceFile { path, text, line_starts, ascii_lines }
    }

    /// The 1-based line and column (in characters) of a byte offset.
    pub fn position(&self, offset: usize) -> (u32, u32) {
        let offset = offset.min(self.text.len());
        let line = self.line_starts.partition_point(|&start| start <= offset) - 1;
        let start = self.line_starts[line];
        let col = match self.ascii_lines[line] {
            true => offset - start,
            false => self.text[start..offset].chars().count(),
        };
        (line as u32 + 1, col as u32 + 1)
    }

    /// The text of a 1-based line, without its line ending.
    pub fn line(&self, line: u32) -> &str {
        let Some(&start) = self.line_starts.get(line.saturating_sub(1) as usize) else {
            return "";
        };
        let end = self.line_starts.get(line as usize).copied().unwrap_or(self.text.len());
        self.text[start..end].trim_end_matches(['\n', '\r'])
    }
}

/// A position in a source file (1-based line and column, columns counted in characters), and
/// for a node made inside macro calls or included files, how evaluation got there: an error
/// found later at the node (while building the scene) then names the calls too.
#[derive(Clone)]
pub struct Span {
    pub file: Arc<SourceFile>,
    pub line: u32,
    pub col: u32,
    pub context: Option<Arc<Context>>,
}

/// One macro call or include around a node, innermost first (`in macro Ball, called at ...`).
#[derive(Debug)]
pub struct Context {
    pub note: Note,
    pub outer: Option<Arc<Context>>,
}

/// What a context is; written out only when an error names it (a macro call formatting its
/// note made up a tenth of the time of a million calls).
#[derive(Debug)]
pub enum Note {
    MacroCall { name: String, at: Span },
    Included { at: Span },
}

impl fmt::Display for Note {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Note::MacroCall { name, at } => write!(f, "in macro {name}, called at {at:?}"),
            Note::Included { at } => write!(f, "included from {at:?}"),
        }
    }
}

/// Spans are equal where they point to the same place, however it was reached.
impl PartialEq for Span {
    fn eq(&self, other: &Self) -> bool {
        self.file == other.file && self.line == other.line && self.col == other.col
    }
}

impl Eq for Span {}

impl Span {
    /// The text of the line this span points into, without its line ending.
    pub fn line_text(&self) -> &str {
        self.file.line(self.line)
    }
}

/// Spans print as `file:line:col` so that scene-graph snapshots stay readable.
impl fmt::Debug for Span {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.path.display(), self.line, self.col)
    }
}

/// An error in a scene, located in its text. `Display` gives `file:line:col: error: message`,
/// then the offending line with a caret under the column, then any notes (e.g. the include chain).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct SceneError {
    pub span: Option<Span>,
    pub message: String,
    pub notes: Vec<String>,
}

impl SceneError {
    /// An error at `span`, with a note for each macro call or include the span was reached by.
    pub fn at(span: &Span, message: impl Into<String>) -> Self {
        let mut error =
            SceneError { span: Some(span.clone()), message: message.into(), notes: Vec::new() };
        let mut context = span.context.as_deref();
        while let Some(c) = context {
            error = error.noted(c.note.to_string());
            context = c.outer.as_deref();
        }
        error
    }

    /// Adds a note of where an error came from (an include, a macro call), but not a wall of
    /// them: a note repeated by recursion is counted, and after four different ones the rest are
    /// elided.
    pub fn noted(mut self, text: String) -> Self {
        if let Some(last) = self.notes.last_mut() {
            if *last == text {
                *last = format!("{text} (2 times)");
                return self;
            }
            let count = last.strip_prefix(&text).and_then(|rest| {
                rest.strip_prefix(" (")?.strip_suffix(" times)")?.parse::<u64>().ok()
            });
            if let Some(count) = count {
                *last = format!("{text} ({} times)", count + 1);
                return self;
            }
        }
        match self.notes.len() {
            0..4 => self.with_note(text),
            4 => self.with_note("(and more)"),
            _ => self,
        }
    }

    /// An error about a file as a whole (e.g. one that cannot be read).
    pub fn unlocated(message: impl Into<String>) -> Self {
        SceneError { span: None, message: message.into(), notes: Vec::new() }
    }

    pub fn with_note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.span {
            None => write!(f, "error: {}", printable(&self.message))?,
            Some(span) => {
                write!(f, "{span:?}: error: {}", printable(&self.message))?;
                let number = span.line.to_string();
                let gutter = " ".repeat(number.len());
                let (text, pad) = excerpt(span.line_text(), span.col.saturating_sub(1) as usize);
                write!(f, "\n{gutter} |\n{number} | {text}\n{gutter} | {pad}^")?;
            }
        }
        for note in &self.notes {
            write!(f, "\n  = note: {}", printable(note))?;
        }
        Ok(())
    }
}

/// Characters of a line shown on each side of an error's column: a scene on one long line (or a
/// 30,000-character name) gives an error of a few lines, not megabytes.
const EXCERPT_REACH: usize = 120;

/// The part of `line` around the character at `column` (0-based), clipped with `…`, and the
/// padding that puts a caret under that character. Tabs are kept so the caret lines up; other
/// control characters are shown escaped.
fn excerpt(line: &str, column: usize) -> (String, String) {
    let first = column.saturating_sub(EXCERPT_REACH);
    let mut chars = line.chars().skip(first).peekable();
    let (mut text, mut pad) = (String::new(), String::new());
    if first > 0 {
        text.push('…');
        pad.push(' ');
    }
    for i in first..column + EXCERPT_REACH {
        let Some(c) = chars.next() else { break };
        let shown = if c == '\t' || !c.is_control() {
            c.to_string()
        } else {
            c.escape_default().to_string()
        };
        if i < column {
            let blank = if c == '\t' { '\t' } else { ' ' };
            pad.extend(std::iter::repeat_n(blank, shown.chars().count()));
        }
        text.push_str(&shown);
    }
    if chars.peek().is_some() {
        text.push('…');
    }
    (text, pad)
}

/// The most characters of a message shown: one that quotes a 30,000-character name shows its
/// start and end.
const MESSAGE_REACH: usize = 400;

/// `text` with control characters shown escaped (a file name can hold an escape sequence that
/// would otherwise drive the terminal), and its middle elided past `MESSAGE_REACH` characters.
pub fn printable(text: &str) -> String {
    let escape = |c: char| match c.is_control() && c != '\n' {
        true => c.escape_default().to_string(),
        false => c.to_string(),
    };
    let count = text.chars().count();
    if count <= MESSAGE_REACH {
        return text.chars().map(escape).collect();
    }
    let half = MESSAGE_REACH / 2;
    let start: String = text.chars().take(half).map(escape).collect();
    let end: String = text.chars().skip(count - half).map(escape).collect();
    format!("{start}…{end}")
}
