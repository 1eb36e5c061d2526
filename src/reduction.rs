//! Parallel sums in a fixed order.
//!
//! rayon's `sum` and `reduce` combine partial results along the tree of splits that work
//! stealing happens to make, so a floating-point sum can differ in its last bits from one run to
//! the next. The ADR damping (paper Eq. 33) and residual feed back into the path of the
//! iteration, and a contact that opens or closes on such a bit changes the iteration count: a
//! scene run twice must give the same answer. Here the items are cut into blocks of a fixed
//! size, each block is summed in order on some thread, and the blocks' sums are added in order.

use rayon::prelude::*;

/// Items per block: small enough that the ranks of a decomposed run, whose ranges start on a
/// block ([`crate::parallel::split_by_cost`]), stay balanced on a model of a few thousand
/// particles; several blocks make one task.
pub const BLOCK: usize = 256;

/// `item(0) ⊕ item(1) ⊕ … ⊕ item(n−1)` with `⊕ = add`, the same bits whatever the thread count
/// and scheduling.
pub fn ordered_reduce<T, I, A>(n: usize, identity: impl Fn() -> T + Sync, item: I, add: A) -> T
where
    T: Send,
    I: Fn(usize) -> T + Sync,
    A: Fn(T, T) -> T + Sync,
{
    block_sums(0..n, &identity, item, &add)
        .into_iter()
        .fold(identity(), &add)
}

/// The sum of each block of [`BLOCK`] items of `range` (which starts on a block), in order:
/// [`ordered_reduce`] is their sum from `identity()`, so that blocks summed on several ranks
/// and then added in order give its bits.
pub fn block_sums<T, I, A>(
    range: std::ops::Range<usize>,
    identity: impl Fn() -> T + Sync,
    item: I,
    add: A,
) -> Vec<T>
where
    T: Send,
    I: Fn(usize) -> T + Sync,
    A: Fn(T, T) -> T + Sync,
{
    debug_assert!(range.start.is_multiple_of(BLOCK) || range.is_empty());
    let (start, end) = (range.start, range.end);
    (0..range.len().div_ceil(BLOCK))
        .into_par_iter()
        .with_min_len(4)
        .map(|b| {
            (start + b * BLOCK..end.min(start + (b + 1) * BLOCK))
                .map(&item)
                .fold(identity(), &add)
        })
        .collect()
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
