//! The settings of a running node: changed by `ros2 param set` (on ros2-client's threads), read by the receive
//! loop and its helper tasks.

use std::sync::{Arc, RwLock};

use ros2_client::ParameterValue;

use super::settings::{is_read_only, NodeSettings, SettingEffect};

/// The node's current settings, shared by the parameter services that change them and the tasks that read
/// them. [`LiveSettings::read`] is the one way to read them.
#[derive(Clone)]
pub struct LiveSettings {
    current: Arc<RwLock<NodeSettings>>,
    /// The start-up values, read instead if a panicking writer ever poisoned the lock.
    started: Arc<NodeSettings>,
}

impl LiveSettings {
    /// Starts with `settings`.
    pub fn new(settings: NodeSettings) -> LiveSettings {
        LiveSettings { current: Arc::new(RwLock::new(settings.clone())), started: Arc::new(settings) }
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

    /// ros2-client's parameter validator: a read-only parameter may only be "set" to its current value; any
    /// other must pass [`NodeSettings::apply`] on a copy of the current settings.
    pub fn validate(&self, name: &str, value: &ParameterValue) -> Result<(), String> {
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
