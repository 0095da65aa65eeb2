//! Bad input never panics: the binary exits non-zero with a message naming the field (and its range).

mod support;

use support::cli::{fails, s};

fn contains_all(stderr: &str, needles: &[&str]) {
    for needle in needles {
        assert!(stderr.contains(needle), "expected '{needle}' in the error message:\n{stderr}");
    }
}

#[test]
fn unknown_preset_names_the_flag_and_the_known_presets() {
    let err = fails(&["modes", "--bat", "louisville-slugger"]);
    contains_all(&err, &["--bat", "louisville-slugger", "r161", "aluminum"]);
}

#[test]
fn ball_cor_above_one_names_the_field_and_range() {
    let err = fails(&["simulate", "--ball-cor", "1.5"]);
    contains_all(&err, &["cor", "1.5", "≤ 1"]);
    let err = fails(&["sweep", "--ball-mass", "-0.1"]);
    contains_all(&err, &["mass", "-0.1"]);
}

#[test]
fn impact_off_the_bat_names_impact_z_and_the_bat_range() {
    let err = fails(&["simulate", "--impact-z", "1.2"]);
    contains_all(&err, &["impact_z", "1.2", "0.84"]);
    let err = fails(&["sweep", "--from", "0.5", "--to", "1.5", "--points", "3"]);
    contains_all(&err, &["impact_z"]);
}

#[test]
fn non_finite_numbers_are_refused_at_the_flag() {
    let err = fails(&["simulate", "--ball-speed", "NaN"]);
    contains_all(&err, &["--ball-speed", "finite"]);
    let err = fails(&["sweep", "--bat-angular-speed", "inf"]);
    contains_all(&err, &["--bat-angular-speed"]);
    let err = fails(&["simulate", "--impact-z", "0.7,nan"]);
    contains_all(&err, &["--impact-z"]);
}

#[test]
fn absurd_counts_and_steps_name_their_field() {
    contains_all(&fails(&["simulate", "--modes", "100000"]), &["modes", "100000"]);
    contains_all(&fails(&["modes", "--modes", "0"]), &["--modes", "0"]);
    contains_all(&fails(&["simulate", "--dt", "0.5"]), &["time_step", "0.5"]);
    contains_all(&fails(&["sweep", "--points", "1"]), &["--points"]);
    contains_all(&fails(&["sweep", "--step", "0"]), &["--step"]);
    contains_all(&fails(&["sweep", "--from", "0.7", "--to", "0.6"]), &["--from", "--to"]);
}

#[test]
fn a_ball_that_never_meets_the_bat_is_refused() {
    let err = fails(&["simulate", "--ball-speed", "-30", "--bat-cm-speed", "0", "--bat-angular-speed", "0"]);
    contains_all(&err, &["ball_speed"]);
}

#[test]
fn malformed_case_files_name_the_file_and_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let syntax = write("syntax.json", "{\"bat\": \"r161\",");
    contains_all(&fails(&["simulate", "--case", s(&syntax)]), &["case file", "syntax.json"]);
    let unknown = write("unknown.json", r#"{"bat": "r161", "ball_sped": 40}"#);
    contains_all(&fails(&["simulate", "--case", s(&unknown)]), &["ball_sped"]);
    let nested = write("nested.json", r#"{"ball": {"e0": 0.5}}"#);
    contains_all(&fails(&["simulate", "--case", s(&nested)]), &["e0"]);
    let bad_cor = write("cor.json", r#"{"ball": {"cor": 1.5}}"#);
    contains_all(&fails(&["simulate", "--case", s(&bad_cor)]), &["ball", "cor", "1.5"]);
    let wrong_type = write("type.json", r#"{"impact_z": "barrel"}"#);
    contains_all(&fails(&["simulate", "--case", s(&wrong_type)]), &["impact_z"]);
    let off = write("off.json", r#"{"impact_z": [0.7, 0.95]}"#);
    contains_all(&fails(&["simulate", "--case", s(&off)]), &["impact_z", "0.95"]);
    let missing = dir.path().join("absent.json");
    contains_all(&fails(&["simulate", "--case", s(&missing)]), &["absent.json"]);
    // --case excludes the flags it replaces.
    contains_all(&fails(&["simulate", "--case", s(&off), "--ball-speed", "30"]), &["--ball-speed"]);
}

#[test]
fn bad_bat_files_name_the_line_or_field() {
    let dir = tempfile::tempdir().unwrap();
    let toml = "slice_length = 0.01\nprofile = \"p.csv\"\n[shell]\ndensity = 649.0\nyoungs_modulus = 1.814e10\nshear_modulus = 1.05e9\n";
    std::fs::write(dir.path().join("bat.toml"), toml).unwrap();
    let bat = dir.path().join("bat.toml");

    std::fs::write(dir.path().join("p.csv"), "z_m,outer_radius_m\n0.0,0.02\n0.4,0.03\n0.3,0.03\n0.84,0.033\n").unwrap();
    contains_all(&fails(&["modes", "--bat", s(&bat)]), &["bat.toml", "p.csv", "line 4", "z_m", "strictly increasing"]);

    std::fs::write(dir.path().join("p.csv"), "z_m,outer_radius_m,inner_radius_m\n0.0,0.02,0.0\n0.84,0.03,0.031\n")
        .unwrap();
    contains_all(&fails(&["modes", "--bat", s(&bat)]), &["inner"]);

    std::fs::write(dir.path().join("p.csv"), "z_m,outer_radius_m\n0.0,0.02\n0.84,thick\n").unwrap();
    contains_all(&fails(&["modes", "--bat", s(&bat)]), &["line 3", "outer_radius_m"]);

    let inline = dir.path().join("inline.toml");
    std::fs::write(
        &inline,
        "slice_length = 0.01\n[shell]\ndensity = 649.0\nyoungs_modulus = 1.814e10\nshear_modulus = 1.05e9\n\
         [[station]]\nz = 0.0\nouter_radius = 0.02\n[[station]]\nz = 0.0\nouter_radius = 0.03\n",
    )
    .unwrap();
    contains_all(&fails(&["modes", "--bat", s(&inline)]), &["station[1]", "strictly increasing"]);

    let unknown = dir.path().join("unknown.toml");
    std::fs::write(&unknown, format!("{toml}colour = \"red\"\n")).unwrap();
    contains_all(&fails(&["modes", "--bat", s(&unknown)]), &["colour"]);

    let soft = dir.path().join("soft.toml");
    std::fs::write(&soft, toml.replace("youngs_modulus = 1.814e10", "youngs_modulus = -1.0")).unwrap();
    std::fs::write(dir.path().join("p.csv"), "z_m,outer_radius_m\n0.0,0.02\n0.84,0.033\n").unwrap();
    contains_all(&fails(&["modes", "--bat", s(&soft)]), &["youngs_modulus", "-1"]);
}

#[test]
fn plot_files_need_a_known_extension() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plot.jpg");
    contains_all(&fails(&["sweep", "--points", "3", "--modes", "2", "--plot", s(&path)]), &[".svg", ".png"]);
}

/// The one output rule (docs/cli.md, "Files a command writes"): `output` (an argument of `args`), a symlink to
/// `input`, is refused naming `flag`, with exit status 1, and `input` is left as it was.
fn refuses_to_overwrite(args: &[&str], flag: &str, input: &std::path::Path) {
    let before = std::fs::read(input).unwrap();
    let run = support::cli::sweetspot(args);
    assert_eq!(run.code, Some(1), "{args:?}: {}{}", run.stdout, run.stderr);
    contains_all(&run.stderr, &[flag, "is the input file", "refused"]);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    assert_eq!(std::fs::read(input).unwrap(), before, "{args:?} changed {}", input.display());
}

/// `link` → `target` (a symlink), returned as a path.
fn symlink(target: &std::path::Path, link: std::path::PathBuf) -> std::path::PathBuf {
    std::os::unix::fs::symlink(target, &link).unwrap();
    link
}

/// A copy of the golden bag with its MCAP file cut short (recovery has something to write); its MCAP file.
fn damaged_bag(dir: &std::path::Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let bag = dir.join("bag");
    std::fs::create_dir(&bag).unwrap();
    let golden = support::repo().join("bags/golden/sweetspot_golden");
    for name in ["metadata.yaml", "sweetspot_golden_0.mcap"] {
        std::fs::copy(golden.join(name), bag.join(name)).unwrap();
    }
    let mcap = bag.join("sweetspot_golden_0.mcap");
    let bytes = std::fs::read(&mcap).unwrap();
    std::fs::write(&mcap, &bytes[..bytes.len() * 2 / 3]).unwrap();
    (bag, mcap)
}

#[test]
fn bag_recover_never_writes_onto_the_bag_it_reads() {
    let dir = tempfile::tempdir().unwrap();
    let (bag, mcap) = damaged_bag(dir.path());
    let link = symlink(&mcap, dir.path().join("copy.mcap"));
    refuses_to_overwrite(&["bag", "recover", s(&bag), "-o", s(&link)], "-o/--output", &mcap);
    refuses_to_overwrite(&["bag", "recover", s(&mcap), "-o", s(&link)], "-o/--output", &mcap);
    // Elsewhere is fine.
    let run = support::cli::sweetspot(&["bag", "recover", s(&bag), "-o", s(&dir.path().join("fixed"))]);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
}

#[test]
fn import_never_writes_its_bag_or_batters_onto_its_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let export = dir.path().join("session.csv");
    std::fs::copy(support::repo().join("tests/data/statcast_search.csv"), &export).unwrap();
    let batter = dir.path().join("batter.toml");
    std::fs::write(&batter, "exponent = 0.25\n").unwrap();
    // -o: the bag directory onto the export (or the batter file) it reads.
    let out = symlink(&export, dir.path().join("out"));
    refuses_to_overwrite(&["import", s(&export), "-o", s(&out)], "-o/--output", &export);
    let out = symlink(&batter, dir.path().join("out2"));
    refuses_to_overwrite(&["import", s(&export), "--batter", s(&batter), "-o", s(&out)], "-o/--output", &batter);
    // --batter-out: a batter's file onto the batter file read (not one of the exports), and the directory
    // itself onto the export.
    let batters = dir.path().join("batters");
    std::fs::create_dir(&batters).unwrap();
    symlink(&batter, batters.join("batter_100001.toml"));
    let (bag1, bag2) = (dir.path().join("bag1"), dir.path().join("bag2"));
    let args = ["import", s(&export), "--batter", s(&batter), "-o", s(&bag1), "--batter-out", s(&batters)];
    refuses_to_overwrite(&args, "--batter-out", &batter);
    let onto_export = symlink(&export, dir.path().join("batters2"));
    let args = ["import", s(&export), "-o", s(&bag2), "--batter-out", s(&onto_export)];
    refuses_to_overwrite(&args, "--batter-out", &export);
}

#[test]
fn validate_never_draws_a_figure_onto_its_data() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    std::fs::create_dir(&data).unwrap();
    for entry in std::fs::read_dir(support::repo().join("validation")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, data.join(path.file_name().unwrap())).unwrap();
    }
    let figures = dir.path().join("figures");
    std::fs::create_dir(&figures).unwrap();
    let measurements = data.join("measurements.toml");
    symlink(&measurements, figures.join("validate-cor-vs-speed.svg"));
    refuses_to_overwrite(&["validate", "--data", s(&data), "--figures", s(&figures)], "--figures", &measurements);
}

#[test]
fn a_plot_never_lands_on_a_bat_files_profile() {
    // The profile CSV is read through the bat file, not named on the command line: it is an input all the same.
    let dir = tempfile::tempdir().unwrap();
    let bat = dir.path().join("bat.toml");
    std::fs::write(
        &bat,
        "slice_length = 0.01\nprofile = \"p.csv\"\n[shell]\ndensity = 649.0\nyoungs_modulus = 1.814e10\n\
         shear_modulus = 1.05e9\n",
    )
    .unwrap();
    let profile = dir.path().join("p.csv");
    std::fs::write(&profile, "z_m,outer_radius_m\n0.0,0.0135\n0.3,0.015\n0.84,0.033\n").unwrap();
    support::cli::ok(&["modes", "--bat", s(&bat), "--modes", "2"]);
    let plot = symlink(&profile, dir.path().join("plot.svg"));
    let args = ["sweep", "--bat", s(&bat), "--points", "3", "--modes", "2", "--plot", s(&plot)];
    refuses_to_overwrite(&args, "--plot", &profile);
    let args = ["compare", "--bats", &format!("r161,{}", s(&bat)), "--modes", "2", "--figure", s(&plot)];
    refuses_to_overwrite(&args, "--figure", &profile);
}

/// The commands that start DDS once their checks pass refuse before anything starts; run inside the private
/// network namespace all the same, should a check ever come too late.
#[test]
fn record_demo_and_bench_refuse_their_outputs_before_starting() {
    support::require_isolated_network();
    let dir = tempfile::tempdir().unwrap();
    let overrides = dir.path().join("qos.yaml");
    std::fs::write(&overrides, "/swing:\n  reliability: reliable\n").unwrap();
    let out = symlink(&overrides, dir.path().join("out"));
    let args = ["bag", "record", "-a", "--qos-profile-overrides-path", s(&overrides), "-o", s(&out)];
    refuses_to_overwrite(&args, "-o/--output", &overrides);

    let batter = dir.path().join("batter.toml");
    std::fs::write(&batter, "exponent = 0.25\n").unwrap();
    let out = symlink(&batter, dir.path().join("demo-out"));
    refuses_to_overwrite(&["demo", "--batter", s(&batter), "--out", s(&out), "--swings", "4"], "--out", &batter);

    let node = dir.path().join("node-exe");
    std::fs::write(&node, "#!/bin/sh\nexit 3\n").unwrap();
    let json = symlink(&node, dir.path().join("bench.json"));
    let args = ["bench", "--quick", "--node-exe", s(&node), "--json", s(&json), "--work-dir", s(dir.path())];
    refuses_to_overwrite(&args, "--json", &node);
}
