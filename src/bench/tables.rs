//! The bench's reports as text.

use std::fmt::Write as _;

use super::full::BenchReport;
use super::latency::InterleavedReport;
use super::machine::machine_line;
use super::recorder::DiskResult;

/// The report as a human-readable table.
pub fn table(r: &BenchReport) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{}", machine_line(&r.machine));
    let _ = writeln!(s, "\nswing → exit_velocity over DDS/loopback (node recording; child processes)");
    let _ = writeln!(
        s,
        "{:>8} | {:>9} {:>9} {:>9} | {:>9} {:>9} {:>9} | {:>9}",
        "rate/s", "raw p50", "raw p99", "raw max", "node p50", "node p99", "node max", "p99 ratio"
    );
    for ((raw, node), (_, ratio)) in r.raw.iter().zip(&r.node).zip(&r.p99_ratio) {
        let _ = writeln!(
            s,
            "{:>8} | {:>7}µs {:>7}µs {:>7}µs | {:>7}µs {:>7}µs {:>7}µs | {:>8.2}×{}",
            raw.target_rate,
            raw.p50_us,
            raw.p99_us,
            raw.max_us,
            node.p50_us,
            node.p99_us,
            node.max_us,
            ratio,
            if node.answered < node.sent || raw.answered < raw.sent {
                format!("  (lost: raw {}, node {})", raw.sent - raw.answered, node.sent - node.answered)
            } else {
                String::new()
            }
        );
    }
    let _ = writeln!(s, "\nsustained rate, recording on (target ≥ 10000/s): {}/s", r.max_sustained_rate);
    for st in &r.steps {
        let _ = writeln!(
            s,
            "  {:>6}/s: sent at {:>7.0}/s, {}/{} answered, p99 {} µs, drain {:.0} ms — {}",
            st.run.target_rate,
            st.run.achieved_rate,
            st.run.answered,
            st.run.sent,
            st.run.p99_us,
            st.run.drain_ms,
            st.verdict
        );
    }
    let mm = &r.memory;
    let _ = writeln!(s, "\nnode memory: peak RSS (VmHWM) after 10000/s: {:.1} MB; soak {}/s × {:.0} s: RSS first quarter {:.1} MB, last quarter {:.1} MB, {} answers lost", mm.peak_rss_kb_at_10k as f64 / 1024.0, mm.soak_rate, mm.soak_s, mm.soak_first_quarter_kb as f64 / 1024.0, mm.soak_last_quarter_kb as f64 / 1024.0, mm.soak_lost);
    s.push('\n');
    s.push_str(&disk_table(&r.disk));
    s
}

/// The recorder-against-dd rows as text (the full report's last part, and `--only recorder`).
pub fn disk_table(disk: &[DiskResult]) -> String {
    let mut s =
        String::from("recorder against dd (1 MiB blocks, fdatasync, same bytes as the messages), target ≥ 80 %:\n");
    for d in disk {
        let _ = writeln!(
            s,
            "  {} ({} B) {}: {} messages, {:.1} MB of messages ({:.1} MB on disk) in {:.2} s incl. fsync = {:.1} MB/s, \
             {:.0} msg/s; dd {:.1} MB/s (faster of {}); ratio {:.0} % (bytes on disk: {:.0} % of dd)",
            d.message_type,
            d.message_bytes,
            d.storage,
            d.messages,
            d.payload_bytes as f64 / 1e6,
            d.bag_bytes as f64 / 1e6,
            d.recorder_s,
            d.recorder_mb_s,
            d.recorder_msgs_s,
            d.dd_mb_s,
            d.dd_runs_mb_s.iter().map(|v| format!("{v:.0}")).collect::<Vec<_>>().join(", "),
            d.ratio * 100.0,
            d.recorder_disk_mb_s / d.dd_mb_s * 100.0
        );
    }
    s
}

/// [`InterleavedReport`] as a table: per rate, each server's p50/p99/max and p99 ratio to the raw echo.
pub fn interleaved_table(r: &InterleavedReport) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{}", machine_line(&r.machine));
    let _ = writeln!(s, "\nswing → exit_velocity over DDS/loopback, servers interleaved in blocks (nodes recording)");
    let _ = writeln!(
        s,
        "{:>8} | {:>13} | {:>9} {:>9} {:>9} | {:>9} | answered",
        "rate/s", "server", "p50", "p99", "max", "p99/raw"
    );
    for (i, (rate, _)) in r.block_seconds.iter().enumerate() {
        for t in &r.targets {
            let run = &t.runs[i];
            let _ = writeln!(
                s,
                "{:>8} | {:>13} | {:>7}µs {:>7}µs {:>7}µs | {:>8.2}× | {}/{}",
                rate, t.label, run.p50_us, run.p99_us, run.max_us, t.p99_ratio[i].1, run.answered, run.sent
            );
        }
    }
    s
}
