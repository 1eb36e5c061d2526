//! A mesh of two solids that share no node (two cubes stacked 0.1 m apart in one file, gmsh's
//! defaults, `meshes/two_boxes_gap.msh`): one body whose pieces no bond joins, kept apart by
//! the contact between its pieces that `convert` writes (docs/guide/scene.md, "Contact").

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use pdcontact::body::PdBody;

const MESH: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/two_boxes_gap.msh");

/// `pdcontact convert` of the mesh into `dir`: the case file.
fn convert(dir: &Path) -> PathBuf {
    convert_mesh(MESH, dir)
}

/// `pdcontact convert` of `mesh` into `dir`: the case file.
fn convert_mesh(mesh: &str, dir: &Path) -> PathBuf {
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["convert", mesh, "-o"])
        .arg(dir)
        .arg("--quiet")
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir.join("case.toml")
}

/// `convert` of `mesh` as written, then `run` of its case: the model, once the case is seen to
/// hold the contact between the mesh's pieces and the run to converge.
fn converted_and_run(mesh: &str, name: &str) -> pdcontact::model::Model {
    let dir = common::temp_dir(name);
    let text = std::fs::read_to_string(convert_mesh(mesh, &dir)).expect("case");
    assert!(
        text.contains("slave = \"part\"\nmaster = \"part\""),
        "{text}"
    );
    // Pieces may start apart: ADR moves them until they touch, Newton's steps do not.
    assert!(text.contains("\nkind = \"adr\""), "{text}");
    let (model, summary) = common::run_text_in(&text, &dir).expect("runs");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(summary.converged);
    model
}

/// The contact across carries a piece's share of the load (by volume): its forces as a slave
/// and its reactions as a master together, within 1e-3 of its load.
fn assert_contact_carries_the_load(pd: &PdBody, in_piece: impl Fn(usize) -> bool) {
    let (mut load, mut contact) = (0.0, 0.0);
    for i in (0..pd.len()).filter(|&i| in_piece(i)) {
        load += pd.load[i].z;
        contact += pd.contact_force[i].z;
    }
    assert!(load < 0.0);
    assert!(
        ((contact + load) / load).abs() < 1e-3,
        "contact {contact} against load {load}"
    );
}

/// Whether particle `i` is of the upper cube (reference z from 1.1 m to 2.1 m).
fn upper(pd: &PdBody, i: usize) -> bool {
    pd.reference[i].z > 1.05
}

#[test]
fn the_pieces_of_a_mesh_rest_on_each_other_and_carry_the_load_across() {
    let model = converted_and_run(MESH, "pieces");
    let pd = model.bodies[0].as_pd().expect("deformable");
    let n = pd.len();
    // Every node of the two facing faces is a surface particle, though each face is nearer to
    // the other than the surface kernel reaches.
    let facing: Vec<usize> = (0..n)
        .filter(|&i| {
            (pd.reference[i].z - 1.0).abs() < 1e-9 || (pd.reference[i].z - 1.1).abs() < 1e-9
        })
        .collect();
    assert!(facing.len() > 100, "{}", facing.len());
    let missed = facing
        .iter()
        .filter(|&&i| !pd.case.surface.is_surface[i])
        .count();
    assert_eq!(missed, 0, "facing-face particles off the surface");
    // The upper cube came down the 0.1 m and rests on the lower one, no particle of its
    // underside deeper than a tenth of a spacing in it.
    let z = |i: usize| pd.reference[i].z + pd.u[i].z;
    let lower_top = (0..n)
        .filter(|&i| !upper(pd, i))
        .map(z)
        .fold(f64::MIN, f64::max);
    let upper_bottom = (0..n)
        .filter(|&i| upper(pd, i))
        .map(z)
        .fold(f64::MAX, f64::min);
    let dx = pd.spacing();
    assert!(
        upper_bottom > lower_top - 0.1 * dx,
        "{upper_bottom} vs {lower_top}"
    );
    assert!(
        upper_bottom < lower_top + 0.01,
        "the gap did not close: {upper_bottom} vs {lower_top}"
    );
    // The contact across carries the upper cube's load.
    assert_contact_carries_the_load(pd, |i| upper(pd, i));
}

/// Two solids of one file that touch (`meshes/roller_on_block.msh`: a roller lying on a
/// block, each meshed by gmsh's defaults, never fragmented) are not glued where they touch:
/// no gap lies between them for the bonds to be cut at, and before, the bonds along their
/// line of contact made them one piece to the model, which carried the roller's load
/// through bonds and left 168 of the facing faces' nodes off the surface. The file as one
/// body, as a user who does not split it into its parts writes it.
#[test]
fn pieces_that_touch_are_not_glued_where_they_touch() {
    let mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/roller_on_block.msh");
    let scene = format!(
        r#"[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 30000

[output]
folder = "out"
every = 100000

[[body]]
name = "part"
mesh = "{mesh}"
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0

[[load]]
body = "part"
force = [0.0, 0.0, -2e5]

[[symmetry]]
body = "part"
axis = "z"
at = -0.5
keep = "positive"

[[constraint]]
body = "part"
nearest = [0.0, 0.0, 0.3]
fix = ["x", "y"]

[[constraint]]
body = "part"
nearest = [0.0, 0.5, 0.3]
fix = ["x"]

[[constraint]]
body = "part"
nearest = [0.0, 0.0, -0.5]
fix = ["x", "y"]

[[constraint]]
body = "part"
nearest = [1.0, 0.0, -0.5]
fix = ["y"]

[[contact]]
slave = "part"
master = "part"
"#
    );
    let (model, summary) = common::run_text(&scene, "pieces-touch");
    assert!(summary.converged);
    let pd = model.bodies[0].as_pd().expect("deformable");
    // No bond joins the two solids: two pieces, the roller the smaller.
    let (label, sizes) = pd.case.bonds.components(|_| true);
    assert_eq!(sizes.len(), 2, "{sizes:?}");
    let roller = (sizes[1] < sizes[0]) as u32;
    // Every node of the mesh's boundary is a surface particle, the two facing faces' too.
    assert_eq!(pd.case.surface_agreement().missed, 0);
    // The roller rests on the block through the contact alone.
    assert_contact_carries_the_load(pd, |i| label[i] == roller);
}

/// `convert` of a file whose physical volumes name its parts (the roller and the block
/// above) writes each part as a body of its own (`elements`), the load shared by volume, the
/// parts pressed together by a two-pass contact; the case runs as written, and the contact
/// carries the roller's share of the load.
#[test]
fn convert_writes_each_named_part_as_a_body() {
    let mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/roller_on_block.msh");
    let dir = common::temp_dir("pieces-convert-parts");
    let text = std::fs::read_to_string(convert_mesh(mesh, &dir)).expect("case");
    for needle in [
        "name = \"block\"\n",
        "elements = \"block\"",
        "elements = \"roller\"",
        "slave = \"block\"\nmaster = \"plane\"",
        "slave = \"block\"\nmaster = \"roller\"\ntwo_pass = true",
    ] {
        assert!(text.contains(needle), "{needle:?} not in:\n{text}");
    }
    // The roller does not reach the plane, and no body is the mesh as a whole.
    assert!(
        !text.contains("slave = \"roller\"\nmaster = \"plane\""),
        "{text}"
    );
    assert!(!text.contains("name = \"part\""), "{text}");
    let (model, summary) = common::run_text_in(&text, &dir).expect("runs");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(summary.converged);
    let [block, roller] = [0, 1].map(|k| model.bodies[k].as_pd().expect("deformable"));
    assert_eq!(block.len() + roller.len(), 1726);
    // The shares by volume add up to the whole load.
    let load = |pd: &PdBody| (0..pd.len()).map(|i| pd.load[i].z).sum::<f64>();
    assert!(((load(block) + load(roller)) / -2e5 - 1.0).abs() < 1e-4);
    assert_contact_carries_the_load(roller, |_| true);
}

#[test]
fn pieces_that_no_contact_keeps_apart_are_named() {
    let dir = common::temp_dir("pieces-warn");
    let case = convert(&dir);
    let text = std::fs::read_to_string(&case).expect("case");
    // As written, with the pieces' contact: no warning of pieces (the mesh's own, that no
    // contact keeps them apart, is not repeated where one does).
    let scene = pdcontact::scene::Scene::load(&case).expect("loads");
    let (_, warnings, _) = pdcontact::run::check_scene(&scene).expect("checks");
    assert!(
        !warnings.iter().any(|w| w.contains("pieces")),
        "{warnings:?}"
    );
    let cut = text
        .find("\n# The mesh is 2 solids")
        .expect("the pieces' contact");
    std::fs::write(&case, &text[..cut]).expect("edited");
    let scene = pdcontact::scene::Scene::load(&case).expect("loads");
    let (_, warnings, _) = pdcontact::run::check_scene(&scene).expect("checks");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("is 2 pieces that no bond joins")
                && w.contains("pass through each other")),
        "{warnings:?}"
    );
}

/// Two unit hex8 cubes stacked, meshed apart: the lower one's top nodes and the upper one's
/// bottom nodes lie on each other (nodes 5-8 and 9-12).
const COINCIDENT: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n16\n\
1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n\
9 0 0 1\n10 1 0 1\n11 1 1 1\n12 0 1 1\n13 0 0 2\n14 1 0 2\n15 1 1 2\n16 0 1 2\n$EndNodes\n\
$Elements\n2\n1 5 2 0 1 1 2 3 4 5 6 7 8\n2 5 2 0 2 9 10 11 12 13 14 15 16\n$EndElements\n";

#[test]
fn nodes_on_top_of_each_other_are_refused_by_name() {
    let dir = common::temp_dir("pieces-coincident");
    let mesh = dir.join("stacked.msh");
    std::fs::write(&mesh, COINCIDENT).expect("mesh");
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["convert", "--quiet", "-o"])
        .arg(dir.join("case"))
        .arg(&mesh)
        .output()
        .expect("runs");
    let _ = std::fs::remove_dir_all(&dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("stacked.msh"), "{err}");
    assert!(err.contains("nodes on top of each other (node 5 and node 9 at [0.000000e0, 0.000000e0, 1.000000e0])"), "{err}");
}

/// The same cubes, each its own physical volume: the parts of an assembly, which touch. Each is
/// a body of its own in the case `convert` writes, so the nodes on top of each other are not
/// refused (gmsh's tet10 and hex meshes of a roller on a block have two such pairs where the
/// roller touches the block).
#[test]
fn nodes_on_top_of_each_other_in_two_named_parts_are_two_bodies_touching() {
    let dir = common::temp_dir("pieces-coincident-parts");
    let mesh = dir.join("stacked.msh");
    let named = COINCIDENT
        .replace(
            "$EndMeshFormat\n",
            "$EndMeshFormat\n$PhysicalNames\n2\n3 1 \"lower\"\n3 2 \"upper\"\n$EndPhysicalNames\n",
        )
        .replace("1 5 2 0 1 ", "1 5 2 1 1 ")
        .replace("2 5 2 0 2 ", "2 5 2 2 2 ");
    std::fs::write(&mesh, named).expect("mesh");
    let text = std::fs::read_to_string(convert_mesh(
        mesh.to_str().expect("utf-8"),
        &dir.join("case"),
    ))
    .expect("case");
    let _ = std::fs::remove_dir_all(&dir);
    for needle in [
        "elements = \"lower\"",
        "elements = \"upper\"",
        "slave = \"lower\"\nmaster = \"upper\"",
    ] {
        assert!(text.contains(needle), "{needle:?} not in:\n{text}");
    }
}

/// A plate written by another tool (`hybrid_hexwedge.msh` of the shared corpus: 6,000 ×
/// 6,000 × 100, one element through the thickness; a row of hexes 1,043 long beside cells of
/// 500-700): one solid, but with the default horizon (3 Δ, Δ = 292) no bond spans the long
/// hexes, and its bonds leave it in two pieces. `run` refuses it by that cause, naming the
/// element and the horizon factor that joins them; `convert` writes that factor (before, it
/// took the pieces for solids that share no node and wrote a contact between them, which
/// pushed on faces inside the one solid: the run diverged, residual 6e2 after 100,000
/// iterations).
#[test]
fn a_solid_that_the_horizon_leaves_in_pieces_is_refused_and_convert_joins_it() {
    let mesh =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus/msh/hybrid_hexwedge.msh");
    if !mesh.exists() {
        common::skipped("the horizon's pieces", "no shared corpus");
        return;
    }
    let dir = common::temp_dir("pieces-horizon");
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["convert", "-o"])
        .arg(dir.join("case"))
        .arg(&mesh)
        .output()
        .expect("runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("with horizon factor 3 the bonds cut the mesh's solids into 1 more piece")
            && err.contains("the case has horizon_factor = 3.2"),
        "{err}"
    );
    let case = dir.join("case/case.toml");
    let text = std::fs::read_to_string(&case).expect("case");
    assert!(text.contains("horizon_factor = 3.2 "), "{text}");
    assert!(!text.contains("master = \"part\""), "{text}");
    // The case as written, from its own folder (its mesh path is relative to it).
    let (model, summary) = common::run_text_in(&text, &dir.join("case")).expect("runs");
    assert!(summary.converged);
    assert!(
        summary.force_balance_error < 1e-3,
        "{}",
        summary.force_balance_error
    );
    let pd = model.bodies[0].as_pd().expect("deformable");
    assert_eq!(pd.case.bonds.components(|_| true).1.len(), 1);

    // The default horizon: refused before the first step, by its cause.
    std::fs::write(
        &case,
        text.replace("horizon_factor = 3.2 ", "horizon_factor = 3 "),
    )
    .expect("edited");
    let scene = pdcontact::scene::Scene::load(&case).expect("loads");
    let Err(err) = pdcontact::run::check_scene(&scene) else {
        panic!("a solid in pieces was not refused");
    };
    let err = err.to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        err.contains("element 28 joins nodes 37 and 38, 1.0434e3 m apart")
            && err.contains("Set horizon_factor = 3.2"),
        "{err}"
    );
}

/// The roller and the block of `meshes/roller_on_block.msh` as two bodies of one file, each
/// the solids of its physical volume (`elements = "roller"`, `"block"`), the roller three
/// times as stiff, pressed on the block through a two-pass contact.
fn assembly(roller_elements: &str) -> String {
    let mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/roller_on_block.msh");
    format!(
        r#"[solver]
kind = "adr"
tolerance = 1e-4
max_iterations = 30000

[output]
folder = "out"
every = 100000

[[body]]
name = "block"
mesh = "{mesh}"
elements = "block"
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0

[[body]]
name = "roller"
mesh = "{mesh}"
elements = "{roller_elements}"
kinematics = "small"
[body.material]
youngs_modulus = 3e9
poisson_ratio = 0.25
density = 1000.0

[[load]]
body = "roller"
force = [0.0, 0.0, -4e4]

[[symmetry]]
body = "block"
axis = "z"
at = -0.5
keep = "positive"

[[constraint]]
body = "roller"
nearest = [0.0, 0.0, 0.3]
fix = ["x", "y"]

[[constraint]]
body = "roller"
nearest = [0.0, 0.5, 0.3]
fix = ["x"]

[[constraint]]
body = "block"
nearest = [0.0, 0.0, -0.5]
fix = ["x", "y"]

[[constraint]]
body = "block"
nearest = [1.0, 0.0, -0.5]
fix = ["y"]

[[contact]]
slave = "roller"
master = "block"
"#
    )
}

/// An assembly meshed in one file, each part a body of its own (`elements`): each body holds
/// the particles of its part alone, in one piece, and the contact between them carries the load.
#[test]
fn the_parts_of_one_mesh_file_are_bodies_of_their_own() {
    let (model, summary) = common::run_text(&assembly("roller"), "pieces-parts");
    assert!(summary.converged);
    let [block, roller] = [0, 1].map(|k| model.bodies[k].as_pd().expect("deformable"));
    // The parts' particles are the file's (`convert` of the whole: 1,726), each where its part
    // lies: the block below z = 0, the roller within its radius of its axis.
    assert_eq!(block.len() + roller.len(), 1726);
    assert!((0..block.len()).all(|i| block.reference[i].z <= 1e-9));
    assert!((0..roller.len()).all(|i| {
        let x = roller.reference[i];
        (x.x * x.x + (x.z - 0.3) * (x.z - 0.3)).sqrt() <= 0.3 + 1e-9
    }));
    for pd in [block, roller] {
        assert_eq!(pd.case.bonds.components(|_| true).1.len(), 1);
    }
    // No warning of a body in pieces: the file's pieces are its parts.
    assert!(
        summary.warnings.iter().all(|w| !w.contains("pieces")),
        "{:?}",
        summary.warnings
    );
    // The contact carries the roller's load (measured 2.6e-5 apart).
    let contact: f64 = (0..roller.len()).map(|i| roller.contact_force[i].z).sum();
    assert!(((contact - 4e4) / 4e4).abs() < 1e-3, "contact {contact}");
}

#[test]
fn a_part_that_the_mesh_does_not_name_is_refused_with_the_names_it_has() {
    let err = match common::try_run_text(&assembly("rollers"), "pieces-no-part") {
        Err(e) => e.to_string(),
        Ok(_) => panic!("no set \"rollers\": the run must fail"),
    };
    for needle in [
        "scene.toml:",
        "elements = \"rollers\" is not a set of the mesh",
        "\"block\", \"roller\"",
    ] {
        assert!(err.contains(needle), "{needle:?} not in: {err}");
    }
}

/// Two unit hex8 cubes 0.5 m apart, as gmsh exports an assembly to INP: each element block
/// an `*ELSET` of its own (`Volume1`, `Volume2`), then the physical volumes' (`base`, `top`),
/// which hold the same elements.
const TWO_PARTS_INP: &str = "*NODE\n\
1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 0, 0, 1\n6, 1, 0, 1\n7, 1, 1, 1\n8, 0, 1, 1\n\
9, 0, 0, 1.5\n10, 1, 0, 1.5\n11, 1, 1, 1.5\n12, 0, 1, 1.5\n\
13, 0, 0, 2.5\n14, 1, 0, 2.5\n15, 1, 1, 2.5\n16, 0, 1, 2.5\n\
*ELEMENT, type=C3D8, ELSET=Volume1\n1, 1, 2, 3, 4, 5, 6, 7, 8\n\
*ELEMENT, type=C3D8, ELSET=Volume2\n2, 9, 10, 11, 12, 13, 14, 15, 16\n\
*ELSET, ELSET=base\n1\n*ELSET, ELSET=top\n2\n";

/// The parts are the user's sets: a set that holds the same solids as a later one gives way
/// to it; sets that overlap name no parts, and the file is one body in pieces.
#[test]
fn convert_takes_the_parts_by_the_users_names_and_not_from_sets_that_overlap() {
    let dir = common::temp_dir("pieces-inp-parts");
    let mesh = dir.join("two.inp");
    std::fs::write(&mesh, TWO_PARTS_INP).expect("mesh");
    let text = std::fs::read_to_string(convert_mesh(mesh.to_str().expect("utf-8"), &dir.join("a")))
        .expect("case");
    for needle in [
        "elements = \"base\"",
        "elements = \"top\"",
        "master = \"top\"\ntwo_pass = true",
    ] {
        assert!(text.contains(needle), "{needle:?} not in:\n{text}");
    }
    assert!(!text.contains("elements = \"Volume"), "{text}");
    // A set over both cubes: the sets overlap, and the file stays one body in pieces.
    std::fs::write(&mesh, format!("{TWO_PARTS_INP}*ELSET, ELSET=all\n1, 2\n")).expect("mesh");
    let text = std::fs::read_to_string(convert_mesh(mesh.to_str().expect("utf-8"), &dir.join("b")))
        .expect("case");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(!text.contains("\nelements = "), "{text}");
    assert!(
        text.contains("slave = \"part\"\nmaster = \"part\""),
        "{text}"
    );
}
