//! Malformed-input test: every `error` file of the shared corpus, and a deterministic set of
//! damaged copies of every readable file (the shared corpus when it is beside the workspace, the
//! project's own `meshes/*.msh`, and small built-in decks), fed to the three readers.
//!
//! Each read runs in a thread with a panic guard and a 5 s limit. The test fails on any panic,
//! any hang, an `error` corpus file that reads, and any error that is not clear: it must read
//! `expected X, found Y`, name a line (or a byte in binary sections) inside the file (only
//! "no nodes at all" errors may name no place), and stay within 280 characters after the file
//! name. A mesh that is read must be consistent (indices in range, finite coordinates) and go
//! through the face finder.
//!
//! Damage, for each readable file (a fixed pseudo-random sequence, the same on every run):
//! truncations at many offsets (line starts, mid-line, mid-number, inside binary records),
//! byte flips, byte insertions (NUL, newline, comma, sign, 0xFF ...), line duplications,
//! deletions and swaps, numbers replaced by huge or invalid ones (18446744073709551615, -1,
//! 1e999, NaN ...; counts after section headers and keyword lines are favoured), raw binary
//! values replaced by huge counts or NaN, other encodings (UTF-16, BOM, CRLF, Latin-1), NUL
//! padding, and garbage. At least 2,000 inputs per reader.
//!
//! `cargo test -p pdcontact-importers --test mutations --release -- --nocapture` prints the
//! counts; with `MUTATIONS_SHOW=1` it also prints every error message.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use common::{inconsistent, read_guarded, shared_corpus, unclear, workspace, Outcome};
use pdcontact_importers::Format;

/// Damaged inputs made per reader (spread over its readable files).
const PER_FORMAT: usize = 2100;

/// Numbers that lying or broken fields hold.
const BAD_NUMBERS: [&str; 16] = [
    "18446744073709551615",
    "18446744073709551616",
    "9223372036854775807",
    "-9223372036854775808",
    "4294967295",
    "2147483648",
    "1000000000000000000",
    "-1",
    "0",
    "1e999",
    "-1e999",
    "NaN",
    "inf",
    "1e-999",
    "99999999999999999999999999",
    "1.5",
];

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn new(seed: &str) -> Rng {
        // FNV-1a of the name, never 0.
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in seed.bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
        Rng(h | 1)
    }

    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in `0..n` (n > 0).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn pick<'a, T>(&mut self, v: &'a [T]) -> &'a T {
        &v[self.below(v.len())]
    }
}

/// A readable file to damage.
struct Seed {
    name: String,
    format: Format,
    data: Vec<u8>,
}

/// Start offsets of the lines of `d`.
fn line_starts(d: &[u8]) -> Vec<usize> {
    let mut v = vec![0];
    v.extend(
        d.iter()
            .enumerate()
            .filter(|&(i, &b)| b == b'\n' && i + 1 < d.len())
            .map(|(i, _)| i + 1),
    );
    v
}

/// Numeric tokens `(start, end)`: runs of digits with an optional sign, point and exponent.
fn numbers(d: &[u8]) -> Vec<(usize, usize)> {
    let mut v = Vec::new();
    let mut i = 0;
    while i < d.len() {
        let b = d[i];
        let starts = b.is_ascii_digit()
            || ((b == b'-' || b == b'+' || b == b'.')
                && d.get(i + 1).is_some_and(u8::is_ascii_digit));
        let after_word = i > 0 && (d[i - 1].is_ascii_alphanumeric() || d[i - 1] == b'.');
        if starts && !after_word {
            let s = i;
            i += 1;
            while i < d.len()
                && (d[i].is_ascii_digit()
                    || matches!(d[i], b'.' | b'e' | b'E' | b'd' | b'D')
                    || ((d[i] == b'-' || d[i] == b'+') && matches!(d[i - 1], b'e' | b'E')))
            {
                i += 1;
            }
            v.push((s, i));
        } else {
            i += 1;
        }
    }
    v
}

/// Numbers on a header line (`$Nodes`, `NBLOCK,...`, `*NODE ...`) or the two lines after it:
/// counts and sizes live there.
fn header_numbers(d: &[u8], nums: &[(usize, usize)]) -> Vec<(usize, usize)> {
    let starts = line_starts(d);
    let mut zones: Vec<(usize, usize)> = Vec::new();
    for (k, &s) in starts.iter().enumerate() {
        let first = d[s..].iter().find(|b| !b.is_ascii_whitespace());
        if matches!(first, Some(b'$' | b'*' | b'(')) || first.is_some_and(u8::is_ascii_alphabetic) {
            let end = starts.get(k + 3).copied().unwrap_or(d.len());
            zones.push((s, end));
        }
    }
    nums.iter()
        .copied()
        .filter(|&(s, _)| zones.iter().any(|&(a, b)| s >= a && s < b))
        .take(5000)
        .collect()
}

/// Where the binary part of a binary MSH file starts (after the `$MeshFormat` line), if any.
fn binary_from(d: &[u8]) -> Option<usize> {
    let head = d.get(..d.len().min(4096))?;
    let k = head.windows(11).position(|w| w == b"$MeshFormat")?;
    let line = k + head[k..].iter().position(|&b| b == b'\n')? + 1;
    let end = line + head[line..].iter().position(|&b| b == b'\n')?;
    let fields: Vec<&[u8]> = head[line..end]
        .split(|b| b.is_ascii_whitespace())
        .filter(|f| !f.is_empty())
        .collect();
    (fields.get(1) == Some(&&b"1"[..])).then_some(end + 1)
}

fn utf16le(d: &[u8]) -> Vec<u8> {
    let mut v = vec![0xff, 0xfe];
    for &b in d {
        v.push(b);
        v.push(0);
    }
    v
}

/// `count` damaged copies of `seed`, deterministic for its name.
fn damage(seed: &Seed, count: usize) -> Vec<(String, Vec<u8>)> {
    let d = &seed.data;
    let mut rng = Rng::new(&seed.name);
    let starts = line_starts(d);
    let nums = numbers(d);
    let head_nums = header_numbers(d, &nums);
    let bin = binary_from(d);
    let mut out: Vec<(String, Vec<u8>)> = Vec::new();

    // Fixed damage first: encodings, padding, the empty and blank file.
    out.push(("empty".into(), Vec::new()));
    out.push(("blank".into(), b" \n\r\n\t\n".to_vec()));
    out.push(("utf16".into(), utf16le(&d[..d.len().min(200_000)])));
    out.push(("bom".into(), [&b"\xEF\xBB\xBF"[..], d].concat()));
    out.push(("nul-pad".into(), [d.as_slice(), &[0u8; 4096]].concat()));
    out.push((
        "nul-pad-mid".into(),
        [&d[..d.len() / 2], &[0u8; 512][..]].concat(),
    ));
    out.push(("all-nul".into(), vec![0u8; d.len().min(65536)]));
    out.push((
        "crlf".into(),
        d.iter()
            .flat_map(|&b| {
                if b == b'\n' {
                    vec![b'\r', b'\n']
                } else {
                    vec![b]
                }
            })
            .collect(),
    ));
    out.push((
        "cr-only".into(),
        d.iter()
            .map(|&b| if b == b'\n' { b'\r' } else { b })
            .collect(),
    ));
    out.push((
        "latin1".into(),
        d.iter()
            .enumerate()
            .map(|(i, &b)| {
                if i % 97 == 13 && b.is_ascii_alphabetic() {
                    0xE9
                } else {
                    b
                }
            })
            .collect(),
    ));

    let kinds = 10;
    let mut k = 0usize;
    while out.len() < count {
        k += 1;
        let kind = k % kinds;
        let (label, v): (String, Vec<u8>) = match kind {
            // Truncation at an even spread of offsets, then at random ones.
            0 | 1 if !d.is_empty() => {
                let at = if k < 2 * count / kinds {
                    (k / 2 * d.len()) / (count / kinds).max(1)
                } else {
                    rng.below(d.len())
                }
                .min(d.len() - 1);
                (format!("cut@{at}"), d[..at].to_vec())
            }
            // Truncation mid-line, or inside the binary part.
            2 if !d.is_empty() => {
                let at = match bin {
                    Some(b) if b < d.len() && rng.below(2) == 0 => b + rng.below(d.len() - b),
                    _ => {
                        let l = rng.below(starts.len());
                        let s = starts[l];
                        let e = starts.get(l + 1).copied().unwrap_or(d.len());
                        s + (e - s) / 2
                    }
                };
                (format!("cut-mid@{at}"), d[..at].to_vec())
            }
            // Byte flip: one bit, or the byte set to a special value.
            3 if !d.is_empty() => {
                let at = rng.below(d.len());
                let mut v = d.clone();
                v[at] = match rng.below(4) {
                    0 => v[at] ^ (1 << rng.below(8)),
                    1 => 0,
                    2 => 0xff,
                    _ => *rng.pick(b"\n ,-+.eE$*9"),
                };
                (format!("flip@{at}"), v)
            }
            // Byte insertion.
            4 => {
                let at = rng.below(d.len() + 1);
                let ins: &[u8] = rng.pick::<&[u8]>(&[
                    b"\0",
                    b"\n",
                    b",",
                    b"-",
                    b"\xff\xfe",
                    b" ",
                    b"\r",
                    b"9",
                    b"\"",
                    b"$",
                    b"*",
                ]);
                let v = [&d[..at], ins, &d[at..]].concat();
                (format!("insert@{at}"), v)
            }
            // Line duplication (one line or a few), deletion, or swap.
            5 if starts.len() > 1 => {
                let l = rng.below(starts.len());
                let n = 1 + rng.below(3);
                let s = starts[l];
                let e = starts.get(l + n).copied().unwrap_or(d.len());
                let v = match rng.below(4) {
                    0 | 1 => [&d[..e], &d[s..e], &d[e..]].concat(),
                    2 => [&d[..s], &d[e..]].concat(),
                    _ => {
                        let f = starts.get(l + 1).copied().unwrap_or(d.len());
                        let g = starts.get(l + 2).copied().unwrap_or(d.len());
                        [&d[..s], &d[f..g], &d[s..f], &d[g..]].concat()
                    }
                };
                (format!("lines@{l}"), v)
            }
            // A number replaced, favouring counts on and after header lines.
            6 | 7 if !nums.is_empty() => {
                let pool = if kind == 6 && !head_nums.is_empty() {
                    &head_nums
                } else {
                    &nums
                };
                let (s, e) = *rng.pick(pool);
                let bad = rng.pick(&BAD_NUMBERS);
                let v = [&d[..s], bad.as_bytes(), &d[e..]].concat();
                (format!("number@{s}={bad}"), v)
            }
            // A raw binary value replaced by a huge count, -1 or NaN.
            8 if bin.is_some_and(|b| b + 8 < d.len()) => {
                let b = bin.unwrap_or(0);
                let at = b + rng.below(d.len() - b - 8);
                let at = if rng.below(2) == 0 { at & !3 } else { at };
                let word: [u8; 8] = match rng.below(5) {
                    0 => u64::MAX.to_le_bytes(),
                    1 => 1_000_000_000_000_000_000u64.to_le_bytes(),
                    2 => {
                        let mut w = d[at..at + 8].try_into().unwrap_or([0; 8]);
                        w[..4].copy_from_slice(&i32::MAX.to_le_bytes());
                        w
                    }
                    3 => f64::NAN.to_le_bytes(),
                    _ => {
                        let mut w = d[at..at + 8].try_into().unwrap_or([0; 8]);
                        w[..4].copy_from_slice(&(-1i32).to_le_bytes());
                        w
                    }
                };
                let mut v = d.clone();
                v[at..at + 8].copy_from_slice(&word);
                (format!("word@{at}"), v)
            }
            // Garbage: random bytes, or a line of the file followed by random bytes.
            9 => {
                let n = 1 + rng.below(4096);
                let mut v: Vec<u8> = if rng.below(2) == 0 || starts.is_empty() {
                    Vec::new()
                } else {
                    let l = rng.below(starts.len().min(64));
                    let e = starts.get(l + 1).copied().unwrap_or(d.len());
                    d[..e].to_vec()
                };
                v.extend((0..n).map(|_| rng.next() as u8));
                (format!("garbage{n}"), v)
            }
            _ => continue,
        };
        out.push((label, v));
    }
    out
}

/// Readable files: the shared corpus (`ok` and `ok_or_error`), the project's meshes, and
/// built-in decks; plus the corpus's `error` files, which are fed as they are.
fn seeds() -> (Vec<Seed>, Vec<Seed>) {
    let mut ok = Vec::new();
    let mut bad = Vec::new();
    if let Some(corpus) = shared_corpus() {
        let text = std::fs::read_to_string(corpus.join("manifest.json")).expect("manifest");
        let manifest: serde_json::Value = serde_json::from_str(&text).expect("manifest JSON");
        for f in manifest["files"].as_array().expect("files") {
            let path = f["path"].as_str().expect("path");
            let format = Format::from_name(f["format"].as_str().expect("format")).expect("fmt");
            let data = std::fs::read(corpus.join(path)).expect("corpus file");
            let seed = Seed {
                name: path.to_string(),
                format,
                data,
            };
            match f["expect"].as_str() {
                Some("error") => bad.push(seed),
                _ => ok.push(seed),
            }
        }
    } else {
        eprintln!("shared corpus not found beside the workspace: using the project's files only");
    }
    let mut meshes: Vec<PathBuf> = std::fs::read_dir(workspace().join("meshes"))
        .expect("meshes/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "msh"))
        .collect();
    meshes.sort();
    assert!(!meshes.is_empty(), "no meshes/*.msh");
    for p in meshes {
        ok.push(Seed {
            name: format!(
                "meshes/{}",
                p.file_name().unwrap_or_default().to_string_lossy()
            ),
            format: Format::Msh,
            data: std::fs::read(&p).expect("mesh"),
        });
    }
    for (name, format, data) in builtin() {
        ok.push(Seed {
            name: name.to_string(),
            format,
            data,
        });
    }
    (ok, bad)
}

/// Small decks of each format written here, so that every reader has seeds without the corpus.
fn builtin() -> Vec<(&'static str, Format, Vec<u8>)> {
    let cube: [[f64; 3]; 9] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.5, 0.5, 2.0],
    ];
    // ANSYS: a hex, a pyramid on top (collapsed brick), a node component.
    let mut cdb = String::from("/PREP7\nET,1,185\nNBLOCK,6,SOLID,9,9\n(3i9,6e21.13e3)\n");
    for (i, p) in cube.iter().enumerate() {
        cdb += &format!("{:9}{:9}{:9}", i + 1, 0, 0);
        for v in p {
            cdb += &format!("{:>21}", format!("{v:.13E}"));
        }
        cdb.push('\n');
    }
    cdb += "N,R5.3,LOC,       -1,\nEBLOCK,19,SOLID,2,2\n(19i9)\n";
    for (id, nodes) in [(1, [1, 2, 3, 4, 5, 6, 7, 8]), (2, [5, 6, 7, 8, 9, 9, 9, 9])] {
        for v in [1, 1, 1, 1, 0, 0, 0, 0, 8, 0, id] {
            cdb += &format!("{v:9}");
        }
        for n in nodes {
            cdb += &format!("{n:9}");
        }
        cdb.push('\n');
    }
    cdb += "       -1\nCMBLOCK,TOP,NODE,       2\n(8i10)\n         5        -8\n";
    // Abaqus: the same cube and pyramid, sets with GENERATE and a part / instance.
    let mut inp = String::from("*HEADING\ncube\n*NODE, NSET=ALL\n");
    for (i, p) in cube.iter().enumerate() {
        inp += &format!("{}, {}, {}, {}\n", i + 1, p[0], p[1], p[2]);
    }
    inp += "*ELEMENT, TYPE=C3D8, ELSET=HEX\n1, 1, 2, 3, 4, 5, 6, 7,\n8\n\
            *ELEMENT, TYPE=C3D5, ELSET=PYR\n2, 5, 6, 7, 8, 9\n\
            *NSET, NSET=TOP, GENERATE\n5, 8, 1\n*ELSET, ELSET=BOTH\nHEX, PYR\n";
    let mut parts = String::from("*Part, name=\"P 1\"\n*Node\n");
    for (i, p) in cube.iter().take(8).enumerate() {
        parts += &format!("{}, {}, {}, {}\n", i + 1, p[0], p[1], p[2]);
    }
    parts += "*Element, type=C3D8R\n1, 1, 2, 3, 4, 5, 6, 7, 8\n*Nset, nset=BASE\n1, 2, 3, 4\n\
              *End Part\n*Assembly, name=A\n*Instance, name=I1, part=\"P 1\"\n*End Instance\n\
              *Instance, name=I2, part=\"P 1\"\n2., 0., 0.\n0., 0., 0., 0., 0., 1., 90.\n\
              *End Instance\n*Nset, nset=BOTH\nI1.1, I2.1\n*Elset, elset=E, instance=I2\n1\n\
              *End Assembly\n";
    // Gmsh 2.2 ASCII and 4.1 binary with the same hex.
    let mut msh2 = String::from(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"body\"\n\
         $EndPhysicalNames\n$Nodes\n8\n",
    );
    for (i, p) in cube.iter().take(8).enumerate() {
        msh2 += &format!("{} {} {} {}\n", i + 1, p[0], p[1], p[2]);
    }
    msh2 += "$EndNodes\n$Elements\n1\n1 5 2 1 1 1 2 3 4 5 6 7 8\n$EndElements\n";
    let mut msh4 = b"$MeshFormat\n4.1 1 8\n".to_vec();
    msh4.extend(1i32.to_le_bytes());
    msh4.extend(b"\n$EndMeshFormat\n$Nodes\n");
    for v in [1u64, 8, 1, 8] {
        msh4.extend(v.to_le_bytes());
    }
    msh4.extend(3i32.to_le_bytes());
    msh4.extend(1i32.to_le_bytes());
    msh4.extend(0i32.to_le_bytes());
    msh4.extend(8u64.to_le_bytes());
    for t in 1..=8u64 {
        msh4.extend(t.to_le_bytes());
    }
    for p in cube.iter().take(8) {
        for v in p {
            msh4.extend(v.to_le_bytes());
        }
    }
    msh4.extend(b"\n$EndNodes\n$Elements\n");
    for v in [1u64, 1, 1, 1] {
        msh4.extend(v.to_le_bytes());
    }
    for v in [3i32, 1, 5] {
        msh4.extend(v.to_le_bytes());
    }
    msh4.extend(1u64.to_le_bytes());
    for v in 1..=9u64 {
        msh4.extend(v.to_le_bytes());
    }
    msh4.extend(b"\n$EndElements\n");
    vec![
        ("builtin/cube.cdb", Format::Cdb, cdb.into_bytes()),
        ("builtin/cube.inp", Format::Inp, inp.into_bytes()),
        ("builtin/parts.inp", Format::Inp, parts.into_bytes()),
        ("builtin/cube22.msh", Format::Msh, msh2.into_bytes()),
        ("builtin/cube41bin.msh", Format::Msh, msh4),
    ]
}

#[derive(Default)]
struct Tally {
    inputs: usize,
    ok: usize,
    errors: usize,
    panics: usize,
    hangs: usize,
    slowest: Duration,
    slowest_input: String,
}

#[test]
fn malformed_inputs_give_clear_errors() {
    let started = Instant::now();
    let (ok_seeds, bad_seeds) = seeds();
    // A folder that does not exist: *INCLUDE lines of damaged decks find nothing.
    let dir = Path::new("/nonexistent-mutations");
    let mut problems: Vec<String> = Vec::new();
    let mut tally: BTreeMap<&'static str, Tally> = BTreeMap::new();
    // MUTATIONS_SHOW=1 prints every error message, to read them.
    let show = std::env::var_os("MUTATIONS_SHOW").is_some();

    let mut run = |format: Format, name: String, data: Vec<u8>, must_fail: bool| {
        let file = name.rsplit('/').next().unwrap_or("x").to_string();
        let path = dir.join(&file);
        let t = tally.entry(format.name()).or_default();
        t.inputs += 1;
        let (outcome, took) = read_guarded(&path, data.clone(), format);
        if took > t.slowest {
            t.slowest = took;
            t.slowest_input = name.clone();
        }
        match outcome {
            Outcome::Ok(mesh) => {
                t.ok += 1;
                if must_fail {
                    problems.push(format!("{name}: read, but the corpus says it is corrupt"));
                }
                if let Some(why) = inconsistent(&mesh) {
                    problems.push(format!("{name}: inconsistent mesh: {why}"));
                }
            }
            Outcome::Err(e) => {
                t.errors += 1;
                if show {
                    println!("{name}: {e}");
                }
                if let Some(why) = unclear(&e, &data) {
                    problems.push(format!("{name}: unclear error: {why}"));
                }
            }
            Outcome::Panic(msg) => {
                t.panics += 1;
                problems.push(format!("{name}: PANIC: {msg}"));
            }
            Outcome::Hang => {
                t.hangs += 1;
                problems.push(format!("{name}: HANG (no answer within 5 s)"));
                // The reader thread cannot be stopped: report now.
                panic!("{}", problems.join("\n"));
            }
        }
    };

    for s in &bad_seeds {
        run(s.format, s.name.clone(), s.data.clone(), true);
    }
    for format in [Format::Cdb, Format::Msh, Format::Inp] {
        let seeds: Vec<&Seed> = ok_seeds.iter().filter(|s| s.format == format).collect();
        assert!(!seeds.is_empty());
        let per_seed = PER_FORMAT.div_ceil(seeds.len());
        for s in seeds {
            for (label, data) in damage(s, per_seed) {
                run(format, format!("{}[{label}]", s.name), data, false);
            }
        }
    }

    for (format, t) in &tally {
        println!(
            "{format}: {} inputs, {} read, {} errors, {} panics, {} hangs; slowest {:.3} s ({})",
            t.inputs,
            t.ok,
            t.errors,
            t.panics,
            t.hangs,
            t.slowest.as_secs_f64(),
            t.slowest_input
        );
    }
    println!("total time {:.1} s", started.elapsed().as_secs_f64());
    for (format, t) in &tally {
        assert!(t.inputs >= 2000, "{format}: only {} inputs", t.inputs);
    }
    assert!(
        problems.is_empty(),
        "{} problem(s):\n{}",
        problems.len(),
        problems.join("\n")
    );
}
