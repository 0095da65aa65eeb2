//! Every command block of README.md, docs/*.md and msgs/sweetspot_msgs/README.md runs as written, from a fresh
//! copy of the repository, twice in a row.
//!
//! A block fenced ```` ```sh ```` (or `bash`, `shell`) is run line by line, each line with `bash -o pipefail -c`
//! in the copy's root (a line ending in `\` continues on the next; full-line comments are skipped); a
//! ```` ```console ```` block runs each `$ ` line, and an example whose shown output starts with `error: ` must
//! fail (docs_cli.rs compares docs/cli.md's shown output). A line whose trailing comment says "until Ctrl-C" is
//! a long-running command a user starts in a terminal of its own (`sweetspot node`, `echo`, `bag record`): it is
//! started in the background, the block's other lines run, and then it gets Ctrl-C (SIGINT) and must exit 0.
//! A block that cannot run here is fenced ```` ```sh no-run: REASON ```` (e.g. it needs a ROS installation);
//! a shell block without a reason, or an unfenced-language block that holds `sweetspot` commands, fails.
//!
//! What stands in for what: the built (debug) `sweetspot` is first on PATH, and `cargo run --release -- ARGS`
//! is run as `sweetspot ARGS` (a release build inside the suite would cost CI minutes); the one line never run
//! is `bash scripts/test`, the suite that runs this test; every line runs on this
//! test's DDS domain with loopback-only discovery, inside the private network namespace `scripts/test` makes.
//! The copy holds the repository's files as a fresh clone would (git's tracked and not-ignored files), so an
//! input a page names must ship with the repository. Any non-zero exit, a hang (no line may take more than
//! [`LIMIT`]) or a panic fails.

mod support;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// DDS domain of this test (unique among the suite's tests).
const DOMAIN: u16 = 223;
/// Only turns a hang into a failure; never a speed assertion.
const LIMIT: Duration = Duration::from_secs(180);
/// The pages whose command blocks are run, relative to the repository (plus every `docs/*.md`).
const PAGES: [&str; 2] = ["README.md", "msgs/sweetspot_msgs/README.md"];

/// How a block is to be treated.
#[derive(Debug, Clone, PartialEq)]
enum Kind {
    /// Shell lines, run one by one.
    Shell,
    /// `$ command` lines, each followed by the output shown for it.
    Console,
    /// Not run, for the reason given.
    NoRun(String),
}

/// One fenced command block of a page.
#[derive(Debug, Clone)]
struct Block {
    page: String,
    /// 1-based line of the opening fence.
    line: usize,
    kind: Kind,
    /// The commands, continuation lines joined; for a console block, whether the example is shown failing.
    commands: Vec<(String, bool)>,
}

/// Drops a trailing `# comment` (a `#` after whitespace, outside quotes) and returns (command, comment).
fn split_comment(line: &str) -> (&str, &str) {
    let mut quote: Option<char> = None;
    let mut previous = ' ';
    for (i, c) in line.char_indices() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '\'' || c == '"' => quote = Some(c),
            None if c == '#' && previous.is_whitespace() => return (line[..i].trim_end(), &line[i + 1..]),
            None => {}
        }
        previous = c;
    }
    (line.trim_end(), "")
}

/// The command blocks of `text` (a page named `page`); Err for a block a user could run that is not marked.
fn blocks(page: &str, text: &str) -> Result<Vec<Block>, String> {
    let mut out = Vec::new();
    let mut lines = text.lines().enumerate();
    while let Some((i, line)) = lines.next() {
        let Some(info) = line.trim_start().strip_prefix("```") else { continue };
        let info = info.trim();
        let (lang, tag) = info.split_once(char::is_whitespace).unwrap_or((info, ""));
        let body: Vec<&str> =
            lines.by_ref().map(|(_, l)| l).take_while(|l| !l.trim_start().starts_with("```")).collect();
        let at = format!("{page}:{}", i + 1);
        let kind = match (lang, tag.trim()) {
            ("sh" | "bash" | "shell", "") => Kind::Shell,
            ("console", "") => Kind::Console,
            ("sh" | "bash" | "shell" | "console", tag) => match tag.strip_prefix("no-run:") {
                Some(reason) if !reason.trim().is_empty() => Kind::NoRun(reason.trim().to_string()),
                _ => return Err(format!("{at}: unknown block tag `{tag}` (run it, or `no-run: REASON`)")),
            },
            ("" | "text", _) => {
                if body.iter().any(|l| l.starts_with("$ ") || l.starts_with("sweetspot ")) {
                    return Err(format!("{at}: a block of commands without a language: fence it ```sh"));
                }
                continue;
            }
            _ => continue,
        };
        let mut commands: Vec<(String, bool)> = Vec::new();
        let mut pending = String::new();
        for l in &body {
            match kind {
                Kind::Console => {
                    if let Some(command) = l.strip_prefix("$ ") {
                        commands.push((command.to_string(), false));
                    } else if l.starts_with("error: ") {
                        if let Some(last) = commands.last_mut() {
                            last.1 = true;
                        }
                    }
                }
                _ => {
                    if l.trim_start().starts_with('#') || l.trim().is_empty() {
                        continue;
                    }
                    match l.strip_suffix('\\') {
                        Some(head) => pending.push_str(head),
                        None => {
                            pending.push_str(l);
                            commands.push((std::mem::take(&mut pending), false));
                        }
                    }
                }
            }
        }
        if commands.is_empty() && !matches!(kind, Kind::NoRun(_)) {
            return Err(format!("{at}: a command block without commands"));
        }
        out.push(Block { page: page.to_string(), line: i + 1, kind, commands });
    }
    Ok(out)
}

/// The line as this test runs it: `cargo run --release -- ARGS` becomes the built `sweetspot ARGS`.
fn as_run(line: &str) -> String {
    match line.trim_start().strip_prefix("cargo run --release -- ") {
        Some(args) => format!("sweetspot {args}"),
        None => line.to_string(),
    }
}

/// The README's second line: the whole test suite, which runs this test (so it is not run from here).
const THE_SUITE: &str = "bash scripts/test";

/// Whether a line is a long-running command started in a terminal of its own.
fn until_ctrl_c(line: &str) -> bool {
    split_comment(line).1.contains("until Ctrl-C")
}

/// Every page whose blocks are run: README.md, docs/*.md (sorted), the messages package's README.
fn pages(repo: &Path) -> Vec<String> {
    let mut docs: Vec<String> = std::fs::read_dir(repo.join("docs"))
        .expect("docs/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    docs.sort();
    let mut all = vec![PAGES[0].to_string()];
    all.extend(docs);
    all.extend(PAGES[1..].iter().map(|p| p.to_string()));
    all
}

/// Copies what a fresh clone holds (git's tracked and not-ignored files) from `repo` into `to`.
fn fresh_clone(repo: &Path, to: &Path) {
    let out = Command::new("git")
        .args(["ls-files", "-z", "--cached", "--others", "--exclude-standard"])
        .current_dir(repo)
        .output()
        .expect("git ls-files");
    assert!(out.status.success(), "git ls-files: {}", String::from_utf8_lossy(&out.stderr));
    for name in out.stdout.split(|b| *b == 0).filter(|n| !n.is_empty()) {
        let name = String::from_utf8_lossy(name).into_owned();
        let from = repo.join(&name);
        if !from.is_file() {
            continue; // deleted in the work tree, or a submodule
        }
        let dest = to.join(&name);
        std::fs::create_dir_all(dest.parent().expect("parent")).expect("mkdir");
        std::fs::copy(&from, &dest).unwrap_or_else(|e| panic!("copy {name}: {e}"));
    }
}

/// `bash -o pipefail -c LINE` in `dir`, as a user's terminal runs it, in a process group of its own.
fn shell(line: &str, dir: &Path, bin: &Path) -> Command {
    use std::os::unix::process::CommandExt;
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut dirs = vec![bin.to_path_buf()];
    dirs.extend(std::env::split_paths(&path));
    let mut c = Command::new("bash");
    c.args(["-o", "pipefail", "-c", line]).current_dir(dir).env("PATH", std::env::join_paths(dirs).expect("PATH"));
    support::dds_env(&mut c, DOMAIN);
    c.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).process_group(0);
    c
}

fn drain(mut pipe: impl Read + Send + 'static) -> JoinHandle<String> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = pipe.read_to_end(&mut bytes);
        String::from_utf8_lossy(&bytes).into_owned()
    })
}

/// A started line with its output collected on the side.
struct Running {
    line: String,
    child: Child,
    out: Option<(JoinHandle<String>, JoinHandle<String>)>,
}

impl Running {
    fn start(line: &str, dir: &Path, bin: &Path) -> Running {
        let mut child = shell(line, dir, bin).spawn().unwrap_or_else(|e| panic!("cannot start `{line}`: {e}"));
        let out = Some((drain(child.stdout.take().expect("stdout")), drain(child.stderr.take().expect("stderr"))));
        Running { line: line.to_string(), child, out }
    }

    /// Ctrl-C at its terminal: SIGINT to its process group (bash waits for the command and keeps its status).
    fn interrupt(&self) {
        let group = format!("-{}", self.child.id());
        let _ = Command::new("kill").args(["-INT", "--", &group]).status();
    }

    /// Waits for the exit (killing the group after [`LIMIT`]); Err describes a failure.
    fn finish(mut self) -> Result<String, String> {
        let started = Instant::now();
        let status = loop {
            if let Some(status) = self.child.try_wait().expect("try_wait") {
                break Some(status);
            }
            if started.elapsed() > LIMIT {
                let group = format!("-{}", self.child.id());
                let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
                let _ = self.child.wait();
                break None;
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        let (stdout, stderr) = self.out.take().expect("pipes");
        let text = format!("{}{}", stdout.join().unwrap_or_default(), stderr.join().unwrap_or_default());
        let tail: Vec<&str> = text.lines().rev().take(30).collect::<Vec<_>>().into_iter().rev().collect();
        let tail = tail.join("\n");
        match status {
            None => Err(format!("`{}` still running after {LIMIT:?}:\n{tail}", self.line)),
            Some(s) if !s.success() => Err(format!("`{}` exited with {s}:\n{tail}", self.line)),
            Some(_) if text.contains("panicked") => Err(format!("`{}` panicked:\n{tail}", self.line)),
            Some(_) => Ok(text),
        }
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

/// Runs one block in `dir`; returns the failures.
fn run_block(block: &Block, dir: &Path, bin: &Path) -> Vec<String> {
    let at = format!("{}:{}", block.page, block.line);
    let mut failures = Vec::new();
    match &block.kind {
        Kind::NoRun(_) => {}
        Kind::Console => {
            for (command, shown_failing) in &block.commands {
                let result = Running::start(&as_run(command), dir, bin).finish();
                match (result, *shown_failing) {
                    (Ok(_), false) => {}
                    (Err(e), true) if !e.contains("panicked") && !e.contains("still running") => {}
                    (Ok(text), true) => {
                        failures.push(format!("{at}: `{command}` is shown failing but succeeded:\n{text}"))
                    }
                    (Err(e), false) | (Err(e), true) => failures.push(format!("{at}: {e}")),
                }
            }
        }
        Kind::Shell => {
            let mut background: Vec<Running> = Vec::new();
            let mut last_started = Instant::now();
            for (line, _) in &block.commands {
                if split_comment(line).0 == THE_SUITE {
                    continue;
                }
                let run = as_run(line);
                if until_ctrl_c(line) {
                    background.push(Running::start(&run, dir, bin));
                    last_started = Instant::now();
                    continue;
                }
                if let Err(e) = Running::start(&run, dir, bin).finish() {
                    failures.push(format!("{at}: {e}"));
                    break;
                }
            }
            // A command started "in another terminal" gets at least two seconds before its Ctrl-C.
            if !background.is_empty() {
                std::thread::sleep(Duration::from_secs(2).saturating_sub(last_started.elapsed()));
            }
            for b in &background {
                b.interrupt();
            }
            for b in background {
                if let Err(e) = b.finish() {
                    failures.push(format!("{at}: after Ctrl-C, {e}"));
                }
            }
        }
    }
    failures
}

#[test]
fn the_parser_reads_tags_comments_and_continuations() {
    let page = "text\n```sh\nsweetspot a   # until Ctrl-C\n# a note\nsweetspot b \\\n  --c 'x # y'\n```\n\
                ```sh no-run: needs ROS\nros2 topic list\n```\n```console\n$ sweetspot x\nerror: bad\n$ sweetspot y\nok\n```\n\
                ```json\n{}\n```\n";
    let b = blocks("p.md", page).expect("parses");
    assert_eq!(b.len(), 3);
    assert_eq!(b[0].kind, Kind::Shell);
    let lines: Vec<&str> = b[0].commands.iter().map(|(l, _)| l.as_str()).collect();
    assert_eq!(lines, ["sweetspot a   # until Ctrl-C", "sweetspot b   --c 'x # y'"]);
    assert!(until_ctrl_c(lines[0]) && !until_ctrl_c(lines[1]));
    assert_eq!(b[1].kind, Kind::NoRun("needs ROS".into()));
    assert_eq!(b[2].commands, [("sweetspot x".to_string(), true), ("sweetspot y".to_string(), false)]);
    assert!(blocks("p.md", "```sh no-run:\nx\n```\n").is_err(), "a no-run block needs its reason");
    assert!(blocks("p.md", "```sh maybe\nx\n```\n").is_err(), "an unknown tag is refused");
    assert!(blocks("p.md", "```\nsweetspot demo\n```\n").is_err(), "commands need a fence language");
    assert_eq!(as_run("cargo run --release -- demo --swings 3"), "sweetspot demo --swings 3");
}

#[test]
fn the_readme_is_a_landing_page() {
    let readme = std::fs::read_to_string(support::repo().join("README.md")).expect("README.md");
    let lines: Vec<&str> = readme.lines().collect();
    assert!(lines.len() < 250, "README.md has {} lines: move detail to docs/", lines.len());
    let long: Vec<String> = lines
        .iter()
        .enumerate()
        .filter(|(_, l)| l.chars().count() >= 120)
        .map(|(i, l)| format!("README.md:{}: {} characters", i + 1, l.chars().count()))
        .collect();
    assert!(long.is_empty(), "lines of 120 characters or more:\n{}", long.join("\n"));
    // The first commands are the two a fresh machine needs (.ci/run calls `bash scripts/test`).
    let first = blocks("README.md", &readme).expect("README parses").remove(0);
    let commands: Vec<&str> = first.commands.iter().map(|(c, _)| split_comment(c).0).collect();
    assert_eq!(commands, ["cargo run --release -- demo", "bash scripts/test"]);
}

#[test]
fn every_documented_command_runs_as_written_twice() {
    support::require_isolated_network();
    let repo = support::repo();
    let mut all = Vec::new();
    for page in pages(&repo) {
        let text = std::fs::read_to_string(repo.join(&page)).unwrap_or_else(|e| panic!("{page}: {e}"));
        all.extend(blocks(&page, &text).unwrap_or_else(|e| panic!("{e}")));
    }
    let run = all.iter().filter(|b| !matches!(b.kind, Kind::NoRun(_))).count();
    assert!(run >= 10, "found only {run} runnable blocks");
    let temp = tempfile::tempdir().expect("temp dir");
    let dir: PathBuf = temp.path().join("sweetspot");
    fresh_clone(&repo, &dir);
    let bin_dir = temp.path().join("bin");
    std::fs::create_dir(&bin_dir).expect("bin dir");
    std::os::unix::fs::symlink(support::BIN, bin_dir.join("sweetspot")).expect("symlink sweetspot");
    let mut failures = Vec::new();
    for pass in 1..=2 {
        for block in &all {
            let started = Instant::now();
            let failed = run_block(block, &dir, &bin_dir);
            if let Kind::NoRun(reason) = &block.kind {
                eprintln!("pass {pass} {}:{} not run: {reason}", block.page, block.line);
            } else {
                eprintln!("pass {pass} {}:{} {:.1} s", block.page, block.line, started.elapsed().as_secs_f64());
            }
            failures.extend(failed.into_iter().map(|f| format!("pass {pass}: {f}")));
        }
        if pass == 1 {
            failures.extend(tour_answers_are_ok(&dir));
        }
    }
    assert!(failures.is_empty(), "{} failure(s):\n\n{}", failures.len(), failures.join("\n\n"));
}

/// The README tour publishes only valid swings: every one in its exported session is answered OK (status 0),
/// one per inline `pub swing` and one per row of examples/swings.csv.
fn tour_answers_are_ok(dir: &Path) -> Vec<String> {
    let Ok(csv) = std::fs::read_to_string(dir.join("session.csv")) else {
        return vec!["the README tour's `bag export … -o session.csv` wrote no session.csv".into()];
    };
    let swings_csv = std::fs::read_to_string(dir.join("examples/swings.csv")).unwrap_or_default();
    let expected = 2 + swings_csv.lines().skip(1).filter(|l| !l.trim().is_empty()).count();
    let mut rows = csv.lines();
    let header = rows.next().unwrap_or_default();
    let Some(status) = header.split(',').position(|c| c == "status") else {
        return vec![format!("session.csv has no status column: {header}")];
    };
    let statuses: Vec<&str> = rows.map(|r| r.split(',').nth(status).unwrap_or_default()).collect();
    if statuses.len() != expected || statuses.iter().any(|s| *s != "0") {
        return vec![format!("the tour's {expected} swings were not all answered OK (status 0):\n{csv}")];
    }
    Vec::new()
}
