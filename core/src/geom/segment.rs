//! A point against a segment in the plane: where it projects and how far it is.

use geo::{Distance, Euclidean, Line, Point};

/// The parameter `t ∈ [0, 1]` of the point of segment `a → b` nearest `p`
/// (0 for a segment of zero length).
pub fn project(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The point of segment `a → b` nearest `p`, with its parameter `t`.
pub fn closest(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> ([f64; 2], f64) {
    let t = project(p, a, b);
    ([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])], t)
}

/// Euclidean distance from `p` to segment `a → b`.
pub fn distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    Euclidean.distance(&Line::new(a, b), &Point::from(p))
}

/// Distance from `p` to the nearest edge of the closed ring `ring`
/// (infinite for an empty ring).
pub fn ring_distance(p: [f64; 2], ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|k| distance(p, ring[k], ring[(k + 1) % n]))
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_middle_and_degenerate() {
        let (a, b) = ([0.0, 0.0], [4.0, 0.0]);
        assert_eq!(distance([2.0, 3.0], a, b), 3.0);
        assert_eq!(distance([7.0, 4.0], a, b), 5.0);
        assert_eq!(closest([1.0, -2.0], a, b), ([1.0, 0.0], 0.25));
        assert_eq!(project([-3.0, 1.0], a, b), 0.0);
        assert_eq!(distance([3.0, 4.0], a, a), 5.0);
        assert_eq!(closest([3.0, 4.0], a, a), (a, 0.0));
        let sq = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert_eq!(ring_distance([1.0, 1.5], &sq), 0.5);
        assert_eq!(ring_distance([1.0, 1.0], &[]), f64::INFINITY);
    }
}
