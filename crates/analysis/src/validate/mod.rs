//! The validation suite: the model against published measurements (`sweetspot validate`, issue 22 §1).
//!
//! The measurements live in data files in the repository (`validation/`): `measurements.toml` (one row per
//! compared quantity, with its conditions, value or range, tolerance rule and source, and a list of what could
//! not be found), `trackman_spin.csv` (real tracker rows: measured spin by launch angle), and, when present,
//! `ball_cor.toml` (a ball's COR against impact speed; its rows join the suite, see [`BallCorRow`]). Each row
//! names a case of [`cases::Lab`], which simulates the measurement's conditions with the public physics API;
//! [`evaluate`] applies the row's rule and gives a verdict: PASS, FAIL (outside the stated tolerance), or N/A
//! (the model has no such output yet). A tolerance is part of the measurement and is never loosened.

pub mod cases;
pub mod figures;
pub mod hit_spin;
pub mod radar;
pub mod statcast;
pub mod trackman;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use cases::{CaseValue, Lab, INCH, MPH};
use sweetspot_physics::{CollisionOptions, PhysicsError, TangentialContact};

/// Errors of the validation suite.
#[derive(Debug, thiserror::Error)]
pub enum ValidateError {
    /// A data file is not a regular file within the input cap, or could not be read.
    #[error(transparent)]
    Input(#[from] sweetspot_model::files::InputError),
    /// A data file is malformed.
    #[error("'{path}': {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A row is inconsistent (unknown case, missing parameter, unit mismatch).
    #[error("row '{id}': {message}")]
    Row {
        /// The row's id.
        id: String,
        /// What is wrong.
        message: String,
    },
    /// The physics refused a case's input.
    #[error("case {case}: {source}")]
    Physics {
        /// The case.
        case: String,
        /// The physics error.
        source: PhysicsError,
    },
    /// A figure could not be drawn.
    #[error("figure '{path}': {message}")]
    Figure {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

/// How a row's model number is judged.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Rule {
    /// low ≤ model ≤ high.
    Range,
    /// model ≤ high.
    AtMost,
    /// model ≥ low.
    AtLeast,
    /// |model − value| ≤ uncertainty.
    Within,
    /// Inside the interquartile range of the TrackMan spins in the row's launch-angle bin.
    TrackmanIqr,
}

/// One measurement of `measurements.toml`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Measurement {
    /// Stable name.
    pub id: String,
    /// What is compared.
    pub quantity: String,
    /// The model computation (see [`case_unit`]).
    pub case: String,
    /// Unit of the numbers.
    pub unit: String,
    /// Conditions of the measurement and of the model's case.
    pub conditions: String,
    /// The verdict rule.
    pub rule: Rule,
    /// Lower bound.
    #[serde(default)]
    pub low: Option<f64>,
    /// Upper bound.
    #[serde(default)]
    pub high: Option<f64>,
    /// Reference value for the ratio.
    #[serde(default)]
    pub value: Option<f64>,
    /// Standard uncertainty (rule `within`).
    #[serde(default)]
    pub uncertainty: Option<f64>,
    /// The tolerance in words, and why.
    pub tolerance: String,
    /// Authors, title, journal, year, where in it.
    pub source: String,
    /// `text`, `abstract`, `figure` or `data`.
    pub read_from: String,
    /// Anything else a reader should know.
    #[serde(default)]
    pub note: Option<String>,
    /// The case's inputs.
    #[serde(default)]
    pub params: BTreeMap<String, toml::Value>,
}

/// Something that could not be found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NotFound {
    /// What was looked for.
    pub what: String,
    /// Where.
    pub searched: String,
}

fn default_game_ball() -> String {
    sweetspot_physics::ball::GAME_BALL.into()
}

/// `measurements.toml`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeasurementFile {
    /// The `Ball::preset` used as the game ball (default [`sweetspot_physics::ball::GAME_BALL`]).
    #[serde(default = "default_game_ball")]
    pub game_ball: String,
    /// The rows.
    pub row: Vec<Measurement>,
    /// What could not be found.
    #[serde(default)]
    pub not_found: Vec<NotFound>,
}

/// One row of `ball_cor.toml` (any array of tables whose entries carry `speed` and `value`): a ball's COR
/// against a rigid surface at an impact speed, compared with the model's ball hitting a rigid wall.
///
/// Fields: `quantity` (text), `speed` (impact speed; m/s unless `speed_unit` is `mph` or `ft/s`), `value`
/// (the COR), `low` and `high` (a stated range: the rule is low ≤ model ≤ high) or else `uncertainty` (± on
/// the COR: |model − value| ≤ uncertainty; a row with neither gets N/A), `source`, `read_from`, and
/// optionally `ball` (a `Ball::preset` name; default: the suite's game ball) and `id`. Other fields are
/// ignored.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct BallCorRow {
    /// Optional stable name.
    #[serde(default)]
    pub id: Option<String>,
    /// What was measured.
    #[serde(default)]
    pub quantity: Option<String>,
    /// Impact speed in `speed_unit`.
    pub speed: f64,
    /// `m/s` (default), `mph` or `ft/s`.
    #[serde(default)]
    pub speed_unit: Option<String>,
    /// The measured COR.
    pub value: f64,
    /// ± on the COR.
    #[serde(default)]
    pub uncertainty: Option<f64>,
    /// Lower end of a stated range (with `high`, the row's bounds).
    #[serde(default)]
    pub low: Option<f64>,
    /// Upper end of a stated range.
    #[serde(default)]
    pub high: Option<f64>,
    /// The ball preset.
    #[serde(default)]
    pub ball: Option<String>,
    /// Where the number was read.
    #[serde(default)]
    pub source: Option<String>,
    /// `text`, `abstract`, `figure`, `data`.
    #[serde(default)]
    pub read_from: Option<String>,
}

/// A row's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Verdict {
    /// Inside the tolerance.
    #[serde(rename = "PASS")]
    Pass,
    /// Outside the tolerance.
    #[serde(rename = "FAIL")]
    Fail,
    /// The model (or the data) has no such number yet.
    #[serde(rename = "N/A")]
    NotApplicable,
}

impl Verdict {
    /// PASS, FAIL or N/A.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Pass => "PASS",
            Verdict::Fail => "FAIL",
            Verdict::NotApplicable => "N/A",
        }
    }
}

/// One judged row.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RowResult {
    /// Stable name.
    pub id: String,
    /// What is compared.
    pub quantity: String,
    /// Unit.
    pub unit: String,
    /// Conditions.
    pub conditions: String,
    /// The rule.
    pub rule: Rule,
    /// Lower bound used.
    pub low: Option<f64>,
    /// Upper bound used.
    pub high: Option<f64>,
    /// Reference value of the ratio.
    pub reference: Option<f64>,
    /// The model's number.
    pub model: Option<f64>,
    /// model / reference.
    pub ratio: Option<f64>,
    /// PASS, FAIL, N/A.
    pub verdict: Verdict,
    /// How the model got its number.
    pub model_detail: String,
    /// The tolerance in words.
    pub tolerance: String,
    /// Source.
    pub source: String,
    /// text / abstract / figure / data.
    pub read_from: String,
    /// Notes.
    pub note: Option<String>,
}

/// The suite's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// Every row, in file order (ball COR rows last).
    pub rows: Vec<RowResult>,
    /// Rows that passed, failed, had no verdict.
    pub pass: usize,
    /// Rows outside their tolerance.
    pub fail: usize,
    /// Rows without a model number.
    pub not_applicable: usize,
    /// The TrackMan bins used (launch angle, count, quartiles).
    pub trackman_bins: Vec<trackman::SpinBin>,
    /// The pitch the game swing met (medians over balls in play).
    pub trackman_pitch: Option<trackman::PitchMedians>,
    /// What could not be found.
    pub not_found: Vec<NotFound>,
    /// Data files read.
    pub files: Vec<String>,
    /// The tangential contact law of the oblique rows.
    pub contact: TangentialContact,
}

/// The unit each case computes in.
pub fn case_unit(case: &str) -> Option<&'static str> {
    Some(match case {
        "collision_efficiency_sweet_spot"
        | "statcast_q_sweet_spot"
        | "ball_wall_cor"
        | "bbcor"
        | "spin_transfer_fixed_cylinder"
        | "bpf_hoop_trend"
        | "bpf_max_in_band"
        | "swing_exit_hoop_trend" => "1",
        "first_mode_hz" | "hoop_frequency_hz" => "Hz",
        "first_node_from_end_in" | "sweet_spot_shift_in" => "in",
        "tee_max_spin_rpm" | "game_spin_rpm" => "rpm",
        "statcast_q_envelope" => "1",
        "cage_exit_difference_mph" | "besr_max_exit_mph" => "mph",
        "contact_time_ms" => "ms",
        _ => return None,
    })
}

/// Reads `measurements.toml`.
pub fn read_measurements(path: &Path) -> Result<MeasurementFile, ValidateError> {
    let text = sweetspot_model::files::read_text(path, "validation data file")?;
    let file: MeasurementFile =
        toml::from_str(&text).map_err(|e| ValidateError::Parse { path: path.into(), message: e.to_string() })?;
    for row in &file.row {
        match case_unit(&row.case) {
            None => {
                return Err(ValidateError::Row { id: row.id.clone(), message: format!("unknown case '{}'", row.case) })
            }
            Some(unit) if unit != row.unit => {
                return Err(ValidateError::Row {
                    id: row.id.clone(),
                    message: format!("unit '{}' but case {} computes in '{unit}'", row.unit, row.case),
                })
            }
            _ => {}
        }
    }
    let mut ids: Vec<&str> = file.row.iter().map(|r| r.id.as_str()).collect();
    ids.sort_unstable();
    if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
        return Err(ValidateError::Row { id: w[0].to_string(), message: "id used twice".into() });
    }
    Ok(file)
}

/// Reads the rows of `ball_cor.toml`: every top-level array of tables whose entries have `speed` and `value`.
pub fn read_ball_cor(path: &Path) -> Result<Vec<BallCorRow>, ValidateError> {
    let text = sweetspot_model::files::read_text(path, "validation data file")?;
    let parse_err = |message: String| ValidateError::Parse { path: path.into(), message };
    let doc: toml::Table = toml::from_str(&text).map_err(|e| parse_err(e.to_string()))?;
    let mut rows = Vec::new();
    for (key, value) in doc {
        let Some(array) = value.as_array() else { continue };
        for (i, entry) in array.iter().enumerate() {
            let Some(table) = entry.as_table() else { continue };
            if !(table.contains_key("speed") && table.contains_key("value")) {
                continue;
            }
            let row: BallCorRow =
                entry.clone().try_into().map_err(|e: toml::de::Error| parse_err(format!("{key}[{i}]: {e}")))?;
            rows.push(row);
        }
    }
    Ok(rows)
}

fn speed_in_m_s(row: &BallCorRow) -> Result<f64, String> {
    match row.speed_unit.as_deref().map(str::trim) {
        None | Some("m/s") => Ok(row.speed),
        Some("mph") => Ok(row.speed * MPH),
        Some("ft/s") => Ok(row.speed * sweetspot_physics::units::FT_PER_S),
        Some(other) => Err(format!("speed_unit '{other}' (expected m/s, mph or ft/s)")),
    }
}

fn param(row: &Measurement, key: &str) -> Result<f64, ValidateError> {
    match row.params.get(key) {
        Some(toml::Value::Float(v)) => Ok(*v),
        Some(toml::Value::Integer(v)) => Ok(*v as f64),
        _ => Err(ValidateError::Row { id: row.id.clone(), message: format!("params.{key}: a number is required") }),
    }
}

fn param_str<'a>(row: &'a Measurement, key: &str) -> Result<&'a str, ValidateError> {
    match row.params.get(key) {
        Some(toml::Value::String(v)) => Ok(v),
        _ => Err(ValidateError::Row { id: row.id.clone(), message: format!("params.{key}: a string is required") }),
    }
}

/// Everything the suite reads.
pub struct Inputs {
    /// The measurements.
    pub measurements: MeasurementFile,
    /// TrackMan rows.
    pub trackman: Vec<trackman::SpinRow>,
    /// Ball COR rows (empty when the file is absent).
    pub ball_cor: Vec<BallCorRow>,
    /// The Statcast tables (empty when absent).
    pub statcast: statcast::Tables,
    /// The files read.
    pub files: Vec<String>,
    /// The MLB radar spin table (empty when the file is absent).
    pub radar: Vec<radar::RadarBin>,
    /// The summer-collegiate TrackMan balls with their spin axis (empty when the file is absent).
    pub hit_spin: Vec<hit_spin::HitBall>,
}

/// Reads the suite's files from `dir` (`ball_cor.toml` only if present).
pub fn read_inputs(dir: &Path) -> Result<Inputs, ValidateError> {
    let m = dir.join("measurements.toml");
    let t = dir.join("trackman_spin.csv");
    let c = dir.join("ball_cor.toml");
    let mut files = vec![m.display().to_string(), t.display().to_string()];
    let ball_cor = if c.exists() {
        files.push(c.display().to_string());
        read_ball_cor(&c)?
    } else {
        Vec::new()
    };
    let statcast = statcast::read(dir, &mut files)?;
    let r = dir.join("mlb2018_radar_spin.csv");
    let radar = if r.exists() {
        files.push(r.display().to_string());
        radar::read(&r)?
    } else {
        Vec::new()
    };
    let h = dir.join("trackman_hit_spin.csv");
    let hit_spin = if h.exists() {
        files.push(h.display().to_string());
        hit_spin::read(&h)?
    } else {
        Vec::new()
    };
    Ok(Inputs {
        measurements: read_measurements(&m)?,
        trackman: trackman::read(&t)?,
        ball_cor,
        statcast,
        radar,
        hit_spin,
        files,
    })
}

/// Judges `model` against the bounds.
pub fn judge(rule: Rule, model: Option<f64>, low: Option<f64>, high: Option<f64>) -> Verdict {
    let Some(m) = model.filter(|m| m.is_finite()) else { return Verdict::NotApplicable };
    let ok = match rule {
        Rule::Range | Rule::Within | Rule::TrackmanIqr => match (low, high) {
            (Some(lo), Some(hi)) => lo <= m && m <= hi,
            _ => return Verdict::NotApplicable,
        },
        Rule::AtMost => match high {
            Some(hi) => m <= hi,
            None => return Verdict::NotApplicable,
        },
        Rule::AtLeast => match low {
            Some(lo) => m >= lo,
            None => return Verdict::NotApplicable,
        },
    };
    if ok {
        Verdict::Pass
    } else {
        Verdict::Fail
    }
}

fn ratio(model: Option<f64>, reference: Option<f64>) -> Option<f64> {
    match (model, reference) {
        (Some(m), Some(r)) if r != 0.0 && m.is_finite() => Some(m / r),
        _ => None,
    }
}

/// Runs the model case of `row`.
fn run_case(lab: &Lab, inputs: &Inputs, row: &Measurement) -> Result<CaseValue, ValidateError> {
    let p = |k: &str| param(row, k);
    let s = |k: &str| param_str(row, k);
    match row.case.as_str() {
        "collision_efficiency_sweet_spot" => lab.collision_efficiency_sweet_spot(s("bat")?, p("pitch_speed")?),
        "statcast_q_sweet_spot" => lab.statcast_q_sweet_spot(s("bat")?, p("pitch_speed")?),
        "ball_wall_cor" => lab.ball_wall_cor(&lab.game_ball, p("speed")?),
        "bbcor" => lab.bbcor(s("bat")?, s("ball")?),
        "besr_max_exit_mph" => lab.besr_max_exit_mph(s("bat")?, s("ball")?),
        "first_mode_hz" => lab.first_mode_hz(s("bat")?),
        "first_node_from_end_in" => lab.first_node_from_end_in(s("bat")?),
        "hoop_frequency_hz" => lab.hoop_frequency_hz(s("bat")?, p("from_end")?),
        "tee_max_spin_rpm" => lab.tee_max_spin_rpm(s("bat")?, p("bat_speed_mph")? * MPH, p("max_launch_deg")?),
        "game_spin_rpm" => game_spin_case(lab, inputs, row),
        "spin_transfer_fixed_cylinder" => lab.spin_transfer_fixed_cylinder(
            p("ball_speed_mph")? * MPH,
            p("cylinder_radius")?,
            p("line_of_centres_deg")?,
            p("incoming_spin_rpm")?,
        ),
        "swing_exit_hoop_trend" => swing_exit_hoop_trend_case(lab, row),
        "bpf_hoop_trend" | "bpf_max_in_band" => bpf_case(lab, row),
        "cage_exit_difference_mph" => lab.cage_exit_difference_mph(s("wood")?, s("metal")?, p("pitch_speed")?),
        "sweet_spot_shift_in" => lab.sweet_spot_shift_in(s("wood")?, s("metal")?, p("pitch_speed")?),
        "contact_time_ms" => lab.contact_time_ms(s("bat")?, p("pitch_speed")?, p("from_end")?),
        other => Err(ValidateError::Row { id: row.id.clone(), message: format!("unknown case '{other}'") }),
    }
}

/// The game spin at a launch angle, with the TrackMan pitch and, when asked, Statcast's attack angle.
fn game_spin_case(lab: &Lab, inputs: &Inputs, row: &Measurement) -> Result<CaseValue, ValidateError> {
    let p = |k: &str| param(row, k);
    match trackman::pitch_medians(&inputs.trackman) {
        Some(pitch) => {
            let (launch, half_width) = (p("launch_deg")?, p("bin_half_width_deg")?);
            let exit_speed = trackman::bin(&inputs.trackman, launch, half_width).median_exit_speed_mph;
            let (attack, measured) = match row.params.get("attack_deg") {
                Some(toml::Value::String(from)) if from == "statcast" => match inputs.statcast.attack_at(launch) {
                    Some(b) => (b.attack_median_deg, Some(b)),
                    None => {
                        return Ok(CaseValue {
                            value: None,
                            detail: format!("no Statcast attack angle for balls launched at {launch}°"),
                        })
                    }
                },
                _ => (p("attack_deg")?, None),
            };
            let mut case = lab.game_spin_rpm(&pitch, attack, launch, exit_speed)?;
            if let Some(b) = measured {
                case.detail.push_str(&format!(
                "; attack angle {:.2}° = Statcast's median for {} balls launched at {}–{}° (quartiles {:.2}–{:.2}°)",
                b.attack_median_deg, b.count, b.launch_low_deg, b.launch_high_deg, b.attack_q1_deg, b.attack_q3_deg
            ));
            }
            Ok(case)
        }
        None => Ok(CaseValue { value: None, detail: "no pitch data in the TrackMan rows".into() }),
    }
}

/// The rank correlation of exit speed with hoop frequency over the walls of matched bats in the band.
fn swing_exit_hoop_trend_case(lab: &Lab, row: &Measurement) -> Result<CaseValue, ValidateError> {
    let p = |k: &str| param(row, k);
    let (lo, hi) = (p("hoop_low_hz")?, p("hoop_high_hz")?);
    let curve = lab.matched_swing_curve()?;
    let band: Vec<&cases::SwingPoint> = curve.iter().filter(|q| q.hoop_hz >= lo && q.hoop_hz <= hi).collect();
    let pairs: Vec<(f64, f64)> = band.iter().map(|q| (q.hoop_hz, q.exit_speed)).collect();
    let detail = match (band.first(), band.last()) {
        (Some(a), Some(b)) => format!(
            "{} walls {:.2}–{:.2} mm at aluminum's mass and swing weight ({:.0}–{:.0} Hz; heavier walls cannot \
             be built to it); exit {:.1} mph at {:.0} Hz (rigid bat {:.1}), {:.1} mph at {:.0} Hz (rigid {:.1})",
            band.len(),
            a.wall * 1e3,
            b.wall * 1e3,
            a.hoop_hz,
            b.hoop_hz,
            a.exit_speed / MPH,
            a.hoop_hz,
            a.rigid_exit_speed / MPH,
            b.exit_speed / MPH,
            b.hoop_hz,
            b.rigid_exit_speed / MPH
        ),
        _ => "no wall in the band".into(),
    };
    Ok(CaseValue { value: cases::rank_correlation(&pairs), detail })
}

/// The BPF over the walls in the hoop band: its rank correlation with hoop frequency, or its largest value.
fn bpf_case(lab: &Lab, row: &Measurement) -> Result<CaseValue, ValidateError> {
    let p = |k: &str| param(row, k);
    let s = |k: &str| param_str(row, k);
    let (lo, hi) = (p("hoop_low_hz")?, p("hoop_high_hz")?);
    let curve = lab.bpf_curve(s("ball")?, p("ball_speed_mph")? * MPH)?;
    let band: Vec<&cases::BpfPoint> = curve.iter().filter(|q| q.hoop_hz >= lo && q.hoop_hz <= hi).collect();
    let walls = match (band.first(), band.last()) {
        (Some(a), Some(b)) => format!("{} walls {:.2}–{:.2} mm", band.len(), a.wall * 1e3, b.wall * 1e3),
        _ => "no wall in the band".into(),
    };
    if row.case == "bpf_hoop_trend" {
        let pairs: Vec<(f64, f64)> = band.iter().map(|q| (q.hoop_hz, q.bpf)).collect();
        Ok(CaseValue { value: cases::rank_correlation(&pairs), detail: format!("{walls}, {lo:.0}–{hi:.0} Hz") })
    } else {
        let best = band.iter().max_by(|a, b| a.bpf.total_cmp(&b.bpf));
        Ok(CaseValue {
            value: best.map(|q| q.bpf),
            detail: match best {
                Some(q) => format!("{walls}; largest at {:.2} mm, {:.0} Hz", q.wall * 1e3, q.hoop_hz),
                None => walls,
            },
        })
    }
}

/// The sorts of `statcast_q.csv` that become rows (season `all`): the batter's season-median bat speed, which
/// the swing's own measurement error does not sort, and the plate pitch speed. Bins on the swing's measured
/// bat speed are biased by that error in the extreme bins (docs/statcast.md) and stay in the table only.
pub const STATCAST_Q_ROWS: &[&str] = &["batter_median_bat", "plate_pitch"];

/// The q-envelope rows: per bin of [`STATCAST_Q_ROWS`], the game ball's largest q over the barrel at the bin's
/// median bat and plate pitch speeds must lie inside the bin's [97th, 99.8th] percentile band.
fn statcast_q_rows(lab: &Lab, tables: &statcast::Tables) -> Result<Vec<RowResult>, ValidateError> {
    use rayon::prelude::*;
    let bins: Vec<&statcast::QBin> = STATCAST_Q_ROWS.iter().flat_map(|by| tables.q_bins(by, "all")).collect();
    let cases: Vec<CaseValue> = bins
        .par_iter()
        .map(|b| lab.statcast_q_max(b.median_bat_mph * MPH, b.median_plate_pitch_mph * MPH))
        .collect::<Result<_, _>>()?;
    Ok(bins
        .iter()
        .zip(cases)
        .map(|(b, case)| {
            let (low, high) = (Some(b.q_p97), Some(b.q_p99_8));
            let sort = match b.by.as_str() {
                "batter_median_bat" => "batter's season-median bat speed",
                "plate_pitch" => "plate pitch speed",
                _ => "bat speed",
            };
            RowResult {
                id: format!("statcast-q/{}-{}-{}", b.by.replace('_', "-"), b.low, b.high),
                quantity: format!("largest collision efficiency q, {sort} {}–{} mph", b.low, b.high),
                unit: "1".into(),
                conditions: format!(
                    "{} MLB balls in play of 2024 (Statcast, measured bat speed), {sort} in [{}, {}) mph; model at \
                     the bin's medians: bat {:.2} mph 6 in from the head, plate pitch {:.2} mph",
                    b.count, b.low, b.high, b.median_bat_mph, b.median_plate_pitch_mph
                ),
                rule: Rule::Range,
                low,
                high,
                reference: Some(b.q_p99),
                model: case.value,
                ratio: ratio(case.value, Some(b.q_p99)),
                verdict: judge(Rule::Range, case.value, low, high),
                model_detail: case.detail,
                tolerance: "inside the bin's [97th, 99.8th] percentile band of q: the best-struck real balls reach \
                            the true maximum, measurement noise puts a few above it (docs/statcast.md); the \
                            reference is the 99th"
                    .into(),
                source: "Baseball Savant 2024 (validation/statcast_q.csv, derived by scripts/statcast_tables.py)"
                    .into(),
                read_from: "data".into(),
                note: None,
            }
        })
        .collect())
}

/// The largest y of the piecewise-linear curve `points` (x, y), in order, over x in [low, high): its points
/// inside and where its segments cross either edge; `None` if it never enters the interval.
pub fn largest_in(points: &[(f64, f64)], low: f64, high: f64) -> Option<f64> {
    let inside = points.iter().filter(|(x, _)| (low..high).contains(x)).map(|p| p.1);
    let crossings = points.windows(2).flat_map(|w| {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        [low, high]
            .into_iter()
            .filter(move |&edge| (x0 - edge) * (x1 - edge) <= 0.0 && x1 != x0)
            .map(move |edge| y0 + (y1 - y0) * (edge - x0) / (x1 - x0))
    });
    inside.chain(crossings).fold(None, |best: Option<f64>, y| Some(best.map_or(y, |b| b.max(y))))
}

/// Largest departure of the model's median spin from the radar's median that a `radar-spin/…` row accepts.
pub const RADAR_MEDIAN_TOLERANCE: f64 = 0.12;

/// The `radar-spin/…` rows: total spin by launch angle against the MLB 2018 radar (`validation/mlb2018_radar_spin.csv`).
/// Per bin the R161 is swung in three dimensions at Statcast's median attack angle and swing-path tilt for
/// the bin, at the speed that sends a ball launched there toward centre field at the bin's median exit speed,
/// against the TrackMan rows' median pitch; the swing's direction is scanned so that the ball goes where the
/// bin's balls went (its 19 spray percentiles), each spray hit by a right-handed batter (weight: their share of
/// balls in play) and its mirror image by a left-handed one. The row's model value is the median of those
/// total spins: the median of a magnitude over a population is not the magnitude of the median ball (the
/// bin's balls hit within 15° of centre field spin 1,000–1,400 rpm less at 5–20° of launch than the others).
/// A row passes inside the radar's interquartile range and within 12 % of its median.
fn radar_spin_rows(
    lab: &Lab,
    bins: &[radar::RadarBin],
    pitch: Option<&trackman::PitchMedians>,
) -> Result<Vec<RowResult>, ValidateError> {
    use rayon::prelude::*;
    let Some(pitch) = pitch else { return Ok(Vec::new()) };
    let scans: Vec<_> = bins
        .par_iter()
        .map(|b| lab.spatial_spray_scan(pitch, b.attack_median_deg, b.tilt_median_deg, b.launch_deg, b.exit_median_mph))
        .collect::<Result<_, ValidateError>>()?;
    Ok(bins
        .iter()
        .zip(scans)
        .map(|(b, scan)| {
            let reference = b.spin_median_rpm;
            let low = b.spin_q1_rpm.max((1.0 - RADAR_MEDIAN_TOLERANCE) * reference);
            let high = b.spin_q3_rpm.min((1.0 + RADAR_MEDIAN_TOLERANCE) * reference);
            let (model, detail) = match &scan {
                Some(points) => radar_model(points, b),
                None => (None, format!("no swing of 0.3–1.5× the average launches at {}° with {:.1} mph", b.launch_deg, b.exit_median_mph)),
            };
            RowResult {
                id: format!("radar-spin/{}deg", b.launch_deg),
                quantity: format!("total batted-ball spin at {}° launch, MLB games, radar", b.launch_deg),
                unit: "rpm".into(),
                conditions: format!(
                    "model: R161 in 3-D, attack {:.2}° and bat tilt {:.2}° (Statcast's medians for balls launched within \
                     ±5°), swing speed matched to {:.1} mph, pitch {:.1} mph descending {:.1}° with {:.0} rpm backspin, \
                     swing direction set per spray percentile; measured: {} MLB balls in play at 80–88 mph launched \
                     within ±2.5°",
                    b.attack_median_deg,
                    b.tilt_median_deg,
                    b.exit_median_mph,
                    pitch.zone_speed_mph,
                    -pitch.vert_appr_angle_deg,
                    pitch.spin_rpm,
                    b.count
                ),
                rule: Rule::Range,
                low: Some(low),
                high: Some(high),
                reference: Some(reference),
                model,
                ratio: ratio(model, Some(reference)),
                verdict: judge(Rule::Range, model, Some(low), Some(high)),
                model_detail: detail,
                tolerance: format!(
                    "inside the radar's interquartile range ({:.0}–{:.0}) and within 12 % of its median",
                    b.spin_q1_rpm, b.spin_q3_rpm
                ),
                source: "TrackMan radar, every MLB ball in play of 1–9 April 2018 (danhogan/batted-ball @e5ffdc8; \
                         validation/mlb2018_radar_spin.csv, derived by scripts/radar_tables.py)"
                    .into(),
                read_from: "data".into(),
                note: None,
            }
        })
        .collect())
}

/// The model's median total spin over the bin's sprays and batter sides, and how it was reached.
fn radar_model(points: &[cases::SpatialGamePoint], b: &radar::RadarBin) -> (Option<f64>, String) {
    let right = b.right_handed_share;
    let share = 1.0 / b.spray_percentiles_deg.len() as f64;
    let mut values = Vec::new();
    let mut missing = 0;
    for &spray in &b.spray_percentiles_deg {
        // A left-handed batter's ball at `spray` is the mirror image of a right-handed one at −spray.
        for (at, weight) in [(spray, right), (-spray, 1.0 - right)] {
            match cases::SpatialGamePoint::at_spray(points, at) {
                Some(p) => values.push((p.total_spin_rpm, weight * share)),
                None => missing += 1,
            }
        }
    }
    let median = radar::weighted_median(&values);
    let centre = cases::SpatialGamePoint::at_spray(points, 0.0);
    let mut detail = format!("median over {} spray/side cases (right-handed share {:.3})", values.len(), right);
    if missing > 0 {
        detail.push_str(&format!(", {missing} sprays beyond the swing directions scanned"));
    }
    if let Some(c) = centre {
        detail.push_str(&format!(
            "; toward centre field: {:.0} rpm (backspin {:.0}, sidespin {:.0}), swing {:.1}° off centre, {:.3}× the average swing",
            c.total_spin_rpm, c.backspin_rpm, c.sidespin_rpm, c.direction_deg, c.scale
        ));
    }
    (median, detail)
}

/// Where the summer-collegiate TrackMan files come from, for the `trackman-backspin/…` and `trackman-sidespin/…`
/// rows.
const HIT_SPIN_SOURCE: &str = "TrackMan, summer collegiate (Pacific Empire League, June and July 2025), files marked \
                               unverified by the system (carson3m/TrackmanAnalyticsProgram @cd0579a; \
                               validation/trackman_hit_spin.csv, derived by scripts/trackman_hit_spin.py)";

/// The swing the model takes for a bin of launch angles: Statcast's median attack angle and swing-path tilt of
/// the radar table's bin nearest `launch` deg.
fn swing_path_near(radar: &[radar::RadarBin], launch: f64) -> Option<(f64, f64)> {
    radar
        .iter()
        .min_by(|a, b| (a.launch_deg - launch).abs().total_cmp(&(b.launch_deg - launch).abs()))
        .map(|b| (b.attack_median_deg, b.tilt_median_deg))
}

/// The model's (backspin, sidespin) in rpm for each of the bin's balls: the ball's spray angle hit by its
/// batter's side (a left-handed batter's ball at `spray` is the mirror image of a right-handed one at −spray:
/// same backspin, opposite sidespin); `None` for a ball beyond the swing directions scanned.
pub fn hit_spin_model(points: &[cases::SpatialGamePoint], bin: &hit_spin::HitSpinBin) -> Vec<Option<(f64, f64)>> {
    bin.balls
        .iter()
        .map(|ball| {
            let (at, side_sign) = if ball.left_handed { (-ball.spray_deg, -1.0) } else { (ball.spray_deg, 1.0) };
            cases::SpatialGamePoint::at_spray(points, at).map(|p| (p.backspin_rpm, side_sign * p.sidespin_rpm))
        })
        .collect()
}

/// The model's spray scan for a bin of the collegiate TrackMan balls: the R161 swung in three dimensions at
/// Statcast's median attack angle and tilt for the bin's median launch angle, at the speed that launches a
/// ball there toward centre field at the bin's median exit speed, against the TrackMan rows' median pitch;
/// `None` when no swing reaches it.
pub fn hit_spin_scan(
    lab: &Lab,
    bin: &hit_spin::HitSpinBin,
    radar: &[radar::RadarBin],
    pitch: &trackman::PitchMedians,
) -> Result<Option<Vec<cases::SpatialGamePoint>>, ValidateError> {
    let (Some((attack, tilt)), Some(exit)) = (swing_path_near(radar, bin.launch_median_deg), bin.exit_median_mph)
    else {
        return Ok(None);
    };
    lab.spatial_spray_scan(pitch, attack, tilt, bin.launch_median_deg, exit)
}

/// The `trackman-backspin/…` and `trackman-sidespin/…` rows: per launch-angle bin of the summer-collegiate
/// TrackMan balls ([`hit_spin::LAUNCH_BINS`]), the median of the model's backspin (sidespin) over the bin's
/// balls — each ball's spray angle hit by its batter's side, by the swing of [`hit_spin_scan`] — against the
/// measured median; a row passes inside the measured interquartile range.
fn hit_spin_rows(
    lab: &Lab,
    bins: &[hit_spin::HitSpinBin],
    radar: &[radar::RadarBin],
    pitch: Option<&trackman::PitchMedians>,
) -> Result<Vec<RowResult>, ValidateError> {
    use rayon::prelude::*;
    let Some(pitch) = pitch else { return Ok(Vec::new()) };
    if radar.is_empty() {
        return Ok(Vec::new());
    }
    let scans: Vec<_> =
        bins.par_iter().map(|b| hit_spin_scan(lab, b, radar, pitch)).collect::<Result<_, ValidateError>>()?;
    let mut rows = Vec::new();
    for (b, scan) in bins.iter().zip(scans) {
        let (attack, tilt) = swing_path_near(radar, b.launch_median_deg).unwrap_or((f64::NAN, f64::NAN));
        let model = scan.as_deref().map(|points| hit_spin_model(points, b));
        for (kind, measured, pick) in [
            ("backspin", b.backspin, (|p: (f64, f64)| p.0) as fn((f64, f64)) -> f64),
            ("sidespin", b.sidespin, |p: (f64, f64)| p.1),
        ] {
            let (value, detail) = hit_spin_median(b, model.as_deref(), pick);
            let (low, high) = (measured.q1, measured.q3);
            rows.push(RowResult {
                id: format!("trackman-{kind}/{}", b.label()),
                quantity: format!(
                    "batted-ball {kind} at {}–{}° launch, summer-collegiate games, TrackMan",
                    b.launch_range_deg.0, b.launch_range_deg.1
                ),
                unit: "rpm".into(),
                conditions: hit_spin_conditions(b, kind, pitch, (attack, tilt)),
                rule: Rule::Range,
                low: Some(low),
                high: Some(high),
                reference: Some(measured.median),
                model: value,
                ratio: ratio(value, Some(measured.median)),
                verdict: judge(Rule::Range, value, Some(low), Some(high)),
                model_detail: detail,
                tolerance: format!(
                    "inside the measured interquartile range ({low:.0}–{high:.0}, n = {})",
                    b.balls.len()
                ),
                source: HIT_SPIN_SOURCE.into(),
                read_from: "data".into(),
                note: None,
            });
        }
    }
    Ok(rows)
}

/// The model's median of one spin component (`pick`) over a bin's balls (`model`: None when no swing
/// reaches the bin), with how it was found.
fn hit_spin_median(
    b: &hit_spin::HitSpinBin,
    model: Option<&[Option<(f64, f64)>]>,
    pick: fn((f64, f64)) -> f64,
) -> (Option<f64>, String) {
    let values: Vec<f64> = model.iter().copied().flatten().flatten().map(|&p| pick(p)).collect::<Vec<_>>();
    let missing = model.map_or(0, |m| m.iter().filter(|p| p.is_none()).count());
    let mut sorted = values.clone();
    sorted.sort_by(f64::total_cmp);
    let value = trackman::quantile(&sorted, 0.5);
    let detail = match model {
        None => format!(
            "no swing of 0.3–1.5× the average launches at {:.1}° with {:.1} mph",
            b.launch_median_deg,
            b.exit_median_mph.unwrap_or(f64::NAN)
        ),
        Some(_) => {
            let mut d = format!(
                "median over {} balls (model quartiles {:.0} / {:.0} / {:.0})",
                values.len(),
                trackman::quantile(&sorted, 0.25).unwrap_or(f64::NAN),
                value.unwrap_or(f64::NAN),
                trackman::quantile(&sorted, 0.75).unwrap_or(f64::NAN)
            );
            if missing > 0 {
                d.push_str(&format!(", {missing} balls sprayed beyond the swing directions scanned"));
            }
            d
        }
    };
    (value, detail)
}

/// The model's swing (its attack and tilt in degrees) and the measured balls of a hit-spin row.
fn hit_spin_conditions(
    b: &hit_spin::HitSpinBin,
    kind: &str,
    pitch: &trackman::PitchMedians,
    (attack, tilt): (f64, f64),
) -> String {
    let lefties = b.balls.iter().filter(|ball| ball.left_handed).count();
    format!(
        "model: R161 in 3-D, attack {attack:.2}° and bat tilt {tilt:.2}° (Statcast's MLB medians near the \
         bin's median launch {:.1}°), swing speed matched to the bin's median exit speed {:.1} mph, pitch \
         {:.1} mph descending {:.1}° with {:.0} rpm backspin, each ball's spray angle hit by its batter's \
         side; measured: n = {} tracked balls in play ({lefties} left-handed), {kind} from HitSpinRate and \
         HitSpinAxis ({})",
        b.launch_median_deg,
        b.exit_median_mph.unwrap_or(f64::NAN),
        pitch.zone_speed_mph,
        -pitch.vert_appr_angle_deg,
        pitch.spin_rpm,
        b.balls.len(),
        if kind == "backspin" { "−T cos a" } else { "T sin a, positive toward left field" },
    )
}

/// The exit-speed-against-undercut rows: per 5° bin of launch − attack angle (`statcast_exit_undercut.csv`),
/// the game ball's largest exit speed in the bin over its head-on peak, against the real balls' 99th
/// percentile over that of the bin where it is largest. The band is that ratio's 95 % confidence interval: the
/// bin's distribution-free interval of the 99th percentile over the peak bin's (low over high, high over
/// low). A ratio needs no pitch speed from the file and cancels the bat-speed spread: it measures how fast the
/// exit speed falls with undercut, the oblique model's part. The model swings at the bin's median bat speed
/// and attack angle against the season's median plate pitch for that bat speed (`statcast_q.csv`) with the
/// TrackMan pitch's descent and spin.
fn statcast_undercut_rows(
    lab: &Lab,
    tables: &statcast::Tables,
    pitch: Option<&trackman::PitchMedians>,
) -> Result<Vec<RowResult>, ValidateError> {
    let Some(pitch) = pitch else { return Ok(Vec::new()) };
    let bins = &tables.undercut;
    let Some(peak_bin) = bins.iter().max_by(|a, b| a.exit_p99_mph.total_cmp(&b.exit_p99_mph)) else {
        return Ok(Vec::new());
    };
    let curves = undercut_curves(lab, tables, pitch)?;
    Ok(bins.iter().zip(curves).map(|(b, curve)| undercut_row(lab, b, peak_bin, curve.as_ref(), pitch)).collect())
}

/// A bin's model curve: (launch − attack deg, exit mph) along the undercut, the point's distance from the end
/// (m) and the plate pitch speed (mph).
type UndercutCurve = (Vec<(f64, f64)>, f64, f64);

/// Per undercut bin its model curve; `None` without a pitch speed for the bin's bat speed.
fn undercut_curves(
    lab: &Lab,
    tables: &statcast::Tables,
    pitch: &trackman::PitchMedians,
) -> Result<Vec<Option<UndercutCurve>>, ValidateError> {
    use rayon::prelude::*;
    let plate_pitch = |bat_mph: f64| {
        tables.q_bins("bat", "all").find(|b| (b.low..b.high).contains(&bat_mph)).map(|b| b.median_plate_pitch_mph)
    };
    tables
        .undercut
        .par_iter()
        .map(|b| {
            let Some(plate) = plate_pitch(b.median_bat_mph) else { return Ok(None) };
            let (curve, from_end) = lab.undercut_curve(
                b.median_bat_mph * MPH,
                plate * MPH,
                b.median_attack_deg,
                -pitch.vert_appr_angle_deg,
                pitch.spin_rpm,
            )?;
            Ok(Some((curve, from_end, plate)))
        })
        .collect()
}

/// The model's ratio for a bin (its largest exit speed in the bin over the head-on peak) and how it was found.
fn undercut_model(
    lab: &Lab,
    b: &statcast::UndercutBin,
    curve: Option<&UndercutCurve>,
    pitch: &trackman::PitchMedians,
) -> (Option<f64>, String) {
    match curve {
        Some((points, from_end, plate)) => {
            let peak = points.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
            let best = largest_in(points, b.low_deg, b.high_deg);
            let detail = format!(
                "R161 about the knob at {:.1} mph 6 in from the head rising {:.2}°, `{}` ball, pitch {:.1} \
                 mph descending {:.1}° with {:.0} rpm backspin, struck {:.2} in from the end; largest exit \
                 speed in the bin {} of the head-on peak {peak:.1} mph",
                b.median_bat_mph,
                b.median_attack_deg,
                lab.game_ball,
                plate,
                -pitch.vert_appr_angle_deg,
                pitch.spin_rpm,
                from_end / INCH,
                best.map(|v| format!("{v:.1} mph")).unwrap_or_else(|| "never reached".into()),
            );
            (best.map(|v| v / peak), detail)
        }
        None => (None, format!("no plate pitch speed for bats at {:.1} mph", b.median_bat_mph)),
    }
}

fn undercut_row(
    lab: &Lab,
    b: &statcast::UndercutBin,
    peak_bin: &statcast::UndercutBin,
    curve: Option<&UndercutCurve>,
    pitch: &trackman::PitchMedians,
) -> RowResult {
    let reference = b.exit_p99_mph / peak_bin.exit_p99_mph;
    let low = b.exit_p99_ci_low_mph / peak_bin.exit_p99_ci_high_mph;
    let high = b.exit_p99_ci_high_mph / peak_bin.exit_p99_ci_low_mph;
    let (model, detail) = undercut_model(lab, b, curve, pitch);
    RowResult {
        id: format!("statcast-undercut/{}-{}", b.low_deg, b.high_deg),
        quantity: format!(
            "largest exit speed over the head-on peak, launch − attack angle {}–{}°",
            b.low_deg, b.high_deg
        ),
        unit: "1".into(),
        conditions: format!(
            "{} MLB balls in play with measured attack angle (bat 55–85 mph), launch − attack in [{}, {})°: \
             99th percentile of the exit speed {:.2} mph (95 % interval {:.2}–{:.2}), over the {}–{}° bin's \
             {:.2} ({:.2}–{:.2})",
            b.count,
            b.low_deg,
            b.high_deg,
            b.exit_p99_mph,
            b.exit_p99_ci_low_mph,
            b.exit_p99_ci_high_mph,
            peak_bin.low_deg,
            peak_bin.high_deg,
            peak_bin.exit_p99_mph,
            peak_bin.exit_p99_ci_low_mph,
            peak_bin.exit_p99_ci_high_mph
        ),
        rule: Rule::Range,
        low: Some(low),
        high: Some(high),
        reference: Some(reference),
        model,
        ratio: ratio(model, Some(reference)),
        verdict: judge(Rule::Range, model, Some(low), Some(high)),
        model_detail: detail,
        tolerance: "inside the 95 % confidence interval of the real ratio (the two bins' distribution-free \
                    intervals of their 99th percentiles; docs/statcast.md)"
            .into(),
        source: "Baseball Savant bat tracking with attack angle (validation/statcast_exit_undercut.csv, \
                 derived by scripts/statcast_tables.py)"
            .into(),
        read_from: "data".into(),
        note: None,
    }
}

/// Runs every row with collisions under `options`, the oblique rows with the tangential contact `contact`.
pub fn evaluate(
    inputs: &Inputs,
    options: CollisionOptions,
    contact: TangentialContact,
) -> Result<(Report, Lab), ValidateError> {
    let mut lab = Lab::new(options, &inputs.measurements.game_ball);
    lab.contact = contact;
    let mut rows = Vec::new();
    let mut bins = Vec::new();
    for row in &inputs.measurements.row {
        rows.push(measurement_row(&lab, inputs, row, &mut bins)?);
    }
    for (i, c) in inputs.ball_cor.iter().enumerate() {
        rows.push(ball_cor_row(&lab, i, c)?);
    }
    rows.extend(statcast_q_rows(&lab, &inputs.statcast)?);
    let pitch = trackman::pitch_medians(&inputs.trackman);
    rows.extend(statcast_undercut_rows(&lab, &inputs.statcast, pitch.as_ref())?);
    rows.extend(radar_spin_rows(&lab, &inputs.radar, pitch.as_ref())?);
    rows.extend(hit_spin_rows(&lab, &hit_spin::bins(&inputs.hit_spin), &inputs.radar, pitch.as_ref())?);
    let count = |v: Verdict| rows.iter().filter(|r| r.verdict == v).count();
    let report = Report {
        pass: count(Verdict::Pass),
        fail: count(Verdict::Fail),
        not_applicable: count(Verdict::NotApplicable),
        rows,
        trackman_bins: bins,
        trackman_pitch: pitch,
        not_found: inputs.measurements.not_found.clone(),
        files: inputs.files.clone(),
        contact: lab.contact,
    };
    Ok((report, lab))
}

/// A row of `measurements.toml` run and judged; a TrackMan-IQR row's bin is added to `bins`.
fn measurement_row(
    lab: &Lab,
    inputs: &Inputs,
    row: &Measurement,
    bins: &mut Vec<trackman::SpinBin>,
) -> Result<RowResult, ValidateError> {
    let case = run_case(lab, inputs, row)?;
    let (low, high, reference) = if row.rule == Rule::TrackmanIqr {
        let b = trackman::bin(&inputs.trackman, param(row, "launch_deg")?, param(row, "bin_half_width_deg")?);
        let bounds = if b.count >= 2 { (b.q1_rpm, b.q3_rpm) } else { (None, None) };
        let r = (bounds.0, bounds.1, b.median_rpm);
        bins.push(b);
        r
    } else {
        stated_bounds(row)
    };
    let mut detail = case.detail;
    if row.rule == Rule::TrackmanIqr {
        if let Some(b) = bins.last() {
            detail.push_str(&format!("; {} balls in the bin", b.count));
        }
    }
    Ok(RowResult {
        id: row.id.clone(),
        quantity: row.quantity.clone(),
        unit: row.unit.clone(),
        conditions: row.conditions.clone(),
        rule: row.rule,
        low,
        high,
        reference,
        model: case.value,
        ratio: ratio(case.value, reference),
        verdict: judge(row.rule, case.value, low, high),
        model_detail: detail,
        tolerance: row.tolerance.clone(),
        source: row.source.clone(),
        read_from: row.read_from.clone(),
        note: row.note.clone(),
    })
}

/// (low, high, reference) of a row from its stated value, range or uncertainty.
fn stated_bounds(row: &Measurement) -> (Option<f64>, Option<f64>, Option<f64>) {
    let reference = row.value.or(match (row.low, row.high) {
        (Some(lo), Some(hi)) => Some(0.5 * (lo + hi)),
        (Some(lo), None) => Some(lo),
        (None, Some(hi)) => Some(hi),
        (None, None) => None,
    });
    match row.rule {
        Rule::Within => {
            let u = row.uncertainty;
            (row.value.zip(u).map(|(v, u)| v - u), row.value.zip(u).map(|(v, u)| v + u), reference)
        }
        _ => (row.low, row.high, reference),
    }
}

/// The `i`th row of `ball_cor.toml` run and judged.
fn ball_cor_row(lab: &Lab, i: usize, c: &BallCorRow) -> Result<RowResult, ValidateError> {
    let id = format!("ball-cor/{}", c.id.clone().unwrap_or_else(|| (i + 1).to_string()));
    let speed = speed_in_m_s(c).map_err(|message| ValidateError::Row { id: id.clone(), message })?;
    let ball = c.ball.clone().unwrap_or_else(|| lab.game_ball.clone());
    let case = lab.ball_wall_cor(&ball, speed)?;
    let (rule, low, high, tolerance) = match (c.low, c.high, c.uncertainty) {
        (Some(lo), Some(hi), _) => (Rule::Range, Some(lo), Some(hi), format!("inside the stated range {lo}–{hi}")),
        (_, _, Some(u)) => {
            (Rule::Within, Some(c.value - u), Some(c.value + u), format!("value ± {u} (the stated uncertainty)"))
        }
        _ => (Rule::Within, None, None, "no range or uncertainty given: not judged".to_string()),
    };
    Ok(RowResult {
        id,
        quantity: c.quantity.clone().unwrap_or_else(|| "ball COR against a rigid surface".into()),
        unit: "1".into(),
        conditions: format!("`{ball}` ball at {speed:.2} m/s ({:.1} mph) on a rigid wall", speed / MPH),
        rule,
        low,
        high,
        reference: Some(c.value),
        model: case.value,
        ratio: ratio(case.value, Some(c.value)),
        verdict: judge(rule, case.value, low, high),
        model_detail: case.detail,
        tolerance,
        source: c.source.clone().unwrap_or_default(),
        read_from: c.read_from.clone().unwrap_or_default(),
        note: Some("from validation/ball_cor.toml".into()),
    })
}

/// The report as an aligned text table with a summary and the TrackMan bins.
pub fn render(report: &Report) -> String {
    use crate::report::table::{num, Table};
    let fmt = |v: Option<f64>| v.map(|v| num(v, 4)).unwrap_or_else(|| "—".into());
    let mut t = Table::new(["id", "unit", "model", "measured", "ratio", "verdict"]);
    for r in &report.rows {
        let bound = match r.rule {
            Rule::AtMost => format!("≤ {}", fmt(r.high)),
            Rule::AtLeast => format!("≥ {}", fmt(r.low)),
            Rule::TrackmanIqr => format!("IQR {}–{}", fmt(r.low), fmt(r.high)),
            _ if r.low.is_none() && r.high.is_none() => "—".to_string(),
            _ => format!("{}–{}", fmt(r.low), fmt(r.high)),
        };
        // The ratio's reference shows whenever it is not the bound itself (or a range's midpoint): two rows of
        // one range but different stated values (a sample mean, a spec's centre) have different ratios.
        let implied = match (r.rule, r.low, r.high) {
            (Rule::AtMost, _, high) => high,
            (Rule::AtLeast, low, _) => low,
            (Rule::TrackmanIqr, _, _) => None,
            (_, Some(lo), Some(hi)) => Some(0.5 * (lo + hi)),
            _ => None,
        };
        let measured = match r.reference {
            Some(v) if implied != Some(v) && bound != "—" => format!("{} ({bound})", fmt(Some(v))),
            _ => bound,
        };
        t.row([r.id.clone(), r.unit.clone(), fmt(r.model), measured, fmt(r.ratio), r.verdict.label().to_string()]);
    }
    let mut out = t.render();
    out.push_str(
        "ratio = model / the measured value: the number before the parentheses, else the range's midpoint or bound\n",
    );
    out.push_str(&format!(
        "\n{} rows: {} PASS, {} FAIL, {} N/A\n",
        report.rows.len(),
        report.pass,
        report.fail,
        report.not_applicable
    ));
    let c = &report.contact;
    let law = match c.stiffness_ratio {
        None => format!("constant e_T = {}", num(c.tangential_cor, 3)),
        Some(eta2) => format!("compliant, η² = k_n/k_t = {}", num(eta2, 3)),
    };
    out.push_str(&format!(
        "Tangential contact of the oblique rows: {law}, μ = {}, I/(m R²) = {}\n",
        num(c.friction, 3),
        num(c.ball_inertia_ratio, 3)
    ));
    out.push_str("\nHow the model got each number:\n");
    for r in &report.rows {
        out.push_str(&format!("  {}: {}\n", r.id, r.model_detail));
    }
    if let Some(p) = &report.trackman_pitch {
        out.push_str(&format!(
            "\nTrackMan pitch (medians of {} balls in play): {} mph, approach {}°, {} rpm\n",
            p.count,
            num(p.zone_speed_mph, 4),
            num(p.vert_appr_angle_deg, 3),
            num(p.spin_rpm, 4)
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::largest_in;

    #[test]
    fn the_largest_value_in_an_interval_counts_the_crossings_at_its_edges() {
        // A tent y = 10 − |x| sampled at the odd integers: over [−2, 2) the samples ±1 give 9; over [2, 6) the
        // largest is where the segment from 1 to 3 crosses 2 (y = 8).
        let tent: Vec<(f64, f64)> =
            (-5..=5).filter(|k| k % 2 != 0).map(|k| (k as f64, 10.0 - (k as f64).abs())).collect();
        assert_eq!(largest_in(&tent, -2.0, 2.0), Some(9.0));
        assert_eq!(largest_in(&tent, 2.0, 6.0), Some(8.0));
        assert_eq!(largest_in(&tent, 7.0, 9.0), None, "the curve never gets there");
        // No sample inside [1, 1.5) of the ramp (0, 0)–(2, 4): the crossings at its edges, 2 and 3.
        assert_eq!(largest_in(&[(0.0, 0.0), (2.0, 4.0), (4.0, 0.0)], 1.0, 1.5), Some(3.0));
    }
}
