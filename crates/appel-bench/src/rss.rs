//! The process's resident memory as Linux reports it in `/proc/self/status`: what `appel bench`
//! gives as a build's peak, and `appel render` as the run's. `None` (and no reset) on other systems.

/// The peak resident size so far (`VmHWM`), in bytes.
pub fn peak_bytes() -> Option<u64> {
    status_kb("VmHWM:").map(|kb| kb * 1024)
}

/// The resident size now (`VmRSS`), in bytes.
pub fn current_bytes() -> Option<u64> {
    status_kb("VmRSS:").map(|kb| kb * 1024)
}

/// Lowers the peak to the resident size now, so that [`peak_bytes`] then measures what follows
/// (writing `5` to `/proc/self/clear_refs`, Linux 4.0 and later). Returns whether it could.
pub fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

fn status_kb(key: &str) -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = text.lines().find(|l| l.starts_with(key))?;
    line.split_whitespace().nth(1)?.parse().ok()
}
