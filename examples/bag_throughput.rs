//! Measures sustained recorder throughput: `cargo run --release --example bag_throughput [MESSAGES] [BYTES]`.
//!
//! Records MESSAGES (default 1,000,000) Swing-sized CDR messages (default 128 bytes) through the public
//! Recorder as fast as the queue accepts them (retrying when it is momentarily full, so nothing is dropped)
//! and prints messages/s and MB/s from start() to finish() (summary and metadata.yaml included).

use std::time::{Duration, Instant};

use sweetspot::bag::{RecordedQos, Recorder, RecorderConfig, TopicInfo};

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let messages: u64 = args.next().map(|a| a.parse()).transpose()?.unwrap_or(1_000_000);
    let size: usize = args.next().map(|a| a.parse()).transpose()?.unwrap_or(128);
    let tmp = tempfile::tempdir()?;
    let dir = tmp.path().join("throughput");
    let started = Instant::now();
    let recorder = Recorder::start(RecorderConfig::new(&dir))?;
    let qos = RecordedQos { reliable: true, transient_local: false, depth: 10 };
    let topic = recorder.register_topic(TopicInfo {
        name: "/bench/swing".into(),
        type_name: "std_msgs/msg/String".into(),
        schema_text: "string data\n".into(),
        type_hash: String::new(),
        qos,
    })?;
    let mut retries = 0u64;
    for i in 0..messages {
        let mut payload = vec![0u8, 1, 0, 0];
        payload.extend_from_slice(&((size - 8) as u32).to_le_bytes());
        // Varying content so zstd has real work to do.
        payload.extend((0..size - 8).map(|k| (i.wrapping_mul(2654435761).wrapping_add(k as u64) % 251) as u8));
        let t = 1_700_000_000_000_000_000 + i * 1000;
        while !recorder.record(topic, payload.clone(), t, t) {
            retries += 1;
            std::thread::sleep(Duration::from_micros(50));
        }
    }
    let stats = recorder.finish()?;
    let elapsed = started.elapsed().as_secs_f64();
    let on_disk: u64 = std::fs::read_dir(&dir)?.filter_map(|e| e.ok()?.metadata().ok()).map(|m| m.len()).sum();
    println!(
        "{} messages of {size} B in {elapsed:.2} s: {:.0} msgs/s, {:.1} MB/s payload; {:.1} MB on disk; \
         {retries} full-queue retries; dropped (counted) {}",
        stats.written,
        stats.written as f64 / elapsed,
        stats.bytes as f64 / elapsed / 1e6,
        on_disk as f64 / 1e6,
        stats.dropped
    );
    Ok(())
}
