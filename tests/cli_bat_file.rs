//! The bat file format: presets round-trip exactly through TOML + CSV, the shipped examples equal their
//! presets, and the binary gives identical numbers for a preset and its file.

mod support;

use support::cli::{json, ok, repo, s};
use sweetspot::cli::bat_file::{load_bat_file, parse_bat_toml, spec_to_toml, write_bat_files, BatSpec};
use sweetspot::physics::Bat;

#[test]
fn every_preset_round_trips_through_toml_and_csv() {
    let dir = tempfile::tempdir().unwrap();
    for name in Bat::preset_names() {
        let preset = Bat::preset(name).unwrap();
        let path = write_bat_files(&preset, dir.path(), name).unwrap();
        assert_eq!(load_bat_file(&path).unwrap(), preset, "{name} via CSV profile");
        // Inline [[station]] form, parsed without touching the file system.
        let inline = spec_to_toml(&BatSpec::from_bat(&preset, None));
        let parsed = parse_bat_toml(&inline, "unused", |_| anyhow::bail!("no CSV for inline stations")).unwrap();
        assert_eq!(parsed, preset, "{name} inline");
    }
}

#[test]
fn shipped_examples_equal_their_presets() {
    for name in ["r161", "r161-corked"] {
        let path = repo().join(format!("examples/bats/{name}.toml"));
        assert_eq!(load_bat_file(&path).unwrap(), Bat::preset(name).unwrap(), "{}", path.display());
    }
    let hollow = load_bat_file(&repo().join("examples/bats/hollow-alloy.toml")).unwrap();
    assert_eq!(hollow.name, "hollow-alloy");
    assert!(hollow.stations.iter().any(|st| st.inner_radius > 0.0), "the hollow example has a bore");
}

#[test]
fn binary_gives_the_same_numbers_for_a_preset_and_its_file() {
    let from_preset = json(&["modes", "--bat", "r161-corked", "--modes", "6"]);
    let from_file = json(&["modes", "--bat", "examples/bats/r161-corked.toml", "--modes", "6"]);
    assert_eq!(from_preset, from_file);
    let dir = tempfile::tempdir().unwrap();
    let path = write_bat_files(&Bat::preset("torpedo").unwrap(), dir.path(), "t").unwrap();
    let a = json(&["simulate", "--bat", "torpedo", "--impact-z", "0.7", "--modes", "6"]);
    let mut b = json(&["simulate", "--bat", s(&path), "--impact-z", "0.7", "--modes", "6"]);
    assert_eq!(b["bat"]["name"], "torpedo");
    b["bat"]["name"] = a["bat"]["name"].clone();
    assert_eq!(a, b);
}

#[test]
fn every_example_case_runs() {
    let dir = repo().join("examples/cases");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "json") {
            let doc = json(&["simulate", "--case", s(&path)]);
            assert!(!doc["results"].as_array().unwrap().is_empty(), "{}", path.display());
            count += 1;
        }
    }
    assert!(count >= 3, "expected at least three example cases, found {count}");
    let text = ok(&["simulate", "--case", "examples/cases/inline-bat.json"]);
    assert!(text.contains("ash-dowel") && text.contains("exit speed (m/s)"), "{text}");
}
