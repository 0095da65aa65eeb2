//! The round trip of `import` and `locate`: swings simulated at known impact points and undercuts by the
//! node's own engine, written out as a TrackMan-style and a Statcast-style CSV (the real header layouts of
//! tests/data), imported, and located: noise-free rows give back the true impact point and undercut to 1 mm,
//! and with tracker-sized noise the truth lies within the reported uncertainty about as often as a standard
//! uncertainty promises; balls no impact point reproduces within tracker accuracy, or that the measurements do
//! not place on the barrel, are not located.

use std::path::Path;

use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use sweetspot::import::mapped::ColumnMap;
use sweetspot::import::statcast::plate_crossing;
use sweetspot::import::{backspin, deg, import_files, mph, rpm, ImportOptions, SwingBuilder, FOOT, MPH};
use sweetspot::locate::{
    locate_bag, BatSpeedFit, BatSpeedSolution, LocateOptions, Outcome, Solution, MAX_CHI2_PER_DOF, MAX_Z_SIGMA_SHARE,
};
use sweetspot::model::engine::{compute, plan_swing, Registry, SwingInput};
use sweetspot::model::settings::ModelSettings;
use sweetspot::physics::Impact;

mod support;

use support::import::{data, options};

/// Exit speed, launch angle and spin the node computes for `input` on the r161 with `baseball`, the ball the
/// imports here announce (`support::import::options`).
/// A level swing toward centre field with nothing measured: the fields a planar test leaves alone.
fn level() -> SwingInput {
    SwingInput::from(Impact { ball_speed: 0.0, bat_cm_speed: 0.0, bat_angular_speed: 0.0, impact_z: 0.0 })
}

fn simulate(input: SwingInput) -> [f64; 3] {
    let settings = ModelSettings::default();
    let mut registry = Registry::with_limits(settings.max_bats, settings.max_balls);
    let (plan, _) = plan_swing(&mut registry, &settings, "r161", "baseball", input);
    let c = compute(&plan, &()).expect("the swing computes");
    [c.launch.exit_speed, c.launch.launch_angle, c.launch.spin]
}

/// A CSV of `header` (a fixture's) with one copy of the fixture's row `template` per swing, cells replaced.
struct Export {
    header: Vec<String>,
    template: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Export {
    fn from_fixture(name: &str, template_line: usize) -> Export {
        let mut reader = csv::Reader::from_path(data(name)).unwrap();
        let header: Vec<String> =
            reader.headers().unwrap().iter().map(|h| h.trim_start_matches('\u{feff}').to_string()).collect();
        let template = reader.records().nth(template_line - 2).unwrap().unwrap().iter().map(String::from).collect();
        Export { header, template, rows: Vec::new() }
    }

    fn push(&mut self, cells: &[(&str, String)]) {
        let mut row = self.template.clone();
        for (name, value) in cells {
            let i = self.header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
            row[i] = value.clone();
        }
        self.rows.push(row);
    }

    fn write(&self, path: &Path, crlf: bool) {
        let mut w = csv::WriterBuilder::new()
            .terminator(if crlf { csv::Terminator::CRLF } else { csv::Terminator::Any(b'\n') })
            .from_path(path)
            .unwrap();
        w.write_record(&self.header).unwrap();
        for r in &self.rows {
            w.write_record(r).unwrap();
        }
        w.flush().unwrap();
    }
}

/// Truth: (impact_z, undercut), m — clear of the sweet spot (≈ 0.70 m on the r161) where dv/dz vanishes.
const TRUTH: [(f64, f64); 4] = [(0.62, 0.010), (0.65, -0.004), (0.76, 0.015), (0.79, 0.006)];

fn nearest(solutions: &[Solution], z: f64) -> &Solution {
    solutions.iter().min_by(|a, b| (a.impact_z - z).abs().total_cmp(&(b.impact_z - z).abs())).unwrap()
}

fn solutions_of(outcome: &Outcome) -> (&[Solution], Option<usize>) {
    match outcome {
        Outcome::Located { solutions, favoured, .. } => (solutions, *favoured),
        other => panic!("not located: {other:?}"),
    }
}

/// TrackMan rows for the truths: pitch 85 mph at −6° with 2300 rpm of backspin, the batter's assumed swing.
fn trackman_export(noise: Option<(u64, usize)>) -> (Export, Vec<(f64, f64)>) {
    let mut truths: Vec<(f64, f64)> = TRUTH.to_vec();
    let mut rng = rand::rngs::StdRng::seed_from_u64(noise.map_or(0, |n| n.0));
    if let Some((_, count)) = noise {
        let z = rand_distr::Uniform::new(0.60, 0.80);
        let d = rand_distr::Uniform::new(-0.005, 0.02);
        truths = (0..count)
            .map(|_| (z.sample(&mut rng), d.sample(&mut rng)))
            .filter(|(z, _)| (z - 0.705f64).abs() > 0.03)
            .collect();
    }
    let export = trackman_rows(&truths, noise.is_some(), 1.0, &mut rng);
    (export, truths)
}

/// TrackMan rows for `truths`, with tracker noise from `rng` if `noisy`, the batter swinging `scale` times the
/// speed the import assumes for him.
fn trackman_rows(truths: &[(f64, f64)], noisy: bool, scale: f64, rng: &mut rand::rngs::StdRng) -> Export {
    let mut export = Export::from_fixture("trackman_game.csv", 5);
    let builder = SwingBuilder::new(&options()).unwrap();
    let mp = options().bat.mass_properties();
    let prediction = options().batter.predict(&mp).unwrap();
    let (zone_speed, vaa, spin_rate) = (85.0, -6.0, 2300.0);
    let base = SwingInput {
        impact: Impact {
            ball_speed: mph(zone_speed),
            bat_cm_speed: prediction.bat_cm_speed * scale,
            bat_angular_speed: prediction.bat_angular_speed * scale,
            impact_z: builder.impact_z(),
        },
        undercut: 0.0,
        attack_angle: 0.0,
        pitch_angle: -deg(vaa),
        pitch_spin: backspin(rpm(spin_rate), 180.0),
        measured_launch_angle: f64::NAN,
        measured_spin: f64::NAN,
        ..level()
    };
    let unit = Normal::new(0.0, 1.0).unwrap();
    let sigma = LocateOptions::default();
    for &(z, d) in truths {
        let mut input = base;
        input.impact.impact_z = z;
        input.undercut = d;
        let [mut v, mut theta, mut omega] = simulate(input);
        if noisy {
            v += sigma.exit_speed_sigma * unit.sample(rng);
            theta += sigma.launch_angle_sigma * unit.sample(rng);
            omega += sigma.spin_sigma * unit.sample(rng);
        }
        export.push(&[
            ("PitchCall", "InPlay".into()),
            ("ZoneSpeed", format!("{zone_speed}")),
            ("VertApprAngle", format!("{vaa}")),
            ("SpinRate", format!("{spin_rate}")),
            ("SpinAxis", "180".into()),
            ("ExitSpeed", format!("{}", v / MPH)),
            ("Angle", format!("{}", theta.to_degrees())),
            ("HitSpinRate", format!("{}", omega.abs() * 60.0 / (2.0 * std::f64::consts::PI))),
            ("HitSpinAxis", if omega >= 0.0 { "180" } else { "0" }.into()),
        ]);
    }
    export
}

#[test]
fn noise_free_trackman_rows_give_back_impact_point_and_undercut_to_a_millimetre() {
    let tmp = tempfile::tempdir().unwrap();
    let (export, truths) = trackman_export(None);
    let csv = tmp.path().join("trackman.csv");
    export.write(&csv, true);
    let bag = tmp.path().join("tm");
    let report = import_files(&[csv], &bag, &options()).unwrap();
    assert_eq!(report.swings, truths.len() as u64);
    let located = locate_bag(&bag, &LocateOptions::default()).unwrap();
    for (swing, &(z, d)) in located.swings.iter().zip(&truths) {
        let (solutions, favoured) = solutions_of(&swing.outcome);
        let s = nearest(solutions, z);
        assert!((s.impact_z - z).abs() < 1e-3, "swing {}: z {} against {z}", swing.swing_id, s.impact_z);
        assert!((s.undercut - d).abs() < 1e-3, "swing {}: D {} against {d}", swing.swing_id, s.undercut);
        // Three measurements, two unknowns: the truth fits exactly, and a solution the spin favours is the truth.
        assert!(s.chi2 < 1e-6, "swing {}: χ² {} at the truth", swing.swing_id, s.chi2);
        eprintln!("swing {}: χ² {:?}", swing.swing_id, solutions.iter().map(|s| s.chi2).collect::<Vec<_>>());
        if let Some(f) = favoured.map(|i| &solutions[i]) {
            assert!((f.impact_z - z).abs() < 1e-3, "swing {}: favoured the mirror solution {f:?}", swing.swing_id);
        }
    }
}

#[test]
fn noise_free_statcast_rows_give_back_impact_point_and_undercut_to_a_millimetre() {
    let tmp = tempfile::tempdir().unwrap();
    let mut export = Export::from_fixture("statcast_search.csv", 2);
    let builder = SwingBuilder::new(&options()).unwrap();
    // The pitch: a crossing at t = 0.40 s with v_y0 = −135 ft/s; bat tracking 72 mph, attack angle 8°.
    let (t, vy0) = (0.40, -135.0);
    let ay = 2.0 * (17.0 / 12.0 - 50.0 - vy0 * t) / (t * t);
    let (v0, a) = ([5.0, vy0, -5.0], [-10.0, ay, -18.0]);
    let crossing = plate_crossing(v0, a).unwrap();
    let (bat_speed, attack) = (72.0, 8.0);
    let (cm, omega) = builder.split_bat_speed(mph(bat_speed)).unwrap();
    for &(z, d) in &TRUTH {
        let input = SwingInput {
            impact: Impact {
                ball_speed: crossing.speed * FOOT,
                bat_cm_speed: cm,
                bat_angular_speed: omega,
                impact_z: z,
            },
            undercut: d,
            attack_angle: deg(attack),
            pitch_angle: crossing.descent_angle,
            pitch_spin: backspin(rpm(2300.0), 180.0),
            measured_launch_angle: f64::NAN,
            measured_spin: f64::NAN,
            ..level()
        };
        let [v, theta, _] = simulate(input);
        let cell = |x: f64| format!("{x}");
        export.push(&[
            ("description", "hit_into_play".into()),
            ("vx0", cell(v0[0])),
            ("vy0", cell(v0[1])),
            ("vz0", cell(v0[2])),
            ("ax", cell(a[0])),
            ("ay", cell(a[1])),
            ("az", cell(a[2])),
            ("release_spin_rate", "2300".into()),
            ("spin_axis", "180".into()),
            ("bat_speed", cell(bat_speed)),
            ("attack_angle", cell(attack)),
            ("launch_speed", cell(v / MPH)),
            ("launch_angle", cell(theta.to_degrees())),
        ]);
    }
    let csv = tmp.path().join("savant.csv");
    export.write(&csv, false);
    let bag = tmp.path().join("sc");
    import_files(&[csv], &bag, &options()).unwrap();
    let located = locate_bag(&bag, &LocateOptions::default()).unwrap();
    assert_eq!(located.swings.len(), TRUTH.len());
    for (swing, &(z, d)) in located.swings.iter().zip(&TRUTH) {
        let (solutions, _) = solutions_of(&swing.outcome);
        let s = nearest(solutions, z);
        assert!((s.impact_z - z).abs() < 1e-3, "swing {}: z {} against {z}", swing.swing_id, s.impact_z);
        assert!((s.undercut - d).abs() < 1e-3, "swing {}: D {} against {d}", swing.swing_id, s.undercut);
        assert!(s.chi2 < 1e-6, "two measurements, two unknowns: reproduced exactly");
    }
}

#[test]
fn with_tracker_noise_the_truth_lies_within_the_reported_uncertainty() {
    let tmp = tempfile::tempdir().unwrap();
    let (export, truths) = trackman_export(Some((7, 80)));
    let csv = tmp.path().join("noisy.csv");
    export.write(&csv, true);
    let bag = tmp.path().join("noisy");
    import_files(&[csv], &bag, &options()).unwrap();
    let located = locate_bag(&bag, &LocateOptions::default()).unwrap();
    let (mut within_z, mut within_d, mut n) = (0, 0, 0);
    for (swing, &(z, d)) in located.swings.iter().zip(&truths) {
        let Outcome::Located { solutions, .. } = &swing.outcome else { continue };
        // The solution on the true side of the sweet spot.
        let s = solutions.iter().find(|s| (s.impact_z < s.sweet_spot_z) == (z < s.sweet_spot_z));
        let Some(s) = s else { continue };
        n += 1;
        within_z += usize::from((s.impact_z - z).abs() <= s.impact_z_sigma);
        within_d += usize::from((s.undercut - d).abs() <= s.undercut_sigma);
    }
    let count = truths.len();
    assert!(n as f64 >= 0.9 * count as f64, "located {n} of {count}");
    // A standard uncertainty holds the truth 68 % of the time; with n ≈ 60 the binomial spread is ±6 %.
    let (share_z, share_d) = (within_z as f64 / n as f64, within_d as f64 / n as f64);
    eprintln!("within 1σ: impact_z {share_z:.2}, undercut {share_d:.2} of {n}");
    assert!((0.5..=0.86).contains(&share_z), "impact_z within 1σ in {share_z:.2} of {n} swings");
    assert!((0.5..=0.86).contains(&share_d), "undercut within 1σ in {share_d:.2} of {n} swings");
}

#[test]
fn a_ball_hit_harder_than_the_sweet_spot_allows_is_reported_with_the_excess() {
    let tmp = tempfile::tempdir().unwrap();
    let mut export = Export::from_fixture("trackman_game.csv", 5);
    // 85 mph pitch, the batter's assumed swing, launch angle and spin not measured: only the impact point is
    // free (undercut 0). 120 mph off the bat is more than any point of the r161 gives.
    let blank = String::new();
    export.push(&[
        ("ZoneSpeed", "85".into()),
        ("VertApprAngle", "-6".into()),
        ("SpinRate", "2300".into()),
        ("SpinAxis", "180".into()),
        ("ExitSpeed", "120".into()),
        ("Angle", blank.clone()),
        ("HitSpinRate", blank.clone()),
        ("HitSpinAxis", blank),
    ]);
    let csv = tmp.path().join("fast.csv");
    export.write(&csv, true);
    let bag = tmp.path().join("fast");
    import_files(&[csv], &bag, &options()).unwrap();
    let report = locate_bag(&bag, &LocateOptions::default()).unwrap();
    assert_eq!(report.too_fast, 1);
    let Outcome::TooFast { max_exit_speed, excess, sweet_spot_z } = report.swings[0].outcome else {
        panic!("{:?}", report.swings[0].outcome)
    };
    // The node's engine over a 1-mm grid of the barrel gives the same best exit speed and place.
    let mp = options().bat.mass_properties();
    let prediction = options().batter.predict(&mp).unwrap();
    let best = (550..=835)
        .map(|mm| {
            let z = mm as f64 / 1000.0;
            let input = SwingInput {
                impact: Impact {
                    ball_speed: mph(85.0),
                    bat_cm_speed: prediction.bat_cm_speed,
                    bat_angular_speed: prediction.bat_angular_speed,
                    impact_z: z,
                },
                undercut: 0.0,
                attack_angle: 0.0,
                pitch_angle: deg(6.0),
                pitch_spin: rpm(2300.0),
                measured_launch_angle: f64::NAN,
                measured_spin: f64::NAN,
                ..level()
            };
            (z, simulate(input)[0])
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    assert!((max_exit_speed - best.1).abs() < 0.01, "{max_exit_speed} against {}", best.1);
    assert!((sweet_spot_z - best.0).abs() < 0.002, "{sweet_spot_z} against {}", best.0);
    assert!((excess - (120.0 * MPH - best.1)).abs() < 0.01, "{excess}");
}

/// A 1-mm scan of the barrel with the node's engine finds exactly the roots `locate` reports with only the
/// exit speed measured (its coarse grid misses none), each within a millimetre — including roots in the
/// grid's first and last cells, at the two ends of the search range.
#[test]
fn every_root_a_one_millimetre_scan_finds_is_located_and_no_other() {
    let mp = options().bat.mass_properties();
    let prediction = options().batter.predict(&mp).unwrap();
    let speed_at = |z: f64| {
        simulate(SwingInput {
            impact: Impact {
                ball_speed: mph(85.0),
                bat_cm_speed: prediction.bat_cm_speed,
                bat_angular_speed: prediction.bat_angular_speed,
                impact_z: z,
            },
            undercut: 0.0,
            attack_angle: 0.0,
            pitch_angle: deg(6.0),
            pitch_spin: rpm(2300.0),
            measured_launch_angle: f64::NAN,
            measured_spin: f64::NAN,
            ..level()
        })[0]
    };
    // The search range of `locate` on the r161 (0.8382 m): L/2 … L − 5 mm.
    let scan: Vec<(f64, f64)> = (420..=833).map(|mm| (mm as f64 / 1000.0, speed_at(mm as f64 / 1000.0))).collect();
    let peak = scan.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    // Two speeds whose roots lie in the grid's first and last cells: the exit speed halfway between the scan's
    // 426 and 427 mm (handle end of the search range) and 825 and 826 mm (8 mm from the barrel end). A grid
    // that stopped short of either end would bracket neither and lose that solution while still "locating".
    let between = |mm: usize| 0.5 * (scan[mm - 420].1 + scan[mm + 1 - 420].1);
    let targets = [peak - 8.0, peak - 3.0, peak - 1.0, peak - 0.3, between(426), between(825)];
    let tmp = tempfile::tempdir().unwrap();
    let mut export = Export::from_fixture("trackman_game.csv", 5);
    let blank = String::new();
    for v in targets {
        export.push(&[
            ("ZoneSpeed", "85".into()),
            ("VertApprAngle", "-6".into()),
            ("SpinRate", "2300".into()),
            ("SpinAxis", "180".into()),
            ("ExitSpeed", format!("{}", v / MPH)),
            ("Angle", blank.clone()),
            ("HitSpinRate", blank.clone()),
            ("HitSpinAxis", blank.clone()),
        ]);
    }
    let csv = tmp.path().join("speeds.csv");
    export.write(&csv, true);
    let bag = tmp.path().join("speeds");
    import_files(&[csv], &bag, &options()).unwrap();
    let report = locate_bag(&bag, &LocateOptions::default()).unwrap();
    for (swing, v) in report.swings.iter().zip(targets) {
        let crossings: Vec<f64> = scan
            .windows(2)
            .filter(|w| (w[0].1 - v).signum() != (w[1].1 - v).signum())
            .map(|w| w[0].0 + (w[1].0 - w[0].0) * (v - w[0].1) / (w[1].1 - w[0].1))
            .collect();
        let (solutions, _) = solutions_of(&swing.outcome);
        let found: Vec<f64> = solutions.iter().map(|s| s.impact_z).collect();
        assert_eq!(found.len(), crossings.len(), "v = {v}: located {found:?}, the scan crosses at {crossings:?}");
        for (z, c) in found.iter().zip(&crossings) {
            assert!((z - c).abs() < 1e-3, "v = {v}: located {z}, the scan crosses at {c}");
        }
    }
}

/// Swings of two batters give a figure with one panel each, and one marker per located solution: the favoured
/// filled, the others hollow — counted in the SVG read back with an XML parser.
#[test]
fn the_figure_has_a_panel_per_batter_and_a_marker_per_solution() {
    use quick_xml::events::Event;
    use sweetspot::locate::figure::{batters_of, draw_figure, Grouping, MARKER_RADIUS};

    let tmp = tempfile::tempdir().unwrap();
    let (mut export, _) = trackman_export(None);
    let batter_col = export.header.iter().position(|h| h == "Batter").unwrap();
    for (i, row) in export.rows.iter_mut().enumerate() {
        row[batter_col] = if i % 2 == 0 { "Batter A" } else { "Batter B" }.to_string();
    }
    let csv = tmp.path().join("two.csv");
    export.write(&csv, true);
    let bag = tmp.path().join("two");
    import_files(&[csv], &bag, &options()).unwrap();
    let report = locate_bag(&bag, &LocateOptions::default()).unwrap();
    let (mut favoured, mut others) = (0, 0);
    for swing in &report.swings {
        let (solutions, f) = solutions_of(&swing.outcome);
        favoured += usize::from(f.is_some());
        others += solutions.len() - usize::from(f.is_some());
    }
    let svg = tmp.path().join("figs/located.svg");
    let batters = batters_of(&bag).unwrap().expect("the import wrote its side table");
    let summary = draw_figure(&svg, &report, Some(&batters)).unwrap();
    assert_eq!(summary.grouping, Grouping::Batter);
    assert_eq!(summary.markers, (favoured, others));

    let text = std::fs::read_to_string(&svg).unwrap();
    let mut reader = quick_xml::Reader::from_str(&text);
    let (mut root, mut filled, mut hollow, mut titles) = (None, 0, 0, Vec::new());
    let mut in_text = false;
    loop {
        match reader.read_event().expect("well-formed XML") {
            Event::Start(e) | Event::Empty(e) => {
                let name = e.name().as_ref().to_string();
                root.get_or_insert(name.clone());
                in_text = name == "text";
                if name == "circle" {
                    let attr = |key: &str| {
                        e.attributes().flatten().find(|a| a.key.as_ref() == key).map(|a| a.value.to_string())
                    };
                    if attr("r").as_deref() == Some(MARKER_RADIUS.to_string().as_str()) {
                        if attr("fill").as_deref() == Some("none") {
                            hollow += 1;
                        } else {
                            filled += 1;
                        }
                    }
                }
            }
            Event::Text(t) if in_text => titles.push(t.trim().to_string()),
            Event::End(_) => in_text = false,
            Event::Eof => break,
            _ => {}
        }
    }
    assert_eq!(root.as_deref(), Some("svg"));
    assert!(favoured + others >= TRUTH.len(), "every truth located at least once");
    assert_eq!((filled, hollow), (favoured, others), "markers in the SVG against the report's solutions");
    for batter in ["Batter A", "Batter B"] {
        assert!(titles.iter().any(|t| t.starts_with(batter)), "no panel for {batter} among {titles:?}");
    }

    // A bag without the import's side table (recorded from a rig) names no batters: one panel per bat.
    std::fs::remove_file(bag.join(sweetspot::import::ROWS_TABLE)).unwrap();
    assert_eq!(batters_of(&bag).unwrap(), None);
    let summary = draw_figure(&tmp.path().join("per_bat.svg"), &report, None).unwrap();
    assert_eq!((summary.grouping, summary.panels.len()), (Grouping::Bat, 1));
    assert_eq!(summary.markers, (favoured, others));
}

/// The bat speed the swings of the bat-speed tests have over the one the import assumes.
const BAT_SPEED_SCALE: f64 = 1.10;
/// Truth (impact_z, undercut), m, for the bat-speed fit: balls undercut enough to spin (the spin is what tells
/// the bat speed from the impact point), clear of the sweet spot.
const BAT_TRUTH: [(f64, f64); 4] = [(0.62, 0.010), (0.64, 0.018), (0.76, 0.015), (0.79, 0.006)];

fn fit_options() -> LocateOptions {
    LocateOptions { fit_bat_speed: true, ..LocateOptions::default() }
}

fn bat_speed_solutions(fit: &Option<BatSpeedFit>) -> &[BatSpeedSolution] {
    match fit {
        Some(BatSpeedFit::Fitted { solutions, .. }) => solutions,
        other => panic!("bat speed not fitted: {other:?}"),
    }
}

fn nearest_fit(solutions: &[BatSpeedSolution], z: f64) -> &BatSpeedSolution {
    solutions.iter().min_by(|a, b| (a.impact_z - z).abs().total_cmp(&(b.impact_z - z).abs())).unwrap()
}

#[test]
fn noise_free_rows_with_spin_give_back_impact_point_undercut_and_a_bat_speed_ten_percent_off() {
    let tmp = tempfile::tempdir().unwrap();
    let mut rng = rand::rngs::StdRng::seed_from_u64(0);
    let export = trackman_rows(&BAT_TRUTH, false, BAT_SPEED_SCALE, &mut rng);
    let csv = tmp.path().join("trackman.csv");
    export.write(&csv, true);
    let bag = tmp.path().join("tm");
    import_files(&[csv], &bag, &options()).unwrap();
    // Without the option nothing is fitted and the JSON has no trace of it.
    let plain = locate_bag(&bag, &LocateOptions::default()).unwrap();
    assert!(plain.swings.iter().all(|s| s.bat_speed_fit.is_none()) && plain.bat_speed_fitted.is_none());
    let json = serde_json::to_string(&plain).unwrap();
    assert!(!json.contains("bat_speed"), "{json}");
    let located = locate_bag(&bag, &fit_options()).unwrap();
    assert_eq!(located.bat_speed_fitted, Some(BAT_TRUTH.len()));
    let mp = options().bat.mass_properties();
    let assumed = options().batter.predict(&mp).unwrap();
    for (swing, &(z, d)) in located.swings.iter().zip(&BAT_TRUTH) {
        let solutions = bat_speed_solutions(&swing.bat_speed_fit);
        eprintln!("swing {}: {solutions:?}", swing.swing_id);
        let s = nearest_fit(solutions, z);
        assert!((s.impact_z - z).abs() < 1e-3, "swing {}: z {} against {z}", swing.swing_id, s.impact_z);
        assert!((s.undercut - d).abs() < 1e-3, "swing {}: D {} against {d}", swing.swing_id, s.undercut);
        assert!((s.scale / BAT_SPEED_SCALE - 1.0).abs() < 1e-3, "swing {}: scale {}", swing.swing_id, s.scale);
        // The bat's speeds themselves, against the batter model's prediction the rows were simulated from.
        let v = assumed.bat_cm_speed * BAT_SPEED_SCALE;
        assert!((s.bat_cm_speed / v - 1.0).abs() < 1e-3, "swing {}: V {} against {v}", swing.swing_id, s.bat_cm_speed);
        let w = assumed.bat_angular_speed * BAT_SPEED_SCALE;
        assert!((s.bat_angular_speed / w - 1.0).abs() < 1e-3, "swing {}: ω {}", swing.swing_id, s.bat_angular_speed);
        assert!(s.chi2 < 1e-6 && s.scale_sigma > 0.0 && s.scale_sigma.is_finite() && s.impact_z_sigma > 0.0);
    }
    // The bag's JSON carries the fit.
    let json = serde_json::to_value(&located).unwrap();
    assert_eq!(json["bat_speed_fitted"], BAT_TRUTH.len());
    assert_eq!(json["swings"][0]["bat_speed_fit"]["verdict"], "fitted");
}

#[test]
fn with_tracker_noise_the_true_bat_speed_lies_within_the_reported_uncertainty() {
    let tmp = tempfile::tempdir().unwrap();
    let mut rng = rand::rngs::StdRng::seed_from_u64(24);
    let z = rand_distr::Uniform::new(0.60, 0.80);
    let d = rand_distr::Uniform::new(0.008, 0.02);
    let truths: Vec<(f64, f64)> = (0..60)
        .map(|_| (z.sample(&mut rng), d.sample(&mut rng)))
        .filter(|(z, _)| (z - 0.705f64).abs() > 0.04)
        .collect();
    let export = trackman_rows(&truths, true, BAT_SPEED_SCALE, &mut rng);
    let csv = tmp.path().join("trackman.csv");
    export.write(&csv, false);
    let bag = tmp.path().join("tm");
    import_files(&[csv], &bag, &options()).unwrap();
    let located = locate_bag(&bag, &fit_options()).unwrap();
    let (mut fitted, mut within_z, mut within_scale) = (0, 0, 0);
    for (swing, &(z, _)) in located.swings.iter().zip(&truths) {
        let Some(BatSpeedFit::Fitted { solutions, .. }) = &swing.bat_speed_fit else { continue };
        let s = nearest_fit(solutions, z);
        fitted += 1;
        within_z += usize::from((s.impact_z - z).abs() <= s.impact_z_sigma);
        within_scale += usize::from((s.scale - BAT_SPEED_SCALE).abs() <= s.scale_sigma);
    }
    let (share_z, share_scale) = (within_z as f64 / fitted as f64, within_scale as f64 / fitted as f64);
    eprintln!("{fitted} of {} fitted; within 1σ: z {share_z:.2}, bat speed {share_scale:.2}", truths.len());
    assert!(fitted as f64 >= 0.6 * truths.len() as f64, "{fitted} of {} fitted", truths.len());
    // A standard uncertainty holds the truth 68 % of the time; the fit is nonlinear over σ, so allow a margin.
    for (name, share) in [("z", share_z), ("bat speed", share_scale)] {
        assert!((0.5..=0.9).contains(&share), "{name}: truth within 1σ in {share:.2} of the swings");
    }
}

#[test]
fn a_swing_without_spin_is_not_fitted_for_bat_speed_and_says_why() {
    let tmp = tempfile::tempdir().unwrap();
    let mut rng = rand::rngs::StdRng::seed_from_u64(0);
    let mut export = trackman_rows(&BAT_TRUTH[..1], false, BAT_SPEED_SCALE, &mut rng);
    let spin = export.header.iter().position(|h| h == "HitSpinRate").unwrap();
    export.rows[0][spin] = String::new();
    let csv = tmp.path().join("trackman.csv");
    export.write(&csv, true);
    let bag = tmp.path().join("tm");
    import_files(&[csv], &bag, &options()).unwrap();
    let located = locate_bag(&bag, &fit_options()).unwrap();
    assert_eq!(located.bat_speed_fitted, Some(0));
    match &located.swings[0].bat_speed_fit {
        Some(BatSpeedFit::NotFitted { reason }) => assert!(reason.contains("no spin measured"), "{reason}"),
        other => panic!("expected not fitted, got {other:?}"),
    }
    // The impact point is still located from exit speed and launch angle.
    assert!(matches!(located.swings[0].outcome, Outcome::Located { .. }));
}

#[test]
fn a_swing_whose_spin_cannot_tell_bat_speed_from_impact_point_is_reported_not_separable() {
    // Topped 4 mm, 5.5 cm inside the sweet spot with a bat 10 % faster than assumed: the truth fits exactly,
    // but the spin hardly changes along the (z, bat speed) trade-off there, so σ(bat speed) is far above 25 %.
    let tmp = tempfile::tempdir().unwrap();
    let mut rng = rand::rngs::StdRng::seed_from_u64(0);
    let export = trackman_rows(&[(0.65, -0.004)], false, BAT_SPEED_SCALE, &mut rng);
    let csv = tmp.path().join("trackman.csv");
    export.write(&csv, true);
    let bag = tmp.path().join("tm");
    import_files(&[csv], &bag, &options()).unwrap();
    let located = locate_bag(&bag, &fit_options()).unwrap();
    assert_eq!(located.bat_speed_fitted, Some(0));
    match &located.swings[0].bat_speed_fit {
        Some(BatSpeedFit::NotSeparable { reason }) => assert!(reason.contains("σ(bat speed)"), "{reason}"),
        other => panic!("expected not separable, got {other:?}"),
    }
}

/// A lab sheet imported through a column map: per row pitch speed and exit speed (mph), launch angle (°)
/// and spin (rpm), NaN for a blank cell; the batter's assumed swing, no pitch angle or spin (assumed 0).
fn import_sheet(dir: &Path, name: &str, rows: &[[f64; 4]]) -> std::path::PathBuf {
    let csv = dir.join(format!("{name}.csv"));
    let cell = |x: f64| if x.is_nan() { String::new() } else { format!("{x}") };
    let mut text = "P,E,LA,S\n".to_string();
    for r in rows {
        text += &format!("{},{},{},{}\n", cell(r[0]), cell(r[1]), cell(r[2]), cell(r[3]));
    }
    std::fs::write(&csv, text).unwrap();
    let columns = [("pitch_speed", "P"), ("exit_speed", "E"), ("launch_angle", "LA"), ("spin", "S")]
        .into_iter()
        .map(|(q, c)| (q.to_string(), c.to_string()))
        .collect();
    let map = ColumnMap { name: "sheet".into(), columns, units: Default::default() };
    let bag = dir.join(name);
    import_files(&[csv], &bag, &ImportOptions { map: Some(map), ..options() }).unwrap();
    bag
}

/// The swing a sheet row becomes, at impact point `z` and undercut `d`: the node's engine gives its answer.
fn sheet_swing(pitch_mph: f64, z: f64, d: f64) -> SwingInput {
    let prediction = options().batter.predict(&options().bat.mass_properties()).unwrap();
    SwingInput {
        impact: Impact {
            ball_speed: mph(pitch_mph),
            bat_cm_speed: prediction.bat_cm_speed,
            bat_angular_speed: prediction.bat_angular_speed,
            impact_z: z,
        },
        undercut: d,
        attack_angle: 0.0,
        pitch_angle: 0.0,
        pitch_spin: 0.0,
        measured_launch_angle: f64::NAN,
        measured_spin: f64::NAN,
        ..level()
    }
}

/// With spin measured, least squares always finds a closest (z, D): a ball it misses by far more than the
/// trackers' accuracy is not located. A 140-mph ball off a 40-mph pitch is too fast with its spin as without
/// it (the same excess); a ball launched at 89.9° with 2,500 rpm is not reproducible, and the node's own
/// engine at the closest fit misses it by χ² > 9 too.
#[test]
fn a_ball_no_impact_point_reproduces_within_tracker_accuracy_is_not_located() {
    let tmp = tempfile::tempdir().unwrap();
    let nan = f64::NAN;
    let rows = [[40.0, 140.0, 20.0, 2500.0], [40.0, 140.0, 20.0, nan], [85.0, 95.0, 89.9, 2500.0]];
    let bag = import_sheet(tmp.path(), "impossible", &rows);
    let report = locate_bag(&bag, &LocateOptions::default()).unwrap();
    assert_eq!((report.located, report.too_fast, report.not_reproducible), (0, 2, 1), "{:#?}", report.swings);
    assert!(report.squared_up_share.is_nan(), "none located, none squared up");
    let max = |o: &Outcome| match o {
        Outcome::TooFast { max_exit_speed, .. } => *max_exit_speed,
        other => panic!("{other:?}"),
    };
    assert_eq!(max(&report.swings[0].outcome), max(&report.swings[1].outcome));
    let Outcome::NotReproducible { reason, solutions } = &report.swings[2].outcome else {
        panic!("{:?}", report.swings[2].outcome)
    };
    assert!(reason.contains("χ² =") && reason.contains("launch angle"), "{reason}");
    let sigma = LocateOptions::default();
    let measured = [mph(95.0), deg(89.9), rpm(2500.0)];
    let sigmas = [sigma.exit_speed_sigma, sigma.launch_angle_sigma, sigma.spin_sigma];
    for s in solutions {
        let engine = simulate(sheet_swing(85.0, s.impact_z, s.undercut));
        let chi2: f64 = (0..3).map(|k| ((engine[k] - measured[k]) / sigmas[k]).powi(2)).sum();
        assert!(chi2 > MAX_CHI2_PER_DOF, "the engine at z = {}, D = {}: χ² {chi2}", s.impact_z, s.undercut);
        assert!((chi2 - s.chi2).abs() < 0.01 * chi2, "the engine's χ² {chi2} against the reported {}", s.chi2);
    }
}

/// With only the exit speed measured by a coarse tracker (σ_v = 5 m/s, 11 mph), a ball within a millimetre per
/// second of the sweet spot's best has two roots a fraction of a millimetre either side of it whose
/// σ_z = σ_v/|dv/dz| (the slope from the node's engine) is more than half the barrel: not placed on the bat.
/// A metre per second slower, 2–3 cm from the sweet spot, it is located.
#[test]
fn a_ball_whose_impact_point_is_uncertain_beyond_half_the_barrel_is_not_located() {
    let tmp = tempfile::tempdir().unwrap();
    let nan = f64::NAN;
    let coarse = LocateOptions { exit_speed_sigma: 5.0, ..LocateOptions::default() };
    let fast = import_sheet(tmp.path(), "fast", &[[85.0, 150.0, nan, nan]]);
    let best = match locate_bag(&fast, &coarse).unwrap().swings[0].outcome {
        Outcome::TooFast { max_exit_speed, .. } => max_exit_speed,
        ref other => panic!("{other:?}"),
    };
    let rows = [[85.0, (best - 1e-3) / MPH, nan, nan], [85.0, (best - 1.0) / MPH, nan, nan]];
    let bag = import_sheet(tmp.path(), "flat", &rows);
    let report = locate_bag(&bag, &coarse).unwrap();
    assert_eq!((report.located, report.not_reproducible), (1, 1), "{:#?}", report.swings);
    let Outcome::NotReproducible { reason, solutions } = &report.swings[0].outcome else {
        panic!("{:?}", report.swings[0].outcome)
    };
    assert!(reason.contains("uncertain by σ") && reason.contains("half the barrel"), "{reason}");
    let length = options().bat.length();
    let bound = MAX_Z_SIGMA_SHARE * (length / 2.0 - 0.005);
    let sigma_v = coarse.exit_speed_sigma;
    for s in solutions {
        let h = 2e-5;
        let slope = (simulate(sheet_swing(85.0, s.impact_z + h, 0.0))[0]
            - simulate(sheet_swing(85.0, s.impact_z - h, 0.0))[0])
            / (2.0 * h);
        assert!(sigma_v / slope.abs() > bound, "z = {}: the engine's slope {slope} m/s per m", s.impact_z);
        assert!(s.impact_z_sigma > bound, "{s:?}");
    }
    let (located, _) = solutions_of(&report.swings[1].outcome);
    assert!(located.iter().all(|s| s.impact_z_sigma <= bound), "{located:?}");
}
