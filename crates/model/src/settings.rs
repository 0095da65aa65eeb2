//! The settings that shape what the model computes (and so travel with a recording in its rosbag2
//! `custom_data`): time step, default bat, ball and mode count, and the registry's limits.

use std::collections::BTreeMap;

use sweetspot_physics::Bat;

/// ball_id a swing with an empty ball_id uses before any BallParams arrived, unless the node's `default_ball`
/// names another preset: the game ball ([`sweetspot_physics::ball::GAME_BALL`], fitted to real games).
pub const DEFAULT_BALL_ID: &str = sweetspot_physics::ball::GAME_BALL;

/// Vibrational modes a bat's discretisation has: 2 DOF per slice minus the two rigid-body modes.
pub fn vibrational_mode_count(bat: &Bat) -> usize {
    (2 * bat.slice_count()).saturating_sub(2)
}

/// rosbag2 `custom_data` key of [`ModelSettings::default_bat`].
pub const CUSTOM_DATA_DEFAULT_BAT: &str = "sweetspot/default_bat";
/// rosbag2 `custom_data` key of [`ModelSettings::default_ball`].
pub const CUSTOM_DATA_DEFAULT_BALL: &str = "sweetspot/default_ball";
/// rosbag2 `custom_data` key of [`ModelSettings::default_modes`].
pub const CUSTOM_DATA_DEFAULT_MODES: &str = "sweetspot/default_modes";
/// rosbag2 `custom_data` key of [`ModelSettings::time_step`].
pub const CUSTOM_DATA_TIME_STEP: &str = "sweetspot/time_step";
/// rosbag2 `custom_data` key of [`ModelSettings::max_bats`]: which bats were forgotten, and so which swings
/// were REJECTED, depends on it.
pub const CUSTOM_DATA_MAX_BATS: &str = "sweetspot/max_bats";
/// rosbag2 `custom_data` key of [`ModelSettings::max_balls`].
pub const CUSTOM_DATA_MAX_BALLS: &str = "sweetspot/max_balls";
/// rosbag2 `custom_data` key of [`ModelSettings::max_bat_slices`]: a BatParams over it was REJECTED, so its bat
/// never answered a swing.
pub const CUSTOM_DATA_MAX_BAT_SLICES: &str = "sweetspot/max_bat_slices";

/// Largest slice count a BatParams may ask for unless `max_bat_slices` says otherwise: a 1-mm grid on any bat
/// up to 1.2 m (the longest legal baseball bat is 42 in = 1.07 m). Solving such a bat's modes takes a fraction
/// of a second; the physics' own limit ([`sweetspot_physics::bat::SLICE_COUNT_RANGE`], 4000) costs ~10 s.
pub const DEFAULT_MAX_BAT_SLICES: usize = 1200;

/// What the model needs besides the messages to turn a swing into an answer. The node's parameters of the same
/// names set it; a recording keeps it in `custom_data` so `bag replay`, `bag export` and `calibrate` compute
/// with the settings the node ran with.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ModelSettings {
    /// bat_id used by swings with an empty bat_id before any BatParams arrived (a preset name).
    pub default_bat: String,
    /// ball_id used by swings with an empty ball_id before any BallParams arrived (a ball preset name).
    pub default_ball: String,
    /// Vibrational modes integrated when a bat's params say 0 (or name a preset).
    pub default_modes: usize,
    /// RK4 time step of every collision, s.
    pub time_step: f64,
    /// Bats kept (least recently used forgotten first, never the latest received).
    pub max_bats: usize,
    /// Balls kept (least recently used forgotten first, never the latest received).
    pub max_balls: usize,
    /// Largest slice count a BatParams may ask for.
    pub max_bat_slices: usize,
}

impl Default for ModelSettings {
    fn default() -> Self {
        ModelSettings {
            default_bat: "r161".to_string(),
            default_ball: DEFAULT_BALL_ID.to_string(),
            default_modes: 18,
            time_step: 5e-6,
            // A lab uses a handful of bats; 64 leaves room for a whole team's and bounds the worst case (each
            // entry at most max_bat_slices slices × 200 modes of shapes, ~4 MB) to a few hundred MB.
            max_bats: 64,
            // A ball is 40 bytes; the cap only stops a publisher inventing ids without end.
            max_balls: 1024,
            max_bat_slices: DEFAULT_MAX_BAT_SLICES,
        }
    }
}

impl ModelSettings {
    /// The modes integrated for `bat` when its params ask for `requested` (`None` = [`Self::default_modes`]):
    /// the default is capped at what the bat's discretisation has; an explicit count was checked already.
    pub fn modes_for(&self, bat: &Bat, requested: Option<usize>) -> usize {
        requested.unwrap_or(self.default_modes).min(vibrational_mode_count(bat))
    }

    /// The `custom_data` entries (key, value) that record these settings; `time_step` keeps every digit.
    pub fn custom_data(&self) -> Vec<(&'static str, String)> {
        vec![
            (CUSTOM_DATA_DEFAULT_BAT, self.default_bat.clone()),
            (CUSTOM_DATA_DEFAULT_BALL, self.default_ball.clone()),
            (CUSTOM_DATA_DEFAULT_MODES, self.default_modes.to_string()),
            // `{:?}` keeps every digit of the f64, so a replay parses back the exact step.
            (CUSTOM_DATA_TIME_STEP, format!("{:?}", self.time_step)),
            (CUSTOM_DATA_MAX_BATS, self.max_bats.to_string()),
            (CUSTOM_DATA_MAX_BALLS, self.max_balls.to_string()),
            (CUSTOM_DATA_MAX_BAT_SLICES, self.max_bat_slices.to_string()),
        ]
    }

    /// The settings a bag's `custom_data` records; a key absent or unreadable keeps its default (a bag
    /// written before a limit existed replays with today's default; `bag replay` takes the default ball of
    /// such a bag from the node's own answers).
    pub fn from_custom_data(custom: &BTreeMap<String, String>) -> ModelSettings {
        let mut settings = ModelSettings::default();
        if let Some(v) = custom.get(CUSTOM_DATA_DEFAULT_BAT) {
            settings.default_bat = v.clone();
        }
        if let Some(v) = custom.get(CUSTOM_DATA_DEFAULT_BALL) {
            settings.default_ball = v.clone();
        }
        let number = |key: &str| custom.get(key).and_then(|v| v.parse::<usize>().ok());
        if let Some(v) = number(CUSTOM_DATA_DEFAULT_MODES) {
            settings.default_modes = v;
        }
        if let Some(v) = custom.get(CUSTOM_DATA_TIME_STEP).and_then(|v| v.parse().ok()) {
            settings.time_step = v;
        }
        if let Some(v) = number(CUSTOM_DATA_MAX_BATS) {
            settings.max_bats = v;
        }
        if let Some(v) = number(CUSTOM_DATA_MAX_BALLS) {
            settings.max_balls = v;
        }
        if let Some(v) = number(CUSTOM_DATA_MAX_BAT_SLICES) {
            settings.max_bat_slices = v;
        }
        settings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn custom_data_round_trips_every_setting_exactly() {
        let settings = ModelSettings {
            default_bat: "torpedo".into(),
            default_ball: "bbcor".into(),
            default_modes: 7,
            time_step: 1.0 / 3.0 * 1e-5,
            max_bats: 3,
            max_balls: 9,
            max_bat_slices: 300,
        };
        let custom: BTreeMap<String, String> =
            settings.custom_data().into_iter().map(|(k, v)| (k.to_string(), v)).collect();
        assert_eq!(custom.len(), 7);
        assert_eq!(ModelSettings::from_custom_data(&custom), settings);
        assert_eq!(ModelSettings::from_custom_data(&BTreeMap::new()), ModelSettings::default());
    }
}
