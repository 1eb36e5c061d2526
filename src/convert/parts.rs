//! The parts of an assembly meshed in one file. Where the mesh's named sets (physical
//! volumes, CDB components, `*ELSET`s) split its solids into two or more parts that share no
//! node, `convert` writes each part as a `[[body]]` of its own (`elements = "NAME"`), so that
//! each can be given its own material, loads and supports, and the parts meet through
//! contacts between them (docs/guide/scene.md, "Contact").

use pdcontact_importers::{Mesh, MISSING_NODE};

use crate::case::PdCase;

/// One part: its set's name, its particles' volume and their bounding box.
pub(super) struct Part {
    pub name: String,
    pub volume: f64,
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

/// The mesh's parts: `None` unless the sets that hold solids are two or more, hold every
/// solid once, share no node, and are named so that a body can take the name (no other set
/// of that name, whatever its case; not the skeleton's rigid "plane"; nothing TOML would
/// need escaped).
pub(super) fn parts(case: &PdCase) -> Option<Vec<Part>> {
    let (names, node_owner) = part_sets(&case.mesh)?;
    let mut parts: Vec<Part> = names
        .into_iter()
        .map(|name| Part {
            name,
            volume: 0.0,
            lo: [f64::INFINITY; 3],
            hi: [f64::NEG_INFINITY; 3],
        })
        .collect();
    let p = &case.particles;
    for i in 0..p.len() {
        let Some(&k) = node_owner.get(p.node[i] as usize) else {
            continue;
        };
        let Some(part) = parts.get_mut(k as usize) else {
            continue;
        };
        part.volume += p.volume[i];
        for d in 0..3 {
            part.lo[d] = part.lo[d].min(p.position[i][d]);
            part.hi[d] = part.hi[d].max(p.position[i][d]);
        }
    }
    parts.iter().all(|q| q.volume > 0.0).then_some(parts)
}

/// The line that makes a body of the part's solids.
pub(super) fn elements_line(name: &str) -> String {
    format!("elements = \"{name}\"      # the solids of the mesh's set \"{name}\": one part of the assembly\n")
}

/// The parts' loads (the skeleton's force `fz` shared by volume), their contacts (on the
/// plane, those whose underside is within two spacings of the lowest; between them, each pair
/// whose boxes come within two spacings, checked both ways) and their pins.
pub(super) fn loads_contacts_pins(
    parts: &[Part],
    fz: f64,
    reason: &str,
    penalty: &str,
    radius: Option<f64>,
    spacing: f64,
    rounded: impl Fn(f64) -> f64,
) -> String {
    let total: f64 = parts.iter().map(|p| p.volume).sum();
    let mut out = format!(
        "# The mesh's sets split its solids into {} parts that share no node: each is a [[body]]
# above (elements = its set), to be given a material of its own. The total force, {:e} N,
# is shared by volume; the contacts below keep the parts apart and carry it across.
# The force: {reason}.
",
        parts.len(),
        rounded(fz),
    );
    for p in parts {
        out.push_str(&format!(
            r#"
[[load]]
body = "{name}"
force = [0.0, 0.0, {f:e}]  # N: its share by volume
"#,
            name = p.name,
            f = rounded(fz * p.volume / total),
        ));
    }
    let bottom = parts.iter().map(|p| p.lo[2]).fold(f64::INFINITY, f64::min);
    for p in parts.iter().filter(|p| p.lo[2] <= bottom + 2.0 * spacing) {
        out.push_str(&format!(
            "\n[[contact]]\nslave = \"{}\"\nmaster = \"plane\"\n{penalty}",
            p.name
        ));
    }
    let radius = radius.map_or(String::new(), |r| format!("radius = {r:e}\n"));
    for (i, a) in parts.iter().enumerate() {
        for b in &parts[i + 1..] {
            let near = (0..3)
                .all(|d| a.lo[d] <= b.hi[d] + 2.0 * spacing && b.lo[d] <= a.hi[d] + 2.0 * spacing);
            if near {
                out.push_str(&format!(
                    "\n[[contact]]\nslave = \"{}\"\nmaster = \"{}\"\ntwo_pass = true        # each part's surface against the other's faces\n{radius}",
                    a.name, b.name
                ));
            }
        }
    }
    out.push('\n');
    out.push_str(super::pins::PINS_INTRO);
    for (k, p) in parts.iter().enumerate() {
        if k > 0 {
            out.push('\n');
        }
        out.push_str(&super::pins::pins(
            &p.name,
            &p.lo,
            &p.hi,
            &format!(" of \"{}\"", p.name),
        ));
    }
    out
}

/// Whether the mesh's sets name its parts ([`parts`]): then its pieces may touch, nodes of
/// two parts on top of each other, as parts of an assembly do.
pub(super) fn named(mesh: &Mesh) -> bool {
    part_sets(mesh).is_some()
}

/// The parts' names and each node's part ([`parts`]).
fn part_sets(mesh: &Mesh) -> Option<(Vec<String>, Vec<u32>)> {
    // Each set's solids, in the file's order of sets.
    let mut sets: Vec<(&str, Vec<usize>)> = mesh
        .sets
        .iter()
        .filter_map(|set| {
            let mut solids: Vec<usize> = set
                .elements
                .as_ref()?
                .iter()
                .map(|&e| e as usize)
                .filter(|&e| e < mesh.element_count() && mesh.element(e).kind.is_solid())
                .collect();
            solids.sort_unstable();
            solids.dedup();
            (!solids.is_empty()).then_some((set.name.as_str(), solids))
        })
        .collect();
    // A set that holds the same solids as a later one names the same part twice (gmsh's INP
    // export writes `Volume1` with the elements, then the physical volume's `*ELSET`): the
    // later name, the user's, is kept.
    let mut k = 0;
    while k < sets.len() {
        if sets[k + 1..].iter().any(|(_, later)| *later == sets[k].1) {
            sets.remove(k);
        } else {
            k += 1;
        }
    }
    let mut owner = vec![u32::MAX; mesh.element_count()];
    let mut node_owner = vec![u32::MAX; mesh.node_count()];
    let mut names: Vec<String> = Vec::new();
    for (name, solids) in sets {
        let k = names.len() as u32;
        for e in solids {
            if owner[e] != u32::MAX {
                return None;
            }
            owner[e] = k;
            for &n in mesh.element(e).nodes.iter().filter(|&&n| n != MISSING_NODE) {
                let seen = &mut node_owner[n as usize];
                if *seen != u32::MAX && *seen != k {
                    return None;
                }
                *seen = k;
            }
        }
        names.push(name.to_string());
    }
    if names.len() < 2 || mesh.solids().any(|e| owner[e.index as usize] == u32::MAX) {
        return None;
    }
    let usable = |name: &String| {
        !name.is_empty()
            && !name.eq_ignore_ascii_case("plane")
            && !name
                .chars()
                .any(|c| c == '"' || c == '\\' || c.is_control())
            && mesh
                .sets
                .iter()
                .filter(|s| s.name.eq_ignore_ascii_case(name))
                .count()
                == 1
    };
    if !names.iter().all(usable) {
        return None;
    }
    Some((names, node_owner))
}
