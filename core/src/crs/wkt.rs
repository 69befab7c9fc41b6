//! Just enough of OGC WKT (WKT1 and WKT2) to name a CRS, find its EPSG code
//! and its horizontal and vertical linear units.

use super::LinearUnit;

/// One `KEYWORD[arg, ...]` node of a WKT text.
#[derive(Debug, Clone, PartialEq)]
pub struct WktNode {
    /// The keyword, upper-cased (`PROJCS`, `UNIT`, ...).
    pub keyword: String,
    /// The arguments in order.
    pub args: Vec<WktArg>,
}

/// An argument of a WKT node.
#[derive(Debug, Clone, PartialEq)]
pub enum WktArg {
    /// A quoted string.
    Text(String),
    /// A number.
    Number(f64),
    /// An unquoted word (`EAST`, `Cartesian`).
    Word(String),
    /// A nested node.
    Node(WktNode),
}

/// The WKT text could not be parsed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("WKT is malformed at byte {at}: {what}")]
pub struct WktError {
    /// Byte offset of the problem.
    pub at: usize,
    /// What was expected.
    pub what: &'static str,
}

/// What a WKT says about units and identity.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct WktFacts {
    /// The CRS's name (first argument of the top node).
    pub name: Option<String>,
    /// The top node's EPSG code (`AUTHORITY["EPSG","n"]` or `ID["EPSG",n]`).
    pub epsg: Option<u32>,
    /// The horizontal CRS's EPSG code inside a compound CRS.
    pub horizontal_epsg: Option<u32>,
    /// The vertical CRS's EPSG code inside a compound CRS.
    pub vertical_epsg: Option<u32>,
    /// Linear unit of the horizontal axes (None for geographic CRSs or when absent).
    pub horizontal_unit: Option<LinearUnit>,
    /// Linear unit of the vertical axis, when the WKT has a vertical CRS.
    pub vertical_unit: Option<LinearUnit>,
    /// True when the horizontal CRS is geographic (angles, not lengths).
    pub geographic: bool,
    /// True when it is geocentric (Earth-centred Cartesian x, y, z): also
    /// `geographic`, as neither has plan axes and an up.
    pub geocentric: bool,
}

const PROJECTED: [&str; 3] = ["PROJCS", "PROJCRS", "PROJECTEDCRS"];
const GEOGRAPHIC: [&str; 6] = [
    "GEOGCS",
    "GEOGCRS",
    "GEOGRAPHICCRS",
    "GEODCRS",
    "GEODETICCRS",
    "GEOCCS",
];
const VERTICAL: [&str; 3] = ["VERT_CS", "VERTCRS", "VERTICALCRS"];
const COMPOUND: [&str; 2] = ["COMPD_CS", "COMPOUNDCRS"];
const UNIT: [&str; 2] = ["UNIT", "LENGTHUNIT"];

impl WktNode {
    /// Direct children that are nodes.
    pub fn children(&self) -> impl Iterator<Item = &WktNode> {
        self.args.iter().filter_map(|a| match a {
            WktArg::Node(n) => Some(n),
            _ => None,
        })
    }

    /// The first direct child whose keyword is one of `keywords`.
    pub fn child(&self, keywords: &[&str]) -> Option<&WktNode> {
        self.children()
            .find(|c| keywords.contains(&c.keyword.as_str()))
    }

    fn text(&self, i: usize) -> Option<&str> {
        match self.args.get(i)? {
            WktArg::Text(s) | WktArg::Word(s) => Some(s),
            _ => None,
        }
    }

    fn number(&self, i: usize) -> Option<f64> {
        match self.args.get(i)? {
            WktArg::Number(v) => Some(*v),
            WktArg::Text(s) => s.trim().parse().ok(),
            _ => None,
        }
    }

    /// The node's own EPSG code, from `AUTHORITY` (WKT1) or `ID` (WKT2).
    pub fn epsg(&self) -> Option<u32> {
        let id = self.child(&["AUTHORITY", "ID"])?;
        if !id.text(0)?.eq_ignore_ascii_case("EPSG") {
            return None;
        }
        match id.args.get(1)? {
            WktArg::Number(v) if v.fract() == 0.0 && *v > 0.0 && *v < f64::from(u32::MAX) => {
                // Whole and in range, checked just above.
                Some(*v as u32)
            }
            WktArg::Text(s) => s.trim().parse().ok(),
            _ => None,
        }
    }

    /// The linear unit of this CRS node: a direct `UNIT`/`LENGTHUNIT`, else the
    /// first axis's (WKT2 may put it there); never a parameter's unit.
    fn linear_unit(&self) -> Option<LinearUnit> {
        let unit = self.child(&UNIT).or_else(|| {
            self.children()
                .filter(|c| c.keyword == "AXIS")
                .find_map(|a| a.child(&UNIT))
        })?;
        LinearUnit::from_name_and_size(unit.text(0).unwrap_or("unit"), unit.number(1)?)
    }
}

/// Parses a WKT text into its top node (trailing NULs and spaces are ignored).
pub fn parse_wkt(text: &str) -> Result<WktNode, WktError> {
    parse_with_spans(text).map(|(node, _)| node)
}

/// The top node, and every node's keyword with the bytes it spans in `text`.
fn parse_with_spans(text: &str) -> Result<(WktNode, Vec<NodeSpan>), WktError> {
    let text = text.trim_end_matches(['\0', ' ', '\n', '\r', '\t']);
    let mut p = Parser {
        s: text.as_bytes(),
        at: 0,
        depth: 0,
        spans: Vec::new(),
    };
    p.skip_space();
    let node = p.node()?;
    p.skip_space();
    if p.at != p.s.len() {
        return Err(p.error("end of text after the top node"));
    }
    Ok((node, p.spans))
}

/// A node's keyword, and where it starts and ends (byte offsets, end excluded).
type NodeSpan = (String, usize, usize);

/// Deepest nesting of nodes a text may have. A real CRS nests about ten
/// deep (a bound compound CRS, its projected CRS, base CRS, datum,
/// ellipsoid, unit, identifier); the parser recurses once per level, so a
/// record of brackets alone (a LAS 1.4 extended record may hold megabytes)
/// would otherwise exhaust the stack and abort the process.
pub const MAX_DEPTH: usize = 64;

/// The name, EPSG codes and units a WKT text states.
pub fn wkt_facts(text: &str) -> Result<WktFacts, WktError> {
    let top = parse_wkt(text)?;
    let mut facts = WktFacts {
        name: top.text(0).map(str::to_string),
        epsg: top.epsg(),
        ..WktFacts::default()
    };
    let (horizontal, vertical) = if COMPOUND.contains(&top.keyword.as_str()) {
        let h = top.child(&PROJECTED).or_else(|| top.child(&GEOGRAPHIC));
        (h, top.child(&VERTICAL))
    } else if VERTICAL.contains(&top.keyword.as_str()) {
        (None, Some(&top))
    } else {
        (Some(&top), None)
    };
    if let Some(h) = horizontal {
        facts.horizontal_epsg = h.epsg();
        if PROJECTED.contains(&h.keyword.as_str()) {
            facts.horizontal_unit = h.linear_unit();
        } else if GEOGRAPHIC.contains(&h.keyword.as_str()) {
            facts.geographic = true;
            // WKT1's GEOCCS; WKT2's geodetic CRS with a Cartesian system.
            let cartesian = h.child(&["CS"]).and_then(|cs| cs.text(0));
            facts.geocentric = h.keyword == "GEOCCS"
                || cartesian.is_some_and(|t| t.eq_ignore_ascii_case("Cartesian"));
        }
    }
    if let Some(v) = vertical {
        facts.vertical_epsg = v.epsg();
        facts.vertical_unit = v.linear_unit();
    }
    Ok(facts)
}

/// `text` without its `keyword[...]` nodes (and the comma that joined
/// each to its neighbours); `text` unchanged when it or the result does
/// not parse.
pub fn without_nodes(text: &str, keyword: &str) -> String {
    let Ok((_, mut spans)) = parse_with_spans(text) else {
        return text.to_string();
    };
    let keyword = keyword.to_ascii_uppercase();
    spans.retain(|(k, _, _)| *k == keyword);
    spans.sort_by_key(|&(_, start, _)| start);
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut kept = 0;
    // A node inside one already cut starts before `kept`.
    for (_, start, end) in spans {
        if start < kept {
            continue;
        }
        let (mut from, mut to) = (start, end);
        while from > kept && b[from - 1].is_ascii_whitespace() {
            from -= 1;
        }
        if from > kept && b[from - 1] == b',' {
            from -= 1;
        } else {
            // The first argument: the comma after it goes instead.
            while to < b.len() && b[to].is_ascii_whitespace() {
                to += 1;
            }
            if b.get(to) == Some(&b',') {
                to += 1;
            }
        }
        out.push_str(&text[kept..from]);
        kept = to;
    }
    out.push_str(&text[kept..]);
    if parse_wkt(&out).is_ok() {
        out
    } else {
        text.to_string()
    }
}

struct Parser<'a> {
    s: &'a [u8],
    at: usize,
    /// Nodes open around the current position.
    depth: usize,
    spans: Vec<NodeSpan>,
}

impl Parser<'_> {
    fn error(&self, what: &'static str) -> WktError {
        WktError { at: self.at, what }
    }

    fn peek(&self) -> Option<u8> {
        self.s.get(self.at).copied()
    }

    fn skip_space(&mut self) {
        while self.peek().is_some_and(|c| c.is_ascii_whitespace()) {
            self.at += 1;
        }
    }

    fn word(&mut self) -> String {
        let start = self.at;
        while self
            .peek()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == b'_')
        {
            self.at += 1;
        }
        String::from_utf8_lossy(&self.s[start..self.at]).into_owned()
    }

    fn node(&mut self) -> Result<WktNode, WktError> {
        if self.depth >= MAX_DEPTH {
            return Err(self.error("nodes nested at most 64 deep"));
        }
        self.depth += 1;
        let node = self.node_inside();
        self.depth -= 1;
        node
    }

    fn node_inside(&mut self) -> Result<WktNode, WktError> {
        let start = self.at;
        let keyword = self.word().to_ascii_uppercase();
        if keyword.is_empty() {
            return Err(self.error("a keyword"));
        }
        self.skip_space();
        let close = match self.peek() {
            Some(b'[') => b']',
            Some(b'(') => b')',
            _ => return Err(self.error("`[` or `(` after a keyword")),
        };
        self.at += 1;
        let mut args = Vec::new();
        loop {
            self.skip_space();
            if self.peek() == Some(close) && args.is_empty() {
                self.at += 1;
                break;
            }
            args.push(self.arg()?);
            self.skip_space();
            match self.peek() {
                Some(b',') => self.at += 1,
                Some(c) if c == close => {
                    self.at += 1;
                    break;
                }
                _ => return Err(self.error("`,` or a closing bracket")),
            }
        }
        self.spans.push((keyword.clone(), start, self.at));
        Ok(WktNode { keyword, args })
    }

    fn arg(&mut self) -> Result<WktArg, WktError> {
        match self.peek() {
            Some(b'"') => self.quoted().map(WktArg::Text),
            Some(c) if c == b'-' || c == b'+' || c == b'.' || c.is_ascii_digit() => {
                let start = self.at;
                while self
                    .peek()
                    .is_some_and(|c| c.is_ascii_digit() || b"+-.eE".contains(&c))
                {
                    self.at += 1;
                }
                std::str::from_utf8(&self.s[start..self.at])
                    .ok()
                    .and_then(|t| t.parse().ok())
                    .map(WktArg::Number)
                    .ok_or(WktError {
                        at: start,
                        what: "a number",
                    })
            }
            Some(c) if c.is_ascii_alphabetic() => {
                let start = self.at;
                let word = self.word();
                self.skip_space();
                if matches!(self.peek(), Some(b'[' | b'(')) {
                    self.at = start;
                    self.node().map(WktArg::Node)
                } else {
                    Ok(WktArg::Word(word))
                }
            }
            _ => Err(self.error("a value")),
        }
    }

    /// A `"..."` string; `""` inside is one quote (WKT2's escape).
    fn quoted(&mut self) -> Result<String, WktError> {
        self.at += 1;
        let mut out = Vec::new();
        loop {
            match self.peek() {
                None => return Err(self.error("a closing quote")),
                Some(b'"') if self.s.get(self.at + 1) == Some(&b'"') => {
                    out.push(b'"');
                    self.at += 2;
                }
                Some(b'"') => {
                    self.at += 1;
                    return Ok(String::from_utf8_lossy(&out).into_owned());
                }
                Some(c) => {
                    out.push(c);
                    self.at += 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The WKT record of laspy's Nebraska test file (EPSG:6880, no AUTHORITY).
    const NEBRASKA: &str = r#"PROJCS["NAD83_2011_Nebraska_ft",GEOGCS["GCS_NAD_1983_2011",DATUM["D_NAD83_NATIONAL_SPATIAL_REFERENCE_SYSTEM_2011",SPHEROID["GRS_1980",6378137,298.257222101]],PRIMEM["Greenwich",0],UNIT["Degree",0.017453292519943295]],PROJECTION["Lambert_Conformal_Conic"],PARAMETER["scale_factor",1],PARAMETER["standard_parallel_1",40],PARAMETER["false_easting",1640416.666666667],UNIT["Foot_US",0.30480060960121924]]"#;

    #[test]
    fn a_datum_shift_comes_out_and_the_rest_stays() {
        let rd = r#"PROJCS["Amersfoort / RD New",GEOGCS["Amersfoort",DATUM["Amersfoort",SPHEROID["Bessel 1841",6377397.155,299.1528128],TOWGS84[565.2369,50.0087,465.658,-0.406857,0.350733,-1.87035,4.0812],AUTHORITY["EPSG","6289"]],UNIT["degree",0.0174532925199433]],UNIT["metre",1],AUTHORITY["EPSG","28992"]]"#;
        let out = without_nodes(rd, "TOWGS84");
        assert!(!out.contains("TOWGS84"), "{out}");
        assert!(
            out.contains(r#"299.1528128],AUTHORITY["EPSG","6289"]]"#),
            "{out}"
        );
        assert_eq!(wkt_facts(&out), wkt_facts(rd));
        // First argument, spaces, a keyword inside a name, and no such node.
        let first = r#"A["x TOWGS84[", TOWGS84 [1, 2] , B[3]]"#;
        assert_eq!(without_nodes(first, "towgs84"), r#"A["x TOWGS84[" , B[3]]"#);
        assert_eq!(without_nodes(NEBRASKA, "TOWGS84"), NEBRASKA);
        // A text that does not parse after the cut stays as it was.
        assert_eq!(without_nodes("A[TOWGS84[1]", "TOWGS84"), "A[TOWGS84[1]");
    }

    #[test]
    fn wkt1_projected_in_us_feet() {
        let f = wkt_facts(NEBRASKA).unwrap();
        assert_eq!(f.name.as_deref(), Some("NAD83_2011_Nebraska_ft"));
        assert_eq!(f.horizontal_unit, Some(LinearUnit::UsSurveyFoot));
        assert_eq!(f.vertical_unit, None);
        assert_eq!(f.epsg, None);
        assert!(!f.geographic);
    }

    #[test]
    fn wkt1_compound_gives_both_units_and_codes() {
        let text = r#"COMPD_CS["RD + NAP",PROJCS["Amersfoort / RD New",GEOGCS["Amersfoort",UNIT["degree",0.0174532925199433]],UNIT["metre",1,AUTHORITY["EPSG","9001"]],AUTHORITY["EPSG","28992"]],VERT_CS["NAP height",VERT_DATUM["Normaal Amsterdams Peil",2005],UNIT["foot",0.3048],AXIS["Up",UP],AUTHORITY["EPSG","5709"]],AUTHORITY["EPSG","7415"]]"#;
        let f = wkt_facts(text).unwrap();
        assert_eq!(f.epsg, Some(7415));
        assert_eq!(f.horizontal_epsg, Some(28992));
        assert_eq!(f.vertical_epsg, Some(5709));
        assert_eq!(f.horizontal_unit, Some(LinearUnit::Metre));
        assert_eq!(f.vertical_unit, Some(LinearUnit::Foot));
    }

    #[test]
    fn wkt2_unit_is_read_from_axes_not_from_parameters() {
        let text = r#"PROJCRS["NAD83 / Oregon GIC Lambert (ft)",BASEGEOGCRS["NAD83",ANGLEUNIT["degree",0.0174532925199433]],CONVERSION["Oregon",METHOD["Lambert Conic Conformal (2SP)",ID["EPSG",9802]],PARAMETER["Easting at false origin",1312335.958,LENGTHUNIT["metre",1]]],CS[Cartesian,2],AXIS["easting (X)",east,ORDER[1],LENGTHUNIT["foot",0.3048]],AXIS["northing (Y)",north,ORDER[2],LENGTHUNIT["foot",0.3048]],ID["EPSG",2992]]"#;
        let f = wkt_facts(text).unwrap();
        assert_eq!(f.horizontal_unit, Some(LinearUnit::Foot));
        assert_eq!(f.epsg, Some(2992));
    }

    #[test]
    fn geocentric_is_told_apart_from_geographic() {
        let wkt1 = r#"GEOCCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563]],PRIMEM["Greenwich",0],UNIT["metre",1],AUTHORITY["EPSG","4978"]]"#;
        let wkt2 = r#"GEODCRS["WGS 84",DATUM["World Geodetic System 1984",ELLIPSOID["WGS 84",6378137,298.257223563]],CS[Cartesian,3],AXIS["(X)",geocentricX],AXIS["(Y)",geocentricY],AXIS["(Z)",geocentricZ],LENGTHUNIT["metre",1]]"#;
        for w in [wkt1, wkt2] {
            let f = wkt_facts(w).unwrap();
            assert!(f.geographic && f.geocentric, "{w}");
        }
        let geog = r#"GEODCRS["WGS 84",DATUM["World Geodetic System 1984",ELLIPSOID["WGS 84",6378137,298.257223563]],CS[ellipsoidal,2],AXIS["latitude",north],AXIS["longitude",east],ANGLEUNIT["degree",0.0174532925199433]]"#;
        let f = wkt_facts(geog).unwrap();
        assert!(f.geographic && !f.geocentric);
    }

    #[test]
    fn geographic_and_malformed_texts() {
        let f = wkt_facts(
            r#"GEOGCS["WGS 84",UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4326"]]"#,
        )
        .unwrap();
        assert!(f.geographic);
        assert_eq!(f.horizontal_unit, None);
        assert_eq!(f.epsg, Some(4326));
        assert!(wkt_facts(r#"PROJCS["x",UNIT["m",1]"#).is_err());
        assert!(wkt_facts("").is_err());
        let e = wkt_facts(r#"PROJCS["x" UNIT]"#).unwrap_err();
        assert_eq!(e.what, "`,` or a closing bracket");
        assert!(
            wkt_facts("PROJCS[\"x\",UNIT[\"m\",1]]\0\0").is_ok(),
            "NUL padding"
        );
    }
    /// `depth` nodes, each the only argument of the one around it.
    fn nested(depth: usize) -> String {
        format!("{}{}", "A[".repeat(depth), "]".repeat(depth))
    }

    #[test]
    fn nesting_past_the_limit_is_an_error_not_a_stack_overflow() {
        let deepest = parse_wkt(&nested(MAX_DEPTH)).unwrap();
        let mut levels = 1;
        let mut node = &deepest;
        while let Some(inner) = node.children().next() {
            node = inner;
            levels += 1;
        }
        assert_eq!(levels, MAX_DEPTH);
        let e = parse_wkt(&nested(MAX_DEPTH + 1)).unwrap_err();
        assert!(e.what.contains(&MAX_DEPTH.to_string()), "{e}");
        // Open at byte 2 × MAX_DEPTH: the keyword one level too deep.
        assert_eq!(e.at, 2 * MAX_DEPTH);
        // 600 kB of brackets, as a LAS 1.4 extended record may hold: it
        // aborted the process before the limit (30,000 levels overflowed
        // a test thread's 2 MiB stack, 200,000 the main thread's 8 MiB).
        let huge = nested(200_000);
        assert_eq!(wkt_facts(&huge).unwrap_err().at, 2 * MAX_DEPTH);
        assert_eq!(
            without_nodes(&huge, "A"),
            huge,
            "unchanged: it does not parse"
        );
    }
}
