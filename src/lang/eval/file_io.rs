//! POV-Ray's text files (`.pov`): `#fopen`, `#read`, `#write` and `#fclose`. A scene writes only
//! in its own folder, at most `MAX_WRITTEN_BYTES` in all; what it reads counts with the text it
//! includes (`MAX_INCLUDED_BYTES`).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;

use super::scope::Slot;
use super::{Evaluator, MAX_INCLUDED_BYTES};
use crate::diagnostic::{SceneError, Span};
use crate::lang::syntax::{
    BinaryWord, Expr, FileAction, FileDirective, Ident, OpenMode, WriteItem,
};
use crate::lang::value::Value;

/// Bytes one scene may write with `#write`, to all its files together.
pub const MAX_WRITTEN_BYTES: u64 = 64 << 20;

/// Files one scene may open with `#fopen` (the same file twice counts twice).
pub const MAX_FILES_OPENED: usize = 10_000;

/// The files a scene has opened: a handle's value (`Value::File`) is its index here.
#[derive(Default)]
pub struct Files {
    /// `None` once closed.
    open: Vec<Option<OpenFile>>,
    written: u64,
}

enum OpenFile {
    /// The file's text, read whole when opened, and how far `#read` has come.
    Reading {
        path: PathBuf,
        text: String,
        at: usize,
    },
    Writing {
        path: PathBuf,
        file: std::fs::File,
    },
}

impl Evaluator {
    pub(super) fn file_directive(&mut self, directive: &FileDirective) -> Result<(), SceneError> {
        let FileDirective { handle, action, span } = directive;
        match action {
            FileAction::Open { name, mode } => self.open_file(handle, name, *mode, span),
            FileAction::Read(names) => self.read_values(handle, names, span),
            FileAction::Write(items) => self.write_values(handle, items),
            FileAction::Close => {
                let index = self.open_file_of(handle)?;
                self.close_file(index, handle);
                Ok(())
            }
        }
    }

    fn open_file(
        &mut self,
        handle: &Ident,
        name: &Expr,
        mode: OpenMode,
        at: &Span,
    ) -> Result<(), SceneError> {
        match self.lookup(&handle.name) {
            None | Some(Value::File(_)) => {}
            Some(other) => {
                return Err(SceneError::at(
                    &handle.span,
                    format!(
                        "`{}` is declared as {}, not a file's handle",
                        handle.name,
                        other.kind()
                    ),
                ));
            }
        }
        if self.files.open.len() >= MAX_FILES_OPENED {
            return Err(SceneError::at(
                at,
                format!("more than {MAX_FILES_OPENED} files opened in one scene"),
            ));
        }
        let file_name = self.string(name, "`#fopen`")?;
        let folder = self.scene_folder();
        let path = folder.join(&file_name);
        let file = match mode {
            OpenMode::Read => {
                let text = self.dialect.read(&path).map_err(|e| {
                    SceneError::at(&name.span, format!("cannot read `{}`: {e}", path.display()))
                })?;
                self.included_bytes += text.len() as u64;
                if self.included_bytes > MAX_INCLUDED_BYTES {
                    return Err(SceneError::at(
                        at,
                        format!(
                            "more than {} MiB of text included and read in one scene",
                            MAX_INCLUDED_BYTES >> 20
                        ),
                    ));
                }
                self.sources.add(text.as_bytes());
                OpenFile::Reading { path, text, at: 0 }
            }
            OpenMode::Write | OpenMode::Append => {
                if let Err(why) = writable_in(&folder, &path) {
                    let message = format!("cannot write `{file_name}`: {why}");
                    return Err(SceneError::at(&name.span, message));
                }
                let file = std::fs::OpenOptions::new()
                    .create(true)
                    .write(true)
                    .append(mode == OpenMode::Append)
                    .truncate(mode == OpenMode::Write)
                    .open(&path)
                    .map_err(|e| {
                        SceneError::at(
                            &name.span,
                            format!("cannot write `{}`: {e}", path.display()),
                        )
                    })?;
                OpenFile::Writing { path, file }
            }
        };
        // A handle reopened without `#fclose` closes its earlier file.
        if let Some(Value::File(earlier)) = self.lookup(&handle.name) {
            let earlier = *earlier;
            self.files.open[earlier] = None;
        }
        self.files.open.push(Some(file));
        // Handles are global, as in POV-Ray.
        let value = Value::File(self.files.open.len() - 1);
        self.scopes[0].names.insert(handle.name.clone(), Slot::Value(value));
        Ok(())
    }

    /// The folder a scene's files are read from and written to: the main scene file's.
    fn scene_folder(&self) -> PathBuf {
        let main = self.open_files.first().map(|(_, path)| path.as_path());
        match main.and_then(Path::parent) {
            Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
            _ => PathBuf::from("."),
        }
    }

    /// The index of the open file `handle` names.
    fn open_file_of(&self, handle: &Ident) -> Result<usize, SceneError> {
        match self.lookup(&handle.name) {
            Some(Value::File(index)) if self.files.open[*index].is_some() => Ok(*index),
            _ => Err(SceneError::at(
                &handle.span,
                format!(
                    "`{0}` is not an open file (`#fopen {0} \"name\" read` opens one)",
                    handle.name
                ),
            )),
        }
    }

    fn close_file(&mut self, index: usize, handle: &Ident) {
        self.files.open[index] = None;
        self.scopes[0].names.remove(&handle.name);
    }

    /// `#read`: binds each name to the next value of the file; past its end the file is closed
    /// and its handle undefined (what `defined(Handle)` tests), as in POV-Ray.
    fn read_values(
        &mut self,
        handle: &Ident,
        names: &[Ident],
        at: &Span,
    ) -> Result<(), SceneError> {
        let index = self.open_file_of(handle)?;
        for name in names {
            let next = match &mut self.files.open[index] {
                Some(OpenFile::Reading { path, text, at: position }) => next_value(text, position)
                    .map_err(|why| {
                        let line = text[..*position].matches('\n').count() + 1;
                        SceneError::at(at, format!("`{}` line {line}: {why}", path.display()))
                    })?,
                Some(OpenFile::Writing { .. }) | None => {
                    return Err(SceneError::at(
                        &handle.span,
                        format!(
                            "`{}` is open for writing: `#read` reads a file opened with `read`",
                            handle.name
                        ),
                    ));
                }
            };
            let Some(value) = next else {
                self.close_file(index, handle);
                return Ok(());
            };
            if let Some(old) = self.lookup(&name.name) {
                let same = matches!(
                    (old, &value),
                    (Value::Float(_), Value::Float(_))
                        | (Value::String(_), Value::String(_))
                        | (
                            Value::Vector(_) | Value::Numbers(_),
                            Value::Vector(_) | Value::Numbers(_)
                        )
                );
                if !same {
                    return Err(SceneError::at(
                        &name.span,
                        format!(
                            "`#read` gives `{}` {}, but it is declared as {}",
                            name.name,
                            value.kind(),
                            old.kind()
                        ),
                    ));
                }
            }
            self.bind(&name.name, value, false);
        }
        Ok(())
    }

    /// `#write`: strings as they are, numbers and vectors as POV-Ray writes them (`%g`), or
    /// after a binary word type as integers.
    fn write_values(&mut self, handle: &Ident, items: &[WriteItem]) -> Result<(), SceneError> {
        let index = self.open_file_of(handle)?;
        let mut bytes = Vec::new();
        for item in items {
            let value = self.value(&item.value)?;
            let refused = |what: &str| {
                let message = format!("`#write` writes {what}, not {}", value.kind());
                Err(SceneError::at(&item.value.span, message))
            };
            match item.word {
                None => {
                    let text = match &value {
                        Value::String(s) => s.to_string(),
                        Value::Float(f) => format_g(*f),
                        Value::Vector(v) => format_vector(&v.to_array()),
                        Value::Numbers(n) => format_vector(n),
                        _ => return refused("strings, numbers and vectors"),
                    };
                    bytes.extend_from_slice(text.as_bytes());
                }
                Some(word) => {
                    let numbers = match &value {
                        Value::Float(f) => vec![*f],
                        Value::Vector(v) => v.to_array().to_vec(),
                        Value::Numbers(n) => n.clone(),
                        _ => return refused("binary words of numbers and vectors"),
                    };
                    for n in numbers {
                        bytes.extend_from_slice(&binary(word, n));
                    }
                }
            }
        }
        self.files.written += bytes.len() as u64;
        let span = &handle.span;
        if self.files.written > MAX_WRITTEN_BYTES {
            let mib = MAX_WRITTEN_BYTES >> 20;
            return Err(SceneError::at(span, format!("more than {mib} MiB written in one scene")));
        }
        match &mut self.files.open[index] {
            Some(OpenFile::Writing { path, file }) => file.write_all(&bytes).map_err(|e| {
                SceneError::at(span, format!("cannot write `{}`: {e}", path.display()))
            }),
            Some(OpenFile::Reading { .. }) | None => Err(SceneError::at(
                span,
                format!(
                    "`{}` is open for reading: `#write` writes a file opened with `write` or `append`",
                    handle.name
                ),
            )),
        }
    }
}

/// Why a scene in `folder` may not write `path`, if it may not: only a file directly in the
/// scene's own folder, and only a regular file (not a folder, a device, or a link that leads
/// elsewhere).
fn writable_in(folder: &Path, path: &Path) -> Result<(), String> {
    let outside = || "a scene writes only files in its own folder".to_string();
    let folder = folder.canonicalize().map_err(|e| format!("{}: {e}", folder.display()))?;
    let parent = path.parent().ok_or_else(outside)?;
    let parent = parent.canonicalize().map_err(|_| outside())?;
    let named_file = path.file_name().is_some_and(|n| n != "." && n != "..");
    if parent != folder || !named_file {
        return Err(outside());
    }
    match std::fs::metadata(path) {
        Ok(metadata) if !metadata.is_file() => Err("it is not a regular file".to_string()),
        Ok(_)
            if path.canonicalize().ok().and_then(|p| p.parent().map(Path::to_path_buf))
                != Some(folder) =>
        {
            Err(outside())
        }
        Ok(_) | Err(_) => Ok(()),
    }
}

/// The value of a data file at `at`, moving past it: a string in quotes, a number, or a vector
/// `<a, b, c>` (two to five components); `None` at the end. Values are separated by commas.
fn next_value(text: &str, at: &mut usize) -> Result<Option<Value>, String> {
    skip_separators(text, at);
    let rest = &text[*at..];
    let Some(first) = rest.chars().next() else {
        return Ok(None);
    };
    match first {
        '"' => {
            let end = rest[1..].find('"').ok_or("a string without its closing `\"`")?;
            *at += end + 2;
            Ok(Some(Value::String(Arc::new(rest[1..=end].to_string()))))
        }
        '<' => {
            *at += 1;
            let mut components = Vec::new();
            loop {
                skip_separators(text, at);
                if text[*at..].starts_with('>') {
                    *at += 1;
                    break;
                }
                if components.len() == 5 {
                    return Err("a vector of more than five components".to_string());
                }
                components.push(number(text, at)?);
            }
            match components.as_slice() {
                [x, y, z] => Ok(Some(Value::Vector(DVec3::new(*x, *y, *z)))),
                [_, _, ..] => Ok(Some(Value::Numbers(components))),
                _ => Err("a vector of fewer than two components".to_string()),
            }
        }
        _ => number(text, at).map(|n| Some(Value::Float(n))),
    }
}

fn skip_separators(text: &str, at: &mut usize) {
    let rest = &text[*at..];
    *at += rest.len() - rest.trim_start_matches(|c: char| c.is_whitespace() || c == ',').len();
}

/// A number (a sign and exponent allowed) at `at`, moving past it.
fn number(text: &str, at: &mut usize) -> Result<f64, String> {
    let rest = &text[*at..];
    let length = rest
        .find(|c: char| !(c.is_ascii_digit() || matches!(c, '+' | '-' | '.' | 'e' | 'E')))
        .unwrap_or(rest.len());
    let word = &rest[..length];
    match word.parse::<f64>() {
        Ok(n) if n.is_finite() => {
            *at += length;
            Ok(n)
        }
        _ => {
            let shown: String = rest.chars().take(20).take_while(|c| *c != '\n').collect();
            Err(format!("expected a string in quotes, a number or a vector, found `{shown}`"))
        }
    }
}

/// A number as C's `printf("%g")` writes it (POV-Ray's `#write`): six significant digits,
/// without trailing zeros, in exponent form below 1e-4 and from 1e6.
fn format_g(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    let scientific = format!("{x:.5e}");
    let (mantissa, exponent) = scientific.split_once('e').expect("`{:e}` writes an exponent");
    let exponent: i32 = exponent.parse().expect("an integer exponent");
    let trim = |s: &str| s.trim_end_matches('0').trim_end_matches('.').to_string();
    if !(-4..6).contains(&exponent) {
        let sign = if exponent < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim(mantissa), exponent.abs())
    } else {
        let decimals = (5 - exponent) as usize;
        trim(&format!("{x:.decimals$}"))
    }
}

fn format_vector(components: &[f64]) -> String {
    let parts: Vec<String> = components.iter().map(|&c| format_g(c)).collect();
    format!("<{}>", parts.join(","))
}

/// `n` rounded to the nearest integer of the word type's range, in its bytes.
fn binary(word: BinaryWord, n: f64) -> Vec<u8> {
    let clamped = |low: f64, high: f64| n.round().clamp(low, high);
    match word {
        BinaryWord::Uint8 => vec![clamped(0.0, 255.0) as u8],
        BinaryWord::Sint8 => (clamped(-128.0, 127.0) as i8).to_le_bytes().to_vec(),
        BinaryWord::Uint16Be => (clamped(0.0, 65535.0) as u16).to_be_bytes().to_vec(),
        BinaryWord::Uint16Le => (clamped(0.0, 65535.0) as u16).to_le_bytes().to_vec(),
        BinaryWord::Sint16Be => (clamped(-32768.0, 32767.0) as i16).to_be_bytes().to_vec(),
        BinaryWord::Sint16Le => (clamped(-32768.0, 32767.0) as i16).to_le_bytes().to_vec(),
        BinaryWord::Sint32Be => {
            (clamped(-2147483648.0, 2147483647.0) as i32).to_be_bytes().to_vec()
        }
        BinaryWord::Sint32Le => {
            (clamped(-2147483648.0, 2147483647.0) as i32).to_le_bytes().to_vec()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_written_as_printf_g_writes_them() {
        let cases = [
            (5.0, "5"),
            (-1.5e-7, "-1.5e-07"),
            (123456789.0, "1.23457e+08"),
            (0.1, "0.1"),
            (1.0 / 3.0, "0.333333"),
            (2.5, "2.5"),
            (999999.4, "999999"),
            (999999.5, "1e+06"),
            (0.0001, "0.0001"),
            (-42.0, "-42"),
        ];
        for (x, written) in cases {
            assert_eq!(format_g(x), written, "{x}");
        }
        assert_eq!(format_vector(&[1.0, 2.5, 3.0]), "<1,2.5,3>");
    }

    #[test]
    fn data_is_read_as_strings_numbers_and_vectors_separated_by_commas() {
        let text = "\"Testing 123\",5,<1,2,3> , -1.5e-07\n<1, 2>";
        let mut at = 0;
        let mut values = Vec::new();
        while let Some(v) = next_value(text, &mut at).unwrap() {
            values.push(v);
        }
        assert!(matches!(&values[0], Value::String(s) if s.as_str() == "Testing 123"));
        assert!(matches!(values[1], Value::Float(f) if f == 5.0));
        assert!(matches!(values[2], Value::Vector(v) if v == DVec3::new(1.0, 2.0, 3.0)));
        assert!(matches!(values[3], Value::Float(f) if f == -1.5e-7));
        assert!(matches!(&values[4], Value::Numbers(n) if n == &[1.0, 2.0]));
        assert_eq!(values.len(), 5);
        let mut at = 0;
        assert!(next_value("abc", &mut at).unwrap_err().contains("found `abc`"));
        assert!(next_value("\"open", &mut 0).unwrap_err().contains("closing"));
    }

    #[test]
    fn binary_words_round_and_clamp_to_their_range() {
        assert_eq!(binary(BinaryWord::Uint8, 254.6), [255]);
        assert_eq!(binary(BinaryWord::Uint8, -3.0), [0]);
        assert_eq!(binary(BinaryWord::Sint8, -1.0), [0xff]);
        assert_eq!(binary(BinaryWord::Uint16Be, 258.0), [1, 2]);
        assert_eq!(binary(BinaryWord::Uint16Le, 258.0), [2, 1]);
        assert_eq!(binary(BinaryWord::Sint16Be, -40000.0), [0x80, 0]);
        assert_eq!(binary(BinaryWord::Sint32Le, 1.0), [1, 0, 0, 0]);
        assert_eq!(binary(BinaryWord::Sint32Be, 1e12), [0x7f, 0xff, 0xff, 0xff]);
    }
}
