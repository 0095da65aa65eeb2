//! The Statcast tables of the suite (`validation/statcast_q.csv`, `statcast_attack.csv`), derived from real
//! 2024 MLB games by `scripts/statcast_tables.py` (counts, medians and percentiles per bin; never raw rows).
//!
//! `statcast_q.csv`: the collision efficiency q = (EV − bat)/(plate pitch + bat) of every ball in play with a
//! measured bat speed, per 5-mph bin of the swing's bat speed (`bat`), of the plate pitch speed
//! (`plate_pitch`) and of the batter's season-median bat speed (`batter_median_bat`), for the whole season
//! (`all`) and its odd and even `game_pk` halves. `statcast_attack.csv`: the attack angle's quartiles by
//! launch-angle bin. `statcast_exit_undercut.csv`: the exit speed's percentiles and the median attack angle per
//! 5° bin of launch angle − attack angle. Lines starting with `#` are the provenance. Every file is optional:
//! without them the suite has no Statcast rows.

use std::path::Path;

use serde::Serialize;

use super::ValidateError;

/// One bin of `statcast_q.csv`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QBin {
    /// What the bin sorts on: `bat`, `plate_pitch` or `batter_median_bat`.
    pub by: String,
    /// `all`, `odd` or `even` (`game_pk` parity).
    pub half: String,
    /// Lower edge, mph.
    pub low: f64,
    /// Upper edge, mph.
    pub high: f64,
    /// Balls in the bin.
    pub count: usize,
    /// Median bat speed 6 in from the head, mph.
    pub median_bat_mph: f64,
    /// Median pitch speed at the front of the plate, mph.
    pub median_plate_pitch_mph: f64,
    /// Median q.
    pub q_p50: f64,
    /// 97th percentile of q.
    pub q_p97: f64,
    /// 99th percentile of q.
    pub q_p99: f64,
    /// 99.8th percentile of q.
    pub q_p99_8: f64,
}

/// One launch-angle bin of `statcast_attack.csv`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttackBin {
    /// Launch angles from, deg.
    pub launch_low_deg: f64,
    /// Launch angles to (exclusive), deg.
    pub launch_high_deg: f64,
    /// Balls in the bin.
    pub count: usize,
    /// First quartile of the attack angle, deg.
    pub attack_q1_deg: f64,
    /// Median attack angle, deg.
    pub attack_median_deg: f64,
    /// Third quartile, deg.
    pub attack_q3_deg: f64,
}

/// One bin of `statcast_exit_undercut.csv`: balls whose launch angle − attack angle lies in [low, high).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UndercutBin {
    /// Lower edge of launch − attack, deg.
    pub low_deg: f64,
    /// Upper edge (exclusive), deg.
    pub high_deg: f64,
    /// Balls in the bin.
    pub count: usize,
    /// Median bat speed 6 in from the head, mph.
    pub median_bat_mph: f64,
    /// Median attack angle, deg.
    pub median_attack_deg: f64,
    /// Median exit speed, mph.
    pub exit_p50_mph: f64,
    /// 97th percentile of the exit speed, mph.
    pub exit_p97_mph: f64,
    /// 99th percentile, mph.
    pub exit_p99_mph: f64,
    /// 99.8th percentile, mph.
    pub exit_p99_8_mph: f64,
    /// Lower end of the 95 % confidence interval of the 99th percentile (distribution-free), mph.
    pub exit_p99_ci_low_mph: f64,
    /// Upper end of that interval, mph.
    pub exit_p99_ci_high_mph: f64,
}

/// The Statcast tables (empty when a file is absent).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tables {
    /// q bins.
    pub q: Vec<QBin>,
    /// Attack-angle bins.
    pub attack: Vec<AttackBin>,
    /// Exit speed by launch − attack bins.
    pub undercut: Vec<UndercutBin>,
}

impl Tables {
    /// The q bins sorted on `by` of the season half `half`.
    pub fn q_bins<'a>(&'a self, by: &'a str, half: &'a str) -> impl Iterator<Item = &'a QBin> + 'a {
        self.q.iter().filter(move |b| b.by == by && b.half == half)
    }

    /// The attack-angle bin centred on `launch_deg` (deg), if the table has it.
    pub fn attack_at(&self, launch_deg: f64) -> Option<&AttackBin> {
        self.attack.iter().find(|b| (0.5 * (b.launch_low_deg + b.launch_high_deg) - launch_deg).abs() < 1e-9)
    }
}

/// The text without its `#` provenance lines.
fn data_lines(text: &str) -> String {
    text.lines().filter(|l| !l.starts_with('#')).map(|l| format!("{l}\n")).collect()
}

/// Parses records of a derived table: `columns` found by name, every cell a number except those named in
/// `text_columns`.
fn records(text: &str, columns: &[&str]) -> Result<Vec<Vec<String>>, String> {
    let body = data_lines(text);
    let mut reader = csv::ReaderBuilder::new().from_reader(body.as_bytes());
    let headers = reader.headers().map_err(|e| format!("header: {e}"))?.clone();
    let idx: Vec<usize> = columns
        .iter()
        .map(|c| headers.iter().position(|h| h == *c).ok_or_else(|| format!("no column '{c}'")))
        .collect::<Result<_, _>>()?;
    let mut out = Vec::new();
    for (n, record) in reader.records().enumerate() {
        let record = record.map_err(|e| format!("record {}: {e}", n + 1))?;
        out.push(idx.iter().map(|&i| record.get(i).unwrap_or("").to_string()).collect());
    }
    Ok(out)
}

fn number(cell: &str, column: &str, n: usize) -> Result<f64, String> {
    cell.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("record {}: {column} '{cell}' is not a number", n + 1))
}

/// Parses `statcast_q.csv`.
pub fn parse_q(text: &str) -> Result<Vec<QBin>, String> {
    let cols = [
        "by",
        "half",
        "low",
        "high",
        "count",
        "median_bat_mph",
        "median_plate_pitch_mph",
        "q_p50",
        "q_p97",
        "q_p99",
        "q_p99_8",
    ];
    records(text, &cols)?
        .into_iter()
        .enumerate()
        .map(|(n, r)| {
            let f = |i: usize| number(&r[i], cols[i], n);
            Ok(QBin {
                by: r[0].clone(),
                half: r[1].clone(),
                low: f(2)?,
                high: f(3)?,
                count: f(4)? as usize,
                median_bat_mph: f(5)?,
                median_plate_pitch_mph: f(6)?,
                q_p50: f(7)?,
                q_p97: f(8)?,
                q_p99: f(9)?,
                q_p99_8: f(10)?,
            })
        })
        .collect()
}

/// Parses `statcast_attack.csv`.
pub fn parse_attack(text: &str) -> Result<Vec<AttackBin>, String> {
    let cols = ["launch_low_deg", "launch_high_deg", "count", "attack_q1_deg", "attack_median_deg", "attack_q3_deg"];
    records(text, &cols)?
        .into_iter()
        .enumerate()
        .map(|(n, r)| {
            let f = |i: usize| number(&r[i], cols[i], n);
            Ok(AttackBin {
                launch_low_deg: f(0)?,
                launch_high_deg: f(1)?,
                count: f(2)? as usize,
                attack_q1_deg: f(3)?,
                attack_median_deg: f(4)?,
                attack_q3_deg: f(5)?,
            })
        })
        .collect()
}

/// Parses `statcast_exit_undercut.csv`.
pub fn parse_undercut(text: &str) -> Result<Vec<UndercutBin>, String> {
    let cols = [
        "low_deg",
        "high_deg",
        "count",
        "median_bat_mph",
        "median_attack_deg",
        "exit_p50_mph",
        "exit_p97_mph",
        "exit_p99_mph",
        "exit_p99_8_mph",
        "exit_p99_ci_low_mph",
        "exit_p99_ci_high_mph",
    ];
    records(text, &cols)?
        .into_iter()
        .enumerate()
        .map(|(n, r)| {
            let f = |i: usize| number(&r[i], cols[i], n);
            Ok(UndercutBin {
                low_deg: f(0)?,
                high_deg: f(1)?,
                count: f(2)? as usize,
                median_bat_mph: f(3)?,
                median_attack_deg: f(4)?,
                exit_p50_mph: f(5)?,
                exit_p97_mph: f(6)?,
                exit_p99_mph: f(7)?,
                exit_p99_8_mph: f(8)?,
                exit_p99_ci_low_mph: f(9)?,
                exit_p99_ci_high_mph: f(10)?,
            })
        })
        .collect()
}

/// Reads the tables present in `dir`; the names of the files read are pushed to `files`.
pub fn read(dir: &Path, files: &mut Vec<String>) -> Result<Tables, ValidateError> {
    let mut tables = Tables::default();
    let q = dir.join("statcast_q.csv");
    if q.exists() {
        let text = sweetspot_model::files::read_text(&q, "validation data file")?;
        tables.q = parse_q(&text).map_err(|message| ValidateError::Parse { path: q.clone(), message })?;
        files.push(q.display().to_string());
    }
    let a = dir.join("statcast_attack.csv");
    if a.exists() {
        let text = sweetspot_model::files::read_text(&a, "validation data file")?;
        tables.attack = parse_attack(&text).map_err(|message| ValidateError::Parse { path: a.clone(), message })?;
        files.push(a.display().to_string());
    }
    let u = dir.join("statcast_exit_undercut.csv");
    if u.exists() {
        let text = sweetspot_model::files::read_text(&u, "validation data file")?;
        tables.undercut = parse_undercut(&text).map_err(|message| ValidateError::Parse { path: u.clone(), message })?;
        files.push(u.display().to_string());
    }
    Ok(tables)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn provenance_lines_are_skipped_and_cells_are_checked() {
        let text = "# from somewhere\nby,half,low,high,count,median_bat_mph,median_plate_pitch_mph,q_p50,q_p97,q_p99,\
                    q_p99_8\nbat,all,55,60,10,58.2,81.5,0.13,0.23,0.24,0.25\n";
        let bins = parse_q(text).unwrap();
        assert_eq!(bins.len(), 1);
        assert_eq!((bins[0].low, bins[0].q_p99_8, bins[0].count), (55.0, 0.25, 10));
        let bad = text.replace("0.24", "x");
        assert!(parse_q(&bad).unwrap_err().contains("q_p99"));
        assert!(parse_q("by,half\nbat,all\n").unwrap_err().contains("no column"));
    }
}
