//! The frames a run leaves for ParaView, read back as XML: `run.pvd` timesteps, the named
//! blocks of each `frame_NNNNNN.vtm`, and the field data of each dataset.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-frames-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// A 1 × 1 × 0.5 m block (spacing 0.25) pressed by 100 kN onto a rigid plane 1 cm below it.
fn scene(solver: &str, every: usize) -> String {
    format!(
        r#"[solver]
{solver}
[output]
every = {every}
folder = "out"
[[body]]
name = "block"
generator = {{ shape = "box", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 0.5], spacing = 0.25 }}
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[body]]
name = "floor"
kind = "rigid"
generator = {{ shape = "plane", point = [0.0, 0.0, -0.01], normal = [0.0, 0.0, 1.0], size = 3.0 }}
[[contact]]
slave = "block"
master = "floor"
[[load]]
body = "block"
force = [0.0, 0.0, -1e5]
"#
    )
}

/// Runs a scene; returns its output folder.
fn run(name: &str, text: &str) -> PathBuf {
    let dir = temp_dir(name);
    std::fs::write(dir.join("scene.toml"), text).expect("scene");
    let out = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["run", "--quiet"])
        .arg(dir.join("scene.toml"))
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir.join("out")
}

/// A one-value field data array of a `.vtu`.
fn field_value(vtu: &Path, name: &str) -> f64 {
    let text = std::fs::read_to_string(vtu).expect("vtu");
    let field = text
        .split_once("<FieldData>")
        .and_then(|(_, r)| r.split_once("</FieldData>"))
        .unwrap_or_else(|| panic!("{vtu:?}: no FieldData"))
        .0;
    let tag = format!("Name=\"{name}\"");
    let (_, rest) = field
        .split_once(&tag)
        .unwrap_or_else(|| panic!("{vtu:?}: no field {name}"));
    let value = rest.split_once('>').expect("element").1;
    value
        .split('<')
        .next()
        .expect("value")
        .trim()
        .parse()
        .expect("number")
}

/// What `view.py --focus` prints (Python's vtk, no ParaView): the camera it would use, the
/// caption and the legend, as JSON. Run from another folder: the script finds its run by
/// its own place.
fn focus(script: &Path) -> serde_json::Value {
    let run = Command::new("python3")
        .arg(script)
        .arg("--focus")
        .current_dir(std::env::temp_dir())
        .output()
        .expect("python3 runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    serde_json::from_slice(&run.stdout).expect("JSON")
}

/// Block and dataset names of a frame, and its files.
fn frame(out: &Path, vtm: &str) -> (Vec<String>, Vec<String>, Vec<String>) {
    let text = std::fs::read_to_string(out.join(vtm)).expect("vtm");
    assert!(text.contains("type=\"vtkMultiBlockDataSet\""), "{text}");
    (
        common::attributes(&text, "Block", "name"),
        common::attributes(&text, "DataSet", "name"),
        common::attributes(&text, "DataSet", "file"),
    )
}

/// ADR in three load increments, frames only at their ends: the timesteps are the load
/// factors 1/3, 2/3, 1, and each frame's `load_factor` says the same.
#[test]
fn adr_frames_at_the_load_factors_with_named_blocks() {
    let out = run("adr", &scene("kind = \"adr\"\nload_steps = 3", 1_000_000));
    let entries = common::pvd(&out);
    assert_eq!(entries.len(), 3, "{entries:?}");
    for (k, (t, vtm)) in entries.iter().enumerate() {
        let factor = (k + 1) as f64 / 3.0;
        assert!((t - factor).abs() < 1e-8, "{entries:?}");
        let (blocks, datasets, files) = frame(&out, vtm);
        assert_eq!(blocks, ["block"]);
        assert_eq!(datasets, ["particles", "surface", "floor"]);
        let stem = vtm.strip_suffix(".vtm").expect("vtm");
        assert_eq!(
            files,
            [
                format!("{stem}/block_particles.vtu"),
                format!("{stem}/block_surface.vtu"),
                format!("{stem}/floor.vtu"),
            ]
        );
        for f in &files {
            let lf = field_value(&out.join(f), "load_factor");
            assert!((lf - factor).abs() < 1e-12, "{f}: {lf}");
        }
    }
    let plane = ["--plane-normal", "0,0,1", "--plane-point", "0,0,-0.01"];
    let mut args = vec![OsStr::new("run"), out.as_os_str()];
    args.extend(plane.map(OsStr::new));
    common::check_vtk(&args);
    view_focus(&out);
    let _ = std::fs::remove_dir_all(out.parent().expect("dir"));
}

/// `view.py` beside `run.pvd` names the pair and, without ParaView (`--focus`, Python's vtk),
/// aims at the contact: the bottom face pressed onto the floor at z = −0.01, normal −z.
fn view_focus(out: &Path) {
    let script = out.join("view.py");
    let text = std::fs::read_to_string(&script).expect("view.py");
    assert!(text.contains("PAIRS = [(\"block\", \"floor\")]"), "{text}");
    assert!(text.contains("DEFORMABLE = [\"block\"]"), "{text}");
    if !common::python_has("vtk") {
        common::skipped(
            "view.py --focus",
            "python3 with vtk not found (pip install vtk)",
        );
        return;
    }
    let r = focus(&script);
    assert_eq!(r["masters"], serde_json::json!(["floor"]));
    assert_eq!(r["slaves"], serde_json::json!(["block"]));
    assert!(r["loaded"].as_u64().expect("count") > 0, "{r}");
    let z = r["centre"][2].as_f64().expect("z");
    assert!((z + 0.01).abs() < 0.005, "{r}");
    assert!(r["normal"][2].as_f64().expect("nz") < -0.99, "{r}");
    // The camera looks up at the contact through the floor.
    assert!(r["position"][2].as_f64().expect("z") < z, "{r}");
    // The picture's corner text names the pair and the frame's load factor; the legend, the
    // pressure's unit.
    let caption = r["caption"].as_str().expect("caption");
    assert!(
        caption.starts_with("block on floor\nload factor 1 (ADR iteration "),
        "{r}"
    );
    let legend = r["legend"].as_str().expect("legend");
    assert!(legend.starts_with("contact pressure ("), "{r}");
}

/// Explicit: the timesteps are the times, as each frame's field data `time` says.
#[test]
fn explicit_frames_at_their_times() {
    let out = run(
        "explicit",
        &scene("kind = \"explicit\"\nend_time = 2e-3", 5),
    );
    let entries = common::pvd(&out);
    assert!(entries.len() >= 2, "{entries:?}");
    assert!(entries.windows(2).all(|w| w[0].0 < w[1].0), "{entries:?}");
    for (t, vtm) in &entries {
        let (_, _, files) = frame(&out, vtm);
        let time = field_value(&out.join(&files[0]), "time");
        assert!(
            (time - t).abs() <= 1e-8 * time.abs(),
            "{vtm}: {time} vs {t}"
        );
    }
    let _ = std::fs::remove_dir_all(out.parent().expect("dir"));
}

/// Whether a command is on the PATH.
fn found(tool: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {tool}")])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Renders a run's `view.py` to `png` offscreen, by the README's command. `-noreset`: pvpython
/// connects to the X server three times in a row, and a server that resets when its last
/// client leaves can refuse the next one ("bad X server connection").
fn render(script: &Path, png: &Path) {
    let render = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x1024x24 -noreset", "pvpython"])
        .arg(script)
        .arg(png)
        .output()
        .expect("xvfb-run runs");
    assert!(
        render.status.success() && png.is_file(),
        "{}{}",
        String::from_utf8_lossy(&render.stdout),
        String::from_utf8_lossy(&render.stderr)
    );
}

/// With ParaView at hand (`pvpython` and `xvfb-run`), `view.py` renders the last frame of the
/// demo offscreen through the README's command, and the PNG, at the script's 1600 × 1000, shows
/// the contact and reads: the image centre, where the camera looks at the loaded surface, is
/// warm (red over blue) and unlike the background (the upper right corner); the upper left
/// corner holds the caption (white text), the lower right the legend: its colour bar (red and
/// blue) and labels; and the text is sized for the picture (a sliver of it white, where the
/// legend of ParaView's scaled fonts was eight times as much). Skipped, saying so, where
/// ParaView or Python's vtk (to read the PNG) is missing.
#[test]
fn view_py_renders_the_contact_in_paraview() {
    let vtk = common::python_has("vtk");
    if !(found("pvpython") && found("xvfb-run") && vtk) {
        common::skipped(
            "view.py render",
            "pvpython, xvfb-run or python3's vtk not found (apt-get install paraview python3-paraview xvfb)",
        );
        return;
    }
    let dir = temp_dir("view");
    let out = dir.join("demo");
    let demo = Command::new(env!("CARGO_BIN_EXE_pdcontact"))
        .args(["demo", "--quiet", "--output"])
        .arg(&out)
        .output()
        .expect("demo runs");
    assert!(
        demo.status.success(),
        "{}",
        String::from_utf8_lossy(&demo.stderr)
    );
    let script = out.join("view.py");
    let r = focus(&script);
    let caption = r["caption"].as_str().expect("caption");
    assert!(
        caption.starts_with("ball on plane\nload factor 1 (Newton iteration "),
        "{r}"
    );
    assert_eq!(r["legend"], "contact pressure (MPa)", "{r}");
    let png = dir.join("contact.png");
    render(&script, &png);
    // The picture's size; the mean colour of a window at the centre and of the upper right
    // corner; the fraction of white (text) pixels; and the count of white pixels in the upper
    // left corner, of white, red and blue ones in the lower right.
    let probe = r#"
import sys, vtk
from vtk.util.numpy_support import vtk_to_numpy
r = vtk.vtkPNGReader(); r.SetFileName(sys.argv[1]); r.Update()
w, h, _ = r.GetOutput().GetDimensions()
img = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).reshape(h, w, -1)[::-1, :, :3] / 255.0
white = (img > 0.85).all(2)
red = (img[:, :, 0] > 0.6) & (img[:, :, 2] < 0.35)
blue = (img[:, :, 2] > 0.6) & (img[:, :, 0] < 0.4)
caption = (slice(0, h // 10), slice(0, w // 4))
legend = (slice(h // 2, h), slice(w * 17 // 20, w))
print(w, h)
print(*img[h // 2 - h // 40: h // 2 + h // 40, w // 2 - w // 40: w // 2 + w // 40].reshape(-1, 3).mean(0))
print(*img[: h // 20, -(w // 20):].reshape(-1, 3).mean(0))
print(white.mean(), white[caption].sum(), white[legend].sum(), red[legend].sum(), blue[legend].sum())
"#;
    let probed = Command::new("python3")
        .args(["-c", probe])
        .arg(&png)
        .output()
        .expect("python3 runs");
    let text = String::from_utf8_lossy(&probed.stdout);
    let rows: Vec<Vec<f64>> = text
        .lines()
        .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(
        rows.iter().map(Vec::len).collect::<Vec<_>>(),
        [2, 3, 3, 5],
        "{text}{}",
        String::from_utf8_lossy(&probed.stderr)
    );
    assert_eq!(rows[0], [1600.0, 1000.0], "picture size");
    let (centre, corner) = (&rows[1], &rows[2]);
    assert!(centre[0] > centre[2] + 0.2, "centre not warm: {centre:?}");
    assert!(
        (centre[0] - corner[0]).abs() > 0.2,
        "centre {centre:?}, corner {corner:?}"
    );
    let (white, caption, legend, red, blue) =
        (rows[3][0], rows[3][1], rows[3][2], rows[3][3], rows[3][4]);
    assert!(
        caption > 100.0,
        "no caption in the upper left corner: {text}"
    );
    assert!(
        legend > 100.0 && red > 100.0 && blue > 100.0,
        "no legend in the lower right corner: {text}"
    );
    assert!(white < 0.004, "text oversized: {:.2}% white", 100.0 * white);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Where bonds broke, `view.py` shows the damage: the block of `scene` cut by a pre-crack
/// reaching down from its top face (the cut shows as damage, METHOD.md §9) is seen along its
/// thinnest axis, z, from the side the damage lies on, above it (the undamaged particles and
/// the floor below would hide it); with ParaView at hand the picture shows the damaged
/// particles in colour at its centre. Skipped, saying so, without Python's vtk (or ParaView
/// for the picture).
#[test]
fn view_py_looks_at_the_damage_from_its_side() {
    let text = scene("kind = \"adr\"\ntolerance = 1e-3", 1_000_000)
        .replace("spacing = 0.25", "spacing = 0.1")
        + "[[precrack]]\nbody = \"block\"\npoint = [0.5, 0.5, 0.45]\nnormal = [1.0, 0.0, 0.0]\n\
           along = [0.0, 0.0, 1.0]\nsize = [0.2, 0.6]\n";
    let out = run("damage", &text);
    if !common::python_has("vtk") {
        common::skipped(
            "view.py --focus on damage",
            "python3 with vtk not found (pip install vtk)",
        );
        return;
    }
    let script = out.join("view.py");
    let r = focus(&script);
    assert!(r["damaged"].as_u64().expect("count") > 0, "{r}");
    assert!(r["normal"][2].as_f64().expect("nz") > 0.99, "{r}");
    let centre = &r["centre"];
    assert!(
        (centre[0].as_f64().expect("x") - 0.5).abs() < 0.1 && centre[2].as_f64().expect("z") > 0.25,
        "{r}"
    );
    assert!(
        r["caption"]
            .as_str()
            .expect("caption")
            .contains("particles damaged"),
        "{r}"
    );
    if !(found("pvpython") && found("xvfb-run")) {
        common::skipped(
            "view.py render of damage",
            "pvpython or xvfb-run not found (apt-get install paraview python3-paraview xvfb)",
        );
        return;
    }
    let png = out.join("damage.png");
    render(&script, &png);
    // Coloured pixels (the colour map's, not the grey body, background or white text) in the
    // middle third of the picture.
    let probe = r#"
import sys, vtk
from vtk.util.numpy_support import vtk_to_numpy
r = vtk.vtkPNGReader(); r.SetFileName(sys.argv[1]); r.Update()
w, h, _ = r.GetOutput().GetDimensions()
img = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3] / 255.0
mid = img[h // 3: 2 * h // 3, w // 3: 2 * w // 3]
print(int(((mid.max(2) - mid.min(2)) > 0.3).sum()))
"#;
    let probed = Command::new("python3")
        .args(["-c", probe])
        .arg(&png)
        .output()
        .expect("python3 runs");
    let coloured: usize = String::from_utf8_lossy(&probed.stdout)
        .trim()
        .parse()
        .unwrap_or_else(|_| panic!("{}", String::from_utf8_lossy(&probed.stderr)));
    assert!(coloured > 200, "{coloured} coloured pixels at the centre");
    let _ = std::fs::remove_dir_all(out.parent().expect("dir"));
}

/// A body pressed on itself across a pre-crack: its contact lies inside it, behind its outer
/// faces, and `view.py` aims along the crack's normal at the faces in contact (the two faces'
/// normals, opposite, counted one way), drawing them alone inside the body drawn faintly; the
/// same on the faces found again (`faces = "found"`), where the pre-crack's broken bonds show
/// as damage in the frames but the picture shows the faces' pressure (it showed the damage).
/// Without python3's vtk, skipped, saying so.
#[test]
fn view_py_aims_at_a_closed_crack_inside_the_body() {
    if !common::python_has("vtk") {
        common::skipped(
            "view.py --focus on a crack",
            "python3 with vtk not found (pip install vtk)",
        );
        return;
    }
    let text = r#"[solver]
kind = "adr"
[output]
every = 1000000
folder = "out"
[[body]]
name = "block"
generator = { shape = "box", min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], spacing = 0.1 }
kinematics = "small"
[body.material]
youngs_modulus = 1e9
poisson_ratio = 0.25
density = 1000.0
[[symmetry]]
body = "block"
axis = "x"
[[symmetry]]
body = "block"
axis = "y"
[[constraint]]
body = "block"
set = "bottom"
fix = ["z"]
[[load]]
body = "block"
force = [0.0, 0.0, -1e5]
[[precrack]]
body = "block"
point = [0.5, 0.5, 0.55]
normal = [0.0, 0.0, 1.0]
along = [1.0, 0.0, 0.0]
size = [3.0, 3.0]
[[contact]]
slave = "block"
master = "block"
"#;
    let found = text.replace(
        "master = \"block\"\n",
        "master = \"block\"\nfaces = \"found\"\n",
    );
    assert!(found.contains("faces = \"found\""));
    for (name, text) in [("crack-view", text), ("crack-view-found", found.as_str())] {
        let out = run(name, text);
        let r = focus(&out.join("view.py"));
        assert!(r["loaded"].as_u64().expect("count") > 0, "{name}: {r}");
        assert_eq!(r["damaged"].as_u64(), Some(0), "{name}: {r}");
        assert!(
            r["normal"][2].as_f64().expect("nz").abs() > 0.99,
            "{name}: {r}"
        );
        assert!(
            (r["centre"][2].as_f64().expect("z") - 0.55).abs() < 0.1,
            "{name}: {r}"
        );
        let caption = r["caption"].as_str().expect("caption");
        assert!(
            caption.starts_with("block on block\n")
                && caption.ends_with("the faces in contact, the body drawn faintly"),
            "{name}: {r}"
        );
        let _ = std::fs::remove_dir_all(out.parent().expect("dir"));
    }
}
