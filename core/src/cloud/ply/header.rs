//! The PLY header: body encoding, elements and their properties.

use std::collections::HashSet;

use super::{PlyError, Scalar};

/// Encoding of a PLY body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PlyFormat {
    /// One whitespace-separated text row per line.
    Ascii,
    /// Packed little-endian binary rows (what [`super::write_ply`] writes).
    #[default]
    BinaryLittleEndian,
    /// Packed big-endian binary rows.
    BinaryBigEndian,
}

impl PlyFormat {
    /// The keyword used on the `format` line.
    pub fn keyword(self) -> &'static str {
        match self {
            Self::Ascii => "ascii",
            Self::BinaryLittleEndian => "binary_little_endian",
            Self::BinaryBigEndian => "binary_big_endian",
        }
    }

    fn from_keyword(word: &str) -> Option<Self> {
        [Self::Ascii, Self::BinaryLittleEndian, Self::BinaryBigEndian]
            .into_iter()
            .find(|f| f.keyword() == word)
    }
}

/// How a property's values are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PropertyKind {
    /// One value.
    Scalar(Scalar),
    /// A length of type `count`, then that many values of type `item`.
    List {
        /// Type of the length prefix (an integer type).
        count: Scalar,
        /// Type of each item.
        item: Scalar,
    },
}

/// One `property` line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Property {
    /// Property name.
    pub name: String,
    /// Storage.
    pub kind: PropertyKind,
}

/// One `element` line and its properties.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Element {
    /// Element name (`vertex`, `face`, ...).
    pub name: String,
    /// Declared number of rows.
    pub count: u64,
    /// Properties in row order.
    pub properties: Vec<Property>,
}

impl Element {
    /// Smallest possible size of one binary row, in bytes.
    pub fn min_row_bytes(&self) -> u64 {
        self.properties
            .iter()
            .map(|p| match p.kind {
                PropertyKind::Scalar(s) => s.size() as u64,
                PropertyKind::List { count, .. } => count.size() as u64,
            })
            .sum()
    }

    /// Size of every binary row when the element has no list properties.
    pub fn fixed_row_bytes(&self) -> Option<u64> {
        self.properties
            .iter()
            .all(|p| matches!(p.kind, PropertyKind::Scalar(_)))
            .then(|| self.min_row_bytes())
    }
}

/// A parsed PLY header.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    /// Body encoding.
    pub format: PlyFormat,
    /// Elements in file order.
    pub elements: Vec<Element>,
    /// Origin from a `comment skyground origin X Y Z` line, if any.
    pub origin: Option<[f64; 3]>,
    /// Byte offset of the body (just after the `end_header` line).
    pub body_offset: usize,
    /// Number of header lines (the body starts on the next line).
    pub lines: usize,
}

/// The comment our writer uses to store [`crate::cloud::Cloud::origin`].
pub const ORIGIN_COMMENT: &str = "skyground origin";

/// Parses the header at the start of `data`.
pub fn parse_header(data: &[u8]) -> Result<Header, PlyError> {
    let mut lines = Lines {
        data,
        pos: 0,
        line: 0,
    };
    // Trailing blanks after the magic word are accepted, as rply and PDAL
    // do (PDAL's own simple_text.ply has `ply `).
    match lines.next().map(<[u8]>::trim_ascii_end) {
        Some(b"ply") => {}
        _ => return Err(PlyError::BadMagic),
    }
    let mut format = None;
    let mut origin = None;
    let mut elements: Vec<Element> = Vec::new();
    // Names seen so far (sets, so that huge headers stay linear).
    let mut element_names = HashSet::new();
    let mut property_names = HashSet::new();
    loop {
        let Some(raw) = lines.next() else {
            return Err(PlyError::MissingEndHeader);
        };
        let line = lines.line;
        let malformed = |reason: String| PlyError::MalformedHeaderLine { line, reason };
        let mut words = raw.split(u8::is_ascii_whitespace).filter(|w| !w.is_empty());
        let keyword = words.next().unwrap_or_default();
        if keyword == b"comment" || keyword == b"obj_info" {
            if keyword == b"comment"
                && let Some(o) = parse_origin_comment(raw, line)?
            {
                origin = Some(o);
            }
            continue;
        }
        let words: Vec<&str> = words
            .map(std::str::from_utf8)
            .collect::<Result<_, _>>()
            .map_err(|_| malformed("not valid UTF-8".into()))?;
        match (keyword, words.as_slice()) {
            (b"format", [name, version]) => {
                if format.is_some() {
                    return Err(malformed("second `format` line".into()));
                }
                let f = PlyFormat::from_keyword(name).ok_or_else(|| PlyError::UnknownFormat {
                    line,
                    found: (*name).into(),
                })?;
                if *version != "1.0" {
                    return Err(PlyError::UnsupportedVersion {
                        line,
                        found: (*version).into(),
                    });
                }
                format = Some(f);
            }
            (b"format", _) => return Err(malformed("expected `format NAME 1.0`".into())),
            (b"element", [name, count]) => {
                if !element_names.insert(*name) {
                    return Err(malformed(format!("element '{name}' declared twice")));
                }
                property_names.clear();
                let count = count.parse::<u64>().map_err(|_| {
                    malformed(format!(
                        "element count '{count}' is not a non-negative integer"
                    ))
                })?;
                elements.push(Element {
                    name: (*name).into(),
                    count,
                    properties: Vec::new(),
                });
            }
            (b"element", _) => return Err(malformed("expected `element NAME COUNT`".into())),
            (b"property", words) => {
                let element = elements
                    .last_mut()
                    .ok_or_else(|| malformed("property before any element".into()))?;
                let property = parse_property(words, line)?;
                if !property_names.insert(property.name.clone()) {
                    return Err(malformed(format!(
                        "property '{}' declared twice in element '{}'",
                        property.name, element.name
                    )));
                }
                element.properties.push(property);
            }
            (b"end_header", []) => break,
            _ => {
                let shown = String::from_utf8_lossy(keyword);
                return Err(malformed(format!("unexpected keyword '{shown}'")));
            }
        }
    }
    Ok(Header {
        format: format.ok_or(PlyError::MissingFormat)?,
        elements,
        origin,
        body_offset: lines.pos,
        lines: lines.line,
    })
}

fn parse_property(words: &[&str], line: usize) -> Result<Property, PlyError> {
    let scalar = |name: &str| {
        Scalar::from_name(name).ok_or_else(|| PlyError::UnknownPropertyType {
            line,
            found: name.into(),
        })
    };
    let (kind, name) = match words {
        ["list", count, item, name] => {
            let count = scalar(count)?;
            if count.is_float() {
                return Err(PlyError::MalformedHeaderLine {
                    line,
                    reason: format!(
                        "list length type must be an integer type, not {}",
                        count.name()
                    ),
                });
            }
            (
                PropertyKind::List {
                    count,
                    item: scalar(item)?,
                },
                name,
            )
        }
        [ty, name] if *ty != "list" => (PropertyKind::Scalar(scalar(ty)?), name),
        _ => {
            return Err(PlyError::MalformedHeaderLine {
                line,
                reason:
                    "expected `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME`"
                        .into(),
            });
        }
    };
    Ok(Property {
        name: (*name).into(),
        kind,
    })
}

/// Reads `comment skyground origin X Y Z`; other comments give `None`.
fn parse_origin_comment(raw: &[u8], line: usize) -> Result<Option<[f64; 3]>, PlyError> {
    let Ok(text) = std::str::from_utf8(raw) else {
        return Ok(None);
    };
    let Some(rest) = text.trim().strip_prefix("comment") else {
        return Ok(None);
    };
    let Some(rest) = rest.trim_start().strip_prefix(ORIGIN_COMMENT) else {
        return Ok(None);
    };
    let values: Vec<f64> = rest
        .split_ascii_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .unwrap_or_default();
    let [x, y, z] = values[..] else {
        return Err(PlyError::MalformedHeaderLine {
            line,
            reason: format!("expected `comment {ORIGIN_COMMENT} X Y Z` with three numbers"),
        });
    };
    let origin = [x, y, z];
    if origin.iter().all(|v| v.is_finite()) {
        Ok(Some(origin))
    } else {
        Err(PlyError::NonFiniteOrigin { origin })
    }
}

/// Header lines: split on `\n`, a trailing `\r` removed, counted from 1.
struct Lines<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Iterator for Lines<'a> {
    type Item = &'a [u8];

    fn next(&mut self) -> Option<&'a [u8]> {
        let rest = self.data.get(self.pos..)?;
        // A header line must end in a newline; without one the header is incomplete.
        let len = rest.iter().position(|&b| b == b'\n')?;
        let line = rest.get(..len)?;
        self.pos += len + 1;
        self.line += 1;
        Some(line.strip_suffix(b"\r").unwrap_or(line))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trailing_blanks_after_the_magic_and_on_lines_are_accepted() {
        let h = parse_header(
            b"ply \t\nformat ascii 1.0 \nelement vertex 3\nproperty float x \nend_header \n",
        )
        .unwrap();
        assert_eq!(h.elements[0].count, 3);
        assert_eq!(h.elements[0].properties.len(), 1);
        assert!(matches!(parse_header(b"plyx\n"), Err(PlyError::BadMagic)));
    }

    fn header(text: &str) -> Result<Header, PlyError> {
        parse_header(text.as_bytes())
    }

    #[test]
    fn parses_elements_properties_and_body_offset() {
        let text = "ply\r\nformat binary_big_endian 1.0\r\ncomment hi\r\nobj_info x\r\n\
                    element vertex 2\r\nproperty float32 x\r\nproperty list uint8 int32 idx\r\n\
                    element face 0\r\nend_header\r\nBODY";
        let h = header(text).unwrap();
        assert_eq!(h.format, PlyFormat::BinaryBigEndian);
        assert_eq!(h.elements.len(), 2);
        assert_eq!(h.elements[0].count, 2);
        assert_eq!(
            h.elements[0].properties[1].kind,
            PropertyKind::List {
                count: Scalar::U8,
                item: Scalar::I32
            }
        );
        assert_eq!(&text.as_bytes()[h.body_offset..], b"BODY");
        assert_eq!(h.lines, 9);
        assert_eq!(h.elements[0].min_row_bytes(), 5);
        assert_eq!(h.elements[0].fixed_row_bytes(), None);
    }

    #[test]
    fn reads_origin_comment() {
        let h = header("ply\nformat ascii 1.0\ncomment skyground origin 1.5 -2 3e5\nend_header\n")
            .unwrap();
        assert_eq!(h.origin, Some([1.5, -2.0, 3e5]));
    }

    #[test]
    fn header_errors_name_the_line() {
        let cases = [
            ("plx\n", "not a PLY file"),
            ("ply\nformat ascii 1.0\n", "no `end_header`"),
            ("ply\nend_header\n", "no `format`"),
            (
                "ply\nformat utf8 1.0\nend_header\n",
                "line 2: unknown PLY format 'utf8'",
            ),
            (
                "ply\nformat ascii 2.0\nend_header\n",
                "line 2: unsupported PLY version",
            ),
            ("ply\nformat ascii 1.0\nelement v\n", "line 3: malformed"),
            ("ply\nformat ascii 1.0\nelement v -1\n", "line 3: malformed"),
            (
                "ply\nformat ascii 1.0\nproperty float x\n",
                "property before any element",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\nproperty int64 x\n",
                "line 4: unknown PLY property type 'int64'",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\nproperty list float int x\n",
                "integer type",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\nproperty float\n",
                "expected `property TYPE NAME`",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\nproperty float x\nproperty int x\n",
                "declared twice",
            ),
            (
                "ply\nformat ascii 1.0\nelement v 1\nelement v 2\n",
                "declared twice",
            ),
            (
                "ply\nformat ascii 1.0\nformat ascii 1.0\n",
                "second `format`",
            ),
            (
                "ply\nformat ascii 1.0\nbogus\n",
                "unexpected keyword 'bogus'",
            ),
            ("ply\nformat ascii 1.0\n\n", "unexpected keyword ''"),
            (
                "ply\nformat ascii 1.0\ncomment skyground origin 1 2\n",
                "three numbers",
            ),
            (
                "ply\nformat ascii 1.0\ncomment skyground origin 1 2 inf\n",
                "not finite",
            ),
        ];
        for (text, want) in cases {
            let err = header(text).unwrap_err().to_string();
            assert!(err.contains(want), "{text:?}: {err}");
        }
        let err = parse_header(b"ply\nformat ascii 1.0\nelement \xff 1\n").unwrap_err();
        assert!(err.to_string().contains("UTF-8"), "{err}");
    }
}
