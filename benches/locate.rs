//! Criterion bench of `sweetspot locate`: a TrackMan export of swings simulated at random impact points and
//! undercuts with tracker-sized noise (exit speed, launch angle and spin measured: the costliest case),
//! imported into a bag, located. Run: `cargo bench --bench locate -- --warm-up-time 1 --measurement-time 20`.
//!
//! `SWEETSPOT_LOCATE_SWINGS=N` sets the swings per bag (default 1,000); `SWEETSPOT_LOCATE_BAG=DIR` writes the
//! bag to DIR and keeps it (for timing `sweetspot locate DIR` as a whole process).
//!
//! **A season.** `SWEETSPOT_LOCATE_SEASON=FILE.csv` instead imports a Statcast season (the shared 2024 file,
//! decompressed; 112,730 swings with bat speed, exit speed and launch angle measured) and times `locate_bag`
//! on it once per pass, `SWEETSPOT_LOCATE_PASSES` passes (default 3), printing each pass and the located
//! counts: a minute-long run is not criterion's kind of sample. See docs/locate-season.md.
//! `SWEETSPOT_LOCATE_SEASON=/tmp/season2024.csv cargo bench --bench locate`
use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, Criterion};
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, Normal};
use sweetspot::import::{backspin, deg, import_files, mph, rpm, ImportOptions, MPH};
use sweetspot::locate::{locate_bag, LocateOptions};
use sweetspot::model::convert::{params_from_ball, params_of_preset};
use sweetspot::model::engine::{compute, plan_swing, Registry, SwingInput};
use sweetspot::model::settings::ModelSettings;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::physics::batter::Batter;
use sweetspot::physics::{Ball, Bat, Impact};

fn options() -> ImportOptions {
    let bat = Bat::preset("r161").expect("r161 preset");
    let batter = Batter::typical(bat.mass_properties()).expect("typical batter");
    ImportOptions {
        format: None,
        bat,
        bat_params: params_of_preset("r161", "r161", Header::default()),
        ball_params: params_from_ball("baseball", &Ball::default(), None, Header::default()),
        batter,
        undercut: 0.0,
        map: None,
        tee: false,
    }
}

/// Writes a TrackMan CSV of `count` swings (the header and a row of tests/data/trackman_game.csv as template).
fn write_export(path: &Path, count: usize) {
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/trackman_game.csv");
    let mut reader = csv::Reader::from_path(fixture).expect("fixture");
    let header: Vec<String> =
        reader.headers().expect("header").iter().map(|h| h.trim_start_matches('\u{feff}').to_string()).collect();
    let template: Vec<String> = reader.records().nth(3).expect("row").expect("row").iter().map(String::from).collect();
    let column = |name: &str| header.iter().position(|h| h == name).expect("column");
    let settings = ModelSettings::default();
    let mut registry = Registry::with_limits(settings.max_bats, settings.max_balls);
    let o = options();
    let prediction = o.batter.predict(&o.bat.mass_properties()).expect("batter swing");
    let sigma = LocateOptions::default();
    let unit = Normal::new(0.0, 1.0).expect("normal");
    let mut rng = rand::rngs::StdRng::seed_from_u64(11);
    let mut writer = csv::Writer::from_path(path).expect("csv");
    writer.write_record(&header).expect("write");
    for _ in 0..count {
        let (z, d, zone) = (rng.gen_range(0.60..0.80), rng.gen_range(-0.005..0.02), rng.gen_range(80.0..95.0));
        let impact = Impact {
            ball_speed: mph(zone),
            bat_cm_speed: prediction.bat_cm_speed,
            bat_angular_speed: prediction.bat_angular_speed,
            impact_z: z,
        };
        let input = SwingInput {
            undercut: d,
            attack_angle: 0.0,
            pitch_angle: deg(6.0),
            pitch_spin: backspin(rpm(2300.0), 180.0),
            ..SwingInput::from(impact)
        };
        let (plan, _) = plan_swing(&mut registry, &settings, "r161", "", input);
        let c = compute(&plan, &()).expect("the swing computes");
        let v = c.launch.exit_speed + sigma.exit_speed_sigma * unit.sample(&mut rng);
        let theta = c.launch.launch_angle + sigma.launch_angle_sigma * unit.sample(&mut rng);
        let omega = c.launch.spin + sigma.spin_sigma * unit.sample(&mut rng);
        let mut row = template.clone();
        for (name, value) in [
            ("PitchCall", "InPlay".to_string()),
            ("ZoneSpeed", format!("{zone}")),
            ("VertApprAngle", "-6".into()),
            ("SpinRate", "2300".into()),
            ("SpinAxis", "180".into()),
            ("ExitSpeed", format!("{}", v / MPH)),
            ("Angle", format!("{}", theta.to_degrees())),
            ("HitSpinRate", format!("{}", omega.abs() * 60.0 / (2.0 * std::f64::consts::PI))),
            ("HitSpinAxis", if omega >= 0.0 { "180" } else { "0" }.into()),
        ] {
            row[column(name)] = value;
        }
        writer.write_record(&row).expect("write");
    }
    writer.flush().expect("flush");
}

/// Times `locate_bag` on a Statcast season (see the module docs).
fn season(csv: &Path) {
    let passes: usize = std::env::var("SWEETSPOT_LOCATE_PASSES").ok().and_then(|s| s.parse().ok()).unwrap_or(3);
    let tmp = tempfile::tempdir().expect("tempdir");
    let bag = tmp.path().join("season");
    let started = std::time::Instant::now();
    // As `sweetspot import statcast` does: the game ball.
    let game =
        ImportOptions { ball_params: params_from_ball("mlb2024", &Ball::game(), None, Header::default()), ..options() };
    let import = import_files(&[csv.to_path_buf()], &bag, &game).expect("import");
    eprintln!("import: {} swings in {:.1} s", import.swings, started.elapsed().as_secs_f64());
    let threads = rayon::current_num_threads();
    for pass in 1..=passes {
        let started = std::time::Instant::now();
        let report = locate_bag(&bag, &LocateOptions::default()).expect("locate");
        let seconds = started.elapsed().as_secs_f64();
        println!(
            "locate_season pass {pass}: {} swings in {seconds:.1} s on {threads} threads ({:.0} µs per swing): \
             {} located, {} too fast; collisions per swing: {:.1} searching, {:.1} with the node's time step",
            report.swings.len(),
            seconds * 1e6 / report.swings.len() as f64,
            report.located,
            report.too_fast,
            report.collisions.0 as f64 / report.swings.len() as f64,
            report.collisions.1 as f64 / report.swings.len() as f64,
        );
    }
}

fn benches(c: &mut Criterion) {
    if let Some(csv) = std::env::var_os("SWEETSPOT_LOCATE_SEASON") {
        season(Path::new(&csv));
        return;
    }
    let count: usize = std::env::var("SWEETSPOT_LOCATE_SWINGS").ok().and_then(|s| s.parse().ok()).unwrap_or(1000);
    let tmp = tempfile::tempdir().expect("tempdir");
    let csv = tmp.path().join("export.csv");
    write_export(&csv, count);
    let bag: PathBuf = std::env::var_os("SWEETSPOT_LOCATE_BAG").map_or_else(|| tmp.path().join("bag"), PathBuf::from);
    import_files(&[csv], &bag, &options()).expect("import");
    let mut group = c.benchmark_group("locate");
    group.sample_size(10);
    group.bench_function(format!("locate_trackman_{count}_swings"), |b| {
        b.iter(|| locate_bag(&bag, &LocateOptions::default()).expect("locate"))
    });
    group.finish();
}

criterion_group!(locate, benches);
criterion_main!(locate);
