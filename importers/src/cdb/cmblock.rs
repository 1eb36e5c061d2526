//! CMBLOCK: node and element components, read as intervals of numbers and resolved to
//! dense indices once the whole file is read.

use super::records::{row, Row};
use super::{Cursor, Reader};
use crate::error::{describe_found, ImportError};
use crate::mesh::NodeIndex;
use crate::text::parse_int;

/// Entity of a CMBLOCK component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Entity {
    Node,
    Element,
}

/// A component as read: closed intervals of node or element numbers (a negative item extends
/// the previous one into a range, FORMATS.md §1.5), resolved once the whole file is read.
pub(super) struct Component {
    pub(super) name: String,
    pub(super) entity: Entity,
    pub(super) intervals: Vec<(u64, u64)>,
}

impl Reader<'_> {
    /// CMBLOCK,Cname,Entity,NUMITEMS: NUMITEMS integers follow, a negative one ending a range
    /// that starts after the previous item (FORMATS.md §1.5). Lines may begin with `-`, so the
    /// block is read by its count, not up to a terminator.
    pub(super) fn cmblock(
        &mut self,
        no: usize,
        args: &[&[u8]],
        cur: &mut Cursor<'_>,
    ) -> Result<(), ImportError> {
        let name_field = args.first().copied().unwrap_or(b"");
        if name_field.is_empty() {
            return Err(self.err(
                no,
                "a component name (CMBLOCK,Cname,Entity,NUMITEMS)",
                "none",
            ));
        }
        let name = String::from_utf8_lossy(name_field).into_owned();
        let entity_field = args.get(1).copied().unwrap_or(b"");
        let upper = entity_field.to_ascii_uppercase();
        let entity = if upper == b"NODE" {
            Some(Entity::Node)
        } else if upper.starts_with(b"ELEM") {
            Some(Entity::Element)
        } else {
            None
        };
        let count_field = args.get(2).copied().unwrap_or(b"");
        let Some(total) = parse_int(count_field).and_then(|v| u64::try_from(v).ok()) else {
            return Err(self.err(
                no,
                "an item count NUMITEMS (CMBLOCK,Cname,Entity,NUMITEMS)",
                if count_field.is_empty() {
                    "none".to_string()
                } else {
                    describe_found(count_field)
                },
            ));
        };
        let (fno, fmt) = self.format_line(cur, "CMBLOCK", "(8i10)")?;
        if !fmt.all_int() {
            return Err(self.err(
                fno,
                "a CMBLOCK format of integer columns, such as '(8i10)'",
                "a format with other columns",
            ));
        }
        let mut intervals: Vec<(u64, u64)> = Vec::new();
        let mut got = 0u64;
        let mut f = std::mem::take(&mut self.fields);
        let result = (|| {
            let expected = |got: u64| {
                format!(
                    "{} more items of component {name} (NUMITEMS = {total})",
                    total - got
                )
            };
            while got < total {
                let Some((lno, line)) = cur.peek() else {
                    return Err(self.err(cur.eof_line(), expected(got), "end of file"));
                };
                match row(line) {
                    Row::Blank | Row::Comment => {
                        cur.next();
                        continue;
                    }
                    Row::End if line.trim_ascii_start().first() != Some(&b'-') => {
                        return Err(self.err(lno, expected(got), describe_found(line)));
                    }
                    _ => {}
                }
                cur.next();
                self.int_fields(lno, line, &fmt.columns, &mut f)?;
                for &v in f.iter() {
                    if got == total {
                        return Err(self.err(
                            lno,
                            format!("{total} items in component {name}, as NUMITEMS says"),
                            "more items on this line",
                        ));
                    }
                    got += 1;
                    if v > 0 {
                        intervals.push((v as u64, v as u64));
                    } else if v < 0 {
                        let end = v.unsigned_abs();
                        match intervals.last_mut() {
                            Some(last) if end > last.1 => last.1 = end,
                            Some(last) => {
                                return Err(self.err(
                                    lno,
                                    format!(
                                        "a range end above {} (a negative item ends a range that \
                                         starts after the previous item)",
                                        last.1
                                    ),
                                    v.to_string(),
                                ))
                            }
                            None => {
                                return Err(self.err(
                                    lno,
                                    "a positive item before a negative (range) item",
                                    v.to_string(),
                                ))
                            }
                        }
                    } else {
                        return Err(self.err(lno, "a non-zero component item", "0"));
                    }
                }
            }
            Ok(())
        })();
        self.fields = f;
        result?;
        match entity {
            Some(entity) => self.components.push(Component {
                name: name.trim().to_string(),
                entity,
                intervals,
            }),
            None => self.warnings.push(format!(
                "line {no}: component {} of entity {} ignored: only NODE and ELEM components \
                 are read",
                name.trim(),
                String::from_utf8_lossy(entity_field)
            )),
        }
        Ok(())
    }
}

/// Dense indices of the ids in `intervals`, sorted and unique, and how many ids the intervals
/// name. Intervals are merged first; long ones are walked through a sorted id list, so neither
/// time nor memory depends on the size of a range in the file.
pub(super) fn members(
    mut intervals: Vec<(u64, u64)>,
    index: &NodeIndex,
    ids: &[u64],
    sorted: &mut Option<Vec<(u64, u32)>>,
) -> (Vec<u32>, u128) {
    intervals.sort_unstable();
    let mut merged: Vec<(u64, u64)> = Vec::with_capacity(intervals.len());
    for (a, b) in intervals {
        match merged.last_mut() {
            Some(last) if a <= last.1.saturating_add(1) => last.1 = last.1.max(b),
            _ => merged.push((a, b)),
        }
    }
    let mut out = Vec::new();
    let mut declared = 0u128;
    for (a, b) in merged {
        declared += u128::from(b - a) + 1;
        if b - a < 64 {
            out.extend((a..=b).filter_map(|id| index.get(id)));
        } else {
            let s = sorted.get_or_insert_with(|| {
                let mut v: Vec<(u64, u32)> = ids
                    .iter()
                    .enumerate()
                    .map(|(i, &id)| (id, i as u32))
                    .collect();
                v.sort_unstable();
                v
            });
            let lo = s.partition_point(|&(id, _)| id < a);
            out.extend(
                s[lo..]
                    .iter()
                    .take_while(|&&(id, _)| id <= b)
                    .map(|&(_, i)| i),
            );
        }
    }
    out.sort_unstable();
    out.dedup();
    (out, declared)
}
