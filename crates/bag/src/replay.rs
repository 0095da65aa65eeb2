//! `bag replay`: re-run the physics on every recorded swing with the bat and ball in force at that moment,
//! exactly as the node decides it, and compare with the recorded ExitVelocity and ModalEnergies.
//!
//! The model the node runs is used (`model::convert::{bat_from_params_capped, ball_from_params,
//! swing_input, exit_velocity, modal_energies}` and `model::engine::{Registry, plan_swing, compute}`), so
//! replay cannot drift from what the node does. One registry per namespace, like one node per rig.
//!
//! Model settings that shape results are not messages; they are read from the bag's rosbag2 `custom_data`
//! (`sweetspot/default_bat`, `default_ball`, `default_modes`, `time_step`, `max_bats`, `max_balls`,
//! `max_bat_slices`; see [`ModelSettings::from_custom_data`]) when present, else the node defaults (so a bag
//! written before the limits existed replays with today's, which only matter beyond 64 bats, 1024 balls or
//! 1200-slice bats), and `default_bat`, `default_modes` and `time_step` can be given on the command line. The
//! default ball of a swing with an empty ball_id is the built-in ball the node's answer names, so a bag
//! recorded without the setting (before it existed, when it was `baseball`, or by another recorder) replays
//! bit for bit.
//! The limits are replayed as the node applies them: the registry forgets the least recently used bats and
//! balls beyond `max_bats` / `max_balls` (so a swing on a forgotten bat is REJECTED again), and a BatParams
//! of more than `max_bat_slices` slices is refused (so its bat stays unknown). The bag holds the settings last
//! in force: a run whose limits were changed by `ros2 param set` midway replays with the last ones.

use std::collections::{BTreeSet, HashMap, HashSet};
use std::path::Path;

use sweetspot_model::convert;
use sweetspot_model::engine::{self, BatEntry, Registry};
use sweetspot_model::settings::ModelSettings;
use sweetspot_msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies};
use sweetspot_msgs::{FieldTable, FieldValue, RosMessage};
use sweetspot_physics::{Ball, Bat};

use super::export::{read_run, RunEvent, SwingRow};
use super::reader::bag_listing;
use super::BagError;

/// "What if" changes; any of them turns the comparison into a report of differences.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WhatIf {
    /// Use this preset bat for every swing (recorded BatParams are ignored).
    pub bat: Option<String>,
    /// Use this preset ball for every swing (recorded BallParams are ignored).
    pub ball: Option<String>,
    /// Integrate this many modes for every bat.
    pub modes: Option<usize>,
}

impl WhatIf {
    /// Whether anything is overridden.
    pub fn any(&self) -> bool {
        self.bat.is_some() || self.ball.is_some() || self.modes.is_some()
    }
}

/// One field that differs beyond the tolerance.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FieldDiff {
    /// Message and field, e.g. `ExitVelocity.exit_speed` or `ModalEnergies.energy[2]`.
    pub field: String,
    /// Recorded value.
    pub recorded: f64,
    /// Replayed value.
    pub replayed: f64,
}

/// The verdict on one swing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum Verdict {
    /// Every compared field within tolerance.
    Match,
    /// At least one field beyond tolerance (or OK vs REJECTED).
    Differs,
    /// No ExitVelocity was recorded for this swing, or only a DROPPED one (the node's queue was full: nothing was
    /// computed live), or recording stopped: nothing to compare.
    NotRecorded,
    /// The node answered OK with a bat or ball whose params the bag does not hold (recorded without
    /// `bat/params` or `ball/params`, or started after they were sent): the replay cannot know what the node
    /// used, so there is nothing to compare ([`ReplayRow::missing_input`] says what is missing).
    MissingInput,
}

/// One replayed swing.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ReplayRow {
    /// Namespace of the swing topic.
    pub namespace: String,
    /// swing_id.
    pub swing_id: u64,
    /// Bat used by the replay.
    pub bat_id: String,
    /// Ball used by the replay.
    pub ball_id: String,
    /// Recorded exit speed, m/s (NaN if none or rejected).
    pub recorded_exit_speed: f64,
    /// Replayed exit speed, m/s (NaN if rejected).
    pub replayed_exit_speed: f64,
    /// The swing's measured exit speed (a tracker's, an import's), m/s (NaN if not measured).
    pub measured_exit_speed: f64,
    /// Replayed status (0 OK, 1 REJECTED).
    pub replayed_status: u8,
    /// Fields beyond tolerance.
    pub differences: Vec<FieldDiff>,
    /// Largest relative difference over all compared fields (0 when identical).
    pub worst_relative: f64,
    /// Verdict.
    pub verdict: Verdict,
    /// For [`Verdict::MissingInput`]: what the bag lacks, e.g. `BallParams of ball 'rig_ball'`.
    pub missing_input: Option<String>,
}

/// The whole replay.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ReplayReport {
    /// Per swing, in recorded order.
    pub rows: Vec<ReplayRow>,
    /// Relative tolerance used (0 = bit-exact).
    pub tolerance: f64,
    /// Whether overrides were applied.
    pub what_if: bool,
    /// The sweetspot version that wrote the bag (from the MCAP library string), if known.
    pub recorded_by: String,
    /// The model settings the replay used: what the recording node ran with (from the bag's `custom_data`),
    /// with any overrides applied.
    pub settings: ModelSettings,
}

impl ReplayReport {
    /// The measured exit speeds against the model's (replayed, OK) ones: (swings, mean and RMS of measured −
    /// model, m/s); None when no replayed swing was measured.
    pub fn measured_against_model(&self) -> Option<(usize, f64, f64)> {
        let residuals: Vec<f64> = self
            .rows
            .iter()
            .filter(|r| r.replayed_status == ExitVelocity::STATUS_OK)
            .map(|r| r.measured_exit_speed - r.replayed_exit_speed)
            .filter(|d| d.is_finite())
            .collect();
        let n = residuals.len();
        (n > 0).then(|| {
            let mean = residuals.iter().sum::<f64>() / n as f64;
            (n, mean, (residuals.iter().map(|d| d * d).sum::<f64>() / n as f64).sqrt())
        })
    }

    /// Swings per verdict: (match, differs, not recorded).
    pub fn tally(&self) -> (usize, usize, usize) {
        let count = |v| self.rows.iter().filter(|r| r.verdict == v).count();
        (count(Verdict::Match), count(Verdict::Differs), count(Verdict::NotRecorded))
    }

    /// Swings that could not be checked because the bag lacks the params they were answered with
    /// ([`Verdict::MissingInput`]), and what is missing (each once, in order of first need).
    pub fn missing_inputs(&self) -> (usize, Vec<String>) {
        let mut what: Vec<String> = Vec::new();
        let mut n = 0;
        for row in self.rows.iter().filter(|r| r.verdict == Verdict::MissingInput) {
            n += 1;
            if let Some(m) = &row.missing_input {
                if !what.contains(m) {
                    what.push(m.clone());
                }
            }
        }
        (n, what)
    }
}

/// Model settings for a replay: bag `custom_data` if present, else the defaults.
pub fn recorded_settings(path: &Path) -> Result<ModelSettings, BagError> {
    let files = bag_listing(path)?.present();
    let scans: Vec<_> = files.iter().map(|f| super::reader::scan_file(f, |_| {})).collect::<Result<_, _>>()?;
    Ok(ModelSettings::from_custom_data(&super::info::custom_data_of(&scans)))
}

fn library_of(path: &Path) -> String {
    bag_listing(path)
        .ok()
        .and_then(|listing| listing.present().first().cloned())
        .and_then(|f| super::reader::scan_file(&f, |_| {}).ok())
        .map(|s| s.library)
        .unwrap_or_default()
}

/// |recorded − replayed| / max(|recorded|, |replayed|); 0 for equal values or two NaNs, ∞ for NaN vs number.
fn relative_difference(recorded: f64, replayed: f64) -> f64 {
    if recorded.is_nan() && replayed.is_nan() || recorded == replayed {
        return 0.0;
    }
    if recorded.is_nan() || replayed.is_nan() || recorded.is_infinite() || replayed.is_infinite() {
        return f64::INFINITY;
    }
    (recorded - replayed).abs() / recorded.abs().max(replayed.abs())
}

struct Comparer<'a> {
    tolerance: f64,
    diffs: &'a mut Vec<FieldDiff>,
    worst: f64,
}

impl Comparer<'_> {
    fn field(&mut self, name: &str, recorded: f64, replayed: f64) {
        let rel = relative_difference(recorded, replayed);
        self.worst = self.worst.max(rel);
        let equal = if self.tolerance == 0.0 { rel == 0.0 } else { rel <= self.tolerance };
        if !equal {
            self.diffs.push(FieldDiff { field: name.to_string(), recorded, replayed });
        }
    }

    fn array(&mut self, name: &str, recorded: &[f64], replayed: &[f64]) {
        if recorded.len() != replayed.len() {
            self.worst = f64::INFINITY;
            self.diffs.push(FieldDiff {
                field: format!("{name}.len"),
                recorded: recorded.len() as f64,
                replayed: replayed.len() as f64,
            });
        }
        for (k, (a, b)) in recorded.iter().zip(replayed).enumerate() {
            self.field(&format!("{name}[{k}]"), *a, *b);
        }
    }

    /// Compares every numeric field and `float64` sequence of two messages of one type, in `.msg` order, but
    /// `swing_id` (the identity they were paired by) and the fields the recording's schema lacks (`recorded`:
    /// a bag made before a field was appended; `None` when the bag gives no schema).
    fn message<T: FieldTable + RosMessage>(&mut self, rec: &T, rep: &T, recorded: Option<&BTreeSet<String>>) {
        let kind = T::INFO.name();
        for ((name, a), (_, b)) in rec.field_table().iter().zip(rep.field_table().iter()) {
            if *name == "swing_id" || recorded.is_some_and(|fields| !fields.contains(*name)) {
                continue;
            }
            match (a, b) {
                (FieldValue::Floats(a), FieldValue::Floats(b)) => self.array(&format!("{kind}.{name}"), a, b),
                _ => {
                    if let (Some(a), Some(b)) = (a.number(), b.number()) {
                        self.field(&format!("{kind}.{name}"), a, b);
                    }
                }
            }
        }
    }

    /// The verdict on `row` replayed as `ev` and `me`, its differences from the recorded answer collected.
    fn verdict(
        &mut self,
        row: &SwingRow,
        ev: &ExitVelocity,
        me: Option<&ModalEnergies>,
        missing_input: bool,
        recorded_fields: &HashMap<String, BTreeSet<String>>,
    ) -> Verdict {
        match &row.exit_velocity {
            None => Verdict::NotRecorded,
            Some(recorded) if recorded.status == ExitVelocity::STATUS_DROPPED => Verdict::NotRecorded,
            Some(_) if missing_input => Verdict::MissingInput,
            Some(recorded) => {
                self.message(recorded, ev, recorded_fields.get(ExitVelocity::TYPE_NAME));
                match (&row.modal_energies, me) {
                    (Some(a), Some(b)) => self.message(a, b, recorded_fields.get(ModalEnergies::TYPE_NAME)),
                    (None, None) => {}
                    (a, b) => self.field(
                        "ModalEnergies.present",
                        f64::from(u8::from(a.is_some())),
                        f64::from(u8::from(b.is_some())),
                    ),
                }
                if self.diffs.is_empty() {
                    Verdict::Match
                } else {
                    Verdict::Differs
                }
            }
        }
    }
}

/// Replays a bag. `settings` are the model settings to use (see [`recorded_settings`]); `tolerance` is the
/// relative tolerance (0 = bit-exact); `on_swing` is called after each swing (progress).
pub fn replay(
    path: &Path,
    settings: &ModelSettings,
    what_if: &WhatIf,
    tolerance: f64,
    mut on_swing: impl FnMut(usize, usize),
) -> Result<ReplayReport, BagError> {
    let mut replayer = Replayer::new(settings, what_if, tolerance)?;
    let run = read_run(path)?;
    let total = run.rows.len();
    let mut rows = Vec::with_capacity(total);
    for event in &run.events {
        match event {
            RunEvent::BatParams(ns, params) => replayer.bat_params(ns, params),
            RunEvent::BallParams(ns, params) => replayer.ball_params(ns, params),
            RunEvent::Swing(index) => {
                rows.push(replayer.swing(&run.rows[*index], &run.recorded_fields));
                on_swing(rows.len(), total);
            }
        }
    }
    let settings = replayer.settings;
    Ok(ReplayReport { rows, tolerance, what_if: what_if.any(), recorded_by: library_of(path), settings })
}

/// The node as a replay runs it: the settings with the "what if" changes, one registry per namespace, and
/// the bats and balls the bag has announced so far.
struct Replayer<'a> {
    settings: ModelSettings,
    what_if: &'a WhatIf,
    tolerance: f64,
    override_bat: Option<(String, Bat)>,
    override_ball: Option<(String, Ball)>,
    registries: HashMap<String, Registry>,
    // The bats and balls the bag announces (by namespace): a swing the node answered with anything else was
    // answered with params the bag does not hold.
    announced_bats: HashSet<(String, String)>,
    announced_balls: HashSet<(String, String)>,
}

impl<'a> Replayer<'a> {
    /// The replay's node with `settings` and the "what if" changes; a tolerance, mode count or preset out of
    /// range is refused before the bag is read.
    fn new(settings: &ModelSettings, what_if: &'a WhatIf, tolerance: f64) -> Result<Replayer<'a>, BagError> {
        if !(tolerance >= 0.0 && tolerance.is_finite()) {
            return Err(BagError::Format(format!(
                "tolerance = {tolerance} is out of range: expected a finite value ≥ 0"
            )));
        }
        let mut settings = settings.clone();
        if let Some(modes) = what_if.modes {
            if !(1..=200).contains(&modes) {
                return Err(BagError::Format(format!("--modes {modes} is out of range: expected 1..=200")));
            }
            settings.default_modes = modes;
        }
        let override_bat = match &what_if.bat {
            Some(name) => Some((name.clone(), Bat::preset(name).map_err(|e| BagError::Format(format!("--bat: {e}")))?)),
            None => None,
        };
        let override_ball = match &what_if.ball {
            Some(name) => {
                Some((name.clone(), Ball::preset(name).map_err(|e| BagError::Format(format!("--ball: {e}")))?))
            }
            None => None,
        };
        Ok(Replayer {
            settings,
            what_if,
            tolerance,
            override_bat,
            override_ball,
            registries: HashMap::new(),
            announced_bats: HashSet::new(),
            announced_balls: HashSet::new(),
        })
    }

    /// The registry of namespace `ns`, taken out to be put back after use; a namespace's first is made as the
    /// node makes its own at start.
    fn take_registry(&mut self, ns: &str) -> Registry {
        self.registries.remove(ns).unwrap_or_else(|| {
            let mut registry = Registry::with_limits(self.settings.max_bats, self.settings.max_balls);
            // As the node at start: the default bat is made (and held) before any message arrives. An error
            // (a default_bat that is neither a preset nor sent yet) only means it is not held.
            let _ = registry.resolve_bat("", &self.settings);
            if let Some((name, bat)) = &self.override_bat {
                registry.set_bat(BatEntry::new(name, bat.clone(), self.what_if.modes, &self.settings));
            }
            if let Some((name, ball)) = &self.override_ball {
                registry.set_ball(name, *ball);
            }
            registry
        })
    }

    /// BatParams received in `ns`: the bat is announced and, unless --bat stands in for every bat, held as the
    /// node holds it (a bat the node refuses stays unknown).
    fn bat_params(&mut self, ns: &str, params: &BatParams) {
        self.announced_bats.insert((ns.to_string(), params.bat_id.clone()));
        let mut registry = self.take_registry(ns);
        if self.override_bat.is_none() {
            if let Ok(built) = convert::bat_from_params_capped(params, self.settings.max_bat_slices) {
                let modes = self.what_if.modes.or(built.max_modes);
                if let Ok(entry) = BatEntry::new_checked(&params.bat_id, built.bat, modes, &self.settings, &()) {
                    registry.set_bat(entry);
                }
            }
        }
        self.registries.insert(ns.to_string(), registry);
    }

    /// BallParams received in `ns`: the ball is announced and, unless --ball stands in for every ball, held.
    fn ball_params(&mut self, ns: &str, params: &BallParams) {
        self.announced_balls.insert((ns.to_string(), params.ball_id.clone()));
        let mut registry = self.take_registry(ns);
        if self.override_ball.is_none() {
            if let Ok(ball) = convert::ball_from_params(params) {
                registry.set_ball(&params.ball_id, ball);
            }
        }
        self.registries.insert(ns.to_string(), registry);
    }

    /// The ball a swing is replayed with: --ball's, else the swing's ball_id. An empty ball_id before any
    /// BallParams is the node's default_ball, which its answer names. A bag that does not record the setting
    /// (another recorder, or a node from before it existed, whose default was `baseball`) is replayed with the
    /// built-in ball named there; one that does names the same.
    fn ball_id_of<'r>(&'r self, row: &'r SwingRow, registry: &Registry) -> &'r str {
        let ball_id = self.override_ball.as_ref().map_or(row.swing.ball_id.as_str(), |(n, _)| n.as_str());
        let recorded_ball = row.exit_velocity.as_ref().map(|ev| ev.ball_id.as_str()).unwrap_or("");
        if ball_id.is_empty()
            && registry.effective_ball_id("", &self.settings) == self.settings.default_ball
            && Ball::preset_names().contains(&recorded_ball)
        {
            recorded_ball
        } else {
            ball_id
        }
    }

    /// Replays one recorded swing and compares the answer with the recorded one.
    fn swing(&mut self, row: &SwingRow, recorded_fields: &HashMap<String, BTreeSet<String>>) -> ReplayRow {
        let mut registry = self.take_registry(&row.namespace);
        let swing = &row.swing;
        let bat_id = self.override_bat.as_ref().map_or(swing.bat_id.as_str(), |(n, _)| n.as_str());
        let ball_id = self.ball_id_of(row, &registry);
        let (plan, _) = convert::plan_swing_message_as(&mut registry, &self.settings, swing, bat_id, ball_id);
        self.registries.insert(row.namespace.clone(), registry);
        let result = engine::compute(&plan, &());
        let ev = convert::exit_velocity(swing, plan.bat_id(), plan.ball_id(), &result);
        let me = result.as_ref().ok().map(|c| convert::modal_energies(swing, plan.bat_id(), c));
        let missing_input = self.missing_input(row, &plan, &ev);
        let mut differences = Vec::new();
        let mut cmp = Comparer { tolerance: self.tolerance, diffs: &mut differences, worst: 0.0 };
        let verdict = cmp.verdict(row, &ev, me.as_ref(), missing_input.is_some(), recorded_fields);
        let worst = cmp.worst;
        ReplayRow {
            namespace: row.namespace.clone(),
            swing_id: swing.swing_id,
            bat_id: plan.bat_id().to_string(),
            ball_id: plan.ball_id().to_string(),
            recorded_exit_speed: row.exit_velocity.as_ref().map_or(f64::NAN, |e| e.exit_speed),
            replayed_exit_speed: ev.exit_speed,
            measured_exit_speed: swing.measured_exit_speed,
            replayed_status: ev.status,
            differences,
            worst_relative: worst,
            verdict,
            missing_input,
        }
    }

    /// Recorded OK with a bat or ball the bag never announced, which the replay could not use: it replayed
    /// "unknown bat_id/ball_id" for that id, or (an empty id: the latest received) resolved another one. The
    /// bag lacks what the node had, not a difference of the model: the params it lacks.
    fn missing_input(&self, row: &SwingRow, plan: &engine::Plan, ev: &ExitVelocity) -> Option<String> {
        let ns = row.namespace.clone();
        match &row.exit_velocity {
            Some(recorded) if recorded.status == ExitVelocity::STATUS_OK => {
                // What the node used, as its answer says (an answer naming none: what the replay used).
                let or_replayed =
                    |recorded: &str, replayed: &str| if recorded.is_empty() { replayed } else { recorded }.to_string();
                let bat_id = or_replayed(&recorded.bat_id, plan.bat_id());
                let ball_id = or_replayed(&recorded.ball_id, plan.ball_id());
                let unknown_bat = self.override_bat.is_none()
                    && !self.announced_bats.contains(&(ns.clone(), bat_id.clone()))
                    && (ev.message.starts_with("unknown bat_id") || bat_id != plan.bat_id());
                let unknown_ball = self.override_ball.is_none()
                    && !self.announced_balls.contains(&(ns.clone(), ball_id.clone()))
                    && (ev.message.starts_with("unknown ball_id") || ball_id != plan.ball_id());
                let at = if ns == "/" { String::new() } else { format!(" in {ns}") };
                if unknown_bat {
                    Some(format!("BatParams of bat '{bat_id}'{at}"))
                } else if unknown_ball {
                    Some(format!("BallParams of ball '{ball_id}'{at}"))
                } else {
                    None
                }
            }
            _ => None,
        }
    }
}
