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

/// Gains below this are rounding, not improvement.
const EPS: f32 = 1.0e-4;

/// One pass of segment reversals; true when the tour got shorter.
fn two_opt(costs: &Costs, order: &mut [usize]) -> bool {
    let n = order.len();
    let mut improved = false;
    for i in 0..n {
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
/// true when the tour got shorter.
fn or_opt(costs: &Costs, order: &mut Vec<usize>) -> bool {
    let mut improved = false;
    for len in 1..=3usize {
        let mut i = 0;
        while i + len <= order.len() {
            let base = costs.tour_cost(order);
            let seg: Vec<usize> = order[i..i + len].to_vec();
            let mut rest: Vec<usize> = order[..i].to_vec();
            rest.extend_from_slice(&order[i + len..]);
            let mut best: Option<(f32, Vec<usize>)> = None;
            for pos in 0..=rest.len() {
                if pos == i {
                    continue;
                }
                for rev in [false, true] {
                    let mut cand = rest[..pos].to_vec();
                    if rev {
                        cand.extend(seg.iter().rev());
                    } else {
                        cand.extend_from_slice(&seg);
                    }
                    cand.extend_from_slice(&rest[pos..]);
                    let c = costs.tour_cost(&cand);
                    if c < base - EPS && best.as_ref().is_none_or(|(b, _)| c < *b) {
                        best = Some((c, cand));
                    }
                }
            }
            if let Some((_, cand)) = best {
                *order = cand;
                improved = true;
            }
            i += 1;
        }
    }
    improved
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
}
