//! Inputs that once made a reader panic, hang, allocate without bound or give an unclear
//! error (found by fuzzing, see docs/RELIABILITY.md, or by review). Each file of
//! `tests/regressions/` must now give a clear `Err` or an `Ok` within 5 s; the format is the
//! file's extension.

mod common;

use common::{inconsistent, read_guarded, unclear, Outcome};
use pdcontact_importers::Format;

#[test]
fn regression_inputs_read_cleanly() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/regressions");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/regressions")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    files.sort();
    let mut problems = Vec::new();
    let mut count = 0;
    for path in &files {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        let Some(format) = Format::from_name(ext) else {
            continue;
        };
        count += 1;
        let data = std::fs::read(path).expect("regression file");
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        // Read as if it were elsewhere: *INCLUDE lines find nothing.
        let fake = std::path::Path::new("/nonexistent-regressions").join(&*name);
        match read_guarded(&fake, data.clone(), format).0 {
            Outcome::Ok(mesh) => {
                if let Some(why) = inconsistent(&mesh) {
                    problems.push(format!("{name}: inconsistent mesh: {why}"));
                }
            }
            Outcome::Err(e) => {
                if let Some(why) = unclear(&e, &data) {
                    problems.push(format!("{name}: {why}"));
                }
            }
            Outcome::Panic(m) => problems.push(format!("{name}: PANIC {m}")),
            Outcome::Hang => panic!("{name}: no answer within 5 s"),
        }
    }
    assert!(count > 0, "no regression files in {}", dir.display());
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
