//! A bag is what its metadata.yaml says, every reader applies one damage rule, and outputs pair with their
//! swings by identity (issue 23, items 1–3). File-only: the bags are written here with the project's
//! Recorder, then damaged or rearranged the way a user's disk or hands would.

mod support;

use std::path::{Path, PathBuf};

use support::bag::top_level_records;
use support::cli::{fails, ok, s, sweetspot};
use support::rig::{finish, record_rig, STREAM, T0};
use sweetspot::bag::{Recorder, RecorderConfig, StorageOptions, TopicInfo};
use sweetspot::model::time::RosTime;
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::encode_cdr;
use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies, Swing};
use sweetspot::rig::{RigConfig, SessionGenerator};

/// A rig session (params, then `swings` measured swings 100 ms apart) recorded into `dir` in small chunks,
/// split every `max_file_size` bytes when given.
fn write_session(dir: &Path, swings: usize, max_file_size: Option<u64>) -> PathBuf {
    let config = RecorderConfig { max_file_size, ..RecorderConfig::new(dir) };
    let storage = StorageOptions { chunk_size: Some(2048), ..StorageOptions::default() };
    let recorder = Recorder::start_with(config, storage).expect("start recorder");
    let config = RigConfig { seed: 5, true_cor: Some(0.5), ..RigConfig::default() };
    record_rig(&recorder, &mut SessionGenerator::new(config).expect("rig").with_block(3), swings, |_| {});
    finish(recorder);
    dir.to_path_buf()
}

/// Copies a bag directory (flat) to `to`.
fn copy_bag(from: &Path, to: &Path) -> PathBuf {
    std::fs::create_dir(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, to.join(path.file_name().unwrap())).unwrap();
    }
    to.to_path_buf()
}

fn info_json(dir: &Path) -> serde_json::Value {
    let run = sweetspot(&["bag", "info", "--json", "--skip-damaged", s(dir)]);
    assert!(run.status_ok, "{}", run.stderr);
    serde_json::from_str(&run.stdout).unwrap()
}

/// Messages per file as metadata.yaml lists them (`files:`, read as plain YAML).
fn listed_counts(dir: &Path) -> Vec<(String, u64)> {
    let yaml = std::fs::read_to_string(dir.join("metadata.yaml")).unwrap();
    let docs = yaml_rust2::YamlLoader::load_from_str(&yaml).unwrap();
    let files = docs[0]["rosbag2_bagfile_information"]["files"].as_vec().expect("a files: list").clone();
    files
        .iter()
        .map(|f| (f["path"].as_str().unwrap().to_string(), f["message_count"].as_i64().unwrap() as u64))
        .collect()
}

#[test]
fn a_split_bag_is_what_its_metadata_yaml_lists() {
    let tmp = tempfile::tempdir().unwrap();
    let good = write_session(&tmp.path().join("split"), 80, Some(4 * 1024));
    let counts = listed_counts(&good);
    assert!(counts.len() >= 3, "the session should split into several files: {counts:?}");
    let total: u64 = counts.iter().map(|c| c.1).sum();
    assert_eq!(info_json(&good)["messages"], total);
    let intact_fit = ok(&["calibrate", "--json", s(&good)]);
    let intact_swings = serde_json::from_str::<serde_json::Value>(&intact_fit).unwrap()["swings"].as_u64().unwrap();

    // A listed file removed: damage, named with the messages metadata.yaml counted in it, for every reader.
    let missing = copy_bag(&good, &tmp.path().join("missing"));
    // A file from the middle of the session holds swings (the first ones may hold only params).
    let (gone, lost) = counts[counts.len() / 2].clone();
    std::fs::remove_file(missing.join(&gone)).unwrap();
    let needle = format!("{gone}: at offset 0: listed in metadata.yaml but missing; {lost} messages lost");
    let out = tmp.path().join("fit.jsonl");
    for args in [
        vec!["bag", "info"],
        vec!["bag", "export", "--csv"],
        vec!["bag", "replay"],
        vec!["calibrate", "--write", s(&out)],
        vec!["calibrate", "--fit-batter"],
    ] {
        let mut all = args.clone();
        all.push(s(&missing));
        let err = fails(&all);
        assert!(err.contains(&needle), "{args:?}: {err}");
        assert!(err.contains("--skip-damaged"), "{args:?} names the way on: {err}");
        assert!(!out.exists(), "{args:?} wrote {} from a damaged bag", out.display());
    }
    let json = info_json(&missing);
    assert_eq!(json["messages"], total - lost, "{json}");
    assert_eq!(json["damaged"], true, "{json}");
    let replay = sweetspot(&["bag", "replay", "--skip-damaged", s(&missing)]);
    assert!(replay.status_ok && replay.stderr.contains(&needle), "{}", replay.stderr);
    let fit = sweetspot(&["calibrate", "--json", "--skip-damaged", "--write", s(&out), s(&missing)]);
    assert!(fit.status_ok, "{}", fit.stderr);
    assert!(fit.stderr.contains(&needle) && fit.stderr.contains("skipped (--skip-damaged)"), "{}", fit.stderr);
    let swings = serde_json::from_str::<serde_json::Value>(&fit.stdout).unwrap()["swings"].as_u64().unwrap();
    assert!(swings < intact_swings, "{swings} of {intact_swings} swings fitted without the missing file");
    assert!(out.exists(), "--skip-damaged fits and writes");

    // An unlisted .mcap (here a copy of split 0): named, left out, nothing counted twice, not an error.
    let stray = copy_bag(&good, &tmp.path().join("stray"));
    std::fs::copy(stray.join(&counts[0].0), stray.join("zzz.mcap")).unwrap();
    for args in [vec!["bag", "info"], vec!["bag", "export", "--csv"], vec!["bag", "replay"], vec!["calibrate"]] {
        let mut all = args.clone();
        all.push(s(&stray));
        let run = sweetspot(&all);
        assert!(run.status_ok, "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains("zzz.mcap: not listed in metadata.yaml: left out"), "{args:?}: {}", run.stderr);
    }
    assert_eq!(info_json(&stray)["messages"], total);
    assert_eq!(info_json(&stray)["damaged"], false);

    // metadata.yaml that does not parse, or does not list files: an error naming it and `bag recover`.
    for (name, text) in
        [("garbage", "rosbag2_bagfile_information: [\n"), ("nolist", "rosbag2_bagfile_information:\n  version: 8\n")]
    {
        let broken = copy_bag(&good, &tmp.path().join(name));
        std::fs::write(broken.join("metadata.yaml"), text).unwrap();
        for args in [
            vec!["bag", "info"],
            vec!["bag", "info", "--skip-damaged"],
            vec!["bag", "export", "--csv"],
            vec!["bag", "replay", "--skip-damaged"],
            vec!["calibrate", "--skip-damaged"],
        ] {
            let mut all = args.clone();
            all.push(s(&broken));
            let err = fails(&all);
            assert!(err.contains("metadata.yaml is unreadable"), "{args:?}: {err}");
            assert!(err.contains("bag recover"), "{args:?}: {err}");
        }
        let recovered = ok(&["bag", "recover", s(&broken)]);
        assert!(recovered.contains("metadata.yaml rebuilt"), "{recovered}");
        let copy = tmp.path().join(format!("{name}.recovered"));
        assert_eq!(info_json(&copy)["messages"], total);
        assert_eq!(info_json(&copy)["damaged"], false);
    }
    // So is a bag directory without one.
    let bare = copy_bag(&good, &tmp.path().join("bare"));
    std::fs::remove_file(bare.join("metadata.yaml")).unwrap();
    assert!(fails(&["bag", "info", s(&bare)]).contains("metadata.yaml is missing"));
}

#[test]
fn calibrate_refuses_a_damaged_bag_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = write_session(&tmp.path().join("one"), 40, None);
    let file = bag.join("one_0.mcap");
    let mut bytes = std::fs::read(&file).unwrap();
    // Flip one byte in the middle of the third chunk (the first holds the definitions).
    let records = top_level_records(&bytes);
    // (start, end) of each chunk record: a record starts where the one before it ends (after the 8-byte magic).
    let chunks: Vec<(u64, u64)> = records
        .iter()
        .enumerate()
        .filter(|(_, r)| r.opcode == 0x06)
        .map(|(i, r)| (if i == 0 { 8 } else { records[i - 1].end }, r.end))
        .collect();
    assert!(chunks.len() >= 4, "small chunks: {}", chunks.len());
    let at = ((chunks[2].0 + chunks[2].1) / 2) as usize;
    bytes[at] ^= 0x55;
    std::fs::write(&file, &bytes).unwrap();
    let info = fails(&["bag", "info", s(&bag)]);
    assert!(info.contains("one_0.mcap: chunk 2 at offset"), "{info}");
    let write = tmp.path().join("ball.jsonl");
    let batter = tmp.path().join("batter.toml");
    for args in [
        vec!["calibrate", s(&bag)],
        vec!["calibrate", "--write", s(&write), s(&bag)],
        vec!["calibrate", "--fit-youngs", "--write", s(&write), s(&bag)],
        vec!["calibrate", "--batter-out", s(&batter), s(&bag)],
        vec!["calibrate", "--fit-tangential", "--json", s(&bag)],
    ] {
        let err = fails(&args);
        assert!(err.contains("damaged bag:") && err.contains("one_0.mcap: chunk 2 at offset"), "{args:?}: {err}");
        assert!(err.contains("--skip-damaged"), "{err}");
        assert!(!write.exists() && !batter.exists(), "{args:?} wrote output from a damaged bag");
    }
    let run = sweetspot(&["calibrate", "--skip-damaged", "--write", s(&write), s(&bag)]);
    assert!(run.status_ok, "{}", run.stderr);
    assert!(run.stderr.contains("one_0.mcap: chunk 2 at offset"), "the damage is still listed: {}", run.stderr);
    assert!(write.exists());
}

const T1: u64 = T0 + 1_000_000_000;

fn stamp(ns: u64) -> sweetspot::msgs::std_msgs::msg::Header {
    sweetspot::msgs::std_msgs::msg::Header { stamp: Time::from_unix_ns(ns), frame_id: "rig".into() }
}

#[test]
fn answers_pair_with_their_swing_by_identity_wherever_they_lie() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("order");
    let r = Recorder::start(RecorderConfig::new(&dir)).unwrap();
    let sw = r.register_topic(TopicInfo::of::<Swing>("/lab/swing", STREAM)).unwrap();
    let ev = r.register_topic(TopicInfo::of::<ExitVelocity>("/lab/exit_velocity", STREAM)).unwrap();
    let me = r.register_topic(TopicInfo::of::<ModalEnergies>("/lab/modal_energies", STREAM)).unwrap();
    // Swing counters restart (ids 1..=10 twice, other stamps); every answer is written before its swing, the
    // modal energies of the second half before everything.
    let swings: Vec<Swing> = (0..20u64)
        .map(|k| Swing {
            header: stamp(T1 + k * 1_000_000),
            swing_id: k % 10 + 1,
            ball_speed: 40.0 + k as f64,
            ..Swing::default()
        })
        .collect();
    for s in &swings[10..] {
        let m = ModalEnergies { header: s.header.clone(), swing_id: s.swing_id, ..ModalEnergies::default() };
        assert!(r.record(me, encode_cdr(&m).unwrap(), T1, T1));
    }
    for (k, s) in swings.iter().enumerate() {
        let t = T1 + k as u64 * 1_000_000;
        let answer = ExitVelocity {
            header: s.header.clone(),
            swing_id: s.swing_id,
            exit_speed: s.ball_speed + 0.5,
            ..ExitVelocity::default()
        };
        assert!(r.record(ev, encode_cdr(&answer).unwrap(), t, t));
        assert!(r.record(sw, encode_cdr(s).unwrap(), t + 1, t));
        if k < 10 {
            let m = ModalEnergies { header: s.header.clone(), swing_id: s.swing_id, ..ModalEnergies::default() };
            assert!(r.record(me, encode_cdr(&m).unwrap(), t + 2, t));
        }
    }
    // An answer to no recorded swing (same id, another stamp).
    let stray = ExitVelocity { header: stamp(T0), swing_id: 3, ..ExitVelocity::default() };
    assert!(r.record(ev, encode_cdr(&stray).unwrap(), T1 + 50_000_000, T1));
    r.finish().unwrap();
    let (rows, counts) = sweetspot::bag::export::swing_rows(&dir).unwrap();
    assert_eq!(rows.len(), 20);
    assert_eq!(
        (counts.matched_exit_velocities, counts.matched_modal_energies, counts.orphan_outputs),
        (20, 20, 1),
        "{counts:?}"
    );
    for row in &rows {
        let answer = row.exit_velocity.as_ref().expect("answered");
        assert_eq!(
            answer.exit_speed,
            row.swing.ball_speed + 0.5,
            "swing {} paired with its own answer",
            row.swing.swing_id
        );
        assert_eq!(row.modal_energies.as_ref().unwrap().header.stamp, row.swing.header.stamp);
        // One node in the bag: its namespace is that of its swing topic.
        assert_eq!(row.namespace, "/lab");
    }
}

#[test]
fn a_bag_recorded_without_ball_params_says_so_instead_of_differs() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("noball");
    let r = Recorder::start(RecorderConfig::new(&dir)).unwrap();
    let sw = r.register_topic(TopicInfo::of::<Swing>("/swing", STREAM)).unwrap();
    let ev = r.register_topic(TopicInfo::of::<ExitVelocity>("/exit_velocity", STREAM)).unwrap();
    for k in 0..5u64 {
        let t = T1 + k * 1_000_000;
        // The node knew ball "rig_ball" (its BallParams were not recorded) and answered OK.
        let s = Swing {
            header: stamp(t),
            swing_id: k + 1,
            ball_id: "rig_ball".into(),
            ball_speed: 40.0,
            bat_cm_speed: 25.0,
            bat_angular_speed: 45.0,
            impact_z: 0.7,
            ..Swing::default()
        };
        let answer = ExitVelocity {
            header: s.header.clone(),
            swing_id: s.swing_id,
            status: ExitVelocity::STATUS_OK,
            exit_speed: 45.0,
            ..ExitVelocity::default()
        };
        assert!(r.record(sw, encode_cdr(&s).unwrap(), t, t));
        assert!(r.record(ev, encode_cdr(&answer).unwrap(), t + 1, t));
    }
    r.finish().unwrap();
    let run = sweetspot(&["bag", "replay", s(&dir)]);
    assert!(!run.status_ok, "nothing could be checked: {}", run.stdout);
    assert!(!run.stdout.contains("DIFFERS"), "{}", run.stdout);
    assert!(run.stdout.contains("not checked: the bag lacks the BallParams of ball 'rig_ball'"), "{}", run.stdout);
    assert!(
        run.stderr.contains("5 swings were answered OK by the node with params the bag does not hold"),
        "{}",
        run.stderr
    );
    assert!(run.stderr.contains("5 of 5 swings could not be checked"), "{}", run.stderr);
}
