//! The code sweetspot patches in its dependencies (patches/, `[patch.crates-io]`) is tested by the suite's own
//! command: each unit test a patch adds is in a module that `scripts/test` (what CI runs) runs, through the
//! offline test package patches/unit-tests/<crate>. A patched crate whose tests that package cannot build yet is
//! named below with the tests of ours that exercise the same change through the crate's public API.

use std::collections::BTreeMap;
use std::path::Path;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Patched crates whose own unit tests need dev-dependencies that are not in any Cargo.lock of ours, and the
/// suite's tests that cover the patched behaviour instead.
const COVERED_FROM_OUTSIDE: [(&str, &str); 2] = [
    ("rustdds", "test-case, test-log and hex-literal; tests/node_dead_subscriber.rs, tests/node_params_cyclone.rs"),
    ("foxglove", "insta, axum, rcgen, …; tests/foxglove_flood.rs, tests/foxglove_hardening.rs"),
];

/// For each patch under patches/, the modules (`a::b::`) in which its diff adds a `#[test]`.
fn modules_with_added_tests() -> BTreeMap<String, Vec<String>> {
    let mut found = BTreeMap::new();
    for entry in std::fs::read_dir(Path::new(ROOT).join("patches")).expect("patches/ is listed") {
        let path = entry.expect("a directory entry").path();
        if path.extension().is_none_or(|ext| ext != "diff") {
            continue;
        }
        let krate = path.file_stem().and_then(|s| s.to_str()).expect("a UTF-8 name").to_string();
        let diff = std::fs::read_to_string(&path).expect("the diff is readable");
        let mut file = "";
        let mut modules: Vec<String> = Vec::new();
        for line in diff.lines() {
            if let Some(name) = line.strip_prefix("+++ ") {
                file = name.split_whitespace().next().unwrap_or("");
            } else if line.strip_prefix('+').is_some_and(|added| added.trim() == "#[test]") {
                let module = module_of(file);
                if !modules.contains(&module) {
                    modules.push(module);
                }
            }
        }
        found.insert(krate, modules);
    }
    found
}

/// `b/src/rtps/message.rs` → `rtps::message::`.
fn module_of(file: &str) -> String {
    let inside = file.split_once("/src/").map_or(file, |(_, rest)| rest);
    let stem = inside.trim_end_matches(".rs").trim_end_matches("/mod");
    format!("{}::", stem.replace('/', "::"))
}

/// The `--lib` filters `scripts/test` passes for the test package of `krate`, if it runs one.
fn filters_run_for(script: &str, krate: &str) -> Option<Vec<String>> {
    let manifest = format!("patches/unit-tests/{krate}/Cargo.toml");
    let command = script.replace("\\\n", " ");
    let line = command.lines().find(|line| line.contains(&manifest) && !line.trim_start().starts_with('#'))?;
    let after_lib = line.split_once("--lib")?.1;
    Some(after_lib.split_whitespace().map(str::to_string).collect())
}

#[test]
fn module_paths_are_read_off_the_diffs_file_names() {
    assert_eq!(module_of("b/src/rtps/message.rs"), "rtps::message::");
    assert_eq!(module_of("b/src/parameters.rs"), "parameters::");
    assert_eq!(module_of("b/src/websocket/mod.rs"), "websocket::");
}

#[test]
fn every_unit_test_a_patch_adds_is_run_by_the_suites_command() {
    let script = std::fs::read_to_string(Path::new(ROOT).join("scripts/test")).expect("scripts/test is readable");
    let patched = modules_with_added_tests();
    assert!(patched.get("ros2-client").is_some_and(|m| !m.is_empty()), "no tests found in the diffs: {patched:?}");
    for (krate, modules) in &patched {
        if modules.is_empty() || COVERED_FROM_OUTSIDE.iter().any(|(name, _)| name == krate) {
            continue;
        }
        let filters = filters_run_for(&script, krate)
            .unwrap_or_else(|| panic!("scripts/test never runs the unit tests of patches/{krate} ({modules:?})"));
        for module in modules {
            assert!(
                filters.iter().any(|filter| module.starts_with(filter.as_str())),
                "scripts/test runs patches/{krate}'s tests with {filters:?}, which leave out {module}"
            );
        }
        let manifest = std::fs::read_to_string(Path::new(ROOT).join(format!("patches/unit-tests/{krate}/Cargo.toml")))
            .expect("the test package's manifest is readable");
        assert!(
            manifest.contains(&format!("path = \"../../{krate}/src/lib.rs\"")),
            "patches/unit-tests/{krate} does not build the patched source"
        );
    }
}
