//! The MCAP files the recorder writes itself (batched messages, whole-chunk compression): every compression
//! is read by the `mcap` crate with every CRC checked, through its summary and message indexes, and by the
//! independent Python readers; batched messages from many threads all arrive, in order.

mod bag_support;

use std::collections::BTreeMap;
use std::sync::Arc;

use bag_support::*;
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
use sweetspot::bag::reader::{bag_files, read_bag, scan_file};
use sweetspot::bag::{ChunkCompression, Recorder, RecorderConfig, StorageOptions, TopicInfo};

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
        let storage = StorageOptions { compression, chunk_size: Some(4096), compression_threads };
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
