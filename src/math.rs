//! The small vocabulary every stage shares: the 3-vector type and the marker of a mesh node
//! that is not a particle (as parry keeps its `math` module at the crate root).

use nalgebra::Vector3;

/// A 3-vector of f64.
pub type Vec3 = Vector3<f64>;

/// Marks a mesh node that is not a particle.
pub const NOT_A_PARTICLE: u32 = u32::MAX;

/// `|v|` without overflow where its components are near f64's limit (a plane placed at
/// 1e300 m); 0 for a zero vector, and not finite for a vector that is not.
pub fn length(v: Vec3) -> f64 {
    let m = v.amax();
    if m > 0.0 && m.is_finite() {
        m * (v / m).norm()
    } else {
        m
    }
}

/// The unit vector along `v`, scaled first so that a scene's direction with huge components
/// (`normal = [0, -1e300, 1]`, a direction along -y) does not overflow its norm into a zero
/// vector. The caller has checked that `v` is finite and not zero.
pub fn unit(v: Vec3) -> Vec3 {
    let m = v.amax();
    (v / m).normalize()
}

/// Two unit vectors completing the unit vector `d` to an orthonormal frame `(e1, e2, d)`.
pub fn tangent_frame(d: Vec3) -> (Vec3, Vec3) {
    let pick = if d.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let e1 = d.cross(&pick).normalize();
    (e1, d.cross(&e1))
}

/// The least-squares plane through `points` (at least one): their centroid, and the unit
/// direction in which they spread least, its sign arbitrary (the caller orients it).
pub fn least_squares_plane(points: &[Vec3]) -> (Vec3, Vec3) {
    let c: Vec3 = points.iter().sum::<Vec3>() / points.len() as f64;
    let cov: nalgebra::Matrix3<f64> = points.iter().map(|d| (d - c) * (d - c).transpose()).sum();
    let eigen = nalgebra::SymmetricEigen::new(cov);
    let m = eigen
        .eigenvectors
        .column(eigen.eigenvalues.imin())
        .into_owned();
    (c, m)
}
