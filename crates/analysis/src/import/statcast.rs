//! Baseball Savant's Statcast search CSV (`statcast_search/csv?…&type=details`: one row per pitch).
//!
//! Sources for the columns (the official column documentation page, baseballsavant.mlb.com/csv-docs, could
//! not be found with the project's search tool, so what follows is from what could be read):
//! - the column names and their order: the schema of a Savant download published as the Hugging Face data
//!   set `jab13/mlb-statcast-dataset` (text: `pitch_type, game_date, release_speed, release_pos_x, …, vx0,
//!   vy0, vz0, ax, ay, az, sz_top, sz_bot, hit_distance_sc, launch_speed, launch_angle, …, at_bat_number …`);
//! - the kinematics: `vx0…az` are the pitch's velocity (ft/s) and acceleration (ft/s²) of a
//!   constant-acceleration fit "determined at y = 50 feet"; the speed at the plate is found by solving
//!   y(t) = 17/12 ft, the front of home plate (J. Edwards, "The Complete Idiot's Guide To Playing With
//!   Statcast Data", 2018, text; the same y = 50 → 17/12 ft solution in public analysis code, e.g. gist
//!   903124/62195251 and the approach-angle code quoted on gist.github.com/sbrown70, text);
//! - bat tracking (2024–): `bat_speed` (mph, "measured at the sweet spot", 6 in from the head of the bat),
//!   `swing_length` (ft), and from 2025 `attack_angle` (deg), `attack_direction`, `swing_path_tilt` (FanGraphs
//!   "Test Driving Statcast's Newest Bat Tracking Metrics", 2025, text; the 6-in point as in
//!   `physics::batter`'s docs).
//!
//! | column | becomes | conversion |
//! |---|---|---|
//! | `vx0 vy0 vz0 ax ay az` | `Swing.ball_speed`, `Swing.pitch_angle` | the speed and descent angle at the front of the plate ([`plate_crossing`]), ft/s → m/s, rad |
//! | `release_spin_rate`, `spin_axis` | `Swing.pitch_spin` | rpm → rad/s × (−cos spin_axis), 180° = backspin as TrackMan's |
//! | `bat_speed` | `bat_cm_speed`, `bat_angular_speed` | mph → m/s at 6 in from the head, split with the batter's pivot |
//! | `attack_angle` | `Swing.attack_angle` | deg → rad |
//! | `swing_path_tilt` | `Swing.bat_tilt` | the swing plane's slope τ (deg) → the bat's tilt ψ, sin ψ = √(sin²τ − sin²α) ([`bat_tilt`]) |
//! | `attack_direction` | `Swing.swing_direction` | deg → rad; + toward the opposite field in Savant, so × −1 for a left-handed batter ([`swing_direction`]) |
//! | `stand` | `Swing.batter_side` | `R` → BATTER_RIGHT, `L` → BATTER_LEFT |
//! | `hc_x`, `hc_y` | `measured_spray_angle` | atan2(hc_x − 125.42, 198.27 − hc_y), positive toward right field ([`spray_angle`]) |
//! | `launch_speed` | `measured_exit_speed` | mph → m/s |
//! | `launch_angle` | `measured_launch_angle` | deg → rad |
//! | — | `measured_spin` | NaN: the search CSV has no batted-ball spin |
//! | `description` | which rows are swings | `hit_into_play…`, `foul…`, or any row with a `launch_speed` |
//! | `game_date`, `at_bat_number`, `pitch_number` | `header.stamp` | the CSV has no time of day: the game date at 00:00 UTC + 60 s × at-bat + 1 s × pitch, an ordering, not a clock |
//! | `batter`, `pitcher`, `player_name`, `game_pk`, … | the side table | |
//!
//! **Bat tracking's angles.** Savant's glossary defines the swing path tilt as the angle of the plane the
//! bat's path follows against the ground, 0° a flat swing and 90° a golf swing (MLB average about 32°, the
//! flattest hitters near 20° and the steepest near 50°; mlb.com glossary "Swing Path (Tilt)", text), and
//! the attack direction as the horizontal angle of the bat's path at contact, positive toward the opposite
//! field and negative toward the pull side (Baseball Prospectus, "How Attack Direction Drives Offensive
//! Production", 2025, text). Savant's own column documentation could not be read; these two are what the
//! import assumes. The hit-chart coordinates are Gameday's fielding location, not the ball's initial
//! direction: their spray angle is that of where the ball was fielded (close to the launch direction for
//! all but the most curving balls).
//!
//! `release_speed` is *not* the ball speed: it is the speed at release, several mph above the speed at the
//! plate where the bat meets the ball.

use super::table::{Row, Table};
use super::{backspin, deg, mph, rpm, Skip, TrackedRow, FOOT};
use sweetspot_msgs::sweetspot_msgs::msg::Swing;

/// Columns a header must have to be read as Statcast's.
pub const REQUIRED: &[&str] =
    &["game_date", "description", "vx0", "vy0", "vz0", "ax", "ay", "az", "launch_speed", "launch_angle"];

/// y of the kinematic fit's reference, ft from the point of home plate.
pub const FIT_Y_FT: f64 = 50.0;
/// y of the front of home plate, ft (17 in).
pub const PLATE_FRONT_Y_FT: f64 = 17.0 / 12.0;

/// The pitch where it crosses the front of home plate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateCrossing {
    /// Time from y = 50 ft, s.
    pub time: f64,
    /// Velocity (x, y, z), ft/s.
    pub velocity: [f64; 3],
    /// Speed, ft/s.
    pub speed: f64,
    /// Descent angle below the horizontal in the vertical plane of travel toward the plate (y–z), rad,
    /// positive descending: atan2(−v_z, −v_y).
    pub descent_angle: f64,
}

/// The constant-acceleration trajectory of velocity `v0` (ft/s) and acceleration `a` (ft/s²) at y = 50 ft,
/// followed to y = 17/12 ft: t solves 50 + v_y0 t + ½ a_y t² = 17/12 (the root that stays finite as a_y → 0,
/// t = 2Δ / (−v_y0 + √(v_y0² − 2 a_y Δ)), Δ = 50 − 17/12), and v = v0 + a t. None when the pitch never gets
/// there (v_y0 ≥ 0, or decelerating to a stop first).
pub fn plate_crossing(v0: [f64; 3], a: [f64; 3]) -> Option<PlateCrossing> {
    let distance = FIT_Y_FT - PLATE_FRONT_Y_FT;
    let discriminant = v0[1] * v0[1] - 2.0 * a[1] * distance;
    if !(v0[1] < 0.0 && discriminant >= 0.0) {
        return None;
    }
    let time = 2.0 * distance / (-v0[1] + discriminant.sqrt());
    let velocity = [v0[0] + a[0] * time, v0[1] + a[1] * time, v0[2] + a[2] * time];
    let speed = velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
    Some(PlateCrossing { time, velocity, speed, descent_angle: (-velocity[2]).atan2(-velocity[1]) })
}

/// Column indexes of one file.
pub struct Columns {
    game_date: Option<usize>,
    description: Option<usize>,
    events: Option<usize>,
    v0: [Option<usize>; 3],
    a: [Option<usize>; 3],
    spin_rate: Option<usize>,
    spin_axis: Option<usize>,
    launch_speed: Option<usize>,
    launch_angle: Option<usize>,
    bat_speed: Option<usize>,
    swing_length: Option<usize>,
    attack_angle: Option<usize>,
    attack_direction: Option<usize>,
    swing_path_tilt: Option<usize>,
    stand: Option<usize>,
    hc_x: Option<usize>,
    hc_y: Option<usize>,
    batter: Option<usize>,
    pitcher: Option<usize>,
    player_name: Option<usize>,
    game_pk: Option<usize>,
    at_bat: Option<usize>,
    pitch_number: Option<usize>,
}

impl Columns {
    /// The columns of `table`'s header.
    pub fn of(table: &Table) -> Columns {
        let c = |name| table.column(name);
        Columns {
            game_date: c("game_date"),
            description: c("description"),
            events: c("events"),
            v0: [c("vx0"), c("vy0"), c("vz0")],
            a: [c("ax"), c("ay"), c("az")],
            spin_rate: c("release_spin_rate"),
            spin_axis: c("spin_axis"),
            launch_speed: c("launch_speed"),
            launch_angle: c("launch_angle"),
            bat_speed: c("bat_speed"),
            swing_length: c("swing_length"),
            attack_angle: c("attack_angle"),
            attack_direction: c("attack_direction"),
            swing_path_tilt: c("swing_path_tilt"),
            stand: c("stand"),
            hc_x: c("hc_x"),
            hc_y: c("hc_y"),
            batter: c("batter"),
            pitcher: c("pitcher"),
            player_name: c("player_name"),
            game_pk: c("game_pk"),
            at_bat: c("at_bat_number"),
            pitch_number: c("pitch_number"),
        }
    }
}

/// Gameday's hit-chart coordinates of home plate (`hc_x`, `hc_y`): the image's x grows toward right field
/// and its y downward, toward the plate.
pub const HIT_CHART_PLATE: (f64, f64) = (125.42, 198.27);

/// The spray angle of a ball fielded at hit-chart coordinates (`hc_x`, `hc_y`), rad, positive toward right
/// field: atan2(hc_x − 125.42, 198.27 − hc_y), the usual atan((hc_x − 125.42)/(198.27 − hc_y)) with the
/// quadrant kept (a ball behind the plate comes out beyond ±90° and is refused). NaN unless both are given.
pub fn spray_angle(hc_x: f64, hc_y: f64) -> f64 {
    (hc_x - HIT_CHART_PLATE.0).atan2(HIT_CHART_PLATE.1 - hc_y)
}

/// The tilt of the bat's long axis below the horizontal, rad, from Savant's `swing_path_tilt` τ (deg, the
/// swing plane's angle from the ground: 0° flat, 90° a golf swing) and the attack angle α (rad; NaN taken as
/// 0, as the swing builder does). The bat and its path both lie in the swing plane, so the plane's slope
/// satisfies cos²τ = cos²α − sin²ψ (the model's axis â and path p̂: cos τ = (â × p̂)·ẑ), i.e.
/// sin ψ = √(sin²τ − sin²α), ψ = τ for a level path. The barrel is below the hands (ψ ≥ 0): Savant's tilt
/// has no sign. NaN when τ is not measured; refused when τ is outside 0–90° or below |α| (a path cannot
/// climb more steeply than the plane it lies in).
pub fn bat_tilt(tilt_deg: f64, attack_angle: f64) -> Result<f64, Skip> {
    if tilt_deg.is_nan() {
        return Ok(f64::NAN);
    }
    if !(0.0..=90.0).contains(&tilt_deg) {
        return Err(Skip::Refused {
            column: "swing_path_tilt",
            value: tilt_deg.to_radians(),
            allowed: "0° ≤ swing_path_tilt ≤ 90°",
        });
    }
    let alpha = if attack_angle.is_nan() { 0.0 } else { attack_angle };
    let sin2 = tilt_deg.to_radians().sin().powi(2) - alpha.sin().powi(2);
    if sin2 < 0.0 {
        return Err(Skip::Refused {
            column: "swing_path_tilt",
            value: tilt_deg.to_radians(),
            allowed: "swing_path_tilt ≥ |attack_angle| (the bat's path lies in its swing plane)",
        });
    }
    Ok(sin2.sqrt().asin())
}

/// The bat path's horizontal direction in the field frame, rad, positive toward right field, from Savant's
/// `attack_direction` (deg, relative to the batter: positive toward the opposite field, negative toward the
/// pull side): as it is for a right-handed batter, the opposite sign for a left-handed one. NaN when not
/// measured; refused when the batter's side (`stand`) is unknown.
pub fn swing_direction(attack_direction_deg: f64, side: Option<u8>) -> Result<f64, Skip> {
    if attack_direction_deg.is_nan() {
        return Ok(f64::NAN);
    }
    match side {
        Some(Swing::BATTER_LEFT) => Ok(-attack_direction_deg.to_radians()),
        Some(_) => Ok(attack_direction_deg.to_radians()),
        None => Err(Skip::NotAChoice {
            column: "stand",
            text: String::new(),
            allowed: "R or L with an attack_direction (it is relative to the batter's side)",
        }),
    }
}

/// Whether a `description` is a pitch the bat hit.
pub fn is_contact(description: &str) -> bool {
    description.starts_with("hit_into_play") || description.contains("foul")
}

/// Reads one row.
pub fn read(row: &Row<'_>, cols: &Columns) -> Result<TrackedRow, Skip> {
    let num = |col: Option<usize>, name: &'static str| {
        row.number(col).map_err(|e| Skip::NotANumber { column: name, text: e.text })
    };
    const V: [&str; 3] = ["vx0", "vy0", "vz0"];
    const A: [&str; 3] = ["ax", "ay", "az"];
    let mut v0 = [0.0; 3];
    let mut a = [0.0; 3];
    for k in 0..3 {
        v0[k] = num(cols.v0[k], V[k])?;
        a[k] = num(cols.a[k], A[k])?;
    }
    let (pitch_speed, pitch_angle) = if v0.iter().chain(a.iter()).all(|v| v.is_finite()) {
        let crossing = plate_crossing(v0, a).ok_or(Skip::Refused {
            column: "vy0",
            value: v0[1],
            allowed: "a pitch that reaches the plate (vy0 < 0, vy0² > 2·ay·(50 − 17/12) ft)",
        })?;
        (crossing.speed * FOOT, crossing.descent_angle)
    } else {
        (f64::NAN, f64::NAN)
    };
    let description = row.text(cols.description);
    let launch_speed = num(cols.launch_speed, "launch_speed")?;
    let at_bat = num(cols.at_bat, "at_bat_number")?;
    let pitch_number = num(cols.pitch_number, "pitch_number")?;
    let stamp_ns = chrono::NaiveDate::parse_from_str(row.text(cols.game_date), "%Y-%m-%d").ok().and_then(|d| {
        let midnight = d.and_hms_opt(0, 0, 0)?.and_utc().timestamp();
        let offset = [at_bat * 60.0, pitch_number].iter().filter(|v| v.is_finite() && **v >= 0.0).sum::<f64>();
        let seconds = u64::try_from(midnight).ok()?.checked_add(offset.min(86_399.0) as u64)?;
        seconds.checked_mul(1_000_000_000)
    });
    let attack_angle = deg(num(cols.attack_angle, "attack_angle")?);
    let side = super::batter_side(row.text(cols.stand), "stand")?;
    let call = match row.text(cols.events) {
        "" => description.to_string(),
        events => format!("{description}/{events}"),
    };
    Ok(TrackedRow {
        line: row.line(),
        stamp_ns,
        contact: is_contact(description) || launch_speed.is_finite(),
        call,
        pitch_speed,
        pitch_speed_column: "vy0",
        pitch_angle,
        pitch_spin: backspin(rpm(num(cols.spin_rate, "release_spin_rate")?), num(cols.spin_axis, "spin_axis")?),
        bat_speed: mph(num(cols.bat_speed, "bat_speed")?),
        attack_angle,
        exit_speed: mph(launch_speed),
        launch_angle: deg(num(cols.launch_angle, "launch_angle")?),
        spin: f64::NAN,
        spin_axis_deg: f64::NAN,
        spray_angle: spray_angle(num(cols.hc_x, "hc_x")?, num(cols.hc_y, "hc_y")?),
        bat_tilt: bat_tilt(num(cols.swing_path_tilt, "swing_path_tilt")?, attack_angle)?,
        swing_direction: swing_direction(num(cols.attack_direction, "attack_direction")?, side)?,
        batter_side: side,
        swing_length: num(cols.swing_length, "swing_length")? * FOOT,
        batter: row.text(cols.batter).to_string(),
        pitcher: match row.text(cols.player_name) {
            "" => row.text(cols.pitcher).to_string(),
            name => format!("{name} ({})", row.text(cols.pitcher)),
        },
        pitch_id: format!("{}/{}/{}", row.text(cols.game_pk), row.text(cols.at_bat), row.text(cols.pitch_number)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pitch built backwards from a chosen crossing time, so the expected velocity is v0 + a t with no
    /// quadratic to solve: t = 0.40 s, v_y0 = −130 ft/s, a_y chosen so y(t) = 17/12 ft exactly.
    #[test]
    fn plate_speed_and_descent_match_a_closed_form_trajectory() {
        let t = 0.40;
        let (vy0, vx0, vz0) = (-130.0, 6.0, -4.0);
        let ay = 2.0 * (PLATE_FRONT_Y_FT - FIT_Y_FT - vy0 * t) / (t * t);
        let (ax, az) = (-10.0, -20.0);
        let c = plate_crossing([vx0, vy0, vz0], [ax, ay, az]).expect("reaches the plate");
        assert!((c.time - t).abs() < 1e-12, "{}", c.time);
        let v = [vx0 + ax * t, vy0 + ay * t, vz0 + az * t];
        let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        assert!((c.speed - speed).abs() < 1e-9);
        // -v_z = 12 ft/s down against -v_y = 130 - 0.4 a_y toward the plate.
        assert!((c.descent_angle - (12.0f64 / -v[1]).atan()).abs() < 1e-12);
        // Hand-computed: a_y = 2(17/12 − 50 + 52)/0.16 = 42.708 ft/s², v_y = −112.917 ft/s,
        // |v| = sqrt(2² + 112.917² + 12²) = 113.571 ft/s = 34.616 m/s; descent atan(12/112.917) = 6.066°.
        assert!((c.speed * FOOT - 34.616).abs() < 1e-3, "{}", c.speed * FOOT);
        assert!((c.descent_angle.to_degrees() - 6.066).abs() < 1e-3);
    }

    #[test]
    fn without_acceleration_the_time_is_distance_over_speed() {
        let c = plate_crossing([0.0, -100.0, 0.0], [0.0, 0.0, 0.0]).unwrap();
        assert!((c.time - (50.0 - 17.0 / 12.0) / 100.0).abs() < 1e-15);
        assert_eq!(c.descent_angle, 0.0);
        assert!(plate_crossing([0.0, 10.0, 0.0], [0.0; 3]).is_none(), "moving away from the plate");
        assert!(plate_crossing([0.0, -10.0, 0.0], [0.0, 10.0, 0.0]).is_none(), "stops before the plate");
    }
}
