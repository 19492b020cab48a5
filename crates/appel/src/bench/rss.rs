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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reset_peak_sees_a_later_allocation_and_not_an_earlier_one() {
        if current_bytes().is_none() {
            return; // not Linux
        }
        let big = vec![1u8; 64 << 20];
        std::hint::black_box(&big);
        drop(big);
        assert!(reset_peak());
        let after_reset = peak_bytes().unwrap();
        let now = current_bytes().unwrap();
        // The 64 MB touched before the reset no longer counts.
        assert!(after_reset < now + (32 << 20), "{after_reset} {now}");
        let again = vec![2u8; 48 << 20];
        std::hint::black_box(&again);
        assert!(peak_bytes().unwrap() >= after_reset + (40 << 20));
    }
}
