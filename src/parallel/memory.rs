//! What a process holds in memory, as the kernel counts it (`/proc/self/status`): what
//! `bench` and `run` report per process and per rank.

/// Resident set size now (`VmRSS`), MB (10⁶ bytes); `None` where there is no such file.
pub fn resident_mb() -> Option<f64> {
    proc_status_mb("VmRSS:")
}

/// Peak resident set size (`VmHWM`), MB (10⁶ bytes); `None` where there is no such file.
pub fn peak_rss_mb() -> Option<f64> {
    proc_status_mb("VmHWM:")
}

fn proc_status_mb(key: &str) -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0 / 1e6)
}

/// Hands the heap's free pages back to the system (glibc keeps what large transient arrays
/// held, up to its dynamic mmap threshold of 32 MB an array), so that [`resident_mb`] then
/// counts what the process holds. Elsewhere nothing.
pub fn give_back_free_pages() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases free memory of the allocator's own heaps.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// The memory this process may use, MB, and what sets it, where something does: the memory
/// limit of its cgroup (v2 `memory.max`, v1 `memory.limit_in_bytes`: a container's, a batch
/// job's, `systemd-run -p MemoryMax=`) or its address-space limit (`ulimit -v`). The
/// smallest wins; `None` where none is set.
pub fn limit_mb() -> Option<(f64, &'static str)> {
    let mut best: Option<(f64, &'static str)> = None;
    let mut take = |bytes: Option<f64>, what: &'static str| {
        // A cgroup without a limit says so with a number near 2⁶³.
        if let Some(b) = bytes.filter(|&b| b > 0.0 && b < 1e18) {
            let mb = b / 1e6;
            if best.is_none_or(|(m, _)| mb < m) {
                best = Some((mb, what));
            }
        }
    };
    let cgroups = std::fs::read_to_string("/proc/self/cgroup").unwrap_or_default();
    for line in cgroups.lines() {
        let mut f = line.splitn(3, ':');
        let (_, controllers, path) = (f.next(), f.next().unwrap_or(""), f.next().unwrap_or(""));
        let path = path.trim_start_matches('/');
        let candidates: &[(&str, &str)] = if controllers.is_empty() {
            &[
                ("/sys/fs/cgroup", "memory.max"),
                ("/sys/fs/cgroup/unified", "memory.max"),
            ]
        } else if controllers.split(',').any(|c| c == "memory") {
            &[("/sys/fs/cgroup/memory", "memory.limit_in_bytes")]
        } else {
            &[]
        };
        for (root, file) in candidates {
            // The path as the process sees it; in a container whose cgroup namespace hides
            // it, the mount's own root.
            let read = |dir: &std::path::Path| {
                std::fs::read_to_string(dir.join(file))
                    .ok()
                    .and_then(|s| s.trim().parse::<f64>().ok())
            };
            let root = std::path::Path::new(root);
            take(
                read(&root.join(path)).or_else(|| read(root)),
                "the memory limit of its cgroup",
            );
        }
    }
    let limits = std::fs::read_to_string("/proc/self/limits").unwrap_or_default();
    if let Some(line) = limits.lines().find(|l| l.starts_with("Max address space")) {
        let soft = line
            .split_whitespace()
            .nth(3)
            .and_then(|s| s.parse::<f64>().ok());
        take(soft, "its address-space limit (ulimit -v)");
    }
    best
}
