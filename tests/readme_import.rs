//! README "Bringing your rig's data": every command line of its `sh` block runs as written (trailing
//! `# comment` dropped) with the built `sweetspot` first on PATH, in a fresh directory holding `game.csv` (the
//! real TrackMan rows of tests/data), `savant.csv` (the Statcast fixture), `session.csv` with its map
//! `my-tracker.toml` (the column-map fixture), `cage.csv` and `tee.csv` (the HitTrax fixture both: its first row,
//! from a real export, has Pitch 0).

use std::path::Path;
use std::process::Command;

fn section(readme: &str) -> Vec<String> {
    let start = readme.find("## Bringing your rig's data").expect("README has the section");
    let rest = &readme[start..];
    let block = rest.split("```sh\n").nth(1).expect("an sh block").split("```").next().unwrap();
    block
        .lines()
        .map(|l| match l.find("  #") {
            Some(i) => l[..i].trim_end().to_string(),
            None => l.trim_end().to_string(),
        })
        .filter(|l| !l.is_empty())
        .collect()
}

#[test]
fn the_import_section_runs_as_written() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(repo.join("README.md")).unwrap();
    let lines = section(&readme);
    assert!(lines.len() >= 4 && lines.iter().all(|l| l.starts_with("sweetspot ")), "{lines:?}");
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(repo.join("tests/data/trackman_game.csv"), dir.path().join("game.csv")).unwrap();
    std::fs::copy(repo.join("tests/data/statcast_search.csv"), dir.path().join("savant.csv")).unwrap();
    std::fs::copy(repo.join("tests/data/mapped_session.csv"), dir.path().join("session.csv")).unwrap();
    std::fs::copy(repo.join("tests/data/mapped_session.toml"), dir.path().join("my-tracker.toml")).unwrap();
    std::fs::copy(repo.join("tests/data/hittrax_session.csv"), dir.path().join("cage.csv")).unwrap();
    std::fs::copy(repo.join("tests/data/hittrax_session.csv"), dir.path().join("tee.csv")).unwrap();
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_sweetspot")).parent().unwrap().to_path_buf();
    let path = format!("{}:{}", bin_dir.display(), std::env::var("PATH").unwrap_or_default());
    let mut outputs = Vec::new();
    for line in &lines {
        let out = Command::new("sh").arg("-c").arg(line).current_dir(dir.path()).env("PATH", &path).output().unwrap();
        assert!(out.status.success(), "{line}: {}", String::from_utf8_lossy(&out.stderr));
        outputs.push(String::from_utf8_lossy(&out.stdout).into_owned());
    }
    assert!(outputs[0].contains("5 swings written to bags/game"), "{}", outputs[0]);
    assert!(outputs[2].contains("4 located"), "{}", outputs[2]);
    let json: serde_json::Value = serde_json::from_str(&outputs[3]).expect("locate --json is one JSON document");
    assert_eq!(json["swings"].as_array().map(Vec::len), Some(3));
    assert!(outputs[5].contains("1 swings written to bags/lab"), "{}", outputs[5]);
    // The real TrackMan rows: two with spin are tried for bat speed, the others say why they were not.
    assert!(outputs[7].contains("bat speed fitted for") && outputs[7].contains("no spin measured"), "{}", outputs[7]);
    assert!(outputs[8].contains("2 swings written to bags/cage"), "{}", outputs[8]);
    assert!(outputs[9].contains("3 swings written to bags/tee"), "the Pitch 0 row off the tee too: {}", outputs[9]);
    let figure = std::fs::read_to_string(dir.path().join("located.svg")).expect("locate --figure wrote its file");
    assert!(figure.contains("<svg") && figure.contains("Located impact points"), "not the figure: {figure:.200}");
}
