//! Memory a run may use, checked before a big render, bake or map starts, so that a size
//! the machine cannot hold fails in one line instead of an abort (out of memory) half-way.

use crate::error::{Error, Result};

/// Bytes this process can still allocate, as far as Linux says: the least of the system's
/// `MemAvailable` (`/proc/meminfo`), the cgroup's `memory.max - memory.current` (a
/// container's limit) and the address-space limit (`ulimit -v`) less what is mapped now.
/// `None` where none of these can be read (another OS).
pub fn available() -> Option<u64> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    // "Key:   123 kB" lines.
    let kb = |text: &str, key: &str| -> Option<u64> {
        let line = text.lines().find(|l| l.starts_with(key))?;
        let n: u64 = line[key.len()..].split_whitespace().next()?.parse().ok()?;
        Some(n * 1024)
    };
    let mem_available = read("/proc/meminfo").and_then(|t| kb(&t, "MemAvailable:"));
    let cgroup = read("/sys/fs/cgroup/memory.max")
        .and_then(|m| m.trim().parse::<u64>().ok())
        .zip(read("/sys/fs/cgroup/memory.current").and_then(|c| c.trim().parse::<u64>().ok()))
        .map(|(max, current)| max.saturating_sub(current));
    let address_space = read("/proc/self/limits")
        .and_then(|t| {
            let line = t.lines().find(|l| l.starts_with("Max address space"))?;
            // "Max address space   <soft>   <hard>   bytes"
            line["Max address space".len()..]
                .split_whitespace()
                .next()?
                .parse::<u64>()
                .ok()
        })
        .map(|limit| {
            let mapped = read("/proc/self/status")
                .and_then(|t| kb(&t, "VmSize:"))
                .unwrap_or(0);
            limit.saturating_sub(mapped)
        });
    [mem_available, cgroup, address_space]
        .into_iter()
        .flatten()
        .min()
}

/// Fails in one line when `what` needs more than the memory available: `need` bytes, and
/// a margin of 256 MiB for the rest of the process (driver, tables, encoder buffers).
pub fn check(what: &str, need: u64) -> Result<()> {
    const MARGIN: u64 = 256 << 20;
    let Some(available) = available() else {
        return Ok(());
    };
    if need.saturating_add(MARGIN) > available {
        let gb = |b: u64| b as f64 / 1e9;
        return Err(Error::Invalid {
            what: "size",
            message: format!(
                "{what} needs about {:.1} GB of memory and {:.1} GB is available \
                 (MemAvailable, cgroup and ulimit -v); choose a smaller size",
                gb(need + MARGIN),
                gb(available)
            ),
        });
    }
    Ok(())
}
