//! The contact cluster's block of the static solver's preconditioner (METHOD.md §6): the
//! particles that a spring between two deformable bodies joins (each slave in contact and
//! the nodes of its master segment), solved together.
//!
//! Block Jacobi takes a contact spring `k n⊗n` into the slave's diagonal block and
//! `N_a² k n⊗n` into each master node's, and leaves out the coupling `−N_a k n⊗n` between
//! them. Against a rigid master that is all of the spring; between two deformable bodies the
//! stiff penalty ties slave and segment together, and the mode in which they move together
//! (which only their bonds resist) then looks to block Jacobi as stiff as the spring: an
//! eigenvalue of the preconditioned tangent near `k_bond / k` for every contact, and 17-21
//! tangent products a Newton iteration on gmsh's sphere pairs against 10 on a rigid plane.
//! Here those particles' rows take their diagonal blocks (bonds and springs) and the springs'
//! couplings, `K_c`, factorised by a sparse Cholesky (faer, fill-reducing ordering), and
//! `z_c = K_c⁻¹ S r_c` replaces block Jacobi there (docs/PERFORMANCE.md, "The contact
//! cluster"). The bonds between the cluster's particles are left out: with them the counts
//! were the same within 2 %.

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Llt;
use faer::sparse::{SparseColMat, Triplet};
use faer::{MatMut, Side};
use nalgebra::Matrix3;

use super::dofs::Dofs;
use super::free_factor;
use super::tangent::{Master, Spring};
use crate::math::Vec3;
use crate::model::Model;

/// The cluster's particles and the factorised `K_c`.
pub(super) struct Cluster {
    /// (body, particle) of each block row, sorted.
    members: Vec<(usize, u32)>,
    factor: Llt<usize, f64>,
}

impl Cluster {
    /// The cluster of `springs` with the diagonal blocks `blocks` of `K` (bonds and springs);
    /// `None` where no spring joins two deformable bodies, or the factorisation fails (block
    /// Jacobi alone then, as before).
    pub fn new(model: &Model, springs: &[Spring], blocks: &[Vec<Matrix3<f64>>]) -> Option<Cluster> {
        fn joined(s: &Spring) -> Option<&Spring> {
            matches!(s.master, Master::Nodes { .. }).then_some(s)
        }
        let mut members = Vec::new();
        for s in springs.iter().filter_map(joined) {
            members.push((s.body, s.slave));
            if let Master::Nodes {
                body,
                nodes,
                weights,
            } = s.master
            {
                members.extend(
                    nodes
                        .iter()
                        .zip(weights)
                        .filter(|(_, w)| *w != 0.0)
                        .map(|(n, _)| (body, *n)),
                );
            }
        }
        if members.is_empty() {
            return None;
        }
        members.sort_unstable();
        members.dedup();
        let at = |b: usize, i: u32| members.binary_search(&(b, i)).ok();
        // The lower triangle of K_c, block by block: (row block, column block, 3×3).
        let mut entries: Vec<(usize, usize, Matrix3<f64>)> = members
            .iter()
            .enumerate()
            .map(|(a, &(b, i))| (a, a, blocks[b][i as usize]))
            .collect();
        for s in springs.iter().filter_map(joined) {
            let Master::Nodes {
                body,
                nodes,
                weights,
            } = s.master
            else {
                continue;
            };
            let c = s.matrix();
            let slave = at(s.body, s.slave)?;
            let corners: Vec<(usize, f64)> = nodes
                .iter()
                .zip(weights)
                .filter(|(_, w)| *w != 0.0)
                .map(|(n, w)| at(body, *n).map(|a| (a, w)))
                .collect::<Option<_>>()?;
            for (k, &(a, wa)) in corners.iter().enumerate() {
                entries.push((slave.max(a), slave.min(a), c * -wa));
                for &(b, wb) in &corners[..k] {
                    entries.push((a.max(b), a.min(b), c * (wa * wb)));
                }
            }
        }
        let free: Vec<Vec3> = members
            .iter()
            .map(|&(b, i)| {
                model.bodies[b]
                    .as_pd()
                    .map_or(Vec3::zeros(), |pd| free_factor(pd.fixed[i as usize]))
            })
            .collect();
        let mut triplets = Vec::with_capacity(9 * entries.len());
        for (ra, ca, m) in entries {
            for r in 0..3 {
                for c in 0..3 {
                    let (row, col) = (3 * ra + r, 3 * ca + c);
                    if row < col {
                        continue;
                    }
                    // A fixed component: its row and column out (1 on the diagonal, below).
                    if free[ra][r] == 0.0 || free[ca][c] == 0.0 {
                        continue;
                    }
                    let value = if ra == ca {
                        // The diagonal block symmetrised, as block Jacobi's.
                        0.5 * (m[(r, c)] + m[(c, r)])
                    } else {
                        m[(r, c)]
                    };
                    triplets.push((row, col, value));
                }
            }
        }
        for (a, f) in free.iter().enumerate() {
            for r in (0..3).filter(|&r| f[r] == 0.0) {
                triplets.push((3 * a + r, 3 * a + r, 1.0));
            }
        }
        // Duplicates summed here, in a fixed order.
        triplets.sort_unstable_by_key(|&(r, c, _)| (c, r));
        let mut merged: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(triplets.len());
        for (r, c, v) in triplets {
            match merged.last_mut() {
                Some(t) if t.row == r && t.col == c => t.val += v,
                _ => merged.push(Triplet::new(r, c, v)),
            }
        }
        let n = 3 * members.len();
        let matrix = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &merged).ok()?;
        let factor = matrix.sp_cholesky(Side::Lower).ok()?;
        Some(Cluster { members, factor })
    }

    /// Overwrites `z` on the cluster's particles by `K_c⁻¹ S r` (`A = S⁻¹ K`: [`super::tangent`]).
    pub fn apply(&self, model: &Model, r: &Dofs, z: &mut Dofs) {
        let mut b = vec![0.0; 3 * self.members.len()];
        for (a, &(body, i)) in self.members.iter().enumerate() {
            let Some(pd) = model.bodies[body].as_pd() else {
                continue;
            };
            let v = r.pd[body][i as usize] * pd.case.ghosts.share(i as usize);
            b[3 * a..3 * a + 3].copy_from_slice(v.as_slice());
        }
        let rows = b.len();
        self.factor
            .solve_in_place(MatMut::from_column_major_slice_mut(&mut b, rows, 1));
        for (a, &(body, i)) in self.members.iter().enumerate() {
            let Some(pd) = model.bodies[body].as_pd() else {
                continue;
            };
            let v = Vec3::new(b[3 * a], b[3 * a + 1], b[3 * a + 2]);
            z.pd[body][i as usize] = v.component_mul(&free_factor(pd.fixed[i as usize]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::coarse::tests::{stacked, vector};
    use super::super::coarse::CoarseSpace;
    use super::super::dofs::Dofs;
    use super::super::krylov::solve;
    use super::super::newton::newton;
    use super::super::tangent::Tangent;
    use super::super::Silent;

    /// At the equilibrium of two gmsh tet4 quarter spheres pressed together (two passes),
    /// conjugate gradients with the contact cluster solved whole reach 1e-6 in far fewer
    /// products than with block Jacobi alone, with the coarse space and without, and to the
    /// residual asked.
    #[test]
    fn the_contact_cluster_cuts_the_linear_iterations() {
        let mut model = stacked();
        newton(&mut model, 1e-5, 200, 1, &mut Silent).expect("the pair converges");
        let mut blocks = vec![None; model.bodies.len()];
        let settled = Tangent::new(&model, 0.0, None, &mut blocks, false);
        let b = vector(&model, 7);
        let space = CoarseSpace::new(&model).expect("a coarse space");
        let mut work = [
            Dofs::zeros(&model),
            Dofs::zeros(&model),
            Dofs::zeros(&model),
        ];
        for coarse in [false, true] {
            let mut counts = Vec::new();
            for cluster in [true, false] {
                let mut t = Tangent::new(&model, 0.0, Some(&settled), &mut blocks, false);
                assert!(t.symmetric());
                assert!(t.has_cluster());
                if !cluster {
                    t.drop_cluster();
                }
                let space = coarse.then_some(&space);
                if let Some(s) = space {
                    t.build_coarse(&model, s);
                }
                let mut x = Dofs::zeros(&model);
                let taken = solve(
                    &mut t, space, &mut model, &b, 1e-6, &mut x, false, &mut work,
                );
                let mut r = Dofs::zeros(&model);
                t.apply(&mut model, &x, &mut r);
                r.axpy(-1.0, &b);
                let rel = r.dot(&r).sqrt() / b.dot(&b).sqrt();
                assert!(rel <= 1.01e-6, "{rel:.3e} after {taken} products");
                counts.push(taken);
            }
            eprintln!(
                "coarse space {coarse}: products with the cluster {}, without {}",
                counts[0], counts[1]
            );
            // Measured: 91 against 133 without the coarse space, 42 against 89 with it.
            let bound = if coarse { 0.6 } else { 0.8 };
            assert!(
                (counts[0] as f64) < bound * counts[1] as f64,
                "coarse space {coarse}: {} products with the cluster, {} without",
                counts[0],
                counts[1]
            );
        }
    }
}
