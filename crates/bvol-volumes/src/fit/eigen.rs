//! Eigen-decomposition of symmetric 3x3 matrices, for the principal axes of
//! covariance matrices.
//!
//! Cyclic Jacobi rotations (Golub & Van Loan, Matrix Computations, 4th ed.,
//! 8.5.2; Numerical Recipes 11.1): each rotation zeroes one off-diagonal entry,
//! and the eigenvectors are the product of the rotations, so they stay
//! orthonormal to rounding whatever the spectrum: repeated eigenvalues
//! (sphere-like clouds), zero ones (flat, collinear or single points) and the
//! zero matrix all give a clean basis, never NaN. Closed-form (cubic root)
//! solvers lose the eigenvectors of nearly equal eigenvalues; Jacobi does not.

use glam::{DMat3, DVec3};

/// A bound on sweeps: Jacobi converges quadratically, and a 3x3 matrix is
/// diagonal to f64 rounding after about 5 of them.
const MAX_SWEEPS: usize = 32;

/// The eigenvalues of a symmetric matrix in decreasing order, and the matching
/// unit eigenvectors as the columns of a right-handed orthonormal matrix.
///
/// Only the upper triangle of `m` is read.
pub(crate) fn symmetric_eigen(m: DMat3) -> (DVec3, DMat3) {
    // Scale to unit size so that squares of entries neither overflow nor vanish.
    let scale =
        [m.x_axis.abs().max_element(), m.y_axis.abs().max_element(), m.z_axis.abs().max_element()]
            .into_iter()
            .fold(0.0, f64::max);
    if !(scale > 0.0 && scale.is_finite()) {
        return (DVec3::ZERO, DMat3::IDENTITY);
    }
    let mut a = [[0.0; 3]; 3];
    for (i, row) in a.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            // Row min(i, j) of column max(i, j): the upper triangle, mirrored.
            *x = m.col(i.max(j))[i.min(j)] / scale;
        }
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..MAX_SWEEPS {
        let mut rotated = false;
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            rotated |= rotate(&mut a, &mut v, p, q);
        }
        if !rotated {
            break;
        }
    }
    sorted(DVec3::new(a[0][0], a[1][1], a[2][2]) * scale, v)
}

/// One Jacobi rotation in the `(p, q)` plane that zeroes `a[p][q]`, applied to
/// `a` on both sides and accumulated into `v`, whose columns become the
/// eigenvectors. Returns whether it
/// rotated: an entry already negligible beside both diagonal entries is set to
/// zero instead (Numerical Recipes' test, which ends the sweeps).
fn rotate(a: &mut [[f64; 3]; 3], v: &mut [[f64; 3]; 3], p: usize, q: usize) -> bool {
    let apq = a[p][q];
    let g = 100.0 * apq.abs();
    if a[p][p].abs() + g == a[p][p].abs() && a[q][q].abs() + g == a[q][q].abs() {
        a[p][q] = 0.0;
        a[q][p] = 0.0;
        return false;
    }
    // tan of the rotation angle, the smaller root of t^2 + 2 theta t - 1 = 0
    // (Golub & Van Loan Algorithm 8.5.1), written to avoid overflow of theta^2.
    let theta = (a[q][q] - a[p][p]) / (2.0 * apq);
    let t = if theta.abs() > 1e150 {
        0.5 / theta
    } else {
        theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
    };
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    for row in a.iter_mut() {
        let (x, y) = (row[p], row[q]);
        row[p] = c * x - s * y;
        row[q] = s * x + c * y;
    }
    let (row_p, row_q) = (a[p], a[q]);
    a[p] = std::array::from_fn(|k| c * row_p[k] - s * row_q[k]);
    a[q] = std::array::from_fn(|k| s * row_p[k] + c * row_q[k]);
    a[p][q] = 0.0;
    a[q][p] = 0.0;
    for row in v.iter_mut() {
        let (x, y) = (row[p], row[q]);
        row[p] = c * x - s * y;
        row[q] = s * x + c * y;
    }
    true
}

/// Eigenpairs sorted by decreasing eigenvalue, the third vector replaced by the
/// cross product of the first two so that the basis is right-handed.
fn sorted(values: DVec3, v: [[f64; 3]; 3]) -> (DVec3, DMat3) {
    let column = |j: usize| DVec3::new(v[0][j], v[1][j], v[2][j]);
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| values[j].total_cmp(&values[i]));
    let (x, y) = (column(order[0]), column(order[1]));
    let values = DVec3::new(values[order[0]], values[order[1]], values[order[2]]);
    (values, DMat3::from_cols(x, y, x.cross(y)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn assert_orthonormal(v: DMat3) {
        let err = (v.transpose() * v - DMat3::IDENTITY).to_cols_array();
        assert!(err.iter().all(|e| e.abs() < 1e-12), "{v:?}");
        assert!((v.determinant() - 1.0).abs() < 1e-12);
    }

    /// `Q diag(l) Q^T` for a rotation `Q` built from a quaternion.
    fn with_spectrum(l: DVec3, q: glam::DQuat) -> DMat3 {
        let r = DMat3::from_quat(q.normalize());
        r * DMat3::from_diagonal(l) * r.transpose()
    }

    #[test]
    fn degenerate_spectra_give_orthonormal_bases() {
        let q = glam::DQuat::from_xyzw(0.3, -0.2, 0.7, 0.4);
        for l in [
            DVec3::ZERO,
            DVec3::splat(2.5),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1e-300, 0.0, 0.0),
            DVec3::new(1e300, 1e300, 1.0),
        ] {
            let (values, v) = symmetric_eigen(with_spectrum(l, q));
            assert_orthonormal(v);
            let mut want = l.to_array();
            want.sort_by(|a, b| b.total_cmp(a));
            for (got, want) in values.to_array().iter().zip(want) {
                assert!((got - want).abs() <= 1e-12 * l.max_element(), "{values} vs {l}");
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]
        /// Residuals `|A v - lambda v|` at rounding level, values sorted, basis orthonormal.
        #[test]
        fn decomposes_random_symmetric_matrices(
            e in prop::array::uniform6(-1e3f64..1e3),
            exp in -30i32..30,
        ) {
            let s = 10f64.powi(exp);
            let m = DMat3::from_cols_array(&[e[0], e[1], e[2], e[1], e[3], e[4], e[2], e[4], e[5]]) * s;
            let (values, v) = symmetric_eigen(m);
            assert_orthonormal(v);
            prop_assert!(values.x >= values.y && values.y >= values.z);
            let norm = m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()));
            for j in 0..3 {
                let r = m * v.col(j) - v.col(j) * values[j];
                prop_assert!(r.length() <= 1e-12 * norm, "residual {r} of {m}");
            }
        }
    }
}
