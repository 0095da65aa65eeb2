//! The game ball fitted to real games (issue 32 §2): e0(v) fitted to the q envelope of the odd `game_pk` half of
//! the 2024 season (validation/statcast_q.csv), checked on the even half, and the `mlb2024` preset is that
//! fit. A change of the physics, of the table or of the preset that moves the fit fails here.

use sweetspot::calibrate::statcast::{fit_game_ball, statcast_q_max, QTarget};
use sweetspot::calibrate::FitOptions;
use sweetspot::physics::{Ball, Bat, CollisionOptions, ModeSet};
use sweetspot::validate::statcast::{parse_q, QBin};

use sweetspot::physics::units::MPH;
/// Bins fitted and checked: those the swing's own bat-speed error does not sort (docs/statcast.md), with
/// enough balls in a half for a stable 99th percentile.
const SORTS: &[&str] = &["batter_median_bat", "plate_pitch"];
const MIN_BALLS: usize = 500;

fn bins(half: &str) -> Vec<QBin> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("validation/statcast_q.csv");
    let text = std::fs::read_to_string(&path).expect("validation/statcast_q.csv");
    parse_q(&text)
        .expect("parses")
        .into_iter()
        .filter(|b| b.half == half && SORTS.contains(&b.by.as_str()) && b.count >= MIN_BALLS)
        .collect()
}

fn targets(bins: &[QBin]) -> Vec<QTarget> {
    bins.iter()
        .map(|b| QTarget {
            label: format!("{} {}-{}", b.by, b.low, b.high),
            bat_speed: b.median_bat_mph * MPH,
            pitch_speed: b.median_plate_pitch_mph * MPH,
            q: b.q_p99,
        })
        .collect()
}

#[test]
fn the_game_ball_is_the_fit_to_one_half_of_the_season_and_holds_on_the_other() {
    let options = CollisionOptions::default();
    let modes = ModeSet::compute(&Bat::preset("r161").unwrap(), options.modes).unwrap();
    let odd = bins("odd");
    assert!(odd.len() >= 8, "{} bins", odd.len());
    let fit = fit_game_ball(&modes, Ball::mlb(), &targets(&odd), &options, &FitOptions::default()).unwrap();
    let (cor, p) = (&fit.parameters[0], &fit.parameters[1]);
    let (e58, e58_sigma) = fit.cor_at(sweetspot::physics::ball::MLB_COR_SPEED);
    let (e70, e70_sigma) = fit.cor_at(70.0);
    eprintln!(
        "fit on {} odd-half bins: cor(25.9 m/s) = {:.4} ± {:.4}, p = {:.4} ± {:.4} (correlation {:.3}); \
         e0(70 m/s) = {e70:.4} ± {e70_sigma:.4}; RMS q residual {:.4} → {:.4}; {} iterations, converged {}",
        odd.len(),
        cor.value,
        cor.std_error,
        p.value,
        p.std_error,
        fit.correlation,
        fit.rms_before,
        fit.rms,
        fit.iterations,
        fit.converged
    );
    assert!(fit.converged);
    assert!((e58 - cor.value).abs() < 1e-12 && e58_sigma > 0.0);
    // The preset is this fit (to well inside its uncertainty).
    let preset = Ball::preset("mlb2024").unwrap();
    assert!((preset.cor - cor.value).abs() < 0.1 * cor.std_error, "preset cor {} vs fit {}", preset.cor, cor.value);
    assert!(
        (preset.cor_speed_exponent - p.value).abs() < 0.1 * p.std_error,
        "preset exponent {} vs fit {}",
        preset.cor_speed_exponent,
        p.value
    );
    // Held out: on the even half, the fitted ball's largest q lies inside every bin's [97th, 99.8th] band.
    let even = bins("even");
    let mut outside = Vec::new();
    for b in &even {
        let (q, _) =
            statcast_q_max(&modes, &fit.ball, b.median_bat_mph * MPH, b.median_plate_pitch_mph * MPH, &options)
                .unwrap();
        eprintln!(
            "even {} {}-{}: model {q:.4}, band {:.4}–{:.4} (99th {:.4})",
            b.by, b.low, b.high, b.q_p97, b.q_p99_8, b.q_p99
        );
        if !(b.q_p97 <= q && q <= b.q_p99_8) {
            outside.push(format!("{} {}-{}: {q:.4} outside {:.4}–{:.4}", b.by, b.low, b.high, b.q_p97, b.q_p99_8));
        }
    }
    assert!(outside.is_empty(), "held-out bins outside their band: {outside:?}");
}
