//! A PD case: a mesh turned into particles, bonds, corrections, surface and master segments
//! (METHOD.md §1-4). This is what `pdcontact convert` writes and what each deformable body of a
//! scene is built from.
//!
//! The stage's modules, in the order the data takes them:
//!
//! | step | module |
//! |---|---|
//! | built-in hex8 shapes (meshes made in memory) | [`generators`] |
//! | particles, volumes, spacing | [`discretize`](mod@discretize) |
//! | the surface layer's volume per area | [`surface_layer`] |
//! | local spacing of a graded mesh | [`spacing`](mod@spacing) |
//! | cell lists, bond families | [`neighbours`] |
//! | the bond-force pass, each pair once | [`pairs`] |
//! | volume and surface correction | [`correction`] |
//! | eigenvalue surface detection | [`surface`] |
//! | master segments, tributary areas | [`segments`] |
//! | the assembled case ([`PdCase`]), symmetry ghosts | this module |

pub mod correction;
pub mod crack_faces;
pub mod discretize;
pub mod generators;
pub mod neighbours;
pub mod pairs;
pub mod part;
pub mod segments;
pub mod sight;
pub mod skin;
pub mod spacing;
pub mod surface;
pub mod surface_layer;
pub mod unbonded;

use std::time::Instant;

use pdcontact_importers::{boundary_faces, FaceSet, Mesh, RefineRefusal};

use crate::case::correction::{
    surface_correction_with, CorrectionMethod, Horizon, SurfaceCorrection,
};
use crate::case::discretize::{discretize, Discretization};
use crate::case::neighbours::{build_bond_rows, BondList, Reach};
use crate::case::part::CasePart;
use crate::case::segments::{master_segments, SegmentSet};
use crate::case::skin::{skin_correction, SkinCorrection, SkinInput};
use crate::case::surface::{detect_surface, SurfaceDetection, NORMAL_KERNEL_WIDTH};
use crate::case::surface_layer::even_surface_layer;
pub use crate::case::surface_layer::SurfaceVolume;
use crate::error::{Error, Result};
use crate::math::Vec3;

/// Default horizon factor `m` (δ = m·Δ).
pub const DEFAULT_HORIZON_FACTOR: f64 = 3.0;

/// A symmetry plane `x_axis = at`: the body is mirrored across it (METHOD.md §6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SymmetryPlane {
    /// 0, 1 or 2 for x, y, z.
    pub axis: usize,
    pub at: f64,
}

/// A point and its mirror images across the symmetry planes (each subset of them), each with
/// the bit mask of the planes that made it (0 for the point itself). A point on a plane is its
/// own image there and is not repeated.
pub fn mirror_images(p: Vec3, planes: &[SymmetryPlane]) -> Vec<(Vec3, u32)> {
    let mut out = vec![(p, 0)];
    for mask in 1u32..(1 << planes.len()) {
        let mut y = p;
        let mut moved = true;
        for (k, pl) in planes.iter().enumerate() {
            if mask & (1 << k) != 0 {
                moved &= (y[pl.axis] - pl.at).abs() > 1e-9 * (1.0 + pl.at.abs());
                y[pl.axis] = 2.0 * pl.at - y[pl.axis];
            }
        }
        if moved {
            out.push((y, mask));
        }
    }
    out
}

/// A direction (a normal, a force) as the mirror image of `mask` sees it: each reflection
/// flips its component along the plane's axis.
pub fn mirror_direction(mut v: Vec3, mask: u32, planes: &[SymmetryPlane]) -> Vec3 {
    for (k, pl) in planes.iter().enumerate() {
        if mask & (1 << k) != 0 {
            v[pl.axis] = -v[pl.axis];
        }
    }
    v
}

/// Mirror images ("ghost particles") of a body across its symmetry planes.
///
/// A particle within reach of a plane bonds to the images of its neighbours across it, so
/// that a half (or quarter) model carries the neighbourhoods of the whole body. Image `g`
/// reflects particle `source[g]` across the planes in the bit mask `mask[g]`; it is indexed
/// `n + g` in the bond partner arrays, after the `n` real particles. Images have no bonds.
#[derive(Clone, Debug, Default)]
pub struct Ghosts {
    pub planes: Vec<SymmetryPlane>,
    pub source: Vec<u32>,
    pub mask: Vec<u8>,
    /// Per real particle: bit mask of the planes it lies on.
    pub on_plane: Vec<u8>,
}

impl Ghosts {
    /// Reflects a point across the planes of `mask`.
    #[inline]
    pub fn reflect(&self, mut p: Vec3, mask: u8) -> Vec3 {
        for (k, plane) in self.planes.iter().enumerate() {
            if mask & (1 << k) != 0 {
                p[plane.axis] = 2.0 * plane.at - p[plane.axis];
            }
        }
        p
    }

    /// Real positions followed by their images.
    pub fn extend_positions(&self, real: &[Vec3], out: &mut Vec<Vec3>) {
        out.clear();
        out.extend_from_slice(real);
        out.extend(
            self.source
                .iter()
                .zip(&self.mask)
                .map(|(&s, &m)| self.reflect(real[s as usize], m)),
        );
    }

    /// Real values followed by their sources' values.
    pub fn extend<T: Copy>(&self, real: &[T]) -> Vec<T> {
        let mut v = real.to_vec();
        v.extend(self.source.iter().map(|&s| real[s as usize]));
        v
    }

    /// The real particle behind index `j` (itself, or an image's source).
    #[inline]
    pub fn source_of(&self, j: usize, n: usize) -> usize {
        if j < n {
            j
        } else {
            self.source[j - n] as usize
        }
    }

    /// The share of a particle that its model holds: ½ per symmetry plane it lies on (no `powi`).
    pub fn share(&self, i: usize) -> f64 {
        f64::from_bits((1023 - u64::from(self.on_plane.get(i).map_or(0, |m| m.count_ones()))) << 52)
    }

    /// Volumes as bond partners see them: a particle on a symmetry plane holds only its
    /// share of a volume that lies on both sides; its partners see the whole. (Its own bonds
    /// keep its share, so the pair weights differ; the mirrored pairs restore the balance.)
    pub fn partner_volumes(&self, volume: &[f64]) -> Vec<f64> {
        let whole: Vec<f64> = volume
            .iter()
            .enumerate()
            .map(|(i, v)| v / self.share(i))
            .collect();
        self.extend(&whole)
    }

    /// Images of the particles within `reach` of the planes.
    fn build(planes: &[SymmetryPlane], position: &[Vec3], reach: f64, tol: f64) -> Ghosts {
        let on_plane: Vec<u8> = position
            .iter()
            .map(|p| {
                planes
                    .iter()
                    .enumerate()
                    .filter(|(_, pl)| (p[pl.axis] - pl.at).abs() <= tol)
                    .fold(0u8, |m, (k, _)| m | (1 << k))
            })
            .collect();
        let mut g = Ghosts {
            planes: planes.to_vec(),
            on_plane,
            ..Default::default()
        };
        for mask in 1u8..(1 << planes.len()) {
            for (i, p) in position.iter().enumerate() {
                // An image across a plane the particle lies on is the particle itself.
                if g.on_plane[i] & mask != 0 {
                    continue;
                }
                let near = planes
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| mask & (1 << k) != 0)
                    .all(|(_, pl)| (p[pl.axis] - pl.at).abs() <= 0.5 * reach);
                if near {
                    g.source.push(i as u32);
                    g.mask.push(mask);
                }
            }
        }
        g
    }
}

/// Whether the horizon follows an imported mesh's local spacing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum HorizonKind {
    /// `δ_ij = m s_ij` from the particles' local spacings ([`spacing::graded_spacing`]) where
    /// the spacing is the mesh's own (no `spacing` given); `δ = mΔ` for a given spacing or a
    /// generated body.
    #[default]
    Local,
    /// `δ = mΔ` for every bond (the paper's).
    Uniform,
}

/// Which nodes of a second-order mesh become particles (METHOD.md §1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SecondOrder {
    /// The corner nodes only: a tet10 is the tet4 of its corners (METHOD.md §1's default).
    #[default]
    Corners,
    /// Every node of a tet10 or hex20: a tet10 is cut at its mid-edge nodes into eight tet4, a
    /// hex20 into eight hex8 with a node added at the centre of each face and of the element
    /// ([`pdcontact_importers::split_second_order`]). The particles are then all the mesh's
    /// nodes, at half the spacing, and the boundary's mid-edge nodes, which gmsh puts on the
    /// curved geometry, are particles and segment corners. Wedge15 and pyramid13 keep their
    /// corners. Measured on gmsh's spheres: docs/VALIDATION.md, "Second-order meshes".
    AllNodes,
}

impl SecondOrder {
    /// The mesh whose corner nodes are the particles under this choice. Where `AllNodes` leaves
    /// second-order elements whole (none to cut, or wedge15, pyramid13, a missing mid-edge
    /// node), the mesh's warnings say so: `run` prints them.
    pub fn apply(self, mesh: Mesh) -> Mesh {
        match self {
            SecondOrder::Corners => mesh,
            SecondOrder::AllNodes => match pdcontact_importers::split_second_order(&mesh) {
                Some(mut split) => {
                    let kept = split.solids().filter(|e| e.kind != e.kind.linear()).count();
                    if kept > 0 {
                        split.warnings.push(format!(
                            "second_order = \"all-nodes\": {kept} second-order elements keep their corners only (wedge15 and pyramid13 are not cut, nor an element whose file leaves out a mid-edge node)"
                        ));
                    }
                    split
                }
                None => {
                    let mut mesh = mesh;
                    mesh.warnings.push(
                        "second_order = \"all-nodes\" has no effect: the mesh has no tet10 or hex20 with all their nodes, so its corners are the particles as before".to_string(),
                    );
                    mesh
                }
            },
        }
    }
}

/// The most levels of [`refine`] a body may ask for: each multiplies the particles by about
/// seven.
pub const MAX_REFINE: u32 = 3;

/// `mesh` with every tet and hex cut into eight at its edges' midpoints, `levels` times
/// ([`pdcontact_importers::refine_uniform`]): twice the spacings across a contact per level, at
/// about seven times the particles. Where the mesh cannot be cut (wedges or pyramids, no tet
/// or hex), it is returned as it is and its warnings say why; where it is second order and its
/// corners alone are cut, they say that its own mid-edge nodes would do better.
pub fn refine(mesh: Mesh, levels: u32) -> Mesh {
    let mut mesh = mesh;
    if levels > 0 && pdcontact_importers::has_splittable(&mesh) {
        mesh.warnings.push(
            "refine: the mesh is second order and its corners are cut at straight midpoints; second_order = \"all-nodes\" uses its own mid-edge nodes, which lie on the geometry, for the same count".to_string(),
        );
    }
    for _ in 0..levels {
        mesh = match pdcontact_importers::refine_uniform(&mesh) {
            Ok(fine) => fine,
            Err(why) => {
                mesh.warnings.push(match why {
                    RefineRefusal::NoSolids => {
                        "refine has no effect: the mesh has no tet or hex to cut".to_string()
                    }
                    RefineRefusal::WedgesOrPyramids(n) => format!(
                        "refine has no effect: the mesh has {n} wedges or pyramids, which are not cut (cut tets or hexes beside them would leave unmatched faces inside the body)"
                    ),
                });
                return mesh;
            }
        };
    }
    mesh
}

/// The mesh's nodes, warnings and named sets, each set as its nodes (an element set's are
/// its elements' nodes, as [`Mesh::set_nodes`] gives them), without its elements.
fn nodes_and_sets(mesh: Mesh) -> Mesh {
    let sets = mesh
        .sets
        .iter()
        .map(|s| pdcontact_importers::NamedSet {
            name: s.name.clone(),
            kind: s.kind,
            nodes: Some(mesh.set_nodes(s)),
            elements: None,
        })
        .collect();
    Mesh {
        node_ids: mesh.node_ids,
        coords: mesh.coords,
        warnings: mesh.warnings,
        sets,
        ..Mesh::new()
    }
}

/// A first-order mesh of tets and hexes only, which [`refine`] cuts (second-order elements
/// have `second_order = "all-nodes"` instead).
pub fn refinable_mesh(mesh: &Mesh) -> bool {
    mesh.solids().all(|e| {
        matches!(
            e.kind,
            pdcontact_importers::ElementKind::Tet4 | pdcontact_importers::ElementKind::Hex8
        )
    })
}

/// Options of the discretisation.
#[derive(Clone, Debug)]
pub struct CaseOptions {
    /// Grid spacing Δ; `None` takes the lattice spacing of the particles' median volume.
    pub spacing: Option<f64>,
    /// Horizon factor m.
    pub horizon_factor: f64,
    /// How to compute surface correction factors.
    pub correction: CorrectionMethod,
    /// Symmetry planes: the body's mirror images across them complete its neighbourhoods.
    pub symmetry: Vec<SymmetryPlane>,
    /// One horizon, or one per bond from the local spacing.
    pub horizon: HorizonKind,
    /// Which nodes of a second-order mesh become particles.
    pub second_order: SecondOrder,
    /// Levels of uniform refinement before the nodes become particles ([`refine`]); 0 keeps
    /// the mesh's nodes.
    pub refine: u32,
    /// Which volume a surface particle carries ([`SurfaceVolume`]).
    pub surface_volume: SurfaceVolume,
    /// Stiffen the surface row's normal bonds ([`skin`]; on by default).
    pub skin_correction: bool,
    /// Keep the mesh's elements in the case (the default). `false` for a model's bodies, which
    /// read of their mesh only its nodes and sets once the particles and faces are made: the
    /// elements go before the bonds ([`PdCase::release_elements`]), and with them most of a
    /// large mesh (a tet mesh's elements are about 200 bytes a node); the surface's
    /// eigenvalues go once it is chosen ([`SurfaceDetection::release_eigenvalues`]).
    pub keep_elements: bool,
    /// The mesh's pieces are the parts of an assembly (`convert` of a mesh whose sets name
    /// them): nodes of two pieces on top of each other are not refused.
    pub pieces_apart: bool,
}

impl Default for CaseOptions {
    fn default() -> Self {
        CaseOptions {
            spacing: None,
            horizon_factor: DEFAULT_HORIZON_FACTOR,
            correction: CorrectionMethod::Balanced,
            symmetry: Vec::new(),
            horizon: HorizonKind::Local,
            second_order: SecondOrder::Corners,
            refine: 0,
            surface_volume: SurfaceVolume::PerArea,
            skin_correction: true,
            keep_elements: true,
            pieces_apart: false,
        }
    }
}

/// Wall time of each stage, in seconds.
#[derive(Clone, Copy, Debug, Default, serde::Serialize)]
pub struct StageTimes {
    pub discretize: f64,
    pub neighbours: f64,
    pub surface: f64,
    pub correction: f64,
    pub segments: f64,
}

/// Agreement between eigenvalue surface particles and mesh boundary nodes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SurfaceAgreement {
    pub surface_particles: usize,
    pub boundary_nodes: usize,
    /// Boundary nodes the eigenvalue method did not flag.
    pub missed: usize,
    /// Interior nodes the eigenvalue method flagged.
    pub extra: usize,
}

/// Everything the pipeline derives from one mesh.
#[derive(Clone, Debug)]
pub struct PdCase {
    pub mesh: Mesh,
    pub faces: FaceSet,
    pub particles: Discretization,
    /// Horizon δ = mΔ (where the horizon is local, the reference of the micromodulus; each
    /// bond's own is `m s_ij`).
    pub horizon: f64,
    /// Local spacing `s_i` per particle where the horizon follows it ([`HorizonKind::Local`]
    /// on an imported mesh), else `None` (Δ everywhere).
    pub local_spacing: Option<Vec<f64>>,
    pub horizon_factor: f64,
    /// Which nodes of a second-order mesh are particles (`mesh` is the split mesh for
    /// [`SecondOrder::AllNodes`]).
    pub second_order: SecondOrder,
    /// Levels of uniform refinement applied to the mesh ([`refine`]; `mesh` is the cut mesh).
    pub refine: u32,
    /// Surface particles whose volume was evened to their area ([`even_surface_layer`]).
    pub surface_layer_evened: usize,
    pub bonds: BondList,
    /// Bonds removed because they crossed a slot, notch or crack of the mesh ([`sight`]).
    pub bonds_across_gaps: usize,
    pub surface: SurfaceDetection,
    pub correction: SurfaceCorrection,
    /// The skin correction's factors, where it was asked for ([`skin`]).
    pub skin: Option<SkinCorrection>,
    pub segments: SegmentSet,
    /// Mirror images across symmetry planes (empty without planes).
    pub ghosts: Ghosts,
    /// This rank's part, where the case was built as one ([`PdCase::build_part`]): then
    /// `bonds` holds the rows of its own particles and of its halo only.
    pub part: Option<CasePart>,
    /// Whether the mesh had second-order elements to split and was first-order tets and
    /// hexes alone, where its elements were let go ([`PdCase::release_elements`]).
    pub elements_released: Option<[bool; 2]>,
    /// Where the bonds leave a solid of the mesh in pieces ([`unbonded`]; `run` refuses it).
    pub split: Option<unbonded::SolidSplit>,
    pub times: StageTimes,
}

impl PdCase {
    /// Second-order elements of the file whose corners alone are particles
    /// ([`SecondOrder::Corners`] on a mesh with a tet10 or hex20 to cut).
    pub fn corners_of_second_order(&self) -> bool {
        self.second_order == SecondOrder::Corners
            && self.elements_released.map_or_else(
                || pdcontact_importers::has_splittable(&self.mesh),
                |[splittable, _]| splittable,
            )
    }

    /// A first-order mesh of tets and hexes that was not refined: `refine = 1` would cut it.
    pub fn refinable(&self) -> bool {
        self.refine == 0
            && self
                .elements_released
                .map_or_else(|| refinable_mesh(&self.mesh), |[_, refinable]| refinable)
    }

    /// Keeps of the mesh its nodes (their numbers name particles in messages, their box sizes
    /// the scene) and its warnings. Once a model is made, the elements and sets have given
    /// their particles, faces and loads, and they are most of a large mesh (a run lets them
    /// go: on a 1M-node tet mesh about 180 MB on every rank); what the case tells of them
    /// later ([`Self::corners_of_second_order`], [`Self::refinable`]) it remembers.
    pub fn release_elements(&mut self) {
        if self.elements_released.is_none() {
            self.elements_released = Some([
                pdcontact_importers::has_splittable(&self.mesh),
                refinable_mesh(&self.mesh),
            ]);
        }
        let mesh = std::mem::take(&mut self.mesh);
        self.mesh = Mesh {
            node_ids: mesh.node_ids,
            coords: mesh.coords,
            warnings: mesh.warnings,
            ..Mesh::new()
        };
    }

    /// Builds the case from a mesh.
    pub fn build(mesh: Mesh, options: CaseOptions) -> Result<PdCase> {
        PdCase::build_part(mesh, options, None, false)
    }

    /// Directed bonds of the whole case (over all ranks where it is a part).
    pub fn bond_count(&self) -> usize {
        self.part.as_ref().map_or(self.bonds.len(), |p| p.bonds)
    }

    /// [`PdCase::build`] on a rank of `comm` (collective): as the rank's part where `in_parts`
    /// and there are several ranks ([`part`]), the same case, bit for bit, in the rows this
    /// rank needs; else whole. Either way a case that would take the process past the memory
    /// it may use is refused before its bonds are made ([`part::check_memory`]; `in_parts`
    /// in one process: a run over ranks would build it so, which the refusal advises).
    pub fn build_part(
        mesh: Mesh,
        options: CaseOptions,
        comm: Option<std::sync::Arc<dyn crate::parallel::Comm>>,
        in_parts: bool,
    ) -> Result<PdCase> {
        if !(options.horizon_factor > 0.0 && options.horizon_factor.is_finite()) {
            return Err(Error::input(format!(
                "horizon factor must be positive, got {}",
                options.horizon_factor
            )));
        }
        if options.refine > MAX_REFINE {
            return Err(Error::input(format!(
                "refine = {}: expected at most {MAX_REFINE} levels (each cuts every element into eight, about seven times the particles)",
                options.refine
            )));
        }
        let mut times = StageTimes::default();
        let t = Instant::now();
        let mut mesh = refine(options.second_order.apply(mesh), options.refine);
        mesh.shrink_to_fit();
        let mut particles = discretize(&mesh, options.spacing)?;
        let spacing = particles.spacing;
        let all_faces = boundary_faces(&mesh);
        let mut faces = all_faces.clone();
        if !options.symmetry.is_empty() {
            // Faces on a symmetry plane are cuts, not surfaces: the images cover them.
            let tol = 1e-6 * spacing;
            faces.boundary.retain(|f| {
                !options.symmetry.iter().any(|pl| {
                    f.nodes
                        .iter()
                        .all(|&n| (mesh.coords[n as usize][pl.axis] - pl.at).abs() <= tol)
                })
            });
        }
        let surface_layer_evened = match options.surface_volume {
            SurfaceVolume::Lumped => 0,
            SurfaceVolume::PerArea => {
                let mut volume = vec![0.0; mesh.node_count()];
                for (&node, &v) in particles.node.iter().zip(&particles.volume) {
                    volume[node as usize] = v;
                }
                let evened =
                    even_surface_layer(&mesh, &mut volume, &faces.boundary, &all_faces.boundary);
                for (v, &node) in particles.volume.iter_mut().zip(&particles.node) {
                    *v = volume[node as usize];
                }
                evened
            }
        };
        drop(all_faces);
        // Element pairs that the bonds may not reach (beyond ¾ of their uniform reach: a
        // hex's diagonals stay below), to find the solids that the horizon leaves in pieces.
        let long_pairs = unbonded::long_pairs(
            &mesh,
            &particles.particle_of_node,
            &particles.position,
            0.75 * (options.horizon_factor + 0.5) * spacing,
        );
        let mesh_pieces =
            unbonded::mesh_pieces(&mesh, &particles.node, spacing, options.pieces_apart);
        // Particles, faces and volumes are made: what the model reads of the mesh from here
        // on is its nodes and its sets.
        let (mesh, elements_released) = if options.keep_elements {
            (mesh, None)
        } else {
            let released = [
                pdcontact_importers::has_splittable(&mesh),
                refinable_mesh(&mesh),
            ];
            let mesh = nodes_and_sets(mesh);
            // The elements' pages back to the system, not kept for later allocations.
            crate::parallel::memory::give_back_free_pages();
            (mesh, Some(released))
        };
        times.discretize = t.elapsed().as_secs_f64();
        let horizon = options.horizon_factor * spacing;

        let t = Instant::now();
        let local_spacing = if options.spacing.is_none() && options.horizon == HorizonKind::Local {
            spacing::graded_spacing(&particles.position, &particles.completed_volume(), spacing)
        } else {
            None
        };
        // Bonds reach δ + r (r = Δ/2, Eq. 10), or δ_ij + r_ij (the mean of the two particles'
        // reaches); the 1e-9 keeps lattice bonds exactly at the edge. Mirror images lie as far
        // from their planes as the bonds and the surface's widest kernel reach (3h at
        // h = 2 s_i, taking s_i = Δ).
        let reach_of = |s: f64| (options.horizon_factor + 0.5) * s * (1.0 + 1e-9);
        let reach = match &local_spacing {
            Some(s) => s.iter().copied().fold(0.0, f64::max),
            None => spacing,
        };
        let reach = reach_of(reach);
        let ghosts = Ghosts::build(
            &options.symmetry,
            &particles.position,
            2.0 * reach.max(3.0 * NORMAL_KERNEL_WIDTH * spacing),
            1e-6 * spacing,
        );
        let mut position = Vec::new();
        ghosts.extend_positions(&particles.position, &mut position);
        let extended_spacing = local_spacing.as_ref().map(|s| ghosts.extend(s));
        let reaches: Option<Vec<f64>> = extended_spacing
            .as_ref()
            .map(|s| s.iter().map(|&x| reach_of(x)).collect());
        let bond_reach = match &reaches {
            Some(r) => Reach::PerPoint(r),
            None => Reach::Uniform(reach),
        };
        let n = particles.len();
        let comm = comm.filter(|c| c.size() > 1);
        let parts = comm.as_ref().filter(|_| in_parts).map(|c| c.size());
        part::check_memory(
            n,
            options.horizon_factor,
            parts.map_or(1.0, |k| 1.08 / k as f64),
            comm.as_ref(),
            in_parts,
        )?;
        let (bonds, mut part) = match comm.filter(|_| in_parts) {
            None => (build_bond_rows(&position, n, bond_reach, |_| true), None),
            Some(comm) => {
                let (bonds, part) = part::rows_of_rank(&position, n, bond_reach, &ghosts, comm);
                (bonds, Some(part))
            }
        };
        let owned = part.as_ref().map_or(0..n, CasePart::owned);
        // A slot, notch or crack the mesh has, narrower than the horizon, and where the
        // mesh's pieces touch: the bonds across go, before the corrections see its faces.
        let gaps = sight::bonds_across_gaps(
            &faces,
            &mesh.coords,
            &ghosts,
            &position,
            &bonds,
            reach,
            spacing,
        );
        let across_gaps = unbonded::and_between_pieces(gaps, &bonds, mesh_pieces.as_ref(), &ghosts);
        let bonds = if across_gaps.is_empty() {
            bonds
        } else {
            bonds.without(&across_gaps)
        };
        sight::refuse_coincident(&bonds, &owned, &particles, &mesh, part.as_ref())?;
        let mine = |i: &&(u32, u32)| owned.contains(&(i.0 as usize));
        let cut = across_gaps.iter().filter(mine).count();
        let bonds_across_gaps = part.as_ref().map_or(cut, |p| p.total(cut));
        if let Some(p) = &mut part {
            let mine = bonds.offsets[owned.end] - bonds.offsets[owned.start];
            p.bonds = p.total(mine);
        }
        times.neighbours = t.elapsed().as_secs_f64();

        let t = Instant::now();
        // Completed volumes V/ω: for a particle on a symmetry plane the share the model holds
        // cancels between V and ω, so they are the whole particle's, as its images need.
        let completed = particles.completed_volume();
        // The pieces no bond joins (solids of the mesh that share no node), each particle's
        // and each image's; one piece, or a decomposed run's rows of one rank, none.
        let mut split = None;
        let piece: Vec<u32> = match &part {
            None => {
                let (label, sizes) = bonds.components(|_| true);
                if sizes.len() > 1 {
                    split = unbonded::split(
                        &long_pairs,
                        &bonds,
                        &label,
                        &mesh.node_ids,
                        &particles.node,
                        spacing,
                    );
                    (0..position.len())
                        .map(|j| label[ghosts.source_of(j, particles.len())])
                        .collect()
                } else {
                    Vec::new()
                }
            }
            Some(_) => Vec::new(),
        };
        let mut surface = detect_surface(
            &position,
            &ghosts.extend(&completed),
            particles.len(),
            spacing,
            &piece,
        );
        if !options.keep_elements {
            // What chose the surface particles, which only `convert` writes out.
            surface.release_eigenvalues();
        }
        times.surface = t.elapsed().as_secs_f64();

        // A spacing far below the mesh's own leaves particles without partners: such a body has
        // no stiffness and the first step divides by zero.
        let lonely = owned.clone().filter(|&i| bonds.range(i).is_empty()).count();
        let lonely = part.as_ref().map_or(lonely, |p| p.total(lonely));
        if particles.len() > 1 && 2 * lonely > particles.len() {
            return Err(Error::input(format!(
                "{lonely} of {} particles have no bond: the horizon δ = {:.4e} (spacing {spacing:.4e} × horizon factor {}) is shorter than the distance between the mesh's nodes; give a spacing near the mesh's element size, or none to use the lattice spacing of its particles' median volume",
                particles.len(),
                horizon,
                options.horizon_factor
            )));
        }

        let t = Instant::now();
        let source: Vec<usize> = (0..position.len())
            .map(|j| ghosts.source_of(j, particles.len()))
            .collect();
        let partner_volume = ghosts.partner_volumes(&particles.volume);
        let mut correction = surface_correction_with(
            &position,
            &partner_volume,
            &source,
            &bonds,
            &Horizon {
                radius: horizon,
                spacing,
                local: extended_spacing.as_deref(),
            },
            options.correction,
            part.as_ref(),
        );
        times.correction = t.elapsed().as_secs_f64();

        let t = Instant::now();
        let segments = master_segments(&faces, &particles, &surface.is_surface);
        times.segments = t.elapsed().as_secs_f64();

        // After the segments: the skin correction balances each surface particle against the
        // area its contact force acts on (its time counts as the correction's).
        let t = Instant::now();
        let skin = options.skin_correction.then(|| {
            let input = SkinInput {
                position: &position,
                partner_volume: &partner_volume,
                volume: &particles.volume,
                is_surface: &surface.is_surface,
                normal: &surface.normal,
                pressure_area: &segments.pressure_area,
                ghosts: &ghosts,
                horizon,
            };
            skin_correction(&input, &bonds, &mut correction.bond_factor, part.as_ref())
        });
        times.correction += t.elapsed().as_secs_f64();

        Ok(PdCase {
            mesh,
            faces,
            particles,
            horizon,
            local_spacing,
            horizon_factor: options.horizon_factor,
            second_order: options.second_order,
            refine: options.refine,
            surface_layer_evened,
            bonds,
            bonds_across_gaps,
            surface,
            correction,
            skin,
            segments,
            ghosts,
            part,
            elements_released,
            split,
            times,
        })
    }

    /// Compares eigenvalue surface particles with mesh boundary nodes.
    pub fn surface_agreement(&self) -> SurfaceAgreement {
        let mut a = SurfaceAgreement::default();
        for (&s, &b) in self
            .surface
            .is_surface
            .iter()
            .zip(&self.segments.boundary_node)
        {
            a.surface_particles += s as usize;
            a.boundary_nodes += b as usize;
            a.missed += (b && !s) as usize;
            a.extra += (s && !b) as usize;
        }
        a
    }
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod symmetry_tests;
