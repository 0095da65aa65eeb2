//! `calibrate` as a command: its iteration limit (0 runs none; the e_T fit honours it too), a fit that did
//! not converge exits 1 and writes nothing unless `--force`, `--fit-batter` refuses `--fit-tangential`, no
//! output lands on (or in) the bag it reads, it ends quietly into a closed pipe, and `bag export -o` and
//! `compare --batter` keep the same rules (outputs, non-regular inputs, the field a bad batter file blames).
//! The session is the rig's (oblique, tracked launch), recorded to a real bag in a temporary directory.

mod support;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use support::cli::{s, sweetspot};
use support::rig::record_rig_session;
use sweetspot::physics::CollisionOptions;
use sweetspot::rig::{LaunchConditions, RigConfig, SessionGenerator};

/// Records `swings` oblique, tracked swings of the rig into DIR/session; returns the bag.
fn session(dir: &Path, swings: usize) -> PathBuf {
    let config = RigConfig {
        bats: vec!["r161".into(), "r161-corked".into()],
        seed: 31,
        options: CollisionOptions { modes: 18, ..CollisionOptions::default() },
        launch: Some(LaunchConditions::default()),
        ..RigConfig::default()
    };
    record_rig_session(dir, swings, SessionGenerator::new(config).expect("rig").with_block(4))
}

/// The bag's MCAP file and its bytes.
fn mcap_of(bag: &Path) -> (PathBuf, Vec<u8>) {
    let file = std::fs::read_dir(bag)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "mcap"))
        .expect("an .mcap file");
    let bytes = std::fs::read(&file).unwrap();
    (file, bytes)
}

#[test]
fn the_iteration_limit_and_convergence_decide_the_exit_status_and_the_files() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = session(tmp.path(), 24);
    let out = tmp.path().join("fitted.jsonl");

    // 0 iterations: none run (the report says so), not converged: status 1 and no file.
    let run = sweetspot(&["calibrate", s(&bag), "--fit-tangential", "--max-iterations", "0", "--write", s(&out)]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(run.stdout.contains("0 iteration(s), NOT converged"), "{}", run.stdout);
    assert!(run.stdout.contains("0 iterations, NOT converged"), "the e_T fit honours the limit: {}", run.stdout);
    assert!(run.stderr.contains("did not converge") && run.stderr.contains("nothing written"), "{}", run.stderr);
    assert!(!out.exists());

    // The e_T fit is held to the limit too: 1 iteration each.
    let run = sweetspot(&["calibrate", s(&bag), "--fit-tangential", "--max-iterations", "1", "--json"]);
    let doc: serde_json::Value = serde_json::from_str(&run.stdout).expect("JSON");
    assert_eq!(doc["iterations"], 1);
    assert_eq!(doc["tangential"]["iterations"], 1);

    // --force writes anyway, with a warning, status 0.
    let run =
        sweetspot(&["calibrate", s(&bag), "--fit-tangential", "--max-iterations", "0", "--write", s(&out), "--force"]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert!(run.stderr.contains("written anyway"), "{}", run.stderr);
    assert!(out.is_file());

    // Converged: status 0, file written.
    std::fs::remove_file(&out).unwrap();
    let run = sweetspot(&["calibrate", s(&bag), "--fit-tangential", "--write", s(&out)]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    assert!(out.is_file());
}

#[test]
fn fit_batter_and_fit_tangential_are_not_silently_merged() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = session(tmp.path(), 8);
    for extra in [["--fit-batter"], ["--batter-out=b.toml"], ["--reference-bat=r161"]] {
        let mut args = vec!["calibrate", s(&bag), "--fit-tangential"];
        args.extend(extra);
        let run = sweetspot(&args);
        assert_eq!(run.code, Some(2), "{args:?}: {}", run.stderr);
        assert!(
            run.stderr.contains("--fit-tangential") && run.stderr.contains("cannot be used with"),
            "{}",
            run.stderr
        );
    }
}

#[test]
fn no_output_lands_on_or_in_the_bag_being_read() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = session(tmp.path(), 24);
    let (mcap, bytes) = mcap_of(&bag);
    let link = tmp.path().join("link.mcap");
    std::os::unix::fs::symlink(&mcap, &link).unwrap();
    let hard = tmp.path().join("hard.mcap");
    std::fs::hard_link(&mcap, &hard).unwrap();
    let metadata = bag.join("metadata.yaml");
    let inside = bag.join("fitted.jsonl");
    let cases: Vec<Vec<&str>> = vec![
        vec!["calibrate", s(&bag), "--write", s(&mcap)],
        vec!["calibrate", s(&bag), "--write", s(&link)],
        vec!["calibrate", s(&bag), "--write", s(&hard)],
        vec!["calibrate", s(&bag), "--write", s(&metadata)],
        vec!["calibrate", s(&bag), "--write", s(&inside)],
        vec!["calibrate", s(&bag), "--batter-out", s(&mcap)],
        vec!["calibrate", s(&bag), "--batter-out", s(&link)],
        vec!["bag", "export", s(&bag), "-o", s(&mcap)],
        vec!["bag", "export", s(&bag), "-o", s(&hard)],
        vec!["bag", "export", s(&mcap), "-o", s(&link)],
    ];
    for args in cases {
        let run = sweetspot(&args);
        assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains("refused"), "{args:?}: {}", run.stderr);
        assert_eq!(std::fs::read(&mcap).unwrap(), bytes, "{args:?} changed the recording");
        assert!(!inside.exists());
    }
    // Other writers keep the rule: a figure onto the batter file it reads (here through a hard link).
    let batter = tmp.path().join("batter.toml");
    std::fs::write(&batter, "exponent = 0.25\n").unwrap();
    let figure = tmp.path().join("batter.svg");
    std::fs::hard_link(&batter, &figure).unwrap();
    let run = sweetspot(&["compare", "--batter", s(&batter), "--figure", s(&figure), "--modes", "2"]);
    assert_eq!(run.code, Some(1), "{}", run.stderr);
    assert!(run.stderr.contains("--figure") && run.stderr.contains("refused"), "{}", run.stderr);
    assert_eq!(std::fs::read_to_string(&batter).unwrap(), "exponent = 0.25\n");
    // Beside the bag is fine.
    let run = sweetspot(&["bag", "export", s(&bag), "-o", s(&tmp.path().join("swings.csv"))]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
}

#[test]
fn calibrate_into_a_closed_pipe_exits_quietly() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = session(tmp.path(), 24);
    for extra in [&[][..], &["--fit-tangential"][..], &["--json"][..]] {
        let (reader, writer) = std::io::pipe().expect("pipe");
        drop(reader);
        let output = Command::new(support::BIN)
            .arg("calibrate")
            .arg(&bag)
            .args(extra)
            .stdout(Stdio::from(writer))
            .stderr(Stdio::piped())
            .output()
            .expect("run");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(0), "{extra:?}: {stderr}");
        assert!(!stderr.contains("panicked") && !stderr.contains("Broken pipe"), "{stderr}");
    }
}

#[test]
fn input_files_are_regular_and_a_bad_batter_file_blames_its_own_field() {
    let tmp = tempfile::tempdir().unwrap();
    let batter = tmp.path().join("batter.toml");
    std::fs::write(&batter, "impact_from_barrel_end = 2.0\n").unwrap();
    let run = sweetspot(&["compare", "--batter", s(&batter)]);
    assert_eq!(run.code, Some(1));
    assert!(run.stderr.contains("impact_from_barrel_end = 2"), "{}", run.stderr);
    assert!(!run.stderr.contains("pivot_z"), "{}", run.stderr);

    let fifo = tmp.path().join("fifo");
    let made = Command::new("mkfifo").arg(&fifo).status().expect("mkfifo");
    assert!(made.success());
    for (args, what) in [
        (vec!["compare", "--batter", "/dev/zero"], "'/dev/zero' is a character device"),
        (vec!["compare", "--batter", s(&fifo)], "is a FIFO"),
        (vec!["compare", "--batter", s(tmp.path())], "is a directory"),
        (vec!["simulate", "--case", "/dev/zero"], "character device"),
        (vec!["simulate", "--bat", s(&fifo)], "is a FIFO"),
        (vec!["demo", "--batter", "/dev/zero"], "character device"),
    ] {
        let run = sweetspot(&args);
        assert_eq!(run.code, Some(1), "{args:?}: {}", run.stderr);
        assert!(run.stderr.contains(what) && run.stderr.contains("not a regular file"), "{args:?}: {}", run.stderr);
    }
}

#[test]
fn oblique_flags_are_refused_in_their_own_units_at_the_nodes_limit() {
    use sweetspot::model::limits::{MAX_PITCH_SPIN, MAX_SWING_ANGLE};
    use sweetspot::physics::oblique::rad_per_s_to_rpm;
    let max_rpm = rad_per_s_to_rpm(MAX_PITCH_SPIN);
    let over = format!("{}", (max_rpm + 1.0).round());
    let under = format!("{}", (max_rpm - 1.0).round());
    let run = sweetspot(&["simulate", "--bat", "r161", "--pitch-spin", &over]);
    assert_eq!(run.code, Some(1));
    assert!(run.stderr.contains(&format!("--pitch-spin {over} rpm is out of range")), "{}", run.stderr);
    assert!(run.stderr.contains("9549 rpm"), "{}", run.stderr);
    let run = sweetspot(&["simulate", "--bat", "r161", "--pitch-spin", &under]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
    // The node refuses the same swing beyond the limit (model::limits is the one limit).
    let swing = |rpm: f64| sweetspot::model::engine::SwingInput {
        pitch_spin: sweetspot::physics::oblique::rpm_to_rad_per_s(rpm),
        ..sweetspot::physics::Impact { ball_speed: 40.0, bat_cm_speed: 20.0, bat_angular_speed: 50.0, impact_z: 0.6 }
            .into()
    };
    assert!(swing(max_rpm + 1.0).validate(0.0366, 0.033).is_err());
    assert!(swing(max_rpm - 1.0).validate(0.0366, 0.033).is_ok());
    assert_eq!(MAX_SWING_ANGLE.to_degrees().round(), 80.0);
    for flag in ["--attack-angle", "--pitch-angle"] {
        let run = sweetspot(&["simulate", "--bat", "r161", flag, "81"]);
        assert_eq!(run.code, Some(1));
        assert!(
            run.stderr.contains(&format!("{flag} 81° is out of range")) && run.stderr.contains("≤ 80°"),
            "{}",
            run.stderr
        );
        assert!(!run.stderr.contains("rad"), "{}", run.stderr);
    }
}

/// An imported session's impact points and bat speeds are the batter model's, not measurements: calibrate says
/// so beside its COR ± σ (and lists them in JSON), and `bag replay` shows the measured exit speeds against the
/// model's. A recorded session with measured swings gets no such warning.
#[test]
fn an_imported_session_warns_what_was_assumed_and_replay_shows_measured_against_model() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("game");
    let csv = support::repo().join("tests/data/trackman_game.csv");
    let out =
        Command::new(env!("CARGO_BIN_EXE_sweetspot")).arg("import").arg(&csv).arg("-o").arg(&bag).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let run = sweetspot(&["calibrate", s(&bag), "--max-iterations", "5", "--force"]);
    assert!(run.stderr.contains("warning: imported session"), "{}", run.stderr);
    assert!(run.stderr.contains("the impact point") && run.stderr.contains("the bat speed"), "{}", run.stderr);
    assert!(run.stderr.contains("for 5 swings"), "five swings were imported: {}", run.stderr);
    let doc = sweetspot(&["calibrate", s(&bag), "--json", "--max-iterations", "5", "--force"]);
    let doc: serde_json::Value = serde_json::from_str(&doc.stdout).unwrap();
    assert_eq!(doc["assumed"]["impact_z"], 5);
    assert_eq!(doc["assumed"]["bat_speed"], 5);

    // The four measured exit speeds of the export (ExitSpeed mph × 0.44704, by hand) beside the model's.
    let replay = sweetspot(&["bag", "replay", s(&bag)]);
    assert!(replay.status_ok, "{}", replay.stderr);
    assert!(replay.stdout.contains("measured v_f") && replay.stdout.contains("meas − model"), "{}", replay.stdout);
    for measured in ["40.419", "42.488", "40.215", "37.430"] {
        assert!(replay.stdout.contains(measured), "{measured} missing:\n{}", replay.stdout);
    }
    assert!(replay.stdout.contains("measured against model: 4 measured swings"), "{}", replay.stdout);

    let recorded = session(tmp.path(), 8);
    let run = sweetspot(&["calibrate", s(&recorded), "--max-iterations", "5", "--force"]);
    assert!(!run.stderr.contains("imported session"), "{}", run.stderr);
}
