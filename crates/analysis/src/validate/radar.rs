//! The MLB radar spin table of the suite (`validation/mlb2018_radar_spin.csv`): total spin by launch angle of
//! every MLB ball in play of 1–9 April 2018 as TrackMan's radar measured it, with each bin's spray-angle
//! percentiles and Statcast's conditional median attack angle and swing-path tilt, derived by
//! `scripts/radar_tables.py` (lines starting with `#` are the provenance). The file is optional: without it
//! the `radar-spin/…` rows are not run.

use std::path::Path;

use serde::Serialize;

use super::ValidateError;

/// One launch-angle bin of the radar table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RadarBin {
    /// Bin centre, deg (the bin holds launch angles in [centre − 2.5°, centre + 2.5°)).
    pub launch_deg: f64,
    /// Balls in the bin (exit speed 80–88 mph, spin measured).
    pub count: usize,
    /// First quartile of the total spin, rpm.
    pub spin_q1_rpm: f64,
    /// Median total spin, rpm.
    pub spin_median_rpm: f64,
    /// Third quartile of the total spin, rpm.
    pub spin_q3_rpm: f64,
    /// Median exit speed, mph.
    pub exit_median_mph: f64,
    /// Spray-angle percentiles 5, 10, …, 95, deg (positive toward right field).
    pub spray_percentiles_deg: Vec<f64>,
    /// Statcast's median attack angle of balls launched within ±5° of the centre, deg.
    pub attack_median_deg: f64,
    /// Statcast's median swing-path tilt of those balls, deg.
    pub tilt_median_deg: f64,
    /// Share of balls in play hit by right-handed batters (2024), 1.
    pub right_handed_share: f64,
}

/// Reads the radar table at `path`.
pub fn read(path: &Path) -> Result<Vec<RadarBin>, ValidateError> {
    let text = sweetspot_model::files::read_text(path, "validation data file")?;
    parse(&text).map_err(|message| ValidateError::Parse { path: path.into(), message })
}

/// Parses the radar table's text (provenance lines first, then a header; columns found by name).
pub fn parse(text: &str) -> Result<Vec<RadarBin>, String> {
    let body: String = text.lines().filter(|l| !l.starts_with('#')).map(|l| format!("{l}\n")).collect();
    let mut reader = csv::ReaderBuilder::new().from_reader(body.as_bytes());
    let headers = reader.headers().map_err(|e| format!("header: {e}"))?.clone();
    let col = |name: &str| headers.iter().position(|h| h == name).ok_or_else(|| format!("no column '{name}'"));
    let spray: Vec<usize> =
        (5..100).step_by(5).map(|p| col(&format!("spray_p{p:02}_deg"))).collect::<Result<_, _>>()?;
    let idx = [
        col("launch_deg")?,
        col("count")?,
        col("spin_q1_rpm")?,
        col("spin_median_rpm")?,
        col("spin_q3_rpm")?,
        col("exit_median_mph")?,
        col("attack_median_deg")?,
        col("tilt_median_deg")?,
        col("right_handed_share")?,
    ];
    let mut bins = Vec::new();
    for (n, record) in reader.records().enumerate() {
        let record = record.map_err(|e| format!("row {}: {e}", n + 1))?;
        let num = |i: usize| -> Result<f64, String> {
            let cell = record.get(i).unwrap_or("").trim();
            cell.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("row {}: '{cell}' is not a number", n + 1))
        };
        let count = num(idx[1])?;
        if !(count >= 0.0 && count.fract() == 0.0) {
            return Err(format!("row {}: count {count} is not a whole number", n + 1));
        }
        bins.push(RadarBin {
            launch_deg: num(idx[0])?,
            count: count as usize,
            spin_q1_rpm: num(idx[2])?,
            spin_median_rpm: num(idx[3])?,
            spin_q3_rpm: num(idx[4])?,
            exit_median_mph: num(idx[5])?,
            spray_percentiles_deg: spray.iter().map(|&i| num(i)).collect::<Result<_, _>>()?,
            attack_median_deg: num(idx[6])?,
            tilt_median_deg: num(idx[7])?,
            right_handed_share: num(idx[8])?,
        });
    }
    Ok(bins)
}

/// The weighted median of `values` (value, weight): the smallest value at which the cumulative weight reaches
/// half the total. `None` when empty or weightless.
pub fn weighted_median(values: &[(f64, f64)]) -> Option<f64> {
    let mut sorted: Vec<(f64, f64)> = values.iter().copied().filter(|(v, w)| v.is_finite() && *w > 0.0).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = sorted.iter().map(|(_, w)| w).sum();
    let mut cumulative = 0.0;
    for (v, w) in sorted {
        cumulative += w;
        if cumulative >= 0.5 * total {
            return Some(v);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_committed_table_parses_with_nine_bins_of_nineteen_percentiles() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation/mlb2018_radar_spin.csv");
        let bins = read(&path).expect("table");
        assert_eq!(bins.iter().map(|b| b.launch_deg).collect::<Vec<_>>(), [5., 10., 15., 20., 25., 30., 35., 40., 45.]);
        for b in &bins {
            assert_eq!(b.spray_percentiles_deg.len(), 19);
            assert!(b.spray_percentiles_deg.windows(2).all(|w| w[0] <= w[1]), "percentiles in order");
            assert!(b.spin_q1_rpm <= b.spin_median_rpm && b.spin_median_rpm <= b.spin_q3_rpm);
        }
    }

    #[test]
    fn weighted_median_by_hand() {
        assert_eq!(weighted_median(&[(3.0, 1.0), (1.0, 1.0), (2.0, 1.0)]), Some(2.0));
        // 0.6 of the weight on 10: the median is 10.
        assert_eq!(weighted_median(&[(1.0, 0.2), (10.0, 0.6), (20.0, 0.2)]), Some(10.0));
        assert_eq!(weighted_median(&[(1.0, 0.5), (5.0, 0.5)]), Some(1.0));
        assert_eq!(weighted_median(&[]), None);
        assert!(parse("launch_deg\n1\n").is_err());
    }
}
