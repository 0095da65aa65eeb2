//! What the bench ran on, and how loaded the machine was before and after: the head of every report.

use std::collections::BTreeMap;

/// Machine description: CPU model, nproc, load average, kernel, build profile, UTC time.
pub fn machine() -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model =
        cpuinfo.lines().find(|l| l.starts_with("model name")).and_then(|l| l.split(':').nth(1)).unwrap_or("?").trim();
    m.insert("cpu".into(), model.to_string());
    m.insert("nproc".into(), std::thread::available_parallelism().map(|n| n.get().to_string()).unwrap_or_default());
    m.insert("loadavg".into(), loadavg());
    m.insert(
        "kernel".into(),
        std::fs::read_to_string("/proc/sys/kernel/osrelease").unwrap_or_default().trim().to_string(),
    );
    m.insert("profile".into(), if cfg!(debug_assertions) { "debug".into() } else { "release".into() });
    m.insert("utc".into(), chrono::Utc::now().format("%Y-%m-%dT%H:%M:%SZ").to_string());
    m
}

/// `machine` (taken before a run) with the load average after it.
pub(super) fn with_load_after(mut machine: BTreeMap<String, String>) -> BTreeMap<String, String> {
    machine.insert("loadavg_after".into(), loadavg());
    machine
}

/// `/proc/loadavg`, trimmed (empty if unreadable).
pub fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg").unwrap_or_default().trim().to_string()
}

/// The machine and its load before and after, one line (the head of both reports).
pub(super) fn machine_line(m: &BTreeMap<String, String>) -> String {
    let get = |key: &str| m.get(key).map(String::as_str).unwrap_or("?");
    format!(
        "machine: {} × {} ({}), load before: {}, after: {}, build: {}",
        get("nproc"),
        get("cpu"),
        get("kernel"),
        get("loadavg"),
        get("loadavg_after"),
        get("profile")
    )
}
