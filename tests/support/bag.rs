//! Shared helpers of the bag tests: a tiny hand-written message type and the independent Python peers.

use std::path::{Path, PathBuf};
use std::process::Command;

use sweetspot::bag::{RecordedQos, TopicInfo};

/// `std_msgs/msg/String` as rosbag2 stores its definition.
pub const STRING_SCHEMA: &str = "string data\n";

/// The RIHS01 type hash of `std_msgs/msg/String` that rosidl generates (tests/type_hashes.rs says where it is
/// published).
pub const STRING_TYPE_HASH: &str = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18";

/// A topic of type std_msgs/msg/String.
pub fn string_topic(name: &str, qos: RecordedQos) -> TopicInfo {
    TopicInfo {
        name: name.to_string(),
        type_name: "std_msgs/msg/String".to_string(),
        schema_text: STRING_SCHEMA.to_string(),
        type_hash: STRING_TYPE_HASH.to_string(),
        qos,
    }
}

/// Reliable, volatile, depth 10.
pub const RELIABLE: RecordedQos = RecordedQos { reliable: true, transient_local: false, depth: 10 };
/// Reliable, transient-local, depth 1 (latched params).
pub const LATCHED: RecordedQos = RecordedQos { reliable: true, transient_local: true, depth: 1 };
/// Best effort, volatile, depth 5.
pub const BEST_EFFORT: RecordedQos = RecordedQos { reliable: false, transient_local: false, depth: 5 };

/// CDR (little endian, with the 4-byte encapsulation header) of a std_msgs/String.
pub fn cdr_string(text: &str) -> Vec<u8> {
    let mut out = vec![0x00, 0x01, 0x00, 0x00];
    out.extend_from_slice(&((text.len() + 1) as u32).to_le_bytes());
    out.extend_from_slice(text.as_bytes());
    out.push(0);
    while out.len() % 4 != 0 {
        out.push(0);
    }
    out
}

pub use super::python;

/// Runs tests/python/check_bag.py on a bag directory and returns its JSON verdict (panics on failure).
pub fn python_check_bag(dir: &Path) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/python/check_bag.py");
    let out = Command::new(python()).arg(&script).arg(dir).output().expect("run check_bag.py");
    assert!(
        out.status.success(),
        "check_bag.py failed on {}:\n{}",
        dir.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("check_bag.py prints JSON")
}

/// The `sweetspot` binary built for these tests.
pub fn sweetspot_bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_sweetspot"))
}

/// `sweetspot bag play BAG --foxglove 0 --no-dds -r RATE` started (its stderr read until it names the port,
/// then drained): the process and the `ws://127.0.0.1:PORT` it serves.
pub fn play_to_foxglove(bag: &Path, rate: f64) -> (std::process::Child, String) {
    use std::io::{BufRead, BufReader};
    let mut player = Command::new(sweetspot_bin())
        .args(["bag", "play"])
        .arg(bag)
        .args(["--foxglove", "0", "--no-dds", "-r", &rate.to_string()])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("starting sweetspot bag play");
    let mut stderr = BufReader::new(player.stderr.take().expect("piped stderr"));
    let mut line = String::new();
    let url = loop {
        line.clear();
        assert!(stderr.read_line(&mut line).unwrap_or(0) > 0, "bag play exited before serving");
        if let Some(rest) = line.strip_prefix("Foxglove WebSocket server on ") {
            break rest.split(':').take(3).collect::<Vec<_>>().join(":");
        }
    };
    std::thread::spawn(move || for _ in stderr.lines() {});
    (player, url)
}

/// One top-level record of an MCAP file (chunks not opened): its opcode, the offset where it ends, and for a
/// Message record its (log time, channel id, payload).
pub struct TopLevelRecord {
    pub opcode: u8,
    pub end: u64,
    pub message: Option<(u64, u16, Vec<u8>)>,
}

/// The top-level records of a complete MCAP file, in order.
pub fn top_level_records(bytes: &[u8]) -> Vec<TopLevelRecord> {
    use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};
    let mut reader = LinearReader::new_with_options(LinearReaderOptions::default().with_emit_chunks(true));
    let (mut offset, mut end) = (0usize, 8u64);
    let mut records = Vec::new();
    while let Some(event) = reader.next_event() {
        match event.unwrap() {
            LinearReadEvent::ReadRequest(need) => {
                let n = need.min(bytes.len() - offset);
                reader.insert(n).copy_from_slice(&bytes[offset..offset + n]);
                reader.notify_read(n);
                offset += n;
            }
            LinearReadEvent::Record { data, opcode } => {
                end += 9 + data.len() as u64;
                let message = match mcap::parse_record(opcode, data).unwrap() {
                    mcap::records::Record::Message { header, data } => {
                        Some((header.log_time, header.channel_id, data.to_vec()))
                    }
                    _ => None,
                };
                records.push(TopLevelRecord { opcode, end, message });
            }
        }
    }
    records
}
