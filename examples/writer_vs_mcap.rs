//! The bag writer against `mcap::Writer`, alone (no DDS, so no network namespace needed), on the node's
//! per-swing mix: a Swing (132 B), its ExitVelocity (~228 B) and its ModalEnergies (~524 B), varied payloads.
//! `cargo run --release --example writer_vs_mcap -- [SWINGS] [WORK_DIR] [WRITERS]`
//! (defaults 200,000 swings, `bench-work`, all writers). WRITERS is a comma list of
//! - `ours-zstd`: `bag::Recorder` with the node's default storage (zstd level 1, 1 MiB chunks, compression pool);
//! - `ours-fastwrite`: `bag::Recorder` with rosbag2's `fastwrite` preset (unchunked);
//! - `mcap-zstd`: `mcap::Writer`, zstd level 1, 1 MiB chunks, compressing on the calling thread;
//! - `mcap-zstd-mt`: the same with the crate's default `compression_threads` (zstd's own workers);
//! - `mcap-unchunked`: `mcap::Writer` with `use_chunks(false)`, no compression;
//! - `baseline`: the same loop over the payloads, writing nothing (subtract it from instruction counts).
//!
//! Every writer is fed from this one thread; the figures are the whole process's CPU time (getrusage user +
//! sys: the recorder compresses and writes on its own threads) and the calling thread's CPU time, per
//! message. Each file is read back with the `mcap` crate, chunk, data-section and summary CRCs checked, and
//! every message compared with what was written. Wall time is printed too but is only meaningful on an
//! idle machine. Instructions, repeatable under load, come from cachegrind on a smaller run:
//! `valgrind --tool=cachegrind --cache-sim=no target/release/examples/writer_vs_mcap 20000 DIR WRITER`,
//! minus the same for `baseline`, divided by the messages.

use std::collections::BTreeMap;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, ensure, Context as _};
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
use sweetspot::bag::{Recorder, RecorderConfig, StorageOptions, StoragePreset, TopicInfo};
use sweetspot::bench::{bench_streams, BenchMessage, BENCH_PAYLOADS};

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
fn run_ours(
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

/// Records `messages` messages through one `mcap::Writer` into `file`.
fn run_mcap(
    file: &Path,
    options: mcap::WriteOptions,
    streams: &[(TopicInfo, Vec<Vec<u8>>)],
    messages: u64,
) -> anyhow::Result<()> {
    let out = BufWriter::new(std::fs::File::create(file).with_context(|| format!("creating {}", file.display()))?);
    let mut writer = options.profile("ros2").create(out)?;
    let mut channels = Vec::new();
    for (topic, _) in streams {
        let schema = writer.add_schema(&topic.type_name, "ros2msg", topic.schema_text.as_bytes())?;
        channels.push(writer.add_channel(schema, &topic.name, "cdr", &BTreeMap::new())?);
    }
    let mut sequences = [0u32; 3];
    for i in 0..messages {
        let (stream, cdr) = message(streams, i);
        let stamp = T0 + i * 1000;
        sequences[stream] += 1;
        let header = mcap::records::MessageHeader {
            channel_id: channels[stream],
            sequence: sequences[stream],
            log_time: stamp,
            publish_time: stamp,
        };
        writer.write_to_known_channel(&header, cdr)?;
    }
    writer.finish()?;
    let out = writer.into_inner();
    out.into_inner().map_err(|e| e.into_error())?.sync_all()?;
    Ok(())
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
    let writers =
        args.next().unwrap_or_else(|| "ours-zstd,ours-fastwrite,mcap-zstd,mcap-zstd-mt,mcap-unchunked".into());
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
        "| writer | process CPU ns/msg | caller CPU ns/msg | wall ns/msg | cores at 120k msg/s | file MB | retries |"
    );
    println!("|---|---|---|---|---|---|---|");
    for writer in writers.split(',') {
        let target = work.join(format!("writer_vs_mcap_{}_{writer}", std::process::id()));
        let _ = std::fs::remove_dir_all(&target);
        let mcap_zstd = || {
            mcap::WriteOptions::new()
                .compression(Some(mcap::Compression::Zstd))
                .compression_level(1)
                .chunk_size(Some(1024 * 1024))
        };
        let (process0, thread0) = cpu_times();
        let start = Instant::now();
        let (retries, files) = match writer {
            "ours-zstd" => run_ours(&target, StorageOptions::default(), &streams, messages)?,
            "ours-fastwrite" => run_ours(&target, StoragePreset::Fastwrite.storage_options(), &streams, messages)?,
            "mcap-zstd" | "mcap-zstd-mt" | "mcap-unchunked" => {
                std::fs::create_dir_all(&target)?;
                let options = match writer {
                    "mcap-zstd" => mcap_zstd().compression_threads(0),
                    "mcap-zstd-mt" => mcap_zstd(),
                    _ => mcap::WriteOptions::new().compression(None).use_chunks(false),
                };
                let file = target.join("bag.mcap");
                run_mcap(&file, options, &streams, messages)?;
                (0, vec![file])
            }
            "baseline" => {
                let mut sum = 0u64;
                for i in 0..messages {
                    let (stream, cdr) = message(&streams, i);
                    sum = sum.wrapping_add(std::hint::black_box(cdr).len() as u64 + stream as u64);
                }
                std::hint::black_box(sum);
                (0, Vec::new())
            }
            other => bail!("unknown writer {other:?}"),
        };
        let wall = start.elapsed().as_secs_f64();
        let (process1, thread1) = cpu_times();
        let file_bytes = if files.is_empty() { 0 } else { verify(&files, &streams, messages)? };
        let _ = std::fs::remove_dir_all(&target);
        let per = |s: f64| s * 1e9 / messages.max(1) as f64;
        println!(
            "| {writer} | {:.0} | {:.0} | {:.0} | {:.3} | {:.1} | {retries} |",
            per(process1 - process0),
            per(thread1 - thread0),
            per(wall),
            (process1 - process0) / messages.max(1) as f64 * 120_000.0,
            file_bytes as f64 / 1e6,
        );
    }
    Ok(())
}
