//! Eigen-decomposition of a symmetric 3×3 matrix (a covariance) by nalgebra.

use nalgebra::Matrix3;

/// Eigenvalues of the symmetric `a` in descending order (clamped ≥ 0, as a
/// covariance's are) and the unit eigenvector of the smallest (a
/// neighbourhood's normal; its sign is arbitrary).
pub fn sym3_eigen(a: [[f64; 3]; 3]) -> ([f64; 3], [f64; 3]) {
    let m = Matrix3::from_fn(|i, j| a[i][j]);
    let e = m.symmetric_eigen();
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&i, &j| e.eigenvalues[j].total_cmp(&e.eigenvalues[i]));
    let vals = idx.map(|i| e.eigenvalues[i].max(0.0));
    let v = e.eigenvectors.column(idx[2]);
    let n = v.norm();
    let normal = if n > 0.0 && n.is_finite() {
        [v[0] / n, v[1] / n, v[2] / n]
    } else {
        [0.0, 0.0, 1.0]
    };
    (vals, normal)
}

#[cfg(test)]
mod tests {
    use super::sym3_eigen;

    #[test]
    fn diagonal_and_rotated() {
        let (l, n) = sym3_eigen([[1.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 2.0]]);
        assert_eq!(l, [3.0, 2.0, 1.0]);
        assert!((n[0].abs() - 1.0).abs() < 1e-12, "{n:?}");
        // Covariance of the plane z = x: smallest axis ∝ (1, 0, −1).
        let (l, n) = sym3_eigen([[1.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 1.0]]);
        assert!((l[0] - 2.0).abs() < 1e-12 && (l[1] - 1.0).abs() < 1e-12 && l[2].abs() < 1e-12);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        assert!(
            (n[0].abs() - s).abs() < 1e-12 && (n[0] + n[2]).abs() < 1e-12,
            "{n:?}"
        );
        // Repeated eigenvalues (a sphere) still give a unit vector.
        let (l, n) = sym3_eigen([[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]]);
        assert_eq!(l, [2.0; 3]);
        assert!((n.iter().map(|v| v * v).sum::<f64>() - 1.0).abs() < 1e-12);
    }
}
