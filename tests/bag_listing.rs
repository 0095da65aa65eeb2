//! A bag's files are what its metadata.yaml lists, each read once however often it is listed, and a listing of
//! tens of thousands of files is read in linear time. No DDS: the committed golden bag, copied and relisted.

mod support;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use support::cli::{s, sweetspot};

const GOLDEN: &str = "bags/golden/sweetspot_golden";
const GOLDEN_FILE: &str = "sweetspot_golden_0.mcap";

/// The golden bag copied to `to`, its metadata.yaml listing `relative_file_paths` (each with a `files:` entry
/// counting the golden file's 36 messages).
fn relisted_golden(to: &Path, listed: &[&str]) -> PathBuf {
    std::fs::create_dir(to).unwrap();
    let golden = support::repo().join(GOLDEN);
    std::fs::copy(golden.join(GOLDEN_FILE), to.join(GOLDEN_FILE)).unwrap();
    let text = std::fs::read_to_string(golden.join("metadata.yaml")).unwrap();
    let (head, _) = text.split_once("  relative_file_paths:").expect("golden metadata lists its files");
    let (_, tail) = text.split_once("  custom_data:").expect("golden metadata has custom_data");
    let mut yaml = head.to_string();
    yaml += "  relative_file_paths:\n";
    for name in listed {
        yaml += &format!("    - \"{name}\"\n");
    }
    yaml += "  files:\n";
    for name in listed {
        yaml += &format!(
            "    - path: \"{name}\"\n      starting_time:\n        nanoseconds_since_epoch: 0\n      \
             duration:\n        nanoseconds: 0\n      message_count: 36\n"
        );
    }
    yaml += "  custom_data:";
    yaml += tail;
    std::fs::write(to.join("metadata.yaml"), yaml).unwrap();
    to.to_path_buf()
}

fn json_of(args: &[&str]) -> (serde_json::Value, String) {
    let run = sweetspot(args);
    assert!(run.status_ok, "{args:?}: {}", run.stderr);
    (serde_json::from_str(&run.stdout).unwrap_or_else(|e| panic!("{args:?}: {e}: {}", run.stdout)), run.stderr)
}

#[test]
fn a_file_listed_twice_is_read_once_and_named_by_every_reader() {
    let tmp = tempfile::tempdir().unwrap();
    let golden = support::repo().join(GOLDEN);
    let (info, _) = json_of(&["bag", "info", "--json", s(&golden)]);
    let golden_export = sweetspot(&["bag", "export", "--csv", s(&golden)]);
    assert!(golden_export.status_ok, "{}", golden_export.stderr);
    let (golden_replay, _) = json_of(&["bag", "replay", "--json", s(&golden)]);
    assert_eq!(info["messages"], 36);

    let cases: [(&str, &[&str]); 3] = [
        ("twice", &[GOLDEN_FILE, GOLDEN_FILE]),
        ("dot", &[GOLDEN_FILE, "./sweetspot_golden_0.mcap", GOLDEN_FILE]),
        ("link", &[GOLDEN_FILE, "link.mcap"]),
    ];
    for (name, listed) in cases {
        let bag = relisted_golden(&tmp.path().join(name), listed);
        if name == "link" {
            std::os::unix::fs::symlink(GOLDEN_FILE, bag.join("link.mcap")).unwrap();
        }
        let warning = format!("{GOLDEN_FILE}: listed {} times in metadata.yaml: read once", listed.len());
        let (doubled, stderr) = json_of(&["bag", "info", "--json", s(&bag)]);
        assert_eq!(doubled["messages"], 36, "{name}: {doubled}");
        assert_eq!(doubled["files"].as_array().map(Vec::len), Some(1), "{name}: {doubled}");
        assert_eq!(stderr.matches(&warning).count(), 1, "{name}: named once: {stderr}");

        let export = sweetspot(&["bag", "export", "--csv", s(&bag)]);
        assert!(export.status_ok, "{name}: {}", export.stderr);
        assert_eq!(export.stdout, golden_export.stdout, "{name}: every swing exported once");
        assert!(export.stderr.contains(&warning), "{name}: {}", export.stderr);

        let (replay, stderr) = json_of(&["bag", "replay", "--json", s(&bag)]);
        assert_eq!(replay, golden_replay, "{name}: every swing replayed once");
        assert!(stderr.contains(&warning), "{name}: {stderr}");
    }
}

/// Runs `sweetspot ARGS`, killing it after `limit`: its stdout and stderr, or None if it ran out of time.
fn run_within(args: &[&str], limit: Duration) -> Option<(bool, String, String)> {
    let tmp = tempfile::tempdir().unwrap();
    let (out, err) = (tmp.path().join("out"), tmp.path().join("err"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(args)
        .stdout(Stdio::from(std::fs::File::create(&out).unwrap()))
        .stderr(Stdio::from(std::fs::File::create(&err).unwrap()))
        .spawn()
        .expect("run sweetspot");
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let read = |p: &Path| std::fs::read_to_string(p).unwrap_or_default();
    Some((status.success(), read(&out), read(&err)))
}

#[test]
fn a_listing_of_80_000_files_is_read_in_linear_time() {
    // The golden file and 79,999 listed files that are not there (~15 MB of metadata.yaml): each missing one
    // is damage naming it. Looking each one's count up by a search of `files:` took more than 5 minutes;
    // linear, it takes about 2 s of CPU. The bound leaves a loaded CI machine room and the quadratic reading none.
    let tmp = tempfile::tempdir().unwrap();
    let names: Vec<String> = std::iter::once(GOLDEN_FILE.to_string())
        .chain((1..80_000).map(|i| format!("sweetspot_golden_{i}.mcap")))
        .collect();
    let listed: Vec<&str> = names.iter().map(String::as_str).collect();
    let bag = relisted_golden(&tmp.path().join("wide"), &listed);
    let size = std::fs::metadata(bag.join("metadata.yaml")).unwrap().len();
    assert!(size > 5_000_000 && size < 16 * 1024 * 1024, "{size} bytes: large, and under the input cap");
    let (ok, stdout, stderr) =
        run_within(&["bag", "info", "--json", "--skip-damaged", s(&bag)], Duration::from_secs(30))
            .expect("bag info of 80,000 listed files within 30 s");
    assert!(ok, "{}", &stderr[..stderr.len().min(2000)]);
    let info: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(info["files"].as_array().map(Vec::len), Some(80_000));
    assert_eq!(info["messages"], 36);
    // Each missing file's loss is what its own `files:` entry says.
    let last = "sweetspot_golden_79999.mcap: at offset 0: listed in metadata.yaml but missing; 36 messages lost";
    assert!(stderr.contains(last), "{}", &stderr[stderr.len().saturating_sub(2000)..]);
}
