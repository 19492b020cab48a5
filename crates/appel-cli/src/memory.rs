//! Refusing scenes that cannot fit: the library's estimate against what the kernel says is
//! available, checked before any large file is read.

use anyhow::{bail, Result};
use appel::description::Description;
use appel::scene::estimate_memory;
use std::path::Path;

/// `MemAvailable` from `/proc/meminfo`, in bytes: what can be allocated without swapping. `None`
/// where there is no such file (not Linux), and then nothing is checked.
fn available_bytes() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

pub fn check_memory(d: &Description, base_dir: &Path) -> Result<()> {
    let e = estimate_memory(d, base_dir)?;
    let Some(available) = available_bytes() else {
        return Ok(());
    };
    if e.bytes > available {
        let gb = |b: u64| b as f64 / 1e9;
        bail!(
            "the scene needs an estimated {:.1} GB of memory ({} triangles stored, {} instances, {} pixels) \
             but only {:.1} GB is available (MemAvailable in /proc/meminfo); nothing was loaded. \
             Lower the resolution, the number of placements or the meshes' detail",
            gb(e.bytes),
            e.triangles,
            e.instances,
            e.pixels,
            gb(available)
        );
    }
    Ok(())
}

/// Peak resident memory of this process so far (`VmHWM`), in bytes, where the kernel reports it.
pub fn peak_rss_bytes() -> Option<u64> {
    appel_bench::rss::peak_bytes()
}
