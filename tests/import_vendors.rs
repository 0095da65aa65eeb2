//! `sweetspot import` of the cage trackers beyond TrackMan and Statcast: HitTrax's session CSV, built from a
//! real export's header row and first row (tests/data/README.md says where from), detected from its header in
//! both of its layouts (with and without the leading `#` column), converted by hand-computed factors, its
//! non-swings and bad rows counted by reason.

use std::path::{Path, PathBuf};
use std::process::Command;

use sweetspot::calibrate::read_inputs;
use sweetspot::import::{import_files, Format, ImportError, ImportOptions, ImportReport, ROWS_TABLE};

mod support;

use support::import::{data, options};

fn import_with(files: &[&str], dir: &Path, options: &ImportOptions) -> Result<ImportReport, ImportError> {
    let paths: Vec<PathBuf> = files.iter().map(|f| data(f)).collect();
    import_files(&paths, dir, options)
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn hittrax_session_converts_by_hand_computed_factors_and_counts_its_skips() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("cage");
    let report = import_with(&["hittrax_session.csv"], &bag, &options()).unwrap();
    assert_eq!(report.files[0].format, Format::HitTrax, "detected from the header");
    assert_eq!(report.files[0].rows, 7);
    assert_eq!(report.swings, 2, "AB 2 and AB 4");
    // Line 2 (the real export's row): Pitch 0, which HitTrax writes for a tee and for no pitch speed entered.
    assert_eq!(report.skipped.get("Pitch not measured"), Some(&1));
    // Lines 4 and 6: Velo 0 and Velo blank, with no result: the bat missed.
    assert_eq!(report.skipped.get("no ball hit (call \"no result\")"), Some(&2));
    // Line 7: LA "high"; line 8: Velo 180 (a km/h column read as mph would look like that).
    assert_eq!(report.skipped.get("LA not a number (refused)"), Some(&1));
    assert_eq!(report.skipped.get("exit speed out of range (refused)"), Some(&1));
    let refused = report.refused.join("\n");
    assert!(refused.contains("line 7: LA = \"high\" is not a number"), "{refused}");
    assert!(refused.contains("line 8: exit speed gives 80.4672"), "180 × 0.44704 = 80.4672 m/s: {refused}");
    assert_eq!(report.skipped.values().sum::<u64>() + report.swings, 7, "every row accounted for");
    // HitTrax measures no bat, no spin, no pitch angle: all assumed for both swings.
    for field in ["bat_speed", "impact_z", "undercut", "attack_angle", "pitch_angle", "pitch_spin"] {
        assert_eq!(report.assumed.get(field), Some(&2), "{field}");
    }

    let inputs = read_inputs(&bag).unwrap();
    let swings: Vec<_> = inputs.swings.iter().map(|(_, s)| s).collect();
    // Line 3: Pitch 55.0 mph, Velo 87.3 mph, LA 18°. By hand: 55.0 × 0.44704 = 24.5872 m/s;
    // 87.3 × 0.44704 = 39.026592 m/s; 18° = π/10 = 0.3141592654 rad.
    let line_drive = swings[0];
    assert!(close(line_drive.ball_speed, 24.5872, 1e-12), "{}", line_drive.ball_speed);
    assert!(close(line_drive.measured_exit_speed, 39.026592, 1e-12), "{}", line_drive.measured_exit_speed);
    assert!(close(line_drive.measured_launch_angle, 0.3141592654, 1e-10));
    assert!(line_drive.measured_spin.is_nan(), "HitTrax measures no spin");
    assert_eq!((line_drive.pitch_angle, line_drive.pitch_spin, line_drive.attack_angle), (0.0, 0.0, 0.0));
    // Date 11/26/2018 16:09:02.120, read as UTC: 2018-11-26T16:09:02Z = 1543248542 s, + 120 ms.
    assert_eq!((line_drive.header.stamp.sec, line_drive.header.stamp.nanosec), (1_543_248_542, 120_000_000));
    // Line 5: Pitch 61.5 mph = 27.49296 m/s; Velo 92.6 mph = 41.395904 m/s; LA −4° = −0.0698131701 rad.
    let grounder = swings[1];
    assert!(close(grounder.ball_speed, 27.49296, 1e-12), "{}", grounder.ball_speed);
    assert!(close(grounder.measured_exit_speed, 41.395904, 1e-12));
    assert!(close(grounder.measured_launch_angle, -0.0698131701, 1e-10));

    // The side table keeps the line, the batter (a quoted cell holding a comma), the result and the AB.
    let table = std::fs::read_to_string(bag.join(ROWS_TABLE)).unwrap();
    let rows: Vec<&str> = table.lines().collect();
    assert!(rows[1].starts_with("1,") && rows[1].contains(",3,hittrax,Batter 01,Machine,AB 2,1B (LD),"), "{}", rows[1]);
    assert!(rows[2].contains(",5,hittrax,\"Batter 01, Jr.\",Machine,AB 4,6-3 (GB),"), "{}", rows[2]);
    let scans = sweetspot::bag::reader::read_bag(&bag, |_| {}).unwrap();
    assert_eq!(sweetspot::bag::info::custom_data_of(&scans)["sweetspot/import/formats"], "hittrax");
}

#[test]
fn hittrax_layout_with_the_number_column_a_bom_and_crlf() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("hash");
    let report = import_with(&["hittrax_hash.csv"], &bag, &options()).unwrap();
    assert_eq!(report.files[0].format, Format::HitTrax, "detected through the BOM, `#` first");
    assert_eq!(report.swings, 1);
    assert_eq!(report.skipped.get("no ball hit (call \"no result\")"), Some(&1));
    let swing = &read_inputs(&bag).unwrap().swings[0].1;
    // Pitch 48.5 mph = 21.68144 m/s; Velo 71.2 mph = 31.829248 m/s; LA −3° = −0.0523598776 rad.
    assert!(close(swing.ball_speed, 21.68144, 1e-12));
    assert!(close(swing.measured_exit_speed, 31.829248, 1e-12));
    assert!(close(swing.measured_launch_angle, -0.0523598776, 1e-10));
    // 1/5/2019 9:15:00.250 (one-digit month, day and hour) = 2019-01-05T09:15:00Z = 1546679700 s, + 250 ms.
    assert_eq!((swing.header.stamp.sec, swing.header.stamp.nanosec), (1_546_679_700, 250_000_000));
    let table = std::fs::read_to_string(bag.join(ROWS_TABLE)).unwrap();
    assert!(table.lines().nth(1).unwrap().contains(",hittrax,Batter 02,,#1 AB 1,5-3 (GB),"), "{table}");
}

#[test]
fn hittrax_is_forced_by_name_and_a_wrong_header_names_what_it_lacks() {
    let tmp = tempfile::tempdir().unwrap();
    let forced = ImportOptions { format: Some("hittrax".parse().unwrap()), ..options() };
    let report = import_with(&["hittrax_session.csv"], &tmp.path().join("forced"), &forced).unwrap();
    assert_eq!(report.swings, 2);
    let err = import_with(&["trackman_game.csv"], &tmp.path().join("wrong"), &forced).unwrap_err().to_string();
    assert!(err.contains("not a hittrax export") && err.contains("lacks AB, Pitch, Velo, LA, Res"), "{err}");
    assert!(!tmp.path().join("wrong").exists());

    // On the command line: the format word first, as for trackman and statcast.
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "hittrax"])
        .arg(data("hittrax_session.csv"))
        .arg("-o")
        .arg(tmp.path().join("cli"))
        .arg("--json")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["swings"], 2, "{json}");
    assert_eq!(json["files"][0]["format"], "hittrax", "{json}");
}

/// A bat sensor (Blast measures the bat, not the ball) joined to a ball tracker's rows and imported through a
/// column map: its bat speed is measured, not assumed, and `--batter-out` writes the batter's mean of it.
#[test]
fn a_bat_sensor_joined_through_a_map_gives_measured_bat_speeds_and_a_batter_file() {
    let tmp = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "--map"])
        .arg(data("mapped_session.toml"))
        .arg(data("mapped_session.csv"))
        .arg("-o")
        .arg(tmp.path().join("joined"))
        .arg("--batter-out")
        .arg(tmp.path().join("batters"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let swing = &read_inputs(&tmp.path().join("joined")).unwrap().swings[0].1;
    assert!(swing.bat_cm_speed > 0.0 && swing.bat_angular_speed > 0.0);
    // Batter 01's two rows carry Bat Speed 32.0 and 31.0 m/s (the miss counts: the bat was measured); the
    // third row is refused whole (its pitch speed is "fast"), so Batter 02 has no measured swing.
    let text = std::fs::read_to_string(tmp.path().join("batters/batter_Batter_01.toml")).unwrap();
    assert!(text.contains("mean of 2 measured bat speeds") && text.contains("bat_speed = 31.5"), "{text}");
    assert!(!tmp.path().join("batters/batter_Batter_02.toml").exists());
}

/// A record that is not UTF-8 text (here a batter's name, field 28, in Latin-1: "Pe\xf1a") is refused as a
/// row, named by the line an editor shows (LF and CRLF files alike); the rows around it are still imported.
#[test]
fn a_record_that_is_not_utf8_is_refused_alone_on_its_line() {
    let tmp = tempfile::tempdir().unwrap();
    let session = std::fs::read(data("hittrax_session.csv")).unwrap();
    let latin1 = String::from_utf8(session).unwrap().replacen(" Batter 01,, R,, Machine", " Pe\u{1}a,, R,, Machine", 1);
    let mut bytes = latin1.into_bytes();
    let at = bytes.iter().position(|&b| b == 1).expect("marker");
    bytes[at] = 0xf1;
    let crlf: Vec<u8> = bytes.iter().flat_map(|&b| if b == b'\n' { vec![b'\r', b'\n'] } else { vec![b] }).collect();
    for (name, text) in [("lf.csv", bytes), ("crlf.csv", crlf)] {
        let file = tmp.path().join(name);
        std::fs::write(&file, text).unwrap();
        let bag = tmp.path().join(format!("{name}.bag"));
        let report = import_files(&[file], &bag, &options()).unwrap();
        assert_eq!(report.files[0].rows, 7, "{name}: every record is a row, the broken one too");
        assert_eq!(report.swings, 1, "{name}: line 3 (AB 2) refused, line 5 (AB 4) imported");
        assert_eq!(report.skipped.get("record not UTF-8 text (refused)"), Some(&1), "{name}");
        let refused = report.refused.join("\n");
        assert!(refused.contains(", line 3: the record's field 28 is not UTF-8 text"), "{name}: {refused}");
        assert_eq!(report.skipped.values().sum::<u64>() + report.swings, 7, "{name}: every row accounted for");
        let rows = std::fs::read_to_string(bag.join(ROWS_TABLE)).unwrap();
        assert!(rows.lines().nth(1).unwrap().contains(",5,hittrax,\"Batter 01, Jr.\","), "{name}: {rows}");
    }
}

/// `--tee`: HitTrax's Pitch 0 (written for a tee and for a speed nobody entered) is a ball at rest, so the
/// real export's row (line 2: Pitch 0, Velo 52.9, LA 21) becomes a swing off a tee, with no pitch assumed.
#[test]
fn a_tee_session_turns_pitch_zero_into_a_ball_at_rest() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("tee");
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "hittrax"])
        .arg(data("hittrax_session.csv"))
        .arg("--tee")
        .arg("-o")
        .arg(&bag)
        .arg("--json")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["swings"], 3, "lines 2, 3 and 5: {json}");
    assert!(json["skipped"].get("Pitch not measured").is_none(), "{json}");
    // Only line 2 is at rest: pitch angle and spin are assumed for the two pitched rows alone.
    assert_eq!((json["assumed"]["pitch_angle"].as_u64(), json["assumed"]["pitch_spin"].as_u64()), (Some(2), Some(2)));
    let inputs = read_inputs(&bag).unwrap();
    let tee = &inputs.swings[0].1;
    assert_eq!((tee.ball_speed, tee.pitch_angle, tee.pitch_spin), (0.0, 0.0, 0.0));
    // 52.9 mph × 0.44704 = 23.648416 m/s; 21° = 0.3665191429 rad.
    assert!(close(tee.measured_exit_speed, 23.648416, 1e-12), "{}", tee.measured_exit_speed);
    assert!(close(tee.measured_launch_angle, 0.3665191429, 1e-10));
    assert!(close(inputs.swings[1].1.ball_speed, 24.5872, 1e-12), "line 3 keeps its 55.0 mph pitch");
}
