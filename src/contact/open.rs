//! The static solver's prediction of the contacts its Newton step makes
//! (`solver::predict`, METHOD.md §6): the open slaves in front of a segment, chosen as the
//! contact would choose them once they touch.

use rayon::prelude::*;

use super::{shared_planes, ContactPass, Projection, NO_SEGMENT};
use crate::body::Body;

impl ContactPass {
    /// The slaves that may touch and are not in contact, each with the segment in front of it
    /// nearest along its normal (facing, the gap open and under two spacings; projected inside
    /// it, or else the one it projects least outside of, by at most a tenth of its gap or the
    /// [`edge_margin`](Self::edge_margin), on a crack's faces the nearest of those, as the
    /// contact takes it): `(slave, segment, projection)`, the static solver's prediction of
    /// its Newton step's contacts. On found faces, gaps and normals as the contact measures
    /// them: without, a pre-crack's faces, touching at rest, were predicted nowhere.
    ///
    /// A slave over an edge or vertex of a convex master projects outside every segment around
    /// it until it has gone through: left out, such slaves went through (two gmsh tet4 spheres,
    /// h = 0.045: 2-7 of 100-120 at each of nine iterations), and the line search cut it back.
    pub fn open_gaps(&self, bodies: &[Body]) -> Vec<(u32, u32, Projection)> {
        let sb = bodies[self.slave].as_pd().expect("slave is deformable");
        let shift = self.shift.clone();
        let view = self.view(bodies, &shift);
        let planes = shared_planes(sb, view);
        let edge_margin = self.edge_margin();
        // On a crack's faces, as the contact chooses: inside first, then the nearest.
        let rank = |outside: f64| match edge_margin > 0.0 {
            true => f64::from(u8::from(outside > 0.0)),
            false => outside,
        };
        (0..self.slaves.len())
            .into_par_iter()
            .filter_map(|k| {
                let s = self.slaves[k];
                if self.held[k] != NO_SEGMENT {
                    return None;
                }
                let p = self.slave_point(sb, s);
                let facing = self.facing_normal(sb, s);
                self.candidates(k)
                    .iter()
                    .filter_map(|&seg| {
                        let (mut pr, outside) =
                            self.project_from_rest(sb, view, &planes, (s, p, seg))?;
                        pr.normal = self.smooth_normal(view, seg, &pr);
                        (outside <= (0.1 * pr.gap).max(edge_margin)
                            && pr.gap >= 0.0
                            && pr.gap < 2.0 * self.spacing
                            && facing.dot(&pr.normal) < 0.0)
                            .then_some((seg, pr, rank(outside)))
                    })
                    .min_by(|a, b| a.2.total_cmp(&b.2).then(a.1.gap.total_cmp(&b.1.gap)))
                    .map(|(seg, pr, _)| (s, seg, pr))
            })
            .collect()
    }
}
