//! `sweetspot import`: real tracker exports (TrackMan, Statcast, HitTrax) into a rosbag2 bag of Swing messages
//! that `bag replay`, `calibrate` and `locate` read like a recorded session.
//!
//! One table mechanism ([`table`]) reads every format: a regular file, streamed record by record, its header
//! row mapped to columns, "not measured" cells (blank, `NA`, `NULL`, `-`, …) read as NaN. Each format
//! ([`trackman`], [`statcast`], [`hittrax`]) turns a record into a [`TrackedRow`] in SI units; [`SwingBuilder`] turns that
//! into a Swing with what the tracker did not measure filled in from the batter model and marked assumed;
//! [`import_files`] writes the bag.
//!
//! # Units
//! mph → m/s × 0.44704 (exact: 1 mph = 1609.344 m / 3600 s); ft → m × 0.3048 (exact); deg → rad × π/180;
//! rpm → rad/s × 2π/60. A spin with an axis becomes its backspin part, rate·(−cos axis), 180° = pure
//! backspin (see [`trackman`]).
//!
//! # What a tracker does not measure, and what the bag says instead
//! - **Bat speed** (TrackMan, HitTrax; Statcast rows without bat tracking): the batter model's swing for the bat
//!   ([`Batter::predict`]: `bat_cm_speed`, `bat_angular_speed`), assumed. A measured Statcast `bat_speed` v
//!   (6 in from the head) is split with the batter's pivot z_p (the instantaneous centre of its reference
//!   swing): ω = v / (L − 6 in − z_p), V = ω (z_cm − z_p) ([`ReferenceSwing::from_speed_at`]).
//! - **Impact point**: the batter's usual impact point (6 in from the barrel end for the default batter),
//!   assumed; `sweetspot locate` finds the one the measurements imply.
//! - **Undercut**: [`ImportOptions::undercut`] (default 0), assumed; NaN leaves it unmeasured for
//!   `calibrate --fit-tangential` (but the node and `bag replay` refuse a NaN undercut).
//! - **Attack angle, pitch angle, pitch spin** when a row lacks them: 0, assumed.
//!
//! Every swing's source (file, line, batter, pitcher, pitch id, the tracker's call) and the fields assumed
//! for it are in the side table `import_rows.csv` inside the bag directory (keyed by `swing_id`; a cell of
//! export text starting with `=`, `+`, `-`, `@` is written with a leading `'`, so no spreadsheet runs it as a
//! formula, see [`spreadsheet_safe`]); the bag's
//! `custom_data` names the formats, files and assumed fields (`sweetspot/import/*`).
//!
//! # Rows that are not swings
//! A row is skipped, and counted by reason, when the bat did not hit the ball (the tracker's call), when the
//! pitch speed is missing, when a cell is not a number, or when a value is out of range (a negative or
//! absurd speed, which is also what a column in other units looks like), when the record is not UTF-8
//! text, or when it is malformed (fewer cells than the header, a stray quote): those are *refused* with the
//! file and line (the line an editor shows, LF or CRLF), and reading goes
//! on with the next row. Nothing is guessed silently.

pub mod hittrax;
pub mod mapped;
pub mod statcast;
pub mod table;
pub mod trackman;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use sweetspot_bag::writer::BagWriter;
use sweetspot_bag::{BagError, RecordedQos, TopicId, TopicInfo};
use sweetspot_model::settings::ModelSettings;
use sweetspot_model::time::RosTime;
use sweetspot_msgs::builtin_interfaces::msg::Time;
use sweetspot_msgs::encode_cdr;
use sweetspot_msgs::std_msgs::msg::Header;
use sweetspot_msgs::sweetspot_msgs::msg::{BallParams, BatParams, Swing};
use sweetspot_physics::batter::{Batter, ReferenceSwing};
use sweetspot_physics::{Bat, MassProperties};

use table::Table;

/// Metres per second in one mile per hour (exact).
pub const MPH: f64 = 0.44704;
/// Metres in one foot (exact).
pub const FOOT: f64 = 0.3048;
/// Distance of Statcast's bat-speed point from the head of the bat, m (6 in).
pub const BAT_SPEED_POINT_FROM_HEAD: f64 = 6.0 * 0.0254;

/// Largest pitch speed accepted, m/s (120 mph; the fastest pitches are near 105 mph).
pub const MAX_PITCH_SPEED: f64 = 120.0 * MPH;
/// Largest exit speed accepted, m/s (150 mph; the hardest-hit balls are near 122 mph).
pub const MAX_EXIT_SPEED: f64 = 150.0 * MPH;
/// Largest bat speed accepted, m/s (120 mph; the fastest swings are near 90 mph).
pub const MAX_BAT_SPEED: f64 = 120.0 * MPH;
/// Largest |spin| accepted, rad/s (the model's pitch-spin limit, ~9,550 rpm).
pub const MAX_SPIN: f64 = 1000.0;
/// Largest |pitch angle| and |attack angle| accepted, rad (80°, the oblique model's limit).
pub const MAX_SWING_ANGLE: f64 = 80.0 * std::f64::consts::PI / 180.0;

/// Largest |spray angle| accepted, rad (90°: along the line through the plate, square to centre field).
pub const MAX_SPRAY_ANGLE: f64 = std::f64::consts::FRAC_PI_2;

/// Name of the side table inside the bag directory.
pub const ROWS_TABLE: &str = "import_rows.csv";

/// mph → m/s.
pub fn mph(v: f64) -> f64 {
    v * MPH
}

/// Degrees → radians.
pub fn deg(v: f64) -> f64 {
    v.to_radians()
}

/// rpm → rad/s.
pub fn rpm(v: f64) -> f64 {
    v * 2.0 * std::f64::consts::PI / 60.0
}

/// The backspin part of a spin `rate` (rad/s) about an axis at `axis_deg` (180° = pure backspin, 0° = pure
/// topspin): rate·(−cos axis); NaN unless both are given.
pub fn backspin(rate: f64, axis_deg: f64) -> f64 {
    if rate.is_finite() && axis_deg.is_finite() {
        -rate * axis_deg.to_radians().cos()
    } else {
        f64::NAN
    }
}

/// The batter's side a cell names: `Right`/`R` or `Left`/`L` (any case); None when not measured (blank,
/// `NA`, …); any other text is refused, naming `column`.
pub fn batter_side(text: &str, column: &'static str) -> Result<Option<u8>, Skip> {
    if table::MISSING.contains(&text) {
        return Ok(None);
    }
    match text.to_ascii_lowercase().as_str() {
        "right" | "r" => Ok(Some(Swing::BATTER_RIGHT)),
        "left" | "l" => Ok(Some(Swing::BATTER_LEFT)),
        _ => Err(Skip::NotAChoice {
            column,
            text: text.chars().take(40).collect(),
            allowed: "Right, R, Left or L (blank: not measured)",
        }),
    }
}

/// Errors of an import.
#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    /// Reading or writing a file failed (the OS error is in the message, not a `source` too, so a printed
    /// error chain says it once).
    #[error("{path}: {error}")]
    Io { path: PathBuf, error: std::io::Error },
    /// A directory, FIFO or device given as an export.
    #[error("{path}: {what}, not a regular file: refused (an export is a regular CSV file)")]
    NotRegularFile { path: PathBuf, what: String },
    /// The CSV itself is broken.
    #[error("{path}{}: {message}", line.map(|l| format!(", line {l}")).unwrap_or_default())]
    Csv { path: PathBuf, line: Option<u64>, message: String },
    /// The header matches no format (or lacks the columns of the forced one).
    #[error("{path}: {message}")]
    UnknownHeader { path: PathBuf, message: String },
    /// Writing the bag failed.
    #[error("writing the bag: {0}")]
    Bag(#[from] BagError),
    /// Nothing became a swing.
    #[error("no row became a swing ({0}); no bag written")]
    NoSwings(String),
    /// A bad option.
    #[error("{0}")]
    Options(String),
}

/// The export formats `import` reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// TrackMan Baseball's CSV ([`trackman`]).
    TrackMan,
    /// Baseball Savant's Statcast search CSV ([`statcast`]).
    Statcast,
    /// HitTrax's session CSV ([`hittrax`]).
    HitTrax,
    /// Any CSV through a user's column map ([`mapped`]; never detected).
    Mapped,
}

impl Format {
    /// Every format, in detection order.
    pub const ALL: [Format; 3] = [Format::TrackMan, Format::Statcast, Format::HitTrax];

    /// The name used on the command line and in the bag.
    pub fn name(self) -> &'static str {
        match self {
            Format::TrackMan => "trackman",
            Format::Statcast => "statcast",
            Format::HitTrax => "hittrax",
            Format::Mapped => "mapped",
        }
    }

    /// Columns a header must have.
    pub fn required(self) -> &'static [&'static str] {
        match self {
            Format::TrackMan => trackman::REQUIRED,
            Format::Statcast => statcast::REQUIRED,
            Format::HitTrax => hittrax::REQUIRED,
            Format::Mapped => &[],
        }
    }

    /// The format whose every required column `headers` has.
    pub fn detect(headers: &[String]) -> Option<Format> {
        Format::ALL.into_iter().find(|f| f.missing(headers).is_empty())
    }

    /// Required columns `headers` lacks.
    pub fn missing(self, headers: &[String]) -> Vec<&'static str> {
        self.required().iter().copied().filter(|c| !headers.iter().any(|h| h == c)).collect()
    }
}

impl std::str::FromStr for Format {
    type Err = ImportError;
    fn from_str(s: &str) -> Result<Format, ImportError> {
        Format::ALL.into_iter().find(|f| f.name() == s.to_ascii_lowercase()).ok_or_else(|| {
            ImportError::Options(format!(
                "unknown format {:?}: expected trackman, statcast or hittrax",
                sweetspot_model::files::echo(s)
            ))
        })
    }
}

/// One tracker row in SI units and the model's signs; NaN = not measured.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackedRow {
    /// Line of the file the row starts on (the header is line 1).
    pub line: u64,
    /// The row's time, ns since the Unix epoch, if it has one.
    pub stamp_ns: Option<u64>,
    /// Whether the bat hit the ball (the tracker's call, or a measured exit speed).
    pub contact: bool,
    /// The tracker's call (TrackMan `PitchCall`, Statcast `description/events`).
    pub call: String,
    /// Pitch speed at the plate, m/s.
    pub pitch_speed: f64,
    /// Column the pitch speed comes from (for messages).
    pub pitch_speed_column: &'static str,
    /// Descent angle of the pitch at the plate, rad, positive descending.
    pub pitch_angle: f64,
    /// Backspin of the pitch, rad/s.
    pub pitch_spin: f64,
    /// Bat speed 6 in from the head, m/s.
    pub bat_speed: f64,
    /// Attack angle, rad, upward positive.
    pub attack_angle: f64,
    /// Exit speed, m/s.
    pub exit_speed: f64,
    /// Launch angle, rad, upward positive.
    pub launch_angle: f64,
    /// Batted-ball spin, rad/s: the backspin without `spin_axis`, the total spin a radar reports with it.
    pub spin: f64,
    /// Spin axis of the batted ball, deg as TrackMan's HitSpinAxis (180° = pure backspin, 90° = curving
    /// toward left field).
    pub spin_axis_deg: f64,
    /// Spray angle, rad, positive toward right field (the first-base side).
    pub spray_angle: f64,
    /// Tilt of the bat's long axis below the horizontal at contact, rad (barrel below the hands positive).
    pub bat_tilt: f64,
    /// Horizontal direction of the bat's path, rad, positive toward right field (the field frame).
    pub swing_direction: f64,
    /// The batter's side (`Swing::BATTER_RIGHT` or `Swing::BATTER_LEFT`), None when the export does not say.
    pub batter_side: Option<u8>,
    /// Statcast swing length, m (side table only).
    pub swing_length: f64,
    /// Batter name / id.
    pub batter: String,
    /// Pitcher name / id.
    pub pitcher: String,
    /// The tracker's id of the pitch.
    pub pitch_id: String,
}

/// Why a row did not become a swing.
#[derive(Debug, Clone, PartialEq)]
pub enum Skip {
    /// The bat did not hit the ball.
    NoContact {
        /// The tracker's call.
        call: String,
    },
    /// A value a swing needs is not measured.
    Missing {
        /// Source column.
        column: &'static str,
    },
    /// A cell that is neither a number nor "not measured".
    NotANumber {
        /// Source column.
        column: &'static str,
        /// Its text.
        text: String,
    },
    /// A value out of range (negative, absurd, or in other units).
    Refused {
        /// Source column.
        column: &'static str,
        /// The value, SI units.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// A text cell that is none of the values the column may hold.
    NotAChoice {
        /// Source column.
        column: &'static str,
        /// Its text.
        text: String,
        /// What is allowed.
        allowed: &'static str,
    },
    /// The record is not text the reader can read (not UTF-8).
    Unreadable {
        /// What is wrong with it.
        why: String,
    },
    /// The record is malformed CSV (cut short, or a stray quote: see [`table::Row::malformed`]).
    Malformed {
        /// What is wrong with it.
        why: String,
    },
}

impl Skip {
    /// The reason rows are counted under.
    pub fn reason(&self) -> String {
        match self {
            Skip::NoContact { call } => format!("no ball hit (call {:?})", sweetspot_model::files::echo(call)),
            Skip::Missing { column } => format!("{column} not measured"),
            Skip::NotANumber { column, .. } => format!("{column} not a number (refused)"),
            Skip::NotAChoice { column, .. } => format!("{column} not recognised (refused)"),
            Skip::Refused { column, .. } => format!("{column} out of range (refused)"),
            Skip::Unreadable { .. } => "record not UTF-8 text (refused)".to_string(),
            Skip::Malformed { .. } => "record malformed (refused)".to_string(),
        }
    }

    /// Whether the row was refused as bad input (as opposed to simply not being a swing).
    pub fn is_refusal(&self) -> bool {
        matches!(
            self,
            Skip::NotANumber { .. }
                | Skip::NotAChoice { .. }
                | Skip::Refused { .. }
                | Skip::Unreadable { .. }
                | Skip::Malformed { .. }
        )
    }
}

impl std::fmt::Display for Skip {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Skip::NotANumber { column, text } => write!(f, "{column} = {text:?} is not a number"),
            Skip::NotAChoice { column, text, allowed } => write!(f, "{column} = {text:?} is not one of {allowed}"),
            Skip::Refused { column, value, allowed } => {
                // Readable at any size: 1e308 mph is `4.4704e307`, not 300 digits.
                let value = sweetspot_model::limits::number(*value);
                write!(f, "{column} gives {value} (SI units), out of range: expected {allowed}")
            }
            Skip::Unreadable { why } => write!(f, "the record's {why}"),
            Skip::Malformed { why } => write!(f, "malformed record: {why}"),
            other => f.write_str(&other.reason()),
        }
    }
}

/// What `import` does with what a tracker did not measure, and the bat and ball it writes.
#[derive(Debug, Clone)]
pub struct ImportOptions {
    /// Force a format (None = detect from each file's header).
    pub format: Option<Format>,
    /// The bat every swing is simulated with, and its BatParams (its `bat_id` is the swings' bat_id).
    pub bat: Bat,
    /// BatParams written first.
    pub bat_params: BatParams,
    /// BallParams written first (its `ball_id` is the swings' ball_id).
    pub ball_params: BallParams,
    /// The batter whose swing stands in for an unmeasured bat speed, and whose pivot splits a measured one.
    pub batter: Batter,
    /// Undercut written for every swing, m (no tracker measures it; NaN = leave unmeasured).
    pub undercut: f64,
    /// A user's column map: every file is read through it (`format` must then be None).
    pub map: Option<mapped::ColumnMap>,
    /// A pitch speed of exactly 0 is a ball on a tee (at rest, no spin) rather than "not measured": HitTrax
    /// writes 0 for both, so only the user can say which.
    pub tee: bool,
}

/// Fields filled in rather than measured, per swing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Assumed {
    /// bat_cm_speed and bat_angular_speed from the batter model.
    pub bat_speed: bool,
    /// impact_z (always: no tracker measures it).
    pub impact_z: bool,
    /// undercut (always: no tracker measures it).
    pub undercut: bool,
    /// attack_angle = 0.
    pub attack_angle: bool,
    /// pitch_angle = 0.
    pub pitch_angle: bool,
    /// pitch_spin = 0.
    pub pitch_spin: bool,
}

impl Assumed {
    /// The assumed fields' names.
    pub fn names(&self) -> Vec<&'static str> {
        [
            (self.bat_speed, "bat_speed"),
            (self.impact_z, "impact_z"),
            (self.undercut, "undercut"),
            (self.attack_angle, "attack_angle"),
            (self.pitch_angle, "pitch_angle"),
            (self.pitch_spin, "pitch_spin"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect()
    }
}

/// Turns tracker rows into Swings for one bat and batter.
#[derive(Debug, Clone)]
pub struct SwingBuilder {
    bat: MassProperties,
    bat_id: String,
    ball_id: String,
    /// The batter's swing with this bat (the assumed bat speed).
    predicted: (f64, f64),
    /// The batter's pivot, m from the knob.
    pivot_z: f64,
    impact_z: f64,
    undercut: f64,
    tee: bool,
}

impl SwingBuilder {
    /// A builder for `options`' bat, ball and batter.
    pub fn new(options: &ImportOptions) -> Result<SwingBuilder, ImportError> {
        let bat = options.bat.mass_properties();
        let prediction = options
            .batter
            .predict(&bat)
            .map_err(|e| ImportError::Options(format!("the batter cannot swing this bat: {e}")))?;
        let reference = &options.batter.reference;
        // The instantaneous centre of the reference swing: where V + ω (z − z_cm) = 0.
        let pivot_z = if reference.bat_angular_speed != 0.0 {
            reference.bat.center_of_mass - reference.bat_cm_speed / reference.bat_angular_speed
        } else {
            f64::NEG_INFINITY
        };
        if !(options.undercut.is_nan() || options.undercut.abs() < 0.2) {
            return Err(ImportError::Options(format!(
                "undercut = {} m: expected |undercut| < 0.2 m, or NaN to leave it unmeasured",
                options.undercut
            )));
        }
        Ok(SwingBuilder {
            bat,
            bat_id: options.bat_params.bat_id.clone(),
            ball_id: options.ball_params.ball_id.clone(),
            predicted: (prediction.bat_cm_speed, prediction.bat_angular_speed),
            pivot_z,
            impact_z: prediction.impact_z,
            undercut: options.undercut,
            tee: options.tee,
        })
    }

    /// The impact point every swing is given (the batter's usual one), m from the knob.
    pub fn impact_z(&self) -> f64 {
        self.impact_z
    }

    /// `bat_cm_speed` and `bat_angular_speed` (m/s, rad/s) of a swing whose speed 6 in from the head is
    /// `bat_speed` (m/s), turning about the batter's pivot.
    pub fn split_bat_speed(&self, bat_speed: f64) -> Result<(f64, f64), String> {
        let at = self.bat.length - BAT_SPEED_POINT_FROM_HEAD;
        let pivot = if self.pivot_z.is_finite() { self.pivot_z } else { 0.0 };
        ReferenceSwing::from_speed_at(self.bat, bat_speed, at, pivot)
            .map(|s| (s.bat_cm_speed, s.bat_angular_speed))
            .map_err(|e| e.to_string())
    }

    /// The Swing of one row (swing_id `id`, stamp `stamp`), with the fields assumed for it.
    pub fn swing(&self, row: &TrackedRow, id: u64, stamp: Time) -> Result<(Swing, Assumed), Skip> {
        if !row.contact {
            return Err(Skip::NoContact { call: row.call.clone() });
        }
        // A pitch speed of 0 is no pitch: a ball on a tee (with `tee`), else a speed nobody entered.
        let on_tee = row.pitch_speed == 0.0;
        if row.pitch_speed.is_nan() || (on_tee && !self.tee) {
            return Err(Skip::Missing { column: row.pitch_speed_column });
        }
        check_measured_ranges(row, on_tee)?;
        let mut assumed = Assumed { impact_z: true, undercut: !self.undercut.is_nan(), ..Assumed::default() };
        let (bat_cm_speed, bat_angular_speed) = self.bat_motion(row.bat_speed, &mut assumed)?;
        let attack_angle = or_assumed_zero(row.attack_angle, &mut assumed.attack_angle);
        // No tilt or direction measured: the planar swing (level bat toward centre field), as Swing.msg's default.
        let bat_tilt = if row.bat_tilt.is_nan() { 0.0 } else { row.bat_tilt };
        let swing_direction = if row.swing_direction.is_nan() { 0.0 } else { row.swing_direction };
        refuse_out_of_range(
            "bat_tilt",
            bat_tilt,
            bat_tilt.abs() + attack_angle.abs() < std::f64::consts::FRAC_PI_2 - 1e-6,
            "|bat_tilt| + |attack_angle| < 90° (a bat across its path cannot tilt further)",
        )?;
        // A ball at rest has no approach angle and no spin: known, not assumed.
        let pitch_angle = if on_tee { 0.0 } else { or_assumed_zero(row.pitch_angle, &mut assumed.pitch_angle) };
        let pitch_spin = if on_tee { 0.0 } else { or_assumed_zero(row.pitch_spin, &mut assumed.pitch_spin) };
        let swing = Swing {
            header: Header { stamp, frame_id: String::new() },
            swing_id: id,
            bat_id: self.bat_id.clone(),
            ball_id: self.ball_id.clone(),
            ball_speed: row.pitch_speed,
            bat_cm_speed,
            bat_angular_speed,
            impact_z: self.impact_z,
            measured_exit_speed: row.exit_speed,
            undercut: self.undercut,
            attack_angle,
            pitch_angle,
            pitch_spin,
            measured_launch_angle: row.launch_angle,
            measured_spin: row.spin,
            bat_tilt,
            swing_direction,
            batter_side: row.batter_side.unwrap_or(Swing::BATTER_RIGHT),
            measured_spray_angle: row.spray_angle,
            // 360° is 0°: the field holds [0, 2π).
            measured_spin_axis: row.spin_axis_deg.rem_euclid(360.0).to_radians(),
        };
        Ok((swing, assumed))
    }

    /// `bat_cm_speed` and `bat_angular_speed` of a swing with the measured `bat_speed` (6 in from the head),
    /// or the batter's predicted swing (assumed) when it is not measured.
    fn bat_motion(&self, bat_speed: f64, assumed: &mut Assumed) -> Result<(f64, f64), Skip> {
        if bat_speed.is_nan() {
            assumed.bat_speed = true;
            return Ok(self.predicted);
        }
        self.split_bat_speed(bat_speed).map_err(|_| Skip::Refused {
            column: "bat_speed",
            value: bat_speed,
            allowed: "a bat speed the batter's pivot can split (pivot on the knob side of the 6-in point)",
        })
    }
}

/// A measured `value` of `column` that is not `ok` is refused; an unmeasured one (NaN) passes.
fn refuse_out_of_range(column: &'static str, value: f64, ok: bool, allowed: &'static str) -> Result<(), Skip> {
    if value.is_nan() || ok {
        Ok(())
    } else {
        Err(Skip::Refused { column, value, allowed })
    }
}

/// Every measured value of `row` within what a swing can have (the pitch speed 0 only `on_tee`).
fn check_measured_ranges(row: &TrackedRow, on_tee: bool) -> Result<(), Skip> {
    let range = refuse_out_of_range;
    let v = row.pitch_speed;
    range(
        row.pitch_speed_column,
        v,
        on_tee || (v > 0.0 && v <= MAX_PITCH_SPEED),
        "0 < pitch speed ≤ 53.6 m/s (120 mph)",
    )?;
    let e = row.exit_speed;
    range("exit speed", e, e > 0.0 && e <= MAX_EXIT_SPEED, "0 < exit speed ≤ 67.1 m/s (150 mph)")?;
    let b = row.bat_speed;
    range("bat_speed", b, b > 0.0 && b <= MAX_BAT_SPEED, "0 < bat speed ≤ 53.6 m/s (120 mph)")?;
    let la = row.launch_angle;
    range("launch angle", la, la.abs() <= std::f64::consts::FRAC_PI_2, "|launch angle| ≤ 90°")?;
    for (column, value) in [("pitch spin", row.pitch_spin), ("batted-ball spin", row.spin)] {
        range(column, value, value.abs() <= MAX_SPIN, "|spin| ≤ 1000 rad/s (9,549 rpm)")?;
    }
    for (column, value) in [
        ("pitch angle", row.pitch_angle),
        ("attack_angle", row.attack_angle),
        ("bat_tilt", row.bat_tilt),
        ("swing_direction", row.swing_direction),
    ] {
        range(column, value, value.abs() <= MAX_SWING_ANGLE, "|angle| ≤ 80°")?;
    }
    let spray = row.spray_angle;
    range("spray angle", spray, spray.abs() <= MAX_SPRAY_ANGLE, "|spray angle| ≤ 90°")?;
    let axis = row.spin_axis_deg;
    range("spin axis", axis.to_radians(), (0.0..=360.0).contains(&axis), "0° ≤ spin axis ≤ 360°")?;
    if axis.is_finite() {
        // With an axis the rate is a radar's total spin, never negative.
        range("batted-ball spin", row.spin, row.spin >= 0.0, "total spin ≥ 0 (with a spin axis)")?;
    }
    Ok(())
}

/// `value`, or 0 with `assumed` set when it is not measured.
fn or_assumed_zero(value: f64, assumed: &mut bool) -> f64 {
    if value.is_nan() {
        *assumed = true;
        0.0
    } else {
        value
    }
}

/// One file's share of an import.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FileReport {
    /// The file.
    pub path: PathBuf,
    /// Its format.
    pub format: Format,
    /// Data rows read.
    pub rows: u64,
    /// Swings written from it.
    pub swings: u64,
}

/// What an import did.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ImportReport {
    /// The bag written.
    pub bag: PathBuf,
    /// Per file.
    pub files: Vec<FileReport>,
    /// Swings written.
    pub swings: u64,
    /// Rows skipped, by reason.
    pub skipped: BTreeMap<String, u64>,
    /// The first refused rows (file, line and why), at most [`MAX_REFUSALS_LISTED`].
    pub refused: Vec<String>,
    /// Swings per assumed field.
    pub assumed: BTreeMap<String, u64>,
    /// The impact point given to every swing, m from the knob (assumed).
    pub impact_z: f64,
    /// Per batter, the measured bat speeds (6 in from the head) of every row with one, swings that missed
    /// included: (count, mean bat speed m/s, mean swing length m or NaN).
    pub batters: BTreeMap<String, BatterStats>,
}

/// A batter's measured swings in an export (Statcast bat tracking).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct BatterStats {
    /// Rows with a measured bat speed.
    pub swings: u64,
    /// Mean bat speed 6 in from the head, m/s.
    pub bat_speed: f64,
    /// Rows with a measured swing length.
    pub swing_lengths: u64,
    /// Mean swing length, m (NaN without any).
    pub swing_length: f64,
}

impl BatterStats {
    fn add(&mut self, bat_speed: f64, swing_length: f64) {
        self.swings += 1;
        self.bat_speed += (bat_speed - self.bat_speed) / self.swings as f64;
        if swing_length.is_finite() {
            if self.swing_lengths == 0 {
                self.swing_length = 0.0;
            }
            self.swing_lengths += 1;
            self.swing_length += (swing_length - self.swing_length) / self.swing_lengths as f64;
        }
    }
}

/// Refused rows listed by name in a report (all are counted).
pub const MAX_REFUSALS_LISTED: usize = 20;

/// The bag being written: created with the first swing, so a file without one leaves nothing behind.
struct Output {
    writer: BagWriter,
    swing_topic: TopicId,
    rows: csv::Writer<std::fs::File>,
    last_log_ns: u64,
}

/// Topics of an imported bag: the node's, in the root namespace (`import --pub --ns` remaps them).
pub mod topics {
    /// BatParams, once, latched.
    pub const BAT_PARAMS: &str = "/bat/params";
    /// BallParams, once, latched.
    pub const BALL_PARAMS: &str = "/ball/params";
    /// One Swing per imported row.
    pub const SWING: &str = "/swing";
}

impl Output {
    fn create(dir: &Path, options: &ImportOptions, first_ns: u64) -> Result<Output, ImportError> {
        let mut writer = BagWriter::create(dir, None, None)?;
        let latched = RecordedQos { reliable: true, transient_local: true, depth: 1 };
        let stream = RecordedQos { reliable: true, transient_local: false, depth: 1000 };
        let bat_topic = writer.add_topic(TopicInfo::of::<BatParams>(topics::BAT_PARAMS, latched))?;
        let ball_topic = writer.add_topic(TopicInfo::of::<BallParams>(topics::BALL_PARAMS, latched))?;
        let swing_topic = writer.add_topic(TopicInfo::of::<Swing>(topics::SWING, stream))?;
        let t = first_ns.saturating_sub(2_000);
        let header = Header { stamp: Time::from_unix_ns(t), frame_id: String::new() };
        let bat = BatParams { header: header.clone(), ..options.bat_params.clone() };
        let ball = BallParams { header, ..options.ball_params.clone() };
        let encode = |e: sweetspot_msgs::MsgError| ImportError::Bag(BagError::Format(e.to_string()));
        writer.write(bat_topic, &encode_cdr(&bat).map_err(encode)?, t, t)?;
        writer.write(ball_topic, &encode_cdr(&ball).map_err(encode)?, t + 1_000, t + 1_000)?;
        let path = dir.join(ROWS_TABLE);
        let file = std::fs::File::create(&path).map_err(|error| ImportError::Io { path: path.clone(), error })?;
        let mut rows = csv::Writer::from_writer(file);
        rows.write_record([
            "swing_id",
            "file",
            "line",
            "format",
            "batter",
            "pitcher",
            "pitch_id",
            "call",
            "swing_length_m",
            "assumed",
        ])
        .map_err(|e| ImportError::Csv { path: path.clone(), line: None, message: e.to_string() })?;
        Ok(Output { writer, swing_topic, rows, last_log_ns: t + 1_000 })
    }
}

/// One file's column indexes, in its format.
enum FormatColumns {
    TrackMan(trackman::Columns),
    Statcast(statcast::Columns),
    HitTrax(hittrax::Columns),
    Mapped(mapped::Columns),
}

impl FormatColumns {
    fn of(table: &Table, format: Format, map: Option<&mapped::ColumnMap>) -> Result<FormatColumns, ImportError> {
        Ok(match (format, map) {
            (Format::TrackMan, _) => FormatColumns::TrackMan(trackman::Columns::of(table)),
            (Format::Statcast, _) => FormatColumns::Statcast(statcast::Columns::of(table)),
            (Format::HitTrax, _) => FormatColumns::HitTrax(hittrax::Columns::of(table)),
            (Format::Mapped, Some(map)) => FormatColumns::Mapped(mapped::Columns::of(table, map)),
            (Format::Mapped, None) => {
                return Err(ImportError::Options("the mapped format needs a column map (--map)".into()))
            }
        })
    }

    /// The table's current row as the tracker's values, or why it is not one.
    fn read(&self, row: &table::Row<'_>) -> Result<TrackedRow, Skip> {
        if let Some(why) = row.unreadable() {
            return Err(Skip::Unreadable { why: why.to_string() });
        }
        if let Some(why) = row.malformed() {
            return Err(Skip::Malformed { why: why.to_string() });
        }
        match self {
            FormatColumns::TrackMan(cols) => trackman::read(row, cols),
            FormatColumns::Statcast(cols) => statcast::read(row, cols),
            FormatColumns::HitTrax(cols) => hittrax::read(row, cols),
            FormatColumns::Mapped(cols) => mapped::read(row, cols),
        }
    }
}

/// The format `table` (read from `path`) is read in: the column map's, the forced one, or the one its header
/// row names, each checked against the header before anything is read.
fn table_format(table: &Table, path: &Path, options: &ImportOptions) -> Result<Format, ImportError> {
    if let Some(map) = &options.map {
        if options.format.is_some() {
            return Err(ImportError::Options("a column map and a forced format exclude each other".into()));
        }
        let missing = map.missing(table.headers());
        if !missing.is_empty() {
            return Err(ImportError::UnknownHeader {
                path: path.to_path_buf(),
                message: format!("the header lacks the mapped columns {}", missing.join(", ")),
            });
        }
        return Ok(Format::Mapped);
    }
    match options.format {
        Some(format) => {
            let missing = format.missing(table.headers());
            if !missing.is_empty() {
                return Err(ImportError::UnknownHeader {
                    path: path.to_path_buf(),
                    message: format!("not a {} export: its header lacks {}", format.name(), missing.join(", ")),
                });
            }
            Ok(format)
        }
        None => Format::detect(table.headers()).ok_or_else(|| ImportError::UnknownHeader {
            path: path.to_path_buf(),
            message: format!(
                "the header row matches no known export: {} (--format to force one, which names what is missing)",
                Format::ALL
                    .iter()
                    .map(|f| format!("{} needs {}", f.name(), f.required().join(", ")))
                    .collect::<Vec<_>>()
                    .join("; ")
            ),
        }),
    }
}

/// The model settings an imported bag names in its `custom_data` (the node's defaults), as a reader of the
/// bag gets them back.
pub fn bag_settings() -> ModelSettings {
    ModelSettings::from_custom_data(&bag_custom_data())
}

fn bag_custom_data() -> BTreeMap<String, String> {
    ModelSettings::default().custom_data().into_iter().map(|(k, v)| (k.to_string(), v)).collect()
}

/// The stamps an import gives its swings: the row's own time, else a millisecond after the previous swing's
/// (the first at the import's start).
struct Stamps {
    start_ns: u64,
    last: Option<u64>,
}

impl Stamps {
    fn new() -> Stamps {
        Stamps { start_ns: sweetspot_model::time::now_ns(), last: None }
    }

    fn of(&self, tracked: &TrackedRow) -> u64 {
        tracked.stamp_ns.unwrap_or_else(|| self.last.map_or(self.start_ns, |s| s + 1_000_000))
    }
}

/// One row that became a swing, in memory.
#[derive(Debug, Clone)]
pub struct ImportedSwing {
    /// The row's line in the export (the side table's `line`).
    pub line: u64,
    /// The swing, as `import` writes it to the bag.
    pub swing: Swing,
    /// The fields assumed for it.
    pub assumed: Assumed,
}

/// An export's swings built in memory, as [`import_files`] would write them to a bag.
#[derive(Debug, Clone)]
pub struct ImportedSwings {
    /// The format the export was read in.
    pub format: Format,
    /// Every swing, in row order (swing ids 1, 2, …).
    pub swings: Vec<ImportedSwing>,
    /// Rows skipped, by reason.
    pub skipped: BTreeMap<String, u64>,
}

/// The swings of one export (`table`, named `path` in messages) built in memory with `import`'s parsing,
/// refusals, numbering and stamps; no bag is written. [`ImportError::NoSwings`] when no row became one.
pub fn import_table(mut table: Table, path: &Path, options: &ImportOptions) -> Result<ImportedSwings, ImportError> {
    let builder = SwingBuilder::new(options)?;
    let format = table_format(&table, path, options)?;
    let columns = FormatColumns::of(&table, format, options.map.as_ref())?;
    let mut out = ImportedSwings { format, swings: Vec::new(), skipped: BTreeMap::new() };
    let mut stamps = Stamps::new();
    while table.next_row()? {
        let row = table.row();
        let built = columns.read(&row).and_then(|t| {
            let stamp_ns = stamps.of(&t);
            let id = out.swings.len() as u64 + 1;
            builder.swing(&t, id, Time::from_unix_ns(stamp_ns)).map(|built| (stamp_ns, t.line, built))
        });
        match built {
            Ok((stamp_ns, line, (swing, assumed))) => {
                stamps.last = Some(stamp_ns);
                out.swings.push(ImportedSwing { line, swing, assumed });
            }
            Err(skip) => *out.skipped.entry(skip.reason()).or_default() += 1,
        }
    }
    if out.swings.is_empty() {
        return Err(no_swings(&out.skipped));
    }
    Ok(out)
}

fn no_swings(skipped: &BTreeMap<String, u64>) -> ImportError {
    let reasons: Vec<String> = skipped.iter().map(|(r, n)| format!("{n} × {r}")).collect();
    ImportError::NoSwings(if reasons.is_empty() { "no data rows".into() } else { reasons.join(", ") })
}

/// Imports `files` into a new bag directory `dir` (which must not exist). Each file's format is detected
/// from its header unless forced; rows stream through one at a time. An import that fails (a bad file, a
/// full disk) removes the directory it created, so the same `dir` can be given again.
pub fn import_files(files: &[PathBuf], dir: &Path, options: &ImportOptions) -> Result<ImportReport, ImportError> {
    if dir.exists() || dir.is_symlink() {
        return Err(ImportError::Options(format!("{}: already exists (the bag directory must be new)", dir.display())));
    }
    let result = import_into(files, dir, options);
    if result.is_err() && dir.is_dir() {
        // Only this import can have made it (it did not exist): a partial bag would block the same -o.
        let _ = std::fs::remove_dir_all(dir);
    }
    result
}

/// A cell of the side table as a spreadsheet shows it, never as a formula: text from an export that starts
/// with `=`, `+`, `-`, `@`, a tab or a carriage return gets a leading `'` (OWASP's advice on CSV injection).
pub fn spreadsheet_safe(cell: &str) -> std::borrow::Cow<'_, str> {
    if cell.starts_with(['=', '+', '-', '@', '\t', '\r']) {
        std::borrow::Cow::Owned(format!("'{cell}"))
    } else {
        std::borrow::Cow::Borrowed(cell)
    }
}

/// The text a [`spreadsheet_safe`] cell stood for.
pub fn spreadsheet_unescaped(cell: &str) -> &str {
    match cell.strip_prefix('\'') {
        Some(rest) if rest.starts_with(['=', '+', '-', '@', '\t', '\r']) => rest,
        _ => cell,
    }
}

fn import_into(files: &[PathBuf], dir: &Path, options: &ImportOptions) -> Result<ImportReport, ImportError> {
    let builder = SwingBuilder::new(options)?;
    // Every file's header is checked before anything is written.
    let mut tables = Vec::new();
    for path in files {
        let table = Table::open(path)?;
        let format = table_format(&table, path, options)?;
        tables.push((path.clone(), table, format));
    }
    let report = ImportReport {
        bag: dir.to_path_buf(),
        files: Vec::new(),
        swings: 0,
        skipped: BTreeMap::new(),
        refused: Vec::new(),
        assumed: BTreeMap::new(),
        impact_z: builder.impact_z(),
        batters: BTreeMap::new(),
    };
    let mut import = Import { dir, options, builder, output: None, report, stamps: Stamps::new() };
    for (path, table, format) in tables {
        let file_report = import.file(&path, table, format)?;
        import.report.files.push(file_report);
    }
    import.finish()
}

/// An import under way: the bag (created with the first swing) and what the import has done so far.
struct Import<'a> {
    dir: &'a Path,
    options: &'a ImportOptions,
    builder: SwingBuilder,
    output: Option<Output>,
    report: ImportReport,
    stamps: Stamps,
}

impl Import<'_> {
    /// Streams the rows of one file (`path`, read in `format`) into the bag.
    fn file(&mut self, path: &Path, mut table: Table, format: Format) -> Result<FileReport, ImportError> {
        let mut file_report = FileReport { path: path.to_path_buf(), format, rows: 0, swings: 0 };
        let columns = FormatColumns::of(&table, format, self.options.map.as_ref())?;
        while table.next_row()? {
            file_report.rows += 1;
            let row = table.row();
            let tracked = columns.read(&row);
            if let Ok(t) = &tracked {
                self.count_bat_speed(t);
            }
            let stamp_ns = match &tracked {
                Ok(t) => self.stamps.of(t),
                Err(_) => 0,
            };
            let built = tracked.and_then(|t| {
                self.builder.swing(&t, self.report.swings + 1, Time::from_unix_ns(stamp_ns)).map(|(s, a)| (t, s, a))
            });
            match built {
                Ok((tracked, swing, assumed)) => {
                    self.write(path, format, &tracked, &swing, &assumed, stamp_ns)?;
                    file_report.swings += 1;
                }
                Err(skip) => self.skip(&skip, path, row.line()),
            }
        }
        Ok(file_report)
    }

    /// A measured bat speed counts toward its batter's statistics whether or not the row becomes a swing.
    fn count_bat_speed(&mut self, t: &TrackedRow) {
        if t.bat_speed.is_finite() && t.bat_speed > 0.0 && t.bat_speed <= MAX_BAT_SPEED {
            let stats = self
                .report
                .batters
                .entry(t.batter.clone())
                .or_insert(BatterStats { swing_length: f64::NAN, ..BatterStats::default() });
            stats.add(t.bat_speed, t.swing_length);
        }
    }

    /// Counts a row that became no swing by its reason; a refusal is also listed, up to [`MAX_REFUSALS_LISTED`].
    fn skip(&mut self, skip: &Skip, path: &Path, line: u64) {
        *self.report.skipped.entry(skip.reason()).or_default() += 1;
        if skip.is_refusal() && self.report.refused.len() < MAX_REFUSALS_LISTED {
            self.report.refused.push(format!("{}, line {line}: {skip}", path.display()));
        }
    }

    /// Writes the swing of a row of `path` to the bag (created with the first) and the row to the side table.
    fn write(
        &mut self,
        path: &Path,
        format: Format,
        tracked: &TrackedRow,
        swing: &Swing,
        assumed: &Assumed,
        stamp_ns: u64,
    ) -> Result<(), ImportError> {
        self.stamps.last = Some(stamp_ns);
        let out = match self.output.as_mut() {
            Some(out) => out,
            None => self.output.insert(Output::create(self.dir, self.options, stamp_ns)?),
        };
        // Log times never go backwards (files need not be in time order); header.stamp keeps the row's time.
        let log_ns = stamp_ns.max(out.last_log_ns + 1);
        out.last_log_ns = log_ns;
        let cdr = encode_cdr(swing).map_err(|e| ImportError::Bag(BagError::Format(e.to_string())))?;
        out.writer.write(out.swing_topic, &cdr, log_ns, log_ns)?;
        let names = assumed.names();
        for name in &names {
            *self.report.assumed.entry((*name).to_string()).or_default() += 1;
        }
        let length = if tracked.swing_length.is_finite() { format!("{}", tracked.swing_length) } else { String::new() };
        out.rows
            .write_record([
                swing.swing_id.to_string().as_str(),
                &spreadsheet_safe(&path.display().to_string()),
                &tracked.line.to_string(),
                format.name(),
                &spreadsheet_safe(&tracked.batter),
                &spreadsheet_safe(&tracked.pitcher),
                &spreadsheet_safe(&tracked.pitch_id),
                &spreadsheet_safe(&tracked.call),
                &length,
                &names.join(";"),
            ])
            .map_err(|e| ImportError::Csv { path: self.dir.join(ROWS_TABLE), line: None, message: e.to_string() })?;
        self.report.swings += 1;
        Ok(())
    }

    /// Closes the bag with the import's custom data; [`ImportError::NoSwings`] when no row became a swing.
    fn finish(self) -> Result<ImportReport, ImportError> {
        let Import { dir, options, output, report, .. } = self;
        let Some(mut out) = output else {
            return Err(no_swings(&report.skipped));
        };
        out.rows.flush().map_err(|error| ImportError::Io { path: dir.join(ROWS_TABLE), error })?;
        out.writer.set_custom_data(import_custom_data(&report, options));
        out.writer.finish()?;
        Ok(report)
    }
}

/// The bag's custom data: the node's settings and what was imported (formats, files, side table, column map,
/// the counts of assumed fields).
fn import_custom_data(report: &ImportReport, options: &ImportOptions) -> BTreeMap<String, String> {
    let mut custom = bag_custom_data();
    let formats: std::collections::BTreeSet<&str> = report.files.iter().map(|f| f.format.name()).collect();
    custom.insert("sweetspot/import/formats".into(), formats.into_iter().collect::<Vec<_>>().join(","));
    custom.insert(
        "sweetspot/import/files".into(),
        report.files.iter().map(|f| f.path.display().to_string()).collect::<Vec<_>>().join(","),
    );
    custom.insert("sweetspot/import/rows_table".into(), ROWS_TABLE.into());
    if let Some(map) = &options.map {
        custom.insert("sweetspot/import/map".into(), map.name.clone());
    }
    custom.insert(
        "sweetspot/import/assumed".into(),
        report.assumed.iter().map(|(k, n)| format!("{k}:{n}")).collect::<Vec<_>>().join(","),
    );
    custom
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_factors_are_the_exact_definitions() {
        // 1 mph = 1609.344 m / 3600 s; 1 ft = 0.3048 m (international yard and pound, 1959).
        assert_eq!(mph(1.0), 1609.344 / 3600.0);
        assert!((FOOT - 12.0 * 0.0254).abs() < 1e-16);
        assert!((rpm(60.0) - 2.0 * std::f64::consts::PI).abs() < 1e-15);
        assert!((deg(180.0) - std::f64::consts::PI).abs() < 1e-15);
    }

    #[test]
    fn spin_axis_180_is_backspin_and_0_topspin() {
        assert_eq!(backspin(100.0, 180.0), 100.0);
        assert_eq!(backspin(100.0, 0.0), -100.0);
        assert!(backspin(100.0, 90.0).abs() < 1e-12);
        assert!(backspin(100.0, f64::NAN).is_nan());
    }

    fn options() -> ImportOptions {
        let bat = Bat::preset("r161").unwrap();
        let mp = bat.mass_properties();
        ImportOptions {
            format: None,
            bat,
            bat_params: sweetspot_model::convert::params_of_preset("r161", "r161", Header::default()),
            ball_params: sweetspot_model::convert::params_from_ball(
                "baseball",
                &sweetspot_physics::Ball::default(),
                None,
                Header::default(),
            ),
            batter: Batter::typical(mp).unwrap(),
            undercut: 0.0,
            map: None,
            tee: false,
        }
    }

    #[test]
    fn a_measured_bat_speed_turns_about_the_batters_pivot() {
        let options = options();
        let builder = SwingBuilder::new(&options).unwrap();
        let mp = options.bat.mass_properties();
        let v = mph(75.0);
        let (cm, omega) = builder.split_bat_speed(v).unwrap();
        // Rigid rotation about the knob (the typical batter's pivot): the knob stands still and the point
        // 6 in from the head moves at the measured speed.
        let speed_at = |z: f64| cm + omega * (z - mp.center_of_mass);
        assert!(speed_at(0.0).abs() < 1e-12);
        assert!((speed_at(mp.length - 0.1524) - v).abs() < 1e-12);
    }

    #[test]
    fn rows_that_are_no_swing_are_skipped_by_reason() {
        let builder = SwingBuilder::new(&options()).unwrap();
        let row = TrackedRow {
            line: 2,
            stamp_ns: None,
            contact: true,
            call: "InPlay".into(),
            pitch_speed: 38.0,
            pitch_speed_column: "ZoneSpeed",
            pitch_angle: 0.1,
            pitch_spin: f64::NAN,
            bat_speed: f64::NAN,
            attack_angle: f64::NAN,
            exit_speed: 40.0,
            launch_angle: 0.2,
            spin: f64::NAN,
            spin_axis_deg: f64::NAN,
            spray_angle: f64::NAN,
            bat_tilt: f64::NAN,
            swing_direction: f64::NAN,
            batter_side: None,
            swing_length: f64::NAN,
            batter: String::new(),
            pitcher: String::new(),
            pitch_id: String::new(),
        };
        let t = Time::default();
        let (swing, assumed) = builder.swing(&row, 1, t.clone()).unwrap();
        assert_eq!(assumed.names(), ["bat_speed", "impact_z", "undercut", "attack_angle", "pitch_spin"]);
        assert_eq!(swing.pitch_spin, 0.0);
        assert!(swing.measured_spin.is_nan());
        let no_contact = TrackedRow { contact: false, call: "BallCalled".into(), ..row.clone() };
        assert_eq!(builder.swing(&no_contact, 1, t.clone()).unwrap_err().reason(), "no ball hit (call \"BallCalled\")");
        let negative = TrackedRow { exit_speed: -3.0, ..row.clone() };
        assert!(builder.swing(&negative, 1, t.clone()).unwrap_err().is_refusal());
        let kmh = TrackedRow { pitch_speed: mph(150.0), ..row.clone() };
        assert!(builder.swing(&kmh, 1, t.clone()).unwrap_err().is_refusal());
        let missing = TrackedRow { pitch_speed: f64::NAN, ..row.clone() };
        assert_eq!(builder.swing(&missing, 1, t.clone()).unwrap_err(), Skip::Missing { column: "ZoneSpeed" });
        // 0 is no pitch: not measured, unless the session is off a tee; a negative speed is refused either way.
        let zero = TrackedRow { pitch_speed: 0.0, ..row.clone() };
        assert_eq!(builder.swing(&zero, 1, t.clone()).unwrap_err(), Skip::Missing { column: "ZoneSpeed" });
        let tee = SwingBuilder::new(&ImportOptions { tee: true, ..options() }).unwrap();
        let (on_tee, assumed) = tee.swing(&zero, 1, t.clone()).unwrap();
        assert_eq!((on_tee.ball_speed, on_tee.pitch_angle, on_tee.pitch_spin), (0.0, 0.0, 0.0));
        assert_eq!(assumed.names(), ["bat_speed", "impact_z", "undercut", "attack_angle"], "at rest: no pitch assumed");
        let backwards = TrackedRow { pitch_speed: -1.0, ..row };
        assert!(tee.swing(&backwards, 1, t).unwrap_err().is_refusal());
    }
}
