//! Facts about the machine tribo runs on, read where both the study (the memory budget of the
//! tables running at once) and the report (the provenance in the page header) need them.

/// The machine's total memory in bytes (`MemTotal` of `/proc/meminfo`, Linux); `None` where it
/// cannot be read.
pub fn machine_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}
