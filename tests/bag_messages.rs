//! Real sweetspot_msgs recorded with the Recorder: every message decodes from the embedded schemas alone
//! (mcap-ros2-support), through metadata.yaml + stored msgdefs (rosbags), and `bag export --csv` joins them.

mod support;

use std::process::Command;

use support::bag::*;
use sweetspot::bag::{RecordedQos, Recorder, RecorderConfig, TopicInfo};
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::encode_cdr;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};

const T0: u64 = 1_763_700_000_000_000_000;

fn header(ns: u64) -> Header {
    Header {
        stamp: Time { sec: (ns / 1_000_000_000) as i32, nanosec: (ns % 1_000_000_000) as u32 },
        frame_id: "bat".into(),
    }
}

fn swing(i: u64) -> Swing {
    Swing {
        header: header(T0 + i * 10_000_000),
        swing_id: i,
        bat_id: "r161".into(),
        ball_id: "mlb".into(),
        ball_speed: 40.0 + i as f64 * 0.25,
        bat_cm_speed: 25.0,
        bat_angular_speed: 50.0 + i as f64,
        impact_z: 0.70 - 0.001 * i as f64,
        measured_exit_speed: if i.is_multiple_of(2) { f64::NAN } else { 45.5 },
        ..Swing::default()
    }
}

/// Records a small but complete run of one rig: params, 40 swings, their outputs (swing 7 never answered),
/// and one output whose swing is not recorded.
fn record_run(dir: &std::path::Path) {
    const LATCHED: RecordedQos = RecordedQos { reliable: true, transient_local: true, depth: 1 };
    const RELIABLE: RecordedQos = RecordedQos { reliable: true, transient_local: false, depth: 100 };
    let r = Recorder::start(RecorderConfig::new(dir)).unwrap();
    let bat = r.register_topic(TopicInfo::of::<BatParams>("/rig/bat_params", LATCHED)).unwrap();
    let ball = r.register_topic(TopicInfo::of::<BallParams>("/rig/ball_params", LATCHED)).unwrap();
    let sw = r.register_topic(TopicInfo::of::<Swing>("/rig/swing", RELIABLE)).unwrap();
    let ev = r.register_topic(TopicInfo::of::<ExitVelocity>("/rig/exit_velocity", RELIABLE)).unwrap();
    let me = r.register_topic(TopicInfo::of::<ModalEnergies>("/rig/modal_energies", RELIABLE)).unwrap();
    let ss = r.register_topic(TopicInfo::of::<SweetSpot>("/rig/sweet_spot", LATCHED)).unwrap();
    let bat_msg = BatParams {
        header: header(T0),
        bat_id: "r161".into(),
        preset: "r161".into(),
        station_z: vec![0.0, 0.5, 0.84],
        outer_radius: vec![0.0125, 0.02, 0.0335],
        inner_radius: vec![],
        density: 649.0,
        youngs_modulus: 1.814e10,
        shear_modulus: 1.0e9,
        max_modes: 10,
        ..BatParams::default()
    };
    assert!(r.record(bat, encode_cdr(&bat_msg).unwrap(), T0, T0));
    let ball_msg = BallParams {
        header: header(T0),
        ball_id: "mlb".into(),
        mass: 0.145,
        radius: 0.0366,
        cor: 0.5,
        stiffness: 7.0e6,
        exponent: 1.5,
        tangential_cor: 0.3,
        friction: 0.5,
        moment_of_inertia: 7.4e-5,
        cor_speed_exponent: 0.068,
        cor_reference_speed: 1.0,
    };
    assert!(r.record(ball, encode_cdr(&ball_msg).unwrap(), T0, T0));
    let spot = SweetSpot {
        header: header(T0),
        bat_id: "r161".into(),
        max_exit_speed_z: 0.71,
        frequency: vec![177.0, 583.0],
        ..SweetSpot::default()
    };
    assert!(r.record(ss, encode_cdr(&spot).unwrap(), T0 + 1, T0));
    for i in 0..40u64 {
        let s = swing(i);
        let t = T0 + 1_000_000 + i * 10_000_000;
        assert!(r.record(sw, encode_cdr(&s).unwrap(), t, t - 1_000_000));
        if i == 7 {
            continue;
        }
        let out = ExitVelocity {
            header: s.header.clone(),
            swing_id: i,
            bat_id: "r161".into(),
            ball_id: "mlb".into(),
            status: ExitVelocity::STATUS_OK,
            impact_z: s.impact_z,
            exit_speed: 30.0 + i as f64 / 8.0,
            rigid_exit_speed: 32.0,
            effective_cor: 0.45,
            collision_efficiency: 0.2,
            contact_time: 6.5e-4,
            peak_force: 2.0e4,
            impulse: 12.0,
            max_compression: 0.012,
            measured_exit_speed: s.measured_exit_speed,
            residual: if i.is_multiple_of(2) { f64::NAN } else { 0.5 },
            message: String::new(),
            ..ExitVelocity::default()
        };
        assert!(r.record(ev, encode_cdr(&out).unwrap(), t + 500_000, t - 1_000_000));
        let energies = ModalEnergies {
            header: s.header.clone(),
            swing_id: i,
            bat_id: "r161".into(),
            frequency: vec![177.0, 583.0, 1179.0],
            energy: vec![1.5, 0.25 + i as f64, 0.125],
            fraction: vec![0.8, 0.15, 0.05],
            vibration_energy: 1.875 + i as f64,
            hysteresis_loss: 40.0,
            energy_residual: 1e-9,
            ..ModalEnergies::default()
        };
        assert!(r.record(me, encode_cdr(&energies).unwrap(), t + 500_000, t - 1_000_000));
    }
    // An answer whose swing was not recorded (e.g. recording started late).
    let orphan = ExitVelocity { swing_id: 999, ..ExitVelocity::default() };
    assert!(r.record(ev, encode_cdr(&orphan).unwrap(), T0 + 900_000_000, T0));
    let stats = r.finish().unwrap();
    assert_eq!(stats.written, 3 + 40 + 39 * 2 + 1);
}

#[test]
fn every_sweetspot_message_decodes_in_independent_readers() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rig");
    record_run(&dir);
    let verdict = python_check_bag(&dir);
    for reader in ["mcap", "rosbags"] {
        let t = &verdict[reader]["topics"];
        assert_eq!(t["/rig/swing"]["count"], 40, "{reader}");
        assert_eq!(t["/rig/exit_velocity"]["count"], 40, "{reader}");
        assert_eq!(t["/rig/modal_energies"]["count"], 39, "{reader}");
        assert_eq!(t["/rig/bat_params"]["count"], 1, "{reader}");
        assert_eq!(t["/rig/ball_params"]["count"], 1, "{reader}");
        assert_eq!(t["/rig/sweet_spot"]["count"], 1, "{reader}");
        assert_eq!(t["/rig/swing"]["type"], "sweetspot_msgs/msg/Swing", "{reader}");
        let first = &t["/rig/swing"]["first"];
        assert_eq!(first["swing_id"], 0, "{reader}");
        assert_eq!(first["ball_speed"], 40.0, "{reader}");
        assert_eq!(first["header"]["stamp"]["sec"], (T0 / 1_000_000_000) as i64, "{reader}");
        assert_eq!(first["header"]["frame_id"], "bat", "{reader}");
        let last = &t["/rig/swing"]["last"];
        assert_eq!(last["swing_id"], 39, "{reader}");
        assert_eq!(last["bat_angular_speed"], 89.0, "{reader}");
        let me = &t["/rig/modal_energies"]["last"];
        assert_eq!(me["energy"], serde_json::json!([1.5, 39.25, 0.125]), "{reader}");
        let bat = &t["/rig/bat_params"]["first"];
        assert_eq!(bat["station_z"], serde_json::json!([0.0, 0.5, 0.84]), "{reader}");
        assert_eq!(bat["max_modes"], 10, "{reader}");
        assert_eq!(t["/rig/ball_params"]["first"]["stiffness"], 7.0e6, "{reader}");
        // The appended contact fields, read through each reader's own schema handling.
        assert_eq!(t["/rig/ball_params"]["first"]["moment_of_inertia"], 7.4e-5, "{reader}");
    }
    assert_eq!(verdict["rosbags"]["topics"]["/rig/bat_params"]["durability"], "transient_local");
}

#[test]
fn export_csv_has_one_row_per_swing_joined_with_its_outputs() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rig");
    record_run(&dir);
    let csv_path = tmp.path().join("swings.csv");
    let out =
        Command::new(sweetspot_bin()).args(["bag", "export", "--csv", "-o"]).arg(&csv_path).arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let note = String::from_utf8_lossy(&out.stderr);
    assert!(
        note.contains("exported 40 swings (39 with ExitVelocity, 39 with ModalEnergies; 1 outputs without their swing"),
        "{note}"
    );
    let mut reader = csv::Reader::from_path(&csv_path).unwrap();
    let headers = reader.headers().unwrap().clone();
    let col = |name: &str| headers.iter().position(|h| h == name).unwrap_or_else(|| panic!("column {name}"));
    assert!(headers.iter().any(|h| h == "mode3_fraction"));
    let rows: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 40);
    for (i, row) in rows.iter().enumerate() {
        let s = swing(i as u64);
        assert_eq!(row[col("namespace")].to_string(), "/rig", "one node in the bag, its namespace that of /rig/swing");
        assert_eq!(row[col("swing_id")].parse::<u64>().unwrap(), i as u64);
        assert_eq!(row[col("ball_speed")].parse::<f64>().unwrap(), s.ball_speed);
        assert_eq!(row[col("impact_z")].parse::<f64>().unwrap(), s.impact_z);
        if i == 7 {
            assert_eq!(&row[col("exit_speed")], "", "swing 7 was never answered");
            assert_eq!(&row[col("mode2_energy")], "");
        } else {
            assert_eq!(row[col("exit_speed")].parse::<f64>().unwrap(), 30.0 + i as f64 / 8.0);
            assert_eq!(row[col("mode2_energy")].parse::<f64>().unwrap(), 0.25 + i as f64);
            assert_eq!(row[col("status")].to_string(), "0");
        }
    }
    assert_eq!(rows[0][col("measured_exit_speed")].to_string(), "NaN");
    assert_eq!(rows[1][col("measured_exit_speed")].parse::<f64>().unwrap(), 45.5);
}
