//! docs/cli.md's examples, run as written: every `$ sweetspot …` line of its `console` blocks goes to
//! `sh -c` (with the built `sweetspot` first on PATH, in a fresh directory that has the repository's
//! `examples/`), and the lines shown after it must appear in its output (stdout then stderr) in that order; a
//! `…` line stands for any number of lines. An example shown failing (`error: …`) must fail; the others must
//! succeed. (The `sh` block of `pub`/`echo` needs DDS and a node: `tests/docs_commands.rs` runs it, and
//! `tests/ros_pubsub_cli.rs` covers those forms.) A doc example whose numbers went stale fails here.

mod support;

use std::path::Path;
use std::process::Command;

/// One example: the command after `$ `, and the lines shown under it.
struct Example {
    command: String,
    shown: Vec<String>,
}

fn examples(doc: &str) -> Vec<Example> {
    let mut out: Vec<Example> = Vec::new();
    let mut in_console = false;
    for line in doc.lines() {
        if line.starts_with("```") {
            in_console = !in_console && line.trim() == "```console";
            continue;
        }
        if !in_console {
            continue;
        }
        if let Some(command) = line.strip_prefix("$ ") {
            out.push(Example { command: command.to_string(), shown: Vec::new() });
        } else if let Some(example) = out.last_mut() {
            example.shown.push(line.to_string());
        }
    }
    out
}

/// Whether `shown` appears in `output` in order, `…` matching any run of lines (a shown line must equal an
/// output line after trimming trailing blanks; blank lines are not compared).
fn appears_in_order(shown: &[String], output: &str) -> Result<(), String> {
    let lines: Vec<&str> = output.lines().map(str::trim_end).filter(|l| !l.is_empty()).collect();
    let mut at = 0;
    let mut skipping = false;
    for want in shown {
        let want = want.trim_end();
        if want.is_empty() {
            continue;
        }
        if want == "…" {
            skipping = true;
            continue;
        }
        match lines[at..].iter().position(|l| *l == want) {
            Some(k) if skipping || k == 0 => {
                at += k + 1;
                skipping = false;
            }
            Some(k) => return Err(format!("`{want}` comes {k} line(s) later than shown")),
            None => return Err(format!("`{want}` is not in the output (after line {at})")),
        }
    }
    Ok(())
}

#[test]
fn every_console_example_of_docs_cli_runs_as_shown() {
    let doc = std::fs::read_to_string(support::repo().join("docs/cli.md")).expect("docs/cli.md");
    let examples = examples(&doc);
    assert!(examples.len() >= 8, "found {} examples", examples.len());
    assert!(examples.iter().any(|e| e.command == "sweetspot bbcor --bat aluminum"));
    let dir = tempfile::tempdir().expect("tempdir");
    std::os::unix::fs::symlink(support::repo().join("examples"), dir.path().join("examples")).expect("symlink");
    let bin_dir = Path::new(support::BIN).parent().expect("binary directory");
    let mut dirs = vec![bin_dir.to_path_buf()];
    dirs.extend(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()));
    let path = std::env::join_paths(dirs).expect("PATH");
    let mut failures = Vec::new();
    for example in &examples {
        assert!(example.command.starts_with("sweetspot "), "{}", example.command);
        let output =
            Command::new("sh").arg("-c").arg(&example.command).current_dir(dir.path()).env("PATH", &path).output();
        let output = output.expect("run sh");
        let text = format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
        let shows_failure = example.shown.iter().any(|l| l.starts_with("error: "));
        if output.status.success() == shows_failure {
            failures.push(format!("$ {}: exit {:?}\n{text}", example.command, output.status.code()));
            continue;
        }
        if let Err(why) = appears_in_order(&example.shown, &text) {
            failures.push(format!("$ {}: {why}\n--- output ---\n{text}", example.command));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn the_matcher_skips_only_at_an_ellipsis() {
    let shown = |s: &[&str]| s.iter().map(|l| l.to_string()).collect::<Vec<_>>();
    assert!(appears_in_order(&shown(&["a", "b"]), "a\nb\nc").is_ok());
    assert!(appears_in_order(&shown(&["a", "…", "c"]), "a\nb\nc").is_ok());
    assert!(appears_in_order(&shown(&["a", "c"]), "a\nb\nc").is_err());
    assert!(appears_in_order(&shown(&["a", "x"]), "a\nb\nc").is_err());
    assert!(appears_in_order(&shown(&["a", "", "b"]), "a\n\nb").is_ok());
}
