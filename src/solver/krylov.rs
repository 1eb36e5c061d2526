//! The linear solves of a Newton iteration, `A x = b` with the tangent of
//! [`super::tangent`]: conjugate gradients where `A` is symmetric, GMRES where a contact between
//! two deformable bodies makes it unsymmetric ([`Tangent::symmetric`]). Both take the
//! same preconditioner (block Jacobi, plus the coarse space's correction).

use super::coarse::CoarseSpace;
use super::dofs::Dofs;
use super::newton::MAX_LINEAR;
use super::tangent::Tangent;
use crate::model::Model;
use nalgebra::{DMatrix, DVector};

/// `A x = b` to `‖r‖ ≤ eta ‖b‖` by [`pcg`] or, where the tangent is unsymmetric, [`gmres`];
/// from zero or, where `warm`, from `x` as it is; returns the tangent products taken.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve(
    tangent: &mut Tangent,
    space: Option<&CoarseSpace>,
    model: &mut Model,
    b: &Dofs,
    eta: f64,
    x: &mut Dofs,
    warm: bool,
    work: &mut [Dofs; 3],
) -> usize {
    if tangent.symmetric() {
        pcg(tangent, space, model, b, eta, x, warm, work)
    } else {
        gmres(tangent, space, model, b, eta, x, warm, work)
    }
}

/// Preconditioned conjugate gradients for `A x = b` in the inner product `xᵀ S y` (where
/// `A` is symmetric: [`super::tangent`]) to `‖r‖ ≤ eta ‖b‖`, from zero or, where `warm`,
/// from `x` as it is; returns the tangent products taken.
#[allow(clippy::too_many_arguments)]
fn pcg(
    tangent: &mut Tangent,
    space: Option<&CoarseSpace>,
    model: &mut Model,
    b: &Dofs,
    eta: f64,
    x: &mut Dofs,
    warm: bool,
    work: &mut [Dofs; 3],
) -> usize {
    let [r, z, p] = work;
    let mut ap = Dofs::zeros(model);
    let norm0 = b.dot(b).sqrt();
    if !(norm0 > 0.0) {
        x.fill_zero();
        return 0;
    }
    // From `x` as it is where `warm` (one product more), else from zero.
    let mut taken = 0;
    if warm {
        tangent.apply(model, x, &mut ap);
        r.clone_from(b);
        r.axpy(-1.0, &ap);
        taken = 1;
        if r.dot(r).sqrt() <= eta * norm0 {
            return taken;
        }
    } else {
        x.fill_zero();
        r.clone_from(b);
    }
    tangent.precondition(space, model, r, z);
    p.clone_from(z);
    let mut rz = r.dot_shares(z, model);
    for k in 1..=MAX_LINEAR {
        tangent.apply(model, p, &mut ap);
        let pap = p.dot_shares(&ap, model);
        if !(pap > 0.0) {
            // Not positive along p (a compressed bond's negative stiffness, say): keep what
            // has been found, or take the preconditioned residual as the direction.
            if k == 1 && !warm {
                x.clone_from(z);
            }
            return k + taken;
        }
        let alpha = rz / pap;
        x.axpy(alpha, p);
        r.axpy(-alpha, &ap);
        if r.dot(r).sqrt() <= eta * norm0 {
            return k + taken;
        }
        tangent.precondition(space, model, r, z);
        let rz_new = r.dot_shares(z, model);
        p.xpby(z, rz_new / rz);
        rz = rz_new;
    }
    MAX_LINEAR
}

/// The Krylov space's size before GMRES restarts.
const RESTART: usize = 60;

/// Right-preconditioned GMRES (Saad and Schultz, 1986), restarted every [`RESTART`]
/// products, for `A x = b`, `A` not symmetric, to `‖r‖ ≤ eta ‖b‖`, from zero or, where
/// `warm`, from `x` as it is; returns the tangent products taken. One product per
/// iteration, and the least residual over the space (the small least-squares problem by
/// nalgebra's QR).
#[allow(clippy::too_many_arguments)]
fn gmres(
    tangent: &mut Tangent,
    space: Option<&CoarseSpace>,
    model: &mut Model,
    b: &Dofs,
    eta: f64,
    x: &mut Dofs,
    warm: bool,
    work: &mut [Dofs; 3],
) -> usize {
    let [r, w, z] = work;
    let norm0 = b.dot(b).sqrt();
    if !(norm0 > 0.0) {
        x.fill_zero();
        return 0;
    }
    if !warm {
        x.fill_zero();
    }
    let mut taken = 0;
    // The basis vectors, kept from solve to solve of this tangent: allocated once.
    let mut pool = std::mem::take(&mut tangent.pool);
    let mut basis: Vec<Dofs> = Vec::with_capacity(RESTART + 1);
    let fresh = |pool: &mut Vec<Dofs>, from: &Dofs, scale: f64| {
        let mut v = pool.pop().unwrap_or_else(|| from.clone());
        v.assign(from);
        v.scale(scale);
        v
    };
    while taken < MAX_LINEAR {
        // r = b − A x
        r.assign(b);
        if warm || taken > 0 {
            tangent.apply(model, x, w);
            r.axpy(-1.0, w);
            taken += 1;
        }
        let beta = r.dot(r).sqrt();
        if beta <= eta * norm0 {
            break;
        }
        pool.append(&mut basis);
        basis.push(fresh(&mut pool, r, 1.0 / beta));
        let mut h = DMatrix::<f64>::zeros(RESTART + 1, RESTART);
        let mut y = DVector::<f64>::zeros(0);
        let mut done = false;
        for j in 0..RESTART {
            tangent.precondition(space, model, &basis[j], z);
            tangent.apply(model, z, w);
            taken += 1;
            // Classical Gram-Schmidt twice (as stable as the modified one), in three sweeps
            // over the particles for the whole basis where the modified one takes two per
            // basis vector: the products, the update with the next products, the update
            // with the norm.
            let first = w.subtract(&[], &basis, true);
            let second = w.subtract(&first, &basis, true);
            let hn = w.subtract(&second, &basis, false)[0].sqrt();
            for (i, (a, b)) in first.iter().zip(&second).enumerate() {
                h[(i, j)] = a + b;
            }
            h[(j + 1, j)] = hn;
            let m = h.view((0, 0), (j + 2, j + 1)).into_owned();
            let mut g = DVector::<f64>::zeros(j + 2);
            g[0] = beta;
            let qr = m.clone().qr();
            let Some(sol) = qr.r().solve_upper_triangular(&(qr.q().transpose() * &g)) else {
                break;
            };
            let res = (&g - &m * &sol).norm();
            y = sol;
            if res <= eta * norm0 || !(hn > 0.0) || taken >= MAX_LINEAR {
                done = true;
                break;
            }
            basis.push(fresh(&mut pool, w, 1.0 / hn));
        }
        // x += M⁻¹ V y
        w.fill_zero();
        let minus: Vec<f64> = y.iter().map(|c| -c).collect();
        w.subtract(&minus, &basis[..minus.len()], false);
        tangent.precondition(space, model, w, z);
        x.axpy(1.0, z);
        if done || y.is_empty() {
            break;
        }
    }
    pool.append(&mut basis);
    tangent.pool = pool;
    taken
}

#[cfg(test)]
mod tests {
    use super::super::coarse::tests::{stacked, vector};
    use super::super::dofs::Dofs;
    use super::super::newton::{newton, residual};
    use super::super::tangent::Tangent;
    use super::super::Silent;
    use super::{gmres, pcg};
    use crate::body::Body;
    use crate::model::Model;

    /// Moves every deformable body's particles by `scale v`.
    fn shift(model: &mut Model, v: &Dofs, scale: f64) {
        for (k, b) in model.bodies.iter_mut().enumerate() {
            if let Body::Deformable(pd) = b {
                for (u, d) in pd.u.iter_mut().zip(&v.pd[k]) {
                    *u += d * scale;
                }
            }
        }
    }

    /// `(S⁻¹R(u − εv) − S⁻¹R(u + εv)) / 2ε`: the tangent's product as the forces give it.
    fn difference(model: &mut Model, v: &Dofs, eps: f64) -> Dofs {
        let mut ends = [Dofs::zeros(model), Dofs::zeros(model)];
        for (sign, end) in [-1.0, 1.0].into_iter().zip(&mut ends) {
            shift(model, v, sign * eps);
            model.compute_forces();
            residual(model, end);
            shift(model, v, -sign * eps);
        }
        model.compute_forces();
        let [mut out, plus] = ends;
        out.axpy(-1.0, &plus);
        out.scale(0.5 / eps);
        out
    }

    /// At the equilibrium of two gmsh tet4 quarter spheres pressed together (two passes), the
    /// product of the consistent contact springs agrees with a central difference of the
    /// out-of-balance force, where the symmetric springs' does not: the bonds' part is exact
    /// (linearised kinematics), so what is left is the contacts'. And GMRES solves the
    /// unsymmetric tangent to the residual asked, as conjugate gradients do the symmetric one.
    #[test]
    fn the_consistent_contact_tangent_is_the_difference_of_the_forces() {
        let mut model = stacked();
        newton(&mut model, 1e-5, 200, 1, &mut Silent).expect("the pair converges");
        assert!(
            model.contact_count() > 20,
            "{} contacts",
            model.contact_count()
        );
        let mut blocks = vec![None; model.bodies.len()];
        let settled = Tangent::new(&model, 0.0, None, &mut blocks, false);
        let mut symmetric = Tangent::new(&model, 0.0, Some(&settled), &mut blocks, false);
        let mut consistent = Tangent::new(&model, 0.0, Some(&settled), &mut blocks, true);
        assert!(symmetric.symmetric() && !consistent.symmetric());
        let v = vector(&model, 3);
        let fd = difference(&mut model, &v, 1e-9);
        let mut mismatch = |t: &mut Tangent| {
            let mut av = Dofs::zeros(&model);
            t.apply(&mut model, &v, &mut av);
            av.axpy(-1.0, &fd);
            av.dot(&av).sqrt() / fd.dot(&fd).sqrt()
        };
        let (s, c) = (mismatch(&mut symmetric), mismatch(&mut consistent));
        eprintln!("relative mismatch: symmetric {s:.3e}, consistent {c:.3e}");
        // Without the nodal normals' derivative 0.081 of the symmetric one's.
        assert!(c < 0.02 * s, "consistent {c:.3e} against symmetric {s:.3e}");

        let b = vector(&model, 4);
        let mut work = [
            Dofs::zeros(&model),
            Dofs::zeros(&model),
            Dofs::zeros(&model),
        ];
        for (t, unsymmetric) in [(&mut symmetric, false), (&mut consistent, true)] {
            let mut x = Dofs::zeros(&model);
            let taken = if unsymmetric {
                gmres(t, None, &mut model, &b, 1e-6, &mut x, false, &mut work)
            } else {
                pcg(t, None, &mut model, &b, 1e-6, &mut x, false, &mut work)
            };
            let mut r = Dofs::zeros(&model);
            t.apply(&mut model, &x, &mut r);
            r.axpy(-1.0, &b);
            let rel = r.dot(&r).sqrt() / b.dot(&b).sqrt();
            assert!(rel <= 1.01e-6, "{rel:.3e} after {taken} products");
        }
    }
}
