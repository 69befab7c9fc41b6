//! Point-in-polygon for region outlines.

/// Even-odd test of `p` against the ring `poly` (open or closed, any orientation).
pub fn contains(poly: &[[f64; 2]], p: [f64; 2]) -> bool {
    let n = poly.len();
    if n < 3 {
        return false;
    }
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if p[0] < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::contains;

    #[test]
    fn square_and_l_shape() {
        let sq = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert!(contains(&sq, [1.0, 1.0]));
        assert!(!contains(&sq, [3.0, 1.0]));
        let l = [
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 1.0],
            [1.0, 1.0],
            [1.0, 4.0],
            [0.0, 4.0],
        ];
        assert!(contains(&l, [0.5, 3.0]));
        assert!(!contains(&l, [3.0, 3.0]));
        assert!(!contains(&sq[..2], [1.0, 0.0]));
    }
}
