//! The recorder's CPU cost per message, alone (no DDS, so no network namespace needed), on the node's
//! per-swing mix: a Swing (132 B), its ExitVelocity (~228 B) and its ModalEnergies (~524 B), varied payloads.
//! `cargo run --release --example recorder_cpu -- [SWINGS] [WORK_DIR] [STORAGES]`
//! (defaults 200,000 swings, `bench-work`, `zstd,fastwrite`). STORAGES is a comma list of what
//! `recorder_vs_dd` takes (a rosbag2 preset such as `fastwrite` or `zstd_fast`, or a chunk compression such
//! as `zstd`, `zstd:3`, `lz4`, `none`), plus `baseline`: the same loop over the payloads, recording nothing
//! (subtract it from instruction counts).
//!
//! Messages go through `bag::Recorder::record_bytes` from this one thread, as the node records them (queue of
//! 65,536; a full queue is retried after a short sleep and counted). The figures are the whole process's CPU
//! time (getrusage user + sys: the writer thread frames, compresses and writes) and the calling thread's CPU
//! time, per message, and the cores that costs at the node's highest sustained rate with recording (120,000
//! messages/s). Each file is read back with the `mcap` crate, chunk, data-section and summary CRCs checked,
//! and every message compared with what was written. Wall time is printed too but is only meaningful on an
//! idle machine. Instructions, repeatable under load, come from cachegrind on a smaller run:
//! `valgrind --tool=cachegrind --cache-sim=no target/release/examples/recorder_cpu 20000 DIR STORAGE`,
//! minus the same for `baseline`, divided by the messages.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, ensure, Context as _};
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
use sweetspot::bag::{Recorder, RecorderConfig, StorageOptions, TopicInfo};
use sweetspot::bench::{bench_streams, storage_spec, BenchMessage, BENCH_PAYLOADS};

/// The three topics of the node's per-swing mix with `count` payloads each, built as `sweetspot bench` builds
/// them.
fn streams(count: usize) -> anyhow::Result<Vec<(TopicInfo, Vec<Vec<u8>>)>> {
    Ok(bench_streams(BenchMessage::PerSwing, count as u64))
}

const T0: u64 = 1_763_700_000_000_000_000;

/// Process CPU time (all threads, user + sys) and the calling thread's CPU time, s.
fn cpu_times() -> (f64, f64) {
    // SAFETY: getrusage and clock_gettime only write into the structs passed.
    unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_SELF, &mut usage);
        let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        let mut ts: libc::timespec = std::mem::zeroed();
        libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts);
        (tv(usage.ru_utime) + tv(usage.ru_stime), ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
    }
}

/// The `i`-th message of the mix: (stream, payload).
fn message(streams: &[(TopicInfo, Vec<Vec<u8>>)], i: u64) -> (usize, &[u8]) {
    let stream = (i % 3) as usize;
    let payloads = &streams[stream].1;
    (stream, &payloads[((i / 3) % payloads.len() as u64) as usize])
}

/// Records `messages` messages through `bag::Recorder` as the node does (queue of 65,536); a full queue is
/// retried after a short sleep and counted. Returns (retries, files written).
fn run_recorder(
    dir: &Path,
    storage: StorageOptions,
    streams: &[(TopicInfo, Vec<Vec<u8>>)],
    messages: u64,
) -> anyhow::Result<(u64, Vec<PathBuf>)> {
    let mut config = RecorderConfig::new(dir);
    config.queue_capacity = 65_536;
    let recorder = Recorder::start_with(config, storage)?;
    let ids = streams.iter().map(|(t, _)| recorder.register_topic(t.clone())).collect::<Result<Vec<_>, _>>()?;
    let mut retries = 0;
    for i in 0..messages {
        let (stream, cdr) = message(streams, i);
        let stamp = T0 + i * 1000;
        while !recorder.record_bytes(ids[stream], cdr, stamp, stamp) {
            retries += 1;
            std::thread::sleep(Duration::from_micros(50));
        }
    }
    let stats = recorder.finish()?;
    // A refused record counts as dropped in the stats; here it was retried, so every message is written.
    ensure!(stats.written == messages, "recorder: {stats:?}");
    let files = sweetspot::bag::reader::bag_files(dir)?;
    Ok((retries, files))
}

/// Reads `file` back with every CRC checked; returns its messages by topic name, in file order.
fn read_back(file: &Path) -> anyhow::Result<Vec<(String, u64, Vec<u8>)>> {
    let bytes = std::fs::read(file)?;
    let mut reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_validate_chunk_crcs(true)
            .with_validate_data_section_crc(true)
            .with_validate_summary_section_crc(true),
    );
    let mut offset = 0;
    let mut channels: BTreeMap<u16, String> = BTreeMap::new();
    let mut messages = Vec::new();
    while let Some(event) = reader.next_event() {
        match event.with_context(|| format!("{}: invalid MCAP or bad CRC", file.display()))? {
            LinearReadEvent::ReadRequest(need) => {
                let n = need.min(bytes.len() - offset);
                reader.insert(n).copy_from_slice(&bytes[offset..offset + n]);
                reader.notify_read(n);
                offset += n;
            }
            LinearReadEvent::Record { data, opcode } => match mcap::parse_record(opcode, data)? {
                mcap::records::Record::Channel(c) => {
                    channels.insert(c.id, c.topic.to_string());
                }
                mcap::records::Record::Message { header, data } => {
                    let topic = channels.get(&header.channel_id).cloned().unwrap_or_default();
                    messages.push((topic, header.log_time, data.to_vec()));
                }
                _ => {}
            },
        }
    }
    ensure!(offset == bytes.len(), "{}: reader stopped at {offset} of {}", file.display(), bytes.len());
    if let Some(summary) = mcap::Summary::read(&bytes)? {
        let counted = summary.stats.map(|s| s.message_count).unwrap_or(messages.len() as u64);
        ensure!(counted == messages.len() as u64, "{}: statistics count {counted}", file.display());
    }
    Ok(messages)
}

/// Every message of the run present once, in order, with its payload.
fn verify(files: &[PathBuf], streams: &[(TopicInfo, Vec<Vec<u8>>)], messages: u64) -> anyhow::Result<u64> {
    let mut read = Vec::new();
    for file in files {
        read.extend(read_back(file)?);
    }
    ensure!(read.len() as u64 == messages, "{} messages read back, {messages} written", read.len());
    read.sort_by_key(|(_, stamp, _)| *stamp);
    for (i, (topic, stamp, data)) in read.iter().enumerate() {
        let (stream, cdr) = message(streams, i as u64);
        if *stamp != T0 + i as u64 * 1000 || *topic != streams[stream].0.name || data.as_slice() != cdr {
            bail!("message {i} differs on reading back");
        }
    }
    Ok(files.iter().map(|f| std::fs::metadata(f).map(|m| m.len()).unwrap_or(0)).sum())
}

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let swings: u64 = args.next().map(|a| a.parse()).transpose()?.unwrap_or(200_000);
    let work = PathBuf::from(args.next().unwrap_or_else(|| "bench-work".into()));
    let storages = args.next().unwrap_or_else(|| "zstd,fastwrite".into());
    let messages = swings * 3;
    let streams = streams((swings as usize).clamp(1, BENCH_PAYLOADS as usize))?;
    let payload_bytes: u64 = (0..messages).map(|i| message(&streams, i).1.len() as u64).sum();
    println!(
        "{swings} swings = {messages} messages, {:.1} MB of CDR ({:.0} B per swing); load average {}",
        payload_bytes as f64 / 1e6,
        payload_bytes as f64 / swings.max(1) as f64,
        std::fs::read_to_string("/proc/loadavg").unwrap_or_default().trim()
    );
    std::fs::create_dir_all(&work)?;
    println!(
        "| storage | process CPU ns/msg | caller CPU ns/msg | wall ns/msg | cores at 120k msg/s | file MB | retries |"
    );
    println!("|---|---|---|---|---|---|---|");
    for name in storages.split(',') {
        let target = work.join(format!("recorder_cpu_{}_{}", std::process::id(), name.replace(':', "_")));
        let _ = std::fs::remove_dir_all(&target);
        let storage: Option<StorageOptions> =
            if name == "baseline" { None } else { Some(storage_spec(name).with_context(|| name.to_string())?.1) };
        let (process0, thread0) = cpu_times();
        let start = Instant::now();
        let (retries, files) = match storage {
            Some(storage) => run_recorder(&target, storage, &streams, messages)?,
            None => {
                let mut sum = 0u64;
                for i in 0..messages {
                    let (stream, cdr) = message(&streams, i);
                    sum = sum.wrapping_add(std::hint::black_box(cdr).len() as u64 + stream as u64);
                }
                std::hint::black_box(sum);
                (0, Vec::new())
            }
        };
        let wall = start.elapsed().as_secs_f64();
        let (process1, thread1) = cpu_times();
        let file_bytes = if files.is_empty() { 0 } else { verify(&files, &streams, messages)? };
        let _ = std::fs::remove_dir_all(&target);
        let per = |s: f64| s * 1e9 / messages.max(1) as f64;
        println!(
            "| {name} | {:.0} | {:.0} | {:.0} | {:.3} | {:.1} | {retries} |",
            per(process1 - process0),
            per(thread1 - thread0),
            per(wall),
            (process1 - process0) / messages.max(1) as f64 * 120_000.0,
            file_bytes as f64 / 1e6,
        );
    }
    Ok(())
}
