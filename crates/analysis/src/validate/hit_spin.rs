//! Batted-ball backspin and sidespin by launch angle from real TrackMan game rows
//! (`validation/trackman_hit_spin.csv`, derived by `scripts/trackman_hit_spin.py`; lines starting with `#` are
//! the provenance): every tracked ball in play of two summer-collegiate game exports marked "unverified" by the
//! system, with its batter's side, launch and spray angles, total spin and spin axis. The file is optional:
//! without it the `trackman-backspin/…` and `trackman-sidespin/…` rows are not run.
//!
//! A ball's backspin and sidespin are the radar's: total spin T and TrackMan's HitSpinAxis a (180° = pure
//! backspin, 90° = curving toward left field) give backspin −T cos a and sidespin T sin a (positive toward left
//! field), the model's [`sweetspot_physics::oblique3d`] definitions. Quantiles as in [`super::trackman`].

use std::path::Path;

use serde::Serialize;

use super::trackman::quantile;
use super::ValidateError;

/// The launch-angle bins, deg, [low, high): as many balls in each as the two games give (about ten).
pub const LAUNCH_BINS: [(f64, f64); 3] = [(-90.0, 10.0), (10.0, 20.0), (20.0, 90.0)];

/// One tracked ball in play.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HitBall {
    /// True for a left-handed batter (`BatterSide` = `Left`).
    pub left_handed: bool,
    /// Exit speed, mph (`None` when the cell is empty).
    pub exit_speed_mph: Option<f64>,
    /// Launch angle, deg.
    pub launch_deg: f64,
    /// Spray angle (TrackMan's Direction), deg, positive toward right field.
    pub spray_deg: f64,
    /// Total spin, rpm.
    pub spin_rpm: f64,
    /// Spin axis (TrackMan's HitSpinAxis), deg.
    pub axis_deg: f64,
}

impl HitBall {
    /// Backspin, rpm: −T cos a.
    pub fn backspin_rpm(&self) -> f64 {
        -self.spin_rpm * self.axis_deg.to_radians().cos()
    }

    /// Sidespin, rpm, positive toward left field: T sin a.
    pub fn sidespin_rpm(&self) -> f64 {
        self.spin_rpm * self.axis_deg.to_radians().sin()
    }
}

/// First quartile, median and third quartile.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Quartiles {
    /// First quartile.
    pub q1: f64,
    /// Median.
    pub median: f64,
    /// Third quartile.
    pub q3: f64,
}

impl Quartiles {
    /// The quartiles of `values` (any order); `None` when empty.
    pub fn of(values: impl Iterator<Item = f64>) -> Option<Quartiles> {
        let mut v: Vec<f64> = values.collect();
        v.sort_by(f64::total_cmp);
        Some(Quartiles { q1: quantile(&v, 0.25)?, median: quantile(&v, 0.5)?, q3: quantile(&v, 0.75)? })
    }
}

/// The balls of one launch-angle bin and their spin statistics.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HitSpinBin {
    /// Launch angles held, deg, [low, high).
    pub launch_range_deg: (f64, f64),
    /// The bin's balls.
    pub balls: Vec<HitBall>,
    /// Median launch angle, deg.
    pub launch_median_deg: f64,
    /// Median exit speed of the balls that carry one, mph.
    pub exit_median_mph: Option<f64>,
    /// Backspin quartiles, rpm.
    pub backspin: Quartiles,
    /// Sidespin quartiles, rpm (positive toward left field).
    pub sidespin: Quartiles,
}

impl HitSpinBin {
    /// The bin's id part, e.g. `launch10to20deg`.
    pub fn label(&self) -> String {
        format!("launch{}to{}deg", self.launch_range_deg.0, self.launch_range_deg.1)
    }
}

/// Reads the table at `path`.
pub fn read(path: &Path) -> Result<Vec<HitBall>, ValidateError> {
    let text = sweetspot_model::files::read_text(path, "validation data file")?;
    parse(&text).map_err(|message| ValidateError::Parse { path: path.into(), message })
}

/// Parses the table's text (provenance lines first, then a header; columns found by name).
pub fn parse(text: &str) -> Result<Vec<HitBall>, String> {
    let body: String = text.lines().filter(|l| !l.starts_with('#')).map(|l| format!("{l}\n")).collect();
    let mut reader = csv::ReaderBuilder::new().from_reader(body.as_bytes());
    let headers = reader.headers().map_err(|e| format!("header: {e}"))?.clone();
    let col = |name: &str| headers.iter().position(|h| h == name).ok_or_else(|| format!("no column '{name}'"));
    let idx = [
        col("BatterSide")?,
        col("ExitSpeed")?,
        col("Angle")?,
        col("Direction")?,
        col("HitSpinRate")?,
        col("HitSpinAxis")?,
    ];
    let mut balls = Vec::new();
    for (n, record) in reader.records().enumerate() {
        let record = record.map_err(|e| format!("row {}: {e}", n + 1))?;
        let cell = |i: usize| record.get(idx[i]).unwrap_or("").trim();
        let optional = |i: usize| -> Result<Option<f64>, String> {
            match cell(i) {
                "" => Ok(None),
                t => t
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .map(Some)
                    .ok_or_else(|| format!("row {}: '{t}' is not a number", n + 1)),
            }
        };
        let required = |i: usize| optional(i)?.ok_or_else(|| format!("row {}: column {} is empty", n + 1, idx[i] + 1));
        let left_handed = match cell(0) {
            "Left" => true,
            "Right" => false,
            other => return Err(format!("row {}: BatterSide '{other}' is neither Left nor Right", n + 1)),
        };
        balls.push(HitBall {
            left_handed,
            exit_speed_mph: optional(1)?,
            launch_deg: required(2)?,
            spray_deg: required(3)?,
            spin_rpm: required(4)?,
            axis_deg: required(5)?,
        });
    }
    Ok(balls)
}

/// The balls in each of [`LAUNCH_BINS`] with their statistics (an empty bin is left out).
pub fn bins(balls: &[HitBall]) -> Vec<HitSpinBin> {
    LAUNCH_BINS
        .iter()
        .filter_map(|&(low, high)| {
            let inside: Vec<HitBall> = balls.iter().filter(|b| (low..high).contains(&b.launch_deg)).cloned().collect();
            let launch = Quartiles::of(inside.iter().map(|b| b.launch_deg))?;
            Some(HitSpinBin {
                launch_range_deg: (low, high),
                launch_median_deg: launch.median,
                exit_median_mph: Quartiles::of(inside.iter().filter_map(|b| b.exit_speed_mph)).map(|q| q.median),
                backspin: Quartiles::of(inside.iter().map(HitBall::backspin_rpm))?,
                sidespin: Quartiles::of(inside.iter().map(HitBall::sidespin_rpm))?,
                balls: inside,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backspin_and_sidespin_follow_the_axis_by_hand() {
        let ball = |axis_deg: f64| HitBall {
            left_handed: false,
            exit_speed_mph: None,
            launch_deg: 15.0,
            spray_deg: 0.0,
            spin_rpm: 2000.0,
            axis_deg,
        };
        // 180°: pure backspin; 90°: pure hook (toward left field); 270°: slice; 0°: topspin; 150°: 30° of hook.
        for (axis, back, side) in [
            (180.0, 2000.0, 0.0),
            (90.0, 0.0, 2000.0),
            (270.0, 0.0, -2000.0),
            (0.0, -2000.0, 0.0),
            (150.0, 1732.05, 1000.0),
        ] {
            let b = ball(axis);
            assert!((b.backspin_rpm() - back).abs() < 0.01 && (b.sidespin_rpm() - side).abs() < 0.01, "{axis}");
        }
        assert!(parse("BatterSide,ExitSpeed,Angle,Direction,HitSpinRate,HitSpinAxis\nBoth,90,10,0,2000,180\n").is_err());
        let balls =
            parse("# p\nBatterSide,ExitSpeed,Angle,Direction,HitSpinRate,HitSpinAxis\nLeft,,12,-3,2000,200\n").unwrap();
        assert_eq!(bins(&balls).len(), 1);
        assert_eq!(bins(&balls)[0].label(), "launch10to20deg");
        assert_eq!(bins(&balls)[0].exit_median_mph, None);
    }
}
