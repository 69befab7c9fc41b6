//! Drone viewpoints: candidates at standoff along each gap's normal, kept
//! where the airspace allows them, then the fewest (greedily) that see
//! every gap some candidate sees.

use std::collections::HashMap;

use super::params::SortieParams;
use crate::airspace::Airspace;
use crate::missing::MissingPoint;

/// A sight line ends this far before its gap (the gap's own wall).
const OWN_WALL_M: f32 = 0.75;

/// Whether a sensor at `sensor` sees the gap `m`: in range, in front of its
/// wall, inside the field of view, and over every column between.
pub fn sees(airspace: &Airspace, sensor: [f32; 3], m: &MissingPoint, p: &SortieParams) -> bool {
    let v = [
        sensor[0] - m.xyz[0],
        sensor[1] - m.xyz[1],
        sensor[2] - m.xyz[2],
    ];
    let h = v[0].hypot(v[1]);
    let d = (h * h + v[2] * v[2]).sqrt();
    if !(d > 0.5 && d <= p.range_m) || h < 1e-3 {
        return false;
    }
    let facing = (v[0] * m.normal[0] + v[1] * m.normal[1]) / h;
    if facing < p.max_incidence_deg.to_radians().cos() {
        return false;
    }
    // The gap's elevation seen from the sensor.
    let elevation = (-v[2]).atan2(h).to_degrees();
    if elevation > p.fov_up_deg || elevation < -p.fov_down_deg {
        return false;
    }
    airspace.line_of_sight(sensor, m.xyz, OWN_WALL_M)
}

/// The candidate viewpoints (body centre) for `missing`: every standoff ×
/// rise along each gap's normal that the airspace allows, thinned.
pub fn candidates(
    missing: &[MissingPoint],
    airspace: &Airspace,
    p: &SortieParams,
) -> Vec<[f32; 3]> {
    let mut kept: HashMap<[i64; 3], [f32; 3]> = HashMap::new();
    let key = |q: [f32; 3]| q.map(|v| (v / p.thin_m.max(1e-3)).floor() as i64);
    for m in missing {
        for &s in &p.standoffs_m {
            for &r in &p.rises_m {
                let q = [
                    m.xyz[0] + s * m.normal[0],
                    m.xyz[1] + s * m.normal[1],
                    m.xyz[2] + r,
                ];
                if !kept.contains_key(&key(q)) && airspace.check(q).is_ok() {
                    kept.insert(key(q), q);
                }
            }
        }
    }
    let mut out: Vec<[f32; 3]> = kept.into_values().collect();
    // HashMap order is not stable: sort so the same input gives the same plan.
    out.sort_by(|a, b| {
        a.iter()
            .zip(b)
            .map(|(x, y)| x.total_cmp(y))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    out
}

/// The fewest candidates (greedily) that see every gap any of them sees,
/// with `sensor_drop` from body to sensor; returns the kept candidates'
/// indices and, per gap, whether a kept one sees it.
pub fn cover(
    cands: &[[f32; 3]],
    missing: &[MissingPoint],
    airspace: &Airspace,
    p: &SortieParams,
    sensor_drop: f32,
) -> (Vec<usize>, Vec<bool>) {
    use rayon::prelude::*;
    let sets: Vec<Vec<usize>> = cands
        .par_iter()
        .map(|c| {
            let sensor = [c[0], c[1], c[2] - sensor_drop];
            (0..missing.len())
                .filter(|&k| sees(airspace, sensor, &missing[k], p))
                .collect()
        })
        .collect();
    let mut seen = vec![false; missing.len()];
    let mut gain: Vec<usize> = sets.iter().map(Vec::len).collect();
    let mut kept = Vec::new();
    while let Some((best, _)) = gain
        .iter()
        .enumerate()
        .filter(|(_, g)| **g > 0)
        .max_by_key(|(i, g)| (**g, std::cmp::Reverse(*i)))
    {
        kept.push(best);
        for &k in &sets[best] {
            seen[k] = true;
        }
        for (i, set) in sets.iter().enumerate() {
            gain[i] = set.iter().filter(|&&k| !seen[k]).count();
        }
    }
    (kept, seen)
}
