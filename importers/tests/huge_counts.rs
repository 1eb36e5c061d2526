//! Files that declare 10^18 nodes (or elements, blocks, set members) in a few hundred bytes
//! must fail fast without allocating for the count. A counting allocator measures the peak
//! memory of each read.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use pdcontact_importers::{Format, Location};

struct Counting;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            let now = CURRENT.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Tests of this file run one at a time (each holds this lock from its start, also while it
/// builds its input), so that the peak is one read's.
static SERIAL: Mutex<()> = Mutex::new(());

fn serial() -> std::sync::MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

/// Most a read of these small files may allocate beyond what was allocated before it.
const MAX_PEAK: usize = 8 << 20;
const MAX_TIME: Duration = Duration::from_millis(500);

/// Reads `data` and returns the error message; checks time, peak memory and the location.
fn fails_fast(name: &str, format: Format, data: &[u8]) -> String {
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let start = Instant::now();
    let result = pdcontact_importers::read_format(Path::new(name), data, format);
    let took = start.elapsed();
    let peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
    let e = match result {
        Ok(m) => panic!("{name}: read {} nodes from a lying file", m.node_count()),
        Err(e) => e,
    };
    check(name, took, peak, &e)
}

/// Checks time, peak memory, and (for an error) the message and its location.
fn check(name: &str, took: Duration, peak: usize, e: &pdcontact_importers::ImportError) -> String {
    let msg = e.to_string();
    assert!(took < MAX_TIME, "{name}: {took:?} ({msg})");
    assert!(peak < MAX_PEAK, "{name}: {peak} bytes at the peak ({msg})");
    assert!(
        matches!(e.location, Location::Line(_) | Location::Byte(_)),
        "{name}: no location: {msg}"
    );
    assert!(
        msg.contains("expected ") && msg.contains(", found "),
        "{msg}"
    );
    println!("{name}: {took:?}, peak {peak} bytes: {msg}");
    msg
}

const HUGE: u64 = 1_000_000_000_000_000_000;

#[test]
fn cdb_nblock_declaring_1e18_nodes() {
    let _serial = serial();
    let data = format!(
        "/PREP7\nNBLOCK,6,SOLID,{HUGE},{HUGE}\n(3i9,6e21.13e3)\n        1        0        0 \
         1.0000000000000E+00\n"
    );
    fails_fast("huge_nblock.cdb", Format::Cdb, data.as_bytes());
    // Node and element numbers of 10^18 (ids are not allocated by value either).
    let data = format!(
        "NBLOCK,6,SOLID\n(3i20,6e21.13e3)\n{HUGE:20}{:20}{:20} 1.0\n-1\n",
        0, 0
    );
    fails_fast("huge_node_id.cdb", Format::Cdb, data.as_bytes());
    let data = format!(
        "ET,1,185\nNBLOCK,6,SOLID,{HUGE}\n(1i9,3e21.13e3)\n        1 1.0\n-1\n\
         EBLOCK,19,SOLID,{HUGE},{HUGE}\n(19i20)\n"
    ) + &[
        1u64, 1, 1, 1, 0, 0, 0, 0, 8, 0, 1, HUGE, 1, 1, 1, 1, 1, 1, 1,
    ]
    .iter()
    .map(|v| format!("{v:20}"))
    .collect::<String>()
        + "\n-1\n";
    fails_fast("huge_eblock.cdb", Format::Cdb, data.as_bytes());
    // A component of 10^18 members by a negative range.
    let data = format!(
        "NBLOCK,6,SOLID\n(3i9,6e21.13e3)\n        1        0        0 1.0\n-1\n\
         CMBLOCK,ALL,NODE,{HUGE}\n(8i20)\n{:20}{:20}\n",
        1,
        -(HUGE as i64)
    );
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let start = Instant::now();
    let r = pdcontact_importers::read_format(
        Path::new("huge_cmblock.cdb"),
        data.as_bytes(),
        Format::Cdb,
    );
    let (took, peak) = (start.elapsed(), PEAK.load(Ordering::Relaxed) - base);
    assert!(took < MAX_TIME && peak < MAX_PEAK, "{took:?} {peak} bytes");
    if let Err(e) = r {
        assert!(!matches!(e.location, Location::File), "{e}");
    }
}

#[test]
fn msh2_ascii_declaring_1e18_nodes_and_elements() {
    let _serial = serial();
    let data =
        format!("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n{HUGE}\n1 0 0 0\n$EndNodes\n");
    fails_fast("huge_nodes22.msh", Format::Msh, data.as_bytes());
    let data = format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n\
         $Elements\n{HUGE}\n1 15 2 0 1 1\n$EndElements\n"
    );
    fails_fast("huge_elements22.msh", Format::Msh, data.as_bytes());
}

#[test]
fn msh41_ascii_declaring_1e18_nodes() {
    let _serial = serial();
    let data = format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n{HUGE} {HUGE} 1 {HUGE}\n\
         3 1 0 {HUGE}\n1\n0 0 0\n$EndNodes\n"
    );
    fails_fast("huge_nodes41.msh", Format::Msh, data.as_bytes());
    let data = format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n{HUGE} {HUGE} {HUGE} {HUGE}\n\
         $EndEntities\n"
    );
    fails_fast("huge_entities41.msh", Format::Msh, data.as_bytes());
}

/// MSH 4.1 binary header: `$MeshFormat`, the int32 1, `$EndMeshFormat`.
fn binary41() -> Vec<u8> {
    let mut d = b"$MeshFormat\n4.1 1 8\n".to_vec();
    d.extend(1i32.to_le_bytes());
    d.extend(b"\n$EndMeshFormat\n");
    d
}

#[test]
fn msh41_binary_declaring_1e18_blocks_and_nodes() {
    let _serial = serial();
    // 10^18 node blocks of 10^18 nodes, one node given.
    let mut d = binary41();
    d.extend(b"$Nodes\n");
    for v in [HUGE, HUGE, 1, HUGE] {
        d.extend(v.to_le_bytes());
    }
    for v in [3i32, 1, 0] {
        d.extend(v.to_le_bytes());
    }
    d.extend(HUGE.to_le_bytes());
    d.extend(1u64.to_le_bytes());
    for v in [0.0f64, 0.0, 0.0] {
        d.extend(v.to_le_bytes());
    }
    fails_fast("huge_blocks41.msh", Format::Msh, &d);
    // u64::MAX elements in a block after one good node.
    let mut d = binary41();
    d.extend(b"$Nodes\n");
    for v in [1u64, 1, 1, 1] {
        d.extend(v.to_le_bytes());
    }
    for v in [3i32, 1, 0] {
        d.extend(v.to_le_bytes());
    }
    d.extend(1u64.to_le_bytes());
    d.extend(1u64.to_le_bytes());
    for v in [0.0f64, 0.0, 0.0] {
        d.extend(v.to_le_bytes());
    }
    d.extend(b"\n$EndNodes\n$Elements\n");
    for v in [u64::MAX, u64::MAX, 1, u64::MAX] {
        d.extend(v.to_le_bytes());
    }
    for v in [3i32, 1, 15] {
        d.extend(v.to_le_bytes());
    }
    d.extend(u64::MAX.to_le_bytes());
    d.extend(1u64.to_le_bytes());
    d.extend(1u64.to_le_bytes());
    fails_fast("huge_elements41.msh", Format::Msh, &d);
}

#[test]
fn msh2_binary_declaring_huge_element_blocks() {
    let _serial = serial();
    let mut d = b"$MeshFormat\n2.2 1 8\n".to_vec();
    d.extend(1i32.to_le_bytes());
    d.extend(b"\n$EndMeshFormat\n$Nodes\n1\n");
    d.extend(1i32.to_le_bytes());
    for v in [0.0f64, 0.0, 0.0] {
        d.extend(v.to_le_bytes());
    }
    d.extend(format!("\n$EndNodes\n$Elements\n{HUGE}\n").as_bytes());
    // type 15 (point), i32::MAX elements following, i32::MAX tags.
    for v in [15i32, i32::MAX, i32::MAX, 1, 0] {
        d.extend(v.to_le_bytes());
    }
    fails_fast("huge_blocks22.msh", Format::Msh, &d);
}

#[test]
fn inp_labels_and_generate_of_1e18() {
    let _serial = serial();
    // A node label of 10^18 and a GENERATE range of 10^18 members: neither is allocated.
    let data = format!("*NODE\n{HUGE}, 0, 0, 0\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, {HUGE}\n");
    fails_fast("huge_label.inp", Format::Inp, data.as_bytes());
    let data = format!(
        "*NODE, NSET=N\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n\
         *NSET, NSET=ALL, GENERATE\n1, {HUGE}, 1\n*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n"
    );
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let start = Instant::now();
    let r = pdcontact_importers::read_format(
        Path::new("huge_generate.inp"),
        data.as_bytes(),
        Format::Inp,
    );
    let (took, peak) = (start.elapsed(), PEAK.load(Ordering::Relaxed) - base);
    assert!(took < MAX_TIME && peak < MAX_PEAK, "{took:?} {peak} bytes");
    let mesh = r.expect("a GENERATE range larger than the model reads");
    assert_eq!(
        mesh.set("ALL").and_then(|s| s.nodes.as_ref()).map(Vec::len),
        Some(4)
    );
    assert!(
        mesh.warnings.iter().any(|w| w.contains("ALL")),
        "{:?}",
        mesh.warnings
    );
    // Sets copied into themselves, doubling at every line.
    let mut data = String::from("*NODE\n1, 0, 0, 0\n*NSET, NSET=A, GENERATE\n1, 1000, 1\n");
    for _ in 0..64 {
        data += "*NSET, NSET=A\nA, A\n";
    }
    fails_fast("set_doubling.inp", Format::Inp, data.as_bytes());
}

/// Reads `data` (Ok or Err), checking only time and peak memory; returns the result.
fn bounded(
    name: &str,
    format: Format,
    data: &[u8],
    max_time: Duration,
    max_peak: usize,
) -> Result<pdcontact_importers::Mesh, pdcontact_importers::ImportError> {
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let start = Instant::now();
    let r = pdcontact_importers::read_format(Path::new(name), data, format);
    let (took, peak) = (start.elapsed(), PEAK.load(Ordering::Relaxed) - base);
    println!("{name}: {} bytes, {took:?}, peak {peak} bytes", data.len());
    assert!(took < max_time, "{name}: {took:?}");
    assert!(peak < max_peak, "{name}: {peak} bytes at the peak");
    r
}

#[test]
fn overlapping_generate_ranges_stay_small() {
    let _serial = serial();
    // 2,000 nodes and 20,000 GENERATE lines naming all of them.
    let mut d = String::from("*NODE\n");
    for i in 1..=2000 {
        d += &format!("{i}, {i}., 0, 0\n");
    }
    d += "*NSET, NSET=ALL, GENERATE\n";
    for _ in 0..20_000 {
        d += "1, 2000\n";
    }
    let mesh = bounded(
        "generate.inp",
        Format::Inp,
        d.as_bytes(),
        Duration::from_secs(2),
        8 << 20,
    )
    .expect("reads");
    assert_eq!(
        mesh.set("ALL").and_then(|s| s.nodes.as_ref()).map(Vec::len),
        Some(2000)
    );
    // 20,000 disjoint ranges of 9,000 labels each, none of them defined but the first.
    let mut d = String::from("*NODE\n");
    for i in 1..=2000 {
        d += &format!("{i}, {i}., 0, 0\n");
    }
    d += "*NSET, NSET=GAPS, GENERATE\n";
    for k in 0..20_000u64 {
        d += &format!("{}, {}\n", k * 10_000 + 1, k * 10_000 + 9_000);
    }
    let mesh = bounded(
        "gaps.inp",
        Format::Inp,
        d.as_bytes(),
        Duration::from_secs(2),
        8 << 20,
    )
    .expect("reads");
    assert_eq!(
        mesh.set("GAPS")
            .and_then(|s| s.nodes.as_ref())
            .map(Vec::len),
        Some(2000)
    );
}

#[test]
fn many_made_up_msh_sections_read_in_linear_time() {
    let _serial = serial();
    let mut d = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    for i in 0..50_000 {
        d += &format!("$Made{i}\n$EndMade{i}\n");
    }
    d += "$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 0\n$EndNodes\n";
    let mesh = bounded(
        "sections.msh",
        Format::Msh,
        d.as_bytes(),
        Duration::from_secs(1),
        8 << 20,
    )
    .expect("reads");
    let listed = mesh
        .warnings
        .iter()
        .find(|w| w.contains("sections not read"));
    assert!(
        listed.is_some_and(|w| w.matches('$').count() == 32),
        "{listed:?}"
    );
}

#[test]
fn cdb_format_of_thousands_of_columns_costs_nothing_per_short_record() {
    let _serial = serial();
    // An EBLOCK whose format line declares 4096 one-character columns, then 200,000 short
    // records of an undefined type (skipped).
    let mut d =
        String::from("NBLOCK,6,SOLID\n(3i9,6e21.13e3)\n        1        0        0 1.0\n-1\n");
    d += "EBLOCK,10,,\n(4096i1)\n";
    for _ in 0..200_000 {
        d += "111111\n";
    }
    let r = bounded(
        "wide.cdb",
        Format::Cdb,
        d.as_bytes(),
        Duration::from_secs(1),
        64 << 20,
    );
    match r {
        Ok(mesh) => println!("{:?}", mesh.warnings),
        Err(e) => assert!(matches!(e.location, Location::Line(_)), "{e}"),
    }
}

#[test]
fn includes_that_fan_out_are_limited() {
    let _serial = serial();
    // Level k includes level k + 1 eight times; 8^6 = 262,144 reads without the limit.
    let dir = std::env::temp_dir().join(format!("pdcontact-fanout-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for k in 0..6 {
        let line = format!("*INCLUDE, INPUT=level{}.inc\n", k + 1);
        std::fs::write(dir.join(format!("level{k}.inc")), line.repeat(8)).expect("write");
    }
    std::fs::write(dir.join("level6.inc"), "** leaf\n").expect("write");
    let main = dir.join("main.inp");
    let deck = "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=level0.inc\n";
    std::fs::write(&main, deck).expect("write");
    let start = Instant::now();
    let r = pdcontact_importers::read_path(&main, Some(Format::Inp));
    let took = start.elapsed();
    let _ = std::fs::remove_dir_all(&dir);
    let e = r.expect_err("more than 10,000 included files");
    println!("fan-out: {took:?}: {e}");
    assert!(e.to_string().contains("10000 *INCLUDE files"), "{e}");
    assert!(matches!(e.location, Location::Line(_)), "{e}");
    assert!(took < Duration::from_secs(5), "{took:?}");
}
