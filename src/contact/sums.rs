//! Sums over a pass's contacts that come out with the same bits in one process and over the
//! ranks of a decomposed run: each block of [`BLOCK`](crate::reduction::BLOCK) slave particles
//! (in order, from zero) that holds a contact gets its own partial sum, and the blocks are
//! added in order. A decomposition's ranges hold whole blocks, so every rank makes whole
//! blocks of its own.

use super::{ContactPass, ContactPoint};
use crate::math::Vec3;

impl ContactPass {
    /// `W` values per contact (`add` puts a contact's into its block's sums), summed over
    /// each block of slave particles that holds a contact: one `[f64; W]` a block, blocks in
    /// order.
    pub fn sum_by_block<const W: usize>(
        &self,
        mut add: impl FnMut(&ContactPoint, &mut [f64; W]),
    ) -> Vec<[f64; W]> {
        let mut out: Vec<[f64; W]> = Vec::new();
        let mut block = usize::MAX;
        for c in &self.contacts {
            let b = c.slave as usize / crate::reduction::BLOCK;
            if b != block {
                out.push([0.0; W]);
                block = b;
            }
            add(c, out.last_mut().expect("pushed above"));
        }
        out
    }

    /// The contacts' forces on the slaves and, against a rigid master of axis `axis`, their
    /// tangent stiffness along it, by blocks ([`Self::sum_by_block`]): `[fx, fy, fz, k]`.
    pub fn block_sums(&self, axis: Option<Vec3>) -> Vec<[f64; 4]> {
        self.sum_by_block(|c, g| {
            for a in 0..3 {
                g[a] += c.force[a];
            }
            if let Some(axis) = axis {
                g[3] += self.weight
                    * self.law.relaxation_stiffness(c.penetration)
                    * c.projection.normal.dot(&axis).powi(2);
            }
        })
    }
}
