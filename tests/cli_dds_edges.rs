//! The DDS commands at their edges, each in the private network namespace (scripts/test) (the documented
//! blocks, the README's calibration among them, run in tests/docs_commands.rs): Ctrl-C on `demo` (a
//! partial report and status 130), duration flags at 1e300 / inf and a node told to split every 1e300 s (no
//! panic: they run until interrupted), `| head -1` on every DDS command that prints, and non-regular files
//! given to `pub --file` and `bag record --qos-profile-overrides-path` (a clear error, no endless read).

mod support;

use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// DDS domain of this test (unique among the suite's tests).
const DOMAIN: u16 = 183;
/// Only turns a hang into a failure; never a speed assertion.
const LIMIT: Duration = Duration::from_secs(300);

/// One test at a time: they share the domain and the default namespaces (a demo must hear only its own rig).
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Takes the domain for one test (a failed test leaves the lock poisoned, not held).
fn domain() -> std::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// `sh -c LINE` in `dir` as a user's terminal runs it: `sweetspot` first on PATH, loopback discovery on this
/// test's domain, its own process group (so a terminal's Ctrl-C can be sent to the group).
fn shell(line: &str, dir: &Path) -> Command {
    shell_in("sh", line, dir)
}

/// [`shell`] with another shell (e.g. `bash` for `pipefail`).
fn shell_in(shell: &str, line: &str, dir: &Path) -> Command {
    use std::os::unix::process::CommandExt;
    let bin_dir = Path::new(support::BIN).parent().expect("binary directory");
    let mut dirs = vec![bin_dir.to_path_buf()];
    dirs.extend(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()));
    let mut c = Command::new(shell);
    c.arg("-c").arg(line).current_dir(dir).env("PATH", std::env::join_paths(dirs).expect("PATH"));
    support::dds_env(&mut c, DOMAIN);
    c.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).process_group(0);
    c
}

/// Waits for `child` (killing its group after [`LIMIT`]); returns (exit code, stdout, stderr).
fn finish(mut child: Child) -> (Option<i32>, String, String) {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            let (mut out, mut err) = (String::new(), String::new());
            child.stdout.take().map(|mut s| s.read_to_string(&mut out));
            child.stderr.take().map(|mut s| s.read_to_string(&mut err));
            return (status.code(), out, err);
        }
        if start.elapsed() > LIMIT {
            let _ = Command::new("kill").args(["-KILL", "--", &format!("-{}", child.id())]).status();
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Runs `line` to its end.
fn run(line: &str, dir: &Path) -> (Option<i32>, String, String) {
    finish(shell(line, dir).spawn().expect("spawn sh"))
}

/// Starts `line` (exec'd by the shell, so the status is the command's own), lets it run `for_how_long`, sends
/// SIGINT to its process group (a terminal's Ctrl-C), and waits for it.
fn interrupt_after(line: &str, dir: &Path, for_how_long: Duration) -> (Option<i32>, String, String) {
    let child = shell(&format!("exec {line}"), dir).spawn().expect("spawn sh");
    std::thread::sleep(for_how_long);
    let _ = Command::new("kill").args(["-INT", "--", &format!("-{}", child.id())]).status();
    finish(child)
}

fn no_panic(line: &str, code: Option<i32>, stderr: &str) {
    assert_ne!(code, Some(101), "{line}: exit 101\n{stderr}");
    assert!(!stderr.contains("panicked"), "{line}: {stderr}");
}

/// Ctrl-C on `demo` (to its process group, node included, as a terminal sends it) stops the session with a
/// partial report and status 130, not "the node exited early".
#[test]
fn ctrl_c_on_demo_gives_a_partial_report_and_130() {
    support::require_isolated_network();
    let _domain = domain();
    let dir = tempfile::tempdir().expect("tempdir");
    let line = "sweetspot demo --swings 100000 --rate 20 --no-figures --out bags";
    let (code, out, err) = interrupt_after(line, dir.path(), Duration::from_secs(25));
    no_panic(line, code, &err);
    assert_eq!(code, Some(130), "stderr:\n{err}\nstdout:\n{out}");
    assert!(err.contains("interrupted after"), "{err}");
    assert!(!err.contains("exited early"), "{err}");
    assert!(out.contains("sweetspot demo —") && out.contains("bag:"), "a partial report: {out}");
}

/// Duration flags at 1e300 and inf, and the node's split time at 1e300: each runs (waiting "for ever")
/// until Ctrl-C, then ends without a panic (a limit at inf is no limit, never refused after parsing).
#[test]
fn huge_durations_run_until_interrupted_without_a_panic() {
    support::require_isolated_network();
    let _domain = domain();
    let dir = tempfile::tempdir().expect("tempdir");
    let golden = support::repo().join("bags/golden/sweetspot_golden");
    let golden = golden.display();
    let lines = [
        "sweetspot pub swing '{}' --timeout 1e300 --keep-alive 1e300".to_string(),
        "sweetspot pub swing '{}' --timeout inf -w 0 --rate 1e300 --times 3 --keep-alive 1e300".to_string(),
        "sweetspot echo swing --timeout 1e300".to_string(),
        "sweetspot echo swing --timeout inf".to_string(),
        "sweetspot rig --wait 1e300 --quiet".to_string(),
        "sweetspot rig --wait inf --quiet".to_string(),
        format!("sweetspot bag play {golden} -q --delay 1e300 --timeout 1e300"),
        format!("sweetspot bag play {golden} -q -r 1e-300 --clock 1e300 --timeout inf"),
        "sweetspot bag record -a -d 1e300 -o rec".to_string(),
        "sweetspot node --ros-args -p record_max_file_duration:=1e300 -p record_path:=node-bags".to_string(),
    ];
    for line in &lines {
        let (code, _, err) = interrupt_after(line, dir.path(), Duration::from_secs(4));
        no_panic(line, code, &err);
        assert!(!err.contains("cannot convert float seconds"), "{line}: {err}");
        assert!(!err.contains("out of range") && !err.contains("must be"), "{line} is accepted: {err}");
    }
    // Refused at parse time, naming the flag (no participant).
    for (line, flag) in [("sweetspot rig --rate 1e-300", "--rate"), ("sweetspot demo --rate 1e-300", "--rate")] {
        let (code, _, err) = run(line, dir.path());
        no_panic(line, code, &err);
        assert_eq!(code, Some(2), "{line}: {err}");
        assert!(err.contains(flag) && err.contains("out of range"), "{line}: {err}");
    }
}

/// `| head -1` on every DDS command that prints: each ends (no endless run into a closed pipe) with status 0
/// and no panic.
#[test]
fn dds_commands_into_head_end_quietly() {
    support::require_isolated_network();
    let _domain = domain();
    let dir = tempfile::tempdir().expect("tempdir");
    let lines = [
        // The rig prints a line per swing, for ever without --count: the closed pipe must end it.
        "sweetspot node --no-record & node=$!; sweetspot rig --rate 50 | head -1; s=$?; kill -INT $node; wait $node; exit $s",
        "sweetspot pub swing '{}' --rate 50 -w 0 | head -1",
        "sweetspot demo --swings 40 --no-figures --out bags | head -1",
        // --no-wait: nothing listens here, and a play nobody heard otherwise fails (exit 1) by design.
        "sweetspot bag play \"$GOLDEN\" -r 10 --no-wait | head -1",
        "sweetspot node --no-record & node=$!; sweetspot rig --rate 50 --quiet & rig=$!; \
         sweetspot echo exit_velocity | head -1; s=$?; kill -INT $rig $node; wait; exit $s",
    ];
    let golden = support::repo().join("bags/golden/sweetspot_golden");
    for line in lines {
        let line = format!("set -o pipefail; {line}");
        let mut c = shell_in("bash", &line, dir.path());
        c.env("GOLDEN", &golden);
        let (code, out, err) = finish(c.spawn().expect("spawn bash"));
        no_panic(&line, code, &err);
        assert_eq!(code, Some(0), "{line}:\n{err}");
        assert_eq!(out.lines().count(), 1, "{line}: {out}");
        assert!(!err.contains("Broken pipe"), "{line}: {err}");
    }
}

/// Non-regular input files are refused by name before anything is read or any participant starts.
#[test]
fn non_regular_inputs_are_refused() {
    support::require_isolated_network();
    let _domain = domain();
    let dir = tempfile::tempdir().expect("tempdir");
    let (code, _, err) = run("mkfifo fifo", dir.path());
    assert_eq!(code, Some(0), "{err}");
    for (line, what) in [
        ("sweetspot pub swing --file /dev/zero -w 0", "'/dev/zero' is a character device"),
        ("sweetspot pub swing --file fifo -w 0", "is a FIFO"),
        ("sweetspot pub swing --file . -w 0", "is a directory"),
        ("sweetspot bag record -a -o r1 --qos-profile-overrides-path /dev/zero", "character device"),
        ("sweetspot bag record -a -o r2 --qos-profile-overrides-path fifo", "is a FIFO"),
        ("sweetspot node --ros-args --params-file /dev/zero", "character device"),
    ] {
        let started = Instant::now();
        let (code, _, err) = run(line, dir.path());
        no_panic(line, code, &err);
        assert_ne!(code, Some(0), "{line}");
        assert!(err.contains(what), "{line}: {err}");
        assert!(started.elapsed() < Duration::from_secs(60), "{line} took {:?}", started.elapsed());
    }
}
