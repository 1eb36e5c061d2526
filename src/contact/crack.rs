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

    /// Whether this pass presses the faces of a pre-crack together ([`ContactPass::crack`]).
    pub fn is_crack(&self) -> bool {
        self.crack.is_some()
    }
}
