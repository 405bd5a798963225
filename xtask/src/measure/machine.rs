//! What the machine a report was measured on is: its CPU and its memory bandwidth.

use rayon::prelude::*;
use std::time::Instant;

/// The CPU's model name from `/proc/cpuinfo`, or "unknown".
pub fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|x| x.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// Read bandwidth in GB/s: the median of 5 parallel sums over 256 MB.
pub fn memory_bandwidth() -> f64 {
    let data: Vec<u64> = (0..32u64 << 20).collect();
    let runs: Vec<f64> = (0..5)
        .map(|_| {
            let t = Instant::now();
            let s: u64 = data.par_chunks(1 << 16).map(|c| c.iter().fold(0u64, |a, &x| a.wrapping_add(x))).sum();
            std::hint::black_box(s);
            (data.len() * 8) as f64 / t.elapsed().as_secs_f64() / 1e9
        })
        .collect();
    vcut_shade::measure::median(runs)
}

/// CPU seconds (user + system) of this process's children that have ended and been waited for,
/// from `/proc/self/stat` (`cutime`, `cstime`; Linux's clock tick, 100 per second). `None`
/// where there is no such file.
pub fn children_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold spaces) start at field 3, `state`.
    let rest: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = |field: usize| rest.get(field - 3)?.parse::<f64>().ok();
    Some((ticks(16)? + ticks(17)?) / 100.0)
}
