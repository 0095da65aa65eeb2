//! The settings of a running node: changed by `ros2 param set` (on ros2-client's threads), read by the receive
//! loop and its helper tasks.

use std::sync::{Arc, Mutex, RwLock};

use ros2_client::ParameterValue;

use super::settings::{is_read_only, NodeSettings, SettingEffect};

/// The node's current settings, shared by the parameter services that change them and the tasks that read
/// them. [`LiveSettings::read`] is the one way to read them.
#[derive(Clone)]
pub struct LiveSettings {
    current: Arc<RwLock<NodeSettings>>,
    /// The start-up values, read instead if a panicking writer ever poisoned the lock.
    started: Arc<NodeSettings>,
    /// The ids of the latest accepted BatParams and BallParams: once one has arrived, swings with an empty id
    /// use it, and `default_bat` / `default_ball` no longer apply.
    latest: Arc<Mutex<Latest>>,
}

/// The bat and ball of the latest accepted params, if any arrived.
#[derive(Debug, Default)]
struct Latest {
    bat: Option<String>,
    ball: Option<String>,
}

impl LiveSettings {
    /// Starts with `settings`.
    pub fn new(settings: NodeSettings) -> LiveSettings {
        LiveSettings {
            current: Arc::new(RwLock::new(settings.clone())),
            started: Arc::new(settings),
            latest: Arc::default(),
        }
    }

    /// Runs `read` on the current settings under the read lock, without copying them (per swing, the strings
    /// would cost); a `ros2 param set` waits for it, so keep it short.
    pub fn read<R>(&self, read: impl FnOnce(&NodeSettings) -> R) -> R {
        match self.current.read() {
            Ok(current) => read(&current),
            Err(_) => read(&self.started),
        }
    }

    /// A copy of the current settings, for work that outlives the lock.
    pub fn snapshot(&self) -> NodeSettings {
        self.read(NodeSettings::clone)
    }

    /// Notes that BatParams of `bat_id` were accepted: swings with an empty bat_id use that bat from now on.
    pub fn note_bat_params(&self, bat_id: &str) {
        if let Ok(mut latest) = self.latest.lock() {
            latest.bat = Some(bat_id.to_string());
        }
    }

    /// Notes that BallParams of `ball_id` were accepted: swings with an empty ball_id use that ball from now on.
    pub fn note_ball_params(&self, ball_id: &str) {
        if let Ok(mut latest) = self.latest.lock() {
            latest.ball = Some(ball_id.to_string());
        }
    }

    /// Why setting `name` would change nothing, if it would not: `default_bat` and `default_ball` name what a
    /// swing with an empty id uses only until params of that kind arrive, and a set that reported success
    /// then would leave the user believing the node had changed.
    fn without_effect(&self, name: &str) -> Option<String> {
        let latest = self.latest.lock().ok()?;
        let (kind, id) = match name {
            "default_bat" => ("BatParams", latest.bat.as_ref()?),
            "default_ball" => ("BallParams", latest.ball.as_ref()?),
            _ => return None,
        };
        let field = if kind == "BatParams" { "bat_id" } else { "ball_id" };
        Some(format!(
            "{name} applies only until {kind} arrive, and they have: swings with an empty {field} use '{}', the \
             latest {kind}; publish {kind} (or name the {field} in the swing) to change that",
            crate::model::limits::quote(id)
        ))
    }

    /// ros2-client's parameter validator: a read-only parameter may only be "set" to its current value; any
    /// other must pass [`NodeSettings::apply`] on a copy of the current settings, and change what the node
    /// does ([`LiveSettings::without_effect`]).
    pub fn validate(&self, name: &str, value: &ParameterValue) -> Result<(), String> {
        if let Some(reason) = self.without_effect(name) {
            return Err(reason);
        }
        self.read(|current| {
            if is_read_only(name) {
                return if current.value_of(name).as_ref() == Some(value) {
                    Ok(())
                } else {
                    Err(format!("{name} is read-only while the node runs: restart with -p {name}:=…"))
                };
            }
            current.clone().apply(name, value).map(|_| ())
        })
    }

    /// ros2-client's parameter set action: stores a value; `Some(effect)` when the settings changed.
    pub fn set(&self, name: &str, value: &ParameterValue) -> Result<Option<SettingEffect>, String> {
        let mut settings = self.current.write().map_err(|_| "settings lock poisoned".to_string())?;
        let before = settings.clone();
        let effect = settings.apply(name, value)?;
        Ok((*settings != before).then_some(effect))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `default_ball` names the ball of swings with an empty ball_id only until BallParams arrive (the
    /// registry's latest ball wins from then on): a set after that is refused, naming the ball in force,
    /// instead of reporting a success that changes nothing. Likewise `default_bat` after BatParams.
    #[test]
    fn a_default_that_no_longer_applies_is_refused_with_the_id_in_force() {
        let live = LiveSettings::new(NodeSettings::default());
        let set = |name: &str, value: &str| live.validate(name, &ParameterValue::String(value.into()));
        assert_eq!(set("default_ball", "bbcor"), Ok(()));
        assert_eq!(set("default_bat", "aluminum"), Ok(()));
        live.note_ball_params("lab_ball");
        let refused = set("default_ball", "bbcor").unwrap_err();
        assert!(refused.contains("'lab_ball'") && refused.contains("BallParams"), "{refused}");
        assert_eq!(set("default_bat", "aluminum"), Ok(()), "no BatParams yet");
        live.note_bat_params("rig_bat");
        let refused = set("default_bat", "aluminum").unwrap_err();
        assert!(refused.contains("'rig_bat'") && refused.contains("BatParams"), "{refused}");
        assert_eq!(
            live.validate("default_modes", &ParameterValue::Integer(5)),
            Ok(()),
            "other parameters are untouched"
        );
    }
}
