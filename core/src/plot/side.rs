//! A mission seen from the south: the prior's skyline (its highest point
//! per column of x), the ground robot's route and the drone's flight in
//! x and height, so a flight's heights read at a glance.

use super::canvas::{Canvas, PlotError};
use super::color::{FLIGHT, GREY, ROUTE, Rgb};
use crate::crs::LinearUnit;

/// Width of a skyline column, m.
const COLUMN_M: f64 = 0.5;

/// The mission from the south (x to the right, height up): the skyline of
/// `prior` grey, the route driven and the drone's flight as lines; legend
/// and a scale bar in `unit`, no north arrow (the legend says the view looks north).
pub fn side_picture(
    prior: &[[f32; 3]],
    route: &[[f32; 3]],
    flight: &[[f32; 3]],
    max_px: u32,
    unit: &LinearUnit,
) -> Result<Canvas, PlotError> {
    let finite = |p: &&[f32; 3]| p.iter().all(|v| v.is_finite());
    let all = || prior.iter().chain(route).chain(flight).filter(finite);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in all() {
        for (k, a) in [0, 2].into_iter().enumerate() {
            lo[k] = lo[k].min(f64::from(p[a]));
            hi[k] = hi[k].max(f64::from(p[a]));
        }
    }
    let mut c = Canvas::new(lo, hi, 2.0, max_px)?;
    let columns = ((hi[0] - lo[0]) / COLUMN_M).ceil() as usize + 1;
    let mut top = vec![f64::NEG_INFINITY; columns];
    for p in prior.iter().filter(finite) {
        let i = ((f64::from(p[0]) - lo[0]) / COLUMN_M) as usize;
        top[i.min(columns - 1)] = top[i.min(columns - 1)].max(f64::from(p[2]));
    }
    for (i, &t) in top.iter().enumerate().filter(|(_, t)| t.is_finite()) {
        let x0 = lo[0] + i as f64 * COLUMN_M;
        let ring = [
            [x0, lo[1]],
            [x0 + COLUMN_M, lo[1]],
            [x0 + COLUMN_M, t],
            [x0, t],
        ];
        c.fill(&[&ring], GREY, 1.0);
    }
    let draw = |c: &mut Canvas, line: &[[f32; 3]], colour: Rgb| {
        for w in line.windows(2) {
            let xz = |p: [f32; 3]| [f64::from(p[0]), f64::from(p[2])];
            c.line(xz(w[0]), xz(w[1]), 2, colour);
        }
    };
    draw(&mut c, route, ROUTE);
    draw(&mut c, flight, FLIGHT);
    let mut legend = vec![
        (GREY, "prior's skyline, looking north"),
        (ROUTE, "route driven"),
    ];
    if !flight.is_empty() {
        legend.push((FLIGHT, "drone flown"));
    }
    c.furnish_view(&legend, unit, false);
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flight_over_a_block_is_drawn_above_its_skyline() {
        // A 10 m block at x 20–30, a flight at 15 m over it.
        let block: Vec<[f32; 3]> = (0..=20)
            .flat_map(|i| (0..=20).map(move |k| [20.0 + i as f32 * 0.5, 0.0, k as f32 * 0.5]))
            .collect();
        let ground: Vec<[f32; 3]> = (0..=100).map(|i| [i as f32 * 0.5, 0.0, 0.0]).collect();
        let prior: Vec<[f32; 3]> = block.into_iter().chain(ground).collect();
        let flight = [[5.0, 0.0, 1.0], [5.0, 0.0, 15.0], [45.0, 0.0, 15.0]];
        let route = [[2.0, 0.0, 0.5], [48.0, 0.0, 0.5]];
        let c = side_picture(&prior, &route, &flight, 500, &LinearUnit::Metre).expect("drawn");
        let at = |x: f64, z: f64| {
            let p = c.to_px([x, z]);
            c.pixel(p[0] as u32, p[1] as u32)
        };
        assert_eq!(at(25.0, 5.0), Some(GREY), "inside the block's skyline");
        assert_eq!(at(10.0, 5.0), Some([255, 255, 255]), "open sky beside it");
        assert_eq!(at(25.0, 15.0), Some(FLIGHT), "the flight over the block");
        let (w, h) = c.size();
        assert!(w > h, "a side view is wide: {w} x {h}");
        assert!(
            side_picture(&[], &[], &[], 500, &LinearUnit::Metre).is_err(),
            "nothing to draw"
        );
    }
}
