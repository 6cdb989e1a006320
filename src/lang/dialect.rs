//! Which language a scene is written in: raydiance's own (`.scn`) or POV-Ray's (`.pov`, section
//! 15 of the language). The main file's name decides, and every file it includes is read in the
//! same dialect.

use crate::input::InputError;
use std::path::Path;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Dialect {
    /// raydiance's physical language (sections 1–14).
    #[default]
    Scn,
    /// POV-Ray 3.7's scene language, read with POV-Ray's conventions (`docs/povray.md`).
    Pov,
}

impl Dialect {
    /// The dialect of a main scene file: `.pov` (any case) is POV-Ray's, anything else ours.
    pub fn of(path: &Path) -> Dialect {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("pov") => Dialect::Pov,
            _ => Dialect::Scn,
        }
    }
}

impl Dialect {
    /// The text of a scene file: UTF-8, or in `.pov` Latin-1 when it is not UTF-8 (POV-Ray's
    /// older sample files are, in their authors' names).
    pub fn read(self, path: &Path) -> Result<String, InputError> {
        match self {
            Dialect::Scn => crate::input::read_text(path, crate::input::MAX_SCENE_BYTES),
            Dialect::Pov => {
                let bytes = crate::input::read(path, crate::input::MAX_SCENE_BYTES)?;
                Ok(String::from_utf8(bytes)
                    .unwrap_or_else(|e| e.into_bytes().iter().map(|&b| char::from(b)).collect()))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pov_file_that_is_not_utf8_is_latin1() {
        let path = std::env::temp_dir().join(format!("latin1-{}.pov", std::process::id()));
        std::fs::write(&path, b"// Jos\xe9\n").unwrap();
        assert_eq!(Dialect::Pov.read(&path).unwrap(), "// Jos\u{e9}\n");
        assert!(Dialect::Scn.read(&path).unwrap_err().to_string().contains("UTF-8"));
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn the_extension_decides() {
        assert_eq!(Dialect::of(Path::new("a/b.pov")), Dialect::Pov);
        assert_eq!(Dialect::of(Path::new("B.POV")), Dialect::Pov);
        assert_eq!(Dialect::of(Path::new("b.scn")), Dialect::Scn);
        assert_eq!(Dialect::of(Path::new("colors.inc")), Dialect::Scn);
    }
}
