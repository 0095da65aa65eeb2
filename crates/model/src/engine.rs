//! The model's state and decisions: which bats and balls are known, which modes are cached, and what a swing
//! turns into (a collision to compute, or a rejection with its reason).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, OnceLock};

use sweetspot_physics::batter::swing_weight;
use sweetspot_physics::oblique::{ObliqueImpact, TangentialContact};
use sweetspot_physics::oblique3d::{collide_spatial, BatterSide, SpatialImpact};
use sweetspot_physics::{
    collide, metrics, Ball, Bat, CollisionOptions, CollisionResult, Impact, MassProperties, ModeSet, PhysicsError,
    SweetSpotSet,
};

use super::limits::{self, quote};
use super::lru::LruMap;
use super::settings::ModelSettings;

pub use super::settings::DEFAULT_BALL_ID;

/// A ball as the model uses it: the force law of every collision and the tangential contact law that oblique
/// swings add (BallParams' appended fields; 0 there = [`TangentialContact::default`]'s value).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BallModel {
    /// Mass, radius and the hysteretic force law.
    pub ball: Ball,
    /// Grip, friction and moment of inertia in an oblique swing.
    pub contact: TangentialContact,
}

impl From<Ball> for BallModel {
    /// `ball` with the default tangential contact (what a BallParams without the contact fields says).
    fn from(ball: Ball) -> BallModel {
        BallModel { ball, contact: TangentialContact::default() }
    }
}

/// Where mode-cache hits and misses are counted (the node's statistics; [`ModeCacheCount`]; `()` for none).
pub trait ModeCacheStats {
    /// One lookup of a bat's modes: `hit` = they were computed already.
    fn count_mode_lookup(&self, hit: bool);
}

impl ModeCacheStats for () {
    fn count_mode_lookup(&self, _hit: bool) {}
}

/// Mode-cache hits and misses counted on their own.
#[derive(Debug, Default)]
pub struct ModeCacheCount {
    /// Lookups that found the modes computed.
    pub hits: AtomicU64,
    /// Lookups that computed them.
    pub misses: AtomicU64,
}

impl ModeCacheStats for ModeCacheCount {
    fn count_mode_lookup(&self, hit: bool) {
        (if hit { &self.hits } else { &self.misses }).fetch_add(1, Ordering::Relaxed);
    }
}

/// One bat the node knows, with its modes computed on first use and shared by every later swing. A new
/// BatParams for the same bat_id makes a new entry, so swings already queued keep the bat they were sent for.
#[derive(Debug)]
pub struct BatEntry {
    /// The bat_id swings use.
    pub bat_id: String,
    /// Geometry and materials.
    pub bat: Bat,
    /// Vibrational modes kept and integrated.
    pub max_modes: usize,
    /// True when `max_modes` came from the `default_modes` parameter (so changing it invalidates this entry).
    pub uses_default_modes: bool,
    modes: OnceLock<Result<Arc<ModeSet>, PhysicsError>>,
}

impl BatEntry {
    /// An entry whose modes are not computed yet.
    pub fn new(bat_id: impl Into<String>, bat: Bat, max_modes: Option<usize>, settings: &ModelSettings) -> BatEntry {
        BatEntry {
            bat_id: bat_id.into(),
            max_modes: settings.modes_for(&bat, max_modes),
            bat,
            uses_default_modes: max_modes.is_none(),
            modes: OnceLock::new(),
        }
    }

    /// The bat's modes: computed by the first caller (a cache miss), shared afterwards (a hit).
    pub fn modes(&self, stats: &impl ModeCacheStats) -> Result<Arc<ModeSet>, PhysicsError> {
        let mut computed = false;
        let modes = self.modes.get_or_init(|| {
            computed = true;
            ModeSet::compute(&self.bat, self.max_modes).map(Arc::new)
        });
        stats.count_mode_lookup(!computed);
        modes.clone()
    }

    /// As [`BatEntry::new`], and refuses a bat whose kept modes the node's `time_step` cannot resolve (the
    /// RK4 criterion of [`CollisionOptions::validate`]), naming max_modes and the most modes it resolves; every
    /// swing on such a bat would be REJECTED. Solves the bat's modes (cached in the entry for its swings).
    /// The solve is counted on `stats`. The error starts with `BatParams 'id':`.
    pub fn new_checked(
        bat_id: impl Into<String>,
        bat: Bat,
        max_modes: Option<usize>,
        settings: &ModelSettings,
        stats: &impl ModeCacheStats,
    ) -> Result<BatEntry, String> {
        let entry = BatEntry::new(bat_id, bat, max_modes, settings);
        entry.check_modes(settings, stats)?;
        Ok(entry)
    }

    /// The check of [`BatEntry::new_checked`] on an entry made already: its modes solved (once, cached in the
    /// entry, counted on `stats`) and resolved by the node's `time_step`. The error starts with `BatParams 'id':`.
    pub fn check_modes(&self, settings: &ModelSettings, stats: &impl ModeCacheStats) -> Result<(), String> {
        let entry = self;
        let context = |e: String| format!("BatParams '{}': {e}", entry.bat_id);
        let modes = entry.modes(stats).map_err(|e| context(e.to_string()))?;
        let options = |modes: usize| CollisionOptions { modes, time_step: settings.time_step };
        let Err(e) = options(entry.max_modes).validate(&modes) else { return Ok(()) };
        // Frequencies rise with the mode number: the most modes resolved is the largest count that passes (0
        // modes always passes: the rigid bat needs no step criterion).
        let resolved = (0..entry.max_modes).rev().find(|&k| options(k).validate(&modes).is_ok()).unwrap_or(0);
        let time_step = limits::number(settings.time_step);
        let (asked, fix) = match (resolved, entry.uses_default_modes) {
            (0, false) => ("max_modes", "not even its first mode".to_string()),
            (0, true) => ("default_modes", "not even its first mode".to_string()),
            (k, false) => ("max_modes", format!("at most {k} modes: expected 1 ≤ max_modes ≤ {k}")),
            (k, true) => ("default_modes", format!("at most {k} modes: send max_modes ≤ {k}")),
        };
        Err(context(format!(
            "{asked} = {} is out of range: for this bat the node's time_step = {time_step} s resolves {fix} ({e})",
            entry.max_modes
        )))
    }

    /// Whether the modes have been computed (successfully or not).
    pub fn modes_cached(&self) -> bool {
        self.modes.get().is_some()
    }
}

/// What the node knows: bats by bat_id, balls by ball_id (each at most `max_bats` / `max_balls`, least
/// recently used forgotten first, never the latest received), and which were received last.
#[derive(Debug)]
pub struct Registry {
    bats: LruMap<Arc<BatEntry>>,
    balls: LruMap<BallModel>,
    latest_bat: Option<String>,
    latest_ball: Option<String>,
}

/// How full the registry is and how much it has forgotten, for `/diagnostics`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RegistryUsage {
    /// Bats held (with their modes, once solved).
    pub bats: usize,
    /// Bats forgotten to stay within `max_bats`, since start.
    pub bats_evicted: u64,
    /// Balls held.
    pub balls: usize,
    /// Balls forgotten to stay within `max_balls`, since start.
    pub balls_evicted: u64,
}

impl Default for Registry {
    fn default() -> Self {
        Registry::new()
    }
}

impl Registry {
    /// The limits of the default settings; bats are created from presets on first use, and the built-in
    /// balls (`Ball::preset_names`) need no params.
    pub fn new() -> Registry {
        let defaults = ModelSettings::default();
        Registry::with_limits(defaults.max_bats, defaults.max_balls)
    }

    /// At most `max_bats` bats and `max_balls` balls.
    pub fn with_limits(max_bats: usize, max_balls: usize) -> Registry {
        Registry { bats: LruMap::new(max_bats), balls: LruMap::new(max_balls), latest_bat: None, latest_ball: None }
    }

    /// Applies the settings' `max_bats` / `max_balls` (forgetting the least recently used at once if they
    /// shrank). Returns how many bats and balls were forgotten.
    pub fn set_limits(&mut self, settings: &ModelSettings) -> (usize, usize) {
        let bats = self.bats.set_capacity(settings.max_bats, self.latest_bat.as_deref());
        let balls = self.balls.set_capacity(settings.max_balls, self.latest_ball.as_deref());
        (bats, balls)
    }

    /// How many bats and balls are held and forgotten.
    pub fn usage(&self) -> RegistryUsage {
        RegistryUsage {
            bats: self.bats.len(),
            bats_evicted: self.bats.evictions(),
            balls: self.balls.len(),
            balls_evicted: self.balls.evictions(),
        }
    }

    /// The bat_id forgotten most recently, if any.
    pub fn last_evicted_bat(&self) -> Option<&str> {
        self.bats.last_evicted()
    }

    /// The ball_id forgotten most recently, if any.
    pub fn last_evicted_ball(&self) -> Option<&str> {
        self.balls.last_evicted()
    }

    /// Stores (or replaces) a bat; it becomes the latest bat. When `max_bats` are held, the least recently
    /// used other bat is forgotten.
    pub fn set_bat(&mut self, entry: BatEntry) -> Arc<BatEntry> {
        let entry = Arc::new(entry);
        self.latest_bat = Some(entry.bat_id.clone());
        self.bats.insert(entry.bat_id.clone(), Arc::clone(&entry), false, None);
        entry
    }

    /// As [`Registry::set_bat`] with an entry another registry holds too (its modes, once solved, are shared):
    /// a call's scratch registry lends the node's bat this way.
    pub fn set_shared_bat(&mut self, entry: Arc<BatEntry>) {
        self.latest_bat = Some(entry.bat_id.clone());
        self.bats.insert(entry.bat_id.clone(), entry, false, None);
    }

    /// Stores (or replaces) a ball; it becomes the latest ball. When `max_balls` are held, the least recently
    /// used other ball is forgotten.
    pub fn set_ball(&mut self, ball_id: &str, ball: impl Into<BallModel>) {
        self.latest_ball = Some(ball_id.to_string());
        self.balls.insert(ball_id.to_string(), ball.into(), false, None);
    }

    /// The bat a swing asks for: empty = the latest received (else `default_bat`); an unknown id that names a
    /// preset becomes a bat (again, if it was forgotten). Returns the entry and whether it was just created
    /// (its SweetSpot is new).
    pub fn resolve_bat(&mut self, requested: &str, settings: &ModelSettings) -> Result<(Arc<BatEntry>, bool), String> {
        let bat_id = self.effective_bat_id(requested, settings);
        if let Some(entry) = self.bats.get(&bat_id) {
            return Ok((Arc::clone(entry), false));
        }
        if self.bats.was_forgotten(&bat_id) {
            // Even when the id names a preset: its BatParams may have said something else.
            return Err(format!(
                "unknown bat_id '{}': its BatParams were forgotten (evicted) to keep at most max_bats = {} \
                 bats, least recently used first; publish its BatParams again (or raise max_bats)",
                quote(&bat_id),
                self.bats.capacity()
            ));
        }
        match Bat::preset(&bat_id) {
            Ok(bat) => {
                let entry = Arc::new(BatEntry::new(&bat_id, bat, None, settings));
                // A preset used by name does not become "the latest received" bat, and may be forgotten
                // without a trace: it is made again on demand.
                self.bats.insert(bat_id, Arc::clone(&entry), true, self.latest_bat.as_deref());
                Ok((entry, true))
            }
            Err(_) => Err(format!(
                "unknown bat_id '{}': no BatParams received for it{} and it is not a preset (known bats: \
                 [{}]; presets: [{}])",
                quote(&bat_id),
                long_forgotten(self.bats.evictions(), "BatParams", "max_bats", self.bats.capacity()),
                limits::list_ids(self.bats.iter().map(|(id, _)| id)),
                Bat::preset_names().join(", ")
            )),
        }
    }

    /// The bat_id an empty or explicit request refers to.
    pub fn effective_bat_id(&self, requested: &str, settings: &ModelSettings) -> String {
        if requested.is_empty() {
            self.latest_bat.clone().unwrap_or_else(|| settings.default_bat.clone())
        } else {
            requested.to_string()
        }
    }

    /// The ball a swing asks for: empty = the latest received (else the default baseball). Does not count as
    /// a use (see [`Registry::use_ball`]).
    pub fn resolve_ball(&self, requested: &str, settings: &ModelSettings) -> Result<(String, BallModel), String> {
        let ball_id = self.effective_ball_id(requested, settings);
        if let Some(ball) = self.balls.peek(&ball_id) {
            return Ok((ball_id, *ball));
        }
        if self.balls.was_forgotten(&ball_id) {
            return Err(format!(
                "unknown ball_id '{}': its BallParams were forgotten (evicted) to keep at most max_balls = {} \
                 balls, least recently used first; publish its BallParams again (or raise max_balls)",
                quote(&ball_id),
                self.balls.capacity()
            ));
        }
        if let Ok(ball) = Ball::preset(&ball_id) {
            return Ok((ball_id, ball.into()));
        }
        // The built-in balls still answer to their names unless BallParams under that name came and went.
        let built_in = Ball::preset_names()
            .iter()
            .copied()
            .filter(|id| self.balls.peek(id).is_none() && !self.balls.was_forgotten(id));
        let known = self.balls.iter().map(|(id, _)| id).chain(built_in);
        Err(format!(
            "unknown ball_id '{}': no BallParams received for it{} (known balls: [{}])",
            quote(&ball_id),
            long_forgotten(self.balls.evictions(), "BallParams", "max_balls", self.balls.capacity()),
            limits::list_ids(known)
        ))
    }

    /// As [`Registry::resolve_ball`], and marks the ball as just used (a swing's use keeps it from being
    /// forgotten first).
    pub fn use_ball(&mut self, requested: &str, settings: &ModelSettings) -> Result<(String, BallModel), String> {
        let resolved = self.resolve_ball(requested, settings)?;
        let _ = self.balls.get(&resolved.0);
        Ok(resolved)
    }

    /// The ball_id a swing's `requested` one stands for: itself, or for an empty one the latest received,
    /// else the settings' `default_ball`.
    pub fn effective_ball_id(&self, requested: &str, settings: &ModelSettings) -> String {
        if requested.is_empty() {
            self.latest_ball.clone().unwrap_or_else(|| settings.default_ball.clone())
        } else {
            requested.to_string()
        }
    }

    /// After `default_modes` changed: replaces every bat that used it with a fresh entry (its modes will be
    /// recomputed on next use). Returns the new entries.
    pub fn refresh_default_modes(&mut self, settings: &ModelSettings) -> Vec<Arc<BatEntry>> {
        let stale: Vec<Arc<BatEntry>> = self
            .bats
            .iter()
            .filter(|(_, e)| e.uses_default_modes && e.max_modes != settings.default_modes)
            .map(|(_, e)| Arc::clone(e))
            .collect();
        stale
            .into_iter()
            .map(|old| {
                let fresh = Arc::new(BatEntry::new(&old.bat_id, old.bat.clone(), None, settings));
                self.bats.replace(&old.bat_id, Arc::clone(&fresh));
                fresh
            })
            .collect()
    }

    /// Every bat held now, by bat_id.
    pub fn bats(&self) -> Vec<Arc<BatEntry>> {
        let mut all: Vec<_> = self.bats.iter().map(|(_, e)| Arc::clone(e)).collect();
        all.sort_by(|a, b| a.bat_id.cmp(&b.bat_id));
        all
    }

    /// Whether `entry` is the one held now for its bat_id (not replaced by newer params, not forgotten).
    pub fn is_current(&self, entry: &Arc<BatEntry>) -> bool {
        self.bats.peek(&entry.bat_id).is_some_and(|held| Arc::ptr_eq(held, entry))
    }
}

/// After evictions an id no longer remembered as forgotten may still have been known once: say so.
fn long_forgotten(evictions: u64, message: &str, limit: &str, capacity: usize) -> String {
    if evictions == 0 {
        String::new()
    } else {
        format!(
            " (or its {message} were forgotten long ago: {evictions} evicted so far to keep at most {limit} = \
             {capacity})"
        )
    }
}

pub use crate::limits::{MAX_PITCH_SPIN, MAX_SWING_ANGLE};

/// What the model takes from a Swing besides its bat and ball (units and signs as in Swing.msg): the impact
/// along the bat's path, the oblique geometry (all 0 = head-on) and the rig's launch measurements (NaN = not
/// measured). An [`Impact`] converts into a head-on swing with nothing measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwingInput {
    /// Ball and bat speeds along the bat's path and the impact point.
    pub impact: Impact,
    /// Undercut D, m, positive when the ball's centre is above the bat's path.
    pub undercut: f64,
    /// Attack angle of the bat's path above the horizontal, rad.
    pub attack_angle: f64,
    /// Descent angle of the pitch, rad, positive descending.
    pub pitch_angle: f64,
    /// Pitch spin about the bat's axis, rad/s, backspin positive.
    pub pitch_spin: f64,
    /// Launch angle measured by the rig, rad; NaN when not measured.
    pub measured_launch_angle: f64,
    /// Spin measured by the rig, rad/s: backspin without an axis, total spin with one; NaN when not measured.
    pub measured_spin: f64,
    /// Tilt of the bat's long axis below the horizontal, rad (barrel below the hands positive).
    pub bat_tilt: f64,
    /// Horizontal direction of the bat's path, rad, positive toward right field.
    pub swing_direction: f64,
    /// The batter's side.
    pub batter_side: BatterSide,
    /// Spray angle measured by the rig, rad; NaN when not measured.
    pub measured_spray_angle: f64,
    /// Spin axis measured by the rig (TrackMan's HitSpinAxis), rad; NaN when not measured.
    pub measured_spin_axis: f64,
}

impl From<Impact> for SwingInput {
    fn from(impact: Impact) -> SwingInput {
        SwingInput {
            impact,
            undercut: 0.0,
            attack_angle: 0.0,
            pitch_angle: 0.0,
            pitch_spin: 0.0,
            measured_launch_angle: f64::NAN,
            measured_spin: f64::NAN,
            bat_tilt: 0.0,
            swing_direction: 0.0,
            batter_side: BatterSide::Right,
            measured_spray_angle: f64::NAN,
            measured_spin_axis: f64::NAN,
        }
    }
}

impl SwingInput {
    /// True when undercut, the angles, the pitch spin, the bat's tilt and the swing's direction are all 0: the
    /// swing is today's head-on collision.
    pub fn is_head_on(&self) -> bool {
        [self.undercut, self.attack_angle, self.pitch_angle, self.pitch_spin, self.bat_tilt, self.swing_direction]
            .iter()
            .all(|v| *v == 0.0)
    }

    /// The backspin the rig measured, rad/s: `measured_spin` itself, or its backspin part −cos(axis) times it
    /// when the rig measured the spin axis (a radar's total spin); NaN when not measured.
    pub fn measured_backspin(&self) -> f64 {
        if self.measured_spin_axis.is_nan() {
            self.measured_spin
        } else {
            -self.measured_spin * self.measured_spin_axis.cos()
        }
    }

    /// Checks the oblique inputs for a ball of radius `ball_radius` on a barrel of radius `barrel_radius` (m)
    /// and the measured values; the error names the field and its allowed range.
    pub fn validate(&self, ball_radius: f64, barrel_radius: f64) -> Result<(), String> {
        let out = |field: &str, value: f64, allowed: String| {
            Err(format!("{field} = {} is out of range: expected {allowed}", limits::number(value)))
        };
        let reach = ball_radius + barrel_radius;
        // Without a barrel radius (impact_z not a number) the collision refuses impact_z itself.
        if reach.is_finite() && !(self.undercut.is_finite() && self.undercut.abs() < reach) {
            return out(
                "undercut",
                self.undercut,
                format!(
                    "|undercut| < ball radius + barrel radius at impact_z = {reach:.4} m (a finite value; beyond it \
                     the bat misses the ball)"
                ),
            );
        }
        for (field, v) in [("attack_angle", self.attack_angle), ("pitch_angle", self.pitch_angle)] {
            if !(v.is_finite() && v.abs() <= MAX_SWING_ANGLE) {
                return out(field, v, format!("|{field}| ≤ {MAX_SWING_ANGLE:.4} rad (80°)"));
            }
        }
        if !(self.pitch_spin.is_finite() && self.pitch_spin.abs() <= MAX_PITCH_SPIN) {
            return out("pitch_spin", self.pitch_spin, format!("|pitch_spin| ≤ {MAX_PITCH_SPIN} rad/s"));
        }
        for (field, v) in [("bat_tilt", self.bat_tilt), ("swing_direction", self.swing_direction)] {
            if !(v.is_finite() && v.abs() <= MAX_SWING_ANGLE) {
                return out(field, v, format!("|{field}| ≤ {MAX_SWING_ANGLE:.4} rad (80°)"));
            }
        }
        if self.bat_tilt.abs() + self.attack_angle.abs() >= 0.5 * std::f64::consts::PI - 1e-6 {
            return out(
                "bat_tilt",
                self.bat_tilt,
                "|bat_tilt| + |attack_angle| < 90° (a bat perpendicular to its path cannot tilt further)".to_string(),
            );
        }
        for (field, v) in [
            ("measured_launch_angle", self.measured_launch_angle),
            ("measured_spin", self.measured_spin),
            ("measured_spray_angle", self.measured_spray_angle),
            ("measured_spin_axis", self.measured_spin_axis),
        ] {
            if v.is_infinite() {
                return out(field, v, "a finite value, or NaN when not measured".to_string());
            }
        }
        Ok(())
    }
}

/// What a swing became after resolving its bat and ball.
#[derive(Debug, Clone)]
pub enum Plan {
    /// A collision to compute off the DDS thread.
    Collide {
        /// The bat (its modes may still need computing).
        bat: Arc<BatEntry>,
        /// Resolved ball_id.
        ball_id: String,
        /// The ball.
        ball: Ball,
        /// The ball's tangential contact law (used by oblique swings only).
        contact: TangentialContact,
        /// Initial conditions along the bat's path.
        impact: Impact,
        /// The oblique geometry, `None` for a head-on swing (today's collision, bit for bit).
        oblique: Option<Box<SpatialImpact>>,
        /// Mode count and time step.
        options: CollisionOptions,
    },
    /// Answered REJECTED without computing.
    Reject {
        /// Resolved (or requested) bat_id.
        bat_id: String,
        /// Resolved (or requested) ball_id.
        ball_id: String,
        /// Why.
        reason: String,
    },
}

impl Plan {
    /// The bat_id the answer will carry.
    pub fn bat_id(&self) -> &str {
        match self {
            Plan::Collide { bat, .. } => &bat.bat_id,
            Plan::Reject { bat_id, .. } => bat_id,
        }
    }

    /// The ball_id the answer will carry.
    pub fn ball_id(&self) -> &str {
        match self {
            Plan::Collide { ball_id, .. } | Plan::Reject { ball_id, .. } => ball_id,
        }
    }
}

/// Resolves a swing's bat and ball and checks its oblique inputs against them (an [`Impact`] is a head-on
/// swing). The second value is a bat created from a preset on first use.
pub fn plan_swing(
    registry: &mut Registry,
    settings: &ModelSettings,
    bat_id: &str,
    ball_id: &str,
    swing: impl Into<SwingInput>,
) -> (Plan, Option<Arc<BatEntry>>) {
    // Over-long ids are refused before any lookup, and the answer carries them cut short.
    if let Err(reason) = limits::check_string("bat_id", bat_id).and_then(|_| limits::check_string("ball_id", ball_id)) {
        let bat_id = limits::echo(bat_id).into_owned();
        let ball_id = limits::echo(ball_id).into_owned();
        return (Plan::Reject { bat_id, ball_id, reason }, None);
    }
    let swing: SwingInput = swing.into();
    let impact = swing.impact;
    let (bat, created) = match registry.resolve_bat(bat_id, settings) {
        Ok((bat, created)) => (bat, created.then_some(())),
        Err(reason) => {
            let ball_id =
                registry.resolve_ball(ball_id, settings).map(|(id, _)| id).unwrap_or_else(|_| ball_id.to_string());
            return (Plan::Reject { bat_id: registry.effective_bat_id(bat_id, settings), ball_id, reason }, None);
        }
    };
    let new_bat = created.map(|_| Arc::clone(&bat));
    match registry.use_ball(ball_id, settings) {
        Ok((ball_id, BallModel { ball, contact })) => {
            let options = CollisionOptions { modes: bat.max_modes, time_step: settings.time_step };
            // A non-finite impact_z is refused by the collision itself, naming impact_z.
            let barrel_radius =
                if impact.impact_z.is_finite() { bat.bat.radii_at(impact.impact_z).0 } else { f64::NAN };
            if let Err(reason) = swing.validate(ball.radius, barrel_radius) {
                return (Plan::Reject { bat_id: bat.bat_id.clone(), ball_id, reason }, new_bat);
            }
            let oblique = (!swing.is_head_on() && barrel_radius.is_finite()).then(|| {
                Box::new(SpatialImpact {
                    oblique: ObliqueImpact {
                        impact,
                        barrel_radius,
                        undercut: swing.undercut,
                        attack_angle: swing.attack_angle,
                        pitch_angle: swing.pitch_angle,
                        pitch_spin: swing.pitch_spin,
                    },
                    bat_tilt: swing.bat_tilt,
                    swing_direction: swing.swing_direction,
                    batter_side: swing.batter_side,
                })
            });
            (Plan::Collide { bat, ball_id, ball, contact, impact, oblique, options }, new_bat)
        }
        Err(reason) => (Plan::Reject { bat_id: bat.bat_id.clone(), ball_id: ball_id.to_string(), reason }, new_bat),
    }
}

/// How the ball leaves the bat (units and signs as in ExitVelocity.msg).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Launch {
    /// Speed of the outgoing ball, m/s.
    pub exit_speed: f64,
    /// Launch angle above the horizontal, rad.
    pub launch_angle: f64,
    /// Backspin, rad/s (about the horizontal axis across the flight; positive lifts).
    pub spin: f64,
    /// Outgoing velocity along the line of centres, m/s.
    pub normal_exit_speed: f64,
    /// Outgoing velocity across the line of centres, around the bat, m/s.
    pub tangential_exit_speed: f64,
    /// Spray angle, rad, positive toward right field.
    pub spray_angle: f64,
    /// Sidespin, rad/s, positive toward left field.
    pub sidespin: f64,
    /// Gyro spin along the flight, rad/s.
    pub gyro_spin: f64,
    /// Total spin, rad/s.
    pub total_spin: f64,
    /// Spin axis (TrackMan's HitSpinAxis), rad.
    pub spin_axis: f64,
}

impl Launch {
    /// A head-on collision's launch: along the bat's path, horizontal, without spin.
    pub fn head_on(collision: &CollisionResult) -> Launch {
        Launch {
            exit_speed: collision.exit_speed,
            launch_angle: 0.0,
            spin: 0.0,
            normal_exit_speed: collision.exit_speed,
            tangential_exit_speed: 0.0,
            spray_angle: 0.0,
            sidespin: 0.0,
            gyro_spin: 0.0,
            total_spin: 0.0,
            spin_axis: std::f64::consts::PI,
        }
    }
}

/// A computed collision with what the answer messages need besides it.
#[derive(Debug, Clone, PartialEq)]
pub struct Computed {
    /// The collision along the line of centres (the whole collision for a head-on swing).
    pub collision: CollisionResult,
    /// How the ball leaves the bat.
    pub launch: Launch,
    /// Kinetic energy in the centre-of-mass frame of ball and bat before impact, J (the denominator of
    /// ModalEnergies.fraction).
    pub collision_energy: f64,
}

/// Runs a planned collision: the bat's modes (cached), then the collision. Errors are the physics' text.
pub fn compute(plan: &Plan, stats: &impl ModeCacheStats) -> Result<Computed, String> {
    match plan {
        Plan::Reject { reason, .. } => Err(reason.clone()),
        Plan::Collide { bat, ball_id, ball, impact, oblique: None, options, .. } => {
            let modes = bat.modes(stats).map_err(|e| format!("bat '{}': {e}", bat.bat_id))?;
            let collision = collide(&modes, ball, impact, options).map_err(|e| e.to_string())?;
            limits::check_compression(ball_id, ball, collision.max_compression)?;
            let collision_energy = centre_of_mass_energy(&collision, &modes.mass_properties(), ball, impact);
            Ok(Computed { launch: Launch::head_on(&collision), collision, collision_energy })
        }
        Plan::Collide { bat, ball_id, ball, contact, oblique: Some(spatial), options, .. } => {
            let modes = bat.modes(stats).map_err(|e| format!("bat '{}': {e}", bat.bat_id))?;
            let result = collide_spatial(&modes, ball, spatial, contact, options).map_err(|e| e.to_string())?;
            limits::check_compression(ball_id, ball, result.normal.max_compression)?;
            let launch = Launch {
                exit_speed: result.exit_speed,
                launch_angle: result.launch_angle,
                spin: result.backspin,
                normal_exit_speed: result.normal_exit_speed,
                tangential_exit_speed: result.tangential_exit_speed,
                spray_angle: result.spray_angle,
                sidespin: result.sidespin,
                gyro_spin: result.gyro_spin,
                total_spin: result.total_spin,
                spin_axis: result.spin_axis,
            };
            let collision_energy =
                centre_of_mass_energy(&result.normal, &modes.mass_properties(), ball, &result.normal_impact);
            Ok(Computed { collision: result.normal, launch, collision_energy })
        }
    }
}

/// Total kinetic energy before impact minus that of the motion of the common centre of mass, J. The ball
/// moves toward the bat (−ball_speed along the bat's direction of motion), the bat's centre toward the ball.
pub fn centre_of_mass_energy(collision: &CollisionResult, bat: &MassProperties, ball: &Ball, impact: &Impact) -> f64 {
    let total_mass = bat.mass + ball.mass;
    let momentum = bat.mass * impact.bat_cm_speed - ball.mass * impact.ball_speed;
    let centre_speed = momentum / total_mass;
    collision.energy.initial - 0.5 * total_mass * centre_speed * centre_speed
}

/// The SweetSpot of one bat for the reference swing: sweet-spot set, BBCOR, frequencies, mass properties.
#[derive(Debug, Clone, PartialEq)]
pub struct BatSummary {
    /// bat_id.
    pub bat_id: String,
    /// Ball used for the reference swing.
    pub ball_id: String,
    /// The reference swing (impact_z unused).
    pub reference: Impact,
    /// Sweet spots for the reference swing.
    pub sweet_spots: SweetSpotSet,
    /// BBCOR.
    pub bbcor: f64,
    /// Vibrational frequencies, Hz.
    pub frequencies_hz: Vec<f64>,
    /// Mass properties.
    pub mass: MassProperties,
    /// Hoop frequency of the barrel wall at the flexible bat's sweet spot, Hz; 0 for a solid section.
    pub hoop_frequency: f64,
    /// Swing weight: moment of inertia about the pivot 6 in from the knob, kg·m².
    pub swing_weight: f64,
}

/// Computes a bat's SweetSpot for the `reference` swing (its impact point is filled in by the sweet-spot
/// search). Slow: a sweep of collisions; run it off the DDS thread.
pub fn summarize_bat(
    bat: &BatEntry,
    ball_id: &str,
    ball: &Ball,
    reference: Impact,
    settings: &ModelSettings,
    stats: &impl ModeCacheStats,
) -> Result<BatSummary, String> {
    let modes = bat.modes(stats).map_err(|e| format!("bat '{}': {e}", bat.bat_id))?;
    let options = CollisionOptions { modes: bat.max_modes, time_step: settings.time_step };
    let sweet_spots = metrics::sweet_spots(&modes, ball, &reference, &options)
        .map_err(|e| format!("bat '{}': sweet spots: {e}", bat.bat_id))?;
    let bbcor = metrics::bbcor(&modes, &options).map_err(|e| format!("bat '{}': BBCOR: {e}", bat.bat_id))?;
    let hoop_frequency = modes.hoop_frequency_at(sweet_spots.max_exit_speed_z).unwrap_or(0.0);
    Ok(BatSummary {
        bat_id: bat.bat_id.clone(),
        ball_id: ball_id.to_string(),
        reference,
        sweet_spots,
        bbcor,
        frequencies_hz: modes.frequencies_hz(),
        mass: modes.mass_properties(),
        hoop_frequency,
        swing_weight: swing_weight(&modes.mass_properties()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn swing(z: f64) -> Impact {
        Impact { ball_speed: 40.0, bat_cm_speed: 20.0, bat_angular_speed: 50.0, impact_z: z }
    }

    #[test]
    fn a_sweet_spot_is_found_for_every_reference_angular_speed_in_the_parameter_s_range() {
        // reference_bat_angular_speed is −500…500 rad/s: at either end the barrel's inner (or outer) part moves
        // away from the ball faster than the ball comes, and the SweetSpot used to fail there for every bat.
        let (settings, stats) = (ModelSettings::default(), ModeCacheCount::default());
        let entry = BatEntry::new("r161", Bat::preset("r161").unwrap(), None, &settings);
        let mp = entry.modes(&stats).unwrap().mass_properties();
        for omega in [-500.0, -200.0, 50.0, 200.0, 500.0] {
            let reference = Impact { ball_speed: 40.0, bat_cm_speed: 20.0, bat_angular_speed: omega, impact_z: 0.0 };
            let summary = summarize_bat(&entry, DEFAULT_BALL_ID, &Ball::default(), reference, &settings, &stats)
                .unwrap_or_else(|e| panic!("ω = {omega}: {e}"));
            let z = summary.sweet_spots.max_exit_speed_z;
            // Independent of the scan: where the rigid bat's point meets the ball at a positive closing speed.
            let closing = 40.0 + 20.0 + omega * (z - mp.center_of_mass);
            assert!(closing > 0.0 && (0.42..0.84).contains(&z), "ω = {omega}: z = {z}, closing {closing} m/s");
            assert!(summary.sweet_spots.max_exit_speed > 0.0, "ω = {omega}");
        }
    }

    #[test]
    fn defaults_answer_without_params_and_modes_are_computed_once() {
        let (settings, stats) = (ModelSettings::default(), ModeCacheCount::default());
        let mut registry = Registry::new();
        let (plan, new_bat) = plan_swing(&mut registry, &settings, "", "", swing(0.7));
        assert!(new_bat.is_some(), "the default bat is created on first use");
        assert_eq!((plan.bat_id(), plan.ball_id()), ("r161", DEFAULT_BALL_ID));
        let first = compute(&plan, &stats).unwrap();
        let (plan2, new_bat) = plan_swing(&mut registry, &settings, "r161", "", swing(0.7));
        assert!(new_bat.is_none());
        assert_eq!(compute(&plan2, &stats).unwrap(), first);
        assert_eq!((stats.misses.load(Ordering::Relaxed), stats.hits.load(Ordering::Relaxed)), (1, 1));
        // The same numbers as calling the library directly with the game ball.
        let modes = ModeSet::compute(&Bat::preset("r161").unwrap(), 18).unwrap();
        let direct = collide(&modes, &Ball::mlb2024(), &swing(0.7), &CollisionOptions::default()).unwrap();
        assert_eq!(first.collision, direct);
        assert!(first.collision_energy > 0.0 && first.collision_energy < direct.energy.initial);
    }

    #[test]
    fn unknown_ids_and_bad_numbers_are_rejected_with_reasons() {
        let (settings, stats) = (ModelSettings::default(), ModeCacheCount::default());
        let mut registry = Registry::new();
        let (plan, _) = plan_swing(&mut registry, &settings, "nope", "", swing(0.7));
        let e = compute(&plan, &stats).unwrap_err();
        assert!(e.contains("unknown bat_id 'nope'") && e.contains("r161"), "{e}");
        let (plan, _) = plan_swing(&mut registry, &settings, "r161", "softball", swing(0.7));
        let e = compute(&plan, &stats).unwrap_err();
        assert!(e.contains("unknown ball_id 'softball'"), "{e}");
        let (plan, _) = plan_swing(&mut registry, &settings, "r161", "", swing(f64::NAN));
        assert!(compute(&plan, &stats).unwrap_err().contains("impact_z"));
        let (plan, _) = plan_swing(&mut registry, &settings, "r161", "", swing(2.0));
        assert!(compute(&plan, &stats).unwrap_err().contains("impact_z"));
    }

    #[test]
    fn bats_beyond_max_bats_are_forgotten_least_recently_used_first_and_then_rejected_with_the_reason() {
        let settings = ModelSettings { max_bats: 3, ..ModelSettings::default() };
        let stats = ModeCacheCount::default();
        let mut registry = Registry::with_limits(settings.max_bats, settings.max_balls);
        let bat = Bat::preset("r161").unwrap();
        for id in ["a", "b", "c"] {
            registry.set_bat(BatEntry::new(id, bat.clone(), Some(4), &settings));
        }
        let (plan, _) = plan_swing(&mut registry, &settings, "a", "", swing(0.7));
        assert!(compute(&plan, &stats).is_ok(), "a is used now: b is the least recently used");
        registry.set_bat(BatEntry::new("d", bat.clone(), Some(4), &settings));
        assert_eq!(registry.last_evicted_bat(), Some("b"));
        let (plan, _) = plan_swing(&mut registry, &settings, "b", "", swing(0.7));
        let e = compute(&plan, &stats).unwrap_err();
        assert!(e.contains("unknown bat_id 'b'") && e.contains("evicted") && e.contains("max_bats = 3"), "{e}");
        assert_eq!(plan.bat_id(), "b");
        // Presets used by name come and go without ever pushing out the latest received bat ("d").
        for preset in Bat::preset_names() {
            let (plan, _) = plan_swing(&mut registry, &settings, preset, "", swing(0.7));
            assert!(matches!(plan, Plan::Collide { .. }), "{preset}");
        }
        assert_eq!(registry.resolve_bat("", &settings).unwrap().0.bat_id, "d");
        let (plan, created) = plan_swing(&mut registry, &settings, "r161", "", swing(0.7));
        assert!(matches!(plan, Plan::Collide { .. }) && created.is_some(), "a forgotten preset is made again");
        let usage = registry.usage();
        assert_eq!(usage.bats, 3);
        // b, then c, a, r161 and r161-corked for the presets, then aluminum for r161 again ("d" spared).
        assert_eq!(usage.bats_evicted, 6, "{usage:?}");
        // New params for a forgotten id make it known again.
        registry.set_bat(BatEntry::new("b", bat.clone(), Some(4), &settings));
        assert!(registry.resolve_bat("b", &settings).is_ok());
        // Shrinking max_bats forgets at once, sparing the latest.
        let (forgotten, _) = registry.set_limits(&ModelSettings { max_bats: 2, ..settings.clone() });
        assert_eq!((forgotten, registry.usage().bats), (1, 2));
        assert_eq!(registry.resolve_bat("", &settings).unwrap().0.bat_id, "b");
    }

    #[test]
    fn balls_beyond_max_balls_are_forgotten_and_the_built_in_ball_stays_available() {
        let settings = ModelSettings { max_balls: 2, ..ModelSettings::default() };
        let mut registry = Registry::with_limits(settings.max_bats, settings.max_balls);
        for (i, id) in ["x", "y", "z"].into_iter().enumerate() {
            registry.set_ball(id, Ball { cor: 0.4 + 0.01 * i as f64, ..Ball::default() });
        }
        let e = registry.use_ball("x", &settings).unwrap_err();
        assert!(e.contains("unknown ball_id 'x'") && e.contains("evicted") && e.contains("max_balls = 2"), "{e}");
        assert_eq!(registry.use_ball("", &settings).unwrap().0, "z");
        // Every built-in ball answers to its preset name without params.
        assert_eq!(registry.use_ball("baseball", &settings).unwrap().1, Ball::default().into());
        assert_eq!(registry.use_ball("bbcor", &settings).unwrap().1, Ball::bbcor_protocol().into());
        assert_eq!(registry.use_ball(DEFAULT_BALL_ID, &settings).unwrap().1, Ball::mlb2024().into());
        let e = registry.use_ball("never", &settings).unwrap_err();
        assert!(e.contains("no BallParams") && e.contains(DEFAULT_BALL_ID) && e.contains("baseball"), "{e}");
        assert_eq!(registry.usage().balls_evicted, 1);
    }

    #[test]
    fn new_params_replace_the_entry_and_latest_wins_for_empty_ids() {
        let settings = ModelSettings::default();
        let mut registry = Registry::new();
        let old = registry.set_bat(BatEntry::new("mine", Bat::preset("r161").unwrap(), Some(6), &settings));
        let new = registry.set_bat(BatEntry::new("mine", Bat::preset("torpedo").unwrap(), None, &settings));
        assert!(!Arc::ptr_eq(&old, &new));
        let (resolved, created) = registry.resolve_bat("", &settings).unwrap();
        assert!(Arc::ptr_eq(&resolved, &new) && !created);
        assert_eq!(resolved.max_modes, 18);
        registry.set_ball("soft", Ball { cor: 0.4, ..Ball::default() });
        assert_eq!(registry.resolve_ball("", &settings).unwrap().0, "soft");
        let changed = ModelSettings { default_modes: 10, ..settings };
        let refreshed = registry.refresh_default_modes(&changed);
        assert_eq!(refreshed.len(), 1);
        assert_eq!(refreshed[0].max_modes, 10);
    }

    #[test]
    fn over_long_ids_are_refused_before_any_lookup_with_a_short_message() {
        let settings = ModelSettings::default();
        let mut registry = Registry::new();
        let huge = "x".repeat(1 << 20);
        let (plan, created) = plan_swing(&mut registry, &settings, &huge, "", swing(0.7));
        assert!(created.is_none());
        let Plan::Reject { bat_id, reason, .. } = &plan else { panic!("{plan:?}") };
        assert!(reason.starts_with("bat_id is 1048576 bytes long, over the limit of 256 bytes"), "{reason}");
        assert!(reason.len() < 200 && bat_id.len() < 300, "{} / {}", reason.len(), bat_id.len());
        let (plan, _) = plan_swing(&mut registry, &settings, "r161", &huge, swing(0.7));
        assert!(compute(&plan, &()).unwrap_err().starts_with("ball_id is 1048576 bytes"));
        assert_eq!(registry.usage().bats, 0, "nothing was stored for the refused swings");
    }

    #[test]
    fn an_unknown_id_among_many_long_ones_gets_a_bounded_message() {
        let settings = ModelSettings::default();
        let mut registry = Registry::new();
        let bat = Bat::preset("r161").unwrap();
        for i in 0..20 {
            let id = format!("{i:02}{}", "b".repeat(254));
            registry.set_bat(BatEntry::new(id, bat.clone(), Some(4), &settings));
        }
        for i in 0..40 {
            registry.set_ball(&format!("{i:02}{}", "c".repeat(254)), Ball::default());
        }
        let unknown = "u".repeat(256);
        let e = registry.resolve_bat(&unknown, &settings).unwrap_err();
        // 20 ids of 256 bytes would be 5 KB; each is cut to 32 bytes, the list to 1 KB.
        assert!(e.len() < 1600, "{} bytes: {e}", e.len());
        assert!(e.contains("unknown bat_id 'uuuu") && e.contains("00bbb"), "{e}");
        let e = registry.resolve_ball(&unknown, &settings).unwrap_err();
        assert!(e.len() < 1600 && e.contains("more"), "{} bytes: {e}", e.len());
    }

    #[test]
    fn a_ball_compressed_beyond_its_radius_is_refused_naming_its_force_law() {
        let (settings, stats) = (ModelSettings::default(), ModeCacheCount::default());
        let mut registry = Registry::new();
        let soft = Ball { stiffness: 1e4, exponent: 1.0, ..Ball::default() };
        registry.set_ball("soft", soft);
        let (plan, _) = plan_swing(&mut registry, &settings, "r161", "soft", swing(0.7));
        let e = compute(&plan, &stats).unwrap_err();
        assert!(e.starts_with("ball 'soft' (stiffness = 10000 N/m^α, exponent α = 1, radius = 0.0366 m)"), "{e}");
        assert!(e.contains("≤ 1 × radius = 0.0366 m"), "{e}");
        // Independent scale: a linear spring stopping the ball alone from the approach speed v compresses by
        // v·√(m/k); the bat's recoil only lowers it, so the compression reported lies between half that and it.
        let modes = ModeSet::compute(&Bat::preset("r161").unwrap(), 18).unwrap();
        let v = 40.0 + sweetspot_physics::rigid::bat_speed_at(&modes.mass_properties(), &swing(0.7));
        let bound = v * (soft.mass / soft.stiffness).sqrt();
        let reported: f64 = e.split("compressed by ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
        assert!(reported > 0.5 * bound && reported <= bound, "{reported} vs {bound}");
        // The regulation ball on the same swing stays well inside the limit and answers.
        let (plan, _) = plan_swing(&mut registry, &settings, "r161", DEFAULT_BALL_ID, swing(0.7));
        assert!(compute(&plan, &stats).unwrap().collision.max_compression < 0.5 * 0.0366, "about R/3");
    }

    #[test]
    fn modes_the_time_step_cannot_resolve_are_refused_at_params_time() {
        let settings = ModelSettings::default();
        let bat = Bat { slice_length: 7e-4, ..Bat::preset("r161").unwrap() };
        let e = BatEntry::new_checked("fine", bat.clone(), Some(200), &settings, &()).unwrap_err();
        assert!(
            e.starts_with(
                "BatParams 'fine': max_modes = 200 is out of range: for this bat the node's time_step = 5e-6 s"
            ),
            "{e}"
        );
        let resolved: usize = e.split("resolves at most ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
        assert!(e.contains(&format!("1 ≤ max_modes ≤ {resolved}")), "{e}");
        // The count quoted is the one the collision itself accepts: one mode more is refused by it.
        let modes = ModeSet::compute(&bat, 200).unwrap();
        let options = |modes| CollisionOptions { modes, time_step: settings.time_step };
        assert!(collide(&modes, &Ball::default(), &swing(0.7), &options(resolved)).is_ok());
        assert!(collide(&modes, &Ball::default(), &swing(0.7), &options(resolved + 1)).is_err());
        let entry = BatEntry::new_checked("fine", bat.clone(), Some(resolved), &settings, &()).unwrap();
        assert!(entry.modes_cached(), "the modes solved for the check serve the swings");
        // Presets with the default modes pass.
        for name in Bat::preset_names() {
            assert!(BatEntry::new_checked(*name, Bat::preset(name).unwrap(), None, &settings, &()).is_ok(), "{name}");
        }
    }

    fn swing_msg(undercut: f64, attack: f64, pitch: f64, spin: f64) -> sweetspot_msgs::sweetspot_msgs::msg::Swing {
        sweetspot_msgs::sweetspot_msgs::msg::Swing {
            swing_id: 7,
            bat_id: "r161".into(),
            ball_speed: 40.0,
            bat_cm_speed: 20.0,
            bat_angular_speed: 50.0,
            impact_z: 0.7,
            measured_exit_speed: f64::NAN,
            undercut,
            attack_angle: attack,
            pitch_angle: pitch,
            pitch_spin: spin,
            measured_launch_angle: 0.3,
            measured_spin: f64::NAN,
            ..Default::default()
        }
    }

    fn answer(s: &sweetspot_msgs::sweetspot_msgs::msg::Swing) -> sweetspot_msgs::sweetspot_msgs::msg::ExitVelocity {
        use super::super::convert;
        let settings = ModelSettings::default();
        let mut registry = Registry::new();
        let (plan, _) = plan_swing(&mut registry, &settings, &s.bat_id, "", convert::swing_input(s));
        let result = compute(&plan, &());
        convert::exit_velocity(s, plan.bat_id(), plan.ball_id(), &result)
    }

    #[test]
    fn a_head_on_swing_answers_the_head_on_collision_bit_for_bit() {
        let s = swing_msg(0.0, 0.0, 0.0, 0.0);
        let ev = answer(&s);
        let modes = ModeSet::compute(&Bat::preset("r161").unwrap(), 18).unwrap();
        let direct = collide(&modes, &Ball::game(), &swing(0.7), &CollisionOptions::default()).unwrap();
        let pairs = [
            (ev.exit_speed, direct.exit_speed),
            (ev.rigid_exit_speed, direct.rigid_exit_speed),
            (ev.effective_cor, direct.effective_cor),
            (ev.collision_efficiency, direct.collision_efficiency),
            (ev.contact_time, direct.contact_time),
            (ev.peak_force, direct.peak_force),
            (ev.impulse, direct.impulse),
            (ev.max_compression, direct.max_compression),
            (ev.normal_exit_speed, direct.exit_speed),
        ];
        for (got, want) in pairs {
            assert_eq!(got.to_bits(), want.to_bits(), "{got} vs {want}");
        }
        assert_eq!((ev.launch_angle, ev.spin, ev.tangential_exit_speed), (0.0, 0.0, 0.0));
        assert_eq!(ev.launch_angle_residual, 0.3, "measured − model");
        assert!(ev.spin_residual.is_nan(), "spin not measured");
        assert_eq!((ev.hoop_frequency, ev.hoop_energy_stored, ev.hoop_energy_returned), (0.0, 0.0, 0.0), "wood");
    }

    #[test]
    fn an_oblique_swing_answers_the_oblique_collision() {
        use sweetspot_physics::oblique::{collide_oblique, ObliqueImpact, TangentialContact};
        let s = swing_msg(0.015, 0.14, 0.1, 200.0);
        let ev = answer(&s);
        assert_eq!(ev.status, sweetspot_msgs::sweetspot_msgs::msg::ExitVelocity::STATUS_OK, "{}", ev.message);
        let bat = Bat::preset("r161").unwrap();
        let modes = ModeSet::compute(&bat, 18).unwrap();
        let oblique = ObliqueImpact {
            impact: swing(0.7),
            barrel_radius: bat.radii_at(0.7).0,
            undercut: 0.015,
            attack_angle: 0.14,
            pitch_angle: 0.1,
            pitch_spin: 200.0,
        };
        let want = collide_oblique(
            &modes,
            &Ball::game(),
            &oblique,
            &TangentialContact::default(),
            &CollisionOptions::default(),
        )
        .unwrap();
        assert_eq!(ev.launch_angle.to_bits(), want.launch_angle.to_bits());
        assert_eq!(ev.spin.to_bits(), want.spin.to_bits());
        assert_eq!(ev.exit_speed.to_bits(), want.exit_speed.to_bits());
        assert_eq!(
            (ev.normal_exit_speed, ev.tangential_exit_speed),
            (want.normal_exit_speed, want.tangential_exit_speed)
        );
        assert_eq!(ev.impulse, want.normal.impulse);
        // An undercut ball leaves upward with backspin.
        assert!(ev.launch_angle > 0.2 && ev.spin > 100.0, "{} rad, {} rad/s", ev.launch_angle, ev.spin);
        assert_eq!(ev.launch_angle_residual, 0.3 - want.launch_angle);
    }

    #[test]
    fn a_hollow_bat_fills_the_hoop_fields() {
        use super::super::convert;
        let s =
            sweetspot_msgs::sweetspot_msgs::msg::Swing { bat_id: "aluminum".into(), ..swing_msg(0.0, 0.0, 0.0, 0.0) };
        let settings = ModelSettings::default();
        let mut registry = Registry::new();
        let (plan, _) = plan_swing(&mut registry, &settings, &s.bat_id, "", convert::swing_input(&s));
        let computed = compute(&plan, &()).unwrap();
        let ev = convert::exit_velocity(&s, plan.bat_id(), plan.ball_id(), &Ok(computed.clone()));
        let me = convert::modal_energies(&s, plan.bat_id(), &computed);
        assert!(ev.hoop_frequency > 500.0 && ev.hoop_frequency < 10_000.0, "{} Hz", ev.hoop_frequency);
        assert!(ev.hoop_energy_stored > 0.0 && ev.hoop_energy_returned > 0.0, "{ev:?}");
        assert!(ev.hoop_energy_returned <= ev.hoop_energy_stored);
        let left = ev.hoop_energy_stored - ev.hoop_energy_returned;
        assert!(me.hoop_energy >= 0.0 && (me.hoop_energy - left).abs() <= 1e-9 * ev.hoop_energy_stored, "{me:?}");
    }

    #[test]
    fn oblique_inputs_out_of_range_are_rejected_naming_the_field_and_range() {
        for (s, field) in [
            (swing_msg(0.2, 0.0, 0.0, 0.0), "undercut"),
            (swing_msg(f64::NAN, 0.0, 0.0, 0.0), "undercut"),
            (swing_msg(0.0, 1.5, 0.0, 0.0), "attack_angle"),
            (swing_msg(0.0, 0.0, f64::INFINITY, 0.0), "pitch_angle"),
            (swing_msg(0.0, 0.0, 0.0, 1500.0), "pitch_spin"),
            (
                sweetspot_msgs::sweetspot_msgs::msg::Swing {
                    measured_spin: f64::INFINITY,
                    ..swing_msg(0.0, 0.0, 0.0, 0.0)
                },
                "measured_spin",
            ),
        ] {
            let ev = answer(&s);
            assert_eq!(ev.status, sweetspot_msgs::sweetspot_msgs::msg::ExitVelocity::STATUS_REJECTED, "{field}");
            assert!(
                ev.message.starts_with(&format!("{field} = ")) && ev.message.contains("expected"),
                "{}",
                ev.message
            );
            assert!(ev.launch_angle.is_nan() && ev.hoop_frequency.is_nan());
        }
    }

    #[test]
    fn the_sweet_spot_carries_the_swing_weight_about_six_inches_from_the_knob() {
        let settings = ModelSettings::default();
        let entry = BatEntry::new("r161", Bat::preset("r161").unwrap(), Some(6), &settings);
        let summary = summarize_bat(&entry, DEFAULT_BALL_ID, &Ball::default(), swing(0.0), &settings, &()).unwrap();
        let mp = Bat::preset("r161").unwrap().mass_properties();
        // Parallel-axis theorem about 6 in = 0.1524 m (ASTM F2398's pivot).
        let arm = mp.center_of_mass - 6.0 * sweetspot_physics::units::INCH;
        let expected = mp.moment_of_inertia + mp.mass * arm * arm;
        assert!((summary.swing_weight - expected).abs() <= 1e-9 * expected, "{} vs {expected}", summary.swing_weight);
        assert_eq!(summary.hoop_frequency, 0.0, "a solid bat");
        let msg = super::super::convert::sweet_spot(&summary, Default::default());
        assert_eq!((msg.swing_weight, msg.hoop_frequency), (summary.swing_weight, 0.0));
    }
}
