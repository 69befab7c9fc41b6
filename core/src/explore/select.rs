//! Choosing viewpoints: greedy set cover of the uncovered samples, with
//! randomized restarts that pick among the near-best instead of the best.

use crate::rng::Rng;
use crate::route::tour::{Costs, tsp};

/// What the selection works on.
pub struct Problem<'a> {
    /// Per candidate, the open samples it sees.
    pub sees: &'a [Vec<u32>],
    /// Per candidate, whether it may still be chosen.
    pub allowed: &'a [bool],
    /// Per candidate, its position (xy is what the tour measures).
    pub position: &'a [[f32; 3]],
    /// Number of samples.
    pub samples: usize,
    /// Candidates adding fewer new samples are not chosen.
    pub min_gain: u32,
}

/// How good a selection is: fewer viewpoints, then more covered, then a shorter tour.
struct Score {
    count: usize,
    covered: usize,
    length: f32,
}

impl Score {
    fn better_than(&self, o: &Score) -> bool {
        (self.count, std::cmp::Reverse(self.covered)) < (o.count, std::cmp::Reverse(o.covered))
            || (self.count == o.count && self.covered == o.covered && self.length < o.length)
    }
}

/// The best of `1 + restarts` greedy covers: fewest viewpoints, then most
/// samples covered, then the shortest tour from `from`. Returns the chosen
/// candidates in tour order.
pub fn select(p: &Problem<'_>, from: [f32; 3], restarts: u32, seed: u64) -> Vec<usize> {
    let mut rng = Rng::from_state(seed);
    // Best so far: (viewpoints, samples covered, tour length) and the tour.
    let mut best: Option<(Score, Vec<usize>)> = None;
    for run in 0..=restarts {
        let (chosen, covered) = greedy(p, if run == 0 { None } else { Some(&mut rng) });
        let order = order_tour(p.position, &chosen, from);
        let len = tour_length(p.position, &order, from);
        let key = Score {
            count: chosen.len(),
            covered,
            length: len,
        };
        if best.as_ref().is_none_or(|(k, _)| key.better_than(k)) {
            best = Some((key, order));
        }
    }
    best.map(|(_, o)| o).unwrap_or_default()
}

/// One greedy cover; with `rng`, each step takes a random one of the
/// candidates within 80 % of the best gain.
fn greedy(p: &Problem<'_>, mut rng: Option<&mut Rng>) -> (Vec<usize>, usize) {
    let mut covered = vec![false; p.samples];
    let mut used = vec![false; p.sees.len()];
    let mut chosen = Vec::new();
    let mut total = 0usize;
    loop {
        crate::work::step();
        let gains: Vec<u32> = p
            .sees
            .iter()
            .enumerate()
            .map(|(c, s)| {
                if used[c] || !p.allowed[c] {
                    0
                } else {
                    s.iter().filter(|&&i| !covered[i as usize]).count() as u32
                }
            })
            .collect();
        let best = gains.iter().copied().max().unwrap_or(0);
        if best < p.min_gain.max(1) {
            break;
        }
        let pick = match rng.as_deref_mut() {
            Some(r) => {
                let near: Vec<usize> = (0..gains.len())
                    .filter(|&c| gains[c] * 5 >= best * 4)
                    .collect();
                near[(r.next_u64() % near.len() as u64) as usize]
            }
            None => (0..gains.len())
                .max_by_key(|&c| (gains[c], std::cmp::Reverse(c)))
                .unwrap_or(0),
        };
        used[pick] = true;
        chosen.push(pick);
        for &i in &p.sees[pick] {
            if !covered[i as usize] {
                covered[i as usize] = true;
                total += 1;
            }
        }
    }
    (chosen, total)
}

fn dxy(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// Orders `chosen` by a small open TSP from `from` (straight-line distances).
pub fn order_tour(position: &[[f32; 3]], chosen: &[usize], from: [f32; 3]) -> Vec<usize> {
    let n = chosen.len();
    let costs = Costs {
        start: chosen.iter().map(|&c| dxy(from, position[c])).collect(),
        between: (0..n * n)
            .map(|k| dxy(position[chosen[k / n]], position[chosen[k % n]]))
            .collect(),
    };
    tsp(&costs, 50).into_iter().map(|k| chosen[k]).collect()
}

/// Straight-line length of visiting `order` from `from`.
fn tour_length(position: &[[f32; 3]], order: &[usize], from: [f32; 3]) -> f32 {
    let mut at = from;
    let mut len = 0.0;
    for &c in order {
        len += dxy(at, position[c]);
        at = position[c];
    }
    len
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cover_uses_few_viewpoints() {
        // Candidate 3 sees everything the first three see together.
        let sees = vec![
            vec![0, 1],
            vec![2, 3],
            vec![4, 5],
            vec![0, 1, 2, 3, 4, 5],
            vec![6],
        ];
        let pos = vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [3.0, 0.0, 0.0],
            [9.0, 0.0, 0.0],
        ];
        let allowed = vec![true; 5];
        let p = Problem {
            sees: &sees,
            allowed: &allowed,
            position: &pos,
            samples: 7,
            min_gain: 1,
        };
        assert_eq!(select(&p, [0.0; 3], 4, 7), vec![3, 4]);
        let p2 = Problem { min_gain: 2, ..p };
        assert_eq!(select(&p2, [0.0; 3], 4, 7), vec![3]);
        let none = vec![false; 5];
        let p3 = Problem {
            allowed: &none,
            ..p2
        };
        assert!(select(&p3, [0.0; 3], 4, 7).is_empty());
    }
}
