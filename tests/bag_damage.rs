//! The bag tools never hide a loss and never harm a file.
//!
//! Damage (a flipped bit, an 8-byte overwrite, every chunk corrupted, a chunk cut short or spliced out) makes
//! `bag info`, `bag export` and `bag replay` exit non-zero naming the file, the chunk (index and offset) and
//! the messages lost, where the truth comes from the `mcap` crate's own reading of the untouched file (its
//! summary's chunk indexes and message indexes); `--skip-damaged` goes on with the rest and still lists the
//! damage; `bag recover` writes a repaired copy beside the original, says what it dropped and leaves the
//! original byte for byte; the Python `mcap` reader agrees that the file is damaged.
//!
//! Hostile inputs (symlinks to /dev/zero and /dev/urandom, a FIFO, a directory, empty, garbage and text files,
//! decompression bombs) are refused with a clear message and a bounded maximum RSS of the tool's process
//! (`wait4`'s rusage of that one child). A bag several times larger than that bound is read by info, export
//! and replay within it.

mod support;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use support::bag::*;
use sweetspot::bag::{ChunkCompression, McapLayout, Recorder, RecorderConfig, StorageOptions, TopicInfo};
use sweetspot::msgs::encode_cdr;
use sweetspot::msgs::sweetspot_msgs::msg::Swing;

/// Max RSS a bag tool may reach on hostile input or while streaming, KiB. The reader holds a chunk or two
/// (1 MiB here) and the binary's own baseline (about 11 MiB in all, measured); the inputs below would need
/// hundreds of MiB to GiB if read whole.
const RSS_BOUND_KIB: i64 = 32 * 1024;

/// What a finished bag tool run left: exit status, stdout, stderr and its own max RSS (KiB).
struct Run {
    ok: bool,
    code: Option<i32>,
    stdout: String,
    stderr: String,
    max_rss_kib: i64,
}

impl Run {
    fn text(&self) -> String {
        format!("exit {:?}\n--- stdout\n{}\n--- stderr\n{}", self.code, self.stdout, self.stderr)
    }
}

/// Runs `sweetspot ARGS…` and measures its max RSS. A child's `ru_maxrss` counts what its parent had resident
/// when it forked, so the tool is started from a small Python process (the tests' Python) that reports
/// `RUSAGE_CHILDREN` for this one child; stdout and stderr go to files so a long output cannot block it.
fn sweetspot(args: &[&dyn AsRef<std::ffi::OsStr>]) -> Run {
    const WRAPPER: &str = r#"
import resource, subprocess, sys
with open(sys.argv[1], "wb") as out, open(sys.argv[2], "wb") as err:
    code = subprocess.run(sys.argv[3:], stdin=subprocess.DEVNULL, stdout=out, stderr=err).returncode
print(code, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
"#;
    let scratch = tempfile::tempdir().unwrap();
    let out_path = scratch.path().join("stdout");
    let err_path = scratch.path().join("stderr");
    let mut command = Command::new(python());
    command.arg("-c").arg(WRAPPER).arg(&out_path).arg(&err_path).arg(sweetspot_bin());
    for a in args {
        command.arg(a);
    }
    let wrapper = command.stdin(Stdio::null()).output().unwrap();
    let report = String::from_utf8_lossy(&wrapper.stdout).to_string();
    let mut fields = report.split_whitespace().map(|f| f.parse::<i64>().unwrap_or(i64::MIN));
    let (code, max_rss_kib) = (fields.next(), fields.next());
    assert!(wrapper.status.success() && max_rss_kib.is_some(), "{report}{}", String::from_utf8_lossy(&wrapper.stderr));
    let code = code.and_then(|c| i32::try_from(c).ok()).filter(|&c| c >= 0);
    Run {
        ok: code == Some(0),
        code,
        stdout: std::fs::read_to_string(&out_path).unwrap_or_default(),
        stderr: std::fs::read_to_string(&err_path).unwrap_or_default(),
        max_rss_kib: max_rss_kib.unwrap_or(i64::MAX),
    }
}

fn swing(i: u64) -> Swing {
    Swing {
        swing_id: i,
        bat_id: "r161".to_string(),
        // A ball no node knows: replay rejects these swings without integrating a collision (fast), which is
        // all the damage tests need of it.
        ball_id: "no-such-ball".to_string(),
        ball_speed: 40.0,
        bat_cm_speed: 25.0,
        bat_angular_speed: 45.0,
        impact_z: 0.7,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    }
}

/// Records `n` swings on `/swing` into the bag directory `dir` (zstd, 16 KiB chunks: several chunks).
fn record_swings(dir: &Path, n: u64) {
    let storage = StorageOptions { chunk_size: Some(16 * 1024), ..StorageOptions::default() };
    let recorder = Recorder::start_with(RecorderConfig::new(dir), storage).unwrap();
    let topic = recorder.register_topic(TopicInfo::of::<Swing>("/swing", RELIABLE)).unwrap();
    for i in 0..n {
        let t = 1_000_000_000 + i * 1_000_000;
        let cdr = encode_cdr(&swing(i)).unwrap();
        while !recorder.record(topic, cdr.clone(), t, t) {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
    }
    recorder.finish().unwrap();
}

/// A chunk as the `mcap` crate reads it from an intact file: offset, record length, messages.
#[derive(Debug, Clone, Copy)]
struct TrueChunk {
    offset: u64,
    length: u64,
    messages: u64,
}

fn true_chunks(bytes: &[u8]) -> Vec<TrueChunk> {
    let summary = mcap::Summary::read(bytes).unwrap().expect("an intact file has a summary");
    summary
        .chunk_indexes
        .iter()
        .map(|index| TrueChunk {
            offset: index.chunk_start_offset,
            length: index.chunk_length,
            // A chunk without message indexes (the Schema and Channel records' own chunk) holds no message; the
            // crate refuses to read an empty index.
            messages: if index.message_index_offsets.is_empty() {
                0
            } else {
                summary.read_message_indexes(bytes, index).unwrap().values().map(|v| v.len() as u64).sum()
            },
        })
        .collect()
}

/// A damaged copy of the intact bag `good`: `damage` edits the bytes of its only file.
fn damaged_copy(good: &Path, name: &str, damage: impl FnOnce(&mut Vec<u8>)) -> PathBuf {
    let dir = good.parent().unwrap().join(name);
    std::fs::create_dir(&dir).unwrap();
    let mut bytes = std::fs::read(good.join("good_0.mcap")).unwrap();
    damage(&mut bytes);
    std::fs::write(dir.join(format!("{name}_0.mcap")), &bytes).unwrap();
    // The copy's metadata.yaml lists the copy's file: a bag is what its metadata.yaml lists.
    let metadata = std::fs::read_to_string(good.join("metadata.yaml")).unwrap();
    std::fs::write(dir.join("metadata.yaml"), metadata.replace("good_0.mcap", &format!("{name}_0.mcap"))).unwrap();
    dir
}

/// Python `mcap` (validating CRCs) reading every message: Ok(count) or Err(its error).
fn python_mcap_reads(file: &Path) -> Result<u64, String> {
    let script = r#"
import sys
from mcap.reader import make_reader
n = 0
try:
    with open(sys.argv[1], "rb") as f:
        for _ in make_reader(f, validate_crcs=True).iter_messages():
            n += 1
    print("ok", n)
except Exception as e:
    print("error", type(e).__name__, e)
"#;
    let out = Command::new(python()).arg("-c").arg(script).arg(file).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout).trim().to_string();
    match text.strip_prefix("ok ") {
        Some(n) => Ok(n.parse().unwrap()),
        None => Err(format!("{text} {}", String::from_utf8_lossy(&out.stderr))),
    }
}

const SWINGS: u64 = 3000;

/// An intact bag of SWINGS swings in several chunks, and the truth about its chunks.
fn intact_bag(tmp: &Path) -> (PathBuf, Vec<TrueChunk>) {
    let good = tmp.join("good");
    record_swings(&good, SWINGS);
    let chunks = true_chunks(&std::fs::read(good.join("good_0.mcap")).unwrap());
    assert!(chunks.len() >= 4, "several chunks: {}", chunks.len());
    assert_eq!(chunks.iter().map(|c| c.messages).sum::<u64>(), SWINGS);
    (good, chunks)
}

fn info_json(dir: &Path) -> serde_json::Value {
    let run = sweetspot(&[&"bag", &"info", &"--json", &"--skip-damaged", &dir]);
    assert!(run.ok, "{}", run.text());
    serde_json::from_str(&run.stdout).unwrap()
}

/// Every tool refuses the damaged bag naming `needle` (file, chunk, loss), and goes on with --skip-damaged.
fn every_tool_reports(dir: &Path, needles: &[String], kept: u64) {
    let info = sweetspot(&[&"bag", &"info", &dir]);
    assert!(!info.ok, "bag info must fail on damage: {}", info.text());
    let export = sweetspot(&[&"bag", &"export", &"--csv", &dir]);
    assert!(!export.ok, "bag export must fail on damage: {}", export.text());
    assert!(export.stdout.is_empty(), "nothing exported from a damaged bag without --skip-damaged");
    let replay = sweetspot(&[&"bag", &"replay", &dir]);
    assert!(!replay.ok, "bag replay must fail on damage: {}", replay.text());
    for run in [&info, &export, &replay] {
        let all = run.stdout.clone() + &run.stderr;
        for needle in needles {
            assert!(all.contains(needle.as_str()), "{needle:?} not named:\n{}", run.text());
        }
        assert!(all.contains("--skip-damaged"), "the way on is named: {}", run.text());
    }

    let info = sweetspot(&[&"bag", &"info", &"--skip-damaged", &dir]);
    assert!(info.ok, "{}", info.text());
    assert!(info.stdout.contains(&format!("Messages:          {kept}\n")), "{}", info.text());
    assert!(info.stdout.contains("DAMAGED:"), "{}", info.text());
    let export = sweetspot(&[&"bag", &"export", &"--csv", &"--skip-damaged", &dir]);
    assert!(export.ok, "{}", export.text());
    assert_eq!(export.stdout.lines().count() as u64, kept + 1, "header + one row per intact swing");
    assert!(export.stderr.contains("skipped"), "{}", export.text());
    let replay = sweetspot(&[&"bag", &"replay", &"--skip-damaged", &dir]);
    assert!(replay.ok, "{}", replay.text());
    assert!(replay.stdout.contains(&format!("{kept} swings:")), "{}", replay.text());
    for run in [&export, &replay] {
        for needle in needles {
            assert!(
                run.stderr.contains(needle.as_str()),
                "{needle:?} still listed with --skip-damaged: {}",
                run.text()
            );
        }
    }
}

/// `bag recover` writes DIR.recovered beside DIR holding exactly `kept` messages, says what it dropped,
/// and leaves the original byte for byte.
fn recover_reports(dir: &Path, needles: &[String], kept: u64) {
    let file = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "mcap"))
        .unwrap();
    let before = std::fs::read(&file).unwrap();
    let metadata_before = std::fs::read(dir.join("metadata.yaml")).unwrap();
    let run = sweetspot(&[&"bag", &"recover", &dir]);
    assert!(run.ok, "{}", run.text());
    assert!(run.stdout.contains("dropped"), "{}", run.text());
    for needle in needles {
        assert!(run.stdout.contains(needle.as_str()), "{needle:?} not named by recover: {}", run.text());
    }
    assert!(!run.stdout.contains("left as is") && !run.stdout.contains("nothing to recover"), "{}", run.text());
    assert_eq!(std::fs::read(&file).unwrap(), before, "the original is untouched");
    assert_eq!(std::fs::read(dir.join("metadata.yaml")).unwrap(), metadata_before, "its metadata.yaml too");
    assert_eq!(std::fs::read_dir(dir).unwrap().count(), 2, "nothing added beside the original's files");
    let copy = dir.with_file_name(format!("{}.recovered", dir.file_name().unwrap().to_string_lossy()));
    let json = info_json(&copy);
    assert_eq!(json["messages"], kept, "{json}");
    assert_eq!(json["damaged"], false, "{json}");
    let metadata = std::fs::read_to_string(copy.join("metadata.yaml")).unwrap();
    assert!(metadata.contains(&format!("message_count: {kept}")), "{metadata}");
    assert!(metadata.contains("sweetspot/recovered_from"), "the copy says what it was recovered from: {metadata}");
}

#[test]
fn one_flipped_bit_in_a_chunk_is_named_by_every_tool_and_recover_drops_exactly_that_chunk() {
    let tmp = tempfile::tempdir().unwrap();
    let (good, chunks) = intact_bag(tmp.path());
    let intact = sweetspot(&[&"bag", &"info", &good]);
    assert!(intact.ok && intact.stdout.contains(&format!("Messages:          {SWINGS}")), "{}", intact.text());
    let victim = chunks[2];
    let dir = damaged_copy(&good, "bitflip", |b| b[(victim.offset + victim.length / 2) as usize] ^= 0x10);
    let file = dir.join("bitflip_0.mcap");
    let needles = vec![
        "bitflip_0.mcap".to_string(),
        format!("chunk 2 at offset {}", victim.offset),
        format!("{} messages lost", victim.messages),
    ];
    every_tool_reports(&dir, &needles, SWINGS - victim.messages);
    assert!(python_mcap_reads(&file).is_err(), "the independent reader finds the damage too");
    recover_reports(&dir, &needles, SWINGS - victim.messages);
}

/// The first chunk holding messages, by the `mcap` crate's reading of the intact file; every chunk before it
/// holds none (the writer's definitions chunk).
fn first_message_chunk(chunks: &[TrueChunk]) -> usize {
    let first = chunks.iter().position(|c| c.messages > 0).unwrap();
    assert!(first > 0, "the Schema and Channel records have a chunk of their own before the messages: {chunks:?}");
    first
}

#[test]
fn one_flipped_bit_in_the_first_message_chunk_loses_only_that_chunks_messages_even_without_a_summary() {
    let tmp = tempfile::tempdir().unwrap();
    let (good, chunks) = intact_bag(tmp.path());
    let first = first_message_chunk(&chunks);
    let victim = chunks[first];
    let flip = |b: &mut Vec<u8>| b[(victim.offset + victim.length / 2) as usize] ^= 0x04;

    // A finished file.
    let dir = damaged_copy(&good, "first", flip);
    let needles = vec![
        "first_0.mcap".to_string(),
        format!("chunk {first} at offset {}", victim.offset),
        format!("{} messages lost", victim.messages),
    ];
    every_tool_reports(&dir, &needles, SWINGS - victim.messages);
    assert!(python_mcap_reads(&dir.join("first_0.mcap")).is_err(), "the independent reader finds the damage too");

    // The same file cut off by a crash inside its last chunk: no summary to fall back on, so only the data
    // section's definitions chunk can name the channel of every later chunk.
    let last = chunks.len() - 1;
    let dir = damaged_copy(&good, "crashed", |b| {
        flip(b);
        b.truncate((chunks[last].offset + chunks[last].length / 2) as usize);
    });
    let kept = chunks[..last].iter().map(|c| c.messages).sum::<u64>() - victim.messages;
    let json = info_json(&dir);
    assert_eq!(json["messages"], kept, "{json}");
    let file = &json["files"][0];
    assert_eq!(file["complete"], false, "{json}");
    assert_eq!(file["lost_messages"], victim.messages, "the damaged chunk, by its message indexes: {json}");
    let kinds: Vec<&str> = file["damage"].as_array().unwrap().iter().map(|d| d["kind"].as_str().unwrap()).collect();
    assert!(kinds.iter().all(|k| *k != "unknown_channel"), "every intact chunk's channel is known: {json}");
    let damage = file["damage"].as_array().unwrap();
    assert_eq!((damage[0]["chunk"].as_u64(), damage[0]["offset"].as_u64()), (Some(first as u64), Some(victim.offset)));
    assert_eq!(damage[0]["lost_messages"], victim.messages, "{json}");
    recover_reports(&dir, &needles[1..], kept);
}

#[test]
fn one_flipped_bit_in_the_definitions_chunk_of_a_finished_file_loses_no_message() {
    let tmp = tempfile::tempdir().unwrap();
    let (good, chunks) = intact_bag(tmp.path());
    assert_eq!(first_message_chunk(&chunks), 1);
    let definitions = chunks[0];
    let dir = damaged_copy(&good, "defs", |b| b[(definitions.offset + definitions.length / 2) as usize] ^= 0x04);
    assert!(python_mcap_reads(&dir.join("defs_0.mcap")).is_err(), "the independent reader finds the damage");
    let needles = vec![
        "defs_0.mcap".to_string(),
        format!("chunk 0 at offset {}", definitions.offset),
        "channel(s) 1 (/swing); their definitions came from the summary".to_string(),
    ];
    // Damage all the same (info, export and replay refuse the bag unless told to skip it), but every message
    // is read, with the definitions of the file's intact summary.
    every_tool_reports(&dir, &needles, SWINGS);
    let json = info_json(&dir);
    let file = &json["files"][0];
    assert_eq!((json["messages"].as_u64(), file["lost_messages"].as_u64()), (Some(SWINGS), Some(0)), "{json}");
    assert_eq!(file["lost_messages_unknown"], false, "the statistics account for every message: {json}");
    let damage = file["damage"].as_array().unwrap();
    assert!(damage.iter().all(|d| d["lost_messages"] == 0), "{json}");
    // The chunk, the data section's CRC (it covers the chunk's bytes too), and where the definitions came from.
    assert_eq!(damage.len(), 3, "{json}");
    assert_eq!((damage[0]["chunk"].as_u64(), damage[0]["offset"].as_u64()), (Some(0), Some(definitions.offset)));
    assert_eq!(damage[1]["kind"], "data_section_crc", "{json}");
    assert_eq!(damage[2]["kind"], "definitions_from_summary", "{json}");
    assert_eq!(damage[2]["topics"], serde_json::json!(["/swing"]), "{json}");
    assert!(json.to_string().contains("sweetspot_msgs/msg/Swing"), "the type, from the summary: {json}");
    recover_reports(&dir, &needles, SWINGS);
}

#[test]
fn an_eight_byte_overwrite_inside_a_chunk_is_named_with_its_loss() {
    let tmp = tempfile::tempdir().unwrap();
    let (good, chunks) = intact_bag(tmp.path());
    let victim = chunks[1];
    let dir = damaged_copy(&good, "overwrite", |b| {
        let at = (victim.offset + victim.length / 3) as usize;
        b[at..at + 8].copy_from_slice(b"\xde\xad\xbe\xef\x00\x11\x22\x33");
    });
    let needles = vec![
        "overwrite_0.mcap".to_string(),
        format!("chunk 1 at offset {}", victim.offset),
        format!("{} messages lost", victim.messages),
    ];
    every_tool_reports(&dir, &needles, SWINGS - victim.messages);
    assert!(python_mcap_reads(&dir.join("overwrite_0.mcap")).is_err());
}

#[test]
fn a_bag_with_every_chunk_corrupted_is_not_an_empty_bag() {
    let tmp = tempfile::tempdir().unwrap();
    let (good, chunks) = intact_bag(tmp.path());
    let dir = damaged_copy(&good, "all", |b| {
        for c in &chunks {
            b[(c.offset + c.length - 5) as usize] ^= 0xff;
        }
    });
    let mut needles = vec!["all_0.mcap".to_string()];
    for (i, c) in chunks.iter().enumerate() {
        needles.push(format!("chunk {i} at offset {}: ", c.offset));
    }
    needles.push(format!("{SWINGS} messages lost"));
    every_tool_reports(&dir, &needles, 0);
    let json = info_json(&dir);
    assert_eq!(json["files"][0]["lost_messages"], SWINGS);
    assert_eq!(json["files"][0]["corrupt_chunks"], chunks.len());
    assert!(python_mcap_reads(&dir.join("all_0.mcap")).is_err());
}

#[test]
fn a_chunk_cut_short_by_the_end_of_the_file_is_damage_and_recover_keeps_the_chunks_before_it() {
    let tmp = tempfile::tempdir().unwrap();
    let (good, chunks) = intact_bag(tmp.path());
    let victim = chunks[3];
    let dir = damaged_copy(&good, "cut", |b| b.truncate((victim.offset + victim.length / 2) as usize));
    let kept: u64 = chunks[..3].iter().map(|c| c.messages).sum();
    let needles =
        vec!["cut_0.mcap".to_string(), format!("chunk 3 at offset {}", victim.offset), "ends inside".to_string()];
    every_tool_reports(&dir, &needles, kept);
    recover_reports(&dir, &needles[..2], kept);
}

#[test]
fn bytes_spliced_out_of_a_finished_file_are_skipped_to_the_next_indexed_chunk() {
    let tmp = tempfile::tempdir().unwrap();
    let (good, chunks) = intact_bag(tmp.path());
    let victim = chunks[1];
    // Remove 100 bytes from the middle of chunk 1, and pad the end so every later offset, the summary and the
    // footer stay where the summary says: chunk 1's record now runs into chunk 2.
    let dir = damaged_copy(&good, "splice", |b| {
        let at = (victim.offset + victim.length / 2) as usize;
        b.drain(at..at + 100);
        let next = chunks[2].offset as usize;
        b.splice(next - 100..next - 100, std::iter::repeat_n(0u8, 100));
    });
    let json = info_json(&dir);
    let damage = json["files"][0]["damage"].as_array().unwrap().clone();
    assert!(!damage.is_empty(), "{json}");
    assert_eq!(damage[0]["chunk"], 1, "{json}");
    assert_eq!(damage[0]["offset"], victim.offset, "{json}");
    let lost = json["files"][0]["lost_messages"].as_u64().unwrap();
    let read = json["messages"].as_u64().unwrap();
    assert_eq!(read + lost, SWINGS, "every message is read or counted lost: {json}");
    assert!(lost >= victim.messages, "{json}");
    let info = sweetspot(&[&"bag", &"info", &dir]);
    assert!(!info.ok && info.stdout.contains(&format!("chunk 1 at offset {}", victim.offset)), "{}", info.text());
}

// ------------------------------------------------------------------------------------------------------------
// Hostile inputs

fn assert_refused(path: &Path, why: &str) {
    for args in [
        vec!["bag", "info"],
        vec!["bag", "export", "--csv"],
        vec!["bag", "replay"],
        vec!["bag", "info", "--skip-damaged"],
        vec!["bag", "recover"],
    ] {
        let mut all: Vec<&dyn AsRef<std::ffi::OsStr>> = args.iter().map(|a| a as &dyn AsRef<std::ffi::OsStr>).collect();
        all.push(&path);
        let run = sweetspot(&all);
        assert!(!run.ok, "{args:?} {} must be refused: {}", path.display(), run.text());
        assert!(run.stderr.contains(why), "{args:?} {}: expected {why:?}: {}", path.display(), run.text());
        assert!(!run.stderr.contains("unfinished") && !run.stdout.contains("unfinished"), "{}", run.text());
        assert!(run.max_rss_kib < RSS_BOUND_KIB, "{args:?} {}: max RSS {} KiB", path.display(), run.max_rss_kib);
    }
}

#[test]
fn non_regular_files_are_refused_without_reading_them() {
    let tmp = tempfile::tempdir().unwrap();
    for (name, target) in [("zero.mcap", "/dev/zero"), ("urandom.mcap", "/dev/urandom")] {
        let link = tmp.path().join(name);
        std::os::unix::fs::symlink(target, &link).unwrap();
        assert_refused(&link, "a character device, not a regular file");
        // Inside a bag directory too.
        let dir = tmp.path().join(format!("dir_{name}"));
        std::fs::create_dir(&dir).unwrap();
        std::os::unix::fs::symlink(target, dir.join("x_0.mcap")).unwrap();
        assert_refused(&dir, "not a regular file");
    }
    let fifo = tmp.path().join("fifo.mcap");
    let c_path = std::ffi::CString::new(fifo.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: plain FFI call with a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0);
    assert_refused(&fifo, "a FIFO, not a regular file");
    let dir = tmp.path().join("dir.mcap.d");
    std::fs::create_dir_all(dir.join("inner_0.mcap")).unwrap();
    assert_refused(&dir, "a directory, not a regular file");

    // A symlink to a regular MCAP file is fine.
    let real = tmp.path().join("real");
    record_swings(&real, 10);
    let link = tmp.path().join("link.mcap");
    std::os::unix::fs::symlink(real.join("real_0.mcap"), &link).unwrap();
    let run = sweetspot(&[&"bag", &"info", &link]);
    assert!(run.ok && run.stdout.contains("Messages:          10"), "{}", run.text());
}

#[test]
fn empty_garbage_and_text_files_are_not_mcap_and_recover_leaves_them_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let mut garbage = vec![0u8; 4096];
    for (i, b) in garbage.iter_mut().enumerate() {
        *b = (i as u32).wrapping_mul(2_654_435_761).to_le_bytes()[3];
    }
    let cases: [(&str, Vec<u8>); 4] = [
        ("empty.mcap", Vec::new()),
        ("garbage.mcap", garbage),
        ("notes.txt", b"Shopping list:\n- bats\n- balls\n".to_vec()),
        ("half_magic.mcap", b"\x89MCA".to_vec()),
    ];
    for (name, bytes) in cases {
        let path = tmp.path().join(name);
        std::fs::write(&path, &bytes).unwrap();
        assert_refused(&path, "not an MCAP file");
        assert_eq!(std::fs::read(&path).unwrap(), bytes, "{name} untouched");
        let names: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert!(
            names.iter().all(|n| !n.to_string_lossy().contains("recovered") && !n.to_string_lossy().contains("broken")),
            "recover wrote nothing: {names:?}"
        );
    }
}

/// A hand-framed MCAP record.
fn record(opcode: u8, body: &[u8]) -> Vec<u8> {
    let mut out = vec![opcode];
    out.extend_from_slice(&(body.len() as u64).to_le_bytes());
    out.extend_from_slice(body);
    out
}

fn mcap_string(s: &str) -> Vec<u8> {
    let mut out = (s.len() as u32).to_le_bytes().to_vec();
    out.extend_from_slice(s.as_bytes());
    out
}

/// zstd of `size` zero bytes, compressed as a stream (never holding them).
fn zstd_zeros(size: u64) -> Vec<u8> {
    let mut encoder = zstd::stream::write::Encoder::new(Vec::new(), 19).unwrap();
    let block = vec![0u8; 1 << 20];
    let mut left = size;
    while left > 0 {
        let n = left.min(block.len() as u64) as usize;
        encoder.write_all(&block[..n]).unwrap();
        left -= n as u64;
    }
    encoder.finish().unwrap()
}

/// An MCAP file (header, then `chunks` zstd chunks claiming `claimed` bytes each holding `compressed`, then a
/// data end and a footer without summary).
fn bomb_file(compressed: &[u8], claimed: u64, chunks: usize) -> Vec<u8> {
    let mut out = sweetspot::bag::reader::MCAP_MAGIC.to_vec();
    out.extend(record(0x01, &[mcap_string("ros2"), mcap_string("bomb")].concat()));
    for _ in 0..chunks {
        let mut body = Vec::new();
        body.extend_from_slice(&0u64.to_le_bytes());
        body.extend_from_slice(&0u64.to_le_bytes());
        body.extend_from_slice(&claimed.to_le_bytes());
        body.extend_from_slice(&0u32.to_le_bytes());
        body.extend(mcap_string("zstd"));
        body.extend_from_slice(&(compressed.len() as u64).to_le_bytes());
        body.extend_from_slice(compressed);
        out.extend(record(0x06, &body));
    }
    out.extend(record(0x0f, &0u32.to_le_bytes()));
    let mut footer = Vec::new();
    footer.extend_from_slice(&0u64.to_le_bytes());
    footer.extend_from_slice(&0u64.to_le_bytes());
    footer.extend_from_slice(&0u32.to_le_bytes());
    out.extend(record(0x02, &footer));
    out.extend_from_slice(sweetspot::bag::reader::MCAP_MAGIC);
    out
}

#[test]
fn decompression_bombs_are_refused_in_bounded_memory() {
    let tmp = tempfile::tempdir().unwrap();
    let claimed = 255_000_000u64;
    let zeros = zstd_zeros(claimed);
    assert!(zeros.len() < 16 * 1024, "a real bomb: {} bytes for {claimed}", zeros.len());
    for (name, chunks) in [("one_bomb.mcap", 1), ("many_bombs.mcap", 200)] {
        let path = tmp.path().join(name);
        std::fs::write(&path, bomb_file(&zeros, claimed, chunks)).unwrap();
        let run = sweetspot(&[&"bag", &"info", &path]);
        assert!(!run.ok, "{}", run.text());
        assert!(
            run.stdout.contains("chunk 0 at offset 8") || run.stdout.contains("chunk 0 at offset"),
            "{}",
            run.text()
        );
        assert!(run.stdout.contains("refused unread: claims 255000000 uncompressed bytes"), "{}", run.text());
        assert_eq!(run.stdout.matches("DAMAGED:").count(), chunks, "{}", run.text());
        assert!(run.max_rss_kib < RSS_BOUND_KIB, "{name}: max RSS {} KiB", run.max_rss_kib);
        let recover = sweetspot(&[&"bag", &"recover", &path]);
        assert!(recover.ok, "{}", recover.text());
        assert!(recover.max_rss_kib < RSS_BOUND_KIB, "{name}: recover max RSS {} KiB", recover.max_rss_kib);
    }
    // A chunk within the size limits whose content is 16 MiB of zeros: refused at its first record, not after
    // decompressing it all, and a chunk that lies about its size (claims 1 KiB, holds 16 MiB) stops at 1 KiB.
    let sixteen = 16 * 1024 * 1024;
    let zeros = zstd_zeros(sixteen);
    for (name, claimed, why) in [("zeros.mcap", sixteen, "opcode 0x00"), ("liar.mcap", 1024, "opcode 0x00")] {
        let path = tmp.path().join(name);
        std::fs::write(&path, bomb_file(&zeros, claimed, 50)).unwrap();
        let run = sweetspot(&[&"bag", &"info", &path]);
        assert!(!run.ok && run.stdout.contains(why), "{}", run.text());
        assert!(run.max_rss_kib < RSS_BOUND_KIB, "{name}: max RSS {} KiB", run.max_rss_kib);
    }
}

// ------------------------------------------------------------------------------------------------------------
// Streaming

#[test]
fn a_bag_several_times_larger_than_the_memory_bound_streams_through_info_export_and_replay() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("big");
    let storage = StorageOptions {
        compression: ChunkCompression::None,
        chunk_size: Some(1024 * 1024),
        compression_threads: None,
        layout: McapLayout::Chunked,
    };
    let recorder = Recorder::start_with(RecorderConfig::new(&dir), storage).unwrap();
    let images = recorder.register_topic(string_topic("/camera/raw", RELIABLE)).unwrap();
    let swings = recorder.register_topic(TopicInfo::of::<Swing>("/swing", RELIABLE)).unwrap();
    // 64 KiB payloads that do not compress (a xorshift stream), 5,000 of them: ~330 MB.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let big: u64 = 5_000;
    for i in 0..big {
        let text: String = (0..64 * 1024)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (b'a' + (state % 26) as u8) as char
            })
            .collect();
        let t = 1_000_000_000 + i * 1_000_000;
        let cdr = cdr_string(&text);
        while !recorder.record(images, cdr.clone(), t, t) {
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        if i % 100 == 0 {
            let cdr = encode_cdr(&swing(i)).unwrap();
            while !recorder.record(swings, cdr.clone(), t, t) {
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
        }
    }
    recorder.finish().unwrap();
    let size: u64 = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().metadata().unwrap().len()).sum();
    assert!(size > 3 * RSS_BOUND_KIB as u64 * 1024, "the bag ({size} bytes) is several times the bound");
    let total = big + big / 100;
    let info = sweetspot(&[&"bag", &"info", &dir]);
    assert!(info.ok && info.stdout.contains(&format!("Messages:          {total}")), "{}", info.text());
    let export = sweetspot(&[&"bag", &"export", &"--csv", &dir]);
    assert!(export.ok, "{}", export.text());
    assert_eq!(export.stdout.lines().count() as u64, big / 100 + 1);
    let replay = sweetspot(&[&"bag", &"replay", &dir]);
    assert!(replay.ok, "{}", replay.text());
    for (tool, run) in [("info", &info), ("export", &export), ("replay", &replay)] {
        eprintln!("{tool}: max RSS {} KiB for a {} MiB bag", run.max_rss_kib, size >> 20);
        assert!(run.max_rss_kib < RSS_BOUND_KIB, "{tool}: max RSS {} KiB for a {size}-byte bag", run.max_rss_kib);
    }
}
