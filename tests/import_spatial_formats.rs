//! The 3-D columns of HitTrax's export (`Horiz. Angle`, `Batting`) and of a user's column map (spray angle,
//! spin axis, batter side, bat tilt, swing direction) reach the Swing. Values are checked against the cells
//! converted by hand; the spray angle's sign is checked against where a fielder stands (a ground ball to the
//! shortstop or third baseman goes to the left side, negative; one to the second baseman to the right side,
//! positive) for right- and left-handed batters alike. Blank cells stay "not measured", a hostile cell refuses
//! its row (named by line) while the rows around it are imported, and exports without the columns import as
//! before.

use std::path::Path;

use sweetspot::calibrate::read_inputs;
use sweetspot::import::mapped::ColumnMap;
use sweetspot::import::{import_files, ImportError, ImportOptions, ImportReport};
use sweetspot::msgs::sweetspot_msgs::msg::Swing;

mod support;

use support::import::{data, options};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn swings_of(bag: &Path) -> Vec<Swing> {
    read_inputs(bag).unwrap().swings.into_iter().map(|(_, s)| s).collect()
}

fn refused_on(report: &ImportReport, line: u64, text: &str) -> bool {
    report.refused.iter().any(|r| r.contains(&format!("line {line}: ")) && r.contains(text))
}

/// A HitTrax CSV of the session fixture's header with copies of its line 3 (a pitched line drive, Velo 87.3),
/// cells set.
fn hittrax_rows(rows: &[Vec<(&str, &str)>], out: &Path) {
    let mut reader = csv::Reader::from_path(data("hittrax_session.csv")).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    let template: Vec<String> = reader.records().nth(1).unwrap().unwrap().iter().map(String::from).collect();
    let mut w = csv::Writer::from_path(out).unwrap();
    w.write_record(&header).unwrap();
    for cells in rows {
        let mut row = template.clone();
        for (name, value) in cells {
            let i = header.iter().position(|h| h.trim() == *name).unwrap_or_else(|| panic!("no column {name}"));
            row[i] = (*value).to_string();
        }
        w.write_record(&row).unwrap();
    }
    w.flush().unwrap();
}

#[test]
fn hittrax_horiz_angle_and_batting_reach_the_swing() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("cage");
    let tee = ImportOptions { tee: true, ..options() };
    let report = import_files(&[data("hittrax_session.csv")], &bag, &tee).unwrap();
    assert_eq!(report.swings, 3, "{:?}", report.refused);
    let swings = swings_of(&bag);
    // Line 2, the real export's row: Res 4-3 (fielded by the second baseman, right of second base) at
    // Horiz. Angle 4° = 0.0698131701 rad: positive, toward right field as Swing.msg's spray angle. Its
    // Batting cell is blank: a right-handed batter, the planar default.
    assert!(close(swings[0].measured_spray_angle, 0.0698131701, 1e-10), "{}", swings[0].measured_spray_angle);
    assert_eq!(swings[0].batter_side, Swing::BATTER_RIGHT);
    // Line 3: a single at −12° = −0.2094395102 rad, Batting R.
    assert!(close(swings[1].measured_spray_angle, -0.2094395102, 1e-10), "{}", swings[1].measured_spray_angle);
    assert_eq!(swings[1].batter_side, Swing::BATTER_RIGHT);
    // Line 5: a 6-3 ground ball (to the shortstop, left of second base) at −8° = −0.1396263402 rad.
    assert!(close(swings[2].measured_spray_angle, -0.1396263402, 1e-10), "{}", swings[2].measured_spray_angle);
    // HitTrax measures no spin axis and no bat: those stay the planar swing's.
    assert!(swings.iter().all(|s| s.measured_spin_axis.is_nan() && s.bat_tilt == 0.0 && s.swing_direction == 0.0));
}

/// `Horiz. Angle` is in the field frame for either batter: a right-hander's pulled grounder to third (5-3)
/// and a left-hander's opposite-field grounder to short (6-3) are both negative (left side); a left-hander's
/// pulled grounder to second (4-3) is positive. The import keeps the sign (no mirroring by batter side).
#[test]
fn hittrax_spray_sign_follows_the_fielders_for_either_batter() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("sides.csv");
    let rows = vec![
        vec![("Res", "5-3"), ("Horiz. Angle", "-27"), ("Batting", "R")],
        vec![("Res", "4-3"), ("Horiz. Angle", "21"), ("Batting", "L")],
        vec![("Res", "6-3"), ("Horiz. Angle", "-6"), ("Batting", "L")],
        // Straight away: 0° is centre field, measured (the misses HitTrax fills with 0 have no Velo).
        vec![("Res", "1B"), ("Horiz. Angle", "0"), ("Batting", "Left")],
        vec![("Res", "1B"), ("Horiz. Angle", ""), ("Batting", "")],
    ];
    hittrax_rows(&rows, &csv);
    let bag = tmp.path().join("bag");
    let report = import_files(&[csv], &bag, &options()).unwrap();
    assert_eq!(report.swings, 5, "{:?}", report.refused);
    let s = swings_of(&bag);
    // −27° = −0.4712388980 rad; 21° = 0.3665191429 rad; −6° = −0.1047197551 rad.
    assert!(close(s[0].measured_spray_angle, -0.4712388980, 1e-10) && s[0].batter_side == Swing::BATTER_RIGHT);
    assert!(close(s[1].measured_spray_angle, 0.3665191429, 1e-10) && s[1].batter_side == Swing::BATTER_LEFT);
    assert!(close(s[2].measured_spray_angle, -0.1047197551, 1e-10) && s[2].batter_side == Swing::BATTER_LEFT);
    assert!(s[3].measured_spray_angle == 0.0 && s[3].batter_side == Swing::BATTER_LEFT);
    assert!(s[4].measured_spray_angle.is_nan() && s[4].batter_side == Swing::BATTER_RIGHT);
}

#[test]
fn hostile_hittrax_cells_refuse_their_row_and_the_rest_is_imported() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("hostile.csv");
    let rows = vec![
        vec![("Horiz. Angle", "left")],
        vec![("Horiz. Angle", "95")],
        vec![("Horiz. Angle", "inf")],
        vec![("Batting", "S")],
        vec![("Batting", "=cmd()")],
        vec![("Horiz. Angle", "-90"), ("Batting", "l")],
        vec![("Horiz. Angle", "NA"), ("Batting", "NA")],
    ];
    hittrax_rows(&rows, &csv);
    let bag = tmp.path().join("bag");
    let report = import_files(&[csv], &bag, &options()).unwrap();
    assert_eq!(report.swings, 2, "{:?}", report.refused);
    assert!(refused_on(&report, 2, "Horiz. Angle = \"left\" is not a number"), "{:?}", report.refused);
    // 95° = 1.658 rad, beyond the foul line's 90°.
    assert!(refused_on(&report, 3, "spray angle gives 1.658"), "{:?}", report.refused);
    assert!(refused_on(&report, 4, "Horiz. Angle = \"inf\" is not a number"), "{:?}", report.refused);
    assert!(refused_on(&report, 5, "Batting = \"S\" is not one of"), "{:?}", report.refused);
    assert!(refused_on(&report, 6, "Batting = \"=cmd()\" is not one of"), "{:?}", report.refused);
    let s = swings_of(&bag);
    // The boundary passes: −90° exactly; a lower-case l is a left-handed batter.
    assert!(close(s[0].measured_spray_angle, -std::f64::consts::FRAC_PI_2, 1e-15));
    assert_eq!(s[0].batter_side, Swing::BATTER_LEFT);
    assert!(s[1].measured_spray_angle.is_nan() && s[1].batter_side == Swing::BATTER_RIGHT);
}

/// An export from before HitTrax wrote these columns (or trimmed of them) imports as it always did.
#[test]
fn a_hittrax_export_without_the_columns_imports_as_before() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("narrow.csv");
    std::fs::write(&csv, "AB,Date,Pitch,Velo,LA,Res\n1,11/26/2018 16:09:02.120,55.0,87.3,18, 1B\n").unwrap();
    let bag = tmp.path().join("bag");
    let report = import_files(&[csv], &bag, &options()).unwrap();
    assert_eq!(report.swings, 1);
    let s = &swings_of(&bag)[0];
    assert!(s.measured_spray_angle.is_nan() && s.measured_spin_axis.is_nan());
    assert_eq!((s.batter_side, s.bat_tilt, s.swing_direction), (Swing::BATTER_RIGHT, 0.0, 0.0));
}

const MAP_3D: &str = r#"
name = "lab-3d"
[columns]
pitch_speed = "Pitch"
exit_speed = "Exit"
spin = "Spin"
spray_angle = "Spray"
spin_axis = "Axis"
batter_side = "Hand"
bat_tilt = "Tilt"
swing_direction = "Path"
[units]
bat_tilt = "rad"
"#;

fn mapped_import(map_text: &str, csv_text: &str, dir: &Path) -> Result<ImportReport, ImportError> {
    let map = dir.join("map.toml");
    std::fs::write(&map, map_text).unwrap();
    let csv = dir.join("lab.csv");
    std::fs::write(&csv, csv_text).unwrap();
    let options = ImportOptions { map: Some(ColumnMap::load(&map)?), ..options() };
    import_files(&[csv], &dir.join("bag"), &options)
}

#[test]
fn a_map_names_the_3d_columns_with_their_units() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = "Pitch,Exit,Spin,Spray,Axis,Hand,Tilt,Path\n\
               80,95,2400,-20,150,R,0.5,-10\n\
               80,95,2400,15,210,1,-0.2,12\n\
               80,95,2400,5,,0,,\n\
               80,95,,,,Left,,\n";
    let report = mapped_import(MAP_3D, csv, tmp.path()).unwrap();
    assert_eq!(report.swings, 4, "{:?}", report.refused);
    let s = swings_of(&tmp.path().join("bag"));
    // Line 2, by hand: −20° = −0.3490658504 rad; axis 150° = 2.6179938780 rad; 2400 rpm × 2π/60 =
    // 251.3274123 rad/s (the total spin, as the axis is given); tilt 0.5 rad as it is; path −10° =
    // −0.1745329252 rad.
    assert!(close(s[0].measured_spray_angle, -0.3490658504, 1e-10), "{}", s[0].measured_spray_angle);
    assert!(close(s[0].measured_spin_axis, 2.6179938780, 1e-10), "{}", s[0].measured_spin_axis);
    assert!(close(s[0].measured_spin, 251.3274123, 1e-6), "{}", s[0].measured_spin);
    assert_eq!((s[0].batter_side, s[0].bat_tilt), (Swing::BATTER_RIGHT, 0.5));
    assert!(close(s[0].swing_direction, -0.1745329252, 1e-10), "{}", s[0].swing_direction);
    // Line 3: Hand 1 = Swing.msg's BATTER_LEFT; 15° = 0.2617993878 rad; 210° = 3.6651914292 rad.
    assert_eq!((s[1].batter_side, s[1].bat_tilt), (Swing::BATTER_LEFT, -0.2));
    assert!(close(s[1].measured_spray_angle, 0.2617993878, 1e-10));
    assert!(close(s[1].measured_spin_axis, 3.6651914292, 1e-10));
    assert!(close(s[1].swing_direction, 0.2094395102, 1e-10), "12° = 0.2094395102 rad");
    // Line 4: Hand 0 = BATTER_RIGHT; blank axis, tilt and path: not measured, the planar swing.
    assert_eq!((s[2].batter_side, s[2].bat_tilt, s[2].swing_direction), (Swing::BATTER_RIGHT, 0.0, 0.0));
    assert!(s[2].measured_spin_axis.is_nan() && close(s[2].measured_spray_angle, 0.0872664626, 1e-10));
    assert_eq!(s[3].batter_side, Swing::BATTER_LEFT);
}

#[test]
fn hostile_mapped_3d_cells_refuse_their_row_and_the_rest_is_imported() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = "Pitch,Exit,Spin,Spray,Axis,Hand,Tilt,Path\n\
               80,95,2400,95,150,R,0.5,-10\n\
               80,95,2400,5,400,R,0.5,-10\n\
               80,95,2400,5,150,2,0.5,-10\n\
               80,95,2400,5,150,R,1.4,-10\n\
               80,95,2400,5,150,R,0.5,81\n\
               80,95,2400,5,150,R,0.5,north\n\
               80,95,-5,5,150,R,0.5,-10\n\
               80,95,2400,-90,360,L,-0.5,80\n";
    let report = mapped_import(MAP_3D, csv, tmp.path()).unwrap();
    assert_eq!(report.swings, 1, "{:?}", report.refused);
    assert!(refused_on(&report, 2, "spray angle gives 1.658"), "95°: {:?}", report.refused);
    assert!(refused_on(&report, 3, "spin axis gives 6.98"), "400°: {:?}", report.refused);
    assert!(refused_on(&report, 4, "batter_side = \"2\" is not one of"), "{:?}", report.refused);
    // 1.4 rad = 80.2°, beyond the model's 80°.
    assert!(refused_on(&report, 5, "bat_tilt gives 1.4"), "{:?}", report.refused);
    assert!(refused_on(&report, 6, "swing_direction gives 1.41"), "81°: {:?}", report.refused);
    assert!(refused_on(&report, 7, "swing_direction = \"north\" is not a number"), "{:?}", report.refused);
    assert!(refused_on(&report, 8, "total spin ≥ 0"), "{:?}", report.refused);
    // The boundaries pass: spray −90°, axis 360° (= 0°), swing direction 80°.
    let s = &swings_of(&tmp.path().join("bag"))[0];
    assert!(close(s.measured_spray_angle, -std::f64::consts::FRAC_PI_2, 1e-15));
    assert_eq!((s.measured_spin_axis, s.batter_side), (0.0, Swing::BATTER_LEFT));
    assert!(close(s.swing_direction, 80f64.to_radians(), 1e-15));
}

#[test]
fn a_map_refuses_a_unit_its_quantity_cannot_have() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = "Pitch,Exit,Hand\n80,95,R\n";
    for (unit_line, named) in [("batter_side = \"deg\"", "batter_side"), ("spin_axis = \"rpm\"", "spin_axis")] {
        let map = format!("{MAP_3D}{unit_line}\n");
        let err = mapped_import(&map, csv, tmp.path()).unwrap_err().to_string();
        assert!(err.contains(&format!("of {named}")), "{err}");
    }
}
