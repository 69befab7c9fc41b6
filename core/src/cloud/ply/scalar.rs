//! PLY scalar types: names, sizes, and decoding one value from bytes or text.

/// One of the eight PLY scalar types.
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
    /// The type for a header type name (both the classic and the sized spelling).
    pub fn from_name(name: &str) -> Option<Self> {
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

    /// The classic header name of this type.
    pub fn name(self) -> &'static str {
        match self {
            Self::I8 => "char",
            Self::U8 => "uchar",
            Self::I16 => "short",
            Self::U16 => "ushort",
            Self::I32 => "int",
            Self::U32 => "uint",
            Self::F32 => "float",
            Self::F64 => "double",
        }
    }

    /// Size of one binary value in bytes.
    pub fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    /// True for `float` and `double`.
    pub fn is_float(self) -> bool {
        matches!(self, Self::F32 | Self::F64)
    }

    /// Decodes one binary value; `bytes` must be exactly [`Scalar::size`] long.
    pub fn decode(self, bytes: &[u8], big_endian: bool) -> Option<f64> {
        macro_rules! num {
            ($t:ty) => {{
                let raw = bytes.try_into().ok()?;
                if big_endian {
                    <$t>::from_be_bytes(raw)
                } else {
                    <$t>::from_le_bytes(raw)
                }
            }};
        }
        Some(match self {
            Self::I8 => f64::from(num!(i8)),
            Self::U8 => f64::from(num!(u8)),
            Self::I16 => f64::from(num!(i16)),
            Self::U16 => f64::from(num!(u16)),
            Self::I32 => f64::from(num!(i32)),
            Self::U32 => f64::from(num!(u32)),
            Self::F32 => f64::from(num!(f32)),
            Self::F64 => num!(f64),
        })
    }

    /// Parses one ASCII value; integers must be whole numbers in the type's range.
    pub fn parse(self, token: &[u8]) -> Option<f64> {
        let text = std::str::from_utf8(token).ok()?;
        match self {
            Self::F32 => text.parse::<f32>().ok().map(f64::from),
            Self::F64 => text.parse::<f64>().ok(),
            _ => {
                let v = text.parse::<i64>().ok()?;
                let (lo, hi) = self.int_range();
                // Every PLY integer fits f64 exactly.
                (lo..=hi).contains(&v).then_some(v as f64)
            }
        }
    }

    fn int_range(self) -> (i64, i64) {
        match self {
            Self::I8 => (i8::MIN.into(), i8::MAX.into()),
            Self::U8 => (0, u8::MAX.into()),
            Self::I16 => (i16::MIN.into(), i16::MAX.into()),
            Self::U16 => (0, u16::MAX.into()),
            Self::I32 => (i32::MIN.into(), i32::MAX.into()),
            Self::U32 => (0, u32::MAX.into()),
            Self::F32 | Self::F64 => (i64::MIN, i64::MAX),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_spellings_name_the_same_type() {
        for (a, b) in [
            ("char", "int8"),
            ("ushort", "uint16"),
            ("double", "float64"),
        ] {
            assert_eq!(Scalar::from_name(a), Scalar::from_name(b));
        }
        assert_eq!(Scalar::from_name("int64"), None);
    }

    #[test]
    fn decode_respects_endianness_and_size() {
        assert_eq!(Scalar::I16.decode(&[0xff, 0xfe], false), Some(-257.0));
        assert_eq!(Scalar::I16.decode(&[0xff, 0xfe], true), Some(-2.0));
        assert_eq!(Scalar::F32.decode(&1.5f32.to_be_bytes(), true), Some(1.5));
        assert_eq!(Scalar::U32.decode(&[1, 2], false), None);
    }

    #[test]
    fn parse_checks_integer_ranges() {
        assert_eq!(Scalar::U8.parse(b"255"), Some(255.0));
        assert_eq!(Scalar::U8.parse(b"256"), None);
        assert_eq!(Scalar::U8.parse(b"-1"), None);
        assert_eq!(Scalar::I32.parse(b"1.5"), None);
        assert_eq!(Scalar::F64.parse(b"-1e3"), Some(-1000.0));
        assert_eq!(Scalar::F32.parse(b"abc"), None);
    }
}
