//! Moving an outline inward by a fixed distance with mitred corners (a
//! negative buffer), used to undo the outward bias of raster outlines.

use geo::algorithm::buffer::{BufferStyle, LineJoin};
use geo::{Buffer, MultiPolygon};

/// `mp` shrunk by `d` metres (≤ 0: unchanged); parts thinner than `2d` vanish.
pub fn inset(mp: &MultiPolygon<f64>, d: f64) -> MultiPolygon<f64> {
    if d <= 0.0 {
        return mp.clone();
    }
    mp.buffer_with_style(BufferStyle::new(-d).line_join(LineJoin::Miter(2.0)))
}
