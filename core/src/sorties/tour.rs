//! The drone's legs and sorties: a leg is the straight line when the
//! airspace allows it, else level first then across, else over everything
//! at a transit height; the viewpoints are toured from home (TSP) and the
//! tour is cut into sorties that each come home within the battery.

use serde::{Deserialize, Serialize};

use crate::airspace::Airspace;
use crate::route::tour::{Costs, tsp};
use crate::vehicle::multirotor::MultirotorConfig;

/// The transit height clears the highest top by this much beyond the
/// distance kept from buildings, m.
const TRANSIT_EXTRA_M: f32 = 2.0;
/// 2-opt / Or-opt passes of the viewpoint tour.
const TSP_PASSES: u32 = 20;

/// One flight from home back home.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sortie {
    /// Way-points from take-off to landing (body centre), home first and last.
    pub path: Vec<[f32; 3]>,
    /// The viewpoints it visits, as indices into the plan's viewpoints, in order.
    pub viewpoints: Vec<usize>,
    /// Its estimated flight time, s (hovering included).
    pub flight_s: f32,
}

/// A leg from `a` to `b` the airspace allows (way-points after `a`, `b`
/// last) and its flight time, s; `None` when no such leg is found.
pub fn leg(
    airspace: &Airspace,
    cfg: &MultirotorConfig,
    a: [f32; 3],
    b: [f32; 3],
) -> Option<(Vec<[f32; 3]>, f32)> {
    let level = a[2].max(b[2]);
    let transit = airspace.highest_top() + airspace.rules().facade_min_m + TRANSIT_EXTRA_M;
    let tries = [
        vec![b],
        vec![[a[0], a[1], level], [b[0], b[1], level], b],
        vec![[a[0], a[1], transit], [b[0], b[1], transit], b],
    ];
    tries.into_iter().find_map(|ways| {
        let mut path = vec![a];
        path.extend(ways.iter().copied());
        path.dedup();
        airspace.check_path(&path).ok()?;
        let t = path.windows(2).map(|w| segment_s(cfg, w[0], w[1])).sum();
        Some((path[1..].to_vec(), t))
    })
}

/// Flight time of a straight segment at the limits, s (accelerations left out).
fn segment_s(cfg: &MultirotorConfig, a: [f32; 3], b: [f32; 3]) -> f32 {
    let h = (b[0] - a[0]).hypot(b[1] - a[1]) / cfg.max_speed;
    let dz = b[2] - a[2];
    let v = if dz > 0.0 {
        dz / cfg.max_climb
    } else {
        -dz / cfg.max_descent
    };
    h.max(v)
}

/// Sorties visiting `viewpoints` from the airspace's home: one TSP tour
/// (times as costs), cut where the next viewpoint and the way home would
/// exceed a sortie's flight time. Returns the sorties and the viewpoints
/// no sortie can reach (no leg, or too far for one battery).
pub fn sorties(
    airspace: &Airspace,
    cfg: &MultirotorConfig,
    viewpoints: &[[f32; 3]],
    hover_s: f32,
) -> (Vec<Sortie>, Vec<usize>) {
    let home = airspace.home();
    let n = viewpoints.len();
    let time = |a: [f32; 3], b: [f32; 3]| leg(airspace, cfg, a, b).map_or(f32::INFINITY, |l| l.1);
    let costs = Costs {
        start: viewpoints.iter().map(|&v| time(home, v)).collect(),
        between: (0..n * n)
            .map(|k| time(viewpoints[k / n], viewpoints[k % n]))
            .collect(),
    };
    let order = tsp(&costs, TSP_PASSES);
    let budget = cfg.sortie_s();
    let (mut out, mut unreachable) = (Vec::new(), Vec::new());
    let mut cur: Option<Sortie> = None;
    for v in order {
        let out_and_back = costs.start[v] + hover_s + time(viewpoints[v], home);
        if !out_and_back.is_finite() || out_and_back > budget {
            unreachable.push(v);
            continue;
        }
        if let Some(s) = cur.as_mut() {
            let last = *s.path.last().unwrap_or(&home);
            if let Some((ways, t)) = leg(airspace, cfg, last, viewpoints[v])
                && s.flight_s + t + hover_s + time(viewpoints[v], home) <= budget
            {
                s.path.extend(ways);
                s.viewpoints.push(v);
                s.flight_s += t + hover_s;
                continue;
            }
            out.extend(cur.take().map(|s| close(airspace, cfg, s)));
        }
        let Some((ways, t)) = leg(airspace, cfg, home, viewpoints[v]) else {
            unreachable.push(v);
            continue;
        };
        let mut path = vec![home];
        path.extend(ways);
        cur = Some(Sortie {
            path,
            viewpoints: vec![v],
            flight_s: t + hover_s,
        });
    }
    out.extend(cur.map(|s| close(airspace, cfg, s)));
    (out, unreachable)
}

/// The sortie with its way home.
fn close(airspace: &Airspace, cfg: &MultirotorConfig, mut s: Sortie) -> Sortie {
    let last = *s.path.last().unwrap_or(&airspace.home());
    if let Some((ways, t)) = leg(airspace, cfg, last, airspace.home()) {
        s.path.extend(ways);
        s.flight_s += t;
    }
    s
}
