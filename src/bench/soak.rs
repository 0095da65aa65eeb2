//! The node's memory: its peak RSS, and whether its RSS stays flat over a long run at a steady rate.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use super::client::Client;
use super::{count_for, log, QUIET};

/// Memory of the node process.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct MemoryResult {
    /// VmHWM after the 10,000/s run, kB.
    pub peak_rss_kb_at_10k: u64,
    /// Rate of the soak, swings/s.
    pub soak_rate: u32,
    /// Soak length, s.
    pub soak_s: f64,
    /// VmRSS sampled once a second during the soak, kB.
    pub soak_rss_kb: Vec<u64>,
    /// Median RSS of the first and of the last quarter of the soak, kB.
    pub soak_first_quarter_kb: u64,
    /// See `soak_first_quarter_kb`.
    pub soak_last_quarter_kb: u64,
    /// Answers missing at the end of the soak.
    pub soak_lost: u64,
}

/// A field of `/proc/<pid>/status` in kB (e.g. `VmRSS`, `VmHWM`).
pub fn proc_status_kb(pid: u32, field: &str) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    status
        .lines()
        .find(|l| l.starts_with(field) && l[field.len()..].starts_with(':'))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
}

/// The memory soak: `soak` at 5,000/s (1,000/s if the node sustained less), the node's RSS sampled once a
/// second, into `memory`.
pub(super) fn soak(
    client: &mut Client,
    pid: u32,
    max_sustained: u32,
    soak: Duration,
    memory: &mut MemoryResult,
) -> anyhow::Result<()> {
    let soak_rate = if max_sustained >= 5_000 { 5_000 } else { 1_000 };
    memory.soak_rate = soak_rate;
    memory.soak_s = soak.as_secs_f64();
    log(&format!("soak: {soak_rate}/s for {:.0} s", memory.soak_s));
    let stop = Arc::new(AtomicBool::new(false));
    let sampler = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            let mut samples = Vec::new();
            while !stop.load(Ordering::Relaxed) {
                samples.push(proc_status_kb(pid, "VmRSS").unwrap_or(0));
                std::thread::sleep(Duration::from_secs(1));
            }
            samples
        })
    };
    let soak = client.run(soak_rate, count_for(soak_rate, memory.soak_s), QUIET)?;
    stop.store(true, Ordering::Relaxed);
    memory.soak_rss_kb = sampler.join().unwrap_or_default();
    memory.soak_lost = soak.sent - soak.answered;
    let quarter = (memory.soak_rss_kb.len() / 4).max(1);
    memory.soak_first_quarter_kb = median(&memory.soak_rss_kb[..quarter.min(memory.soak_rss_kb.len())]);
    memory.soak_last_quarter_kb = median(&memory.soak_rss_kb[memory.soak_rss_kb.len().saturating_sub(quarter)..]);
    log(&format!(
        "soak: RSS first quarter {} kB, last quarter {} kB, {} lost",
        memory.soak_first_quarter_kb, memory.soak_last_quarter_kb, memory.soak_lost
    ));
    Ok(())
}

fn median(values: &[u64]) -> u64 {
    let mut v = values.to_vec();
    v.sort_unstable();
    v.get(v.len() / 2).copied().unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_this_process_rss_and_peak_from_proc() {
        let rss = proc_status_kb(std::process::id(), "VmRSS").expect("VmRSS");
        let peak = proc_status_kb(std::process::id(), "VmHWM").expect("VmHWM");
        assert!(rss > 0 && peak >= rss, "rss {rss} kB, peak {peak} kB");
        assert_eq!(proc_status_kb(std::process::id(), "NoSuchField"), None);
    }

    #[test]
    fn median_of_samples() {
        assert_eq!(median(&[]), 0);
        assert_eq!(median(&[5]), 5);
        assert_eq!(median(&[9, 1, 5]), 5);
    }
}
