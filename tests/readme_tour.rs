//! The README's five-minute tour, sections 2 (node, publisher, listener) and 3 (the bag), run exactly as
//! written: every command line of their `sh` blocks goes to `sh -c` unchanged (only its trailing `# comment`
//! is dropped), with the built `sweetspot` first on PATH, in a fresh directory where the node writes its bag.
//! A README line that no longer works for a user fails here.

mod support;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// DDS domain of this test (unique among the suite's tests).
const DOMAIN: u16 = 221;
/// Only turns a hang into a failure; never a speed assertion.
const LIMIT: Duration = Duration::from_secs(120);

/// The swings a user has in `swings.csv`: header plus one row per swing.
const SWINGS_CSV: &str = "bat_id,ball_speed,bat_cm_speed,bat_angular_speed,impact_z
mine,40,25,45,0.62
r161,38,27,40,0.68
r161,42,24,50,0.58
";

/// The command lines of the tour's sections 2 and 3, in README order.
struct Tour {
    node_publisher_listener: Vec<String>,
    bag: Vec<String>,
}

/// Drops a trailing `# comment` (a `#` after whitespace, outside quotes) and the blanks before it.
fn strip_comment(line: &str) -> &str {
    let mut quote: Option<char> = None;
    let mut previous = ' ';
    for (i, c) in line.char_indices() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '\'' || c == '"' => quote = Some(c),
            None if c == '#' && previous.is_whitespace() => return line[..i].trim_end(),
            None => {}
        }
        previous = c;
    }
    line.trim_end()
}

/// Extracts the `sh` blocks between "**2. Node, publisher, listener**" and "**4. Figures.**", split at
/// "**3. The bag.**".
fn tour(readme: &str) -> Tour {
    let start = readme.find("**2. Node, publisher, listener**").expect("README has tour section 2");
    let bag_start = readme.find("**3. The bag.**").expect("README has tour section 3");
    let end = readme.find("**4. Figures.**").expect("README has tour section 4");
    assert!(start < bag_start && bag_start < end, "tour sections out of order");
    let commands = |text: &str| {
        let mut out = Vec::new();
        let mut in_sh = false;
        for line in text.lines() {
            let trimmed = line.trim();
            if trimmed.starts_with("```") {
                in_sh = !in_sh && trimmed == "```sh";
                continue;
            }
            if in_sh {
                let command = strip_comment(line);
                if !command.trim().is_empty() {
                    out.push(command.to_string());
                }
            }
        }
        out
    };
    Tour { node_publisher_listener: commands(&readme[start..bag_start]), bag: commands(&readme[bag_start..end]) }
}

/// `sh -c LINE` in `dir`, as a user's terminal would run it: `sweetspot` first on PATH, the tour's
/// loopback-only discovery, this test's domain, and its own process group (Ctrl-C goes to the group).
fn shell(line: &str, dir: &Path) -> Command {
    use std::os::unix::process::CommandExt;
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_sweetspot")).parent().expect("binary directory");
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut dirs = vec![bin_dir.to_path_buf()];
    dirs.extend(std::env::split_paths(&path));
    let mut c = Command::new("sh");
    c.arg("-c").arg(line).current_dir(dir).env("PATH", std::env::join_paths(dirs).expect("PATH"));
    support::dds_env(&mut c, DOMAIN);
    c.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).process_group(0);
    c
}

/// A started tour line with its output collected on the side.
struct Running {
    line: String,
    child: Child,
    stdout: Option<JoinHandle<String>>,
    stderr: Option<JoinHandle<String>>,
}

/// What a finished line did.
struct Finished {
    status: ExitStatus,
    stdout: String,
    stderr: String,
}

fn drain(mut pipe: impl Read + Send + 'static) -> JoinHandle<String> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = pipe.read_to_end(&mut bytes);
        String::from_utf8_lossy(&bytes).into_owned()
    })
}

impl Running {
    fn start(line: &str, dir: &Path) -> Running {
        let mut child = shell(line, dir).spawn().unwrap_or_else(|e| panic!("cannot start `{line}`: {e}"));
        let stdout = Some(drain(child.stdout.take().expect("stdout")));
        let stderr = Some(drain(child.stderr.take().expect("stderr")));
        Running { line: line.to_string(), child, stdout, stderr }
    }

    /// The process running the command: the shell's child, or the shell itself when it exec'd the command.
    fn command_pid(&self) -> u32 {
        let shell = self.child.id();
        let children = std::fs::read_to_string(format!("/proc/{shell}/task/{shell}/children")).unwrap_or_default();
        children.split_whitespace().next().and_then(|p| p.parse().ok()).unwrap_or(shell)
    }

    /// Ctrl-C at the command's terminal: SIGINT to the command. (An interactive shell keeps its foreground job
    /// in a process group of its own; `sh -c` does not, so signalling its group would kill the shell first
    /// and lose the command's exit status.)
    fn interrupt(&self) {
        let pid = self.command_pid().to_string();
        let status = Command::new("kill").args(["-INT", &pid]).status().expect("kill");
        assert!(status.success(), "kill -INT {pid} failed");
    }

    /// Waits for the exit (killing the group after [`LIMIT`], then failing).
    fn finish(mut self) -> Finished {
        let started = Instant::now();
        let status = loop {
            if let Some(status) = self.child.try_wait().expect("try_wait") {
                break status;
            }
            if started.elapsed() > LIMIT {
                let group = format!("-{}", self.child.id());
                let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
                let _ = self.child.wait();
                let stderr = self.stderr.take().map(|h| h.join().unwrap_or_default()).unwrap_or_default();
                panic!("`{}` still running after {LIMIT:?}; stderr:\n{stderr}", self.line);
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        let stdout = self.stdout.take().map(|h| h.join().unwrap_or_default()).unwrap_or_default();
        let stderr = self.stderr.take().map(|h| h.join().unwrap_or_default()).unwrap_or_default();
        Finished { status, stdout, stderr }
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        if self.child.try_wait().ok().flatten().is_none() {
            let group = format!("-{}", self.child.id());
            let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
            let _ = self.child.wait();
        }
    }
}

/// Runs `line` to the end and asserts exit status 0; returns what it printed.
fn run_ok(line: &str, dir: &Path) -> Finished {
    let done = Running::start(line, dir).finish();
    assert!(
        done.status.success(),
        "README line `{line}` failed ({}):\nstdout:\n{}\nstderr:\n{}",
        done.status,
        done.stdout,
        done.stderr
    );
    assert!(!done.stderr.contains("panicked"), "`{line}` panicked:\n{}", done.stderr);
    done
}

/// The one line of `lines` that starts with `prefix` (the README names each step once).
fn take_line(lines: &mut Vec<String>, prefix: &str) -> String {
    let i = lines
        .iter()
        .position(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no README tour line starts with `{prefix}`: {lines:?}"));
    lines.remove(i)
}

#[test]
fn comments_are_stripped_outside_quotes_only() {
    assert_eq!(strip_comment("sweetspot node      # records to bags/"), "sweetspot node");
    assert_eq!(
        strip_comment("sweetspot pub swing '{a: \"#x\"}' -1   # the form"),
        "sweetspot pub swing '{a: \"#x\"}' -1"
    );
    assert_eq!(strip_comment("echo a#b"), "echo a#b");
}

#[test]
fn readme_tour_runs_as_written() {
    support::require_isolated_network();
    let readme = std::fs::read_to_string(support::repo().join("README.md")).expect("README.md");
    let Tour { node_publisher_listener: mut section2, bag: section3 } = tour(&readme);
    assert!(
        section2.len() + section3.len() >= 10,
        "found only {} + {} command lines in the tour",
        section2.len(),
        section3.len()
    );
    let temp = tempfile::tempdir().expect("temp dir");
    let dir: PathBuf = temp.path().to_path_buf();

    // `pub swing --file swings.csv` reads a file the user already has: one written in the CSV form `pub --help`
    // documents (one column per Swing field, a row per swing).
    std::fs::write(dir.join("swings.csv"), SWINGS_CSV).expect("swings.csv");

    // Section 2: the node and the listener in their own "terminals", then every publisher in order.
    let node_line = take_line(&mut section2, "sweetspot node");
    let echo_line = take_line(&mut section2, "sweetspot echo exit_velocity");
    assert!(section2.iter().all(|l| l.starts_with("sweetspot pub ")), "unexpected tour lines: {section2:?}");
    assert!(section2.len() >= 4, "the tour publishes bat, swings and a file: {section2:?}");
    // One swing per inline `pub` of a swing, one per row of swings.csv.
    let swings_published = section2
        .iter()
        .filter(|l| l.contains("swing"))
        .map(|l| if l.contains("--file swings.csv") { SWINGS_CSV.lines().count() - 1 } else { 1 })
        .sum::<usize>();
    let node = Running::start(&node_line, &dir);
    let echo = Running::start(&echo_line, &dir);
    for line in &section2 {
        let done = run_ok(line, &dir);
        eprintln!("$ {line}\n{}{}", done.stdout, done.stderr);
    }

    // "Stop the node with Ctrl-C (the bag is finished with its summary)".
    node.interrupt();
    let node = node.finish();
    assert!(node.status.success(), "`{node_line}` did not exit 0 on Ctrl-C ({}):\n{}", node.status, node.stderr);
    echo.interrupt();
    let echo = echo.finish();
    assert!(echo.status.success(), "`{echo_line}` did not exit 0 on Ctrl-C ({}):\n{}", echo.status, echo.stderr);
    eprintln!("$ {echo_line}\n{}{}", echo.stdout, echo.stderr);
    let exit_speeds: Vec<f64> = echo
        .stdout
        .lines()
        .filter_map(|l| l.trim().strip_prefix("exit_speed:"))
        .filter_map(|v| v.trim().parse().ok())
        .filter(|v: &f64| v.is_finite() && *v > 0.0)
        .collect();
    assert!(
        !exit_speeds.is_empty(),
        "`{echo_line}` printed no exit velocity for the published swings:\n{}\nstderr:\n{}",
        echo.stdout,
        echo.stderr
    );
    let bags: Vec<_> = std::fs::read_dir(dir.join("bags"))
        .expect("the node wrote bags/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("sweetspot_"))
        .collect();
    assert_eq!(bags.len(), 1, "one bag from the node in bags/: {bags:?}");

    // Section 3: every bag command on that bag.
    for line in &section3 {
        let done = run_ok(line, &dir);
        let printed = format!("{}{}", done.stdout, done.stderr);
        eprintln!("$ {line}\n{printed}");
        assert!(!printed.trim().is_empty(), "`{line}` printed nothing");
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.get(2).copied() {
            Some("info") => assert!(done.stdout.contains("/swing"), "`{line}` does not list /swing:\n{printed}"),
            Some("replay") if !line.contains("--bat") => {
                let summary = printed.lines().find(|l| l.contains(" swings: ")).unwrap_or_default();
                let (swings, rest) = summary.split_once(" swings: ").unwrap_or_default();
                assert!(
                    rest.starts_with(&format!("{swings} match, 0 differ")) && swings != "0",
                    "`{line}` does not say every swing matched:\n{printed}"
                )
            }
            Some("replay") => {}
            Some("export") => {
                let csv = std::fs::read_to_string(dir.join("session.csv")).expect("export wrote session.csv");
                let mut rows = csv.lines();
                let header = rows.next().unwrap_or_default();
                assert!(header.contains("exit_speed"), "session.csv header: {header}");
                let status = header.split(',').position(|c| c == "status").expect("session.csv has a status column");
                let statuses: Vec<&str> = rows.map(|r| r.split(',').nth(status).unwrap_or_default()).collect();
                // Every swing the tour publishes is a valid one: answered with status OK (0), none REJECTED.
                assert_eq!(statuses.len(), swings_published, "session.csv rows:\n{csv}");
                assert!(statuses.iter().all(|s| *s == "0"), "a tour swing was not answered OK:\n{csv}");
            }
            Some("play") => {}
            // The node finished its bag on Ctrl-C, so there is nothing to repair (a crashed bag gets a copy).
            Some("recover") => {
                assert!(printed.contains("nothing to recover"), "`{line}` on a finished bag:\n{printed}")
            }
            _ => panic!("unexpected tour line in section 3: `{line}`"),
        }
    }
}
