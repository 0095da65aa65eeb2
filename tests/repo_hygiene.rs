//! What the repository holds is what a newcomer should find there: inputs, fixtures and sources, never a
//! program's output. Plots, images and bags are committed only where fixtures and documentation images
//! belong, and nothing under `out/` (where the docs' examples write; ignored).

use std::process::Command;

/// File kinds the programs write.
const GENERATED: [&str; 4] = [".svg", ".png", ".mcap", ".pdf"];
/// Where such files are inputs: the golden bag, the fuzzers' seed inputs, the vendored crates' own test
/// data, and the images of the docs.
const FIXTURE_FOLDERS: [&str; 4] = ["bags/golden/", "fuzz/corpus/", "patches/", "docs/images/"];

/// The committed files of the repository (none when it is not a git checkout, e.g. a packaged crate).
fn committed_files() -> Vec<String> {
    let out = Command::new("git").args(["ls-files", "-z"]).current_dir(env!("CARGO_MANIFEST_DIR")).output();
    match out {
        Ok(out) if out.status.success() => String::from_utf8_lossy(&out.stdout)
            .split('\0')
            .filter(|name| !name.is_empty())
            .map(str::to_string)
            .collect(),
        _ => Vec::new(),
    }
}

/// The names of `files` that look generated and lie outside the fixture folders, or lie under `out/`.
fn misplaced(files: &[String]) -> Vec<&str> {
    files
        .iter()
        .map(String::as_str)
        .filter(|name| {
            let generated = GENERATED.iter().any(|ext| name.to_ascii_lowercase().ends_with(ext));
            let fixture = FIXTURE_FOLDERS.iter().any(|folder| name.starts_with(folder));
            (generated && !fixture) || name.starts_with("out/")
        })
        .collect()
}

#[test]
fn a_plot_at_the_root_or_anything_under_out_is_misplaced_and_fixtures_are_not() {
    let files = [
        "sweep-r161.svg",
        "out/notes.txt",
        "docs/tour.svg",
        "bags/golden/a/a_0.mcap",
        "docs/images/x.png",
        "src/lib.rs",
    ]
    .map(String::from);
    assert_eq!(misplaced(&files), ["sweep-r161.svg", "out/notes.txt", "docs/tour.svg"]);
}

#[test]
fn no_generated_file_is_committed() {
    let files = committed_files();
    let misplaced = misplaced(&files);
    assert!(
        misplaced.is_empty(),
        "generated files are committed (write outputs under out/, which git ignores; fixtures belong in {}): {}",
        FIXTURE_FOLDERS.join(", "),
        misplaced.join(", ")
    );
}
