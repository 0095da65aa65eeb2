//! The highest rate the node sustains with recording on: rising steps until one fails twice.

use std::time::Duration;

use super::client::{Client, RunResult};
use super::{count_for, log, QUIET};

/// One step of the sustained-rate search.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StepResult {
    /// Latencies and counts of the step.
    pub run: RunResult,
    /// Swings the node dropped during the step (diagnostics `swings_dropped`).
    pub node_dropped: u64,
    /// Messages the recorder dropped during the step (diagnostics `recorder_dropped`).
    pub recorder_dropped: u64,
    /// Whether the step counts as sustained: no loss anywhere (answers, node drops, transport, recorder), rate
    /// reached, p99 ≤ 100 ms, no backlog.
    pub sustained: bool,
    /// Why not, if not.
    pub verdict: String,
}

/// Steps the node through rising rates (each retried once, as a shared machine can stall any few seconds)
/// until one fails twice; returns every step and the highest sustained rate (0 if none).
pub(super) fn sustained_search(client: &mut Client, quick: bool) -> anyhow::Result<(Vec<StepResult>, u32)> {
    let step_rates: &[u32] =
        if quick { &[5_000, 10_000, 20_000] } else { &[2_000, 5_000, 10_000, 15_000, 20_000, 30_000, 40_000] };
    let step_seconds = if quick { 2.0 } else { 5.0 };
    let mut steps = Vec::new();
    let mut max_sustained = 0;
    for &rate in step_rates {
        for attempt in 0..2 {
            let step = run_step(client, rate, step_seconds)?;
            log(&format!("step {rate:>6}/s (attempt {}): {} (p99 {} µs)", attempt + 1, step.verdict, step.run.p99_us));
            let sustained = step.sustained;
            steps.push(step);
            if sustained {
                max_sustained = rate;
                break;
            }
        }
        if max_sustained != rate {
            break;
        }
    }
    Ok((steps, max_sustained))
}

/// One step at `rate` for `seconds`, with the node's drop counters read from its diagnostics around it.
fn run_step(client: &mut Client, rate: u32, seconds: f64) -> anyhow::Result<StepResult> {
    // The node publishes diagnostics every 0.5 s: wait for fresh counters before and after the step.
    let settle = Duration::from_millis(1200);
    std::thread::sleep(settle);
    let counters =
        |c: &Client| ["swings_dropped", "recorder_dropped", "swings_lost_in_transport"].map(|key| c.diagnostic(key));
    let before = counters(client);
    let run = client.run(rate, count_for(rate, seconds), QUIET)?;
    std::thread::sleep(settle);
    let after = counters(client);
    let [node_dropped, recorder_dropped, lost] = [0, 1, 2].map(|i| after[i].saturating_sub(before[i]));
    let why = shortfalls(rate, &run, node_dropped, lost, recorder_dropped);
    let sustained = why.is_empty();
    let verdict = if sustained { "sustained".to_string() } else { why.join("; ") };
    Ok(StepResult { run, node_dropped, recorder_dropped, sustained, verdict })
}

/// Why a step at `rate` does not count as sustained (empty if it does).
fn shortfalls(rate: u32, r: &RunResult, node_dropped: u64, lost: u64, recorder_dropped: u64) -> Vec<String> {
    let mut why = Vec::new();
    if r.answered < r.sent {
        why.push(format!("{} answers missing", r.sent - r.answered));
    }
    if node_dropped > 0 {
        why.push(format!("node dropped {node_dropped}"));
    }
    if lost > 0 {
        why.push(format!("{lost} swings lost in transport"));
    }
    if recorder_dropped > 0 {
        why.push(format!("recorder dropped {recorder_dropped}"));
    }
    if r.achieved_rate < 0.95 * f64::from(rate) {
        why.push(format!("client reached only {:.0}/s", r.achieved_rate));
    }
    if r.p99_us > 100_000 {
        why.push(format!("lag: p99 {} ms", r.p99_us / 1000));
    }
    // NaN (no answer at all) counts as a backlog too.
    if r.drain_ms.is_nan() || r.drain_ms >= 500.0 {
        why.push(format!("backlog: last answer {:.0} ms after the last swing", r.drain_ms));
    }
    why
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(rate: u32, answered: u64, p99_us: u64, drain_ms: f64) -> RunResult {
        RunResult {
            target_rate: rate,
            achieved_rate: f64::from(rate),
            sent: 100,
            answered,
            p50_us: 50,
            p99_us,
            max_us: p99_us,
            drain_ms,
        }
    }

    #[test]
    fn a_step_is_sustained_only_without_loss_lag_or_backlog() {
        assert!(shortfalls(1_000, &run(1_000, 100, 900, 3.0), 0, 0, 0).is_empty());
        assert_eq!(shortfalls(1_000, &run(1_000, 97, 900, 3.0), 0, 0, 0), ["3 answers missing"]);
        assert_eq!(shortfalls(1_000, &run(1_000, 100, 900, 3.0), 2, 0, 1), ["node dropped 2", "recorder dropped 1"]);
        assert_eq!(shortfalls(1_000, &run(1_000, 100, 150_000, 3.0), 0, 0, 0), ["lag: p99 150 ms"]);
        assert_eq!(
            shortfalls(1_000, &run(1_000, 0, 0, f64::NAN), 0, 0, 0),
            ["100 answers missing", "backlog: last answer NaN ms after the last swing"]
        );
    }
}
