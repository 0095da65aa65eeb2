//! The in-process ros2-client peer that drives a server (the node or the raw echo) on one domain: paced
//! swings out, answers matched by `swing_id`, latencies into an HDR histogram; the latest diagnostics kept.

use std::collections::BTreeMap;
use std::pin::pin;
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::bail;
use futures::StreamExt;
use hdrhistogram::Histogram;
use ros2_client::qos::{History, Reliability, WhenFull};
use ros2_client::{NodeName, NodeOptions, Publisher};

use super::{bench_swing, require_private_network};
use crate::msgs::diagnostic_msgs::msg::DiagnosticArray;
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};
use crate::ros::{DdsConfig, DiscoveryRange};

/// Latency figures of one paced run, µs.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct RunResult {
    /// Target rate, swings/s.
    pub target_rate: u32,
    /// Rate the client actually published at, swings/s.
    pub achieved_rate: f64,
    /// Swings sent.
    pub sent: u64,
    /// Answers received.
    pub answered: u64,
    /// Median latency, µs.
    pub p50_us: u64,
    /// 99th percentile latency, µs.
    pub p99_us: u64,
    /// Worst latency, µs.
    pub max_us: u64,
    /// Time from the last publish to the last answer, ms (a growing backlog shows here).
    pub drain_ms: f64,
}

/// The in-process ros2-client peer that drives the node or the echo on one domain.
pub struct Client {
    rt: tokio::runtime::Runtime,
    node: ros2_client::Node,
    publisher: Publisher<Swing>,
    answers: mpsc::Receiver<(u64, Instant)>,
    diagnostics: Arc<Mutex<BTreeMap<String, String>>>,
    next_id: u64,
}

impl Client {
    /// A client on `domain` (loopback only).
    pub fn new(domain: u16) -> anyhow::Result<Client> {
        require_private_network()?;
        let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
        let context = crate::ros::context(&dds_config(domain))?;
        let mut node = context
            .new_node(NodeName::new("/", "sweetspot_bench").map_err(dds)?, NodeOptions::new().enable_rosout(false))
            .map_err(dds)?;
        let swing_topic = crate::ros::create_topic::<Swing>(&node, "/swing", &crate::ros::swing_qos())?;
        let ev_topic = crate::ros::create_topic::<ExitVelocity>(&node, "/exit_velocity", &crate::ros::results_qos())?;
        let diag_topic =
            crate::ros::create_topic::<DiagnosticArray>(&node, "/diagnostics", &crate::ros::diagnostics_qos())?;
        let writer_qos = crate::ros::swing_qos().reliability(Reliability::Reliable { when_full: WhenFull::Block });
        let publisher = node.create_publisher::<Swing>(&swing_topic, Some(writer_qos)).map_err(dds)?;
        let reader_qos = crate::ros::results_qos().history(History::KeepLast { depth: 65_536 });
        let ev_sub = node.create_subscription::<ExitVelocity>(&ev_topic, Some(reader_qos)).map_err(dds)?;
        let diag_sub = node.create_subscription::<DiagnosticArray>(&diag_topic, None).map_err(dds)?;
        let spinner = node.spinner().map_err(dds)?;
        rt.spawn(spinner.spin());
        let (tx, answers) = mpsc::channel();
        rt.spawn(async move {
            let mut stream = pin!(ev_sub.async_stream());
            while let Some(received) = stream.next().await {
                if let Ok((ev, _)) = received {
                    if tx.send((ev.swing_id, Instant::now())).is_err() {
                        break;
                    }
                }
            }
        });
        let diagnostics = Arc::new(Mutex::new(BTreeMap::new()));
        let latest = Arc::clone(&diagnostics);
        rt.spawn(async move {
            let mut stream = pin!(diag_sub.async_stream());
            while let Some(received) = stream.next().await {
                if let Ok((array, _)) = received {
                    if let Ok(mut map) = latest.lock() {
                        for status in array.status {
                            for kv in status.values {
                                map.insert(kv.key, kv.value);
                            }
                        }
                    }
                }
            }
        });
        Ok(Client { rt, node, publisher, answers, diagnostics, next_id: 1 })
    }

    /// Waits for the server to match and answer a few swings.
    pub fn warm_up(&mut self, limit: Duration) -> anyhow::Result<()> {
        let matched = self
            .rt
            .block_on(async { tokio::time::timeout(limit, self.publisher.wait_for_subscription(&self.node)).await });
        if matched.is_err() {
            bail!("no subscriber on /swing matched within {limit:?}");
        }
        let start = Instant::now();
        while start.elapsed() < limit {
            let run = self.run(200, 40, Duration::from_secs(2))?;
            if run.answered == run.sent {
                return Ok(());
            }
        }
        bail!("the server did not answer within {limit:?}")
    }

    /// The latest diagnostics value `key` as an integer (0 if absent).
    pub fn diagnostic(&self, key: &str) -> u64 {
        self.diagnostics.lock().ok().and_then(|m| m.get(key).and_then(|v| v.parse().ok())).unwrap_or(0)
    }

    /// Publishes `count` swings paced at `rate`/s, then waits for their answers (at most `quiet` without a
    /// new one), and returns the latencies.
    pub fn run(&mut self, rate: u32, count: u64, quiet: Duration) -> anyhow::Result<RunResult> {
        Ok(self.run_histogram(rate, count, quiet)?.0)
    }

    /// [`Client::run`], also returning the histogram of latencies (µs) so runs can be merged.
    pub fn run_histogram(
        &mut self,
        rate: u32,
        count: u64,
        quiet: Duration,
    ) -> anyhow::Result<(RunResult, Histogram<u64>)> {
        while self.answers.try_recv().is_ok() {}
        let first = self.next_id;
        self.next_id += count;
        let mut sent_at: Vec<Option<Instant>> = vec![None; count as usize];
        let interval = Duration::from_secs_f64(1.0 / f64::from(rate.max(1)));
        let mut histogram = Histogram::<u64>::new_with_bounds(1, 600_000_000, 3)?;
        let mut answered = 0u64;
        let mut last_answer = None;
        let take = |id: u64,
                    at: Instant,
                    sent_at: &[Option<Instant>],
                    h: &mut Histogram<u64>,
                    n: &mut u64,
                    last: &mut Option<Instant>| {
            if id >= first && id < first + count {
                if let Some(sent) = sent_at[(id - first) as usize] {
                    let _ = h.record(at.saturating_duration_since(sent).as_micros().max(1) as u64);
                    *n += 1;
                    *last = Some(at);
                }
            }
        };
        let start = Instant::now();
        for i in 0..count {
            let due = start + interval.mul_f64(i as f64);
            loop {
                let now = Instant::now();
                if now >= due {
                    break;
                }
                let wait = due - now;
                if wait > Duration::from_micros(200) {
                    std::thread::sleep(wait - Duration::from_micros(100));
                } else {
                    std::thread::yield_now();
                }
            }
            sent_at[i as usize] = Some(Instant::now());
            if let Err(e) = self.publisher.publish(bench_swing(first + i)) {
                bail!("publishing swing {}: {e:?}", first + i);
            }
            while let Ok((id, at)) = self.answers.try_recv() {
                take(id, at, &sent_at, &mut histogram, &mut answered, &mut last_answer);
            }
        }
        let send_end = Instant::now();
        let achieved = count as f64 / send_end.duration_since(start).as_secs_f64().max(1e-9);
        while answered < count {
            match self.answers.recv_timeout(quiet) {
                Ok((id, at)) => take(id, at, &sent_at, &mut histogram, &mut answered, &mut last_answer),
                Err(_) => break,
            }
        }
        let drain_ms =
            last_answer.map(|t| t.saturating_duration_since(send_end).as_secs_f64() * 1e3).unwrap_or(f64::NAN);
        let result = RunResult {
            target_rate: rate,
            achieved_rate: achieved,
            sent: count,
            answered,
            p50_us: histogram.value_at_quantile(0.5),
            p99_us: histogram.value_at_quantile(0.99),
            max_us: histogram.max(),
            drain_ms,
        };
        Ok((result, histogram))
    }
}

pub(super) fn dds<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow::anyhow!("{e:?}")
}

/// DDS on `domain`, loopback only.
pub(super) fn dds_config(domain: u16) -> DdsConfig {
    DdsConfig { domain_id: domain, range: DiscoveryRange::Localhost }
}
