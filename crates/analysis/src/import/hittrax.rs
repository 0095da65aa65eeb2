//! HitTrax's session CSV export (one row per swing of a batting-cage session).
//!
//! **Source of the layout.** No HitTrax documentation of the export could be found with the project's search
//! tool; the header row is taken from a real export as a public application reads it: the repository
//! ngallion/driveline-assessment-api (commit 43e54c6, January 2019, a HitTrax report service), whose test
//! `src/test/java/net/stlgamers/hittraxreporterapi/ReportServiceTest.java` holds the header row and one data
//! row verbatim, and whose `models/AtBatCsvWithHashColumn.java` names the same columns with a leading `#`
//! column (the two variants HitTrax writes). The names carry a leading space after each comma
//! (`AB,Date, Time Stamp, Pitch, …`); the table mechanism trims them. `tests/data/hittrax_session.csv` starts
//! with that header and row (attribution in `tests/data/README.md`).
//!
//! **Units.** HitTrax shows speeds in mph, angles in degrees and distances in feet; the export carries no
//! unit in its names. The same application filters `Velo` and `Pitch` at 50 (mph: a cage's slowest useful
//! batted balls) and its row (`Velo` 52.9, `LA` 21, `Dist` 116) is consistent only with mph and feet: a
//! 52.9 mph (23.65 m/s) ball launched at 21° carries v² sin 42°/g = 38.1 m = 125 ft without drag, somewhat
//! less with it, while 52.9 km/h would carry 14.7 m = 48 ft even in vacuum. So mph, deg and ft are read; a
//! column in other units is caught by the range checks. Other public parsers of HitTrax exports, which could
//! not be tied to a repository to cite, read the `#` layout by position the same way (strike zone, exit
//! velocity, launch angle and distance in columns F, H, I and J).
//!
//! | column | becomes | conversion |
//! |---|---|---|
//! | `Pitch` | `Swing.ball_speed` | mph → m/s; 0 (a tee, or no pitch speed entered: HitTrax writes 0 for both) is *not measured*, so the row is skipped and counted — unless `--tee` ([`super::ImportOptions::tee`]) says it is a ball on a tee: then ball speed, pitch angle and pitch spin are 0 |
//! | `Velo` | `measured_exit_speed` | mph → m/s; blank or 0 = the bat missed the ball (no contact) |
//! | `LA` | `measured_launch_angle` | deg → rad |
//! | `Horiz. Angle` | `measured_spray_angle` | deg → rad, as it is: positive toward right field (the first-base side) for either batter, as TrackMan's `Direction`; 0 is centre field; blank = not measured |
//! | `Batting` | `batter_side` | `R`/`Right` → BATTER_RIGHT, `L`/`Left` → BATTER_LEFT (any case); blank = right (the planar default) |
//! | `Res` | the call (side table) | e.g. `4-3`, the fielded result |
//! | `Date` | `header.stamp` | `M/D/YYYY HH:MM:SS.fff`, the cage computer's local time, read as UTC (the export names no zone) |
//! | `User`, `Opposing Player`, `#` or `AB` | batter, pitcher, pitch id (side table) | |
//!
//! **`Horiz. Angle`'s sign.** No HitTrax document defining it was found (searched: "HitTrax Horiz. Angle",
//! "HitTrax export columns", "HitTrax spray angle", "HitTrax AA attack angle"), so the sign is taken from
//! where fielders stand, in a real HitTrax data set: Driveline's OpenBiomechanics Project publishes the
//! HitTrax rows of its hitting sessions (repository drivelineresearch/openbiomechanics,
//! `baseball_hitting/data/poi/hittrax.csv`, whose README calls its columns those of a raw HitTrax export and
//! `bearing` the spray angle in degrees; `bearing` stands between `res` and `vertical_distance`, where the
//! export has `Horiz. Angle`), and each session's batter side (`hitter_side` in
//! `baseball_hitting/data/metadata.csv`). Of its 126 balls fielded on one side of the field, all 88 fielded by
//! the third baseman, shortstop or left fielder (`5-3`, `6-3`, `F5`, `F6`, `F7`) have a negative angle and all
//! 38 fielded by the first or second baseman or the right fielder (`4-3`, `U3`, `F3`, `F4`, `F9`) a positive
//! one, for right-handed (89 balls) and left-handed (37) batters alike: the angle is in the field frame,
//! positive toward right field, and is not mirrored for a left-handed batter. The real row of
//! `tests/data/hittrax_session.csv` agrees (a `4-3` at 4°). Its singles to centre at exactly 0° show that 0 is
//! a direction, not HitTrax's "nothing tracked" (the rows filled with 0 are misses, skipped by their `Velo`).
//!
//! **Not read.** HitTrax measures no spin (so no spin axis) and no bat tilt or swing direction. `Dist`,
//! `Strike Zone…`, `POI X/Y/Z` (where the ball was met relative to the plate, not where on the bat) are not
//! Swing fields. `Hand Speed`, `BV`,
//! `Trigger to Impact`, `AA` and `Impact Momentum` come from a paired bat sensor and are 0 when none is
//! paired (as in the source row); which point of the bat `BV` is measured at and how `AA` is signed could not
//! be confirmed, so they are not read: the bat speed is the batter model's, assumed (as for TrackMan). For
//! `Pitch Angle` the definition and sign could not be confirmed either; the pitch angle is assumed 0.

use super::table::{Row, Table};
use super::{deg, mph, Skip, TrackedRow};

/// Columns a header must have to be read as HitTrax's.
pub const REQUIRED: &[&str] = &["AB", "Date", "Pitch", "Velo", "LA", "Res"];

/// Column indexes of one file.
pub struct Columns {
    number: Option<usize>,
    ab: Option<usize>,
    date: Option<usize>,
    pitch: Option<usize>,
    velo: Option<usize>,
    la: Option<usize>,
    res: Option<usize>,
    kind: Option<usize>,
    horiz_angle: Option<usize>,
    batting: Option<usize>,
    user: Option<usize>,
    opposing: Option<usize>,
}

impl Columns {
    /// The columns of `table`'s header.
    pub fn of(table: &Table) -> Columns {
        let c = |name| table.column(name);
        Columns {
            number: c("#"),
            ab: c("AB"),
            date: c("Date"),
            pitch: c("Pitch"),
            velo: c("Velo"),
            la: c("LA"),
            res: c("Res"),
            kind: c("Type"),
            horiz_angle: c("Horiz. Angle"),
            batting: c("Batting"),
            user: c("User"),
            opposing: c("Opposing Player"),
        }
    }
}

/// The row's time, ns since the Unix epoch, from `M/D/YYYY HH:MM:SS[.fff]` read as UTC.
fn stamp(text: &str) -> Option<u64> {
    let naive = chrono::NaiveDateTime::parse_from_str(text, "%m/%d/%Y %H:%M:%S%.f").ok()?;
    u64::try_from(naive.and_utc().timestamp_nanos_opt()?).ok()
}

/// Reads one row.
pub fn read(row: &Row<'_>, cols: &Columns) -> Result<TrackedRow, Skip> {
    let num = |col: Option<usize>, name: &'static str| {
        row.number(col).map_err(|e| Skip::NotANumber { column: name, text: e.text })
    };
    let velo = num(cols.velo, "Velo")?;
    let pitch = num(cols.pitch, "Pitch")?;
    let res = row.text(cols.res);
    let call = match row.text(cols.kind) {
        "" => res.to_string(),
        kind => format!("{res} ({kind})"),
    };
    Ok(TrackedRow {
        line: row.line(),
        stamp_ns: stamp(row.text(cols.date)),
        // A blank or zero Velo is a swing that missed (HitTrax writes 0 where nothing was tracked).
        contact: velo.is_finite() && velo != 0.0,
        call: if call.is_empty() { "no result".into() } else { call },
        // 0 is what HitTrax writes for a tee and for a pitch speed nobody entered: kept as 0, which the
        // swing builder counts as not measured unless `--tee` says the session was off a tee.
        pitch_speed: mph(pitch),
        pitch_speed_column: "Pitch",
        pitch_angle: f64::NAN,
        pitch_spin: f64::NAN,
        bat_speed: f64::NAN,
        attack_angle: f64::NAN,
        exit_speed: mph(velo),
        launch_angle: deg(num(cols.la, "LA")?),
        spin: f64::NAN,
        spin_axis_deg: f64::NAN,
        spray_angle: deg(num(cols.horiz_angle, "Horiz. Angle")?),
        bat_tilt: f64::NAN,
        swing_direction: f64::NAN,
        batter_side: super::batter_side(row.text(cols.batting), "Batting")?,
        swing_length: f64::NAN,
        batter: row.text(cols.user).to_string(),
        pitcher: row.text(cols.opposing).to_string(),
        pitch_id: match (row.text(cols.number), row.text(cols.ab)) {
            ("", ab) => format!("AB {ab}"),
            (n, ab) => format!("#{n} AB {ab}"),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_export_date_is_month_first_with_milliseconds() {
        // 11/26/2018 16:08:24.883 (the source row's) = 1543248504 s + 883 ms after the epoch, read as UTC.
        assert_eq!(stamp("11/26/2018 16:08:24.883"), Some(1_543_248_504_883_000_000));
        assert_eq!(stamp("11/26/2018 16:08:24"), Some(1_543_248_504_000_000_000));
        assert_eq!(stamp("26/11/2018 16:08:24"), None, "day first is not HitTrax's");
        assert_eq!(stamp(""), None);
    }
}
