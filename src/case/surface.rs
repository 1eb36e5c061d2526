//! Surface particles by the eigenvalue method, with outward normals (paper Eqs. 11-16,
//! METHOD.md §3).
//!
//! `L_i = Σ_j (x_j − x_i) ⊗ ∇_i W_ij V_j` tends to the identity inside a body. Its smallest
//! eigenvalue λ is ≈ 1 inside, ≈ 0.5 on a flat face and → 0 for an isolated particle; a particle
//! with `λ ≤ 0.75` is on the surface (Eq. 15). The outward normal is
//! `v_i = −L_i⁻¹ Σ_j ∇_i W_ij V_j`, normalised (Eq. 16).
//!
//! The kernel is the modified Gaussian with the bracket where METHOD.md puts it (the paper's
//! Eq. 12 misplaces it): `W(r,h) = α (exp(−(r/h)²) − c0)/(1 − c1)` for `r ≤ 3h`,
//! `c0 = e⁻⁹`, `c1 = 10 c0`, `α = 1/(π^{3/2} h³)`. On a lattice `h = Δ`; on the irregular
//! clouds of unstructured meshes the width follows the local spacing and the test is confirmed
//! at a wider kernel (see [`detect_surface`]): on a lattice the result is the paper's.

use nalgebra::{Matrix3, SymmetricEigen};
use rayon::prelude::*;

use crate::case::neighbours::CellGrid;
use crate::math::Vec3;

/// The threshold of Eq. 15.
pub const SURFACE_LAMBDA: f64 = 0.75;

/// Width of the confirming kernel over the local spacing: `1.5 s_i` (see [`detect_surface`]).
/// Measured on gmsh spheres (docs/VALIDATION.md, "Unstructured meshes"): at `1.1 s` boundary
/// particles of tets split into hexes read above 0.75 (29 missed), at `1.25-1.5 s` none is
/// missed or added, at `1.75 s` and beyond the band under the surface starts to count (19 added).
pub const CONFIRM_KERNEL_WIDTH: f64 = 1.5;

/// Width of the normals' kernel over the local spacing: `2 s_i`. The normal of Eq. 16 is a
/// difference of kernel sums and takes a sparse cloud's quadrature noise at first order: on
/// gmsh's tets split into hexes its mean error is 7° at `1.25 s`, 5° at `1.5 s`, 2.6° at `2 s`.
pub const NORMAL_KERNEL_WIDTH: f64 = 2.0;

/// Reach of the occlusion test over the local spacing, and its cone: a surface particle with
/// another one within `2 s_i` inside the 45° cone about its normal, facing the same way
/// (normals within 45°), lies under the surface rather than on it.
pub const OCCLUSION_RADIUS: f64 = 2.0;
const OCCLUSION_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// The occlusion test leaves alone particles whose `kernel_fill` is under ½.
const OCCLUSION_MIN_FILL: f64 = 0.5;

/// Radius, in global spacings, over which the local spacing is averaged.
const LOCAL_SPACING_RADIUS: f64 = 2.0;

/// Result of surface detection for one body.
#[derive(Clone, Debug, Default)]
pub struct SurfaceDetection {
    /// Smallest eigenvalue of `L_i` at `h = s_i` (Eq. 15): ≈ 1 inside, ½ on a flat face.
    pub lambda_min: Vec<f64>,
    /// Mean eigenvalue of `L_i` at `h = 1.5 s_i` for the candidates (`λ_min ≤ 0.75`), 1 for the
    /// others: the share of the kernel that the body fills, ½ on a flat face, ¼ on an edge.
    pub kernel_fill: Vec<f64>,
    /// `λ_min ≤ 0.75` and `kernel_fill ≤ 0.75`, and no other such particle above it.
    pub is_surface: Vec<bool>,
    /// Outward unit normal (Eq. 16) of a surface particle; zero inside the body.
    pub normal: Vec<Vec3>,
    /// The local spacing `s_i`, the kernel width of Eq. 15 at each particle.
    pub spacing: Vec<f64>,
}

impl SurfaceDetection {
    /// Lets `lambda_min` and `kernel_fill` go (empty after): 16 bytes a particle that the
    /// surface, once chosen, no longer reads.
    pub fn release_eigenvalues(&mut self) {
        self.lambda_min = Vec::new();
        self.kernel_fill = Vec::new();
    }
}

impl SurfaceDetection {
    /// Number of surface particles.
    pub fn count(&self) -> usize {
        self.is_surface.iter().filter(|&&s| s).count()
    }
}

/// `−W'(r)/r` for the modified Gaussian: the factor that turns `r_vec r_vecᵀ` into the
/// kernel-gradient outer product. Zero beyond `3h`. `W` vanishes at `3h` but `W'` does not, and
/// lattice neighbours may lie exactly there: the cutoff is inclusive up to round-off, so that
/// the result does not depend on the last bit of a coordinate.
#[inline]
fn kernel_factor(r: f64, h: f64) -> f64 {
    if r > 3.0 * h * (1.0 + 1e-9) {
        return 0.0;
    }
    let c0 = (-9.0f64).exp();
    let c1 = 10.0 * c0;
    let alpha = 1.0 / (std::f64::consts::PI.powf(1.5) * h * h * h);
    alpha * 2.0 / (h * h) * (-(r / h) * (r / h)).exp() / (1.0 - c1)
}

/// `L_i = Σ_j (x_j − x_i) ⊗ ∇_i W_ij V_j` and `Σ_j ∇_i W_ij V_j` (Eqs. 13, 16) at kernel
/// width `h`.
fn kernel_moments(
    position: &[Vec3],
    volume: &[f64],
    grid: &CellGrid,
    piece: &[u32],
    i: usize,
    h: f64,
) -> (Matrix3<f64>, Vec3) {
    let xi = position[i];
    let mut l = Matrix3::<f64>::zeros();
    let mut grad = Vec3::zeros();
    grid.for_each_candidate(&xi, 3.0 * h * (1.0 + 1e-9), |j| {
        let j = j as usize;
        if j == i || !same_piece(piece, i, j) {
            return;
        }
        let d = position[j] - xi;
        let f = kernel_factor(d.norm(), h);
        if f == 0.0 {
            return;
        }
        // ∇_i W_ij = W'(r) (x_i − x_j)/r = f · (x_j − x_i).
        let g = d * f;
        l += d * g.transpose() * volume[j];
        grad += g * volume[j];
    });
    (l, grad)
}

/// Whether particles `i` and `j` are of one piece (`piece` empty: one piece in all).
#[inline]
fn same_piece(piece: &[u32], i: usize, j: usize) -> bool {
    piece.is_empty() || piece[i] == piece[j]
}

/// The outward normal `−L⁻¹ Σ ∇W V` of Eq. 16, normalised; zero where the kernel sum cancels.
pub(crate) fn outward_normal(l: &Matrix3<f64>, grad: &Vec3, h: f64) -> Vec3 {
    let eig = SymmetricEigen::new(*l);
    // Pseudo-inverse: drop eigen-directions below 1e-6 of the largest.
    let lmax = eig.eigenvalues.max().max(0.0);
    let mut v = Vec3::zeros();
    for k in 0..3 {
        let ev = eig.eigenvalues[k];
        if ev > 1e-6 * lmax && ev > 0.0 {
            let q = eig.eigenvectors.column(k);
            v -= q * (q.dot(grad) / ev);
        }
    }
    let norm = v.norm();
    if norm > 1e-3 / h {
        v / norm
    } else {
        Vec3::zeros()
    }
}

/// Detects the surface among the first `particles` of `position` (the rest are mirror images
/// across symmetry planes, which only serve as neighbours). `volume` holds the completed
/// volumes (`V_i/ω_i`, so that a face particle weighs a whole cell as a lattice one does);
/// `spacing` is the body's grid spacing Δ. `piece` (each particle's and image's, or empty)
/// keeps each piece of a body whose pieces no bond joins (solids of one mesh that share no
/// node) from filling the others' kernels: a piece's face a gap narrower than the kernel's
/// reach from another's is on the surface all the same.
///
/// Three steps, each at a kernel width proportional to the local spacing `s_i` (the mean
/// `V_j^{1/3}` within 2Δ; `s_i = Δ` on a lattice), so that a mesh graded 3:1 sees the same test
/// in its fine and coarse zones:
/// 1. Candidates by Eq. 15 at `h = s_i`: `λ_min(L_i) ≤ 0.75`. On a lattice this is the paper's
///    test and nothing below removes a lattice candidate.
/// 2. Confirmed where the mean eigenvalue `tr L_i / 3` at `h = 1.5 s_i` is ≤ 0.75 too. On a
///    half-space `L = ½ I`, so both read ½ on a flat face, but a sparse cloud under-samples one
///    direction and drags λ_min below 0.75 deep inside (25 % of the interior of gmsh's tets
///    split into hexes, median λ_min 0.81), while the mean at the wider kernel stays above 0.8.
/// 3. The normal of Eq. 16 at `h = 2 s_i`.
/// 4. Dropped where another surface particle lies above it: within `2 s_i`, inside the 45°
///    cone about its normal, with a normal within 45° of its own. A mesh can hold interior
///    nodes a fraction of a spacing under its boundary (the centroids of flat boundary tets
///    split into hexes lie 0.45-0.9 s deep); a kernel cannot tell them from the surface, but
///    they are covered by it, and as slaves they would face the master and never touch it.
///    On a lattice no surface particle has another above it.
pub fn detect_surface(
    position: &[Vec3],
    volume: &[f64],
    particles: usize,
    spacing: f64,
    piece: &[u32],
) -> SurfaceDetection {
    let grid = CellGrid::new(position, 3.0 * spacing);
    let cube_root: Vec<f64> = volume.iter().map(|v| v.max(0.0).cbrt()).collect();
    let window = LOCAL_SPACING_RADIUS * spacing;
    let results: Vec<(f64, f64, Vec3, f64)> = (0..particles)
        .into_par_iter()
        .map(|i| {
            let xi = position[i];
            let (mut sum, mut count) = (0.0, 0usize);
            grid.for_each_candidate(&xi, window, |j| {
                let j = j as usize;
                if (position[j] - xi).norm_squared() <= window * window && same_piece(piece, i, j) {
                    sum += cube_root[j];
                    count += 1;
                }
            });
            let s = sum / count.max(1) as f64;
            let (l, _) = kernel_moments(position, volume, &grid, piece, i, s);
            let lambda = SymmetricEigen::new(l).eigenvalues.min();
            // A candidate by Eq. 15, confirmed by the mean eigenvalue at a wider kernel.
            let fill = if lambda <= SURFACE_LAMBDA {
                let (l, _) =
                    kernel_moments(position, volume, &grid, piece, i, CONFIRM_KERNEL_WIDTH * s);
                l.trace() / 3.0
            } else {
                1.0
            };
            let normal = if fill <= SURFACE_LAMBDA {
                let h = NORMAL_KERNEL_WIDTH * s;
                let (l, grad) = kernel_moments(position, volume, &grid, piece, i, h);
                outward_normal(&l, &grad, h)
            } else {
                Vec3::zeros()
            };
            (lambda, fill, normal, s)
        })
        .collect();
    let flagged: Vec<bool> = results.iter().map(|r| r.1 <= SURFACE_LAMBDA).collect();
    let covered: Vec<bool> = (0..particles)
        .into_par_iter()
        .map(|i| {
            let (n, reach) = (results[i].2, OCCLUSION_RADIUS * results[i].3);
            // Less than half a kernel filled: an edge, a corner or a body a few spacings thin,
            // where the normal cannot tell "above" from "beside".
            if !flagged[i] || n == Vec3::zeros() || results[i].1 < OCCLUSION_MIN_FILL {
                return false;
            }
            let mut covered = false;
            grid.for_each_candidate(&position[i], reach, |j| {
                let j = j as usize;
                if covered || j >= particles || j == i || !flagged[j] || !same_piece(piece, i, j) {
                    return;
                }
                let d = position[j] - position[i];
                let r = d.norm();
                covered = r <= reach
                    && d.dot(&n) > OCCLUSION_COS * r
                    && results[j].2.dot(&n) > OCCLUSION_COS;
            });
            covered
        })
        .collect();
    let is_surface: Vec<bool> = (0..particles).map(|i| flagged[i] && !covered[i]).collect();
    SurfaceDetection {
        lambda_min: results.iter().map(|r| r.0).collect(),
        kernel_fill: results.iter().map(|r| r.1).collect(),
        normal: results
            .iter()
            .zip(&is_surface)
            .map(|(r, &s)| if s { r.2 } else { Vec3::zeros() })
            .collect(),
        is_surface,
        spacing: results.iter().map(|r| r.3).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A simple cubic lattice block of unit cells (the completed volumes of a hex mesh).
    fn lattice(n: usize) -> (Vec<Vec3>, Vec<f64>) {
        let mut p = Vec::new();
        let mut v = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    p.push(Vec3::new(i as f64, j as f64, k as f64));
                    v.push(1.0);
                }
            }
        }
        (p, v)
    }

    #[test]
    fn flat_face_lattice_values() {
        let n = 15;
        let (p, v) = lattice(n);
        let s = detect_surface(&p, &v, p.len(), 1.0, &[]);
        let at = |i: usize, j: usize, k: usize| i + n * (j + n * k);
        let c = n / 2;
        // Eq. 15 at h = Δ: the paper's lattice values.
        let face = s.lambda_min[at(c, c, 0)];
        let first = s.lambda_min[at(c, c, 1)];
        let deep = s.lambda_min[at(c, c, c)];
        assert!((face - 0.50).abs() < 0.02, "face {face}");
        assert!((first - 0.91).abs() < 0.02, "first layer {first}");
        assert!((deep - 1.0).abs() < 0.02, "bulk {deep}");
        // ½ in the normal direction, a little more in-plane, where the face's own row adds.
        let fill = s.kernel_fill[at(c, c, 0)];
        assert!(fill > 0.5 && fill < 0.7, "face fill {fill}");
        // Exactly the six faces, as the paper's test gives on a lattice.
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let on_face = [i, j, k].iter().any(|&a| a == 0 || a == n - 1);
                    assert_eq!(s.is_surface[at(i, j, k)], on_face, "({i}, {j}, {k})");
                }
            }
        }
        // Outward normal of the bottom face is −z; none inside.
        let nrm = s.normal[at(c, c, 0)];
        assert!((nrm - Vec3::new(0.0, 0.0, -1.0)).norm() < 1e-6, "{nrm}");
        assert_eq!(s.normal[at(c, c, c)], Vec3::zeros());
    }

    /// A lattice block whose particles two or more layers deep are moved by up to ±0.3 Δ in
    /// each direction: an irregular cloud on which Eq. 15 alone flags particles inside.
    #[test]
    fn jittered_cloud_finds_exactly_the_faces() {
        let n = 16;
        let (mut p, v) = lattice(n);
        // A fixed integer hash, so that the cloud is the same on every run.
        let jitter = |i: usize, k: usize| {
            let mut x = (3 * i as u64 + k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            x ^= x >> 29;
            x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
            x ^= x >> 32;
            0.6 * ((x % 1_000_000) as f64 / 1e6 - 0.5)
        };
        let last = (n - 1) as f64;
        let on_face = |x: &Vec3| (0..3).any(|k| x[k] == 0.0 || x[k] == last);
        for (i, x) in p.iter_mut().enumerate() {
            if (0..3).all(|k| x[k] >= 2.0 && x[k] <= last - 2.0) {
                for k in 0..3 {
                    x[k] += jitter(i, k);
                }
            }
        }
        let s = detect_surface(&p, &v, p.len(), 1.0, &[]);
        let mut paper_inside = 0;
        for (i, x) in p.iter().enumerate() {
            assert_eq!(s.is_surface[i], on_face(x), "particle {i} at {x:?}");
            if !on_face(x) && s.lambda_min[i] <= SURFACE_LAMBDA {
                paper_inside += 1;
            }
            // Particles in the middle of a face: the face's normal.
            let middle = (0..3).filter(|&k| x[k] > 3.0 && x[k] < last - 3.0).count() == 2;
            if on_face(x) && middle {
                let k = (0..3).find(|&k| x[k] == 0.0 || x[k] == last).unwrap();
                let outward = if x[k] == 0.0 { -1.0 } else { 1.0 };
                assert!(
                    s.normal[i][k] * outward > 5f64.to_radians().cos(),
                    "normal {:?} at {x:?}",
                    s.normal[i]
                );
            }
        }
        assert!(
            paper_inside > 0,
            "Eq. 15 alone flags nothing inside: the cloud is too even"
        );
    }

    /// A node a fraction of a spacing under a face node (as the centroids of flat boundary
    /// tets split into hexes lie): the kernel tests flag it, the face above covers it.
    #[test]
    fn a_node_under_the_face_is_not_surface() {
        let n = 12;
        let (mut p, mut v) = lattice(n);
        let c = (n / 2) as f64;
        p.push(Vec3::new(c, c, 0.45));
        v.push(0.3);
        let s = detect_surface(&p, &v, p.len(), 1.0, &[]);
        let under = p.len() - 1;
        assert!(
            s.lambda_min[under] <= SURFACE_LAMBDA,
            "{}",
            s.lambda_min[under]
        );
        assert!(
            s.kernel_fill[under] <= SURFACE_LAMBDA,
            "{}",
            s.kernel_fill[under]
        );
        assert!(!s.is_surface[under]);
        assert_eq!(s.normal[under], Vec3::zeros());
        let face = p
            .iter()
            .position(|x| (x - Vec3::new(c, c, 0.0)).norm() < 1e-12)
            .unwrap();
        assert!(s.is_surface[face]);
        assert_eq!(s.count(), n * n * n - (n - 2) * (n - 2) * (n - 2));
    }
}
