//! An axis-aligned rectangle in a scene's local xy frame.

use super::CropError;

/// The xy rectangle `[min, max]` (both edges inside), metres, local frame.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Window {
    /// Lower-left corner x, y.
    pub min: [f64; 2],
    /// Upper-right corner x, y.
    pub max: [f64; 2],
}

impl Window {
    /// The window with corners `(x0, y0)` and `(x1, y1)`; finite, `x0 < x1`, `y0 < y1`.
    pub fn new(x0: f64, y0: f64, x1: f64, y1: f64) -> Result<Self, CropError> {
        let ok = [x0, y0, x1, y1].iter().all(|v| v.is_finite()) && x0 < x1 && y0 < y1;
        if ok {
            Ok(Self {
                min: [x0, y0],
                max: [x1, y1],
            })
        } else {
            Err(CropError::InvalidWindow { x0, y0, x1, y1 })
        }
    }

    /// The `size` × `size` square centred on `centre`.
    pub fn square(centre: [f64; 2], size: f64) -> Result<Self, CropError> {
        let h = size / 2.0;
        Self::new(centre[0] - h, centre[1] - h, centre[0] + h, centre[1] + h)
    }

    /// Width and height, metres.
    pub fn size(&self) -> [f64; 2] {
        [self.max[0] - self.min[0], self.max[1] - self.min[1]]
    }

    /// Whether `(x, y)` lies inside (edges included).
    pub fn contains(&self, x: f64, y: f64) -> bool {
        (self.min[0]..=self.max[0]).contains(&x) && (self.min[1]..=self.max[1]).contains(&y)
    }

    /// The smallest window holding both.
    pub fn union(&self, other: &Window) -> Window {
        Window {
            min: [self.min[0].min(other.min[0]), self.min[1].min(other.min[1])],
            max: [self.max[0].max(other.max[0]), self.max[1].max(other.max[1])],
        }
    }

    /// Centre x, y.
    pub fn centre(&self) -> [f64; 2] {
        [
            (self.min[0] + self.max[0]) / 2.0,
            (self.min[1] + self.max[1]) / 2.0,
        ]
    }
}

impl std::fmt::Display for Window {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:.1},{:.1},{:.1},{:.1}",
            self.min[0], self.min[1], self.max[0], self.max[1]
        )
    }
}

impl std::str::FromStr for Window {
    type Err = CropError;

    /// Parses `x0,y0,x1,y1` (metres, local frame).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || CropError::Syntax {
            text: s.to_string(),
        };
        let v: Vec<f64> = s
            .split(',')
            .map(|t| t.trim().parse::<f64>().map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        match v.as_slice() {
            &[x0, y0, x1, y1] => Self::new(x0, y0, x1, y1),
            _ => Err(bad()),
        }
    }
}
