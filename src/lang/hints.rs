//! What a parse error says beyond "expected ..., found ...": the blocks open where it stopped
//! (to name a `{` left unclosed), and the written form of the construct an argument is missing
//! from.

/// Each construct with positional arguments, as it is written.
const FORMS: &[(&str, &str)] = &[
    ("plane", "plane { normal, d }"),
    ("sphere", "sphere { centre, radius }"),
    ("box", "box { corner, opposite corner }"),
    ("triangle", "triangle { a, b, c }"),
    ("quad", "quad { corner, edge1, edge2 }"),
    ("disk", "disk { centre, normal, radius }"),
    ("cylinder", "cylinder { base centre, cap centre, radius }"),
    ("cone", "cone { base centre, base radius, cap centre, cap radius }"),
    ("torus", "torus { major radius, minor radius }"),
    ("mesh", "mesh { \"file.ply\" }"),
    ("object", "object { Name }"),
    ("light_source", "light_source { centre  power rgb <r, g, b> }"),
    ("checker", "checker { colour, colour }"),
    ("stripes", "stripes { colour, colour }"),
    ("mix", "mix { a, b, amount }"),
    ("image_map", "image_map { \"file.png\" }"),
];

/// How the construct named `word` is written, if it takes positional arguments.
pub fn form(word: &str) -> Option<&'static str> {
    FORMS.iter().find(|f| f.0 == word).map(|f| f.1)
}

/// A `{` not closed before some offset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OpenBlock<'a> {
    /// Byte offset of the `{`.
    pub offset: usize,
    /// The word before it (`sphere`, `material`, ...), or "" when there is none.
    pub word: &'a str,
}

/// Where code continues after a comment or string starting at `i`, if one starts there;
/// `Err(())` when it is not terminated.
pub fn skip_comment_or_string(text: &[u8], i: usize) -> Option<Result<usize, ()>> {
    match (text[i], text.get(i + 1)) {
        (b'/', Some(b'/')) => {
            Some(Ok(text[i..].iter().position(|&c| c == b'\n').map_or(text.len(), |n| i + n)))
        }
        (b'/', Some(b'*')) => {
            Some(text[i + 2..].windows(2).position(|w| w == b"*/").map(|n| i + 2 + n + 2).ok_or(()))
        }
        (b'"', _) => {
            let mut j = i + 1;
            Some(loop {
                match text.get(j) {
                    Some(b'"') => break Ok(j + 1),
                    Some(b'\\') if text.get(j + 1).is_some_and(|&c| c != b'\n') => j += 2,
                    Some(b'\n') | None => break Err(()),
                    Some(_) => j += 1,
                }
            })
        }
        _ => None,
    }
}

/// The blocks open at `offset` in `text`, outermost first. Comments and strings are skipped;
/// linear in `offset`.
pub fn open_blocks(text: &str, offset: usize) -> Vec<OpenBlock<'_>> {
    let code = &text.as_bytes()[..offset.min(text.len())];
    let mut open = Vec::new();
    let mut i = 0;
    while i < code.len() {
        if let Some(end) = skip_comment_or_string(code, i) {
            i = end.unwrap_or(code.len());
            continue;
        }
        match code[i] {
            b'{' => open.push(OpenBlock { offset: i, word: word_before(text, i).1 }),
            b'}' => {
                open.pop();
            }
            _ => {}
        }
        i += 1;
    }
    open
}

/// The word that ends just before `offset` (spaces between allowed), and where it starts; empty
/// when a symbol stands there.
pub fn word_before(text: &str, offset: usize) -> (usize, &str) {
    let before = text[..offset].trim_end();
    let start = before
        .char_indices()
        .rev()
        .find(|&(_, c)| !(c.is_alphanumeric() || c == '_'))
        .map_or(0, |(i, c)| i + c.len_utf8());
    (start, &before[start..])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn open_blocks_skip_comments_and_strings() {
        let text = "union { sphere { <0,0,0>, 1 } // {\n mesh { \"a{b.ply\" /* } */ material {";
        let words: Vec<&str> = open_blocks(text, text.len()).iter().map(|b| b.word).collect();
        assert_eq!(words, ["union", "mesh", "material"]);
        assert_eq!(open_blocks(text, 6), []);
        assert_eq!(open_blocks(text, 7), [OpenBlock { offset: 6, word: "union" }]);
    }
}
