//! The MCAP files the recorder writes itself (batched messages, whole-chunk compression): every compression
//! is read by the `mcap` crate with every CRC checked, through its summary and message indexes, and by the
//! independent Python readers; batched messages from many threads all arrive, in order. rosbag2's storage
//! presets, unchunked `fastwrite` included, write what rosbag2 writes and read back everywhere.

mod support;

use std::collections::BTreeMap;
use std::sync::Arc;

use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
use support::bag::*;
use sweetspot::bag::reader::{bag_files, read_bag, scan_file};
use sweetspot::bag::{
    ChunkCompression, McapLayout, Recorder, RecorderConfig, StorageOptions, StoragePreset, TopicId, TopicInfo,
};

const T0: u64 = 1_763_700_000_000_000_000;

/// Every message record of a file, read linearly with chunk, data-section and summary CRCs validated.
fn read_validated(bytes: &[u8]) -> Vec<(u16, u32, u64, Vec<u8>)> {
    let mut reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_validate_chunk_crcs(true)
            .with_validate_data_section_crc(true)
            .with_validate_summary_section_crc(true),
    );
    let mut offset = 0;
    let mut messages = Vec::new();
    while let Some(event) = reader.next_event() {
        match event.expect("a valid MCAP file with correct CRCs") {
            LinearReadEvent::ReadRequest(need) => {
                let n = need.min(bytes.len() - offset);
                reader.insert(n).copy_from_slice(&bytes[offset..offset + n]);
                reader.notify_read(n);
                offset += n;
            }
            LinearReadEvent::Record { data, opcode } => {
                if let mcap::records::Record::Message { header, data } = mcap::parse_record(opcode, data).unwrap() {
                    messages.push((header.channel_id, header.sequence, header.log_time, data.to_vec()));
                }
            }
        }
    }
    assert_eq!(offset, bytes.len(), "the reader consumed the whole file");
    messages
}

fn int32_topic(name: &str) -> TopicInfo {
    TopicInfo {
        name: name.to_string(),
        type_name: "std_msgs/msg/Int32".to_string(),
        schema_text: "int32 data\n".to_string(),
        type_hash: String::new(),
        qos: RELIABLE,
    }
}

#[test]
fn every_chunk_compression_reads_back_with_crcs_summary_and_indexes() {
    // Threads: None = a pool per core, Some(0) = on the writer thread, Some(3) = more workers than cores.
    for (compression, compression_threads) in
        [("zstd", None), ("zstd:9", Some(0)), ("zstd:-5", Some(3)), ("lz4", None), ("none", None)]
    {
        let compression: ChunkCompression = compression.parse().unwrap();
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("compressed");
        // Small chunks, so the file holds many chunks (many in flight at once) and many chunk indexes.
        let storage =
            StorageOptions { compression, chunk_size: Some(4096), compression_threads, layout: McapLayout::Chunked };
        let recorder = Recorder::start_with(RecorderConfig::new(&dir), storage).unwrap();
        let a = recorder.register_topic(string_topic("/rig/a", RELIABLE)).unwrap();
        let b = recorder.register_topic(string_topic("/rig/b", BEST_EFFORT)).unwrap();
        let n = recorder.register_topic(int32_topic("/rig/n")).unwrap();
        let mut expected = Vec::new();
        for i in 0..3000u64 {
            // Log times go backwards now and then: the chunk bounds and file duration must still hold.
            let t = T0 + i * 1_000_000 - if i % 7 == 0 { 500_000_000 } else { 0 };
            let (topic, cdr) = match i % 3 {
                0 => (a, cdr_string(&format!("a {i}"))),
                1 => (b, cdr_string(&format!("b {i} {}", "x".repeat((i % 50) as usize)))),
                _ => (n, [0u8, 1, 0, 0].into_iter().chain((i as i32).to_le_bytes()).collect()),
            };
            assert!(recorder.record(topic, cdr.clone(), t, t + 1));
            expected.push((topic, t, cdr));
        }
        let stats = recorder.finish().unwrap();
        assert_eq!((stats.written, stats.dropped), (3000, 0), "{compression}");

        let files = bag_files(&dir).unwrap();
        assert_eq!(files.len(), 1);
        let bytes = std::fs::read(&files[0]).unwrap();

        // Linear read, CRCs checked: every message, in order, with per-channel sequences from 1.
        let messages = read_validated(&bytes);
        assert_eq!(messages.len(), 3000, "{compression}");
        let mut sequences: BTreeMap<u16, u32> = BTreeMap::new();
        for (m, (topic, t, cdr)) in messages.iter().zip(&expected) {
            assert_eq!(m.0, topic.0 + 1, "channel id of topic {topic:?}");
            let seq = sequences.entry(m.0).or_insert(0);
            *seq += 1;
            assert_eq!(m.1, *seq, "sequence");
            assert_eq!((m.2, &m.3), (*t, cdr));
        }

        // Summary: statistics, schemas (String shared by two channels), channels, chunk and metadata indexes.
        let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary section");
        let stats = summary.stats.as_ref().unwrap();
        assert_eq!(stats.message_count, 3000);
        assert_eq!((stats.schema_count, stats.channel_count, stats.metadata_count), (2, 3, 1));
        assert_eq!(stats.channel_message_counts, BTreeMap::from([(1, 1000), (2, 1000), (3, 1000)]));
        assert_eq!(stats.message_start_time, expected.iter().map(|e| e.1).min().unwrap());
        assert_eq!(stats.message_end_time, expected.iter().map(|e| e.1).max().unwrap());
        assert_eq!(summary.schemas.len(), 2);
        assert_eq!(summary.channels.len(), 3);
        assert_eq!(summary.channels[&3].schema.as_ref().unwrap().name, "std_msgs/msg/Int32");
        assert_eq!(summary.metadata_indexes.len(), 1);
        assert_eq!(summary.metadata_indexes[0].name, "rosbag2");
        assert!(mcap::read::metadata(&bytes, &summary.metadata_indexes[0]).is_ok());
        assert_eq!(stats.chunk_count as usize, summary.chunk_indexes.len());
        assert!(summary.chunk_indexes.len() > 5, "{} chunks", summary.chunk_indexes.len());
        let expected_name = match compression {
            ChunkCompression::Zstd { .. } => "zstd",
            ChunkCompression::Lz4 => "lz4",
            ChunkCompression::None => "",
        };

        // Every message again through the chunk indexes and message indexes (random access).
        let mut by_index = Vec::new();
        for chunk in &summary.chunk_indexes {
            assert_eq!(chunk.compression, expected_name);
            let streamed: Vec<_> = summary.stream_chunk(&bytes, chunk).unwrap().map(|m| m.unwrap()).collect();
            assert!(streamed.iter().all(|m| (chunk.message_start_time..=chunk.message_end_time).contains(&m.log_time)));
            if chunk.message_index_offsets.is_empty() {
                // The chunk of Schema and Channel records holds no message, so it has no message index (which
                // the crate refuses to read).
                assert!(streamed.is_empty(), "{compression}");
                continue;
            }
            let indexes = summary.read_message_indexes(&bytes, chunk).unwrap();
            assert_eq!(indexes.values().map(Vec::len).sum::<usize>(), streamed.len());
            for (channel, entries) in indexes {
                for entry in entries {
                    let m = summary.seek_message(&bytes, chunk, &entry).unwrap();
                    assert_eq!((m.channel.id, m.log_time), (channel.id, entry.log_time));
                    by_index.push((m.channel.id, m.sequence, m.log_time, m.data.to_vec()));
                }
            }
        }
        by_index.sort();
        let mut linear = messages.clone();
        linear.sort();
        assert_eq!(by_index, linear, "{compression}: indexes reach every message exactly once");

        // The project's reader and the independent Python readers.
        let scan = scan_file(&files[0], |_| {}).unwrap();
        assert!(scan.complete);
        let compressions: Vec<String> = if expected_name.is_empty() { vec![] } else { vec![expected_name.into()] };
        assert_eq!(scan.compressions, compressions);
        let verdict = python_check_bag(&dir);
        for reader in ["mcap", "rosbags"] {
            let t = &verdict[reader]["topics"];
            assert_eq!(t["/rig/a"]["count"], 1000, "{compression} {reader}");
            assert_eq!(t["/rig/b"]["count"], 1000, "{compression} {reader}");
            assert_eq!(t["/rig/n"]["count"], 1000, "{compression} {reader}");
            assert_eq!(t["/rig/a"]["first"]["data"], "a 0", "{compression} {reader}");
            assert_eq!(t["/rig/a"]["last"]["data"], "a 2997", "{compression} {reader}");
        }
    }
}

#[test]
fn batched_records_from_many_threads_all_arrive_in_order_after_finish() {
    const THREADS: u64 = 4;
    const PER_THREAD: u64 = 30_000;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("threads");
    let mut config = RecorderConfig::new(&dir);
    // Room for everything, so that no record is refused and every one must come back.
    config.queue_capacity = (THREADS * PER_THREAD) as usize;
    let recorder = Arc::new(Recorder::start(config).unwrap());
    let topic = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    let threads: Vec<_> = (0..THREADS)
        .map(|k| {
            let recorder = recorder.clone();
            std::thread::spawn(move || {
                for i in 0..PER_THREAD {
                    let t = T0 + i;
                    assert!(recorder.record_bytes(topic, &cdr_string(&format!("{k} {i}")), t, t));
                }
            })
        })
        .collect();
    for t in threads {
        t.join().unwrap();
    }
    let recorder = Arc::try_unwrap(recorder).ok().expect("threads are done");
    let stats = recorder.finish().unwrap();
    assert_eq!((stats.written, stats.dropped), (THREADS * PER_THREAD, 0));

    let mut next = vec![0u64; THREADS as usize];
    let mut last_sequence = 0;
    read_bag(&dir, |m| {
        let text = std::str::from_utf8(&m.data[8..]).unwrap().trim_end_matches('\0');
        let (k, i) = text.split_once(' ').unwrap();
        let (k, i): (usize, u64) = (k.parse().unwrap(), i.parse().unwrap());
        assert_eq!(i, next[k], "thread {k}'s messages arrive complete and in order");
        next[k] += 1;
        // Sequence numbers follow the order in the file: batches are written in the order they were filled.
        assert_eq!(m.sequence, last_sequence + 1);
        last_sequence = m.sequence;
    })
    .unwrap();
    assert!(next.iter().all(|&n| n == PER_THREAD), "{next:?}");
    assert_eq!(python_check_bag(&dir)["mcap"]["topics"]["/rig/swing"]["count"], THREADS * PER_THREAD);
}

#[test]
fn compression_names_parse_and_bad_ones_are_refused() {
    assert_eq!("zstd".parse::<ChunkCompression>().unwrap(), ChunkCompression::default());
    assert_eq!("zstd:19".parse::<ChunkCompression>().unwrap(), ChunkCompression::Zstd { level: 19 });
    assert_eq!("none".parse::<ChunkCompression>().unwrap(), ChunkCompression::None);
    assert_eq!("lz4".parse::<ChunkCompression>().unwrap(), ChunkCompression::Lz4);
    assert_eq!("zstd:-3".parse::<ChunkCompression>().unwrap(), ChunkCompression::Zstd { level: -3 });
    for bad in ["", "gzip", "zstd:0", "zstd:23", "zstd:-8", "zstd:x", "none:1"] {
        let err = bad.parse::<ChunkCompression>().unwrap_err().to_string();
        assert!(err.contains("zstd, zstd:LEVEL"), "{bad}: {err}");
    }
    let tmp = tempfile::tempdir().unwrap();
    let zero = StorageOptions { chunk_size: Some(0), ..StorageOptions::default() };
    assert!(Recorder::start_with(RecorderConfig::new(tmp.path().join("zero")), zero).is_err());
}

/// Reads every message of a bag with PyPI `mcap` (`make_reader(...).iter_messages()`, `get_summary()`) and
/// with `rosbags.rosbag2.Reader` on the directory; payloads as hex. A rosbags exception is reported, not
/// raised, so that the test can assert on it.
const PYTHON_READ_ALL: &str = r#"
import json, sys
from pathlib import Path
from mcap.reader import make_reader
bag = Path(sys.argv[1])
out = {"mcap": [], "summary": {}}
for path in sorted(bag.glob("*.mcap"), key=lambda p: int(p.stem.rsplit("_", 1)[1])):
    with open(path, "rb") as f:
        reader = make_reader(f)
        s = reader.get_summary()
        out["summary"][path.name] = {
            "chunk_indexes": len(s.chunk_indexes), "message_count": s.statistics.message_count,
            "chunk_count": s.statistics.chunk_count, "schemas": len(s.schemas), "channels": len(s.channels),
            "channel_message_counts": {str(k): v for k, v in s.statistics.channel_message_counts.items()},
            "start": s.statistics.message_start_time, "end": s.statistics.message_end_time,
            "compressions": sorted({c.compression for c in s.chunk_indexes}),
        }
        for schema, channel, message in reader.iter_messages():
            out["mcap"].append([channel.topic, message.sequence, message.log_time, message.data.hex()])
try:
    from rosbags.rosbag2 import Reader
    with Reader(bag) as r:
        out["rosbags"] = [[c.topic, t, bytes(raw).hex()] for c, t, raw in r.messages()]
except Exception as e:
    out["rosbags_error"] = f"{type(e).__name__}: {e}"
json.dump(out, sys.stdout)
"#;

fn python_read_all(dir: &std::path::Path) -> serde_json::Value {
    let out = std::process::Command::new(python()).arg("-c").arg(PYTHON_READ_ALL).arg(dir).output().unwrap();
    assert!(out.status.success(), "python readers failed: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Opcodes of the top-level records of a file, in order (chunks not opened).
fn top_level_opcodes(bytes: &[u8]) -> Vec<u8> {
    top_level_records(bytes).into_iter().map(|r| r.opcode).collect()
}

/// Records `count` messages round-robin on three topics (two sharing a schema), log times `times(i)`;
/// returns (topic, log time, CDR) of each.
fn record_three_topics(
    dir: &std::path::Path,
    storage: StorageOptions,
    count: u64,
    times: impl Fn(u64) -> u64,
) -> Vec<(TopicId, u64, Vec<u8>)> {
    let recorder = Recorder::start_with(RecorderConfig::new(dir), storage).unwrap();
    let a = recorder.register_topic(string_topic("/rig/a", RELIABLE)).unwrap();
    let b = recorder.register_topic(string_topic("/rig/b", BEST_EFFORT)).unwrap();
    let n = recorder.register_topic(int32_topic("/rig/n")).unwrap();
    let mut expected = Vec::new();
    for i in 0..count {
        let t = times(i);
        let (topic, cdr) = match i % 3 {
            0 => (a, cdr_string(&format!("a {i}"))),
            1 => (b, cdr_string(&format!("b {i} {}", "x".repeat((i % 50) as usize)))),
            _ => (n, [0u8, 1, 0, 0].into_iter().chain((i as i32).to_le_bytes()).collect()),
        };
        assert!(recorder.record(topic, cdr.clone(), t, t + 1));
        expected.push((topic, t, cdr));
    }
    let stats = recorder.finish().unwrap();
    assert_eq!((stats.written, stats.dropped), (count, 0));
    expected
}

#[test]
fn fastwrite_writes_unchunked_mcap_that_every_reader_reads_byte_for_byte() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("fastwrite");
    let storage = StorageOptions::preset("fastwrite").unwrap();
    assert_eq!((storage.layout, storage.compression), (McapLayout::Unchunked, ChunkCompression::None));
    let expected = record_three_topics(&dir, storage, 3000, |i| T0 + i * 1_000_000);
    let files = bag_files(&dir).unwrap();
    assert_eq!(files.len(), 1);
    let bytes = std::fs::read(&files[0]).unwrap();

    // The layout: messages are top-level records; no chunk, message index or chunk index anywhere;
    // schemas and channels come before the first message.
    let opcodes = top_level_opcodes(&bytes);
    use mcap::records::op;
    for absent in [op::CHUNK, op::MESSAGE_INDEX, op::CHUNK_INDEX] {
        assert!(!opcodes.contains(&absent), "opcode {absent:#x} in an unchunked file");
    }
    assert_eq!(opcodes.iter().filter(|&&o| o == op::MESSAGE).count(), 3000);
    let first_message = opcodes.iter().position(|&o| o == op::MESSAGE).unwrap();
    assert_eq!(opcodes[..first_message].iter().filter(|&&o| o == op::CHANNEL).count(), 3);
    assert_eq!(opcodes[..first_message].iter().filter(|&&o| o == op::SCHEMA).count(), 2);

    // The mcap crate: linear read with data-section and summary CRCs checked, then MessageStream.
    let messages = read_validated(&bytes);
    assert_eq!(messages.len(), 3000);
    let mut sequences: BTreeMap<u16, u32> = BTreeMap::new();
    for (m, (topic, t, cdr)) in messages.iter().zip(&expected) {
        assert_eq!(m.0, topic.0 + 1);
        let seq = sequences.entry(m.0).or_insert(0);
        *seq += 1;
        assert_eq!((m.1, m.2, &m.3), (*seq, *t, cdr));
    }
    let streamed: Vec<_> = mcap::MessageStream::new(&bytes).unwrap().map(|m| m.unwrap()).collect();
    assert_eq!(streamed.len(), 3000);
    for (m, (topic, t, cdr)) in streamed.iter().zip(&expected) {
        assert_eq!((m.channel.id, m.log_time, m.publish_time, &m.data[..]), (topic.0 + 1, *t, t + 1, &cdr[..]));
    }

    // Summary: schemas, channels, statistics, metadata index; no chunk index.
    let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary section");
    let stats = summary.stats.as_ref().unwrap();
    assert_eq!(stats.message_count, 3000);
    assert_eq!((stats.schema_count, stats.channel_count, stats.metadata_count, stats.chunk_count), (2, 3, 1, 0));
    assert_eq!(stats.channel_message_counts, BTreeMap::from([(1, 1000), (2, 1000), (3, 1000)]));
    assert_eq!((stats.message_start_time, stats.message_end_time), (T0, T0 + 2999 * 1_000_000));
    assert!(summary.chunk_indexes.is_empty());
    assert_eq!((summary.schemas.len(), summary.channels.len()), (2, 3));
    assert_eq!(summary.metadata_indexes[0].name, "rosbag2");
    assert!(mcap::read::metadata(&bytes, &summary.metadata_indexes[0]).is_ok());

    // The project's reader.
    let mut ours = Vec::new();
    let scan = scan_file(&files[0], |m| ours.push((m.channel_id, m.log_time_ns, m.data.to_vec()))).unwrap();
    assert!(scan.complete);
    assert_eq!((scan.chunks, scan.unchunked_messages, scan.layout()), (0, 3000, Some(McapLayout::Unchunked)));
    assert!(scan.compressions.is_empty());
    let wanted: Vec<_> = expected.iter().map(|(topic, t, cdr)| (topic.0 + 1, *t, cdr.clone())).collect();
    assert_eq!(ours, wanted);
    let info = sweetspot::bag::info::bag_info(&dir).unwrap();
    assert_eq!(info.layout, vec![McapLayout::Unchunked]);
    assert_eq!(info.files[0].layout, Some(McapLayout::Unchunked));
    assert!(info.to_string().contains("Chunks:            none (unchunked"), "{info}");
    let json = serde_json::to_value(&info).unwrap();
    assert_eq!(json["layout"], serde_json::json!(["unchunked"]));
    assert_eq!(json["files"][0]["layout"], "unchunked");

    // Python mcap (iter_messages, get_summary) and rosbags, byte for byte.
    let names = ["/rig/a", "/rig/b", "/rig/n"];
    let python = python_read_all(&dir);
    let summary = &python["summary"]["fastwrite_0.mcap"];
    assert_eq!(summary["chunk_indexes"], 0);
    assert_eq!(summary["chunk_count"], 0);
    assert_eq!(summary["message_count"], 3000);
    assert_eq!(summary["channel_message_counts"], serde_json::json!({"1": 1000, "2": 1000, "3": 1000}));
    let mcap_messages = python["mcap"].as_array().unwrap();
    assert_eq!(mcap_messages.len(), 3000);
    for (m, (topic, t, cdr)) in mcap_messages.iter().zip(&expected) {
        assert_eq!(m[0], names[topic.0 as usize]);
        assert_eq!((m[2].as_u64(), m[3].as_str()), (Some(*t), Some(hex(cdr).as_str())));
    }
    assert!(python.get("rosbags_error").is_none(), "rosbags: {}", python["rosbags_error"]);
    let rosbags_messages = python["rosbags"].as_array().unwrap();
    assert_eq!(rosbags_messages.len(), 3000);
    for (m, (topic, t, cdr)) in rosbags_messages.iter().zip(&expected) {
        assert_eq!(m[0], names[topic.0 as usize]);
        assert_eq!((m[1].as_u64(), m[2].as_str()), (Some(*t), Some(hex(cdr).as_str())));
    }
    // And the full independent check (decoding from the embedded schemas, QoS, metadata.yaml counts).
    let verdict = python_check_bag(&dir);
    for reader in ["mcap", "rosbags"] {
        assert_eq!(verdict[reader]["topics"]["/rig/a"]["count"], 1000, "{reader}");
        assert_eq!(verdict[reader]["topics"]["/rig/a"]["last"]["data"], "a 2997", "{reader}");
    }
}

#[test]
fn rosbags_refuses_unchunked_files_whose_log_times_go_backwards_and_the_others_read_them() {
    // rosbags reads an MCAP without chunk indexes by a linear scan and insists on time order there
    // (rosbags/rosbag2/storage_mcap.py, McapReader.messages); the node's log times come from several
    // threads, so this is the limitation the docs name.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("backwards");
    let storage = StorageOptions::preset("fastwrite").unwrap();
    let expected =
        record_three_topics(&dir, storage, 300, |i| T0 + i * 1_000_000 - if i == 150 { 2_000_000 } else { 0 });
    let python = python_read_all(&dir);
    assert_eq!(
        python["rosbags_error"],
        "ReaderError: Unindexed MCAP messages are not in timestamp order. Use an indexed file."
    );
    assert_eq!(python["mcap"].as_array().unwrap().len(), 300, "Python mcap reads it in file order");
    let mut ours = 0;
    read_bag(&dir, |_| ours += 1).unwrap();
    assert_eq!(ours, expected.len());
    let bytes = std::fs::read(&bag_files(&dir).unwrap()[0]).unwrap();
    let streamed = mcap::MessageStream::new(&bytes).unwrap().collect::<Result<Vec<_>, _>>().unwrap().len();
    assert_eq!(streamed, 300);

    // The same messages in a chunked bag (rosbag2's `none`) are read by rosbags through its indexes.
    let chunked = tmp.path().join("chunked");
    record_three_topics(&chunked, StorageOptions::preset("none").unwrap(), 300, |i| {
        T0 + i * 1_000_000 - if i == 150 { 2_000_000 } else { 0 }
    });
    let python = python_read_all(&chunked);
    assert!(python.get("rosbags_error").is_none(), "{}", python["rosbags_error"]);
    assert_eq!(python["rosbags"].as_array().unwrap().len(), 300);
}

#[test]
fn every_rosbag2_preset_writes_what_rosbag2_writes_and_reads_back() {
    // (preset, chunk compression name in the file, zstd/lz4 level, chunk size)
    for (name, compression, chunk_size) in [
        ("none", ChunkCompression::None, Some(768 * 1024)),
        ("zstd_fast", ChunkCompression::Zstd { level: -5 }, Some(768 * 1024)),
        ("zstd_small", ChunkCompression::Zstd { level: 19 }, Some(4 * 1024 * 1024)),
        ("fastwrite", ChunkCompression::None, None),
    ] {
        let preset: StoragePreset = name.parse().unwrap();
        assert_eq!(preset.name(), name);
        let storage = StorageOptions::preset(name).unwrap();
        assert_eq!(storage, preset.storage_options());
        assert_eq!((storage.compression, storage.chunk_size), (compression, chunk_size), "{name}");
        let layout = if name == "fastwrite" { McapLayout::Unchunked } else { McapLayout::Chunked };
        assert_eq!(storage.layout, layout, "{name}");

        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join(name);
        let expected = record_three_topics(&dir, storage, 600, |i| T0 + i * 1_000_000);
        let bytes = std::fs::read(&bag_files(&dir).unwrap()[0]).unwrap();
        let messages = read_validated(&bytes);
        let wanted: Vec<_> = expected.iter().map(|(topic, t, cdr)| (topic.0 + 1, *t, cdr.clone())).collect();
        assert_eq!(messages.into_iter().map(|m| (m.0, m.2, m.3)).collect::<Vec<_>>(), wanted, "{name}");
        let python = python_read_all(&dir);
        let summary = &python["summary"][format!("{name}_0.mcap")];
        let file_compression = match compression {
            ChunkCompression::Zstd { .. } => vec!["zstd"],
            _ if layout == McapLayout::Chunked => vec![""],
            _ => vec![],
        };
        assert_eq!(summary["compressions"], serde_json::json!(file_compression), "{name}");
        assert_eq!(python["mcap"].as_array().unwrap().len(), 600, "{name}");
        assert_eq!(python["rosbags"].as_array().map(Vec::len), Some(600), "{name}: {}", python["rosbags_error"]);
    }
}

#[test]
fn preset_names_and_combinations_are_checked() {
    let err = StorageOptions::preset("fast").unwrap_err().to_string();
    assert_eq!(
        err,
        "unknown MCAP storage preset profile (valid options are 'none', 'fastwrite', 'zstd_fast', 'zstd_small'): \
         \"fast\""
    );
    assert!("".parse::<StoragePreset>().is_err());
    let fastwrite = StorageOptions::preset("fastwrite").unwrap();
    // An explicit compression overrides a chunked preset's, and cannot apply to unchunked files.
    let zstd_small = StorageOptions::preset("zstd_small").unwrap();
    let lz4 = zstd_small.with_compression(ChunkCompression::Lz4).unwrap();
    assert_eq!((lz4.compression, lz4.chunk_size), (ChunkCompression::Lz4, zstd_small.chunk_size));
    let err = fastwrite.with_compression(ChunkCompression::Zstd { level: 1 }).unwrap_err().to_string();
    assert!(err.contains("zstd:1 needs chunks") && err.contains("fastwrite"), "{err}");
    assert_eq!(fastwrite.with_compression(ChunkCompression::None).unwrap(), fastwrite);
    assert_eq!(StorageOptions::from_parameters("", "").unwrap(), StorageOptions::default());
    assert_eq!(StorageOptions::from_parameters("fastwrite", "none").unwrap(), fastwrite);
    assert!(StorageOptions::from_parameters("fastwrite", "lz4").is_err());
    assert!(StorageOptions::from_parameters("", "zstd:0").is_err());
    // The writer refuses the combination too when the options are put together by hand.
    let tmp = tempfile::tempdir().unwrap();
    let by_hand = StorageOptions { compression: ChunkCompression::Lz4, ..fastwrite };
    let err = Recorder::start_with(RecorderConfig::new(tmp.path().join("x")), by_hand).err().unwrap().to_string();
    assert!(err.contains("needs chunks"), "{err}");
    assert!(!tmp.path().join("x").exists(), "nothing is created for refused options");
}
