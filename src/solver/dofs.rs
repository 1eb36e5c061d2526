//! The unknowns of the static solver ([`super::newton`]) and the vector operations its
//! conjugate gradients take, in a fixed order (the same bits on any thread count).

use rayon::prelude::*;

use crate::math::Vec3;
use crate::model::Model;
use crate::reduction::{block_sums, BLOCK};

/// The unknowns of a static run: per deformable body its particles' displacements (empty
/// for a rigid body), per free rigid body its translation along its axis (0 otherwise).
#[derive(Clone, Debug)]
pub(super) struct Dofs {
    pub pd: Vec<Vec<Vec3>>,
    pub rigid: Vec<f64>,
}

impl Dofs {
    /// Zeros shaped like the model.
    pub fn zeros(model: &Model) -> Dofs {
        Dofs {
            pd: model
                .bodies
                .iter()
                .map(|b| {
                    b.as_pd()
                        .map_or(Vec::new(), |pd| vec![Vec3::zeros(); pd.len()])
                })
                .collect(),
            rigid: vec![0.0; model.bodies.len()],
        }
    }

    /// `Σ self·other`, in a fixed order (the same bits on any thread count).
    pub fn dot(&self, other: &Dofs) -> f64 {
        let mut s = 0.0;
        for (a, b) in self.pd.iter().zip(&other.pd) {
            s += block_sums(0..a.len(), || 0.0, |i| a[i].dot(&b[i]), |x, y| x + y)
                .into_iter()
                .fold(0.0, |x, y| x + y);
        }
        s + self.rigid_dot(other)
    }

    /// `Σ self·S·other`, each particle's product weighted by its share `s_i` (a free rigid
    /// body's by 1): the inner product in which `A = S⁻¹ K` is symmetric, `K` being so (a
    /// particle on a symmetry plane bonds to its neighbours and to their images, and
    /// `S⁻¹` counts those rows twice over). Fixed order, as [`Dofs::dot`].
    pub fn dot_shares(&self, other: &Dofs, model: &Model) -> f64 {
        let mut s = 0.0;
        for ((a, b), body) in self.pd.iter().zip(&other.pd).zip(&model.bodies) {
            let Some(pd) = body.as_pd() else { continue };
            let ghosts = &pd.case.ghosts;
            s += block_sums(
                0..a.len(),
                || 0.0,
                |i| a[i].dot(&b[i]) * ghosts.share(i),
                |x, y| x + y,
            )
            .into_iter()
            .fold(0.0, |x, y| x + y);
        }
        s + self.rigid_dot(other)
    }

    /// The free rigid bodies' part of a product.
    fn rigid_dot(&self, other: &Dofs) -> f64 {
        self.rigid
            .iter()
            .zip(&other.rigid)
            .map(|(a, b)| a * b)
            .fold(0.0, |x, y| x + y)
    }

    /// `self += alpha · other`.
    pub fn axpy(&mut self, alpha: f64, other: &Dofs) {
        for (a, b) in self.pd.iter_mut().zip(&other.pd) {
            a.par_iter_mut()
                .zip(b.par_iter())
                .with_min_len(1024)
                .for_each(|(a, b)| *a += b * alpha);
        }
        for (a, b) in self.rigid.iter_mut().zip(&other.rigid) {
            *a += alpha * b;
        }
    }

    /// `self = other + beta · self`.
    pub fn xpby(&mut self, other: &Dofs, beta: f64) {
        for (a, b) in self.pd.iter_mut().zip(&other.pd) {
            a.par_iter_mut()
                .zip(b.par_iter())
                .with_min_len(1024)
                .for_each(|(a, b)| *a = b + *a * beta);
        }
        for (a, b) in self.rigid.iter_mut().zip(&other.rigid) {
            *a = b + beta * *a;
        }
    }

    /// `self ← alpha self`.
    pub fn scale(&mut self, alpha: f64) {
        for a in &mut self.pd {
            a.par_iter_mut()
                .with_min_len(1024)
                .for_each(|a| *a *= alpha);
        }
        for a in &mut self.rigid {
            *a *= alpha;
        }
    }

    /// `self = other`, in place.
    pub fn assign(&mut self, other: &Dofs) {
        for (a, b) in self.pd.iter_mut().zip(&other.pd) {
            a.par_iter_mut()
                .zip(b.par_iter())
                .with_min_len(1024)
                .for_each(|(a, b)| *a = *b);
        }
        self.rigid.clone_from(&other.rigid);
    }

    /// `self −= Σ c_j basis_j`, in one sweep over the particles; then, from the same sweep,
    /// `[self·v for v in basis]` where `dots`, else `[self·self]`, each product in
    /// [`Dofs::dot`]'s fixed order (a Krylov method's Gram-Schmidt: one pass over the basis
    /// where an update and the next products would take two; with no `c`, the products
    /// alone).
    pub fn subtract(&mut self, c: &[f64], basis: &[Dofs], dots: bool) -> Vec<f64> {
        let m = if dots { basis.len() } else { 1 };
        let mut out = vec![0.0; m];
        for (k, a) in self.pd.iter_mut().enumerate() {
            let blocks: Vec<Vec<f64>> = a
                .par_chunks_mut(BLOCK)
                .enumerate()
                .map(|(b, chunk)| {
                    let mut acc = vec![0.0; m];
                    for (o, x) in chunk.iter_mut().enumerate() {
                        let i = b * BLOCK + o;
                        for (cj, v) in c.iter().zip(basis) {
                            *x -= v.pd[k][i] * *cj;
                        }
                        if dots {
                            for (s, v) in acc.iter_mut().zip(basis) {
                                *s += x.dot(&v.pd[k][i]);
                            }
                        } else {
                            acc[0] += x.dot(x);
                        }
                    }
                    acc
                })
                .collect();
            for (j, o) in out.iter_mut().enumerate() {
                *o += blocks.iter().fold(0.0, |x, b| x + b[j]);
            }
        }
        for (r, a) in self.rigid.iter_mut().enumerate() {
            for (cj, v) in c.iter().zip(basis) {
                *a -= cj * v.rigid[r];
            }
        }
        if dots {
            for (o, v) in out.iter_mut().zip(basis) {
                *o += self.rigid_dot(v);
            }
        } else {
            out[0] += self.rigid_dot(self);
        }
        out
    }

    /// Every entry zero.
    pub fn fill_zero(&mut self) {
        for a in &mut self.pd {
            a.iter_mut().for_each(|x| *x = Vec3::zeros());
        }
        self.rigid.iter_mut().for_each(|x| *x = 0.0);
    }
}
