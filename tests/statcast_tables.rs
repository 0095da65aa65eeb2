//! The committed Statcast and radar tables (validation/statcast_*.csv, mlb2018_radar_spin.csv) are what `scripts/statcast_tables.py` derives from
//! the shared season files: re-derived here when ../shared/reference/statcast/ is present (skipped, saying so,
//! when it is not), so a hand-edited or stale table fails. The script needs the Python standard library only:
//! $SWEETSPOT_PYTHON, else `python3` on PATH.

use std::path::PathBuf;
use std::process::Command;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn committed_tables_equal_a_fresh_derivation_from_the_season_files() {
    let shared = repo().join("../shared/reference/statcast");
    if !shared.join("statcast_2024_in_play_bat_tracking.csv.gz").is_file() {
        eprintln!("skipped: {} is absent, the tables cannot be re-derived here", shared.display());
        return;
    }
    let python = std::env::var_os("SWEETSPOT_PYTHON").map(PathBuf::from).unwrap_or_else(|| "python3".into());
    let out = Command::new(&python)
        .arg(repo().join("scripts/statcast_tables.py"))
        .arg("--check")
        .env("SWEETSPOT_STATCAST_DIR", &shared)
        .output()
        .unwrap_or_else(|e| panic!("running {}: {e}", python.display()));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}{stderr}");
    for name in ["statcast_q.csv", "statcast_exit_undercut.csv", "statcast_attack.csv"] {
        assert!(stdout.contains(name), "{name} not checked: {stdout}");
    }
}

/// The radar table (validation/mlb2018_radar_spin.csv) is what `scripts/radar_tables.py` derives from the shared
/// TrackMan and Statcast files (skipped, saying so, when they are absent).
#[test]
fn committed_radar_table_equals_a_fresh_derivation() {
    let reference = repo().join("../shared/reference");
    if !reference.join("trackman/mlb_2018_batted_ball_spin.csv.gz").is_file() {
        eprintln!("skipped: {} is absent, the radar table cannot be re-derived here", reference.display());
        return;
    }
    let python = std::env::var_os("SWEETSPOT_PYTHON").map(PathBuf::from).unwrap_or_else(|| "python3".into());
    let out = Command::new(&python)
        .arg(repo().join("scripts/radar_tables.py"))
        .arg("--check")
        .env("SWEETSPOT_REFERENCE_DIR", &reference)
        .output()
        .unwrap_or_else(|e| panic!("running {}: {e}", python.display()));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}{stderr}");
    assert!(stdout.contains("mlb2018_radar_spin.csv matches"), "{stdout}");
}

/// The q table's own arithmetic, checked without the script: every bin's percentiles are ordered, the halves
/// add up to the season, and the season's first look in the shared README (bats 65–80 mph: 97th/99th/99.8th
/// 0.224/0.233/0.239) is bracketed by the 65–70 … 75–80 bins.
#[test]
fn the_q_table_is_consistent_with_itself_and_with_the_first_look() {
    let text = std::fs::read_to_string(repo().join("validation/statcast_q.csv")).unwrap();
    let bins = sweetspot::validate::statcast::parse_q(&text).unwrap();
    for b in &bins {
        assert!(b.q_p50 <= b.q_p97 && b.q_p97 <= b.q_p99 && b.q_p99 <= b.q_p99_8, "{b:?}");
        assert!(b.low < b.high && b.count > 0, "{b:?}");
    }
    for b in bins.iter().filter(|b| b.half == "all") {
        let part = |half: &str| bins.iter().find(|o| o.half == half && o.by == b.by && o.low == b.low);
        if let (Some(odd), Some(even)) = (part("odd"), part("even")) {
            assert_eq!(odd.count + even.count, b.count, "{b:?}");
        }
    }
    let central: Vec<_> =
        bins.iter().filter(|b| b.by == "bat" && b.half == "all" && (65.0..80.0).contains(&b.low)).collect();
    assert_eq!(central.len(), 3);
    for (p, first_look) in [(0usize, 0.224), (1, 0.233), (2, 0.239)] {
        let v = |b: &&sweetspot::validate::statcast::QBin| [b.q_p97, b.q_p99, b.q_p99_8][p];
        let lo = central.iter().map(v).fold(f64::INFINITY, f64::min);
        let hi = central.iter().map(v).fold(f64::NEG_INFINITY, f64::max);
        assert!(lo <= first_look && first_look <= hi, "percentile {p}: {first_look} outside {lo}–{hi}");
    }
}
