//! `import` carries the trackers' 3-D columns into the Swing: TrackMan's Direction, HitSpinAxis and
//! BatterSide, Savant's stand, attack_direction, swing_path_tilt and hit-chart coordinates. Values are
//! checked against the CSV cells converted by hand; blank cells stay "not measured"; a hostile cell refuses
//! its row (named by line) while the rows around it are imported. The sign conventions are pinned with a
//! real TrackMan row and with the model's 3-D collision.

use std::path::Path;

use sweetspot::calibrate::read_inputs;
use sweetspot::import::{import_files, ImportReport};
use sweetspot::msgs::sweetspot_msgs::msg::Swing;
use sweetspot::physics::oblique::{ObliqueImpact, TangentialContact};
use sweetspot::physics::oblique3d::{collide_spatial, BatterSide, ContactFrame, SpatialImpact};
use sweetspot::physics::{Ball, Bat, CollisionOptions, Impact, ModeSet};

mod support;

use support::import::{data, options};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn swings_of(bag: &Path) -> Vec<Swing> {
    read_inputs(bag).unwrap().swings.into_iter().map(|(_, s)| s).collect()
}

/// A CSV of a fixture's header (plus `extra` columns) with copies of its row on `template_line`, cells set.
fn write_rows(fixture: &str, template_line: usize, extra: &[&str], rows: &[Vec<(&str, &str)>], out: &Path) {
    let mut reader = csv::Reader::from_path(data(fixture)).unwrap();
    let mut header: Vec<String> =
        reader.headers().unwrap().iter().map(|h| h.trim_start_matches('\u{feff}').to_string()).collect();
    let mut template: Vec<String> =
        reader.records().nth(template_line - 2).unwrap().unwrap().iter().map(String::from).collect();
    for name in extra {
        header.push((*name).to_string());
        template.push(String::new());
    }
    let mut w = csv::Writer::from_path(out).unwrap();
    w.write_record(&header).unwrap();
    for cells in rows {
        let mut row = template.clone();
        for (name, value) in cells {
            let i = header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
            row[i] = (*value).to_string();
        }
        w.write_record(&row).unwrap();
    }
    w.flush().unwrap();
}

fn refused_on(report: &ImportReport, line: u64, text: &str) -> bool {
    report.refused.iter().any(|r| r.contains(&format!("line {line}: ")) && r.contains(text))
}

#[test]
fn trackman_direction_spin_axis_and_batter_side_reach_the_swing() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("tm");
    let report = import_files(&[data("trackman_game.csv")], &bag, &options()).unwrap();
    assert_eq!(report.swings, 5);
    let swings = swings_of(&bag);
    // By hand, deg × π/180: Direction −29.586236° = −0.516377 rad, HitSpinAxis 149.822007° = 2.614887 rad
    // (line 3, a right-handed batter's foul, no HitSpinRate).
    let foul = &swings[0];
    assert!(close(foul.measured_spray_angle, -0.516377, 1e-6), "{}", foul.measured_spray_angle);
    assert!(close(foul.measured_spin_axis, 2.614887, 1e-6), "{}", foul.measured_spin_axis);
    assert!(foul.measured_spin.is_nan(), "an axis without a rate is no spin");
    assert_eq!(foul.batter_side, Swing::BATTER_RIGHT);
    // Line 5: Direction 10.739672° = 0.187443 rad; HitSpinAxis 254.393031° = 4.439996 rad; HitSpinRate
    // 2740.943835 rpm × 2π/60 = 287.0310 rad/s, the total spin.
    let single = &swings[1];
    assert!(close(single.measured_spray_angle, 0.187443, 1e-6));
    assert!(close(single.measured_spin_axis, 4.439996, 1e-6));
    assert!(close(single.measured_spin, 287.0310, 1e-4), "{}", single.measured_spin);
    // Line 6: BatterSide Left; Direction −20.087253° = −0.350589 rad; HitSpinAxis 142.58367° = 2.488555 rad.
    let left = &swings[2];
    assert_eq!(left.batter_side, Swing::BATTER_LEFT);
    assert!(close(left.measured_spray_angle, -0.350589, 1e-6));
    assert!(close(left.measured_spin_axis, 2.488555, 1e-6));
    // Line 7: HitSpinRate without HitSpinAxis: neither is measured; Direction 36.741038° = 0.641252 rad.
    assert!(swings[3].measured_spin_axis.is_nan() && swings[3].measured_spin.is_nan());
    assert!(close(swings[3].measured_spray_angle, 0.641252, 1e-6));
    // Line 8: blank Direction and HitSpinAxis: not measured.
    assert!(swings[4].measured_spray_angle.is_nan() && swings[4].measured_spin_axis.is_nan());
    // TrackMan measures no bat: the planar swing's level bat toward centre field.
    assert!(swings.iter().all(|s| s.bat_tilt == 0.0 && s.swing_direction == 0.0));
}

/// A right-handed batter's pulled ball goes to left field (Direction < 0) and hooks toward it: HitSpinAxis
/// below 180°. The real row (line 3 of the export) says so, and so does the model: a right-handed swing whose
/// path points toward left field with the barrel below the hands sends the ball left of centre with its
/// spin axis below 180° (the Magnus force toward left field).
#[test]
fn a_right_handed_batters_pulled_ball_has_a_spin_axis_below_180_degrees_in_the_data_and_the_model() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("tm");
    import_files(&[data("trackman_game.csv")], &bag, &options()).unwrap();
    let pulled = &swings_of(&bag)[0];
    assert_eq!(pulled.batter_side, Swing::BATTER_RIGHT);
    assert!(pulled.measured_spray_angle < 0.0, "to left field");
    assert!(pulled.measured_spin_axis < std::f64::consts::PI, "hooks toward left field");

    let modes = ModeSet::compute(&Bat::preset("r161").unwrap(), 8).unwrap();
    let impact = Impact { ball_speed: 38.0, bat_cm_speed: 22.0, bat_angular_speed: 48.0, impact_z: 0.70 };
    let oblique = ObliqueImpact {
        undercut: 0.012,
        attack_angle: 10f64.to_radians(),
        pitch_angle: 6f64.to_radians(),
        pitch_spin: 230.0,
        ..ObliqueImpact::head_on(impact, 0.0325)
    };
    let options = CollisionOptions { modes: 8, time_step: 2e-6 };
    let contact = TangentialContact::default();
    let ball = Ball::default();
    for side in [BatterSide::Right, BatterSide::Left] {
        // The pull side: left field for a right-handed batter, right field for a left-handed one.
        let pull = match side {
            BatterSide::Right => -20f64.to_radians(),
            BatterSide::Left => 20f64.to_radians(),
        };
        let swing = SpatialImpact { oblique, bat_tilt: 30f64.to_radians(), swing_direction: pull, batter_side: side };
        let r = collide_spatial(&modes, &ball, &swing, &contact, &options).unwrap();
        assert_eq!(r.spray_angle.signum(), pull.signum(), "{side:?}: the ball goes to the pull side ({r:?})");
        // Toward left field the axis is below 180° (hook), toward right field above it (the mirror).
        assert_eq!(r.spin_axis < std::f64::consts::PI, pull < 0.0, "{side:?}: spin axis {}°", r.spin_axis.to_degrees());
    }
}

#[test]
fn hostile_trackman_cells_refuse_their_row_and_the_rest_is_imported() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("tm.csv");
    let rows = vec![
        vec![("Direction", "left")],
        vec![("Direction", "95")],
        vec![("HitSpinAxis", "400")],
        vec![("HitSpinAxis", "inf")],
        vec![("BatterSide", "Switch")],
        vec![("Direction", "-90"), ("HitSpinAxis", "360")],
        vec![("Direction", ""), ("HitSpinAxis", "NA"), ("BatterSide", "")],
    ];
    write_rows("trackman_game.csv", 5, &[], &rows, &csv);
    let bag = tmp.path().join("bag");
    let report = import_files(&[csv], &bag, &options()).unwrap();
    assert_eq!(report.swings, 2, "{:?}", report.refused);
    assert!(refused_on(&report, 2, "Direction = \"left\" is not a number"), "{:?}", report.refused);
    assert!(refused_on(&report, 3, "spray angle gives 1.658"), "{:?}", report.refused);
    // 400° = 6.981 rad.
    assert!(refused_on(&report, 4, "spin axis gives 6.98"), "{:?}", report.refused);
    assert!(refused_on(&report, 5, "HitSpinAxis = \"inf\" is not a number"), "{:?}", report.refused);
    assert!(refused_on(&report, 6, "BatterSide = \"Switch\" is not one of"), "{:?}", report.refused);
    let swings = swings_of(&bag);
    // The boundaries pass: −90° exactly, and 360° (= 0°, the field holds [0, 2π)).
    assert!(close(swings[0].measured_spray_angle, -std::f64::consts::FRAC_PI_2, 1e-15));
    assert_eq!(swings[0].measured_spin_axis, 0.0);
    // Blank cells: nothing measured, a right-handed batter by default.
    assert!(swings[1].measured_spray_angle.is_nan() && swings[1].measured_spin_axis.is_nan());
    assert_eq!(swings[1].batter_side, Swing::BATTER_RIGHT);
}

const STATCAST_EXTRA: [&str; 2] = ["attack_direction", "swing_path_tilt"];

#[test]
fn savant_bat_tracking_and_hit_chart_columns_reach_the_swing() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("savant.csv");
    // The fixture's line 2 has attack_angle 12°.
    let rows = vec![
        vec![
            ("stand", "R"),
            ("attack_direction", "5"),
            ("swing_path_tilt", "30"),
            ("hc_x", "225.42"),
            ("hc_y", "98.27"),
        ],
        vec![
            ("stand", "L"),
            ("attack_direction", "5"),
            ("swing_path_tilt", "12"),
            ("hc_x", "25.42"),
            ("hc_y", "98.27"),
        ],
        vec![("stand", "R"), ("attack_direction", ""), ("swing_path_tilt", "NA"), ("hc_x", ""), ("hc_y", "")],
    ];
    write_rows("statcast_search.csv", 2, &STATCAST_EXTRA, &rows, &csv);
    let bag = tmp.path().join("bag");
    let report = import_files(&[csv], &bag, &options()).unwrap();
    assert_eq!(report.swings, 3, "{:?}", report.refused);
    let swings = swings_of(&bag);
    let right = &swings[0];
    assert_eq!(right.batter_side, Swing::BATTER_RIGHT);
    // hc (225.42, 98.27) is 100 right of and 100 beyond the plate (125.42, 198.27): the right-field line, +45°.
    assert!(close(right.measured_spray_angle, std::f64::consts::FRAC_PI_4, 1e-12));
    // attack_direction +5°, toward the opposite field: right field for a right-handed batter.
    assert!(close(right.swing_direction, 5f64.to_radians(), 1e-12));
    // swing_path_tilt 30° with a 12° attack angle: sin ψ = √(sin²30° − sin²12°) = √(0.25 − 0.0432273)
    // = 0.454723, ψ = 27.0471° = 0.472061 rad.
    assert!(close(right.bat_tilt, 0.472061, 1e-6), "{}", right.bat_tilt);
    // Independently, the model's contact frame at that tilt and attack angle spans a plane 30° from the ground.
    let frame = ContactFrame::new(right.attack_angle, right.swing_direction, right.bat_tilt, 0.0);
    let plane_tilt = frame.axis.cross(&frame.path).z.acos();
    assert!(close(plane_tilt, 30f64.to_radians(), 1e-9), "{}", plane_tilt.to_degrees());
    let left = &swings[1];
    assert_eq!(left.batter_side, Swing::BATTER_LEFT);
    // The left-field line, −45°; the opposite field of a left-handed batter is left field: −5°.
    assert!(close(left.measured_spray_angle, -std::f64::consts::FRAC_PI_4, 1e-12));
    assert!(close(left.swing_direction, -5f64.to_radians(), 1e-12));
    // A path as steep as its plane: the bat lies level (sin²12° − sin²12° = 0).
    assert!(left.bat_tilt.abs() < 1e-7, "{}", left.bat_tilt);
    let blank = &swings[2];
    assert!(blank.measured_spray_angle.is_nan());
    assert_eq!((blank.bat_tilt, blank.swing_direction), (0.0, 0.0), "not measured: the planar swing");
    assert!(swings.iter().all(|s| s.measured_spin_axis.is_nan()), "Savant measures no batted-ball spin");
}

#[test]
fn hostile_savant_cells_refuse_their_row_and_the_rest_is_imported() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("savant.csv");
    let rows = vec![
        vec![("swing_path_tilt", "steep")],
        vec![("swing_path_tilt", "8")],
        vec![("swing_path_tilt", "95")],
        vec![("stand", "S")],
        vec![("stand", ""), ("attack_direction", "4")],
        vec![("attack_direction", "80.01")],
        vec![("hc_x", "inf"), ("hc_y", "100")],
        vec![("hc_x", "125.42"), ("hc_y", "250")],
        vec![("swing_path_tilt", "80.01"), ("attack_angle", "0")],
        vec![("stand", "L"), ("attack_direction", "-79.99"), ("swing_path_tilt", "79.99"), ("attack_angle", "0")],
    ];
    write_rows("statcast_search.csv", 2, &STATCAST_EXTRA, &rows, &csv);
    let bag = tmp.path().join("bag");
    let report = import_files(&[csv], &bag, &options()).unwrap();
    assert!(refused_on(&report, 2, "swing_path_tilt = \"steep\" is not a number"), "{:?}", report.refused);
    // The fixture row's attack angle is 12°: a path cannot climb more steeply than its 8° plane.
    assert!(refused_on(&report, 3, "swing_path_tilt ≥ |attack_angle|"), "{:?}", report.refused);
    assert!(refused_on(&report, 4, "0° ≤ swing_path_tilt ≤ 90°"), "{:?}", report.refused);
    assert!(refused_on(&report, 5, "stand = \"S\" is not one of"), "{:?}", report.refused);
    assert!(
        refused_on(&report, 6, "stand = \"\" is not one of R or L with an attack_direction"),
        "{:?}",
        report.refused
    );
    // 80.01° = 1.39644 rad: beyond the model's 80°; 79.99° passes (the last row).
    assert!(refused_on(&report, 7, "swing_direction gives 1.396"), "{:?}", report.refused);
    assert!(refused_on(&report, 8, "hc_x = \"inf\" is not a number"), "{:?}", report.refused);
    // Behind the plate: atan2(0, 198.27 − 250) = π.
    assert!(refused_on(&report, 9, "spray angle gives 3.14"), "{:?}", report.refused);
    // A level path: the bat tilts as its plane, 80.01° beyond the model's 80°; 79.99° passes.
    assert!(refused_on(&report, 10, "bat_tilt gives 1.396"), "{:?}", report.refused);
    assert_eq!(report.swings, 1, "{:?}", report.refused);
    let swing = &swings_of(&bag)[0];
    assert!(close(swing.swing_direction, 79.99f64.to_radians(), 1e-12), "left-handed: the sign turns");
    assert!(close(swing.bat_tilt, 79.99f64.to_radians(), 1e-9), "{}", swing.bat_tilt);
}
