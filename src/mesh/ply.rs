//! PLY (Stanford polygon files): ASCII and binary of either byte order; `vertex` elements with
//! x, y, z (and nx, ny, nz for smooth shading), `face` elements with a vertex index list
//! (polygons are triangulated). Other elements and properties are read and skipped.

use glam::Vec3;

use super::{ContentError, Mesh, Place, triangulate};

#[derive(Debug, Clone, Copy, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

#[derive(Debug)]
enum Property {
    Scalar { name: String, ty: Scalar },
    List { name: String, count: Scalar, item: Scalar },
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    LittleEndian,
    BigEndian,
}

pub fn parse(bytes: &[u8]) -> Result<Mesh, ContentError> {
    let (format, elements, body) = header(bytes)?;
    let mut reader = match format {
        Format::Ascii => Reader::Ascii(
            std::str::from_utf8(body)
                .map_err(|_| ContentError::BodyNotText)?
                .split_ascii_whitespace(),
        ),
        Format::LittleEndian | Format::BigEndian => {
            Reader::Binary { bytes: body, at: 0, big_endian: format == Format::BigEndian }
        }
    };
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut has_normals = false;
    let mut triangles = Vec::new();
    let mut polygon = Vec::new();
    for element in &elements {
        // Never reserve more than the body could hold: a corrupt count must not exhaust memory.
        let plausible = element.count.min(body.len());
        if element.name == "vertex" {
            let find = |n: &str| {
                element
                    .properties
                    .iter()
                    .position(|p| matches!(p, Property::Scalar { name, .. } if name == n))
            };
            let xyz = [find("x"), find("y"), find("z")];
            let nxyz = [find("nx"), find("ny"), find("nz")];
            let [Some(x), Some(y), Some(z)] = xyz else {
                return Err(ContentError::NoCoordinates);
            };
            has_normals = nxyz.iter().all(Option::is_some);
            positions.reserve(plausible);
            let mut values = vec![0.0f64; element.properties.len()];
            for i in 0..element.count {
                for (value, property) in values.iter_mut().zip(&element.properties) {
                    *value = match property {
                        Property::Scalar { ty, .. } => reader.scalar(*ty),
                        Property::List { count, item, .. } => {
                            reader.skip_list(*count, *item).map(|_| 0.0)
                        }
                    }
                    .map_err(|e| e.at(Place::Item { element: "vertex".to_string(), index: i }))?;
                }
                positions.push(Vec3::new(values[x] as f32, values[y] as f32, values[z] as f32));
                if let [Some(nx), Some(ny), Some(nz)] = nxyz {
                    normals.push(Vec3::new(
                        values[nx] as f32,
                        values[ny] as f32,
                        values[nz] as f32,
                    ));
                }
            }
        } else if element.name == "face" {
            let indices = element.properties.iter().position(
                |p| matches!(p, Property::List { name, .. } if name == "vertex_indices" || name == "vertex_index"),
            );
            let Some(indices) = indices else {
                return Err(ContentError::NoVertexIndices);
            };
            triangles.reserve(plausible);
            for i in 0..element.count {
                let at =
                    |e: ContentError| e.at(Place::Item { element: "face".to_string(), index: i });
                for (k, property) in element.properties.iter().enumerate() {
                    match property {
                        Property::List { count, item, .. } if k == indices => {
                            let n = reader.scalar(*count).map_err(at)?;
                            if !(3.0..=1e6).contains(&n) {
                                return Err(at(ContentError::PlyFaceTooSmall(n)));
                            }
                            polygon.clear();
                            for _ in 0..n as usize {
                                let index = reader.scalar(*item).map_err(at)?;
                                if index < 0.0
                                    || index.fract() != 0.0
                                    || index > f64::from(u32::MAX)
                                {
                                    return Err(at(ContentError::NotAVertexIndex(index)));
                                }
                                polygon.push(index as u32);
                            }
                            triangulate(&polygon, &mut triangles).map_err(at)?;
                        }
                        Property::List { count, item, .. } => {
                            reader.skip_list(*count, *item).map_err(at)?
                        }
                        Property::Scalar { ty, .. } => reader.scalar(*ty).map(drop).map_err(at)?,
                    }
                }
            }
        } else if !element.properties.is_empty() {
            // (An element without properties takes no bytes, however many it claims.)
            for i in 0..element.count {
                for property in &element.properties {
                    match property {
                        Property::List { count, item, .. } => reader.skip_list(*count, *item),
                        Property::Scalar { ty, .. } => reader.scalar(*ty).map(drop),
                    }
                    .map_err(|e| e.at(Place::Item { element: element.name.clone(), index: i }))?;
                }
            }
        }
    }
    Ok(Mesh { positions, normals: has_normals.then_some(normals), triangles })
}

/// Parses the header; returns the format, the elements and the body's bytes.
fn header(bytes: &[u8]) -> Result<(Format, Vec<Element>, &[u8]), ContentError> {
    if !bytes.starts_with(b"ply") {
        return Err(ContentError::NotPly);
    }
    let end = find(bytes, b"end_header").ok_or(ContentError::NoEndHeader)?;
    let mut body_start = end + b"end_header".len();
    // The header's last line ends with \n or \r\n.
    if bytes.get(body_start) == Some(&b'\r') {
        body_start += 1;
    }
    if bytes.get(body_start) == Some(&b'\n') {
        body_start += 1;
    }
    let text = std::str::from_utf8(&bytes[..end]).map_err(|_| ContentError::HeaderNotText)?;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    for (number, line) in text.lines().enumerate().skip(1) {
        let at = |problem: ContentError| problem.at(Place::HeaderLine(number + 1));
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", name, _version] => {
                format = Some(match *name {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::LittleEndian,
                    "binary_big_endian" => Format::BigEndian,
                    _ => return Err(at(ContentError::UnknownFormat(name.to_string()))),
                })
            }
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count.parse().map_err(|_| at(ContentError::NotACount(count.to_string())))?,
                properties: Vec::new(),
            }),
            ["property", "list", count, item, name] => {
                let element =
                    elements.last_mut().ok_or_else(|| at(ContentError::PropertyBeforeElement))?;
                let ty = |t: &str| {
                    Scalar::parse(t).ok_or_else(|| at(ContentError::UnknownType(t.to_string())))
                };
                element.properties.push(Property::List {
                    name: name.to_string(),
                    count: ty(count)?,
                    item: ty(item)?,
                });
            }
            ["property", ty, name] => {
                let element =
                    elements.last_mut().ok_or_else(|| at(ContentError::PropertyBeforeElement))?;
                let ty = Scalar::parse(ty)
                    .ok_or_else(|| at(ContentError::UnknownType(ty.to_string())))?;
                element.properties.push(Property::Scalar { name: name.to_string(), ty });
            }
            _ => return Err(at(ContentError::UnreadableLine(line.to_string()))),
        }
    }
    let format = format.ok_or(ContentError::NoFormat)?;
    Ok((format, elements, &bytes[body_start..]))
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

enum Reader<'a> {
    Ascii(std::str::SplitAsciiWhitespace<'a>),
    Binary { bytes: &'a [u8], at: usize, big_endian: bool },
}

impl Reader<'_> {
    fn scalar(&mut self, ty: Scalar) -> Result<f64, ContentError> {
        match self {
            Reader::Ascii(words) => {
                let word = words.next().ok_or(ContentError::EndsEarly)?;
                word.parse::<f64>().map_err(|_| ContentError::NotANumber(word.to_string()))
            }
            Reader::Binary { bytes, at, big_endian } => {
                let size = ty.size();
                let chunk = bytes.get(*at..*at + size).ok_or(ContentError::EndsEarlyAtByte(*at))?;
                *at += size;
                let mut raw = [0u8; 8];
                raw[..size].copy_from_slice(chunk);
                if *big_endian {
                    raw[..size].reverse();
                }
                Ok(match ty {
                    Scalar::I8 => f64::from(raw[0] as i8),
                    Scalar::U8 => f64::from(raw[0]),
                    Scalar::I16 => f64::from(i16::from_le_bytes([raw[0], raw[1]])),
                    Scalar::U16 => f64::from(u16::from_le_bytes([raw[0], raw[1]])),
                    Scalar::I32 => f64::from(i32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]])),
                    Scalar::U32 => f64::from(u32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]])),
                    Scalar::F32 => f64::from(f32::from_le_bytes([raw[0], raw[1], raw[2], raw[3]])),
                    Scalar::F64 => f64::from_le_bytes(raw),
                })
            }
        }
    }

    fn skip_list(&mut self, count: Scalar, item: Scalar) -> Result<(), ContentError> {
        let n = self.scalar(count)?;
        if !(0.0..=1e6).contains(&n) {
            return Err(ContentError::LongList(n));
        }
        (0..n as usize).try_for_each(|_| self.scalar(item).map(drop))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII_SQUARE: &str = "ply\nformat ascii 1.0\ncomment a unit square\nelement vertex 4\n\
        property float x\nproperty float y\nproperty float z\nelement face 1\n\
        property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";

    fn binary_square(big_endian: bool) -> Vec<u8> {
        let format = if big_endian { "binary_big_endian" } else { "binary_little_endian" };
        let mut bytes = format!(
            "ply\r\nformat {format} 1.0\r\nelement vertex 4\r\nproperty float x\r\nproperty float y\r\n\
             property float z\r\nproperty uchar red\r\nelement face 1\r\nproperty list uchar uint vertex_indices\r\nend_header\r\n"
        )
        .into_bytes();
        let f = |v: f32| if big_endian { v.to_be_bytes() } else { v.to_le_bytes() };
        let u = |v: u32| if big_endian { v.to_be_bytes() } else { v.to_le_bytes() };
        for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]] {
            p.iter().for_each(|c| bytes.extend(f(*c)));
            bytes.push(255);
        }
        bytes.push(4);
        (0..4).for_each(|i| bytes.extend(u(i)));
        bytes
    }

    #[test]
    fn ascii_and_binary_read_the_same_mesh() {
        let ascii = parse(ASCII_SQUARE.as_bytes()).unwrap();
        assert_eq!(ascii.positions.len(), 4);
        assert_eq!(ascii.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(parse(&binary_square(false)).unwrap(), ascii);
        assert_eq!(parse(&binary_square(true)).unwrap(), ascii);
    }

    #[test]
    fn errors_name_the_element_or_header_line() {
        let error = |bytes: &[u8]| parse(bytes).unwrap_err().to_string();
        let truncated = &binary_square(false)[..binary_square(false).len() - 3];
        assert_eq!(error(truncated), "face 0: the file ends too early (at byte 65 of the data)");
        assert_eq!(error(b"plx"), "not a PLY file (it does not start with `ply`)");
        let bad_type = ASCII_SQUARE.replace("property float y", "property quad y");
        assert_eq!(error(bad_type.as_bytes()), "header line 6: unknown type `quad`");
        let bad_value = ASCII_SQUARE.replace("1 1 0", "1 one 0");
        assert_eq!(error(bad_value.as_bytes()), "vertex 2: `one` is not a number");
        let huge = ASCII_SQUARE.replace("element vertex 4", "element vertex 4000000000000");
        // The face's numbers are read as vertex 4; vertex 5 runs out.
        assert_eq!(error(huge.as_bytes()), "vertex 5: the file ends too early");
        // Found by fuzzing: a huge count of an element with no properties took forever.
        let empty_element = "ply\nformat ascii 1.0\nelement junk 376000000000000000\nend_header\n";
        assert!(parse(empty_element.as_bytes()).unwrap().triangles.is_empty());
    }
}
