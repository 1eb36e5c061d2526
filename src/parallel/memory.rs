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
