//! Label → index maps for node and element labels.
//!
//! Labels are usually dense (1..n), so a direct table is used while the labels stay below a
//! bound proportional to the number of labels stored so far (never to a number read from the
//! file); larger labels go to a hash map.

use std::collections::HashMap;

const EMPTY: u32 = u32::MAX;

/// Maps labels to `u32` indices.
#[derive(Clone, Debug, Default)]
pub(super) struct LabelMap {
    table: Vec<u32>,
    map: HashMap<u64, u32>,
    len: usize,
}

impl LabelMap {
    /// Number of labels stored.
    pub fn len(&self) -> usize {
        self.len
    }

    /// The index of `label`.
    #[inline]
    pub fn get(&self, label: u64) -> Option<u32> {
        if let Some(&v) = usize::try_from(label).ok().and_then(|l| self.table.get(l)) {
            if v != EMPTY {
                return Some(v);
            }
        }
        if self.map.is_empty() {
            None
        } else {
            self.map.get(&label).copied()
        }
    }

    /// Stores `label → index`; returns the index it had before, if any (which is replaced).
    #[inline]
    pub fn insert(&mut self, label: u64, index: u32) -> Option<u32> {
        let slot = usize::try_from(label).ok();
        if let Some(l) = slot {
            if l < self.table.len() && self.table[l] != EMPTY {
                return Some(std::mem::replace(&mut self.table[l], index));
            }
        }
        if !self.map.is_empty() {
            if let Some(old) = self.map.get_mut(&label) {
                return Some(std::mem::replace(old, index));
            }
        }
        self.len += 1;
        let limit = self.len.saturating_mul(4).saturating_add(65536);
        match slot {
            Some(l) if l < self.table.len() => self.table[l] = index,
            Some(l) if l < limit => {
                let new_len = (l + 1).max(self.table.len().saturating_mul(2)).min(limit);
                self.table.resize(new_len, EMPTY);
                self.table[l] = index;
            }
            _ => {
                self.map.insert(label, index);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dense_sparse_and_replace() {
        let mut m = LabelMap::default();
        assert_eq!(m.insert(5, 0), None);
        assert_eq!(m.insert(10_000_000_000, 1), None);
        assert_eq!(m.insert(3, 2), None);
        assert_eq!(m.get(5), Some(0));
        assert_eq!(m.get(10_000_000_000), Some(1));
        assert_eq!(m.get(4), None);
        assert_eq!(m.insert(5, 7), Some(0));
        assert_eq!(m.get(5), Some(7));
        assert_eq!(m.len(), 3);
        // A label that went to the map before the table grew past it is still found.
        let mut m = LabelMap::default();
        m.insert(100_000, 0);
        for i in 1..40_000u64 {
            m.insert(i, i as u32);
        }
        assert_eq!(m.get(100_000), Some(0));
        assert_eq!(m.insert(100_000, 9), Some(0));
        assert_eq!(m.get(100_000), Some(9));
        assert_eq!(m.len(), 40_000);
    }
}
