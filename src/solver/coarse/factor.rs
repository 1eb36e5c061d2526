//! The coarse matrix's inverse, each Newton iteration: `Pᵀ K P = B + E D Eᵀ`, `B` the
//! bonds' part (the same every iteration until bonds break) and `D` the springs' part on the
//! rows `E` of the boxes they touch, a few boxes around the contact. `B` is factorised once
//! and the springs come in by the Sherman-Morrison-Woodbury identity,
//! `(B + E D Eᵀ)⁻¹ v = y − Z (I + D Eᵀ Z)⁻¹ D Eᵀ y`, `y = B⁻¹ v`, `Z = B⁻¹ E`: the columns of
//! `B⁻¹` at those rows, kept until bonds break, and a dense solve the size of those rows.
//! Refactorising the whole matrix each iteration cost 1-2 ms on the demo (438 rows) and 3-5
//! ms on the 25k hex pair (636 rows) (docs/PERFORMANCE.md, "Frames and the coarse matrix").
//!
//! `B` alone is singular where a body is held only by contact (its rigid motion along the
//! load stretches no bond): its diagonal is raised by [`REGULAR`] of itself, so that `B⁻¹`
//! exists; the springs hold that motion in `B + E D Eᵀ`, whose inverse the identity gives to
//! rounding.

use std::collections::HashMap;
use std::sync::Mutex;

use faer::linalg::solvers::{Llt, SolveCore};
use faer::{Conj, MatMut, Side};
use nalgebra::{DMatrix, DVector, Dyn, LU};

/// The share of its diagonal that `B` is raised by: as the whole matrix is (a body held only
/// by contact has a zero eigenvalue in `B`; this leaves 6 of the 16 digits of its rigid
/// motion's correction, where a preconditioner needs two or three).
pub(super) const REGULAR: f64 = 1e-10;

/// Where the springs touch more than this share of the coarse rows, the whole matrix is
/// factorised instead (the identity's dense solve and columns would cost more).
const UPDATE_AT_MOST: f64 = 0.25;

/// A mode that nothing moves (a box whose particles are all held in that direction) has a
/// zero row, and a zero column in P: any diagonal will do (the largest); the others are
/// raised by `by` of themselves.
pub(super) fn regularise(m: &mut DMatrix<f64>, by: f64) {
    let top = m.diagonal().iter().fold(0.0f64, |a, &v| a.max(v));
    for i in 0..m.nrows() {
        if m[(i, i)] <= 1e-12 * top {
            m[(i, i)] = top;
        } else {
            m[(i, i)] *= 1.0 + by;
        }
    }
}

/// A dense Cholesky factor (faer's: at 372 coarse unknowns, nalgebra's took 1.8 ms, faer's
/// 1.1 ms).
pub(in crate::solver) struct Cholesky(Llt<f64>);

impl Cholesky {
    fn new(m: &DMatrix<f64>) -> Option<Cholesky> {
        let n = m.nrows();
        let a = faer::Mat::<f64>::from_fn(n, n, |i, j| m[(i, j)]);
        a.llt(Side::Lower).ok().map(Cholesky)
    }

    fn solve(&self, mut v: DVector<f64>) -> DVector<f64> {
        let n = v.len();
        self.0.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(v.as_mut_slice(), n, 1),
        );
        v
    }
}

/// `B` factorised, and the columns of `B⁻¹` asked for so far.
pub(super) struct Base {
    factor: Cholesky,
    /// Rows of `B`.
    n: usize,
    columns: Mutex<HashMap<usize, DVector<f64>>>,
}

impl Base {
    /// `None` where `b`, raised by [`REGULAR`], is not positive definite.
    pub fn new(b: &DMatrix<f64>) -> Option<Base> {
        let mut b = b.clone();
        regularise(&mut b, REGULAR);
        Some(Base {
            factor: Cholesky::new(&b)?,
            n: b.nrows(),
            columns: Mutex::new(HashMap::new()),
        })
    }

    /// `B⁻¹ Eᵀ`'s columns at `rows`, as a matrix.
    fn columns(&self, rows: &[usize]) -> DMatrix<f64> {
        let n = self.n;
        let mut kept = self.columns.lock().unwrap_or_else(|e| e.into_inner());
        let mut z = DMatrix::zeros(n, rows.len());
        for (c, &r) in rows.iter().enumerate() {
            let column = kept.entry(r).or_insert_with(|| {
                let mut e = DVector::zeros(n);
                e[r] = 1.0;
                self.factor.solve(e)
            });
            z.set_column(c, column);
        }
        z
    }
}

/// A tangent's `(Pᵀ K P)⁻¹`.
pub(in crate::solver) enum CoarseFactor {
    /// The whole matrix factorised.
    Whole(Cholesky),
    /// The space's `B` and the springs' update on `rows`: `Z = B⁻¹ E`, `D`, and
    /// `I + D Eᵀ Z` factorised.
    Updated {
        rows: Vec<usize>,
        z: DMatrix<f64>,
        d: DMatrix<f64>,
        small: LU<f64, Dyn, Dyn>,
    },
}

impl CoarseFactor {
    /// `m` factorised whole; `None` where it is not positive definite.
    pub fn whole(m: &DMatrix<f64>) -> Option<CoarseFactor> {
        Cholesky::new(m).map(CoarseFactor::Whole)
    }

    /// `B + E D Eᵀ` from `base` (`B`'s), `d` the springs' part on `rows` (ascending);
    /// `None` where the springs touch too many rows or `I + D Eᵀ Z` is singular (the
    /// caller factorises the whole matrix).
    pub(super) fn updated(base: &Base, rows: Vec<usize>, d: DMatrix<f64>) -> Option<CoarseFactor> {
        let n = base.n;
        if rows.len() as f64 > UPDATE_AT_MOST * n as f64 {
            return None;
        }
        let z = base.columns(&rows);
        let g = DMatrix::from_fn(rows.len(), rows.len(), |i, j| z[(rows[i], j)]);
        let small = (DMatrix::identity(rows.len(), rows.len()) + &d * g).lu();
        if !small.is_invertible() {
            return None;
        }
        Some(CoarseFactor::Updated { rows, z, d, small })
    }

    /// `(Pᵀ K P)⁻¹ v`, `base` the space's `B` (for [`CoarseFactor::Updated`]).
    pub(super) fn solve(&self, base: Option<&Base>, v: DVector<f64>) -> DVector<f64> {
        match self {
            CoarseFactor::Whole(f) => f.solve(v),
            CoarseFactor::Updated { rows, z, d, small } => {
                let base = base.expect("an updated coarse factor comes with its base");
                let mut y = base.factor.solve(v);
                // No springs (a scene without contact): `B` alone; nalgebra's LU of the
                // empty `I + D Eᵀ Z` panics on a solve.
                if rows.is_empty() {
                    return y;
                }
                let dy = d * DVector::from_iterator(rows.len(), rows.iter().map(|&r| y[r]));
                let s = small.solve(&dy).expect("checked invertible");
                y -= z * s;
                y
            }
        }
    }
}
