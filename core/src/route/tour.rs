//! Open tours over a symmetric cost matrix from a fixed start: the paper's
//! greedy alternation and nearest neighbour + 2-opt + Or-opt.

/// Costs between stops and from the start; infinite where there is no way.
#[derive(Debug, Clone)]
pub struct Costs {
    /// Cost from the start to each stop.
    pub start: Vec<f32>,
    /// Row-major `n × n` costs between stops.
    pub between: Vec<f32>,
}

impl Costs {
    /// Number of stops.
    pub fn len(&self) -> usize {
        self.start.len()
    }

    /// Cost from `a` (`None`: the start) to stop `b`.
    pub fn cost(&self, a: Option<usize>, b: usize) -> f32 {
        match a {
            None => self.start[b],
            Some(a) => self.between[a * self.len() + b],
        }
    }

    /// Total cost of visiting `order` from the start (open: no way back).
    #[cfg(test)]
    pub fn tour_cost(&self, order: &[usize]) -> f32 {
        let mut prev = None;
        let mut sum = 0.0;
        for &s in order {
            sum += self.cost(prev, s);
            prev = Some(s);
        }
        sum
    }
}

/// The paper's tour: from where it stands, go to the nearest remaining stop
/// of the other kind than the last (`is_region[i]` tells the kinds), or of
/// the same kind when none of the other is left.
pub fn greedy_alternating(costs: &Costs, is_region: &[bool]) -> Vec<usize> {
    let n = costs.len();
    let mut left = vec![true; n];
    let mut order = Vec::with_capacity(n);
    let mut prev: Option<usize> = None;
    while order.len() < n {
        let want = prev.map(|p| !is_region[p]);
        let pick = |kind: Option<bool>| {
            (0..n)
                .filter(|&i| left[i] && kind.is_none_or(|k| is_region[i] == k))
                .min_by(|&a, &b| costs.cost(prev, a).total_cmp(&costs.cost(prev, b)))
        };
        let Some(next) = pick(want).or_else(|| pick(None)) else {
            break;
        };
        left[next] = false;
        order.push(next);
        prev = Some(next);
    }
    order
}

/// Nearest neighbour from the start, then 2-opt and Or-opt passes until no
/// move shortens the tour (or `max_passes`).
pub fn tsp(costs: &Costs, max_passes: u32) -> Vec<usize> {
    let n = costs.len();
    let mut left = vec![true; n];
    let mut order = Vec::with_capacity(n);
    let mut prev = None;
    for _ in 0..n {
        crate::work::step();
        let Some(next) = (0..n)
            .filter(|&i| left[i])
            .min_by(|&a, &b| costs.cost(prev, a).total_cmp(&costs.cost(prev, b)))
        else {
            break;
        };
        left[next] = false;
        order.push(next);
        prev = Some(next);
    }
    for _ in 0..max_passes {
        let a = two_opt(costs, &mut order);
        let b = or_opt(costs, &mut order);
        if !(a || b) {
            break;
        }
    }
    order
}

/// Two stops lie on one street when the way between them is at most this
/// much longer than the straight line (no turn round a block)...
const STREET_DETOUR: f32 = 1.15;
/// ...and at most this long, metres (a street's stops are a few buildings apart).
const STREET_LINK_M: f32 = 30.0;
/// What leaving a street with stops still on it costs the street tour, metres:
/// each change is a turn and often a way back later.
const STREET_CHANGE_M: f32 = 20.0;

/// Streets: stops joined (transitively) where the way between them is
/// short and nearly straight, i.e. runs along one corridor of the ground
/// graph; `xy` are the stops' positions. Returns a street id per stop.
pub fn street_ids(costs: &Costs, xy: &[[f32; 2]]) -> Vec<usize> {
    let n = costs.len();
    let mut uf = petgraph::unionfind::UnionFind::<usize>::new(n);
    for a in 0..n {
        for b in a + 1..n {
            let way = costs.cost(Some(a), b);
            let line = (xy[a][0] - xy[b][0]).hypot(xy[a][1] - xy[b][1]);
            if way <= STREET_LINK_M && way <= STREET_DETOUR * line + 1.0 {
                uf.union(a, b);
            }
        }
    }
    uf.into_labeling()
}

/// The street-by-street tour: the 2-opt/Or-opt tour on costs where every
/// change of street ([`street_ids`]) costs [`STREET_CHANGE_M`] more, so a
/// street is worked to its end before the next one instead of criss-crossing.
pub fn street_tour(costs: &Costs, xy: &[[f32; 2]], max_passes: u32) -> Vec<usize> {
    let ids = street_ids(costs, xy);
    let n = costs.len();
    let between = (0..n * n)
        .map(|k| {
            let (a, b) = (k / n, k % n);
            let change = if ids[a] != ids[b] {
                STREET_CHANGE_M
            } else {
                0.0
            };
            costs.between[k] + change
        })
        .collect();
    let penalised = Costs {
        start: costs.start.clone(),
        between,
    };
    tsp(&penalised, max_passes)
}

/// Gains below this are rounding, not improvement.
const EPS: f32 = 1.0e-4;

/// One pass of segment reversals; true when the tour got shorter.
fn two_opt(costs: &Costs, order: &mut [usize]) -> bool {
    let n = order.len();
    let mut improved = false;
    for i in 0..n {
        crate::work::step();
        for j in i + 1..n {
            let before = if i == 0 { None } else { Some(order[i - 1]) };
            let old_in = costs.cost(before, order[i]);
            let new_in = costs.cost(before, order[j]);
            let (old_out, new_out) = if j + 1 < n {
                (
                    costs.cost(Some(order[j]), order[j + 1]),
                    costs.cost(Some(order[i]), order[j + 1]),
                )
            } else {
                (0.0, 0.0)
            };
            if new_in + new_out < old_in + old_out - EPS {
                order[i..=j].reverse();
                improved = true;
            }
        }
    }
    improved
}

/// One pass of moving segments of 1–3 stops elsewhere (either way round);
/// true when the tour got shorter. Each move is priced from the edges it
/// changes, so a pass is O(n²).
fn or_opt(costs: &Costs, order: &mut Vec<usize>) -> bool {
    let mut improved = false;
    for len in 1..=3usize {
        let mut i = 0;
        while i + len <= order.len() {
            crate::work::step();
            if let Some((pos, rev)) = best_move(costs, order, i, len) {
                let seg: Vec<usize> = order.drain(i..i + len).collect();
                let at = if pos > i { pos - len } else { pos };
                if rev {
                    order.splice(at..at, seg.into_iter().rev());
                } else {
                    order.splice(at..at, seg);
                }
                improved = true;
            }
            i += 1;
        }
    }
    improved
}

/// The best place (a position in `order`, before which the segment goes,
/// and whether reversed) for `order[i..i + len]`, if it shortens the tour.
fn best_move(costs: &Costs, order: &[usize], i: usize, len: usize) -> Option<(usize, bool)> {
    let n = order.len();
    let seg = &order[i..i + len];
    let (first, last) = (seg[0], seg[len - 1]);
    let before = (i > 0).then(|| order[i - 1]);
    let after = order.get(i + len).copied();
    let inner = |rev: bool| -> f32 {
        let mut sum = 0.0;
        for w in seg.windows(2) {
            let (a, b) = if rev { (w[1], w[0]) } else { (w[0], w[1]) };
            sum += costs.cost(Some(a), b);
        }
        sum
    };
    let inner_fwd = inner(false);
    // Taking the segment out joins `before` to `after`.
    let removed =
        costs.cost(before, first) + inner_fwd + after.map_or(0.0, |q| costs.cost(Some(last), q))
            - after.map_or(0.0, |q| costs.cost(before, q));
    let mut best: Option<(f32, usize, bool)> = None;
    // Insert between order[pos - 1] and order[pos], outside the segment.
    for pos in (0..=n).filter(|&p| p < i || p > i + len) {
        let a = if pos == 0 { None } else { Some(order[pos - 1]) };
        let b = order.get(pos).copied();
        for rev in [false, true] {
            let (h, t) = if rev { (last, first) } else { (first, last) };
            let added = costs.cost(a, h)
                + if rev { inner(true) } else { inner_fwd }
                + b.map_or(0.0, |q| costs.cost(Some(t), q))
                - b.map_or(0.0, |q| costs.cost(a, q));
            let gain = removed - added;
            if gain > EPS && best.is_none_or(|(g, _, _)| gain > g) {
                best = Some((gain, pos, rev));
            }
        }
    }
    // In place, reversed.
    if len > 1 {
        let added = costs.cost(before, last)
            + inner(true)
            + after.map_or(0.0, |q| costs.cost(Some(first), q))
            - after.map_or(0.0, |q| costs.cost(before, q));
        let gain = removed - added;
        if gain > EPS && best.is_none_or(|(g, _, _)| gain > g) {
            best = Some((gain, i, true));
        }
    }
    best.map(|(_, pos, rev)| (pos, rev))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stops on a line at x = 1..=n, start at 0, visited in shuffled order costs more.
    fn line(xs: &[f32]) -> Costs {
        let n = xs.len();
        let mut between = vec![0.0; n * n];
        for a in 0..n {
            for b in 0..n {
                between[a * n + b] = (xs[a] - xs[b]).abs();
            }
        }
        Costs {
            start: xs.iter().map(|x| x.abs()).collect(),
            between,
        }
    }

    #[test]
    fn tsp_finds_the_straight_sweep() {
        let xs = [5.0, -1.0, 3.0, 9.0, 1.0, 7.0, -3.0];
        let c = line(&xs);
        let t = tsp(&c, 50);
        let mut sorted = t.clone();
        sorted.sort();
        assert_eq!(sorted, (0..xs.len()).collect::<Vec<_>>());
        // Optimal open tour: go to -3 first then to 9: 3 + 12 = 15.
        assert!((c.tour_cost(&t) - 15.0).abs() < 1e-4, "{}", c.tour_cost(&t));
    }

    #[test]
    fn greedy_alternates_kinds() {
        let xs = [1.0, 2.0, 3.0, 50.0];
        let c = line(&xs);
        let is_region = [false, false, false, true];
        let g = greedy_alternating(&c, &is_region);
        assert_eq!(g, vec![0, 3, 2, 1]);
        assert!(c.tour_cost(&g) > c.tour_cost(&tsp(&c, 10)));
        assert!(
            tsp(
                &Costs {
                    start: vec![],
                    between: vec![]
                },
                5
            )
            .is_empty()
        );
    }

    /// Two parallel streets 20 m apart (y = 0 and y = 20), stops every
    /// 10 m along x = 10..100, joined only at x = 0 and x = 110; start at
    /// the origin. Ways are along the streets and round through a cross street.
    fn ladder() -> (Costs, Vec<[f32; 2]>) {
        let xy: Vec<[f32; 2]> = (0..2)
            .flat_map(|s| (1..=10).map(move |i| [i as f32 * 10.0, s as f32 * 20.0]))
            .collect();
        let way = |a: [f32; 2], b: [f32; 2]| {
            if a[1] == b[1] {
                (a[0] - b[0]).abs()
            } else {
                (a[0] + b[0]).min(220.0 - a[0] - b[0]) + 20.0
            }
        };
        let n = xy.len();
        let between = (0..n * n).map(|k| way(xy[k / n], xy[k % n])).collect();
        let start = xy.iter().map(|&p| way([0.0, 0.0], p)).collect();
        (Costs { start, between }, xy)
    }

    #[test]
    fn the_street_tour_works_one_street_then_the_next() {
        let (c, xy) = ladder();
        let ids = street_ids(&c, &xy);
        assert!(ids[..10].iter().all(|&i| i == ids[0]));
        assert!(ids[10..].iter().all(|&i| i == ids[10]));
        assert_ne!(ids[0], ids[10]);
        let t = street_tour(&c, &xy, 50);
        let mut sorted = t.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..20).collect::<Vec<_>>());
        let changes = t.windows(2).filter(|w| ids[w[0]] != ids[w[1]]).count();
        assert_eq!(changes, 1, "{t:?}");
        // To x = 10, along y = 0 to x = 100, across at x = 110 (10 + 20 + 10),
        // back along y = 20: 10 + 90 + 40 + 90, the shortest open tour.
        assert!(
            (c.tour_cost(&t) - 230.0).abs() < 1e-3,
            "{}",
            c.tour_cost(&t)
        );
    }

    fn plane(pts: &[(f32, f32)]) -> Costs {
        let n = pts.len();
        let d = |a: (f32, f32), b: (f32, f32)| (a.0 - b.0).hypot(a.1 - b.1);
        let mut between = vec![0.0; n * n];
        for a in 0..n {
            for b in 0..n {
                between[a * n + b] = d(pts[a], pts[b]);
            }
        }
        Costs {
            start: pts.iter().map(|&p| d((0.0, 0.0), p)).collect(),
            between,
        }
    }

    proptest::proptest! {
        // Every Or-opt move is priced from the edges it changes: the tour it
        // leaves must cost what the move promised, never more than before.
        #[test]
        fn or_opt_moves_only_shorten_and_keep_every_stop(
            pts in proptest::collection::vec((-50.0f32..50.0, -50.0f32..50.0), 1..40)
        ) {
            let c = plane(&pts);
            let mut order: Vec<usize> = (0..pts.len()).rev().collect();
            let mut cost = c.tour_cost(&order);
            for _ in 0..20 {
                let improved = or_opt(&c, &mut order);
                let now = c.tour_cost(&order);
                proptest::prop_assert!(now <= cost + 1e-3, "{now} > {cost}");
                if !improved {
                    break;
                }
                cost = now;
            }
            let mut sorted = order.clone();
            sorted.sort_unstable();
            proptest::prop_assert_eq!(sorted, (0..pts.len()).collect::<Vec<_>>());
        }
    }
}
