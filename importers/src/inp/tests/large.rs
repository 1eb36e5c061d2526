//! Large generated decks and their read rate.

use super::*;

#[test]
fn reads_a_large_deck_quickly() {
    // 20x20x50 hexes: about 23k nodes, 20k elements; the rate is only reported.
    let n = 20usize;
    let nz = 50usize;
    let id = |i: usize, j: usize, k: usize| 1 + i + (n + 1) * (j + (n + 1) * k);
    let mut deck = String::from("*NODE, NSET=ALL\n");
    for k in 0..=nz {
        for j in 0..=n {
            for i in 0..=n {
                deck.push_str(&format!(
                    "{}, {:.6e}, {:.6e}, {:.6e}\n",
                    id(i, j, k),
                    i as f64,
                    j as f64,
                    k as f64
                ));
            }
        }
    }
    deck.push_str("*ELEMENT, TYPE=C3D8R, ELSET=ALL\n");
    let mut e = 1;
    for k in 0..nz {
        for j in 0..n {
            for i in 0..n {
                deck.push_str(&format!(
                    "{e}, {}, {}, {}, {}, {}, {}, {}, {}\n",
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1)
                ));
                e += 1;
            }
        }
    }
    let start = std::time::Instant::now();
    let m = ok(&deck);
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "{:.1} MB in {secs:.3} s: {:.1} MB/s",
        deck.len() as f64 / 1e6,
        deck.len() as f64 / 1e6 / secs
    );
    assert_eq!(m.node_count(), (n + 1) * (n + 1) * (nz + 1));
    assert_eq!(m.element_count(), n * n * nz);
    assert_eq!(count(set(&m, "ALL")), m.node_count());
}

/// Throughput on a deck of about a million nodes (run with `--ignored`; prints MB/s).
#[test]
#[ignore]
fn million_node_throughput() {
    let n = 100usize;
    let nz = 100usize;
    let id = |i: usize, j: usize, k: usize| 1 + i + (n + 1) * (j + (n + 1) * k);
    let mut deck = String::from("*NODE, NSET=ALL\n");
    for k in 0..=nz {
        for j in 0..=n {
            for i in 0..=n {
                deck.push_str(&format!(
                    "{:>8}, {:>15.8e}, {:>15.8e}, {:>15.8e}\n",
                    id(i, j, k),
                    i as f64 * 0.013,
                    j as f64 * 0.017,
                    k as f64 * 0.019
                ));
            }
        }
    }
    deck.push_str("*ELEMENT, TYPE=C3D8R, ELSET=ALL\n");
    let mut e = 1;
    for k in 0..nz {
        for j in 0..n {
            for i in 0..n {
                deck.push_str(&format!(
                    "{e}, {}, {}, {}, {}, {}, {}, {}, {}\n",
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1)
                ));
                e += 1;
            }
        }
    }
    let start = std::time::Instant::now();
    let m = ok(&deck);
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "{} nodes, {:.1} MB in {secs:.3} s: {:.1} MB/s",
        m.node_count(),
        deck.len() as f64 / 1e6,
        deck.len() as f64 / 1e6 / secs
    );
    assert_eq!(m.node_count(), (n + 1) * (n + 1) * (nz + 1));
}
