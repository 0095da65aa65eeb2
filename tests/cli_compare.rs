//! `sweetspot compare`: bats at equal batter effort, run through the real binary.

mod support;

use serde_json::Value;
use support::cli::{fails, json, num, ok, s};

/// 71.5 mph in m/s (Statcast's 2024 MLB average bat speed), written out by hand.
const STATCAST_SPEED: f64 = 31.963_36;

fn bat<'a>(doc: &'a Value, name: &str) -> &'a Value {
    doc["bats"].as_array().expect("bats").iter().find(|b| b["name"] == name).unwrap_or_else(|| panic!("no {name}"))
}

#[test]
fn default_comparison_puts_the_lighter_swing_weights_ahead_in_time() {
    let doc = json(&["compare", "--modes", "6"]);
    let names: Vec<&str> = doc["bats"].as_array().expect("bats").iter().map(|b| b["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["r161", "r161-corked", "aluminum", "torpedo"]);
    for b in doc["bats"].as_array().unwrap() {
        // Swing weight by the parallel-axis theorem from the document's own mass properties, 6-in pivot.
        let d = num(b, "/center_of_mass") - 0.1524;
        let expected = num(b, "/moment_of_inertia") + num(b, "/mass") * d * d;
        assert!((num(b, "/swing_weight") - expected).abs() < 1e-12, "{b}");
        assert!((num(b, "/pitch_travel") - 40.0 * num(b, "/reaction_time_gained")).abs() < 1e-12);
        let bbcor = num(b, "/bbcor");
        assert!(bbcor > 0.3 && bbcor < 0.8, "{bbcor}");
    }
    let r161 = bat(&doc, "r161");
    assert!((num(r161, "/bat_speed") - STATCAST_SPEED).abs() < 1e-9);
    assert_eq!(num(r161, "/reaction_time_gained"), 0.0);
    // T = 2 · 7.3 ft / 71.5 mph = 0.13922 s.
    assert!((num(r161, "/swing_time") - 0.139_224_411_95).abs() < 1e-9);
    let corked = bat(&doc, "r161-corked");
    assert!(num(corked, "/swing_weight") < num(r161, "/swing_weight"));
    assert!(num(corked, "/bat_speed") > num(r161, "/bat_speed"));
    assert!(num(corked, "/reaction_time_gained") > 0.0);
    // The seed's Table 2 aluminum bat is lighter about the knob than the R161 too.
    let aluminum = bat(&doc, "aluminum");
    assert!(num(aluminum, "/swing_weight") < num(r161, "/swing_weight"));
    assert!(num(aluminum, "/reaction_time_gained") > 0.0);
}

#[test]
fn exponent_zero_with_the_same_ratio_is_the_equal_speed_sweep_bit_for_bit() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("batter.toml");
    std::fs::write(&file, "exponent = 0.0\nshape = \"same-ratio\"\n").expect("write");
    let doc = json(&["compare", "--bats", "r161,r161-corked", "--batter", s(&file), "--modes", "6"]);
    let (v, w) = (num(&doc, "/batter/bat_cm_speed"), num(&doc, "/batter/bat_angular_speed"));
    let corked = bat(&doc, "r161-corked");
    assert_eq!((num(corked, "/bat_cm_speed"), num(corked, "/bat_angular_speed")), (v, w));
    // `sweep` compares bats at one (V, ω): the same numbers must come out.
    let (v_text, w_text) = (format!("{v:?}"), format!("{w:?}"));
    let sweep = json(&[
        "sweep",
        "--bat",
        "r161-corked",
        "--ball-speed",
        "40",
        "--bat-cm-speed",
        &v_text,
        "--bat-angular-speed",
        &w_text,
        "--modes",
        "6",
        "--points",
        "2",
    ]);
    assert_eq!(num(corked, "/max_exit_speed"), num(&sweep, "/sweet_spots/max_exit_speed"));
    assert_eq!(num(corked, "/sweet_spot_z"), num(&sweep, "/sweet_spots/max_exit_speed_z"));
}

#[test]
fn text_table_and_bad_inputs() {
    let text = ok(&["compare", "--bats", "r161,aluminum", "--modes", "4", "--pitch-speed", "38"]);
    assert!(text.contains("swing weight (kg·m²)") && text.contains("gained (ms)"), "{text}");
    assert!(text.lines().any(|l| l.starts_with("aluminum")), "{text}");
    assert!(fails(&["compare", "--exponent", "0.9"]).contains("exponent"));
    assert!(fails(&["compare", "--bats", "r161,nonesuch"]).contains("nonesuch"));
    assert!(fails(&["compare", "--pitch-speed", "-3"]).contains("pitch-speed"));
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("batter.toml");
    std::fs::write(&file, "bat_speed = -1.0\n").expect("write");
    assert!(fails(&["compare", "--batter", s(&file)]).contains("speed"));
}

/// A fitted exponent (as `calibrate --batter-out` writes it, all 17 digits) prints as the report's other
/// numbers do, with 4 significant digits.
#[test]
fn a_fitted_exponent_prints_in_four_digits() {
    let dir = tempfile::tempdir().unwrap();
    let batter = dir.path().join("batter.toml");
    std::fs::write(&batter, "exponent = 0.27378123456789012\n").unwrap();
    let out = ok(&["compare", "--modes", "4", "--bats", "r161,aluminum", "--batter", s(&batter)]);
    assert!(out.contains("n = 0.2738,"), "{out}");
    assert!(!out.contains("0.273781"), "{out}");
}
