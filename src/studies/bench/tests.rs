use super::*;

#[test]
fn lattice_sphere_counts_match_lammps() {
    // `lattice sc 0.2` in a unit sphere: every lattice point of norm ≤ 1, once.
    let x = lattice_sphere(0.2);
    let brute = (-5i32..=5)
        .flat_map(|i| (-5i32..=5).flat_map(move |j| (-5i32..=5).map(move |k| (i, j, k))))
        .filter(|&(i, j, k)| i * i + j * j + k * k <= 25)
        .count();
    assert_eq!(x.len(), brute);
}

#[test]
fn energy_is_conserved() {
    let spec = LatticeSphere {
        spacing: 0.2,
        horizon_factor: LATTICE_HORIZON_FACTOR,
        steps: 50,
        threads: Some(2),
    };
    let r = run_lattice_sphere(&spec, None).expect("runs");
    assert!(r.energy_drift < 1e-3, "drift {}", r.energy_drift);
    assert!(r.bond_updates_per_second > 0.0);
}
