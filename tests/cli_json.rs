//! `--json` output of the physics commands: one document with exactly the documented fields
//! (docs/file-formats.md), and numbers equal to the library's for the same inputs.

mod support;

use serde_json::Value;
use support::cli::{json, num};
use sweetspot::physics::metrics::{bbcor_report, besr, besr_scan, sweep, sweet_spots};
use sweetspot::physics::{collide, Ball, Bat, CollisionOptions, Impact, ModeSet};

const BAT_FIELDS: &[&str] = &[
    "name",
    "mass",
    "length",
    "center_of_mass",
    "moment_of_inertia",
    "radius_of_gyration",
    "pivot_z",
    "moment_about_pivot",
    "center_of_percussion",
];
/// The default ball (the game ball) carries its COR's speed law; a constant-COR ball writes only the first five.
const BALL_FIELDS: &[&str] =
    &["mass", "radius", "stiffness", "exponent", "cor", "cor_speed_exponent", "cor_reference_speed"];
const SWING_FIELDS: &[&str] = &["ball_speed", "bat_cm_speed", "bat_angular_speed"];
const OPTIONS_FIELDS: &[&str] = &["modes", "time_step"];
const RESULT_FIELDS: &[&str] = &[
    "impact_z",
    "exit_speed",
    "rigid_exit_speed",
    "effective_cor",
    "collision_efficiency",
    "contact_time",
    "peak_force",
    "impulse",
    "max_compression",
    "energy",
    "mode_energies",
];
const ENERGY_FIELDS: &[&str] = &["initial", "ball", "bat_rigid", "vibration", "hysteresis_loss", "residual"];
/// A hollow section's energy budget adds the wall's hoop energies.
const HOLLOW_ENERGY_FIELDS: &[&str] = &[
    "initial",
    "ball",
    "bat_rigid",
    "vibration",
    "hysteresis_loss",
    "hoop",
    "hoop_stored",
    "hoop_returned",
    "residual",
];
/// A hollow section's result adds the wall's hoop mode.
const HOOP_FIELDS: &[&str] =
    &["frequency_hz", "stiffness", "effective_mass", "decay_length", "radius", "wall_thickness", "coupling"];
const MODE_ENERGY_FIELDS: &[&str] = &["mode", "frequency_hz", "energy"];
const SWEET_FIELDS: &[&str] =
    &["max_exit_speed_z", "max_exit_speed", "rigid_optimum_z", "node1_z", "node2_z", "center_of_percussion_z"];

/// The object at `pointer` has exactly `fields`.
fn has_exactly(doc: &Value, pointer: &str, fields: &[&str]) {
    let object = doc.pointer(pointer).and_then(Value::as_object).unwrap_or_else(|| panic!("no object at '{pointer}'"));
    let mut keys: Vec<&str> = object.keys().map(String::as_str).collect();
    let mut expected = fields.to_vec();
    keys.sort_unstable();
    expected.sort_unstable();
    assert_eq!(keys, expected, "fields of '{pointer}'");
}

fn check_result(doc: &Value, pointer: &str, modes: usize) {
    let hollow = doc.pointer(&format!("{pointer}/hoop")).is_some();
    if hollow {
        has_exactly(doc, pointer, &[RESULT_FIELDS, &["hoop"]].concat());
        has_exactly(doc, &format!("{pointer}/energy"), HOLLOW_ENERGY_FIELDS);
        has_exactly(doc, &format!("{pointer}/hoop"), HOOP_FIELDS);
    } else {
        has_exactly(doc, pointer, RESULT_FIELDS);
        has_exactly(doc, &format!("{pointer}/energy"), ENERGY_FIELDS);
    }
    let energies = doc.pointer(&format!("{pointer}/mode_energies")).and_then(Value::as_array).expect("mode_energies");
    assert_eq!(energies.len(), modes);
    has_exactly(doc, &format!("{pointer}/mode_energies/0"), MODE_ENERGY_FIELDS);
}

/// Asserts the JSON result equals the library's collision result exactly (JSON floats round-trip).
fn same_result(doc: &Value, pointer: &str, r: &sweetspot::physics::CollisionResult) {
    let at = |field: &str| num(doc, &format!("{pointer}/{field}"));
    assert_eq!(at("exit_speed"), r.exit_speed);
    assert_eq!(at("rigid_exit_speed"), r.rigid_exit_speed);
    assert_eq!(at("effective_cor"), r.effective_cor);
    assert_eq!(at("collision_efficiency"), r.collision_efficiency);
    assert_eq!(at("contact_time"), r.contact_time);
    assert_eq!(at("peak_force"), r.peak_force);
    assert_eq!(at("impulse"), r.impulse);
    assert_eq!(at("max_compression"), r.max_compression);
    assert_eq!(at("energy/initial"), r.energy.initial);
    assert_eq!(at("energy/ball"), r.energy.ball);
    assert_eq!(at("energy/bat_rigid"), r.energy.bat_rigid);
    assert_eq!(at("energy/vibration"), r.energy.vibration);
    assert_eq!(at("energy/hysteresis_loss"), r.energy.hysteresis_loss);
    assert_eq!(at("energy/residual"), r.energy.residual);
    match &r.hoop {
        Some(hoop) => {
            assert_eq!(at("energy/hoop"), r.energy.hoop);
            assert_eq!(at("energy/hoop_stored"), r.energy.hoop_stored);
            assert_eq!(at("energy/hoop_returned"), r.energy.hoop_returned);
            assert_eq!(at("hoop/frequency_hz"), hoop.frequency_hz());
            assert_eq!(at("hoop/stiffness"), hoop.stiffness);
            assert_eq!(at("hoop/effective_mass"), hoop.effective_mass);
        }
        None => assert!(doc.pointer(&format!("{pointer}/hoop")).is_none(), "a solid section has no hoop"),
    }
    for (i, m) in r.mode_energies.iter().enumerate() {
        assert_eq!(at(&format!("mode_energies/{i}/frequency_hz")), m.frequency);
        assert_eq!(at(&format!("mode_energies/{i}/energy")), m.energy);
        assert_eq!(at(&format!("mode_energies/{i}/mode")), (i + 1) as f64);
    }
}

#[test]
fn simulate_json_has_the_documented_fields_and_the_library_numbers() {
    let doc = json(&[
        "simulate",
        "--bat",
        "r161-corked",
        "--ball-speed",
        "38.5",
        "--bat-cm-speed",
        "22",
        "--bat-angular-speed",
        "40",
        "--ball-cor",
        "0.5",
        "--modes",
        "10",
        "--dt",
        "4e-6",
        "--impact-z",
        "0.64,0.7",
        "--impact-z",
        "0.75",
    ]);
    let top: Vec<&str> = doc.as_object().expect("object").keys().map(String::as_str).collect();
    assert_eq!(top.len(), 5, "{top:?}");
    has_exactly(&doc, "/bat", BAT_FIELDS);
    has_exactly(&doc, "/ball", BALL_FIELDS);
    has_exactly(&doc, "/swing", SWING_FIELDS);
    has_exactly(&doc, "/options", OPTIONS_FIELDS);
    assert_eq!(doc["results"].as_array().map(Vec::len), Some(3));

    let bat = Bat::preset("r161-corked").unwrap();
    let options = CollisionOptions { modes: 10, time_step: 4e-6 };
    let modes = ModeSet::compute(&bat, options.modes).unwrap();
    let ball = Ball { cor: 0.5, ..Ball::game() };
    let props = modes.mass_properties();
    assert_eq!(num(&doc, "/bat/mass"), props.mass);
    assert_eq!(num(&doc, "/bat/center_of_mass"), props.center_of_mass);
    assert_eq!(num(&doc, "/bat/moment_of_inertia"), props.moment_of_inertia);
    assert_eq!(num(&doc, "/ball/cor"), 0.5);
    assert_eq!(num(&doc, "/options/time_step"), 4e-6);
    for (i, z) in [0.64, 0.7, 0.75].into_iter().enumerate() {
        let pointer = format!("/results/{i}");
        check_result(&doc, &pointer, 10);
        assert_eq!(num(&doc, &format!("{pointer}/impact_z")), z);
        let impact = Impact { ball_speed: 38.5, bat_cm_speed: 22.0, bat_angular_speed: 40.0, impact_z: z };
        same_result(&doc, &pointer, &collide(&modes, &ball, &impact, &options).unwrap());
    }
}

#[test]
fn simulate_case_file_equals_the_same_flags() {
    let from_case = json(&["simulate", "--case", "examples/cases/r161-barrel.json"]);
    let from_flags = json(&[
        "simulate",
        "--bat",
        "r161",
        "--ball-speed",
        "40",
        "--bat-cm-speed",
        "25",
        "--bat-angular-speed",
        "45",
        "--impact-z",
        "0.62,0.66,0.70,0.74,0.78",
        "--modes",
        "18",
        "--dt",
        "5e-6",
    ]);
    assert_eq!(from_case, from_flags);
    assert_eq!(from_case["results"].as_array().map(Vec::len), Some(5));
}

#[test]
fn sweep_json_matches_the_library() {
    let doc = json(&["sweep", "--bat", "aluminum", "--from", "0.5", "--to", "0.78", "--points", "8", "--modes", "8"]);
    has_exactly(&doc, "", &["bat", "ball", "swing", "options", "sweet_spots", "nodes", "points", "plot"]);
    has_exactly(&doc, "/sweet_spots", SWEET_FIELDS);
    has_exactly(&doc, "/nodes", &["mode1", "mode2"]);
    assert!(doc["plot"].is_null());

    let bat = Bat::preset("aluminum").unwrap();
    let options = CollisionOptions { modes: 8, ..CollisionOptions::default() };
    let modes = ModeSet::compute(&bat, 8).unwrap();
    let ball = Ball::game();
    let swing = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 45.0, impact_z: 0.0 };
    let zs: Vec<f64> = (0..8).map(|i| 0.5 + (0.78 - 0.5) * i as f64 / 7.0).collect();
    let points = sweep(&modes, &ball, &swing, &zs, &options).unwrap();
    assert_eq!(doc["points"].as_array().map(Vec::len), Some(8));
    for (i, p) in points.iter().enumerate() {
        let pointer = format!("/points/{i}");
        check_result(&doc, &pointer, 8);
        assert_eq!(num(&doc, &format!("{pointer}/impact_z")), p.impact_z);
        same_result(&doc, &pointer, &p.result);
    }
    let spots = sweet_spots(&modes, &ball, &swing, &options).unwrap();
    assert_eq!(num(&doc, "/sweet_spots/max_exit_speed_z"), spots.max_exit_speed_z);
    assert_eq!(num(&doc, "/sweet_spots/max_exit_speed"), spots.max_exit_speed);
    assert_eq!(num(&doc, "/sweet_spots/rigid_optimum_z"), spots.rigid_optimum_z);
    assert_eq!(num(&doc, "/sweet_spots/node1_z"), spots.node1_z);
    assert_eq!(num(&doc, "/sweet_spots/node2_z"), spots.node2_z);
    assert_eq!(num(&doc, "/sweet_spots/center_of_percussion_z"), spots.center_of_percussion_z);
    assert!(doc.pointer("/points/3/hoop").is_some(), "the aluminum barrel is hollow: its wall is in the JSON");
    let node1: Vec<f64> = doc["nodes"]["mode1"].as_array().unwrap().iter().filter_map(Value::as_f64).collect();
    assert_eq!(node1, modes.nodes(1));
}

#[test]
fn default_sweep_covers_the_barrel() {
    let doc = json(&["sweep", "--modes", "4", "--step", "0.05"]);
    let zs: Vec<f64> = doc["points"].as_array().unwrap().iter().map(|p| p["impact_z"].as_f64().unwrap()).collect();
    let length = num(&doc, "/bat/length");
    assert!(zs.len() >= 5, "{zs:?}");
    assert!((zs[0] - (length - 0.35)).abs() < 1e-12, "{zs:?}");
    assert!(zs.iter().all(|z| *z <= length - 0.01 + 1e-12), "{zs:?}");
}

#[test]
fn modes_json_matches_the_library() {
    let doc = json(&["modes", "--bat", "torpedo", "--modes", "5"]);
    has_exactly(&doc, "", &["bat", "modes"]);
    has_exactly(&doc, "/bat", BAT_FIELDS);
    has_exactly(&doc, "/modes/0", &["mode", "frequency_hz", "nodes", "modal_mass"]);
    let bat = Bat::preset("torpedo").unwrap();
    let set = ModeSet::compute(&bat, 5).unwrap();
    let frequencies = set.frequencies_hz();
    let listed = doc["modes"].as_array().unwrap();
    assert_eq!(listed.len(), 5);
    for (i, mode) in listed.iter().enumerate() {
        assert_eq!(mode["mode"].as_u64(), Some(i as u64 + 1));
        assert_eq!(mode["frequency_hz"].as_f64(), Some(frequencies[i]));
        assert_eq!(mode["modal_mass"].as_f64(), Some(set.modal_mass(i + 2)));
        let nodes: Vec<f64> = mode["nodes"].as_array().unwrap().iter().filter_map(Value::as_f64).collect();
        assert_eq!(nodes, set.nodes(i + 1));
        assert_eq!(nodes.len(), i + 2, "a free–free mode n has n + 1 nodes");
    }
    let props = set.mass_properties();
    assert_eq!(num(&doc, "/bat/mass"), props.mass);
    assert_eq!(num(&doc, "/bat/radius_of_gyration"), props.radius_of_gyration);
    assert_eq!(num(&doc, "/bat/center_of_percussion"), props.center_of_percussion(0.1524));
}

#[test]
fn bbcor_json_matches_the_library() {
    let doc = json(&["bbcor", "--bat", "r161", "--modes", "12"]);
    has_exactly(&doc, "", &["bat", "ball", "options", "bbcor", "besr"]);
    has_exactly(
        &doc,
        "/bbcor",
        &[
            "bbcor",
            "impact_z",
            "collision_efficiency",
            "ball_speed",
            "bat_speed",
            "pivot_z",
            "search_from_z",
            "search_to_z",
        ],
    );
    has_exactly(
        &doc,
        "/besr",
        &[
            "besr",
            "impact_z",
            "exit_speed",
            "ball_speed",
            "bat_speed",
            "pivot_z",
            "best_besr",
            "best_impact_z",
            "best_exit_speed",
        ],
    );
    let bat = Bat::preset("r161").unwrap();
    let options = CollisionOptions { modes: 12, ..CollisionOptions::default() };
    let modes = ModeSet::compute(&bat, 12).unwrap();
    let ball = Ball::bbcor_protocol();
    let report = bbcor_report(&modes, &ball, &options).unwrap();
    assert_eq!(num(&doc, "/bbcor/bbcor"), report.bbcor);
    assert_eq!(num(&doc, "/bbcor/impact_z"), report.impact_z);
    assert_eq!(num(&doc, "/bbcor/ball_speed"), report.ball_speed);
    let b = besr(&modes, &ball, &options).unwrap();
    assert_eq!(num(&doc, "/besr/besr"), b.besr);
    assert_eq!(num(&doc, "/besr/exit_speed"), b.exit_speed);
    let best = besr_scan(&modes, &ball, &options).unwrap();
    assert_eq!(num(&doc, "/besr/best_besr"), best.besr);
    assert_eq!(num(&doc, "/besr/best_impact_z"), best.impact_z);
    assert_eq!(num(&doc, "/besr/best_exit_speed"), best.exit_speed);
    assert!(best.exit_speed >= b.exit_speed, "the scan includes the 6-in point's neighbourhood");
    assert_eq!(num(&doc, "/ball/cor"), ball.cor);
}

/// Every field path of a JSON value in output order (`a.b`, arrays as `a[]`, their elements' fields merged).
fn field_paths(value: &Value, prefix: &str, out: &mut Vec<String>) {
    match value {
        Value::Object(map) => {
            for (key, child) in map {
                let path = if prefix.is_empty() { key.clone() } else { format!("{prefix}.{key}") };
                if !matches!(child, Value::Object(_) | Value::Array(_)) && !out.contains(&path) {
                    out.push(path.clone());
                }
                field_paths(child, &path, out);
            }
        }
        Value::Array(items) => {
            let path = format!("{prefix}[]");
            for item in items {
                field_paths(item, &path, out);
            }
        }
        _ => {}
    }
}

/// The `simulate --json` interface, pinned: every field name, in output order. A change here is a change of
/// the documented interface (docs/file-formats.md), so the docs are checked against the output as well.
#[test]
fn simulate_json_field_names_are_exactly_the_documented_ones_in_order() {
    const PINNED: &[&str] = &[
        "bat.name",
        "bat.mass",
        "bat.length",
        "bat.center_of_mass",
        "bat.moment_of_inertia",
        "bat.radius_of_gyration",
        "bat.pivot_z",
        "bat.moment_about_pivot",
        "bat.center_of_percussion",
        "ball.mass",
        "ball.radius",
        "ball.stiffness",
        "ball.exponent",
        "ball.cor",
        "ball.cor_speed_exponent",
        "ball.cor_reference_speed",
        "swing.ball_speed",
        "swing.bat_cm_speed",
        "swing.bat_angular_speed",
        "options.modes",
        "options.time_step",
        "results[].impact_z",
        "results[].exit_speed",
        "results[].rigid_exit_speed",
        "results[].effective_cor",
        "results[].collision_efficiency",
        "results[].contact_time",
        "results[].peak_force",
        "results[].impulse",
        "results[].max_compression",
        "results[].energy.initial",
        "results[].energy.ball",
        "results[].energy.bat_rigid",
        "results[].energy.vibration",
        "results[].energy.hysteresis_loss",
        "results[].energy.residual",
        "results[].mode_energies[].mode",
        "results[].mode_energies[].frequency_hz",
        "results[].mode_energies[].energy",
    ];
    let doc = json(&["simulate", "--bat", "torpedo", "--modes", "3", "--impact-z", "0.6,0.7"]);
    let mut paths = Vec::new();
    field_paths(&doc, "", &mut paths);
    assert_eq!(paths, PINNED);
    let top: Vec<&str> = doc.as_object().expect("an object").keys().map(String::as_str).collect();
    assert_eq!(top, ["bat", "ball", "swing", "options", "results"]);

    // docs/file-formats.md lists the same: the top-level keys, the bat table and the collision-result table
    // (in output order), and the mode_energies entry's fields.
    let docs = std::fs::read_to_string(support::repo().join("docs/file-formats.md")).expect("docs/file-formats.md");
    assert!(
        docs.contains(r#"`{"bat", "ball", "swing", "options", "results": [collision result, …]}`"#),
        "simulate's top level"
    );
    let table_after = |heading: &str| -> Vec<String> {
        let start = docs.find(heading).unwrap_or_else(|| panic!("'{heading}' in docs/file-formats.md"));
        docs[start..]
            .lines()
            .skip_while(|l| !l.starts_with("| `"))
            .take_while(|l| l.starts_with('|'))
            .filter_map(|l| l.split('`').nth(1).map(str::to_string))
            .collect()
    };
    let documented_bat: Vec<String> =
        table_after("`bat` (mass properties").iter().map(|f| format!("bat.{f}")).collect();
    let documented_result: Vec<String> =
        table_after("A collision result:").iter().map(|f| format!("results[].{f}")).collect();
    let output_result: Vec<String> =
        paths.iter().filter(|p| p.starts_with("results[].") && !p.contains("mode_energies")).cloned().collect();
    assert_eq!(documented_bat, paths.iter().filter(|p| p.starts_with("bat.")).cloned().collect::<Vec<_>>());
    assert_eq!(documented_result[..documented_result.len() - 1], output_result[..], "the collision-result table");
    assert_eq!(documented_result.last().map(String::as_str), Some("results[].mode_energies[]"));
    let mode_row = docs.lines().find(|l| l.starts_with("| `mode_energies[]`")).expect("the mode_energies row");
    for field in ["mode", "frequency_hz", "energy"] {
        assert!(mode_row.contains(&format!("`{field}`")), "mode_energies[].{field} is not documented: {mode_row}");
    }
}
