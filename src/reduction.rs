//! Parallel sums in a fixed order.
//!
//! rayon's `sum` and `reduce` combine partial results along the tree of splits that work
//! stealing happens to make, so a floating-point sum can differ in its last bits from one run to
//! the next. The ADR damping (paper Eq. 33) and residual feed back into the path of the
//! iteration, and a contact that opens or closes on such a bit changes the iteration count: a
//! scene run twice must give the same answer. Here the items are cut into blocks of a fixed
//! size, each block is summed in order on some thread, and the blocks' sums are added in order.

use rayon::prelude::*;

/// Items per block: large enough to amortise a task, small enough to balance two to a few
/// dozen threads on the particle counts of a run.
pub const BLOCK: usize = 1024;

/// `item(0) ⊕ item(1) ⊕ … ⊕ item(n−1)` with `⊕ = add`, the same bits whatever the thread count
/// and scheduling.
pub fn ordered_reduce<T, I, A>(n: usize, identity: impl Fn() -> T + Sync, item: I, add: A) -> T
where
    T: Send,
    I: Fn(usize) -> T + Sync,
    A: Fn(T, T) -> T + Sync,
{
    let blocks: Vec<T> = (0..n.div_ceil(BLOCK))
        .into_par_iter()
        .map(|b| {
            (b * BLOCK..n.min((b + 1) * BLOCK))
                .map(&item)
                .fold(identity(), &add)
        })
        .collect();
    blocks.into_iter().fold(identity(), &add)
}

/// `Σ item(i)` over `0..n`, in a fixed order.
pub fn ordered_sum(n: usize, item: impl Fn(usize) -> f64 + Sync) -> f64 {
    ordered_reduce(n, || 0.0, item, |a, b| a + b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_bits_on_any_thread_count() {
        // Terms of very different sizes, so that the order of addition shows in the result.
        let term = |i: usize| ((i * 7919 % 1000) as f64 - 500.0) * 10f64.powi((i % 17) as i32 - 8);
        let n: usize = 100_003;
        let serial = (0..n.div_ceil(BLOCK))
            .map(|b| (b * BLOCK..n.min((b + 1) * BLOCK)).map(term).sum::<f64>())
            .sum::<f64>();
        for threads in [1, 2, 3, 7] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            for _ in 0..5 {
                let s = pool.install(|| ordered_sum(n, term));
                assert_eq!(s.to_bits(), serial.to_bits(), "{threads} threads");
            }
        }
    }

    #[test]
    fn reduces_in_order() {
        // A non-commutative reduction (concatenation) shows the order itself.
        let s = ordered_reduce(
            3000,
            String::new,
            |i| format!("{},", i),
            |mut a, b| {
                a.push_str(&b);
                a
            },
        );
        let expected: String = (0..3000).map(|i| format!("{},", i)).collect();
        assert_eq!(s, expected);
    }
}
