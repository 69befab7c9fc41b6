//! The drone's legs and sorties: a leg is the straight line when the
//! airspace allows it, else level first then across, else over everything
//! at a transit height; the viewpoints are toured from home (TSP) and the
//! tour is cut into sorties that each come home within the battery.

use serde::{Deserialize, Serialize};

use crate::airspace::{Airspace, Refusal};
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
    tries(airspace, a, b).into_iter().find_map(|path| {
        airspace.check_path(&path).ok()?;
        let t = path.windows(2).map(|w| segment_s(cfg, w[0], w[1])).sum();
        Some((path[1..].to_vec(), t))
    })
}

/// The polylines a leg from `a` to `b` may take, in the order tried:
/// straight, level first then across, over everything at transit height.
fn tries(airspace: &Airspace, a: [f32; 3], b: [f32; 3]) -> [Vec<[f32; 3]>; 3] {
    let level = a[2].max(b[2]);
    let transit = transit_z(airspace);
    [
        vec![b],
        vec![[a[0], a[1], level], [b[0], b[1], level], b],
        vec![[a[0], a[1], transit], [b[0], b[1], transit], b],
    ]
    .map(|ways| {
        let mut path = vec![a];
        path.extend(ways);
        path.dedup();
        path
    })
}

/// The height legs over everything fly at: the highest top cleared by the
/// distance kept from buildings and a little more.
fn transit_z(airspace: &Airspace) -> f32 {
    airspace.highest_top() + airspace.rules().facade_min_m + TRANSIT_EXTRA_M
}

/// `Ok` when the drone may climb from its home straight up to the transit
/// height (every leg over everything starts so), else the rule it breaks.
pub fn take_off(airspace: &Airspace) -> Result<(), Refusal> {
    let home = airspace.home();
    airspace.check_path(&[home, [home[0], home[1], transit_z(airspace)]])
}

/// Why no sortie reaches `viewpoint` from the airspace's home: the rule
/// the way over everything breaks out or back, or the battery.
pub fn why_unreachable(
    airspace: &Airspace,
    cfg: &MultirotorConfig,
    viewpoint: [f32; 3],
    hover_s: f32,
) -> String {
    let home = airspace.home();
    let at = |p: [f32; 3]| format!("({:.1}, {:.1}, {:.1})", p[0], p[1], p[2]);
    let refused = |a, b| {
        let [.., over] = tries(airspace, a, b);
        airspace.check_path(&over).err()
    };
    if let Some(r) = refused(home, viewpoint) {
        return format!(
            "from home {} to {}, even over everything: {r}",
            at(home),
            at(viewpoint)
        );
    }
    if let Some(r) = refused(viewpoint, home) {
        return format!(
            "from {} back home, even over everything: {r}",
            at(viewpoint)
        );
    }
    let there = leg(airspace, cfg, home, viewpoint).map_or(f32::INFINITY, |l| l.1);
    let back = leg(airspace, cfg, viewpoint, home).map_or(f32::INFINITY, |l| l.1);
    format!(
        "{} out and back takes {:.0} s, over a sortie's {:.0} s",
        at(viewpoint),
        there + hover_s + back,
        cfg.sortie_s()
    )
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

/// Every leg a tour may take, found once: from home to each viewpoint,
/// back, and between every two (`None`: no leg the airspace allows).
struct Legs {
    out: Vec<Option<(Vec<[f32; 3]>, f32)>>,
    back: Vec<Option<(Vec<[f32; 3]>, f32)>>,
    between: Vec<Option<(Vec<[f32; 3]>, f32)>>,
}

impl Legs {
    fn new(airspace: &Airspace, cfg: &MultirotorConfig, viewpoints: &[[f32; 3]]) -> Self {
        let (home, n) = (airspace.home(), viewpoints.len());
        let leg = |a, b| leg(airspace, cfg, a, b);
        Self {
            out: viewpoints.iter().map(|&v| leg(home, v)).collect(),
            back: viewpoints.iter().map(|&v| leg(v, home)).collect(),
            between: (0..n * n)
                .map(|k| leg(viewpoints[k / n], viewpoints[k % n]))
                .collect(),
        }
    }

    /// The leg from `a` (`None`: home) to viewpoint `b`.
    fn to(&self, a: Option<usize>, b: usize) -> Option<&(Vec<[f32; 3]>, f32)> {
        match a {
            None => self.out[b].as_ref(),
            Some(a) => self.between[a * self.out.len() + b].as_ref(),
        }
    }

    /// Flight time of that leg, s (infinite without one).
    fn time(&self, a: Option<usize>, b: usize) -> f32 {
        self.to(a, b).map_or(f32::INFINITY, |l| l.1)
    }

    /// Flight time from viewpoint `v` home, s (infinite without a leg).
    fn home_time(&self, v: usize) -> f32 {
        self.back[v].as_ref().map_or(f32::INFINITY, |l| l.1)
    }
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
    let legs = Legs::new(airspace, cfg, viewpoints);
    let costs = Costs {
        start: (0..n).map(|v| legs.time(None, v)).collect(),
        between: (0..n * n).map(|k| legs.time(Some(k / n), k % n)).collect(),
    };
    let budget = cfg.sortie_s();
    let (mut out, mut unreachable) = (Vec::new(), Vec::new());
    // The sortie being flown and the last viewpoint it visits.
    let mut cur: Option<(Sortie, usize)> = None;
    for v in tsp(&costs, TSP_PASSES) {
        let out_and_back = legs.time(None, v) + hover_s + legs.home_time(v);
        if !out_and_back.is_finite() || out_and_back > budget {
            unreachable.push(v);
            continue;
        }
        if let Some((s, last)) = cur.as_mut() {
            if let Some((ways, t)) = legs.to(Some(*last), v)
                && s.flight_s + t + hover_s + legs.home_time(v) <= budget
            {
                s.path.extend(ways);
                s.viewpoints.push(v);
                s.flight_s += t + hover_s;
                *last = v;
                continue;
            }
            out.extend(cur.take().map(|(s, last)| close(&legs, s, last)));
        }
        // Reachable out and back (checked above), so the leg out exists.
        let Some((ways, t)) = legs.to(None, v) else {
            continue;
        };
        let mut path = vec![home];
        path.extend(ways);
        let s = Sortie {
            path,
            viewpoints: vec![v],
            flight_s: t + hover_s,
        };
        cur = Some((s, v));
    }
    out.extend(cur.map(|(s, last)| close(&legs, s, last)));
    (out, unreachable)
}

/// The sortie with its way home from its `last` viewpoint.
fn close(legs: &Legs, mut s: Sortie, last: usize) -> Sortie {
    if let Some((ways, t)) = &legs.back[last] {
        s.path.extend(ways);
        s.flight_s += t;
    }
    s
}
