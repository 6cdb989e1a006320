//! Which language a scene is written in: raydiance's own (`.scn`) or POV-Ray's (`.pov`, section
//! 15 of the language). The main file's name decides, and every file it includes is read in the
//! same dialect.

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extension_decides() {
        assert_eq!(Dialect::of(Path::new("a/b.pov")), Dialect::Pov);
        assert_eq!(Dialect::of(Path::new("B.POV")), Dialect::Pov);
        assert_eq!(Dialect::of(Path::new("b.scn")), Dialect::Scn);
        assert_eq!(Dialect::of(Path::new("colors.inc")), Dialect::Scn);
    }
}
