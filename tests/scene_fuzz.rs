//! Mutated scenes never crash the program: the demo scene and a validation scene, each mutated
//! hundreds of ways (values set to 0, −1, 1e300, 1e-300, NaN and huge strings, keys deleted or
//! added where they do not belong, blocks duplicated, bytes flipped), all deterministic (a fixed
//! seed), go through the scene check that `pdcontact run --check` makes (parse, then build the
//! model: meshes, particles, bonds, surfaces, contact pairs; no solve). Each must be accepted or
//! refused as bad input (exit code 2) with a short message: no panic, no abort, no numerical
//! failure, no message that repeats a 100 kB value or prints a 300-digit number.
//!
//! The demo scene runs on the whole coarse sphere meshes/sphere_r1_d012.msh (same radius, no
//! quarter set or symmetry planes) to keep the test short.
//!
//! `PDCONTACT_MEMORY_LIMIT` holds models to 300 MB, so that a mutation that asks for a large
//! but possible model (a flipped digit in a spacing) is refused by the memory check instead of
//! taking minutes: the check it meets is the same one that refuses a model larger than the
//! machine.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use pdcontact::run::check_scene;
use pdcontact::scene::Scene;
use pdcontact::studies::{demo, scenarios};
use pdcontact::Error;

/// Mutations per seed scene.
const PER_SCENE: usize = 200;

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdcontact-fuzz-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// xorshift64*: a fixed sequence, the same on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
}

const VALUES: &[&str] = &[
    "0", "-1", "1", "1e300", "-1e300", "1e-300", "nan", "inf", "-inf", "\"NaN\"", "100000", "0.0",
];

/// Keys that belong somewhere in a scene, inserted where they may not.
const EXTRA_KEYS: &[&str] = &[
    "spacing = 0.1",
    "spacing = 1e-300",
    "radius = 1.0",
    "divisions = 0",
    "divisions = 100000",
    "size = 1e300",
    "scale = 1e300",
    "scale = 1e-300",
    "max_iterations = 0",
    "dt = 1e-6",
    "tolerance = 1e-4",
    "horizon_factor = 1e300",
    "translate = [1e300, 0.0, 0.0]",
];

/// Byte ranges of the number literals of `text` (outside comments).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let mut comment = false;
    while i < b.len() {
        match b[i] {
            b'#' => comment = true,
            b'\n' => comment = false,
            b'"' if !comment => {
                // Skip a string.
                i += 1;
                while i < b.len() && b[i] != b'"' && b[i] != b'\n' {
                    i += 1;
                }
            }
            c if !comment
                && (c.is_ascii_digit() || c == b'-')
                && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) =>
            {
                let start = i;
                while i < b.len()
                    && (b[i].is_ascii_digit() || matches!(b[i], b'.' | b'e' | b'E' | b'-' | b'+'))
                {
                    i += 1;
                }
                if b[start..i].iter().any(u8::is_ascii_digit) {
                    out.push((start, i));
                }
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// Byte ranges of the contents of the string literals of `text` (outside comments).
fn strings(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for (offset, line) in line_offsets(text) {
        let code = line.split('#').next().unwrap_or("");
        let quotes: Vec<usize> = code.match_indices('"').map(|(p, _)| p).collect();
        for pair in quotes.chunks(2) {
            if let [a, b] = pair {
                out.push((offset + a + 1, offset + b));
            }
        }
    }
    out
}

fn line_offsets(text: &str) -> Vec<(usize, &str)> {
    let mut offset = 0;
    text.split_inclusive('\n')
        .map(|l| {
            let o = offset;
            offset += l.len();
            (o, l)
        })
        .collect()
}

/// One mutation of `text`, and what it did.
fn mutate(text: &str, rng: &mut Rng) -> (String, String) {
    let splice =
        |(a, b): (usize, usize), with: &str| format!("{}{}{}", &text[..a], with, &text[b..]);
    match rng.below(7) {
        0 | 1 => {
            let nums = numbers(text);
            let at = *rng.pick(&nums);
            let v = *rng.pick(VALUES);
            (splice(at, v), format!("{} -> {v}", &text[at.0..at.1]))
        }
        2 => {
            let strs = strings(text);
            let at = *rng.pick(&strs);
            let v = match rng.below(4) {
                0 => String::new(),
                1 => "x".repeat(100_000),
                2 => "ball".into(),
                _ => "plane".into(),
            };
            let what = format!("\"{}\" -> \"{}\"", &text[at.0..at.1], excerpt(&v));
            (splice(at, &v), what)
        }
        3 => {
            // Delete a key line.
            let lines: Vec<(usize, &str)> = line_offsets(text)
                .into_iter()
                .filter(|(_, l)| l.contains('=') && !l.trim_start().starts_with('#'))
                .collect();
            let (o, l) = *rng.pick(&lines);
            (splice((o, o + l.len()), ""), format!("delete {}", l.trim()))
        }
        4 => {
            // Duplicate a block: its header to the next header.
            let heads: Vec<usize> = line_offsets(text)
                .into_iter()
                .filter(|(_, l)| l.starts_with('['))
                .map(|(o, _)| o)
                .collect();
            let k = rng.below(heads.len());
            let end = heads.get(k + 1).copied().unwrap_or(text.len());
            let block = &text[heads[k]..end];
            let what = format!("duplicate {}", block.lines().next().unwrap_or(""));
            (format!("{text}\n{block}"), what)
        }
        5 => {
            // Insert a key: in an inline table, or after a header.
            let key = *rng.pick(EXTRA_KEYS);
            let tables: Vec<usize> = text.match_indices(" }").map(|(p, _)| p).collect();
            if rng.below(2) == 0 && !tables.is_empty() {
                let p = *rng.pick(&tables);
                (
                    splice((p, p), &format!(", {key}")),
                    format!("+ {{ {key} }}"),
                )
            } else {
                let heads: Vec<(usize, &str)> = line_offsets(text)
                    .into_iter()
                    .filter(|(_, l)| l.starts_with('['))
                    .collect();
                let (o, l) = *rng.pick(&heads);
                let p = o + l.len();
                let what = format!("+ {key} under {}", l.trim());
                (splice((p, p), &format!("{key}\n")), what)
            }
        }
        _ => {
            // Flip 1 to 3 bytes to printable ASCII.
            let mut bytes = text.as_bytes().to_vec();
            let mut what = String::from("flip");
            for _ in 0..1 + rng.below(3) {
                let i = rng.below(bytes.len());
                let c = 0x20 + rng.below(0x5f) as u8;
                what += &format!(" @{i} {:?}->{:?}", bytes[i] as char, c as char);
                bytes[i] = c;
            }
            (String::from_utf8_lossy(&bytes).into_owned(), what)
        }
    }
}

fn excerpt(s: &str) -> String {
    if s.len() > 20 {
        format!("{}…({})", &s[..20], s.len())
    } else {
        s.to_string()
    }
}

/// What the check made of a scene.
#[derive(Debug, PartialEq, Eq, PartialOrd, Ord, Clone, Copy)]
enum Outcome {
    Accepted,
    Refused,
    Numerical,
    Panicked,
}

/// The check of `pdcontact run --check`, in process: the outcome and the error message.
fn check(text: &str, dir: &Path) -> (Outcome, String) {
    let result = catch_unwind(AssertUnwindSafe(|| {
        let scene = Scene::parse(text, "fuzz.toml", dir)?;
        check_scene(&scene).map(|_| ())
    }));
    match result {
        Ok(Ok(())) => (Outcome::Accepted, String::new()),
        Ok(Err(e @ (Error::Input(_) | Error::Import(_)))) => (Outcome::Refused, e.to_string()),
        Ok(Err(e)) => (Outcome::Numerical, e.to_string()),
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            (Outcome::Panicked, msg)
        }
    }
}

/// Mutates `seed` [`PER_SCENE`] ways and checks each; returns the failures (panics, numerical
/// failures, overlong messages) and the counts of each outcome.
fn fuzz(name: &str, seed: &str, dir: &Path, rng_seed: u64) -> (Vec<String>, [usize; 4]) {
    let (base, _) = check(seed, dir);
    assert_eq!(base, Outcome::Accepted, "the {name} seed scene itself");
    let mut rng = Rng(rng_seed);
    let mut failures = Vec::new();
    let mut counts = [0; 4];
    for k in 0..PER_SCENE {
        let (text, what) = mutate(seed, &mut rng);
        // PDCONTACT_FUZZ_DUMP=DIR writes the mutated scenes, to run them through another build
        // (docs/RELIABILITY.md counts the crashes before and after this way).
        if let Ok(out) = std::env::var("PDCONTACT_FUZZ_DUMP") {
            let _ = std::fs::write(Path::new(&out).join(format!("{name}-{k:03}.toml")), &text);
        }
        let (outcome, msg) = check(&text, dir);
        counts[outcome as usize] += 1;
        if let Ok(out) = std::env::var("PDCONTACT_FUZZ_DUMP") {
            let line = format!(
                "{name}-{k:03}\t{outcome:?}\t{what}\t{}\n",
                excerpt_msg(&msg)
            );
            let log = Path::new(&out).join("outcomes.tsv");
            let mut old = std::fs::read_to_string(&log).unwrap_or_default();
            old.push_str(&line);
            let _ = std::fs::write(log, old);
        }
        let long_number = msg
            .split(|c: char| !c.is_ascii_digit())
            .any(|run| run.len() > 30);
        if matches!(outcome, Outcome::Numerical | Outcome::Panicked)
            || msg.chars().count() > 600
            || long_number
        {
            failures.push(format!(
                "{name} #{k} ({what}): {outcome:?}: {}",
                excerpt_msg(&msg)
            ));
        }
    }
    (failures, counts)
}

fn excerpt_msg(m: &str) -> String {
    let head: String = m.chars().take(300).collect();
    format!("{head} [{} chars]", m.chars().count())
}

#[test]
fn mutated_scenes_are_accepted_or_refused_never_crash() {
    std::env::set_var("PDCONTACT_MEMORY_LIMIT", "3e8");
    // Keep the panic hook quiet: every panic is caught and reported below.
    std::panic::set_hook(Box::new(|_| {}));
    let dir = temp_dir("mutations");
    // The demo scene as `pdcontact demo` writes it, on the coarse cubed sphere of the same
    // radius, to keep the test short.
    let coarse = "sphere_r1_d012.msh";
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("meshes")
            .join(coarse),
        dir.join(coarse),
    )
    .unwrap();
    let demo_scene =
        demo::scene_text(demo::DemoSolver::Static).replace(demo::DEMO_MESH_NAME, coarse);
    assert!(demo_scene.contains(coarse));
    // The demo's quarter shell would take seconds per mutant: the same scene on a whole sphere,
    // without the quarter's set and symmetry planes.
    let demo_scene = demo_scene
        .replace("set = \"top\"", "")
        .split("[[symmetry]]")
        .next()
        .expect("scene")
        .to_string();
    let validation = scenarios::hertz_sphere_case(2.0).scene;
    let mut failures = Vec::new();
    for (name, seed, rng_seed) in [
        ("demo", demo_scene.as_str(), 0x5eed_0001),
        ("hertz-sphere", validation.as_str(), 0x5eed_0002),
    ] {
        let start = std::time::Instant::now();
        let (f, counts) = fuzz(name, seed, &dir, rng_seed);
        eprintln!(
            "{name}: {PER_SCENE} mutations: {} accepted, {} refused (exit 2), {} numerical (exit 1), {} panicked; {:.1} s",
            counts[0], counts[1], counts[2], counts[3], start.elapsed().as_secs_f64()
        );
        failures.extend(f);
    }
    let _ = std::panic::take_hook();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        failures.is_empty(),
        "{} of {} mutations failed:\n{}",
        failures.len(),
        2 * PER_SCENE,
        failures.join("\n")
    );
}

#[test]
fn a_plane_facing_away_from_its_slave_is_refused() {
    let dir = temp_dir("plane-side");
    let text = scenarios::hertz_sphere_case(2.0)
        .scene
        .replace("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, -1.0]");
    let (outcome, msg) = check(&text, &dir);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(outcome, Outcome::Refused, "{msg}");
    assert!(
        msg.contains("contact pair \"sphere\" / \"plane\"")
            && msg.contains("behind the plane \"plane\"")
            && msg.contains("[0, 0, -1]"),
        "{msg}"
    );
}
