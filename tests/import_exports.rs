//! `sweetspot import`: real TrackMan rows and a Statcast search export in its header layout become a bag
//! that `bag replay` and `calibrate` read unchanged; the conversions are checked against hand-computed values
//! (tests/data/README.md says where each fixture comes from), and bad input is refused by row.

use std::path::{Path, PathBuf};
use std::process::Command;

use sweetspot::bag::replay::{recorded_settings, replay, Verdict, WhatIf};
use sweetspot::calibrate::{fit, problem_from_bag, read_inputs, FitOptions};
use sweetspot::import::{import_files, Format, ImportError, ImportOptions, ImportReport, ROWS_TABLE};
use sweetspot::physics::Bat;

mod support;

use support::import::{data, options};

fn import(files: &[&str], dir: &Path) -> Result<ImportReport, ImportError> {
    let paths: Vec<PathBuf> = files.iter().map(|f| data(f)).collect();
    import_files(&paths, dir, &options())
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn real_trackman_rows_convert_by_hand_computed_factors() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("game");
    let report = import(&["trackman_game.csv"], &bag).unwrap();
    assert_eq!(report.files[0].format, Format::TrackMan);
    assert_eq!(report.files[0].rows, 7);
    // BallCalled and StrikeSwinging are no swing; the foul with an ExitSpeed and four InPlay rows are.
    assert_eq!(report.swings, 5);
    assert_eq!(report.skipped.get("no ball hit (call \"BallCalled\")"), Some(&1));
    assert_eq!(report.skipped.get("no ball hit (call \"StrikeSwinging\")"), Some(&1));
    assert_eq!(report.assumed.get("bat_speed"), Some(&5), "TrackMan has no bat speed");

    let inputs = read_inputs(&bag).unwrap();
    assert_eq!(inputs.bats.len(), 1);
    assert_eq!(inputs.balls.len(), 1);
    assert!(inputs.bats[0].0 < inputs.swings[0].0, "params before the first swing");
    let swings: Vec<_> = inputs.swings.iter().map(|(_, s)| s).collect();
    // Line 3 of the export: FoulBallNotFieldable, ZoneSpeed 86.16315 mph, VertApprAngle −6.078796°,
    // SpinRate 2513.10845 rpm at SpinAxis 224.570496°, ExitSpeed 90.41575 mph, Angle 39.171373°, no HitSpinRate.
    // By hand: 86.16315 × 0.44704 = 38.51837 m/s; 6.078796° = 0.106095 rad; 2513.10845 rpm × 2π/60 ×
    // (−cos 224.570496°) = 263.172 rad/s × 0.712387 = 187.481 rad/s; 90.41575 × 0.44704 = 40.41946 m/s;
    // 39.171373° = 0.683669 rad.
    let foul = swings[0];
    assert!(close(foul.ball_speed, 38.51837, 1e-5), "{}", foul.ball_speed);
    assert!(close(foul.pitch_angle, 0.106095, 1e-6), "{}", foul.pitch_angle);
    assert!(close(foul.pitch_spin, 187.481, 1e-3), "{}", foul.pitch_spin);
    assert!(close(foul.measured_exit_speed, 40.41946, 1e-5), "{}", foul.measured_exit_speed);
    assert!(close(foul.measured_launch_angle, 0.683669, 1e-6), "{}", foul.measured_launch_angle);
    assert!(foul.measured_spin.is_nan(), "no HitSpinRate: not measured");
    // UTCDateTime 2025-06-13T01:42:14.6984960Z = 1749778934 s + 698496000 ns.
    assert_eq!((foul.header.stamp.sec, foul.header.stamp.nanosec), (1_749_778_934, 698_496_000));
    // Line 5: HitSpinRate 2740.943835 rpm = 287.031 rad/s of total spin at HitSpinAxis 254.393031°, whose
    // backspin part is 287.031 × (−cos 254.393°) = 77.22 rad/s (mostly side spin, a little backspin).
    let in_play = swings[1];
    assert!(close(in_play.measured_spin, 287.031, 1e-3), "{}", in_play.measured_spin);
    let backspin = sweetspot::model::convert::swing_input(in_play).measured_backspin();
    assert!(close(backspin, 77.22, 0.01), "{backspin}");
    // Line 8: InPlay without an ExitSpeed: a swing, nothing measured off the bat.
    assert!(swings[4].measured_exit_speed.is_nan());
    // The assumed contact: the default batter's usual point, 6 in from the barrel end, centre-line.
    let length = Bat::preset("r161").unwrap().mass_properties().length;
    assert!(swings.iter().all(|s| close(s.impact_z, length - 0.1524, 1e-12) && s.undercut == 0.0));

    // The bag says what it is and what was assumed (custom_data, in every MCAP file and metadata.yaml).
    let scans = sweetspot::bag::reader::read_bag(&bag, |_| {}).unwrap();
    let custom = sweetspot::bag::info::custom_data_of(&scans);
    assert_eq!(custom["sweetspot/import/formats"], "trackman");
    assert_eq!(custom["sweetspot/import/assumed"], "attack_angle:5,bat_speed:5,impact_z:5,undercut:5");
    assert_eq!(custom["sweetspot/default_modes"], "18");
    assert!(std::fs::read_to_string(bag.join("metadata.yaml")).unwrap().contains("sweetspot/import/rows_table"));

    // The side table names each swing's source line.
    let table = std::fs::read_to_string(bag.join(ROWS_TABLE)).unwrap();
    let first = table.lines().nth(1).unwrap();
    assert!(first.starts_with("1,") && first.contains(",3,trackman,"), "{first}");
    assert!(first.contains("Batter") && first.ends_with("bat_speed;impact_z;undercut;attack_angle"), "{first}");
}

#[test]
fn the_imported_bag_replays_and_calibrates_unchanged() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("game");
    import(&["trackman_game.csv"], &bag).unwrap();
    let settings = recorded_settings(&bag).unwrap();
    let report = replay(&bag, &settings, &WhatIf::default(), 0.0, |_, _| {}).unwrap();
    assert_eq!(report.rows.len(), 5);
    for row in &report.rows {
        assert_eq!(row.verdict, Verdict::NotRecorded, "an import has no answers to compare");
        assert_eq!(row.replayed_status, 0, "swing {} was refused by the model", row.swing_id);
        assert!(row.replayed_exit_speed > 20.0 && row.replayed_exit_speed < 60.0, "{}", row.replayed_exit_speed);
    }
    let problem = problem_from_bag(&bag, None).unwrap();
    assert_eq!(problem.observations.len(), 4, "the four swings with a measured exit speed");
    let fitted = fit(&problem, &FitOptions::default()).unwrap();
    assert!(fitted.parameters[0].value.is_finite());

    // And from the command line, as a user runs it.
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot")).args(["bag", "replay"]).arg(&bag).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn the_cli_detects_or_is_told_the_format() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("cli");
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "trackman"])
        .arg(data("trackman_game.csv"))
        .arg("-o")
        .arg(&bag)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("5 swings written"), "{stdout}");
    // Forcing the wrong format names what its header lacks.
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "--format", "statcast"])
        .arg(data("trackman_game.csv"))
        .arg("-o")
        .arg(tmp.path().join("wrong"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.contains("not a statcast export") && stderr.contains("launch_speed"), "{stderr}");
    assert!(!tmp.path().join("wrong").exists());
}

#[test]
fn bom_quoted_comma_and_missing_cells() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("edited");
    let report = import(&["trackman_edited.csv"], &bag).unwrap();
    assert_eq!(report.files[0].format, Format::TrackMan, "detected through the BOM");
    assert_eq!(report.swings, 2);
    let inputs = read_inputs(&bag).unwrap();
    let second = &inputs.swings[1].1;
    assert!(second.measured_spin.is_nan(), "HitSpinRate NA");
    assert_eq!(second.pitch_spin, 0.0, "SpinAxis '-': pitch spin assumed 0");
    assert_eq!(report.assumed.get("pitch_spin"), Some(&1));
}

#[test]
fn bad_values_are_refused_row_by_row_with_their_lines() {
    let tmp = tempfile::tempdir().unwrap();
    let report = import(&["trackman_bad.csv"], &tmp.path().join("bad")).unwrap();
    assert_eq!(report.swings, 1, "only the last row is sound");
    let refused = report.refused.join("\n");
    assert!(refused.contains("line 2: exit speed gives -42.") && refused.contains("out of range"), "{refused}");
    assert!(refused.contains("line 3: Angle = \"high\" is not a number"), "{refused}");
    assert!(refused.contains("line 4: ZoneSpeed gives 57.22"), "128 mph, km/h written as mph: {refused}");
    assert_eq!(report.skipped.get("ZoneSpeed not measured"), Some(&1));
}

#[test]
fn statcast_kinematics_and_bat_speed() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("savant");
    let report = import(&["statcast_search.csv"], &bag).unwrap();
    assert_eq!(report.files[0].format, Format::Statcast);
    assert_eq!(report.swings, 3, "single, foul, field out");
    assert_eq!(report.skipped.get("no ball hit (call \"ball\")"), Some(&1));
    assert_eq!(report.skipped.get("no ball hit (call \"swinging_strike\")"), Some(&1));
    let inputs = read_inputs(&bag).unwrap();
    let single = &inputs.swings[0].1;
    // Row 1 was built from a crossing at t = 0.40 s: v = (6 − 4, −130 + 0.4·42.7083, −4 − 8) ft/s,
    // |v| = 113.5701 ft/s = 34.61617 m/s, descent atan(12/112.9167) = 6.0662° (not release_speed's 95.1 mph).
    assert!(close(single.ball_speed, 34.61617, 1e-5), "{}", single.ball_speed);
    assert!(close(single.pitch_angle.to_degrees(), 6.06623, 1e-4), "{}", single.pitch_angle.to_degrees());
    assert!(close(single.measured_exit_speed, 100.2 * 0.44704, 1e-12));
    assert!(close(single.attack_angle.to_degrees(), 12.0, 1e-12));
    assert!(single.measured_spin.is_nan(), "no batted-ball spin in the search CSV");
    // bat_speed 74.5 mph 6 in from the head, turning about the default batter's pivot (the knob).
    let mp = Bat::preset("r161").unwrap().mass_properties();
    let speed_at = |z: f64| single.bat_cm_speed + single.bat_angular_speed * (z - mp.center_of_mass);
    assert!(close(speed_at(mp.length - 0.1524), 74.5 * 0.44704, 1e-9));
    assert!(close(speed_at(0.0), 0.0, 1e-9));
    // The foul had no bat tracking (NA): the batter's swing, assumed.
    assert_eq!(report.assumed.get("bat_speed"), Some(&2));
    // The out without a launch_speed is a swing with nothing measured.
    assert!(inputs.swings[2].1.measured_exit_speed.is_nan());
    // game_date 2025-06-01 + 21 at-bats × 60 s + pitch 3.
    assert_eq!(single.header.stamp.sec, 1_748_736_000 + 21 * 60 + 3);
}

#[test]
fn unknown_headers_directories_and_fifos_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let other = tmp.path().join("other.csv");
    std::fs::write(&other, "date,speed\n2025-01-01,90\n").unwrap();
    let err = import_files(&[other], &tmp.path().join("x"), &options()).unwrap_err().to_string();
    assert!(err.contains("matches no known export"), "{err}");
    assert!(err.contains("trackman needs PitchCall, ZoneSpeed") && err.contains("statcast needs game_date"), "{err}");

    let err = import_files(&[tmp.path().to_path_buf()], &tmp.path().join("y"), &options()).unwrap_err();
    assert!(err.to_string().contains("a directory, not a regular file"), "{err}");

    let fifo = tmp.path().join("pipe.csv");
    let status = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(status.success());
    let err = import_files(&[fifo], &tmp.path().join("z"), &options()).unwrap_err();
    assert!(err.to_string().contains("a FIFO, not a regular file"), "{err}");
    assert!(!tmp.path().join("x").exists() && !tmp.path().join("z").exists(), "nothing written");
}

#[test]
fn a_large_export_streams_row_by_row() {
    // 200,000 rows (≈ 60 MB) of the TrackMan layout through one record buffer: the bag holds every swing.
    let tmp = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(data("trackman_game.csv")).unwrap();
    let mut lines = text.split("\r\n");
    let header = lines.next().unwrap();
    let in_play = lines.find(|l| l.contains(",InPlay,") && l.contains("95.04375")).unwrap();
    let big = tmp.path().join("big.csv");
    {
        use std::io::Write;
        let mut f = std::io::BufWriter::new(std::fs::File::create(&big).unwrap());
        write!(f, "{header}\r\n").unwrap();
        for _ in 0..200_000 {
            write!(f, "{in_play}\r\n").unwrap();
        }
    }
    let report = import_files(&[big], &tmp.path().join("big"), &options()).unwrap();
    assert_eq!(report.swings, 200_000);
}

#[test]
fn another_trackers_export_through_a_column_map() {
    use sweetspot::import::mapped::ColumnMap;
    let tmp = tempfile::tempdir().unwrap();
    let map = ColumnMap::load(&data("mapped_session.toml")).unwrap();
    let options = ImportOptions { map: Some(map), ..options() };
    let bag = tmp.path().join("mapped");
    let report = import_files(&[data("mapped_session.csv")], &bag, &options).unwrap();
    assert_eq!(report.swings, 1);
    assert_eq!(report.skipped.get("no ball hit (call \"no exit speed\")"), Some(&1));
    assert!(report.refused[0].contains("line 4: pitch_speed = \"fast\" is not a number"), "{:?}", report.refused);
    let swing = &read_inputs(&bag).unwrap().swings[0].1;
    // By hand: 130 km/h = 36.1111 m/s; 95 mph = 42.4688 m/s; 20° = 0.349066 rad; 2500 rpm = 261.799 rad/s.
    assert!(close(swing.ball_speed, 36.1111, 1e-4), "{}", swing.ball_speed);
    assert!(close(swing.measured_exit_speed, 42.4688, 1e-9));
    assert!(close(swing.measured_launch_angle, 0.349066, 1e-6));
    assert!(close(swing.measured_spin, 261.799, 1e-3));
    // 32.0 m/s 6 in from the head, split about the knob.
    let mp = Bat::preset("r161").unwrap().mass_properties();
    let at = swing.bat_cm_speed + swing.bat_angular_speed * (mp.length - 0.1524 - mp.center_of_mass);
    assert!(close(at, 32.0, 1e-9));
    assert_eq!(swing.header.stamp.sec, 1_751_652_000);
    // A map naming an unknown quantity or unit is refused with what is allowed.
    let bad: Result<ColumnMap, _> = toml::from_str(
        "name = \"x\"\n[columns]\nexit_speed = \"EV\"\npitch_speed = \"PV\"\n[units]\nexit_speed = \"knots\"\n",
    );
    assert!(bad.unwrap().check().unwrap_err().contains("unit 'knots'"));
}

#[test]
fn statcast_bat_tracking_gives_a_batter_file_that_compare_reads() {
    let tmp = tempfile::tempdir().unwrap();
    let bin = env!("CARGO_BIN_EXE_sweetspot");
    let batters = tmp.path().join("batters");
    let out = Command::new(bin)
        .arg("import")
        .arg(data("statcast_search.csv"))
        .arg("-o")
        .arg(tmp.path().join("savant"))
        .arg("--batter-out")
        .arg(&batters)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let file = batters.join("batter_100001.toml");
    let spec: toml::Value = toml::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    // Batter 100001's rows with bat tracking: 74.5 mph (the single) and 71.0 mph (the swing and miss), swing
    // lengths 7.4 and 7.1 ft: means 72.75 mph = 32.52216 m/s and 7.25 ft = 2.2098 m.
    assert!(close(spec["bat_speed"].as_float().unwrap(), 32.52216, 1e-9), "{spec}");
    assert!(close(spec["swing_length"].as_float().unwrap(), 2.2098, 1e-12), "{spec}");
    assert_eq!(spec["reference_bat"].as_str(), Some("r161"));
    let out = Command::new(bin).args(["compare", "--bats", "r161,torpedo", "--batter"]).arg(&file).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}
