//! raydiance's own versions of POV-Ray's standard include files, built into the binary so that a
//! `.pov` scene needs nothing beside it (`docs/povray.md`). Searched after the including file's
//! folder and the include path; only names whose every declaration raydiance can honour are here.

/// The text of the built-in include file `name`, if there is one.
pub fn file(name: &str) -> Option<&'static str> {
    match name {
        "colors.inc" => Some(include_str!("library/colors.inc")),
        _ => None,
    }
}
