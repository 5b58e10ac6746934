//! Memory a run may use, checked before a big render, bake or map starts, so that a size
//! the machine cannot hold fails in one line instead of an abort (out of memory) half-way.

use crate::error::{Error, Result};

/// Bytes this process can still allocate, as far as Linux says: the least of the system's
/// `MemAvailable` (`/proc/meminfo`), the cgroup's `memory.max - memory.current` (a
/// container's limit) and the address-space limit (`ulimit -v`) less what is mapped now;
/// `None` where none of these can be read (another OS). With it, what bounds it for a
/// message (issue 38, 8: the figure alone, which follows what is mapped when it is read,
/// looked arbitrary against the limit): `MemAvailable`, `the cgroup's memory.max 2.00 GB
/// less 1.20 GB in use` or `ulimit -v 0.41 GB less 0.16 GB mapped`.
pub(crate) fn available_bound() -> Option<(u64, String)> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    // "Key:   123 kB" lines.
    let kb = |text: &str, key: &str| -> Option<u64> {
        let line = text.lines().find(|l| l.starts_with(key))?;
        let n: u64 = line[key.len()..].split_whitespace().next()?.parse().ok()?;
        Some(n * 1024)
    };
    let mem_available = read("/proc/meminfo")
        .and_then(|t| kb(&t, "MemAvailable:"))
        .map(|b| (b, "MemAvailable".to_string()));
    let cgroup = read("/sys/fs/cgroup/memory.max")
        .and_then(|m| m.trim().parse::<u64>().ok())
        .zip(read("/sys/fs/cgroup/memory.current").and_then(|c| c.trim().parse::<u64>().ok()))
        .map(|(max, current)| {
            (
                max.saturating_sub(current),
                format!(
                    "the cgroup's memory.max {} less {} in use",
                    gb(max),
                    gb(current)
                ),
            )
        });
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
            (
                limit.saturating_sub(mapped),
                format!("ulimit -v {} less {} mapped", gb(limit), gb(mapped)),
            )
        });
    [mem_available, cgroup, address_space]
        .into_iter()
        .flatten()
        .min_by_key(|(bytes, _)| *bytes)
}

/// Bytes as gigabytes for a message: `0.41 GB`.
fn gb(bytes: u64) -> String {
    format!("{:.2} GB", bytes as f64 / 1e9)
}

/// What the GPU path needs besides the bytes it counts: the driver (lavapipe compiles its
/// shaders with LLVM in this process), tables, encoder buffers.
pub(crate) const GPU_MARGIN: u64 = 256 << 20;

/// What the CPU renderers need besides the bytes they count: the worker threads' stacks
/// and allocator arenas, tables, encoder buffers (issue 38, 8: the CPU had the GPU's
/// margin, and a 160x90 render was refused under a limit it renders in). Measured in
/// docs/reliability.md ("Issue 38").
pub(crate) const CPU_MARGIN: u64 = 64 << 20;

/// Fails in one line when `what` needs more than the memory available: `need` bytes, and
/// the GPU path's margin ([`GPU_MARGIN`]).
pub(crate) fn check(what: &str, need: u64) -> Result<()> {
    check_with_margin(what, need, GPU_MARGIN)
}

/// [`check`] for the CPU renderers, with their margin ([`CPU_MARGIN`]). It first starts
/// the worker threads (rayon's pool) and has each allocate once, so that what is mapped
/// counts their stacks and their allocator arenas (glibc reserves 64 MiB of address space
/// an arena, which `ulimit -v` counts): the margin then holds only what the render adds.
pub(crate) fn check_on_cpu(what: &str, need: u64) -> Result<()> {
    rayon::broadcast(|_| std::hint::black_box(vec![0u8; 64]));
    check_with_margin(what, need, CPU_MARGIN)
}

/// Fails in one line when `what` needs more than the memory available: `need` bytes, and
/// `margin` for the rest of the process.
pub(crate) fn check_with_margin(what: &str, need: u64, margin: u64) -> Result<()> {
    let Some((available, bound)) = available_bound() else {
        return Ok(());
    };
    if need.saturating_add(margin) > available {
        return Err(Error::Invalid {
            what: "size",
            message: format!(
                "{what} needs about {} of memory and {} is available ({bound}); choose a \
                 smaller size",
                gb(need.saturating_add(margin)),
                gb(available)
            ),
        });
    }
    Ok(())
}

/// Memory below which a GPU driver that fails to start, or loses its device, may have
/// done so for want of memory: lavapipe maps several hundred MB of address space (LLVM)
/// before it draws anything.
pub(crate) const DRIVER_NEEDS: u64 = 1 << 30;

/// Where memory is short for a GPU driver ([`DRIVER_NEEDS`]), what a message about its
/// failure should say instead of advising a driver package (issue 38, 8).
pub(crate) fn short_for_driver() -> Option<String> {
    let (available, bound) = available_bound()?;
    (available < DRIVER_NEEDS).then(|| {
        format!(
            "only {} of memory is available ({bound}): the driver may have failed for want \
             of memory",
            gb(available)
        )
    })
}
