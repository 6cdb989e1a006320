//! Wavefront OBJ: `v`, `vn`, `vt` and `f` with the forms `a`, `a/b`, `a//c`, `a/b/c`
//! (1-based, or negative: relative to the end). Other statements are ignored.

use glam::Vec3;

use super::{ContentError, Mesh, Place, triangulate};

pub fn parse(bytes: &[u8]) -> Result<Mesh, ContentError> {
    let text = std::str::from_utf8(bytes)?;
    let mut positions = Vec::new();
    let mut file_normals = Vec::new();
    let mut texcoords = 0usize;
    // Per position, the normal its faces give it (OBJ indexes normals per face corner).
    let mut corner_normals: Vec<Option<u32>> = Vec::new();
    let mut triangles = Vec::new();
    let mut all_corners_have_normals = true;
    let mut polygon = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let at = |problem: ContentError| problem.at(Place::Line(number + 1));
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => positions.push(vector(&mut words).map_err(at)?),
            Some("vn") => file_normals.push(vector(&mut words).map_err(at)?),
            Some("vt") => texcoords += 1,
            Some("f") => {
                polygon.clear();
                for corner in words {
                    let mut parts = corner.split('/');
                    let position = index(parts.next(), positions.len(), "vertex").map_err(at)?;
                    if let Some(t) = parts.next().filter(|t| !t.is_empty()) {
                        index(Some(t), texcoords, "texture coordinate").map_err(at)?;
                    }
                    match parts.next() {
                        Some(n) => {
                            let normal =
                                index(Some(n), file_normals.len(), "normal").map_err(at)?;
                            corner_normals.resize(positions.len(), None);
                            corner_normals[position as usize] = Some(normal);
                        }
                        None => all_corners_have_normals = false,
                    }
                    polygon.push(position);
                }
                if polygon.len() < 3 {
                    return Err(at(ContentError::ObjFaceTooSmall(polygon.len())));
                }
                triangulate(&polygon, &mut triangles).map_err(at)?;
            }
            _ => {}
        }
    }
    corner_normals.resize(positions.len(), None);
    let normals = (all_corners_have_normals && !file_normals.is_empty()).then(|| {
        corner_normals.iter().map(|n| n.map_or(Vec3::ZERO, |i| file_normals[i as usize])).collect()
    });
    Ok(Mesh { positions, normals, triangles })
}

fn vector<'a>(words: &mut impl Iterator<Item = &'a str>) -> Result<Vec3, ContentError> {
    let mut xyz = [0.0f32; 3];
    for c in &mut xyz {
        let word = words.next().ok_or(ContentError::NotThreeNumbers)?;
        *c = word.parse().map_err(|_| ContentError::NotANumber(word.to_string()))?;
    }
    Ok(Vec3::from(xyz))
}

/// A 1-based (or negative, from the end) OBJ index into a list of `count`, as 0-based.
fn index(word: Option<&str>, count: usize, what: &'static str) -> Result<u32, ContentError> {
    let word = word.ok_or(ContentError::MissingIndex(what))?;
    let i: i64 =
        word.parse().map_err(|_| ContentError::NotAnIndex { word: word.to_string(), what })?;
    let resolved = if i < 0 { count as i64 + i } else { i - 1 };
    if i == 0 || resolved < 0 || resolved >= count as i64 {
        return Err(ContentError::IndexOutOfRange { what, index: i, count });
    }
    Ok(resolved as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_of_every_form_and_polygons() {
        let mesh = parse(
            b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nf 1 2 3\nf 1/1 3/1 4/1\nf -4 -3 -2 -1\n",
        )
        .unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 2, 3]]);
        assert!(mesh.normals.is_none());
        let smooth = parse(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n").unwrap();
        assert_eq!(smooth.normals, Some(vec![Vec3::Z; 3]));
    }

    #[test]
    fn errors_name_the_line() {
        let error = |bytes: &[u8]| parse(bytes).unwrap_err().to_string();
        assert_eq!(error(b"v 0 0 0\nv 1 x 0\n"), "line 2: `x` is not a number");
        assert_eq!(
            error(b"v 0 0 0\nf 1 2 3\n"),
            "line 2: vertex index 2 is out of range (there are 1 so far)"
        );
        assert_eq!(error(b"v 0 0 0\nf 1 1\n"), "line 2: a face needs 3 vertices, this one has 2");
    }
}
