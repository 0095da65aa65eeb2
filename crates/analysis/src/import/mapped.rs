//! Any other tracker's CSV through a user-given column map (`import --map FILE`): Rapsodo's hitting export
//! and the like, whose column lists could not be confirmed from a real export or vendor document, so no
//! built-in layout is guessed for them (HitTrax has one: [`super::hittrax`]).
//!
//! The map (TOML) names, for each quantity, the export's column and its unit (the column names below are an
//! illustration, not any vendor's):
//!
//! ```toml
//! name = "my-tracker"               # recorded in the bag as the format
//! [columns]                         # quantity = column name in the export's header
//! pitch_speed = "Pitch Velocity"    # required
//! exit_speed = "Exit Velocity"      # required
//! launch_angle = "Launch Angle"
//! spin = "Spin"                     # batted-ball backspin (topspin negative); with spin_axis the total spin
//! bat_speed = "Bat Speed"           # 6 in from the head, as Statcast's and Blast's
//! attack_angle = "Attack Angle"
//! pitch_angle = "Pitch Descent"     # descent angle, positive descending
//! spray_angle = "Direction"         # positive toward right field (the first-base side)
//! spin_axis = "Spin Axis"           # TrackMan's HitSpinAxis: 180° backspin, 0° topspin, 90° hooking to left field
//! batter_side = "Bats"              # R/Right or 0 = right-handed, L/Left or 1 = left-handed
//! bat_tilt = "Bat Tilt"             # the bat's long axis below the horizontal (barrel below the hands)
//! swing_direction = "Attack Dir"    # the bat's path, positive toward right field (not pull-relative)
//! time = "Date"                     # RFC 3339, or YYYY-MM-DD HH:MM:SS[.f] read as UTC
//! batter = "Player"
//! [units]                           # mph (default for speeds), km/h, m/s, ft/s; deg (default), rad; rpm (default), rad/s
//! exit_speed = "km/h"
//! ```
//!
//! The 3-D quantities follow Swing.msg's field frame whatever the batter's side: a tracker that writes them
//! relative to the batter (Savant's `attack_direction`, positive toward the opposite field) must be
//! converted first. `bat_tilt` is the bat's own tilt, not a swing plane's slope (Savant's `swing_path_tilt`,
//! which the Statcast reader converts).
//!
//! Every row with a measured exit speed is a swing (the map has no "call" column); the rest is as for the
//! built-in formats: blank/`NA`/`NULL`/`-` is not measured, out-of-range values are refused with the line.
//! A map naming one column for two quantities is refused, naming both.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use super::table::{Row, Table};
use super::{ImportError, Skip, TrackedRow, MPH};
use sweetspot_msgs::sweetspot_msgs::msg::Swing;

/// The quantities a map may name.
pub const QUANTITIES: &[&str] = &[
    "pitch_speed",
    "exit_speed",
    "launch_angle",
    "spin",
    "bat_speed",
    "attack_angle",
    "pitch_angle",
    "spray_angle",
    "spin_axis",
    "batter_side",
    "bat_tilt",
    "swing_direction",
    "time",
    "batter",
];

/// A user's column map.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColumnMap {
    /// Name of the layout (recorded in the bag).
    pub name: String,
    /// Quantity → column.
    pub columns: BTreeMap<String, String>,
    /// Quantity → unit.
    #[serde(default)]
    pub units: BTreeMap<String, String>,
}

/// Factor from a unit to SI, for the kind of quantity ("speed", "angle", "spin").
fn factor(kind: &str, unit: &str) -> Option<f64> {
    match (kind, unit) {
        ("speed", "mph") => Some(MPH),
        ("speed", "km/h") => Some(1000.0 / 3600.0),
        ("speed", "m/s") => Some(1.0),
        ("speed", "ft/s") => Some(super::FOOT),
        ("angle", "deg") => Some(std::f64::consts::PI / 180.0),
        ("angle", "rad") => Some(1.0),
        ("spin", "rpm") => Some(2.0 * std::f64::consts::PI / 60.0),
        ("spin", "rad/s") => Some(1.0),
        _ => None,
    }
}

fn kind(quantity: &str) -> &'static str {
    match quantity {
        "pitch_speed" | "exit_speed" | "bat_speed" => "speed",
        "launch_angle" | "attack_angle" | "pitch_angle" | "spray_angle" | "spin_axis" | "bat_tilt"
        | "swing_direction" => "angle",
        "spin" => "spin",
        _ => "text",
    }
}

impl ColumnMap {
    /// Reads and checks a map file.
    pub fn load(path: &Path) -> Result<ColumnMap, ImportError> {
        // A regular file of bounded size (a FIFO or /dev/zero is refused, not read for ever).
        let text =
            sweetspot_model::files::read_text(path, "column map").map_err(|e| ImportError::Options(e.to_string()))?;
        let map: ColumnMap =
            toml::from_str(&text).map_err(|e| ImportError::Options(format!("{}: {e}", path.display())))?;
        map.check().map_err(|e| ImportError::Options(format!("{}: {e}", path.display())))?;
        Ok(map)
    }

    /// Names known quantities and units only, and the two a swing needs.
    pub fn check(&self) -> Result<(), String> {
        let echo = sweetspot_model::files::echo;
        for q in self.columns.keys().chain(self.units.keys()) {
            if !QUANTITIES.contains(&q.as_str()) {
                return Err(format!("unknown quantity '{}': expected one of {}", echo(q), QUANTITIES.join(", ")));
            }
        }
        for need in ["pitch_speed", "exit_speed"] {
            if !self.columns.contains_key(need) {
                return Err(format!("the map must name the column of {need}"));
            }
        }
        // One column read as two quantities (a pitch speed that is the exit speed) is a slip in the map.
        let mut quantity_of: BTreeMap<&str, &str> = BTreeMap::new();
        for (q, column) in &self.columns {
            if let Some(first) = quantity_of.insert(column, q) {
                return Err(format!(
                    "{first} and {q} both name the column \"{}\": each quantity needs a column of its own",
                    echo(column)
                ));
            }
        }
        for (q, unit) in &self.units {
            if kind(q) == "text" {
                return Err(format!("unit '{}' of {q}: a text column has no unit", echo(unit)));
            }
            if factor(kind(q), unit).is_none() {
                return Err(format!(
                    "unit '{}' of {q}: expected one of mph, km/h, m/s, ft/s (speeds), deg, rad (angles), rpm, rad/s (spin)",
                    echo(unit)
                ));
            }
        }
        Ok(())
    }

    /// The mapped columns this header lacks.
    pub fn missing(&self, headers: &[String]) -> Vec<String> {
        self.columns
            .values()
            .filter(|c| !headers.iter().any(|h| h == *c))
            .map(|c| sweetspot_model::files::echo(c).into_owned())
            .collect()
    }

    fn scale(&self, quantity: &str) -> f64 {
        let default = match kind(quantity) {
            "speed" => "mph",
            "angle" => "deg",
            _ => "rpm",
        };
        let unit = self.units.get(quantity).map_or(default, String::as_str);
        factor(kind(quantity), unit).unwrap_or(f64::NAN)
    }
}

/// Column indexes and scales of one file.
pub struct Columns {
    index: BTreeMap<&'static str, Option<usize>>,
    scale: BTreeMap<&'static str, f64>,
    /// Degrees per unit of the spin axis, kept in degrees as the rows carry it (1 for deg: 360 stays 360).
    spin_axis_degrees: f64,
}

impl Columns {
    /// The columns of `table`'s header under `map`.
    pub fn of(table: &Table, map: &ColumnMap) -> Columns {
        let mut index = BTreeMap::new();
        let mut scale = BTreeMap::new();
        for &q in QUANTITIES {
            index.insert(q, map.columns.get(q).and_then(|c| table.column(c)));
            scale.insert(q, map.scale(q));
        }
        let spin_axis_degrees = match map.units.get("spin_axis").map(String::as_str) {
            Some("rad") => 180.0 / std::f64::consts::PI,
            _ => 1.0,
        };
        Columns { index, scale, spin_axis_degrees }
    }

    fn col(&self, q: &str) -> Option<usize> {
        self.index.get(q).copied().flatten()
    }
}

/// The batter's side of a `batter_side` cell: Swing.msg's values 0 (right) and 1 (left), or the words
/// trackers write ([`super::batter_side`]).
fn batter_side(text: &str) -> Result<Option<u8>, Skip> {
    match text {
        "0" => Ok(Some(Swing::BATTER_RIGHT)),
        "1" => Ok(Some(Swing::BATTER_LEFT)),
        _ => super::batter_side(text, "batter_side").map_err(|skip| match skip {
            Skip::NotAChoice { column, text, .. } => {
                Skip::NotAChoice { column, text, allowed: "Right, R, 0, Left, L or 1 (blank: not measured)" }
            }
            other => other,
        }),
    }
}

/// Reads one row.
pub fn read(row: &Row<'_>, cols: &Columns) -> Result<TrackedRow, Skip> {
    let num = |q: &'static str| {
        row.number(cols.col(q))
            .map(|v| v * cols.scale.get(q).copied().unwrap_or(f64::NAN))
            .map_err(|e| Skip::NotANumber { column: q, text: e.text })
    };
    let exit_speed = num("exit_speed")?;
    let time = row.text(cols.col("time"));
    let stamp_ns = chrono::DateTime::parse_from_rfc3339(time)
        .ok()
        .and_then(|t| t.timestamp_nanos_opt())
        .or_else(|| {
            chrono::NaiveDateTime::parse_from_str(time, "%Y-%m-%d %H:%M:%S%.f")
                .ok()
                .and_then(|t| t.and_utc().timestamp_nanos_opt())
        })
        .and_then(|ns| u64::try_from(ns).ok());
    Ok(TrackedRow {
        line: row.line(),
        stamp_ns,
        contact: exit_speed.is_finite(),
        call: if exit_speed.is_finite() { "exit speed measured".into() } else { "no exit speed".into() },
        pitch_speed: num("pitch_speed")?,
        pitch_speed_column: "pitch_speed",
        pitch_angle: num("pitch_angle")?,
        pitch_spin: f64::NAN,
        bat_speed: num("bat_speed")?,
        attack_angle: num("attack_angle")?,
        exit_speed,
        launch_angle: num("launch_angle")?,
        spin: num("spin")?,
        spin_axis_deg: row
            .number(cols.col("spin_axis"))
            .map(|v| v * cols.spin_axis_degrees)
            .map_err(|e| Skip::NotANumber { column: "spin_axis", text: e.text })?,
        spray_angle: num("spray_angle")?,
        bat_tilt: num("bat_tilt")?,
        swing_direction: num("swing_direction")?,
        batter_side: batter_side(row.text(cols.col("batter_side")))?,
        swing_length: f64::NAN,
        batter: row.text(cols.col("batter")).to_string(),
        pitcher: String::new(),
        pitch_id: String::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(columns: &[(&str, &str)], units: &[(&str, &str)]) -> ColumnMap {
        let owned = |pairs: &[(&str, &str)]| pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
        ColumnMap { name: "t".into(), columns: owned(columns), units: owned(units) }
    }

    #[test]
    fn the_3d_quantities_are_angles_and_the_side_takes_no_unit() {
        let base = [("pitch_speed", "P"), ("exit_speed", "E")];
        let with = |extra: (&str, &str), units: &[(&str, &str)]| {
            let mut columns = base.to_vec();
            columns.push(extra);
            map(&columns, units).check()
        };
        for q in ["spray_angle", "spin_axis", "bat_tilt", "swing_direction"] {
            assert_eq!(with((q, "A"), &[(q, "rad")]), Ok(()), "{q}");
            assert!(with((q, "A"), &[(q, "rpm")]).unwrap_err().contains(&format!("of {q}")), "{q}");
        }
        assert_eq!(with(("batter_side", "B"), &[]), Ok(()));
        let err = with(("batter_side", "B"), &[("batter_side", "deg")]).unwrap_err();
        assert!(err.contains("text column has no unit"), "{err}");
    }

    #[test]
    fn a_side_is_swing_msgs_number_or_a_trackers_word() {
        assert_eq!(batter_side("0"), Ok(Some(Swing::BATTER_RIGHT)));
        assert_eq!(batter_side("1"), Ok(Some(Swing::BATTER_LEFT)));
        assert_eq!(batter_side("Left"), Ok(Some(Swing::BATTER_LEFT)));
        assert_eq!(batter_side(""), Ok(None));
        match batter_side("2") {
            Err(Skip::NotAChoice { column, allowed, .. }) => {
                assert_eq!((column, allowed.contains("0")), ("batter_side", true))
            }
            other => panic!("{other:?}"),
        }
    }
}
