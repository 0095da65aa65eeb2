//! The golden bag (bags/golden/sweetspot_golden, recorded from the real node over DDS by
//! bags/golden/make_golden.sh) must replay bit-exactly: any change to the physics, the params→model
//! conversion or the node's decisions shows up here. Regenerate it deliberately when such a change is intended.

mod support;

use std::path::PathBuf;
use std::process::Command;

use support::bag::*;
use sweetspot::bag::replay::{recorded_settings, replay, Verdict};

fn golden() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("bags/golden/sweetspot_golden")
}

#[test]
fn golden_bag_replays_bit_exactly() {
    let settings = recorded_settings(&golden()).unwrap();
    let report = replay(&golden(), &settings, &Default::default(), 0.0, |_, _| {}).unwrap();
    let differing: Vec<_> = report.rows.iter().filter(|r| r.verdict != Verdict::Match).collect();
    assert!(
        differing.is_empty(),
        "the golden bag no longer replays exactly — the physics or the node's decisions changed. If intended, \
         regenerate it with bags/golden/make_golden.sh and say why in the commit. Differences: {differing:#?}"
    );
    assert_eq!(report.rows.len(), 10);
    assert_eq!(report.rows.iter().filter(|r| r.replayed_status == 1).count(), 1, "swing 9 asks for an unknown bat");
    let out = Command::new(sweetspot_bin()).args(["bag", "replay"]).arg(golden()).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stdout));
}

#[test]
fn golden_bag_is_small_complete_and_read_by_independent_readers() {
    let size: u64 = std::fs::read_dir(golden()).unwrap().map(|e| e.unwrap().metadata().unwrap().len()).sum();
    assert!(size < 1_000_000, "golden bag is {size} bytes; keep it under 1 MB");
    let info = sweetspot::bag::info::bag_info(&golden()).unwrap();
    assert!(info.complete());
    assert_eq!(info.profile, "ros2");
    let verdict = python_check_bag(&golden());
    for reader in ["mcap", "rosbags"] {
        let t = &verdict[reader]["topics"];
        assert_eq!(t["/golden/swing"]["count"], 10, "{reader}");
        // 10 answers plus the rejection of the malformed BatParams.
        assert_eq!(t["/golden/exit_velocity"]["count"], 11, "{reader}");
        assert_eq!(t["/golden/modal_energies"]["count"], 9, "{reader}");
        assert_eq!(t["/golden/bat/params"]["count"], 2, "{reader}");
    }
}
