//! The PLY header: format and elements with their properties.

use super::error::{PlyMeshError, PlyPlace};

/// Body encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Whitespace-separated text.
    Ascii,
    /// Binary, little-endian.
    LittleEndian,
    /// Binary, big-endian.
    BigEndian,
}

/// A scalar type of a property.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scalar {
    /// `char` / `int8`.
    I8,
    /// `uchar` / `uint8`.
    U8,
    /// `short` / `int16`.
    I16,
    /// `ushort` / `uint16`.
    U16,
    /// `int` / `int32`.
    I32,
    /// `uint` / `uint32`.
    U32,
    /// `float` / `float32`.
    F32,
    /// `double` / `float64`.
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    /// Size in bytes in a binary body.
    pub fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    /// The type's name, for messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::I8 => "int8",
            Self::U8 => "uint8",
            Self::I16 => "int16",
            Self::U16 => "uint16",
            Self::I32 => "int32",
            Self::U32 => "uint32",
            Self::F32 => "float32",
            Self::F64 => "float64",
        }
    }

    /// True for integer types.
    pub fn is_integer(self) -> bool {
        !matches!(self, Self::F32 | Self::F64)
    }
}

/// One property of an element.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Property {
    /// One value.
    Scalar {
        /// Property name.
        name: String,
        /// Type.
        ty: Scalar,
    },
    /// A count followed by that many values.
    List {
        /// Property name.
        name: String,
        /// Type of the count.
        count: Scalar,
        /// Type of the items.
        item: Scalar,
    },
}

impl Property {
    /// The property's name.
    pub fn name(&self) -> &str {
        match self {
            Self::Scalar { name, .. } | Self::List { name, .. } => name,
        }
    }
}

/// One element declaration.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Element {
    /// Element name (`vertex`, `face`, ...).
    pub name: String,
    /// Number of rows.
    pub count: usize,
    /// Properties in row order.
    pub properties: Vec<Property>,
}

/// A parsed header.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Header {
    /// Body encoding.
    pub format: Format,
    /// Elements in body order.
    pub elements: Vec<Element>,
    /// Byte offset of the body.
    pub body_offset: usize,
    /// Number of header lines (the body's first line is this + 1).
    pub lines: usize,
}

/// Parses the header at the start of `data`.
pub fn parse_header(data: &[u8]) -> Result<Header, PlyMeshError> {
    let mut pos = 0;
    let mut line_no = 0;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some(len) = data
            .get(pos..)
            .and_then(|rest| rest.iter().position(|&b| b == b'\n'))
        else {
            return Err(if line_no == 0 {
                PlyMeshError::NotPly
            } else {
                PlyMeshError::NoEndHeader
            });
        };
        let raw = &data[pos..pos + len];
        pos += len + 1;
        line_no += 1;
        let text = String::from_utf8_lossy(raw)
            .trim_end_matches('\r')
            .to_string();
        let bad = |reason| PlyMeshError::Header {
            at: PlyPlace::Line(line_no),
            text: text.clone(),
            reason,
        };
        let words: Vec<&str> = text.split_whitespace().collect();
        if line_no == 1 {
            if words != ["ply"] {
                return Err(PlyMeshError::NotPly);
            }
            continue;
        }
        match words.as_slice() {
            ["format", f, _version] => {
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::LittleEndian,
                    "binary_big_endian" => Format::BigEndian,
                    _ => return Err(bad("unknown format")),
                });
            }
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => {
                let count = count.parse().map_err(|_| bad("bad element count"))?;
                elements.push(Element {
                    name: (*name).to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            ["property", "list", count, item, name] => {
                let count = Scalar::parse(count).filter(|s| s.is_integer());
                let item = Scalar::parse(item);
                let (Some(count), Some(item)) = (count, item) else {
                    return Err(bad("unknown list type"));
                };
                let element = elements
                    .last_mut()
                    .ok_or_else(|| bad("property before any element"))?;
                element.properties.push(Property::List {
                    name: (*name).to_string(),
                    count,
                    item,
                });
            }
            ["property", ty, name] => {
                let ty = Scalar::parse(ty).ok_or_else(|| bad("unknown property type"))?;
                let element = elements
                    .last_mut()
                    .ok_or_else(|| bad("property before any element"))?;
                element.properties.push(Property::Scalar {
                    name: (*name).to_string(),
                    ty,
                });
            }
            ["end_header"] => break,
            _ => return Err(bad("unknown keyword")),
        }
    }
    let format = format.ok_or(PlyMeshError::Header {
        at: PlyPlace::Line(line_no),
        text: "end_header".to_string(),
        reason: "no format line before end_header",
    })?;
    if let Some(e) = elements
        .iter()
        .find(|e| e.count > 0 && e.properties.is_empty())
    {
        return Err(PlyMeshError::Header {
            at: PlyPlace::Line(line_no),
            text: format!("element {} {}", e.name, e.count),
            reason: "element with rows but no properties",
        });
    }
    Ok(Header {
        format,
        elements,
        body_offset: pos,
        lines: line_no,
    })
}
