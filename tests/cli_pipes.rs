//! The bag tools as Unix filters: a reader that closes the pipe early (`| head`) ends them quietly with
//! status 0, CSV is what `bag export` writes without being asked, and a mistyped what-if preset is blamed on
//! its flag. No DDS: these run the binary on the committed golden bag.

mod support;

use std::process::{Command, Stdio};

use support::cli::sweetspot;

const GOLDEN: &str = "bags/golden/sweetspot_golden";

/// Runs `sweetspot ARGS` with stdout a pipe whose reader is already gone (what `| head` leaves once it has
/// its lines), so every write fails with EPIPE; returns the exit code and stderr.
fn run_into_a_closed_pipe(args: &[&str]) -> (Option<i32>, String) {
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    let output = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(args)
        .current_dir(support::repo())
        .stdout(Stdio::from(writer))
        .stderr(Stdio::piped())
        .output()
        .expect("run sweetspot");
    (output.status.code(), String::from_utf8_lossy(&output.stderr).into_owned())
}

#[test]
fn bag_info_into_a_closed_pipe_exits_quietly_with_status_0() {
    let (code, stderr) = run_into_a_closed_pipe(&["bag", "info", GOLDEN]);
    assert_eq!(code, Some(0), "stderr: {stderr}");
    assert!(!stderr.contains("Broken pipe") && !stderr.contains("panicked"), "stderr: {stderr}");
}

#[test]
fn bag_export_to_stdout_into_a_closed_pipe_exits_quietly_with_status_0() {
    let (code, stderr) = run_into_a_closed_pipe(&["bag", "export", GOLDEN]);
    assert_eq!(code, Some(0), "stderr: {stderr}");
    assert!(!stderr.contains("Broken pipe") && !stderr.contains("bad bag"), "stderr: {stderr}");
}

#[test]
fn bag_export_writes_csv_without_being_asked() {
    let run = sweetspot(&["bag", "export", GOLDEN]);
    assert!(run.status_ok, "stderr: {}", run.stderr);
    let header = run.stdout.lines().next().expect("a header line");
    assert!(header.starts_with("namespace,swing_id,"), "{header}");
    let with_flag = sweetspot(&["bag", "export", "--csv", GOLDEN]);
    assert_eq!(with_flag.stdout, run.stdout);
}

#[test]
fn a_mistyped_what_if_preset_is_blamed_on_its_flag_not_on_the_bag() {
    let run = sweetspot(&["bag", "replay", GOLDEN, "--bat", "alumnium"]);
    assert!(!run.status_ok);
    assert!(run.stderr.contains("--bat 'alumnium' is not a preset"), "{}", run.stderr);
    assert!(run.stderr.contains("aluminum"), "lists the presets: {}", run.stderr);
    assert!(!run.stderr.contains("bad bag"), "{}", run.stderr);
}

/// `| head -1` on every command that prints without DDS: each ends with status 0, no panic, no "Broken pipe".
#[test]
fn every_printing_command_into_a_closed_pipe_exits_quietly_with_status_0() {
    let dir = tempfile::tempdir().expect("tempdir");
    let figures = dir.path().join("figs");
    let figures = figures.to_str().expect("utf-8 path");
    let commands: Vec<Vec<&str>> = vec![
        vec!["modes", "--bat", "r161"],
        vec!["modes", "--bat", "r161", "--json"],
        vec!["simulate", "--bat", "r161", "--impact-z", "0.6,0.65,0.7"],
        vec!["simulate", "--bat", "r161", "--undercut", "0.01", "--pitch-spin", "1500"],
        vec!["sweep", "--bat", "r161", "--points", "20"],
        vec!["bbcor", "--bat", "aluminum"],
        vec!["compare", "--bats", "r161,aluminum", "--modes", "4"],
        vec!["figures", figures, "--format", "svg"],
        vec!["bag", "replay", GOLDEN],
        vec!["bag", "info", GOLDEN, "--json"],
        vec!["--help"],
        vec!["calibrate", "--help"],
    ];
    for args in commands {
        let (code, stderr) = run_into_a_closed_pipe(&args);
        assert_eq!(code, Some(0), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked") && !stderr.contains("Broken pipe"), "{args:?}: {stderr}");
    }
}
