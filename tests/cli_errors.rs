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
