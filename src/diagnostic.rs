//! Source locations and located errors, shared by the language front end and scene building.

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;

/// A source file as read, kept so that any later error can quote its line.
#[derive(PartialEq, Eq)]
pub struct SourceFile {
    pub path: PathBuf,
    pub text: String,
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
    pub note: String,
    pub outer: Option<Arc<Context>>,
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
        let line = self.file.text.lines().nth(self.line.saturating_sub(1) as usize);
        line.unwrap_or("").trim_end_matches('\r')
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
            error = error.noted(c.note.clone());
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
            None => write!(f, "error: {}", self.message)?,
            Some(span) => {
                write!(f, "{span:?}: error: {}", self.message)?;
                let number = span.line.to_string();
                let gutter = " ".repeat(number.len());
                let text = span.line_text();
                // The caret goes under the column's character; tabs are kept so it lines up.
                let pad: String = text
                    .chars()
                    .take(span.col.saturating_sub(1) as usize)
                    .map(|c| if c == '\t' { '\t' } else { ' ' })
                    .collect();
                write!(f, "\n{gutter} |\n{number} | {text}\n{gutter} | {pad}^")?;
            }
        }
        for note in &self.notes {
            write!(f, "\n  = note: {note}")?;
        }
        Ok(())
    }
}
