//! The coarse space of the static solver's preconditioner (METHOD.md §6): the rigid modes
//! (three translations, three rotations) of boxes of particles, so that the smooth part of
//! a linear solve is found at once instead of spreading one horizon a conjugate-gradient
//! iteration through block Jacobi (two-level additive Schwarz,
//! `M⁻¹ = D⁻¹ + P (Pᵀ K P)⁻¹ Pᵀ S`, `K = S A` symmetric: [`super::tangent`]).
//!
//! `Pᵀ K P` is assembled from the bonds' linearised tangent once (it does not change under
//! small kinematics; under finite ones it stands for the tangent in the preconditioner
//! only) and from each Newton iteration's contact springs ([`super::tangent::Tangent`]).
//! Bodies of the LPS model (whose dilatation couples a particle to its neighbours'
//! neighbours) have no coarse space: block Jacobi alone, as before.

use nalgebra::linalg::Cholesky;
use nalgebra::{DMatrix, DVector, Dyn, Matrix3, SMatrix, SVector};
use rayon::prelude::*;

use super::dofs::Dofs;
use super::free_factor;
use super::tangent::{Master, Spring};
use crate::body::Body;
use crate::math::Vec3;
use crate::model::Model;

/// A particle's rows of `P`: its box and the 3×6 block of that box's modes.
pub(super) type Rows = (usize, SMatrix<f64, 3, 6>);

/// Particles a box holds, about: fewer boxes leave the CG count high, more make the dense
/// coarse factorisation the cost (docs/PERFORMANCE.md, "The static solver").
const PARTICLES_PER_BOX: usize = 500;
/// Boxes over the whole model at most (a coarse matrix of 6 × 128 = 768 rows, factorised
/// once a Newton iteration in tens of milliseconds).
const MAX_BOXES: usize = 128;

/// The boxes and the bonds' part of `Pᵀ K P`.
pub(super) struct CoarseSpace {
    /// Per body, per particle: its box (empty for a rigid body).
    aggregate: Vec<Vec<u32>>,
    /// Per box: the centre its rotations turn about.
    centre: Vec<Vec3>,
    /// The bonds' part of `Pᵀ K P`.
    bonds: DMatrix<f64>,
}

impl CoarseSpace {
    /// Boxes over each deformable body's reference box, about [`PARTICLES_PER_BOX`]
    /// particles each; `None` where a body is LPS or the model has no deformable body.
    pub fn new(model: &Model) -> Option<CoarseSpace> {
        let mut sizes = Vec::new();
        for b in &model.bodies {
            if let Body::Deformable(pd) = b {
                if pd.lps.is_some() {
                    return None;
                }
                sizes.push(pd.len());
            }
        }
        let total: usize = sizes.iter().sum();
        if total == 0 {
            return None;
        }
        let boxes = (total / PARTICLES_PER_BOX).clamp(1, MAX_BOXES);
        let mut aggregate = Vec::with_capacity(model.bodies.len());
        let mut centre: Vec<Vec3> = Vec::new();
        for b in &model.bodies {
            let Body::Deformable(pd) = b else {
                aggregate.push(Vec::new());
                continue;
            };
            let n = pd.len();
            let per_body = (boxes * n / total).max(1);
            let x = &pd.reference[..n];
            let (mut lo, mut hi) = (x[0], x[0]);
            for p in x {
                lo = lo.inf(p);
                hi = hi.sup(p);
            }
            let ext = (hi - lo).map(|e| e.max(1e-30));
            let side = (ext.x * ext.y * ext.z / per_body as f64).cbrt();
            let dims = ext.map(|e| ((e / side).round() as usize).max(1));
            let cell = |p: &Vec3| {
                let mut c = [0usize; 3];
                for d in 0..3 {
                    let t = ((p[d] - lo[d]) / ext[d] * dims[d] as f64) as usize;
                    c[d] = t.min(dims[d] - 1);
                }
                c[0] + dims[0] * (c[1] + dims[1] * c[2])
            };
            // Boxes numbered in the order their first particle comes: the same on any
            // thread count.
            let mut index = vec![u32::MAX; dims.x * dims.y * dims.z];
            let mut sums: Vec<(Vec3, f64)> = Vec::new();
            let base = centre.len();
            let agg: Vec<u32> = x
                .iter()
                .map(|p| {
                    let c = cell(p);
                    if index[c] == u32::MAX {
                        index[c] = (base + sums.len()) as u32;
                        sums.push((Vec3::zeros(), 0.0));
                    }
                    let a = index[c] as usize - base;
                    sums[a].0 += p;
                    sums[a].1 += 1.0;
                    index[c]
                })
                .collect();
            centre.extend(sums.iter().map(|(s, w)| s / *w));
            aggregate.push(agg);
        }
        let mut space = CoarseSpace {
            aggregate,
            centre,
            bonds: DMatrix::zeros(0, 0),
        };
        space.bonds = space.assemble_bonds(model);
        Some(space)
    }

    /// Coarse unknowns.
    pub fn len(&self) -> usize {
        6 * self.centre.len()
    }

    /// Assembles the bonds' part again (bonds broke).
    pub fn reassemble(&mut self, model: &Model) {
        self.bonds = self.assemble_bonds(model);
    }

    /// Particle `i` of body `k`: its box and the modes' values there, fixed components
    /// removed (a mode does not move what a support holds).
    #[inline]
    pub fn rows(&self, model: &Model, k: usize, i: usize) -> Rows {
        let Body::Deformable(pd) = &model.bodies[k] else {
            unreachable!("a coarse row of a rigid body")
        };
        let a = self.aggregate[k][i] as usize;
        let r = pd.reference[i] - self.centre[a];
        let f = free_factor(pd.fixed[i]);
        let mut m = SMatrix::<f64, 3, 6>::zeros();
        for d in 0..3 {
            let mut e = Vec3::zeros();
            e[d] = 1.0;
            m.set_column(d, &e.component_mul(&f));
            m.set_column(3 + d, &e.cross(&r).component_mul(&f));
        }
        (a, m)
    }

    /// `Pᵀ K P` of a tangent: the bonds' part and its `springs`' (each couples its slave's
    /// rows to its master nodes', `C` between them).
    pub fn matrix(&self, model: &Model, springs: &[Spring]) -> DMatrix<f64> {
        let mut ac = self.bonds.clone();
        let mut d: Vec<Rows> = Vec::with_capacity(5);
        for s in springs {
            if model.bodies[s.body].as_pd().is_none() {
                continue;
            }
            let c = s.matrix();
            d.clear();
            d.push(self.rows(model, s.body, s.slave as usize));
            if let Master::Nodes {
                body,
                nodes,
                weights,
            } = s.master
            {
                for (n, w) in nodes.iter().zip(weights) {
                    if w != 0.0 {
                        let (a, m) = self.rows(model, body, *n as usize);
                        d.push((a, -m * w));
                    }
                }
            }
            for (a, ma) in &d {
                let left = ma.transpose() * c;
                for (b, mb) in &d {
                    let mut blk = ac.fixed_view_mut::<6, 6>(6 * a, 6 * b);
                    blk += left * mb;
                }
            }
        }
        // A mode that nothing moves (a box whose particles are all held in that direction)
        // has a zero row, and a zero column in P: any diagonal will do.
        let top = ac.diagonal().iter().fold(0.0f64, |a, &v| a.max(v));
        for i in 0..ac.nrows() {
            if ac[(i, i)] <= 1e-12 * top {
                ac[(i, i)] = top;
            } else {
                ac[(i, i)] *= 1.0 + 1e-10;
            }
        }
        ac
    }

    /// `z += P (Pᵀ K P)⁻¹ Pᵀ S r`, `factor` the factorised `Pᵀ K P`.
    pub fn correct(&self, model: &Model, factor: &Cholesky<f64, Dyn>, r: &Dofs, z: &mut Dofs) {
        let mut pr = DVector::zeros(self.len());
        for (k, rk) in r.pd.iter().enumerate() {
            let Some(pd) = model.bodies[k].as_pd() else {
                continue;
            };
            for (i, ri) in rk.iter().enumerate() {
                let (a, m) = self.rows(model, k, i);
                let mut seg = pr.fixed_rows_mut::<6>(6 * a);
                seg += m.transpose() * (ri * pd.case.ghosts.share(i));
            }
        }
        let y = factor.solve(&pr);
        for (k, zk) in z.pd.iter_mut().enumerate() {
            if model.bodies[k].as_pd().is_none() {
                continue;
            }
            for (i, zi) in zk.iter_mut().enumerate() {
                let (a, m) = self.rows(model, k, i);
                *zi += m * y.fixed_rows::<6>(6 * a);
            }
        }
    }

    /// `Σ_i P_iᵀ (K P)_i` over every directed bond, linearised: each bond adds
    /// `w g_i (g_i − g_j)ᵀ`, `g = P e`, `e` the bond's reference direction (Eq. 26
    /// linearised); a bond to a mirror image moves with its source reflected. Summed per
    /// block of particles in a fixed order (the same bits on any thread count).
    fn assemble_bonds(&self, model: &Model) -> DMatrix<f64> {
        let nc = self.len();
        let mut ac = DMatrix::zeros(nc, nc);
        for (k, b) in model.bodies.iter().enumerate() {
            let Body::Deformable(pd) = b else { continue };
            let n = pd.len();
            let bonds = &pd.case.bonds;
            let ghosts = &pd.case.ghosts;
            let part = |range: std::ops::Range<usize>| {
                let mut m = DMatrix::<f64>::zeros(nc, nc);
                for i in range {
                    let (ai, pi) = self.rows(model, k, i);
                    for bd in bonds.range(i) {
                        let w = f64::from(pd.bond_weight[bd]);
                        if w == 0.0 {
                            continue;
                        }
                        let j = bonds.partner[bd] as usize;
                        let xi = pd.reference[j] - pd.reference[i];
                        let e = xi / xi.norm();
                        let gi: SVector<f64, 6> = pi.transpose() * e;
                        let (aj, pj) = if j < n {
                            self.rows(model, k, j)
                        } else {
                            let (a, m) = self.rows(model, k, ghosts.source[j - n] as usize);
                            let mut reflect = Matrix3::identity();
                            for (q, plane) in ghosts.planes.iter().enumerate() {
                                if ghosts.mask[j - n] & (1 << q) != 0 {
                                    reflect[(plane.axis, plane.axis)] = -1.0;
                                }
                            }
                            (a, reflect * m)
                        };
                        let gj: SVector<f64, 6> = pj.transpose() * e;
                        let mut blk = m.fixed_view_mut::<6, 6>(6 * ai, 6 * ai);
                        blk += gi * gi.transpose() * w;
                        let mut blk = m.fixed_view_mut::<6, 6>(6 * ai, 6 * aj);
                        blk -= gi * gj.transpose() * w;
                    }
                }
                m
            };
            // At most 16 blocks of particles (each holds a whole coarse matrix), summed in
            // their order.
            let block = n.div_ceil(16).max(1024);
            let parts: Vec<DMatrix<f64>> = (0..n.div_ceil(block))
                .into_par_iter()
                .map(|c| part(c * block..((c + 1) * block).min(n)))
                .collect();
            for p in parts {
                ac += p;
            }
        }
        // K is symmetric; the sum over directed bonds is so up to rounding.
        (&ac + ac.transpose()) * 0.5
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::super::dofs::Dofs;
    use super::super::free_factor;
    use super::super::tangent::Tangent;
    use super::CoarseSpace;
    use crate::body::Body;
    use crate::math::Vec3;
    use crate::model::Model;
    use crate::scene::Scene;

    /// The two gmsh tet4 quarter spheres of `tests/two_bodies.rs` (symmetry planes x = 0 and
    /// y = 0 on both, z = −1 on the lower: particles on one plane and on two), touching at
    /// the origin, two passes: springs to master nodes and, by the stabilisation, to the
    /// ground.
    fn stacked() -> Model {
        let mesh = |name: &str| {
            format!(
                "{:?}",
                Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("meshes")
                    .join(name)
                    .display()
                    .to_string()
            )
        };
        let body = |name: &str, file: &str, planes: &str| {
            format!(
                r#"[[body]]
name = "{name}"
mesh = {}
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[symmetry]]
body = "{name}"
axis = "x"
[[symmetry]]
body = "{name}"
axis = "y"
{planes}"#,
                mesh(file)
            )
        };
        let text = format!(
            r#"[solver]
kind = "static"
[output]
every = 100000
{}{}[[load]]
body = "upper"
force = [0.0, 0.0, -9.6e6]
[[contact]]
slave = "upper"
master = "lower"
radius = 2290.0
two_pass = true
"#,
            body("upper", "two_spheres_upper_h006.msh", ""),
            body(
                "lower",
                "two_spheres_lower_h006.msh",
                "[[symmetry]]\nbody = \"lower\"\naxis = \"z\"\nat = -1.0\nkeep = \"positive\"\n"
            ),
        );
        let scene = Scene::parse(&text, "scene.toml", Path::new(".")).expect("scene");
        let mut model = Model::from_scene(&scene).expect("model");
        model.compute_forces();
        model
    }

    /// A vector of the free components, deterministic.
    fn vector(model: &Model, seed: u64) -> Dofs {
        let mut state = seed;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut v = Dofs::zeros(model);
        for (k, b) in model.bodies.iter().enumerate() {
            if let Body::Deformable(pd) = b {
                for (i, x) in v.pd[k].iter_mut().enumerate() {
                    *x = Vec3::new(next(), next(), next()).component_mul(&free_factor(pd.fixed[i]));
                }
            }
        }
        v
    }

    /// `K = S A` is symmetric: `b·S A a = a·S A b` to rounding, while the plain `b·A a`
    /// differs (the inner product the conjugate gradients once used); and the coarse
    /// matrix assembled from the bonds and springs is `Pᵀ K P` as the product gives it,
    /// column by column.
    #[test]
    fn the_tangent_is_symmetric_in_the_shares_and_the_coarse_matrix_is_its_projection() {
        let mut model = stacked();
        let mut blocks = vec![None; model.bodies.len()];
        let mut tangent = Tangent::new(&model, 1.0, None, &mut blocks);
        assert!(!tangent.springs().is_empty());
        let (a, b) = (vector(&model, 1), vector(&model, 2));
        let (mut aa, mut ab) = (Dofs::zeros(&model), Dofs::zeros(&model));
        tangent.apply(&mut model, &a, &mut aa);
        tangent.apply(&mut model, &b, &mut ab);
        let scale = a.dot_shares(&aa, &model);
        let shares = b.dot_shares(&aa, &model) - a.dot_shares(&ab, &model);
        let plain = b.dot(&aa) - a.dot(&ab);
        assert!(shares.abs() < 1e-12 * scale, "{shares} against {scale}");
        assert!(plain.abs() > 1e-6 * scale, "{plain} against {scale}");

        let space = CoarseSpace::new(&model).expect("a coarse space");
        let assembled = space.matrix(&model, tangent.springs());
        let nc = space.len();
        let mut probed = nalgebra::DMatrix::<f64>::zeros(nc, nc);
        let (mut v, mut out) = (Dofs::zeros(&model), Dofs::zeros(&model));
        for c in 0..nc {
            v.fill_zero();
            for k in 0..v.pd.len() {
                for i in 0..v.pd[k].len() {
                    let (box_, m) = space.rows(&model, k, i);
                    if box_ == c / 6 {
                        v.pd[k][i] = m.column(c % 6).into_owned();
                    }
                }
            }
            tangent.apply(&mut model, &v, &mut out);
            for (k, body) in model.bodies.iter().enumerate() {
                let Some(pd) = body.as_pd() else { continue };
                for i in 0..out.pd[k].len() {
                    let (box_, m) = space.rows(&model, k, i);
                    let mut col = probed.fixed_view_mut::<6, 1>(6 * box_, c);
                    col += m.transpose() * out.pd[k][i] * pd.case.ghosts.share(i);
                }
            }
        }
        let gap = (&assembled - &probed).norm() / probed.norm();
        assert!(gap < 1e-8, "assembled against probed: {gap:e}");
    }
}
