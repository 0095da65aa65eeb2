//! TrackMan Baseball's CSV export (the "V3" layout: one row per pitch, 167 columns, CRLF lines, empty cells
//! for what was not tracked).
//!
//! The layout was learned from two real game exports (summer-collegiate games of June and July 2025, as
//! published in the public repository carson3m/TrackmanAnalyticsProgram; rows copied into
//! `tests/data/trackman_*.csv` with that attribution in `tests/data/README.md`). Units are TrackMan's:
//! mph, degrees, rpm, feet.
//!
//! | column | becomes | conversion |
//! |---|---|---|
//! | `ZoneSpeed` | `Swing.ball_speed` | mph → m/s: the pitch's speed at the plate, not `RelSpeed` (at release) |
//! | `VertApprAngle` | `Swing.pitch_angle` | −deg → rad (TrackMan's is negative for a descending pitch) |
//! | `SpinRate`, `SpinAxis` | `Swing.pitch_spin` | rpm → rad/s × (−cos SpinAxis): the backspin part |
//! | `ExitSpeed` | `measured_exit_speed` | mph → m/s |
//! | `Angle` | `measured_launch_angle` | deg → rad |
//! | `HitSpinRate` | `measured_spin` | rpm → rad/s: the total spin (its backspin part is × −cos HitSpinAxis); NaN without the axis |
//! | `HitSpinAxis` | `measured_spin_axis` | deg → rad, as it is (180° = pure backspin, 90° = curving toward left field) |
//! | `Direction` | `measured_spray_angle` | deg → rad, as it is: positive toward right field in both |
//! | `BatterSide` | `batter_side` | `Right` → BATTER_RIGHT, `Left` → BATTER_LEFT; blank = right (the planar default) |
//! | `PitchCall` | which rows are swings | `InPlay`, `FoulBall…` or any row with an `ExitSpeed` |
//! | `UTCDateTime` (else `UTCDate`+`UTCTime`, else `Date`+`Time` read as UTC) | `header.stamp` | |
//! | `Batter`, `BatterId`, `Pitcher`, `PitchUID`, `PitchNo`, `GameID` | the side table | |
//!
//! **Spin axis.** TrackMan's glossary ("Radar Measurement Glossary of Terms", trackman.zendesk.com, text):
//! Tilt is the spin axis as clock time, "12:00 is perfect back spin", "6:00 is perfect top spin". In the
//! real exports `SpinAxis` 216° comes with Tilt 1:15 and 33° with 7:00, so SpinAxis = 180° + 30°/hour of
//! tilt: 180° is pure backspin, 0° pure topspin, and the backspin part of the spin is SpinRate·(−cos SpinAxis)
//! (the spin's gyro part, which TrackMan's total includes, is not separated). `HitSpinAxis` is taken in the
//! same convention; the glossary does not define it for batted balls, so this is an assumption, and a
//! `HitSpinRate` without a `HitSpinAxis` gives no measured spin (a total alone does not say back or top).
//!
//! **Direction and HitSpinAxis agree with the model's field frame.** In the two real exports, 31 of the 33
//! balls with both a `Direction` and a `PositionAt110Z` (TrackMan's side coordinate where the ball passes
//! 110 ft, positive toward first base) have the same sign in both (the other two within 1.2° of centre), and
//! balls curve toward the line they are hit to: of the 34 fair balls with a `HitSpinRate`, 14 of 15 with
//! Direction below 0 have HitSpinAxis below 180° (a hook toward left field, as the model's spin axis 90°
//! is), 15 of 19 with Direction above 0 have it above 180°. The model's 3-D collision, whose spray angle is
//! positive toward right field (`physics::oblique3d`), gives the same: a right-handed batter's pulled ball,
//! Direction below 0, has HitSpinAxis below 180° (tests/import_spatial.rs pins it with a row of the export
//! and with the model).
//!
//! TrackMan measures no bat tilt or swing direction: those stay the planar swing's 0.
//!
//! TrackMan does not measure the bat: its speed comes from the batter model (assumed, see [`super`]).

use super::table::{Row, Table};
use super::{backspin, deg, mph, rpm, Skip, TrackedRow};

/// Columns a header must have to be read as TrackMan's.
pub const REQUIRED: &[&str] = &["PitchCall", "ZoneSpeed", "VertApprAngle", "ExitSpeed", "Angle"];

/// `PitchCall` values of a pitch the bat hit.
pub const CONTACT_CALLS: &[&str] = &["InPlay", "FoulBall", "FoulBallFieldable", "FoulBallNotFieldable", "FoulTip"];

/// Column indexes of one file.
pub struct Columns {
    call: Option<usize>,
    zone_speed: Option<usize>,
    vaa: Option<usize>,
    spin_rate: Option<usize>,
    spin_axis: Option<usize>,
    exit_speed: Option<usize>,
    angle: Option<usize>,
    hit_spin_rate: Option<usize>,
    hit_spin_axis: Option<usize>,
    direction: Option<usize>,
    batter_side: Option<usize>,
    utc_date_time: Option<usize>,
    utc_date: Option<usize>,
    utc_time: Option<usize>,
    date: Option<usize>,
    time: Option<usize>,
    batter: Option<usize>,
    batter_id: Option<usize>,
    pitcher: Option<usize>,
    pitch_uid: Option<usize>,
    pitch_no: Option<usize>,
    game_id: Option<usize>,
}

impl Columns {
    /// The columns of `table`'s header.
    pub fn of(table: &Table) -> Columns {
        let c = |name| table.column(name);
        Columns {
            call: c("PitchCall"),
            zone_speed: c("ZoneSpeed"),
            vaa: c("VertApprAngle"),
            spin_rate: c("SpinRate"),
            spin_axis: c("SpinAxis"),
            exit_speed: c("ExitSpeed"),
            angle: c("Angle"),
            hit_spin_rate: c("HitSpinRate"),
            hit_spin_axis: c("HitSpinAxis"),
            direction: c("Direction"),
            batter_side: c("BatterSide"),
            utc_date_time: c("UTCDateTime"),
            utc_date: c("UTCDate"),
            utc_time: c("UTCTime"),
            date: c("Date"),
            time: c("Time"),
            batter: c("Batter"),
            batter_id: c("BatterId"),
            pitcher: c("Pitcher"),
            pitch_uid: c("PitchUID"),
            pitch_no: c("PitchNo"),
            game_id: c("GameID"),
        }
    }
}

/// The row's time, ns since the Unix epoch (UTC), if it has one.
fn stamp(row: &Row<'_>, cols: &Columns) -> Option<u64> {
    let utc = row.text(cols.utc_date_time);
    if let Ok(t) = chrono::DateTime::parse_from_rfc3339(utc) {
        return u64::try_from(t.timestamp_nanos_opt()?).ok();
    }
    let (date, time) = match (row.text(cols.utc_date), row.text(cols.utc_time)) {
        (d, t) if !d.is_empty() && !t.is_empty() => (d, t),
        _ => (row.text(cols.date), row.text(cols.time)),
    };
    let naive = chrono::NaiveDateTime::parse_from_str(&format!("{date} {time}"), "%Y-%m-%d %H:%M:%S%.f").ok()?;
    u64::try_from(naive.and_utc().timestamp_nanos_opt()?).ok()
}

/// Reads one row.
pub fn read(row: &Row<'_>, cols: &Columns) -> Result<TrackedRow, Skip> {
    let num = |col: Option<usize>, name: &'static str| {
        row.number(col).map_err(|e| Skip::NotANumber { column: name, text: e.text })
    };
    let call = row.text(cols.call).to_string();
    let exit_speed = num(cols.exit_speed, "ExitSpeed")?;
    let contact = CONTACT_CALLS.contains(&call.as_str()) || exit_speed.is_finite();
    let spin_rate = num(cols.spin_rate, "SpinRate")?;
    let spin_axis = num(cols.spin_axis, "SpinAxis")?;
    let hit_spin_rate = num(cols.hit_spin_rate, "HitSpinRate")?;
    let hit_spin_axis = num(cols.hit_spin_axis, "HitSpinAxis")?;
    let batter = match row.text(cols.batter_id) {
        "" => row.text(cols.batter).to_string(),
        id => format!("{} ({id})", row.text(cols.batter)),
    };
    Ok(TrackedRow {
        line: row.line(),
        stamp_ns: stamp(row, cols),
        contact,
        call,
        pitch_speed: mph(num(cols.zone_speed, "ZoneSpeed")?),
        pitch_speed_column: "ZoneSpeed",
        pitch_angle: -deg(num(cols.vaa, "VertApprAngle")?),
        pitch_spin: backspin(rpm(spin_rate), spin_axis),
        bat_speed: f64::NAN,
        attack_angle: f64::NAN,
        exit_speed: mph(exit_speed),
        launch_angle: deg(num(cols.angle, "Angle")?),
        // A total spin says back or top only with its axis.
        spin: if hit_spin_axis.is_finite() { rpm(hit_spin_rate) } else { f64::NAN },
        spin_axis_deg: hit_spin_axis,
        spray_angle: deg(num(cols.direction, "Direction")?),
        bat_tilt: f64::NAN,
        swing_direction: f64::NAN,
        batter_side: super::batter_side(row.text(cols.batter_side), "BatterSide")?,
        swing_length: f64::NAN,
        batter,
        pitcher: row.text(cols.pitcher).to_string(),
        pitch_id: match row.text(cols.pitch_uid) {
            "" => format!("{}#{}", row.text(cols.game_id), row.text(cols.pitch_no)),
            uid => uid.to_string(),
        },
    })
}
