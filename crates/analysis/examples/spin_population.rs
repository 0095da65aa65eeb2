//! The `radar-spin/…` rows' question asked of the measured swing population: each MLB ball at 80–88 mph
//! (Statcast bat tracking, `batted_balls_attack_angle.csv`) is struck by its own measured swing — bat speed
//! 6 in from the head, attack angle, swing-path tilt — and (impact_z, undercut) are solved so the model's
//! ball leaves at the measured exit speed and launch angle; the model's total spin of each located ball is
//! then binned as the radar rows bin it.
//!
//! `cargo run --offline -p sweetspot-analysis --example spin_population -- CSV [centre|spray|row] [MAX_PER_BIN]`
//! (from the repository's root: it reads `validation/`). CSV: `batted_balls_attack_angle.csv` of the shared
//! Statcast reference (columns launch_angle, launch_speed, bat_speed, attack_angle, swing_path_tilt,
//! is_stand_left).
//!
//! `centre`: every swing toward centre field. `spray`: ball k of a bin takes the bin's (k mod 19)-th radar
//! spray percentile (mirrored for a left-handed batter), through the swing direction the row's median-swing
//! scan needs for that spray. `row`: the rows' own median swing located the same way, a check that the
//! solver finds the rows' impact point. The pitch is the rows' (the TrackMan medians), the ball the suite's
//! game ball, the contact law the default.

use std::path::Path;

use rayon::prelude::*;
use sweetspot_analysis::validate::{self, cases::Lab, radar::RadarBin, trackman};
use sweetspot_physics::batter::Batter;
use sweetspot_physics::oblique::{rpm_to_rad_per_s, ObliqueImpact, TangentialContact};
use sweetspot_physics::oblique3d::{collide_spatial, SpatialImpact};
use sweetspot_physics::{Ball, Bat, CollisionOptions, Impact, ModeSet};

use sweetspot_analysis::validate::cases::SIX_INCHES;
use sweetspot_physics::units::{INCH, MPH};

/// The model's ball: exit speed (mph), launch angle (deg), total spin and backspin (rpm).
type Outcome = (f64, f64, f64, f64);

struct Swing {
    launch: f64,
    exit: f64,
    bat_speed: f64,
    attack: f64,
    tilt: f64,
    left: bool,
}

struct Setup {
    bat: Bat,
    modes: ModeSet,
    ball: Ball,
    contact: TangentialContact,
    options: CollisionOptions,
    pitch: trackman::PitchMedians,
    /// The typical swing's impact (speeds at scale 1) and its speed 6 in from the head.
    typical: Impact,
    typical_six: f64,
}

#[derive(Clone, Copy)]
struct Hit {
    spin: f64,
    backspin: f64,
    z_from_end: f64,
    sweet_from_end: f64,
    undercut: f64,
}

impl Setup {
    fn collide(&self, s: &Swing, direction: f64, z: f64, d: f64) -> Option<Outcome> {
        let scale = s.bat_speed * MPH / self.typical_six;
        let impact = Impact {
            impact_z: z,
            bat_cm_speed: scale * self.typical.bat_cm_speed,
            bat_angular_speed: scale * self.typical.bat_angular_speed,
            ..self.typical
        };
        let barrel = self.bat.radii_at(z).0;
        let oblique = ObliqueImpact {
            undercut: d,
            attack_angle: s.attack.to_radians(),
            pitch_angle: (-self.pitch.vert_appr_angle_deg).to_radians(),
            pitch_spin: rpm_to_rad_per_s(self.pitch.spin_rpm),
            ..ObliqueImpact::head_on(impact, barrel)
        };
        let spatial = SpatialImpact {
            bat_tilt: s.tilt.to_radians(),
            swing_direction: direction.to_radians(),
            ..SpatialImpact::planar(oblique)
        };
        let r = collide_spatial(&self.modes, &self.ball, &spatial, &self.contact, &self.options).ok()?;
        Some((
            r.exit_speed / MPH,
            r.launch_angle.to_degrees(),
            r.total_spin * 60.0 / std::f64::consts::TAU,
            r.backspin * 60.0 / std::f64::consts::TAU,
        ))
    }

    /// The undercut at `z` launching at `s.launch` (first crossing from below), and the result there.
    fn at_launch(&self, s: &Swing, direction: f64, z: f64) -> Option<(f64, Outcome)> {
        let reach = self.ball.radius + self.bat.radii_at(z).0;
        let grid: Vec<f64> = (0..=24).map(|i| -0.4 * reach + 1.35 * reach * i as f64 / 24.0).collect();
        let mut prev: Option<(f64, f64)> = None;
        for &d in &grid {
            let Some(r) = self.collide(s, direction, z, d) else { continue };
            let f = r.1 - s.launch;
            if let Some((d0, f0)) = prev {
                if f0 <= 0.0 && f >= 0.0 {
                    let (mut a, mut b, mut fa, mut fb) = (d0, d, f0, f);
                    let mut best = (d, r);
                    for _ in 0..30 {
                        let m = a - fa * (b - a) / (fb - fa);
                        let m = if m <= a || m >= b { 0.5 * (a + b) } else { m };
                        let rm = self.collide(s, direction, z, m)?;
                        let fm = rm.1 - s.launch;
                        best = (m, rm);
                        if fm.abs() < 1e-3 {
                            break;
                        }
                        if fm < 0.0 {
                            (a, fa) = (m, fm);
                            fb *= 0.5;
                        } else {
                            (b, fb) = (m, fm);
                            fa *= 0.5;
                        }
                    }
                    return Some(best);
                }
            }
            prev = Some((d, f));
        }
        None
    }

    /// Every (z, D) along the barrel that reproduces the ball's exit speed and launch: (handle side, end side).
    fn locate(&self, s: &Swing, direction: f64) -> (Option<Hit>, Option<Hit>, bool) {
        let length = self.bat.length();
        let (lo, hi) = (0.5 * length, length - 0.005);
        let zs: Vec<f64> = (0..=16).map(|i| lo + (hi - lo) * i as f64 / 16.0).collect();
        let vals: Vec<Option<(f64, Outcome)>> = zs.iter().map(|&z| self.at_launch(s, direction, z)).collect();
        let speed = |i: usize| vals[i].map_or(f64::NAN, |v| v.1 .0);
        let Some(peak) = (0..zs.len()).filter(|&i| speed(i).is_finite()).max_by(|&a, &b| speed(a).total_cmp(&speed(b)))
        else {
            return (None, None, false);
        };
        let too_fast = speed(peak) < s.exit;
        let sweet = zs[peak];
        let refine = |i0: usize, i1: usize| -> Option<Hit> {
            let (mut a, mut b) = (zs[i0], zs[i1]);
            let (mut fa, mut fb) = (speed(i0) - s.exit, speed(i1) - s.exit);
            if !(fa.is_finite() && fb.is_finite()) || fa * fb > 0.0 {
                return None;
            }
            let mut best = None;
            for _ in 0..30 {
                let m = a - fa * (b - a) / (fb - fa);
                let m = if m <= a.min(b) || m >= a.max(b) { 0.5 * (a + b) } else { m };
                let (d, r) = self.at_launch(s, direction, m)?;
                let fm = r.0 - s.exit;
                best = Some(Hit {
                    spin: r.2,
                    backspin: r.3,
                    z_from_end: length - m,
                    sweet_from_end: length - sweet,
                    undercut: d,
                });
                if fm.abs() < 0.02 {
                    break;
                }
                if fm * fa < 0.0 {
                    (b, fb) = (m, fm);
                    fa *= 0.5;
                } else {
                    (a, fa) = (m, fm);
                    fb *= 0.5;
                }
            }
            best
        };
        let handle = (0..peak).rev().find(|&i| speed(i) <= s.exit).and_then(|i| refine(i, i + 1));
        let end = (peak + 1..zs.len()).find(|&i| speed(i) <= s.exit).and_then(|i| refine(i - 1, i));
        (handle, end, too_fast)
    }
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

impl Setup {
    /// The suite's R161 and game ball, the rows' pitch (the TrackMan medians) and the typical batter's swing.
    fn new(inputs: &validate::Inputs) -> anyhow::Result<Setup> {
        let pitch = trackman::pitch_medians(&inputs.trackman).ok_or_else(|| anyhow::anyhow!("no pitch"))?;
        let options = CollisionOptions::default();
        let bat = Bat::preset("r161")?;
        let modes = ModeSet::compute(&bat, options.modes.max(2))?;
        let ball = Ball::preset(&inputs.measurements.game_ball)?;
        let swing = Batter::typical(modes.mass_properties())?.predict(&modes.mass_properties())?;
        let typical = swing.impact(pitch.zone_speed_mph * MPH);
        let six = modes.length() - SIX_INCHES;
        let typical_six =
            typical.bat_cm_speed + typical.bat_angular_speed * (six - modes.mass_properties().center_of_mass);
        Ok(Setup { bat, modes, ball, contact: TangentialContact::default(), options, pitch, typical, typical_six })
    }

    /// The suite's scan of the bin's median swing over the swing direction, as the radar rows make it.
    fn median_swing_scan(
        &self,
        inputs: &validate::Inputs,
        b: &RadarBin,
    ) -> anyhow::Result<Option<Vec<validate::cases::SpatialGamePoint>>> {
        Ok(Lab::new(self.options, &inputs.measurements.game_ball).spatial_spray_scan(
            &self.pitch,
            b.attack_median_deg,
            b.tilt_median_deg,
            b.launch_deg,
            b.exit_median_mph,
        )?)
    }
}

/// The swings of the bat-tracking CSV whose ball left at 80–88 mph (the radar rows' range).
fn read_swings(csv_path: &str) -> anyhow::Result<Vec<Swing>> {
    let mut reader = csv::Reader::from_path(csv_path)?;
    let headers = reader.headers()?.clone();
    let col = |name: &str| headers.iter().position(|h| h == name).ok_or_else(|| anyhow::anyhow!("no column {name}"));
    let (cl, cs, cb, ca, ct, cleft) = (
        col("launch_angle")?,
        col("launch_speed")?,
        col("bat_speed")?,
        col("attack_angle")?,
        col("swing_path_tilt")?,
        col("is_stand_left")?,
    );
    let mut swings = Vec::new();
    for rec in reader.records() {
        let rec = rec?;
        let num = |i: usize| rec.get(i).and_then(|v| v.trim().parse::<f64>().ok());
        if let (Some(launch), Some(exit), Some(bat_speed), Some(attack), Some(tilt)) =
            (num(cl), num(cs), num(cb), num(ca), num(ct))
        {
            if (80.0..88.0).contains(&exit) {
                swings.push(Swing { launch, exit, bat_speed, attack, tilt, left: num(cleft) == Some(1.0) });
            }
        }
    }
    Ok(swings)
}

/// `row` mode: each row's own median swing located as the population's are, beside the row's centre point.
fn locate_row_swings(setup: &Setup, inputs: &validate::Inputs) -> anyhow::Result<()> {
    for b in inputs.radar.iter().filter(|b| (10.0..=40.0).contains(&b.launch_deg)) {
        let Some(scan) = setup.median_swing_scan(inputs, b)? else { continue };
        let centre = validate::cases::SpatialGamePoint::at_spray(&scan, 0.0);
        let s = Swing {
            launch: b.launch_deg,
            exit: b.exit_median_mph,
            bat_speed: scan[0].scale * setup.typical_six / MPH,
            attack: b.attack_median_deg,
            tilt: b.tilt_median_deg,
            left: false,
        };
        let (h, e, _) = setup.locate(&s, 0.0);
        println!(
            "{}°: row swing {:.1} mph; row centre point {:?}; located handle {:?} end {:?} (z from end, in: {:?} {:?}; typical {:.2})",
            b.launch_deg,
            s.bat_speed,
            centre.map(|c| (c.total_spin_rpm.round(), c.direction_deg, c.spray_deg)),
            h.map(|x| x.spin.round()),
            e.map(|x| x.spin.round()),
            h.map(|x| x.z_from_end / INCH),
            e.map(|x| x.z_from_end / INCH),
            (setup.bat.length() - setup.typical.impact_z) / INCH
        );
    }
    Ok(())
}

/// `spray` mode: the swing direction of each of a bin's balls, the k-th taking the bin's (k mod 19)-th radar
/// spray percentile (mirrored for a left-handed batter).
fn spray_directions(
    setup: &Setup,
    inputs: &validate::Inputs,
    b: &RadarBin,
    mine: &[&Swing],
) -> anyhow::Result<Vec<f64>> {
    let scan = setup.median_swing_scan(inputs, b)?.ok_or_else(|| anyhow::anyhow!("no scan at {}", b.launch_deg))?;
    Ok(mine
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let p = b.spray_percentiles_deg[k % b.spray_percentiles_deg.len()];
            let at = if s.left { -p } else { p };
            validate::cases::SpatialGamePoint::at_spray(&scan, at).map_or(0.0, |q| q.direction_deg)
        })
        .collect())
}

/// A bin's row of the table (to stdout) and its undercut and distance from the sweet spot (to stderr).
fn print_bin(b: &RadarBin, mine: &[&Swing], results: &[(Option<Hit>, Option<Hit>, bool)]) {
    let mut handle: Vec<f64> = results.iter().filter_map(|r| r.0.map(|h| h.spin)).collect();
    let mut end: Vec<f64> = results.iter().filter_map(|r| r.1.map(|h| h.spin)).collect();
    let mut both: Vec<f64> = handle.iter().chain(end.iter()).copied().collect();
    let hits = || results.iter().flat_map(|r| [r.0, r.1]).flatten();
    let mut back: Vec<f64> = hits().map(|h| h.backspin).collect();
    let mut undercut: Vec<f64> = hits().map(|h| h.undercut * 1000.0).collect();
    let mut off: Vec<f64> = hits().map(|h| (h.z_from_end - h.sweet_from_end).abs() / INCH).collect();
    let too_fast = results.iter().filter(|r| r.2).count();
    let mut bat: Vec<f64> = mine.iter().map(|s| s.bat_speed).collect();
    let mut attack: Vec<f64> = mine.iter().map(|s| s.attack).collect();
    let low = b.spin_q1_rpm.max(0.88 * b.spin_median_rpm);
    let high = b.spin_q3_rpm.min(1.12 * b.spin_median_rpm);
    let (nh, ne) = (handle.len(), end.len());
    println!(
        "| {}° | {} | {}/{} | {} | {:.1} | {:.1} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} ({:.0}–{:.0}) | {:.0}–{:.0} |",
        b.launch_deg,
        mine.len(),
        nh,
        ne,
        too_fast,
        median(&mut bat),
        median(&mut attack),
        median(&mut handle),
        median(&mut end),
        median(&mut both),
        median(&mut back),
        b.spin_median_rpm,
        b.spin_q1_rpm,
        b.spin_q3_rpm,
        low,
        high
    );
    eprintln!(
        "  {}°: undercut median {:.1} mm, impact |off the sweet spot| median {:.2} in",
        b.launch_deg,
        median(&mut undercut),
        median(&mut off)
    );
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let csv_path =
        args.get(1).ok_or_else(|| anyhow::anyhow!("usage: spin_population CSV [centre|spray|row] [MAX_PER_BIN]"))?;
    let spray_mode = args.get(2).map(String::as_str) == Some("spray");
    let max_per_bin: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(usize::MAX);
    let inputs = validate::read_inputs(Path::new("validation"))?;
    let setup = Setup::new(&inputs)?;
    eprintln!(
        "pitch {:.1} mph descending {:.1}° {:.0} rpm; typical swing {:.1} mph 6 in from the head; ball {}",
        setup.pitch.zone_speed_mph,
        -setup.pitch.vert_appr_angle_deg,
        setup.pitch.spin_rpm,
        setup.typical_six / MPH,
        inputs.measurements.game_ball
    );
    let swings = read_swings(csv_path)?;
    if args.get(2).map(String::as_str) == Some("row") {
        return locate_row_swings(&setup, &inputs);
    }
    let bins: Vec<&RadarBin> = inputs.radar.iter().filter(|b| (10.0..=40.0).contains(&b.launch_deg)).collect();
    println!(
        "| launch | balls | located (handle/end) | too fast | bat mph med | attack med | model spin: handle | end | both | backspin both | radar median (IQR) | row band |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for b in bins {
        let mine: Vec<&Swing> = swings
            .iter()
            .filter(|s| s.launch >= b.launch_deg - 2.5 && s.launch < b.launch_deg + 2.5)
            .take(max_per_bin)
            .collect();
        let directions = if spray_mode { spray_directions(&setup, &inputs, b, &mine)? } else { vec![0.0; mine.len()] };
        let results: Vec<(Option<Hit>, Option<Hit>, bool)> =
            mine.par_iter().zip(directions.par_iter()).map(|(s, &dir)| setup.locate(s, dir)).collect();
        print_bin(b, &mine, &results);
    }
    Ok(())
}
