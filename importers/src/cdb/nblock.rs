//! NBLOCK: node records (number, then coordinates) up to the block terminator.

use super::records::{found_field, int_field, parse_fortran_real, row, Row};
use super::{lineno, Cursor, Reader, MAX_NODE_ID};
use crate::error::{describe_found, ImportError};
use crate::text::parse_int;

impl Reader<'_> {
    /// NBLOCK: records until the terminator, whatever the header counts say (they are missing
    /// or wrong in real files, FORMATS.md §1.3). Omitted trailing coordinates are 0.
    pub(super) fn nblock(
        &mut self,
        args: &[&[u8]],
        cur: &mut Cursor<'_>,
    ) -> Result<(), ImportError> {
        let (fno, fmt) = self.format_line(cur, "NBLOCK", "(3i9,6e21.13e3)")?;
        let Some(layout) = fmt.node_layout() else {
            return Err(self.err(
                fno,
                "an NBLOCK format with integer columns then real columns, such as \
                 '(3i9,6e21.13e3)'",
                "a format without that layout",
            ));
        };
        // Capacity hint from the header, capped by what the file can hold.
        let declared = args
            .iter()
            .skip(2)
            .filter_map(|a| parse_int(a))
            .max()
            .unwrap_or(0)
            .max(0) as usize;
        let hint = declared.min(self.data_len / (layout.id.width + 2));
        self.mesh.node_ids.reserve(hint);
        self.mesh.coords.reserve(hint);
        self.node_lines.reserve(hint);
        const AXES: [&str; 3] = ["x", "y", "z"];
        loop {
            let Some((no, line)) = cur.peek() else {
                return Err(self.err(
                    cur.eof_line(),
                    "more NBLOCK records or the block terminator ('N,R5.3,LOC,-1' or '-1')",
                    "end of file",
                ));
            };
            match row(line) {
                Row::Blank | Row::Comment => {
                    cur.next();
                    continue;
                }
                Row::End => return Ok(()),
                Row::Data => {}
            }
            cur.next();
            let id_field = layout.id.slice(line);
            let id = match int_field(id_field) {
                Some(v) if (1..=MAX_NODE_ID).contains(&v) => v,
                _ => {
                    return Err(self.err(
                        no,
                        format!("a node number in {}", layout.id.describe()),
                        found_field(id_field),
                    ))
                }
            };
            let mut xyz = [0.0; 3];
            for (k, col) in layout.coords.iter().enumerate() {
                let Some(col) = col else { break };
                let f = col.slice(line);
                if f.trim_ascii().is_empty() {
                    continue;
                }
                xyz[k] = parse_fortran_real(f).ok_or_else(|| {
                    self.err(
                        no,
                        format!(
                            "the {} coordinate of node {id} in {}",
                            AXES[k],
                            col.describe()
                        ),
                        found_field(f),
                    )
                })?;
            }
            if line.len() > layout.end && !line[layout.end..].trim_ascii().is_empty() {
                return Err(self.err(
                    no,
                    format!(
                        "at most {} columns, as the NBLOCK format line gives",
                        layout.end
                    ),
                    describe_found(&line[layout.end..]),
                ));
            }
            self.mesh.push_node(id as u64, xyz);
            self.node_lines.push(lineno(no));
        }
    }
}
