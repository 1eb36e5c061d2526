//! Contact between the two faces of a body's pre-crack (docs/FRACTURE.md, "Contact on new
//! surfaces"; the faces themselves: [`crate::case::crack_faces`]): a pass of the body against
//! itself whose slaves are the face particles of each side and whose segments are the other
//! side's, every face particle moved onto the crack plane.

use super::{ContactLaw, ContactPass};
use crate::body::Body;
use crate::math::Vec3;

/// How far beyond the other face's edge a crack's face particle still presses on it, in
/// spacings ([`ContactPass::crack`]).
pub const CRACK_EDGE_MARGIN: f64 = 0.25;

/// The two faces of a pre-crack in one pass.
#[derive(Clone, Debug)]
pub(super) struct CrackSides {
    /// Per slave, its side (0 or 1).
    pub(super) slave_side: Vec<u8>,
    /// Per segment of the master body, its side (`u8::MAX`: not of this crack).
    pub(super) segment_side: Vec<u8>,
    /// Whether a slave presses beyond the other face's edge ([`CRACK_EDGE_MARGIN`]): a
    /// crack's faces, moved onto its plane, meet edge to edge.
    pub(super) edge_margin: bool,
}

impl ContactPass {
    /// The pass that presses the two faces of a body's pre-crack together
    /// ([`crate::case::crack_faces`]): the face particles of each side are slaves against the
    /// other side's segments, with the weight of a two-pass pair, and every face particle,
    /// slave point and master node alike, is moved onto the crack plane by a fixed offset, so
    /// that the faces touch where the body was whole.
    pub fn crack(bodies: &[Body], body: usize, faces: usize, law: ContactLaw) -> ContactPass {
        let pd = bodies[body].as_pd().expect("a cracked body is deformable");
        let f = &pd.crack_faces[faces];
        let mut slaves: Vec<(u32, u8)> = f.particles[0]
            .iter()
            .map(|&p| (p, 0))
            .chain(f.particles[1].iter().map(|&p| (p, 1)))
            .collect();
        slaves.sort_unstable();
        slaves.dedup_by_key(|s| s.0);
        let segments = pd.segments().len();
        let segment_side: Vec<u8> = (0..segments)
            .map(|s| f.side_of_segment(s).unwrap_or(u8::MAX))
            .collect();
        let mut pass = ContactPass::new_with(
            bodies,
            body,
            body,
            law,
            0.5,
            slaves.iter().map(|s| s.0).collect(),
            |s| segment_side[s] != u8::MAX,
        );
        pass.crack = Some(CrackSides {
            slave_side: slaves.iter().map(|s| s.1).collect(),
            segment_side,
            edge_margin: true,
        });
        // Each face particle moved onto the crack plane: the two faces meet there, as the
        // body did before the cut.
        let mut shift = vec![Vec3::zeros(); pd.len()];
        for &(p, _) in &slaves {
            let x = pd.reference[p as usize];
            shift[p as usize] = -f.normal * f.normal.dot(&(x - f.point));
        }
        pass.reference_normals =
            super::normal::reference_normals(super::MasterView::Shifted(pd, &shift));
        pass.shift = std::sync::Arc::new(shift);
        pass
    }

    /// The pass that keeps a body's pieces apart: a mesh of solids that share no node (a
    /// ball and a plate in one file) is one body whose pieces no bond joins
    /// ([`crate::case::neighbours::BondList::components`]), and each piece's surface
    /// particles are slaves against the other pieces' segments, with the weight of a
    /// two-pass pair (each piece is the others' master as well). `piece`: each particle's.
    pub fn pieces(bodies: &[Body], body: usize, piece: &[u32], law: ContactLaw) -> ContactPass {
        let pd = bodies[body].as_pd().expect("checked deformable");
        let slaves: Vec<u32> = (0..pd.len() as u32)
            .filter(|&i| pd.case.surface.is_surface[i as usize])
            .collect();
        let side = |p: u32| piece[p as usize].min(u8::MAX as u32 - 1) as u8;
        let segment_side: Vec<u8> = pd.segments().iter().map(|s| side(s.nodes[0])).collect();
        let mut pass =
            ContactPass::new_with(bodies, body, body, law, 0.5, slaves.clone(), |_| true);
        pass.crack = Some(CrackSides {
            slave_side: slaves.iter().map(|&p| side(p)).collect(),
            segment_side,
            edge_margin: false,
        });
        pass
    }

    /// Whether this pass presses the faces of a pre-crack together ([`ContactPass::crack`]).
    pub fn is_crack(&self) -> bool {
        self.crack.as_ref().is_some_and(|c| c.edge_margin)
    }

    /// Whether this pass keeps a body's pieces apart ([`ContactPass::pieces`]).
    pub fn is_pieces(&self) -> bool {
        self.crack.as_ref().is_some_and(|c| !c.edge_margin)
    }
}
