//! Gmsh MSH reader: versions 2 / 2.2 and 4.1, ASCII and binary (either byte order).
//!
//! # What is read
//!
//! * `$MeshFormat` (version `2`, `2.0`, `2.1`, `2.2` or `4.1`; file type 0 or 1; in binary files
//!   the int32 `1` decides the byte order, so byte-swapped files read too). MSH 4.1 binary files
//!   may use a `size_t` of 8 or 4 bytes. **MSH 4.0** (also written as version `4`) has another
//!   layout and is rejected with an error saying so, as are MSH 1 and 3.
//! * `$PhysicalNames`, keyed by (dimension, tag): the same tag may name groups of different
//!   dimensions.
//! * `$Entities` (4.1): points carry X Y Z, curves / surfaces / volumes a bounding box; each
//!   entity lists its physical tags (several allowed). `$PartitionedEntities`: each partition
//!   entity names its parent and carries physical tags (the parent's are used when it has none).
//! * `$Nodes`: sparse, unordered tags kept in [`Mesh::node_ids`]; 4.1 parametric blocks (u, v, w
//!   are skipped); ASCII is read token by token, so several nodes on one line are fine. Tag 0
//!   (old partitioned files) is accepted with a warning.
//! * `$Elements`: every type of gmsh's table (see `types.rs`). The eight solids map to the mesh
//!   kinds with Gmsh's second-order node order permuted to the VTK/Abaqus convention of
//!   [`crate::mesh`]; hex27 / prism18 / pyramid14 are stored as hex20 / wedge15 / pyramid13 and
//!   higher-order solids as their linear shape by their corners, each with one warning per type.
//!   Points, lines, triangles and quadrilaterals of any order are kept (corners first) for the
//!   physical groups. Polygons, polyhedra, order-0 and sub-elements are refused, as are unknown
//!   type numbers, with the line or byte of the type.
//! * MSH 2: an element in k physical groups is listed k times. Gmsh (every version checked, up
//!   to 4.15) gives each listing a **new element number**, one right after the other, with the
//!   same type, elementary tag and nodes; other writers repeat the number. So a record is merged
//!   with the record just before it when type, elementary tag and nodes agree, and with any
//!   earlier record of the same number (which must then have the same type and nodes, else it
//!   is an error). The merged element keeps the first number and every physical tag. Tags after
//!   the second (partitions) are ignored, so partitioned and old `2` files read too. Binary
//!   element blocks may hold one or many elements per header.
//! * MSH 4.1 lists each element once, so an element tag used twice is an error at the second
//!   record, naming the line or byte of the first. It is checked after `$Elements` is read: one
//!   pass while the tags increase (as gmsh writes them), else a bitset over the tag range, or a
//!   sort when that range is too wide.
//! * Any other section (`$Comments`, also before `$MeshFormat`, `$Periodic`, `$NodeData`,
//!   `$GhostElements`, ...) is skipped by searching for its `\n$EndXxx` line, without decoding.
//!
//! # Physical groups
//!
//! Each physical group with at least one element becomes a [`NamedSet`] of kind
//! [`SetKind::PhysicalGroup`] with its elements and the distinct nodes of those elements, in
//! order of (dimension, tag). Unnamed groups are named as gmsh's INP export names them:
//! `PhysicalPoint<tag>`, `PhysicalLine<tag>`, `PhysicalSurface<tag>`, `PhysicalVolume<tag>`.
//! A file without physical groups gives no sets.
//!
//! # Errors
//!
//! Every problem is an [`ImportError`] with the 1-based line (ASCII files) or the byte offset
//! (binary files, past the `$MeshFormat` line), what was expected and what was found. Counts
//! in the file are never trusted for allocation: capacity hints are capped by the bytes left,
//! and every loop consumes input, so a lying count ends at the end of the file with an error.
//! `$Nodes` must come before `$Elements` (as gmsh itself requires), and `$Entities` before both.
//!
//! # Speed
//!
//! Nodes and element records are read by the small tokenizer of `lex.rs`; the grammar around
//! them (section lines, headers, counts, entities, names) by the nom parsers of `grammar.rs`.
//! Both take their number conversions from `num.rs`, so `lex.rs` uses `grammar.rs` and not back.
//! Node tags are resolved with [`NodeIndex`] while the elements are read, so no tag array is
//! kept for the elements.

mod grammar;
mod lex;
mod num;
mod types;
mod v2;
mod v4;

#[cfg(test)]
mod tests;

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use crate::error::ImportError;
use crate::mesh::{Mesh, NamedSet, NodeIndex, SetKind, MISSING_NODE};

use grammar::{Enc, EntityPhysicals, PartEntity};
use lex::Cur;
use types::{ElemType, Lookup};

/// A problem at a byte offset; turned into an [`ImportError`] with a line or byte at the end.
#[derive(Debug)]
pub(crate) struct Fail {
    pub at: usize,
    pub expected: Cow<'static, str>,
    pub found: String,
}

pub(crate) type Res<T> = Result<T, Box<Fail>>;

#[cold]
#[inline(never)]
pub(crate) fn fail(
    at: usize,
    expected: impl Into<Cow<'static, str>>,
    found: impl Into<String>,
) -> Box<Fail> {
    Box::new(Fail {
        at,
        expected: expected.into(),
        found: found.into(),
    })
}

/// Reads a Gmsh MSH file (2.x or 4.1, ASCII or binary) held in `data`; `path` names it in errors.
pub fn read(path: &Path, data: &[u8]) -> Result<Mesh, ImportError> {
    let mut cx = Ctx::new(data);
    match cx.read_all() {
        Ok(()) => Ok(cx.finish()),
        Err(f) => Err(locate(path, data, cx.binary_from, &f)),
    }
}

/// Converts a failure to a line (text) or byte offset (binary part of a binary file).
fn locate(path: &Path, data: &[u8], binary_from: Option<usize>, f: &Fail) -> ImportError {
    let at = f.at.min(data.len());
    match binary_from {
        Some(b) if at >= b => ImportError::at_byte(path, at as u64, f.expected.clone(), &*f.found),
        _ => {
            let line = 1 + memchr::memchr_iter(b'\n', &data[..at]).count();
            ImportError::at_line(path, line, f.expected.clone(), &*f.found)
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Version {
    V2,
    V41,
}

impl std::fmt::Display for Version {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Version::V2 => "2",
            Version::V41 => "4.1",
        })
    }
}

/// Reading state shared by the section readers.
pub(crate) struct Ctx<'a> {
    pub data: &'a [u8],
    pub enc: Enc,
    /// Offset from which errors are given as bytes (binary files).
    binary_from: Option<usize>,
    /// Mesh sections read so far: name and the byte range of the body.
    mesh_sections: Vec<(Vec<u8>, usize, usize)>,
    version: Option<Version>,
    pub mesh: Mesh,
    pub index: Option<NodeIndex>,
    /// Elements of each physical group (dimension, tag), possibly with repeats.
    pub groups: BTreeMap<(u8, i64), Vec<u32>>,
    names: HashMap<(u8, i64), String>,
    pub entities: Option<EntityPhysicals>,
    pub partitioned: Option<HashMap<(u8, i64), PartEntity>>,
    /// Element types stored in a reduced form, with their counts.
    pub reduced: BTreeMap<i64, (usize, ElemType)>,
    skipped: Vec<String>,
    elements_read: bool,
    /// (element, node) for nodes of reduced elements that the connectivity leaves out.
    pub dropped: Vec<(u32, u32)>,
}

impl<'a> Ctx<'a> {
    fn new(data: &'a [u8]) -> Ctx<'a> {
        Ctx {
            data,
            enc: Enc::Ascii,
            binary_from: None,
            mesh_sections: Vec::new(),
            version: None,
            mesh: Mesh::new(),
            index: None,
            groups: BTreeMap::new(),
            names: HashMap::new(),
            entities: None,
            partitioned: None,
            reduced: BTreeMap::new(),
            skipped: Vec::new(),
            elements_read: false,
            dropped: Vec::new(),
        }
    }

    fn read_all(&mut self) -> Res<()> {
        let data = self.data;
        let mut pos = 0usize;
        loop {
            let mut cur = Cur::new(data, pos, Enc::Ascii);
            let at = cur.token_start();
            if at >= data.len() {
                break;
            }
            let name = cur.run(
                grammar::section_header,
                "a section header such as $MeshFormat",
            )?;
            let body = cur.p;
            let name_str = String::from_utf8_lossy(name).into_owned();
            let shown = short_name(&name_str).into_owned();
            pos = match name {
                b"MeshFormat" => self.mesh_format(at, body)?,
                b"Comments" => skip_section(data, at, body, &name_str)?,
                b"NOD" | b"NOE" | b"ELM" => {
                    return Err(fail(
                        at,
                        "a Gmsh MSH 2 or 4.1 file ($MeshFormat)",
                        format!("${shown}, an MSH 1 file (not supported; save as MSH 4.1)"),
                    ))
                }
                _ if name.starts_with(b"End") => {
                    return Err(fail(
                        at,
                        "a section header such as $Nodes",
                        format!("'${shown}' without its opening section"),
                    ))
                }
                b"PhysicalNames"
                | b"Entities"
                | b"PartitionedEntities"
                | b"Nodes"
                | b"Elements"
                | b"ParametricNodes"
                    if self.is_identical_repeat(name, at, body)? =>
                {
                    skip_section(data, at, body, &name_str)?
                }
                b"PhysicalNames" => self.record_section(name, body, Self::physical_names)?,
                b"Entities"
                | b"PartitionedEntities"
                | b"Nodes"
                | b"Elements"
                | b"ParametricNodes" => {
                    let Some(version) = self.version else {
                        return Err(fail(
                            at,
                            "$MeshFormat before the mesh data",
                            format!("${shown}"),
                        ));
                    };
                    self.record_section(name, body, |cx, body| {
                        cx.data_section(version, name, at, body)
                    })?
                }
                _ => {
                    if self.version.is_some()
                        && self.skipped.len() < MAX_SKIPPED_NAMES
                        && !self.skipped.contains(&name_str)
                    {
                        self.skipped.push(name_str.clone());
                    }
                    skip_section(data, at, body, &name_str)?
                }
            };
        }
        if self.version.is_none() {
            return Err(fail(
                data.len(),
                "a $MeshFormat section",
                if data.is_empty() {
                    "an empty file"
                } else {
                    "end of file"
                },
            ));
        }
        if self.index.is_none() {
            return Err(fail(data.len(), "a $Nodes section", "end of file"));
        }
        Ok(())
    }

    /// Reads a mesh section with `read` and remembers where its bytes lie.
    fn record_section(
        &mut self,
        name: &[u8],
        body: usize,
        read: impl FnOnce(&mut Self, usize) -> Res<usize>,
    ) -> Res<usize> {
        let end = read(self, body)?;
        self.mesh_sections.push((name.to_vec(), body, end));
        Ok(end)
    }

    /// True when this mesh section repeats, byte for byte, one already read: gmsh writes the
    /// whole mesh again, after a second `$MeshFormat`, before each block of post-processing
    /// data it appends (`gmsh.view.write(..., append=True)`). A repeat that differs is read,
    /// and its section reader refuses it.
    fn is_identical_repeat(&self, name: &[u8], at: usize, body: usize) -> Res<bool> {
        let Some(&(_, first, first_end)) = self.mesh_sections.iter().find(|(n, ..)| n == name)
        else {
            return Ok(false);
        };
        let end = skip_section(self.data, at, body, &String::from_utf8_lossy(name))?;
        Ok(self.data[body..end] == self.data[first..first_end])
    }

    /// `$MeshFormat`. A second one is accepted with the same version: gmsh writes one before
    /// each block of post-processing data it appends to a mesh file (`$NodeData` after
    /// `gmsh.view.write(..., append=True)`); its file type applies to the sections after it.
    fn mesh_format(&mut self, at: usize, body: usize) -> Res<usize> {
        let first = self.version;
        let end = self.read_mesh_format(body)?;
        if let (Some(first), Some(now)) = (first, self.version) {
            if first != now {
                return Err(fail(
                    at,
                    format!("a second $MeshFormat of the first one's version ({first})"),
                    format!("version {now}"),
                ));
            }
        }
        Ok(end)
    }

    fn read_mesh_format(&mut self, body: usize) -> Res<usize> {
        let data = self.data;
        let mut cur = Cur::new(data, body, Enc::Ascii);
        let line_at = cur.token_start();
        let (version, file_type, data_size) =
            cur.run(grammar::mesh_format, "a $MeshFormat line")?;
        let v = num::parse_f64(version).unwrap_or(f64::NAN);
        let same = |x: f64| (v - x).abs() < 1e-9;
        let shown = String::from_utf8_lossy(version).into_owned();
        let version = if same(2.0) || same(2.1) || same(2.2) {
            Version::V2
        } else if same(4.1) {
            Version::V41
        } else if same(4.0) {
            return Err(fail(
                line_at,
                "MSH version 2.2 or 4.1",
                format!("version {shown}: MSH 4.0 is not supported (save as 4.1 with gmsh)"),
            ));
        } else {
            return Err(fail(
                line_at,
                "MSH version 2, 2.2 or 4.1",
                format!("version {}", crate::error::describe_found(version)),
            ));
        };
        match file_type {
            0 => self.enc = Enc::Ascii,
            1 => {
                let ok_size = match version {
                    Version::V2 => data_size == 8,
                    Version::V41 => data_size == 8 || data_size == 4,
                };
                if !ok_size {
                    return Err(fail(
                        line_at,
                        match version {
                            Version::V2 => "data size 8 (double precision) in a binary MSH 2 file",
                            Version::V41 => "data size 8 or 4 (size_t) in a binary MSH 4.1 file",
                        },
                        format!("data size {data_size}"),
                    ));
                }
                let check = cur.p;
                // Positions past the first binary data are reported as byte offsets.
                self.binary_from.get_or_insert(check);
                let big = match data.get(check..check + 4) {
                    Some([1, 0, 0, 0]) => false,
                    Some([0, 0, 0, 1]) => true,
                    Some(b) => {
                        return Err(fail(
                            check,
                            "the binary byte-order check (int32 1)",
                            format!("bytes {:02x} {:02x} {:02x} {:02x}", b[0], b[1], b[2], b[3]),
                        ))
                    }
                    None => {
                        return Err(fail(
                            check,
                            "the binary byte-order check (int32 1)",
                            "end of file",
                        ))
                    }
                };
                cur.p = check + 4;
                self.enc = Enc::Binary {
                    big,
                    wide: data_size == 8,
                };
            }
            _ => {
                return Err(fail(
                    line_at,
                    "file type 0 (ASCII) or 1 (binary)",
                    format!("file type {file_type}"),
                ))
            }
        }
        self.version = Some(version);
        cur.end_of("MeshFormat")?;
        Ok(cur.p)
    }

    fn physical_names(&mut self, body: usize) -> Res<usize> {
        let mut cur = Cur::new(self.data, body, Enc::Ascii);
        let n = cur.run(
            grammar::size_t(Enc::Ascii, "the number of physical names"),
            "the number of physical names",
        )?;
        for _ in 0..n {
            let (dim, tag, name) = cur.run(grammar::physical_name, "a physical name line")?;
            let name = String::from_utf8_lossy(name).trim().to_string();
            self.names.entry((dim, tag)).or_insert(name);
        }
        cur.end_of("PhysicalNames")?;
        Ok(cur.p)
    }

    fn data_section(
        &mut self,
        version: Version,
        name: &[u8],
        at: usize,
        body: usize,
    ) -> Res<usize> {
        let mut cur = Cur::new(self.data, body, self.enc);
        match (version, name) {
            (Version::V41, b"Entities") => {
                if self.entities.is_some() || self.index.is_some() {
                    return Err(fail(at, "one $Entities section before $Nodes", "$Entities"));
                }
                let enc = self.enc;
                let map = cur.run(|i| grammar::entities(enc, i), "an $Entities section")?;
                self.entities = Some(map);
                cur.end_of("Entities")?;
            }
            (Version::V41, b"PartitionedEntities") => {
                if self.partitioned.is_some() || self.index.is_some() {
                    return Err(fail(
                        at,
                        "one $PartitionedEntities section before $Nodes",
                        "$PartitionedEntities",
                    ));
                }
                let enc = self.enc;
                let map = cur.run(
                    |i| grammar::partitioned_entities(enc, i),
                    "a $PartitionedEntities section",
                )?;
                self.partitioned = Some(map);
                cur.end_of("PartitionedEntities")?;
            }
            (_, b"Nodes") => {
                if self.index.is_some() {
                    return Err(fail(at, "one $Nodes section", "a second $Nodes section"));
                }
                self.nodes(version, &mut cur)?;
            }
            (_, b"Elements") => {
                if self.index.is_none() {
                    return Err(fail(at, "$Nodes before $Elements", "$Elements"));
                }
                if self.elements_read {
                    return Err(fail(
                        at,
                        "one $Elements section",
                        "a second $Elements section",
                    ));
                }
                self.elements_read = true;
                match version {
                    Version::V2 => v2::elements(self, &mut cur)?,
                    Version::V41 => v4::elements(self, &mut cur)?,
                }
            }
            (Version::V2, b"ParametricNodes") => {
                return Err(fail(
                    at,
                    "$Nodes",
                    "$ParametricNodes (MSH 2 parametric nodes are not supported; save as MSH 4.1)",
                ))
            }
            _ => {
                // Sections of the other version ($Entities in MSH 2...): not ours to read.
                let name_str = String::from_utf8_lossy(name).into_owned();
                if self.skipped.len() < MAX_SKIPPED_NAMES && !self.skipped.contains(&name_str) {
                    self.skipped.push(name_str.clone());
                }
                return skip_section(self.data, at, body, &name_str);
            }
        }
        Ok(cur.p)
    }

    /// A position for a message: `line N`, or `byte N` in the binary part of a binary file.
    pub(crate) fn place(&self, at: usize) -> String {
        let at = at.min(self.data.len());
        match self.binary_from {
            Some(b) if at >= b => format!("byte {at}"),
            _ => format!(
                "line {}",
                1 + memchr::memchr_iter(b'\n', &self.data[..at]).count()
            ),
        }
    }

    /// Reads `$Nodes` and builds the node index; a repeated tag is located by reading again.
    fn nodes(&mut self, version: Version, cur: &mut Cur<'a>) -> Res<()> {
        let body = cur.p;
        let mut ids = Vec::new();
        let mut xyz = Vec::new();
        let read = |cur: &mut Cur<'a>,
                    ids: &mut Vec<u64>,
                    xyz: &mut Vec<[f64; 3]>,
                    offsets: Option<&mut Vec<usize>>| match version {
            Version::V2 => v2::nodes(cur, ids, xyz, offsets),
            Version::V41 => v4::nodes(cur, ids, xyz, offsets),
        };
        read(cur, &mut ids, &mut xyz, None)?;
        let index = match NodeIndex::build(&ids) {
            Ok(index) => index,
            Err(dup) => {
                drop(ids);
                drop(xyz);
                let mut again = Cur::new(self.data, body, self.enc);
                let (mut ids, mut xyz, mut offsets) = (Vec::new(), Vec::new(), Vec::new());
                read(&mut again, &mut ids, &mut xyz, Some(&mut offsets))?;
                let second = ids
                    .iter()
                    .enumerate()
                    .filter(|&(_, &t)| t == dup)
                    .nth(1)
                    .map_or(body, |(k, _)| offsets.get(k).copied().unwrap_or(body));
                return Err(fail(
                    second,
                    "a node tag not defined before",
                    format!("node tag {dup} a second time"),
                ));
            }
        };
        if index.get(0).is_some() {
            self.mesh.warnings.push(
                "node tag 0 used (MSH tags start at 1); it is kept as a node like any other"
                    .to_string(),
            );
        }
        self.mesh.node_ids = ids;
        self.mesh.coords = xyz;
        self.index = Some(index);
        Ok(())
    }

    /// Physical tags of the entity `(dim, tag)` of an MSH 4.1 element block.
    pub(crate) fn physicals_of(&self, dim: u8, tag: i64) -> &[i64] {
        if let Some(p) = self.partitioned.as_ref().and_then(|m| m.get(&(dim, tag))) {
            if !p.physicals.is_empty() {
                return &p.physicals;
            }
            return self
                .entities
                .as_ref()
                .and_then(|m| m.get(&p.parent))
                .map_or(&[], |v| v.as_slice());
        }
        self.entities
            .as_ref()
            .and_then(|m| m.get(&(dim, tag)))
            .map_or(&[], |v| v.as_slice())
    }

    /// Counts an element stored in a reduced form (for one warning per type).
    #[inline]
    pub(crate) fn note_reduced(&mut self, ty: &ElemType, count: usize) {
        if ty.note.is_some() && count > 0 {
            self.reduced.entry(ty.code).or_insert((0, *ty)).0 += count;
        }
    }

    fn finish(mut self) -> Mesh {
        let mut mesh = std::mem::take(&mut self.mesh);
        for (count, ty) in self.reduced.values() {
            mesh.warnings.push(format!(
                "{count} {} element(s) (gmsh type {}) {}",
                ty.name,
                ty.code,
                ty.note.unwrap_or("")
            ));
        }
        if !self.skipped.is_empty() {
            let list: Vec<String> = self.skipped.iter().map(|s| format!("${s}")).collect();
            mesh.warnings
                .push(format!("sections not read: {}", list.join(", ")));
        }
        let groups = std::mem::take(&mut self.groups);
        let mut mark: Vec<u32> = Vec::new();
        for (stamp, ((dim, tag), mut elements)) in groups.into_iter().enumerate() {
            elements.sort_unstable();
            elements.dedup();
            if elements.is_empty() {
                continue;
            }
            if mark.is_empty() {
                mark = vec![u32::MAX; mesh.node_count()];
            }
            let mut nodes = Vec::new();
            let dropped = &self.dropped;
            for &e in &elements {
                let from = dropped.partition_point(|&(x, _)| x < e);
                let extra = dropped[from..].iter().take_while(|&&(x, _)| x == e);
                let all = mesh
                    .element(e as usize)
                    .nodes
                    .iter()
                    .chain(extra.map(|(_, n)| n));
                for &n in all {
                    if n != MISSING_NODE && mark[n as usize] != stamp as u32 {
                        mark[n as usize] = stamp as u32;
                        nodes.push(n);
                    }
                }
            }
            nodes.sort_unstable();
            let name = self
                .names
                .remove(&(dim, tag))
                .filter(|n| !n.is_empty())
                .unwrap_or_else(|| default_name(dim, tag));
            mesh.sets.push(NamedSet {
                name,
                kind: SetKind::PhysicalGroup,
                nodes: Some(nodes),
                elements: Some(elements),
            });
        }
        if !mesh.element_kinds.iter().any(|k| k.is_solid()) {
            let lower = mesh.element_kinds.len();
            mesh.warnings.push(if mesh.sets.is_empty() {
                format!("no 3D solid elements ({lower} of lower dimension): mesh the volume (gmsh -3)")
            } else {
                format!(
                    "no 3D solid elements ({lower} of lower dimension, in physical groups): gmsh saves only the elements of physical groups once any is defined, so a Physical Surface without a Physical Volume leaves the volume out; add a Physical Volume, or set Mesh.SaveAll = 1"
                )
            });
        }
        mesh
    }
}

/// The name gmsh's INP export gives an unnamed physical group.
fn default_name(dim: u8, tag: i64) -> String {
    let what = match dim {
        0 => "Point",
        1 => "Line",
        2 => "Surface",
        _ => "Volume",
    };
    format!("Physical{what}{tag}")
}

/// At most this many names of skipped sections are listed in the warning (a file of many
/// distinct made-up sections would otherwise make the list and its search grow without end).
const MAX_SKIPPED_NAMES: usize = 32;

/// A section name for a message: at most 40 characters (a name is any run of letters).
fn short_name(name: &str) -> Cow<'_, str> {
    match name.char_indices().nth(40) {
        Some((cut, _)) => Cow::Owned(format!("{}...", &name[..cut])),
        None => Cow::Borrowed(name),
    }
}

/// Skips a section by searching for its `$EndName` line (at the start of a line), without
/// decoding what is in between (binary sections can hold any bytes). Returns the offset after.
fn skip_section(data: &[u8], at: usize, body: usize, name: &str) -> Res<usize> {
    let end = format!("$End{name}");
    let needle = end.as_bytes();
    // `body` is just past the header's newline, so search from that newline.
    let mut from = body.saturating_sub(1);
    let finder = memchr::memmem::Finder::new(needle);
    loop {
        let hay = data.get(from..).unwrap_or_default();
        let Some(k) = finder.find(hay) else {
            let name = short_name(name);
            return Err(fail(
                at,
                format!("$End{name} closing the ${name} section that starts here"),
                "end of file",
            ));
        };
        let start = from + k;
        let after = start + needle.len();
        let at_line_start = start == 0 || data[start - 1] == b'\n';
        let ends = match data.get(after) {
            None => true,
            Some(&b) => num::is_ws(b),
        };
        if at_line_start && ends {
            let mut p = after;
            while p < data.len() && data[p] != b'\n' {
                p += 1;
            }
            return Ok((p + 1).min(data.len()));
        }
        from = start + 1;
    }
}

/// Pushes an element given its nodes in file order (dense indices), converting the order.
/// Nodes a reduced type drops (hex27 centres, higher-order nodes) go to `dropped`, so that the
/// physical groups still list them.
#[inline]
pub(crate) fn push_converted(
    mesh: &mut Mesh,
    dropped: &mut Vec<(u32, u32)>,
    id: u64,
    ty: &ElemType,
    raw: &[u32],
    conv: &mut Vec<u32>,
) -> u32 {
    match ty.take {
        None => mesh.push_element(id, ty.kind, raw),
        Some(map) => {
            conv.clear();
            conv.extend(map.iter().map(|&k| raw[k as usize]));
            let e = mesh.push_element(id, ty.kind, conv);
            if ty.note.is_some() {
                // Reduced maps use exactly the first `map.len()` file nodes.
                dropped.extend(raw[map.len()..].iter().map(|&n| (e, n)));
            }
            e
        }
    }
}

/// Resolves an element type number read at `at`; unknown and unsupported types are errors.
pub(crate) fn element_type(cur: &Cur<'_>, at: usize, code: i64) -> Res<ElemType> {
    match types::lookup(code) {
        Lookup::Known(t) => Ok(t),
        Lookup::Unsupported(name, why) => Err(fail(
            at,
            "a supported element type",
            format!("type {code} ({name}): {why}"),
        )),
        Lookup::Unknown => {
            if cur.enc.is_binary() {
                Err(fail(
                    at,
                    "a known gmsh element type number",
                    format!("type {code}"),
                ))
            } else {
                Err(cur.fail_at(at, "a known gmsh element type number"))
            }
        }
    }
}

/// The dense index of node tag `tag` read at `at`, or an error naming the tag.
#[inline(always)]
pub(crate) fn node_of(index: &NodeIndex, tag: u64, cur: &Cur<'_>, at: usize) -> Res<u32> {
    match index.get(tag) {
        Some(i) => Ok(i),
        None => Err(undefined_node(tag, cur, at)),
    }
}

#[cold]
#[inline(never)]
fn undefined_node(tag: u64, cur: &Cur<'_>, at: usize) -> Box<Fail> {
    let mut s = at;
    if !cur.enc.is_binary() {
        while s < cur.d.len() && num::is_ws(cur.d[s]) {
            s += 1;
        }
    }
    fail(
        s,
        "a node tag defined in $Nodes",
        format!("node tag {tag}, which is not defined"),
    )
}

/// A capacity hint: the count from the file, capped by what the bytes left can hold.
pub(crate) fn cap(count: u64, fit: usize) -> usize {
    count.min(fit as u64) as usize
}
