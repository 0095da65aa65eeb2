//! Measured batted-ball spin by launch angle from real TrackMan game rows (`validation/trackman_spin.csv`).
//!
//! The file holds the columns the suite needs, copied unchanged from two TrackMan V3 game exports (see
//! `validation/README.md`): `Game`, `PitchNo`, `PitchCall`, `ZoneSpeed` (mph), `VertApprAngle` (deg, negative
//! descending), `SpinRate` (pitch, rpm), `ExitSpeed` (mph), `Angle` (launch, deg), `HitSpinRate` (rpm),
//! `HitSpinAxis` (deg), `HitLaunchConfidence`. Empty cells are missing values.
//!
//! Selection: balls in play (`PitchCall` = `InPlay`) whose launch was tracked with `High` or `Medium`
//! confidence and that carry both `Angle` and `HitSpinRate`; a bin holds those launched within a half-width
//! of its centre. Quantiles interpolate linearly between order statistics (position p·(n − 1), the
//! "type 7" rule).

use std::path::Path;

use serde::Serialize;

use super::ValidateError;

/// One row of the spin file (missing cells are `None`).
#[derive(Debug, Clone, PartialEq)]
pub struct SpinRow {
    /// The game (export file) the row comes from.
    pub game: String,
    /// What happened to the pitch (`InPlay`, `FoulBallNotFieldable`, …).
    pub pitch_call: String,
    /// Pitch speed at the plate, mph.
    pub zone_speed_mph: Option<f64>,
    /// Pitch's vertical approach angle, deg (negative: descending).
    pub vert_appr_angle_deg: Option<f64>,
    /// Pitch spin, rpm.
    pub pitch_spin_rpm: Option<f64>,
    /// Exit speed, mph.
    pub exit_speed_mph: Option<f64>,
    /// Launch angle, deg.
    pub launch_deg: Option<f64>,
    /// Batted-ball spin (total), rpm.
    pub hit_spin_rpm: Option<f64>,
    /// Batted-ball spin axis, deg (convention not documented here; kept for the record).
    pub hit_spin_axis_deg: Option<f64>,
    /// `High`, `Medium`, `Low`, `Estimated` or empty.
    pub launch_confidence: String,
}

/// Spin statistics of one launch-angle bin.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpinBin {
    /// Bin centre, deg.
    pub launch_deg: f64,
    /// Bin half-width, deg.
    pub half_width_deg: f64,
    /// Balls in the bin.
    pub count: usize,
    /// Median spin, rpm (`None` for an empty bin).
    pub median_rpm: Option<f64>,
    /// First quartile, rpm.
    pub q1_rpm: Option<f64>,
    /// Third quartile, rpm.
    pub q3_rpm: Option<f64>,
    /// The spins in the bin, sorted, rpm.
    pub spins_rpm: Vec<f64>,
    /// Median exit speed of the bin's balls that carry one, mph (`None` if none does): the game swing's
    /// exit speed is matched to it.
    pub median_exit_speed_mph: Option<f64>,
}

/// The pitch the model swings at: medians over balls in play.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PitchMedians {
    /// Median pitch speed at the plate, mph.
    pub zone_speed_mph: f64,
    /// Median vertical approach angle, deg (negative: descending).
    pub vert_appr_angle_deg: f64,
    /// Median pitch spin, rpm.
    pub spin_rpm: f64,
    /// Balls in play the medians were taken over.
    pub count: usize,
}

fn cell(value: &str) -> Result<Option<f64>, String> {
    let t = value.trim();
    if t.is_empty() {
        return Ok(None);
    }
    t.parse::<f64>().map(Some).map_err(|_| format!("'{t}' is not a number"))
}

/// Reads the spin file.
pub fn read(path: &Path) -> Result<Vec<SpinRow>, ValidateError> {
    let text = sweetspot_model::files::read_text(path, "validation data file")?;
    parse(&text).map_err(|message| ValidateError::Parse { path: path.into(), message })
}

/// Parses the spin file's text (header row first; columns found by name).
pub fn parse(text: &str) -> Result<Vec<SpinRow>, String> {
    let mut reader = csv::ReaderBuilder::new().from_reader(text.as_bytes());
    let headers = reader.headers().map_err(|e| format!("header: {e}"))?.clone();
    let col = |name: &str| headers.iter().position(|h| h == name).ok_or_else(|| format!("no column '{name}'"));
    let idx = [
        col("Game")?,
        col("PitchCall")?,
        col("ZoneSpeed")?,
        col("VertApprAngle")?,
        col("SpinRate")?,
        col("ExitSpeed")?,
        col("Angle")?,
        col("HitSpinRate")?,
        col("HitSpinAxis")?,
        col("HitLaunchConfidence")?,
    ];
    let mut rows = Vec::new();
    for (n, record) in reader.records().enumerate() {
        let record = record.map_err(|e| format!("row {}: {e}", n + 2))?;
        let get = |i: usize| record.get(idx[i]).unwrap_or("");
        let num = |i: usize| cell(get(i)).map_err(|e| format!("row {}: {e}", n + 2));
        rows.push(SpinRow {
            game: get(0).to_string(),
            pitch_call: get(1).to_string(),
            zone_speed_mph: num(2)?,
            vert_appr_angle_deg: num(3)?,
            pitch_spin_rpm: num(4)?,
            exit_speed_mph: num(5)?,
            launch_deg: num(6)?,
            hit_spin_rpm: num(7)?,
            hit_spin_axis_deg: num(8)?,
            launch_confidence: get(9).to_string(),
        });
    }
    Ok(rows)
}

/// Balls in play whose launch was tracked with High or Medium confidence, with launch angle and spin:
/// (launch deg, spin rpm).
pub fn tracked_balls_in_play(rows: &[SpinRow]) -> Vec<(f64, f64)> {
    rows.iter().filter(|r| is_tracked_ball_in_play(r)).filter_map(|r| Some((r.launch_deg?, r.hit_spin_rpm?))).collect()
}

/// A ball in play whose launch was tracked with High or Medium confidence.
fn is_tracked_ball_in_play(r: &SpinRow) -> bool {
    r.pitch_call == "InPlay" && matches!(r.launch_confidence.as_str(), "High" | "Medium")
}

/// The quantile `p` (0…1) of sorted `values`, linear between order statistics at p·(n − 1).
pub fn quantile(sorted: &[f64], p: f64) -> Option<f64> {
    if sorted.is_empty() {
        return None;
    }
    let pos = p * (sorted.len() - 1) as f64;
    let lo = pos.floor() as usize;
    let hi = pos.ceil() as usize;
    Some(sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - lo as f64))
}

/// Spin statistics of the tracked balls in play launched within `half_width` deg of `launch` deg.
pub fn bin(rows: &[SpinRow], launch: f64, half_width: f64) -> SpinBin {
    let in_bin = |r: &&SpinRow| {
        is_tracked_ball_in_play(r)
            && r.hit_spin_rpm.is_some()
            && r.launch_deg.is_some_and(|angle| (angle - launch).abs() <= half_width)
    };
    let mut spins: Vec<f64> = rows.iter().filter(in_bin).filter_map(|r| r.hit_spin_rpm).collect();
    spins.sort_by(f64::total_cmp);
    let mut exit_speeds: Vec<f64> = rows.iter().filter(in_bin).filter_map(|r| r.exit_speed_mph).collect();
    exit_speeds.sort_by(f64::total_cmp);
    SpinBin {
        launch_deg: launch,
        half_width_deg: half_width,
        count: spins.len(),
        median_rpm: quantile(&spins, 0.5),
        q1_rpm: quantile(&spins, 0.25),
        q3_rpm: quantile(&spins, 0.75),
        spins_rpm: spins,
        median_exit_speed_mph: quantile(&exit_speeds, 0.5),
    }
}

/// Medians of the pitch over balls in play (any launch confidence) that carry all three pitch values.
pub fn pitch_medians(rows: &[SpinRow]) -> Option<PitchMedians> {
    let picked: Vec<(f64, f64, f64)> = rows
        .iter()
        .filter(|r| r.pitch_call == "InPlay")
        .filter_map(|r| Some((r.zone_speed_mph?, r.vert_appr_angle_deg?, r.pitch_spin_rpm?)))
        .collect();
    let median = |f: fn(&(f64, f64, f64)) -> f64| {
        let mut v: Vec<f64> = picked.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        quantile(&v, 0.5)
    };
    Some(PitchMedians {
        zone_speed_mph: median(|p| p.0)?,
        vert_appr_angle_deg: median(|p| p.1)?,
        spin_rpm: median(|p| p.2)?,
        count: picked.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate_between_order_statistics() {
        // Hand values: n = 4, p = 0.25 → position 0.75 between 1 and 2; median between 2 and 10.
        let v = [1.0, 2.0, 10.0, 20.0];
        assert_eq!(quantile(&v, 0.25), Some(1.75));
        assert_eq!(quantile(&v, 0.5), Some(6.0));
        assert_eq!(quantile(&v, 0.75), Some(12.5));
        assert_eq!(quantile(&[], 0.5), None);
    }

    #[test]
    fn only_tracked_balls_in_play_with_spin_are_binned() {
        let text = "Game,PitchNo,PitchCall,ZoneSpeed,VertApprAngle,SpinRate,ExitSpeed,Angle,HitSpinRate,HitSpinAxis,HitLaunchConfidence\n\
                    g,1,InPlay,80,-6,2200,90,11,2000,200,High\n\
                    g,2,InPlay,82,-5,2300,91,9,3000,,Medium\n\
                    g,3,InPlay,84,-7,2400,92,10,9999,,Low\n\
                    g,4,FoulBallNotFieldable,85,-6,2500,93,10,8888,,High\n\
                    g,5,InPlay,86,-6,2600,94,10,,,High\n\
                    g,6,InPlay,87,-6,2700,95,25,1000,,High\n";
        let rows = parse(text).unwrap();
        let b = bin(&rows, 10.0, 5.0);
        assert_eq!(b.spins_rpm, vec![2000.0, 3000.0]);
        assert_eq!(b.median_rpm, Some(2500.0));
        let p = pitch_medians(&rows).unwrap();
        assert_eq!(p.count, 5);
        assert_eq!(p.zone_speed_mph, 84.0);
    }
}
