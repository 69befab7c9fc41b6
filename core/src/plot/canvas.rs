//! A north-up raster of a rectangle of the xy plane.

use std::path::Path;

use image::RgbImage;

use super::color::{Rgb, WHITE};

/// Why a picture could not be made or written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The area to draw is empty or not finite.
    #[error("nothing to draw: the area {min:?}..{max:?} is empty or not finite")]
    EmptyArea {
        /// Lower corner.
        min: [f64; 2],
        /// Upper corner.
        max: [f64; 2],
    },
    /// A plan picture was asked for without a ground graph to draw.
    #[error("nothing to draw: the plan has no set-down (no ground graph)")]
    NoGraph,
    /// The file could not be created or renamed into place.
    #[error(transparent)]
    File(#[from] crate::file::FileError),
    /// The PNG could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: String,
        /// What went wrong.
        source: image::ImageError,
    },
}

/// A picture of the rectangle `min..max` of the xy plane, x to the right,
/// y up, at a fixed number of pixels per metre; bands above and below the
/// map may hold its furniture.
pub struct Canvas {
    img: RgbImage,
    min: [f64; 2],
    px_per_m: f64,
    /// Rows above the map.
    top: u32,
    /// Rows of the map itself.
    map_h: u32,
}

impl Canvas {
    /// A white canvas showing `min..max` plus `margin_m` around it, at most
    /// `max_px` pixels on its longer side.
    pub fn new(
        min: [f64; 2],
        max: [f64; 2],
        margin_m: f64,
        max_px: u32,
    ) -> Result<Self, PlotError> {
        let ok =
            min.iter().chain(&max).all(|v| v.is_finite()) && max[0] > min[0] && max[1] > min[1];
        if !ok || max_px < 2 {
            return Err(PlotError::EmptyArea { min, max });
        }
        let min = [min[0] - margin_m, min[1] - margin_m];
        let size = [max[0] + margin_m - min[0], max[1] + margin_m - min[1]];
        let px_per_m = f64::from(max_px) / size[0].max(size[1]);
        let w = ((size[0] * px_per_m).ceil() as u32).clamp(1, max_px);
        let h = ((size[1] * px_per_m).ceil() as u32).clamp(1, max_px);
        Ok(Self {
            img: RgbImage::from_pixel(w, h, image::Rgb(WHITE)),
            min,
            px_per_m,
            top: 0,
            map_h: h,
        })
    }

    /// Width and height of the map, without the bands.
    pub fn map_size(&self) -> (u32, u32) {
        (self.img.width(), self.map_h)
    }

    /// Rows above the map (0 until bands are added).
    pub fn map_top(&self) -> u32 {
        self.top
    }

    /// Adds white bands of `top` rows above the map and `bottom` below it,
    /// so furniture drawn there hides nothing of the map.
    pub(super) fn add_bands(&mut self, top: u32, bottom: u32) {
        let (w, h) = self.img.dimensions();
        let mut img = RgbImage::from_pixel(w, h + top + bottom, image::Rgb(WHITE));
        image::imageops::replace(&mut img, &self.img, 0, i64::from(top));
        self.img = img;
        self.top += top;
    }

    /// Pixels per metre.
    pub fn scale(&self) -> f64 {
        self.px_per_m
    }

    /// Width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        self.img.dimensions()
    }

    /// The pixel (column, row, as reals) of a point of the plane.
    pub fn to_px(&self, p: [f64; 2]) -> [f64; 2] {
        let bottom = f64::from(self.top + self.map_h);
        [
            (p[0] - self.min[0]) * self.px_per_m,
            bottom - (p[1] - self.min[1]) * self.px_per_m,
        ]
    }

    /// The colour at pixel (column, row), if inside.
    pub fn pixel(&self, col: u32, row: u32) -> Option<Rgb> {
        (col < self.img.width() && row < self.img.height()).then(|| self.img.get_pixel(col, row).0)
    }

    /// Sets one pixel; outside the picture nothing happens.
    pub(super) fn put(&mut self, col: i64, row: i64, c: Rgb) {
        if col >= 0
            && row >= 0
            && (col as u64) < u64::from(self.img.width())
            && (row as u64) < u64::from(self.img.height())
        {
            self.img.put_pixel(col as u32, row as u32, image::Rgb(c));
        }
    }

    /// A filled square dot of `radius_px` around a point.
    pub fn dot(&mut self, p: [f64; 2], radius_px: i64, c: Rgb) {
        let [x, y] = self.to_px(p);
        if !(x.is_finite() && y.is_finite()) {
            return;
        }
        let (cx, cy) = (x.floor() as i64, y.floor() as i64);
        for dy in -radius_px..=radius_px {
            for dx in -radius_px..=radius_px {
                self.put(cx + dx, cy + dy, c);
            }
        }
    }

    /// A line from `a` to `b`, `width_px` wide.
    pub fn line(&mut self, a: [f64; 2], b: [f64; 2], width_px: i64, c: Rgb) {
        let (pa, pb) = (self.to_px(a), self.to_px(b));
        if !pa.iter().chain(&pb).all(|v| v.is_finite()) {
            return;
        }
        let steps = (pb[0] - pa[0])
            .abs()
            .max((pb[1] - pa[1]).abs())
            .ceil()
            .max(1.0);
        // Lines far outside the picture are clipped by `put`; bound the work.
        let steps = steps.min(1.0e5) as i64;
        let r = (width_px - 1) / 2;
        for i in 0..=steps {
            let t = i as f64 / steps as f64;
            let x = (pa[0] + (pb[0] - pa[0]) * t).floor() as i64;
            let y = (pa[1] + (pb[1] - pa[1]) * t).floor() as i64;
            for dy in -r..=r {
                for dx in -r..=r {
                    self.put(x + dx, y + dy, c);
                }
            }
        }
    }

    /// A polyline; closed rings join the last point to the first.
    pub fn polyline(&mut self, pts: &[[f64; 2]], closed: bool, width_px: i64, c: Rgb) {
        for w in pts.windows(2) {
            self.line(w[0], w[1], width_px, c);
        }
        if closed && pts.len() > 2 {
            self.line(pts[pts.len() - 1], pts[0], width_px, c);
        }
    }

    /// Fills a polygon (even–odd rule over all `rings`, so holes stay open),
    /// blending `c` over what is there by `alpha` (0..=1).
    pub fn fill(&mut self, rings: &[&[[f64; 2]]], c: Rgb, alpha: f64) {
        let px: Vec<Vec<[f64; 2]>> = rings
            .iter()
            .map(|r| r.iter().map(|&p| self.to_px(p)).collect())
            .collect();
        let (lo, hi) = px
            .iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[1]), hi.max(p[1]))
            });
        if !(lo.is_finite() && hi.is_finite()) {
            return;
        }
        let a = alpha.clamp(0.0, 1.0);
        let row0 = lo.floor().max(0.0) as u32;
        let row1 = (hi.ceil().min(f64::from(self.img.height()))) as u32;
        let mut xs = Vec::new();
        for row in row0..row1 {
            let y = f64::from(row) + 0.5;
            xs.clear();
            for ring in &px {
                for i in 0..ring.len() {
                    let (p, q) = (ring[i], ring[(i + 1) % ring.len()]);
                    if (p[1] <= y) != (q[1] <= y) {
                        xs.push(p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]));
                    }
                }
            }
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                let c0 = pair[0].round().max(0.0) as u32;
                let c1 = (pair[1].round().min(f64::from(self.img.width()))) as u32;
                for col in c0..c1 {
                    let old = self.img.get_pixel(col, row).0;
                    let mix =
                        |o: u8, n: u8| (f64::from(o) * (1.0 - a) + f64::from(n) * a).round() as u8;
                    self.img.put_pixel(
                        col,
                        row,
                        image::Rgb([mix(old[0], c[0]), mix(old[1], c[1]), mix(old[2], c[2])]),
                    );
                }
            }
        }
    }

    /// Writes the picture as PNG (atomically: a failure leaves an earlier
    /// picture at `path` as it was).
    pub fn save(&self, path: &Path) -> Result<(), PlotError> {
        let failed = |source| PlotError::Write {
            path: path.display().to_string(),
            source,
        };
        crate::file::write_with(path, |f| {
            let mut w = std::io::BufWriter::new(f);
            self.img
                .write_to(&mut w, image::ImageFormat::Png)
                .map_err(failed)?;
            std::io::Write::flush(&mut w)
                .map_err(|e| PlotError::File(crate::file::FileError::new(path, e)))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_corners_north_up() {
        let c = Canvas::new([0.0, 0.0], [100.0, 50.0], 0.0, 200).unwrap();
        assert_eq!(c.size(), (200, 100));
        assert_eq!(c.to_px([0.0, 0.0]), [0.0, 100.0]);
        assert_eq!(c.to_px([100.0, 50.0]), [200.0, 0.0]);
    }

    #[test]
    fn fill_keeps_holes_open() {
        let mut c = Canvas::new([0.0, 0.0], [10.0, 10.0], 0.0, 100).unwrap();
        let outer = [[1.0, 1.0], [9.0, 1.0], [9.0, 9.0], [1.0, 9.0]];
        let hole = [[4.0, 4.0], [6.0, 4.0], [6.0, 6.0], [4.0, 6.0]];
        c.fill(&[&outer, &hole], [255, 0, 0], 1.0);
        assert_eq!(c.pixel(20, 80), Some([255, 0, 0]));
        assert_eq!(c.pixel(50, 50), Some(WHITE));
        assert_eq!(c.pixel(5, 5), Some(WHITE));
    }

    #[test]
    fn empty_area_is_an_error() {
        assert!(Canvas::new([0.0, 0.0], [0.0, 5.0], 1.0, 100).is_err());
        assert!(Canvas::new([0.0, f64::NAN], [1.0, 5.0], 1.0, 100).is_err());
    }

    #[test]
    fn lines_and_dots_land_where_expected() {
        let mut c = Canvas::new([0.0, 0.0], [10.0, 10.0], 0.0, 100).unwrap();
        c.line([0.0, 5.0], [10.0, 5.0], 1, [0, 0, 255]);
        assert_eq!(c.pixel(50, 50), Some([0, 0, 255]));
        c.dot([2.0, 2.0], 1, [0, 255, 0]);
        assert_eq!(c.pixel(20, 80), Some([0, 255, 0]));
        // Far outside: clipped, no panic.
        c.line([-1e9, -1e9], [1e9, 1e9], 3, [1, 2, 3]);
    }
}
