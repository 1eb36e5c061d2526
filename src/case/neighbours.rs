//! Neighbour search by cell list, and bond families in CSR arrays (METHOD.md §2).
//!
//! The cell list bins points into cubes of side ≥ the search radius, so each query visits the
//! 27 cells around a point. Bond families are built once, in parallel over blocks of particles,
//! into compressed-row arrays: `offsets[i]..offsets[i+1]` indexes particle `i`'s partners, with
//! 32-bit partner indices and the reference bond length stored alongside (structure of arrays).
//! Bonds are directed: `(i, j)` and `(j, i)` are both stored, as LAMMPS counts them, so that each
//! particle's force is summed by one thread without atomics.

use rayon::prelude::*;

use crate::math::Vec3;

/// Points binned into a uniform grid of cubic cells.
#[derive(Clone, Debug)]
pub struct CellGrid {
    origin: Vec3,
    cell: f64,
    dims: [usize; 3],
    /// `start[c]..start[c+1]` indexes `items` for cell `c`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl CellGrid {
    /// Bins `points` into cells of side at least `cell`. The side grows when a body is so
    /// sparse that the grid would have many more cells than points.
    pub fn new(points: &[Vec3], cell: f64) -> CellGrid {
        let mut lo = Vec3::repeat(f64::INFINITY);
        let mut hi = Vec3::repeat(f64::NEG_INFINITY);
        for p in points {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        if points.is_empty() {
            lo = Vec3::zeros();
            hi = Vec3::zeros();
        }
        let mut cell = if cell > 0.0 && cell.is_finite() {
            cell
        } else {
            1.0
        };
        let limit = (8 * points.len()).max(4096) as f64;
        // Counted in f64: a huge extent or a tiny cell (a scene's `size = 1e300` or
        // `spacing = 1e-300`) must grow the cell, not overflow `usize`. An infinite or NaN
        // extent counts as the largest finite one; the cell then grows until it covers it
        // (at worst to infinity, where every point falls in the one cell).
        let extent: [f64; 3] = std::array::from_fn(|k| {
            let e = hi[k] - lo[k];
            if e.is_finite() {
                e
            } else {
                f64::MAX
            }
        });
        let dims = loop {
            // An overflowing quotient is infinite: more than the limit, so the cell grows.
            let d: [f64; 3] = std::array::from_fn(|k| (extent[k] / cell).floor() + 1.0);
            if d[0] * d[1] * d[2] <= limit {
                break d.map(|n| n as usize);
            }
            cell *= 1.5;
        };
        let ncell = dims[0] * dims[1] * dims[2];
        let cell_of = |p: &Vec3| -> usize {
            // `as usize` saturates (NaN gives 0), and `min` keeps the index in the grid.
            let i: [usize; 3] =
                std::array::from_fn(|k| (((p[k] - lo[k]) / cell) as usize).min(dims[k] - 1));
            i[0] + dims[0] * (i[1] + dims[1] * i[2])
        };
        let mut count = vec![0u32; ncell + 1];
        let ids: Vec<usize> = points.iter().map(cell_of).collect();
        for &c in &ids {
            count[c + 1] += 1;
        }
        for c in 0..ncell {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; points.len()];
        for (i, &c) in ids.iter().enumerate() {
            items[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        CellGrid {
            origin: lo,
            cell,
            dims,
            start: count,
            items,
        }
    }

    /// Cell side actually used.
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    /// Calls `f` with every binned point index whose cell lies within `radius` of `p`
    /// (a superset of the points within `radius`; the caller measures the distance).
    #[inline]
    pub fn for_each_candidate(&self, p: &Vec3, radius: f64, mut f: impl FnMut(u32)) {
        let range = |k: usize| {
            let a = ((p[k] - radius - self.origin[k]) / self.cell).floor();
            let b = ((p[k] + radius - self.origin[k]) / self.cell).floor();
            let hi = self.dims[k] as f64 - 1.0;
            if b < 0.0 || a > hi {
                None
            } else {
                Some((a.max(0.0) as usize, b.min(hi) as usize))
            }
        };
        let (Some((x0, x1)), Some((y0, y1)), Some((z0, z1))) = (range(0), range(1), range(2))
        else {
            return;
        };
        for z in z0..=z1 {
            for y in y0..=y1 {
                let row = self.dims[0] * (y + self.dims[1] * z);
                let (a, b) = (
                    self.start[row + x0] as usize,
                    self.start[row + x1 + 1] as usize,
                );
                for &i in &self.items[a..b] {
                    f(i);
                }
            }
        }
    }
}

/// Directed bonds in compressed-row form.
#[derive(Clone, Debug, Default)]
pub struct BondList {
    /// `offsets[i]..offsets[i+1]` are particle `i`'s bonds. Length `n + 1`.
    pub offsets: Vec<usize>,
    /// Partner particle of each bond.
    pub partner: Vec<u32>,
    /// Reference length `|ξ|` of each bond. Single precision: 4 bytes a bond instead of 8, and
    /// the rounding (6e-8 of the length) is far below any stretch a contact problem produces.
    pub length: Vec<f32>,
}

impl BondList {
    /// The list without `removed` (`(i, bond)`, each real pair once): both directions of a
    /// real pair, the bond alone to a mirror image.
    pub fn without(&self, removed: &[(u32, u32)]) -> BondList {
        let n = self.particles();
        let mut drop = vec![false; self.len()];
        for &(i, b) in removed {
            drop[b as usize] = true;
            let j = self.partner[b as usize] as usize;
            if j < n {
                if let Some(c) = self.range(j).find(|&c| self.partner[c] == i) {
                    drop[c] = true;
                }
            }
        }
        let mut out = BondList {
            offsets: Vec::with_capacity(n + 1),
            partner: Vec::with_capacity(self.len()),
            length: Vec::with_capacity(self.len()),
        };
        out.offsets.push(0);
        for i in 0..n {
            for b in self.range(i).filter(|&b| !drop[b]) {
                out.partner.push(self.partner[b]);
                out.length.push(self.length[b]);
            }
            out.offsets.push(out.partner.len());
        }
        out
    }

    /// The pieces: groups of particles joined by the bonds that `keep` keeps (mirror images
    /// aside). Each particle's piece, numbered from 0 by size, largest first (equal sizes in
    /// the order of their first particle), and the sizes in that order.
    pub fn components(&self, keep: impl Fn(usize) -> bool) -> (Vec<u32>, Vec<usize>) {
        let n = self.particles();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        for i in 0..n {
            for b in self.range(i) {
                let j = self.partner[b] as usize;
                if j < n && j > i && keep(b) {
                    join(&mut parent, i, j);
                }
            }
        }
        // Roots are each group's first particle (the smaller root wins every union).
        let roots: Vec<usize> = (0..n).map(|i| root(&mut parent, i)).collect();
        let mut size = vec![0usize; n];
        for &r in &roots {
            size[r] += 1;
        }
        let mut order: Vec<usize> = (0..n).filter(|&r| size[r] > 0).collect();
        order.sort_by(|&a, &b| size[b].cmp(&size[a]).then(a.cmp(&b)));
        let mut label = vec![0u32; n];
        for (k, &r) in order.iter().enumerate() {
            label[r] = k as u32;
        }
        let labels = roots.iter().map(|&r| label[r]).collect();
        (labels, order.iter().map(|&r| size[r]).collect())
    }

    /// Number of particles.
    pub fn particles(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of directed bonds.
    pub fn len(&self) -> usize {
        self.partner.len()
    }

    /// True when there are no bonds.
    pub fn is_empty(&self) -> bool {
        self.partner.is_empty()
    }

    /// The bond index range of particle `i`.
    #[inline]
    pub fn range(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i]..self.offsets[i + 1]
    }

    /// The bond back to `i` from the partner of its bond `b`, where that partner is a real
    /// particle (`None` for a mirror image, whose bonds are not listed).
    pub fn reverse(&self, i: usize, b: usize) -> Option<usize> {
        let j = self.partner[b] as usize;
        if j >= self.particles() {
            return None;
        }
        self.range(j).find(|&c| self.partner[c] as usize == i)
    }

    /// Reference length of bond `b`.
    #[inline]
    pub fn length(&self, b: usize) -> f64 {
        f64::from(self.length[b])
    }

    /// Splits a per-bond array into disjoint slices, one per block of `block` consecutive
    /// particles, so that the blocks can be filled in parallel. Each item is the block's
    /// particle range and its bonds' part of `values` (which must have one value per bond).
    pub fn blocks<'a, T>(
        &self,
        values: &'a mut [T],
        block: usize,
    ) -> Vec<(std::ops::Range<usize>, &'a mut [T])> {
        let n = self.particles();
        let block = block.max(1);
        let mut out = Vec::with_capacity(n.div_ceil(block));
        let mut rest = values;
        for start in (0..n).step_by(block) {
            let end = (start + block).min(n);
            let (head, tail) =
                std::mem::take(&mut rest).split_at_mut(self.offsets[end] - self.offsets[start]);
            rest = tail;
            out.push((start..end, head));
        }
        out
    }

    /// Bytes held by the arrays.
    pub fn bytes(&self) -> usize {
        self.offsets.len() * std::mem::size_of::<usize>()
            + self.partner.len() * std::mem::size_of::<u32>()
            + self.length.len() * std::mem::size_of::<f32>()
    }
}

/// The root of `a`'s group in a union-find forest `parent` (paths halved on the way).
pub(crate) fn root(parent: &mut [u32], mut a: usize) -> usize {
    while parent[a] as usize != a {
        parent[a] = parent[parent[a] as usize];
        a = parent[a] as usize;
    }
    a
}

/// Joins the groups of `a` and `b` (the smaller root wins, so a group's root is its first
/// member); whether they were apart.
pub(crate) fn join(parent: &mut [u32], a: usize, b: usize) -> bool {
    let (ra, rb) = (root(parent, a), root(parent, b));
    if ra != rb {
        parent[ra.max(rb)] = ra.min(rb) as u32;
    }
    ra != rb
}

/// All pairs `(i, j)`, `i ≠ j`, with `|x_j − x_i| ≤ radius`, partners sorted by index.
pub fn build_bonds(points: &[Vec3], radius: f64) -> BondList {
    build_bonds_from(points, points.len(), radius)
}

/// Particles per parallel work item of the neighbour search.
const BLOCK: usize = 512;

/// Bonds of the first `queries` points to any point within `radius` (the points after them
/// are partners only: mirror images across symmetry planes).
///
/// Two passes over the cell grid, one counting and one filling the final arrays in place, so
/// that the peak memory is the bond list itself and not twice it (the list dominates the
/// memory of a run).
pub fn build_bonds_from(points: &[Vec3], queries: usize, radius: f64) -> BondList {
    build(points, queries, radius, false)
}

/// Each pair `i < j` with `|x_j − x_i| ≤ radius` once, on its lower index (the half list of
/// [`crate::case::pairs`]).
pub fn build_pairs(points: &[Vec3], radius: f64) -> BondList {
    build(points, points.len(), radius, true)
}

/// Bonds of the first `queries` points to every point `j` with `|x_j − x_i| ≤ (ρ_i + ρ_j)/2`,
/// `ρ = reach` given per point (mirror images included): the bond families of a body whose
/// horizon follows its local spacing ([`crate::case::correction::Horizon`]). The criterion is
/// symmetric, so `j` is a partner of `i` exactly when `i` is one of `j`.
pub fn build_bonds_variable(points: &[Vec3], queries: usize, reach: &[f64]) -> BondList {
    build_bond_rows(points, queries, Reach::PerPoint(reach), |_| true)
}

/// How far bonds reach: one radius ([`build_bonds_from`]) or one per point
/// ([`build_bonds_variable`]).
#[derive(Clone, Copy, Debug)]
pub enum Reach<'a> {
    Uniform(f64),
    PerPoint(&'a [f64]),
}

/// The search of a [`Reach`]: the typical radius (the grid's cell), each row's search
/// radius, and the test of a candidate at squared distance `d²`.
pub(crate) struct Search<'a> {
    reach: Reach<'a>,
    typical: f64,
    widest: f64,
}

impl<'a> Search<'a> {
    pub(crate) fn new(reach: Reach<'a>, queries: usize) -> Search<'a> {
        match reach {
            Reach::Uniform(r) => Search {
                reach,
                typical: r,
                widest: r,
            },
            Reach::PerPoint(reach) => {
                let widest = reach.iter().copied().fold(0.0, f64::max);
                let mut typical: Vec<f64> = reach[..queries].to_vec();
                let typical = if typical.is_empty() {
                    widest
                } else {
                    let mid = typical.len() / 2;
                    *typical.select_nth_unstable_by(mid, f64::total_cmp).1
                };
                Search {
                    reach: Reach::PerPoint(reach),
                    typical,
                    widest,
                }
            }
        }
    }

    fn radius(&self, i: usize) -> f64 {
        match self.reach {
            Reach::Uniform(r) => r,
            Reach::PerPoint(reach) => 0.5 * (reach[i] + self.widest),
        }
    }

    fn bonded(&self, i: usize, j: usize, d2: f64) -> bool {
        match self.reach {
            Reach::Uniform(r) => d2 <= r * r,
            Reach::PerPoint(reach) => {
                let r = 0.5 * (reach[i] + reach[j]);
                d2 <= r * r
            }
        }
    }
}

/// The bonds [`build_bonds_from`] or [`build_bonds_variable`] give the rows `active(i)`, the
/// other rows empty: the rows a rank of a decomposed run holds, in memory proportional to
/// them ([`crate::case::part`]).
pub fn build_bond_rows(
    points: &[Vec3],
    queries: usize,
    reach: Reach,
    active: impl Fn(usize) -> bool + Sync,
) -> BondList {
    if let Reach::PerPoint(r) = reach {
        assert_eq!(points.len(), r.len());
    }
    build_rows_with(
        points,
        queries,
        &Search::new(reach, queries),
        active,
        |_, _| true,
    )
}

/// [`build_bond_rows`] keeping of each row `i` only the partners `j` with `keep(i, j)`.
pub(crate) fn build_rows_with(
    points: &[Vec3],
    queries: usize,
    s: &Search,
    active: impl Fn(usize) -> bool + Sync,
    keep: impl Fn(usize, usize) -> bool + Sync,
) -> BondList {
    build_with(
        points,
        queries,
        s.typical,
        |i| s.radius(i),
        active,
        |i, j, d2| keep(i, j) && s.bonded(i, j, d2),
        false,
    )
}

/// Per row, how many bonds [`build_bond_rows`] gives it, without holding them: what a rank
/// needs to cut the particles over the ranks by cost before it builds its rows.
pub fn count_bonds(points: &[Vec3], queries: usize, reach: Reach) -> Vec<usize> {
    let s = Search::new(reach, queries);
    let grid = CellGrid::new(points, 0.5 * s.typical);
    (0..queries)
        .into_par_iter()
        .map(|i| {
            let mut n = 0;
            grid.for_each_candidate(&points[i], s.radius(i), |j| {
                let j = j as usize;
                n += (j != i && s.bonded(i, j, (points[j] - points[i]).norm_squared())) as usize
            });
            n
        })
        .collect()
}

/// How many bonds [`build_bond_rows`] gives the rows `rows` to particles before
/// `rows.start`, without holding them: what a rank's halo rows hold of its bonds when the
/// particles `rows` are its own ([`crate::case`]: a halo row keeps its bonds to later
/// particles of the rank), so that the ranks can be cut by what each will hold.
pub fn count_bonds_before(
    points: &[Vec3],
    queries: usize,
    reach: Reach,
    rows: std::ops::Range<usize>,
) -> usize {
    if rows.is_empty() || rows.start == 0 {
        return 0;
    }
    let s = Search::new(reach, queries);
    let grid = CellGrid::new(&points[..rows.start.min(queries)], 0.5 * s.typical);
    rows.into_par_iter()
        .map(|i| {
            let mut n = 0;
            grid.for_each_candidate(&points[i], s.radius(i), |j| {
                let j = j as usize;
                n += s.bonded(i, j, (points[j] - points[i]).norm_squared()) as usize
            });
            n
        })
        .sum()
}

/// Per point, how many pairs `(i, j > i)` within `radius` [`build_pairs`] gives it, without
/// holding them: what a rank needs to cut the particles over the ranks by cost before it
/// builds only its part ([`build_pairs_touching`]).
pub fn count_pairs(points: &[Vec3], radius: f64) -> Vec<usize> {
    let r2 = radius * radius;
    let grid = CellGrid::new(points, 0.5 * radius);
    (0..points.len())
        .into_par_iter()
        .map(|i| {
            let mut n = 0;
            grid.for_each_candidate(&points[i], radius, |j| {
                n += (j as usize > i && (points[j as usize] - points[i]).norm_squared() <= r2)
                    as usize
            });
            n
        })
        .collect()
}

/// The pairs of [`build_pairs`] with either end in `owned`, each on its lower index as
/// there: exactly the rows that [`PairList::restricted`](crate::case::pairs::PairList::restricted)
/// keeps of the whole list, made without the whole list (a rank's part of a decomposed
/// model, in memory proportional to the part).
pub fn build_pairs_touching(
    points: &[Vec3],
    radius: f64,
    owned: std::ops::Range<usize>,
) -> BondList {
    let r2 = radius * radius;
    // A row below the range has pairs in it only if it lies within the radius of the
    // range's bounding box; rows past the range have none (their partners are higher).
    let (lo, hi) = owned.clone().fold(
        (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
        |(lo, hi), i| (lo.inf(&points[i]), hi.sup(&points[i])),
    );
    let near = |p: &Vec3| {
        let d = (lo - p).sup(&(p - hi)).sup(&Vec3::zeros());
        d.norm_squared() <= r2
    };
    let mut list = build_with(
        points,
        owned.end.min(points.len()),
        radius,
        |_| radius,
        |i| owned.contains(&i) || near(&points[i]),
        |i, j, d2| d2 <= r2 && (owned.contains(&i) || owned.contains(&j)),
        true,
    );
    // Every point has its row, as in the whole list.
    let total = list.partner.len();
    list.offsets.resize(points.len() + 1, total);
    list
}

fn build(points: &[Vec3], queries: usize, radius: f64, half: bool) -> BondList {
    let r2 = radius * radius;
    build_with(
        points,
        queries,
        radius,
        |_| radius,
        |_| true,
        |_, _, d2| d2 <= r2,
        half,
    )
}

/// The neighbour search: `search(i)` bounds the distance of `i`'s partners, `bonded(i, j, d²)`
/// decides each candidate, `cell` is the typical search radius; a row that is not
/// `active(i)` has no bonds and is not searched.
fn build_with(
    points: &[Vec3],
    queries: usize,
    cell: f64,
    search: impl Fn(usize) -> f64 + Sync,
    active: impl Fn(usize) -> bool + Sync,
    bonded: impl Fn(usize, usize, f64) -> bool + Sync,
    half: bool,
) -> BondList {
    // Cells of half the radius: the 5×5×5 block around a point holds about half the candidates
    // of the 3×3×3 block of cells of side `radius`.
    let grid = CellGrid::new(points, 0.5 * cell);
    let within = |i: usize, j: u32| {
        (if half {
            j as usize > i
        } else {
            j as usize != i
        }) && bonded(
            i,
            j as usize,
            (points[j as usize] - points[i]).norm_squared(),
        )
    };
    let counts: Vec<usize> = (0..queries)
        .into_par_iter()
        .map(|i| {
            let mut n = 0;
            if active(i) {
                grid.for_each_candidate(&points[i], search(i), |j| n += within(i, j) as usize);
            }
            n
        })
        .collect();
    let mut offsets = Vec::with_capacity(queries + 1);
    offsets.push(0);
    for c in counts {
        offsets.push(offsets.last().copied().unwrap_or(0) + c);
    }
    let total = offsets[queries];
    let mut partner = vec![0u32; total];
    let mut length = vec![0f32; total];

    // Disjoint output slices, one per block of particles.
    let mut work = Vec::with_capacity(queries.div_ceil(BLOCK));
    let (mut p_rest, mut l_rest) = (&mut partner[..], &mut length[..]);
    for start in (0..queries).step_by(BLOCK) {
        let end = (start + BLOCK).min(queries);
        let len = offsets[end] - offsets[start];
        let (p, pr) = std::mem::take(&mut p_rest).split_at_mut(len);
        let (l, lr) = std::mem::take(&mut l_rest).split_at_mut(len);
        (p_rest, l_rest) = (pr, lr);
        work.push((start, end, p, l));
    }
    work.into_par_iter().for_each(|(start, end, p, l)| {
        let base = offsets[start];
        for i in start..end {
            let range = offsets[i] - base..offsets[i + 1] - base;
            let dst = &mut p[range.clone()];
            if dst.is_empty() {
                continue;
            }
            let mut k = 0;
            grid.for_each_candidate(&points[i], search(i), |j| {
                // Same test as the counting pass, so exactly `dst.len()` partners arrive.
                if within(i, j) && k < dst.len() {
                    dst[k] = j;
                    k += 1;
                }
            });
            dst.sort_unstable();
            for (len, &j) in l[range].iter_mut().zip(dst.iter()) {
                *len = (points[j as usize] - points[i]).norm() as f32;
            }
        }
    });
    BondList {
        offsets,
        partner,
        length,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_partner_counts() {
        // Simple cubic lattice, radius 3.5 spacing (horizon 3Δ + Δ/2): an interior point has
        // every lattice point within 3.5 of it: 178 in all.
        let n = 11;
        let pts: Vec<Vec3> = (0..n * n * n)
            .map(|i| Vec3::new((i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64))
            .collect();
        let bonds = build_bonds(&pts, 3.5);
        let centre = 5 + n * (5 + n * 5);
        let brute = pts
            .iter()
            .enumerate()
            .filter(|(j, q)| *j != centre && (*q - pts[centre]).norm() <= 3.5)
            .count();
        assert_eq!(bonds.range(centre).len(), brute);
        assert_eq!(brute, 178);
        // Symmetry: every bond has its reverse.
        for i in 0..pts.len() {
            for b in bonds.range(i) {
                let j = bonds.partner[b] as usize;
                assert!(bonds.partner[bonds.range(j)].contains(&(i as u32)));
            }
        }
    }

    #[test]
    fn counts_and_rows_are_the_whole_lists() {
        // An irregular cloud with a reach that varies from point to point.
        let pts: Vec<Vec3> = (0..600u64)
            .map(|i| {
                let h = |k: u64| ((i * 2654435761 + k * 40503) % 1000) as f64 / 100.0;
                Vec3::new(h(1), h(2), h(3))
            })
            .collect();
        let reach: Vec<f64> = (0..pts.len()).map(|i| 1.5 + (i % 7) as f64 * 0.1).collect();
        for r in [Reach::Uniform(1.8), Reach::PerPoint(&reach)] {
            let whole = build_bond_rows(&pts, 500, r, |_| true);
            let count = count_bonds(&pts, 500, r);
            let rows = build_bond_rows(&pts, 500, r, |i| (100..250).contains(&i));
            assert_eq!(rows.particles(), 500);
            // The bonds of the rows to the particles before them (not to the images).
            let before: usize = (100..250)
                .flat_map(|i| whole.partner[whole.range(i)].iter())
                .filter(|&&j| j < 100)
                .count();
            assert!(before > 0);
            assert_eq!(count_bonds_before(&pts, 500, r, 100..250), before);
            assert_eq!(count_bonds_before(&pts, 500, r, 0..250), 0);
            for i in 0..500 {
                assert_eq!(count[i], whole.range(i).len());
                if (100..250).contains(&i) {
                    assert_eq!(rows.partner[rows.range(i)], whole.partner[whole.range(i)]);
                    assert_eq!(rows.length[rows.range(i)], whole.length[whole.range(i)]);
                } else {
                    assert!(rows.range(i).is_empty());
                }
            }
        }
        let uniform = build_bonds_from(&pts, 500, 1.8);
        let rows = build_bond_rows(&pts, 500, Reach::Uniform(1.8), |_| true);
        assert_eq!(
            (uniform.offsets, uniform.partner),
            (rows.offsets, rows.partner)
        );
    }

    #[test]
    fn a_ranks_pairs_are_the_whole_lists_that_touch_it() {
        // An irregular cloud (a lattice jittered by a fixed hash), cut into ranges of every
        // kind: the pairs built for a range are, row by row, those of the whole list with an
        // end in it, and the counts are the whole list's rows.
        let n = 9;
        let pts: Vec<Vec3> = (0..n * n * n)
            .map(|i| {
                let h = |k: usize| ((i * 2654435761 + k * 40503) % 1000) as f64 / 2500.0;
                Vec3::new(
                    (i % n) as f64 + h(1),
                    ((i / n) % n) as f64 + h(2),
                    (i / (n * n)) as f64 + h(3),
                )
            })
            .collect();
        let r = 2.2;
        let whole = build_pairs(&pts, r);
        let counts = count_pairs(&pts, r);
        assert!((0..pts.len()).all(|i| counts[i] == whole.range(i).len()));
        for own in [
            0..pts.len(),
            0..100,
            100..400,
            400..pts.len(),
            300..301,
            5..5,
        ] {
            let part = build_pairs_touching(&pts, r, own.clone());
            assert_eq!(part.particles(), pts.len());
            for i in 0..pts.len() {
                let kept: Vec<u32> = whole.partner[whole.range(i)]
                    .iter()
                    .copied()
                    .filter(|&j| own.contains(&i) || own.contains(&(j as usize)))
                    .collect();
                assert_eq!(
                    &part.partner[part.range(i)],
                    &kept[..],
                    "row {i} of {own:?}"
                );
            }
            assert_eq!(part.length.len(), part.partner.len());
        }
    }

    #[test]
    fn huge_extents_and_tiny_cells_grow_the_cell() {
        // A plane of size 1e300, a mesh scaled by 1e300, a spacing of 1e-300: no overflow, and
        // every point is still found from its own position.
        for (pts, cell) in [
            (
                vec![Vec3::new(-5e299, 0.0, 0.0), Vec3::new(5e299, 1.0, 0.0)],
                0.1,
            ),
            (
                vec![
                    Vec3::new(-1e307, -1e307, 0.0),
                    Vec3::new(1e307, 1e307, 1e307),
                ],
                1.0,
            ),
            (vec![Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0)], 1e-300),
            (vec![Vec3::zeros(), Vec3::new(f64::INFINITY, 0.0, 0.0)], 1.0),
        ] {
            let grid = CellGrid::new(&pts, cell);
            assert!(
                grid.dims.iter().product::<usize>() <= 4096,
                "{:?}",
                grid.dims
            );
            for (i, p) in pts
                .iter()
                .enumerate()
                .filter(|(_, p)| p.iter().all(|x| x.is_finite()))
            {
                let mut found = false;
                grid.for_each_candidate(p, cell, |j| found |= j as usize == i);
                assert!(found, "point {i} of {pts:?} not found");
            }
        }
    }
}
