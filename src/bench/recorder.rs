//! The bag recorder against `dd` on the same disk: messages as the node records them, through the recorder
//! alone (no DDS), and `dd` of as many bytes right before and after.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{bail, Context as _};
use rand::{Rng, SeedableRng};

use super::{bench_swing, log};
use crate::bag::{BagError, Recorder, RecorderConfig, StorageOptions, StoragePreset, TopicInfo};
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies, Swing};

/// Recorder against `dd`: one message type and storage, with `dd` of the same bytes.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DiskResult {
    /// ROS type recorded (`sweetspot_msgs/msg/Swing`, `…/ExitVelocity`, or `per swing: …` for the node's mix).
    pub message_type: String,
    /// Mean CDR size of one message, bytes.
    pub message_bytes: u64,
    /// Storage: a chunk compression (`zstd:1`, `none`, …) or a rosbag2 preset (`fastwrite`, …).
    pub storage: String,
    /// Messages recorded.
    pub messages: u64,
    /// Message bytes recorded (CDR payloads, as the recorder counts them).
    pub payload_bytes: u64,
    /// Bytes of the bag files on disk (MCAP framing, indexes and summary included; compressed chunks).
    pub bag_bytes: u64,
    /// Recorder wall time including the final fsync, s.
    pub recorder_s: f64,
    /// Recorder throughput, MB/s (10^6 message bytes per second).
    pub recorder_mb_s: f64,
    /// Bag bytes written per second, MB/s.
    pub recorder_disk_mb_s: f64,
    /// Recorder messages per second.
    pub recorder_msgs_s: f64,
    /// `dd` throughput writing as many bytes as the messages (1 MiB blocks, fdatasync), MB/s: the faster of
    /// the runs right before and right after the recorder.
    pub dd_mb_s: f64,
    /// Both `dd` runs (before, after), MB/s.
    pub dd_runs_mb_s: Vec<f64>,
    /// recorder_mb_s / dd_mb_s.
    pub ratio: f64,
}

/// The message a recorder bench records.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BenchMessage {
    /// The node's input, 84 B of CDR: the worst case (most messages per byte).
    Swing,
    /// The node's main output, ~156 B of CDR (ids and ten doubles).
    ExitVelocity,
    /// What the node records for each answered swing, in turn on three topics: the Swing (84 B), its
    /// ExitVelocity (~156 B) and its ModalEnergies (18 modes, ~520 B).
    PerSwing,
}

impl BenchMessage {
    /// How the report names it.
    fn label(self) -> &'static str {
        match self {
            BenchMessage::Swing => <Swing as crate::msgs::RosMessage>::TYPE_NAME,
            BenchMessage::ExitVelocity => <ExitVelocity as crate::msgs::RosMessage>::TYPE_NAME,
            BenchMessage::PerSwing => "per swing: Swing + ExitVelocity + ModalEnergies",
        }
    }
}

/// The recorder against `dd` for Swing messages, ExitVelocity messages and the node's per-swing mix, each
/// with zstd chunks (the default), uncompressed chunks and unchunked (rosbag2's `fastwrite`).
pub fn disk_bench(dir: &Path, messages: u64) -> anyhow::Result<Vec<DiskResult>> {
    let storages = ["zstd", "none", "fastwrite"].map(|s| storage_spec(s).map_err(anyhow::Error::from));
    disk_bench_with(dir, messages, &storages.into_iter().collect::<Result<Vec<_>, _>>()?)
}

/// A storage the recorder bench can use, by name: a rosbag2 preset (`none`, `fastwrite`, `zstd_fast`,
/// `zstd_small`) or a chunk compression (`zstd`, `zstd:LEVEL`, `lz4`).
pub fn storage_spec(name: &str) -> Result<(String, StorageOptions), BagError> {
    let storage = if name.parse::<StoragePreset>().is_ok() {
        StorageOptions::preset(name)?
    } else {
        StorageOptions::from_parameters("", name)?
    };
    Ok((name.to_string(), storage))
}

/// [`disk_bench`] with the given storages, as (label, options).
pub fn disk_bench_with(
    dir: &Path,
    messages: u64,
    storages: &[(String, StorageOptions)],
) -> anyhow::Result<Vec<DiskResult>> {
    let mut results = Vec::new();
    for message in [BenchMessage::Swing, BenchMessage::ExitVelocity, BenchMessage::PerSwing] {
        for (label, storage) in storages {
            let r = disk_bench_one(dir, message, messages, label, *storage)?;
            log(&format!(
                "recorder {} {}: {:.1} MB/s of messages ({:.0} msg/s, {:.1} MB/s on disk) vs dd {:.1} MB/s: {:.0} %",
                r.message_type,
                r.storage,
                r.recorder_mb_s,
                r.recorder_msgs_s,
                r.recorder_disk_mb_s,
                r.dd_mb_s,
                r.ratio * 100.0
            ));
            results.push(r);
        }
    }
    Ok(results)
}

/// Distinct CDR payloads of `message` with random measured values. 65,536 of them (5–10 MB), more than
/// any zstd window of the levels used, so the compressor sees no exact repeats, as with real swings.
pub const BENCH_PAYLOADS: u64 = 65_536;

/// The topics a recorder bench records, each with `payloads` distinct CDR payloads (the benches use
/// [`BENCH_PAYLOADS`]): one topic, or for [`BenchMessage::PerSwing`] three, recorded in turn.
pub fn bench_streams(message: BenchMessage, payloads: u64) -> Vec<(TopicInfo, Vec<Vec<u8>>)> {
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let (mut swings, mut exits, mut energies) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..payloads {
        let swing = Swing {
            ball_speed: rng.gen_range(30.0..45.0),
            bat_cm_speed: rng.gen_range(15.0..25.0),
            bat_angular_speed: rng.gen_range(30.0..60.0),
            impact_z: rng.gen_range(0.4..0.8),
            measured_exit_speed: rng.gen_range(30.0..50.0),
            ..bench_swing(i)
        };
        let exit_speed = rng.gen_range(35.0..50.0);
        let exit = ExitVelocity {
            header: swing.header.clone(),
            swing_id: swing.swing_id,
            bat_id: "r161".into(),
            ball_id: "baseball".into(),
            status: ExitVelocity::STATUS_OK,
            impact_z: swing.impact_z,
            exit_speed,
            rigid_exit_speed: exit_speed * rng.gen_range(1.0..1.1),
            effective_cor: rng.gen_range(0.3..0.5),
            collision_efficiency: rng.gen_range(0.1..0.3),
            contact_time: rng.gen_range(0.0006..0.0012),
            peak_force: rng.gen_range(1.0e4..3.0e4),
            impulse: rng.gen_range(10.0..15.0),
            max_compression: rng.gen_range(0.005..0.02),
            measured_exit_speed: swing.measured_exit_speed,
            residual: swing.measured_exit_speed - exit_speed,
            ..ExitVelocity::default()
        };
        let modes = 18;
        let energy: Vec<f64> = (0..modes).map(|_| rng.gen_range(0.0..2.0)).collect();
        let total: f64 = energy.iter().sum();
        let modal = ModalEnergies {
            header: swing.header.clone(),
            swing_id: swing.swing_id,
            bat_id: "r161".into(),
            frequency: (0..modes).map(|m| 170.0 * (m + 1) as f64 * rng.gen_range(0.99..1.01)).collect(),
            fraction: energy.iter().map(|e| e / total.max(1e-12)).collect(),
            energy,
            vibration_energy: total,
            hysteresis_loss: rng.gen_range(20.0..40.0),
            energy_residual: rng.gen_range(-1e-5..1e-5),
            ..ModalEnergies::default()
        };
        match message {
            BenchMessage::Swing => swings.push(crate::msgs::encode_cdr(&swing).unwrap_or_default()),
            BenchMessage::ExitVelocity => exits.push(crate::msgs::encode_cdr(&exit).unwrap_or_default()),
            BenchMessage::PerSwing => {
                swings.push(crate::msgs::encode_cdr(&swing).unwrap_or_default());
                exits.push(crate::msgs::encode_cdr(&exit).unwrap_or_default());
                energies.push(crate::msgs::encode_cdr(&modal).unwrap_or_default());
            }
        }
    }
    let swing_topic = TopicInfo::of::<Swing>("/swing", crate::node::recording::recorded_qos(&crate::ros::swing_qos()));
    let results_qos = crate::node::recording::recorded_qos(&crate::ros::results_qos());
    let exit_topic = TopicInfo::of::<ExitVelocity>("/exit_velocity", results_qos);
    let modal_topic = TopicInfo::of::<ModalEnergies>("/modal_energies", results_qos);
    match message {
        BenchMessage::Swing => vec![(swing_topic, swings)],
        BenchMessage::ExitVelocity => vec![(exit_topic, exits)],
        BenchMessage::PerSwing => vec![(swing_topic, swings), (exit_topic, exits), (modal_topic, energies)],
    }
}

/// Records `messages` messages (as the node records them) with the bag recorder into `dir`; right before and
/// right after, writes the same number of message bytes with `dd … conv=fdatasync` to the same directory.
pub fn disk_bench_one(
    dir: &Path,
    message: BenchMessage,
    messages: u64,
    label: &str,
    storage: StorageOptions,
) -> anyhow::Result<DiskResult> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let bag = dir.join(format!("recorder_bench_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&bag);
    let (topic_infos, payloads): (Vec<_>, Vec<_>) = bench_streams(message, BENCH_PAYLOADS).into_iter().unzip();
    let streams = payloads.len().max(1) as u64;
    let payload_bytes: u64 = (0..messages)
        .map(|i| payloads[(i % streams) as usize][((i / streams) % BENCH_PAYLOADS) as usize].len() as u64)
        .sum();
    let dd_before = dd_mb_s(dir, payload_bytes)?;
    let mut config = RecorderConfig::new(&bag);
    config.queue_capacity = 65_536;
    let t0 = crate::model::time::now_ns();
    let start = Instant::now();
    let recorder = Recorder::start_with(config, storage)?;
    let topics = topic_infos.into_iter().map(|t| recorder.register_topic(t)).collect::<Result<Vec<_>, _>>()?;
    for i in 0..messages {
        let stream = (i % streams) as usize;
        let cdr = &payloads[stream][((i / streams) % BENCH_PAYLOADS) as usize];
        let stamp = t0 + i * 1000;
        // The recorder never waits for its writer (a full queue is a counted drop); to measure its
        // throughput, retry until the writer thread has made room. Sleeping rather than spinning leaves
        // the writer the core while it catches up (this machine has two).
        while !recorder.record_bytes(topics[stream], cdr, stamp, stamp) {
            std::thread::sleep(Duration::from_micros(50));
        }
    }
    let stats = recorder.finish()?;
    let recorder_s = start.elapsed().as_secs_f64();
    let bag_bytes = dir_bytes(&bag);
    let _ = std::fs::remove_dir_all(&bag);

    let dd_after = dd_mb_s(dir, stats.bytes)?;
    let recorder_mb_s = stats.bytes as f64 / 1e6 / recorder_s;
    // The faster dd is the reference: on this VM's disk a dd writing where nothing was written lately runs at
    // a quarter of its speed on blocks just freed, and which one comes out fast depends on what ran before.
    let dd_mb_s = dd_before.max(dd_after);
    Ok(DiskResult {
        message_type: message.label().to_string(),
        message_bytes: payloads.iter().flatten().map(|p| p.len() as u64).sum::<u64>()
            / payloads.iter().map(Vec::len).sum::<usize>().max(1) as u64,
        storage: label.to_string(),
        messages: stats.written,
        payload_bytes: stats.bytes,
        bag_bytes,
        recorder_s,
        recorder_mb_s,
        recorder_disk_mb_s: bag_bytes as f64 / 1e6 / recorder_s,
        recorder_msgs_s: stats.written as f64 / recorder_s,
        dd_mb_s,
        dd_runs_mb_s: vec![dd_before, dd_after],
        ratio: recorder_mb_s / dd_mb_s,
    })
}

/// `dd if=/dev/zero bs=1M conv=fdatasync` of `bytes` (whole MiB, at least one) into `dir`, MB/s.
fn dd_mb_s(dir: &Path, bytes: u64) -> anyhow::Result<f64> {
    let dd_file = dir.join(format!("dd_bench_{}", std::process::id()));
    let mib = (bytes / (1 << 20)).max(1);
    let start = Instant::now();
    let status = Command::new("dd")
        .arg("if=/dev/zero")
        .arg(format!("of={}", dd_file.display()))
        .arg("bs=1M")
        .arg(format!("count={mib}"))
        .arg("conv=fdatasync")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .context("running dd")?;
    let seconds = start.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&dd_file);
    if !status.success() {
        bail!("dd failed: {status}");
    }
    Ok((mib << 20) as f64 / 1e6 / seconds)
}

fn dir_bytes(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .map(|entries| entries.filter_map(Result::ok).filter_map(|e| e.metadata().ok()).map(|m| m.len()).sum())
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_per_swing_mix_records_swing_exit_velocity_and_modal_energies_in_turn() {
        let streams = bench_streams(BenchMessage::PerSwing, BENCH_PAYLOADS);
        let names: Vec<&str> = streams.iter().map(|(t, _)| t.name.as_str()).collect();
        assert_eq!(names, ["/swing", "/exit_velocity", "/modal_energies"]);
        let sizes: Vec<usize> = streams.iter().map(|(_, p)| p[0].len()).collect();
        // CDR sizes as the node publishes them: a Swing of 172 B (ids, ten inputs, six oblique fields, the 3-D
        // tail: four doubles and a byte padded to 8), an ExitVelocity of ids and twenty-six doubles, a
        // ModalEnergies of three arrays of 18 doubles.
        assert_eq!(sizes[0], 172, "{sizes:?}");
        assert!((250..320).contains(&sizes[1]) && (450..600).contains(&sizes[2]), "{sizes:?}");
        assert!(streams.iter().all(|(_, p)| p.len() as u64 == BENCH_PAYLOADS));

        let dir = tempfile::tempdir().unwrap();
        let r = disk_bench_one(dir.path(), BenchMessage::PerSwing, 3_000, "zstd", StorageOptions::default()).unwrap();
        assert_eq!(r.messages, 3_000);
        let per_swing: usize = sizes.iter().sum();
        assert_eq!(r.payload_bytes, 1_000 * per_swing as u64, "1,000 swings of three messages each");
        assert_eq!(r.message_bytes, (per_swing / 3) as u64);
        assert!(r.ratio > 0.0 && r.dd_mb_s > 0.0, "{r:?}");
        assert!(super::super::disk_table(&[r]).contains("per swing: Swing + ExitVelocity + ModalEnergies"));
    }
}
