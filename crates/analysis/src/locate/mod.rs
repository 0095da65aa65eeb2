//! `sweetspot locate BAG`: where on the bat each ball was hit — the impact point `impact_z` and the undercut
//! for which the model reproduces what the tracker measured off the bat.
//!
//! **Model.** The node's own: the bat and ball in force for the swing (BatParams/BallParams of the bag,
//! modes and time step from its `custom_data`), the head-on collision for a head-on swing and the oblique
//! one otherwise ([`crate::calibrate::tangential::exit_speed`]'s rule), with the swing's recorded speeds and
//! angles; only `impact_z` (z) and `undercut` (D) are free.
//!
//! **What is solved.** With only the exit speed v measured, z alone (D kept at the swing's value, 0 if
//! NaN): v(z) = v_m. Exit speed is not monotonic along the barrel — it rises from the handle to the sweet
//! spot z* and falls toward the end — so every root is found: the grid of [`GRID_POINTS`] points over the
//! barrel half of the bat (L/2 … L − 5 mm) plus the sweet spot (the grid's best point refined by Brent's
//! parabolic search) brackets them, and each is refined by regula falsi (Illinois). The grid only has to
//! find the one maximum: v(z) rises to it and falls beyond, so a coarse grid brackets every root (a 1-mm
//! scan in tests/locate_round_trip.rs finds the same roots). With the launch angle θ measured too, (z, D)
//! are found together from each of those roots — the undercut started where the launch angle matches, by
//! secant steps — by Levenberg–Marquardt on the weighted residuals (v − v_m)/σ_v, (θ − θ_m)/σ_θ and, when
//! the spin ω is measured, (ω − ω_m)/σ_ω (forward-difference Jacobian).
//!
//! **Cost.** With D free, the search runs at up to 4× the node's time step ([`search_options`]: a collision
//! there costs about half of one at the node's step, and moves the answers by ~10⁻⁴ m/s and ~10⁻⁴ °), and
//! Levenberg–Marquardt finishes each solution with the node's own options from the search's solution and
//! Jacobian, so every reported number (solution, χ², covariance at the solution, model values) is the node's
//! model. A Statcast swing (v and θ measured) takes ~75 search collisions and ~13 at the node's step; with v
//! alone (z only) the node's options throughout, 25–45 collisions. The bat's modes are solved once per bat,
//! and swings run in parallel (rayon).
//!
//! **Uncertainty.** The trackers' accuracies (default σ_v = 0.45 m/s ≈ 1 mph, σ_θ = 1°, σ_ω = 100 rpm: the
//! exit radar's noise of `sweetspot rig` and the accuracies `calibrate --fit-tangential` weights by)
//! propagated linearly: Cov(z, D) = (JᵀJ)⁻¹ with J the Jacobian of the weighted residuals at the solution;
//! for z alone σ_z = σ_v / |dv/dz|. Near the sweet spot dv/dz → 0 and σ_z grows without bound: the honest
//! answer there is "somewhere near the sweet spot".
//!
//! **Located.** A solution is located only when it reproduces the measurements within the trackers'
//! accuracy and its impact point is known to better than the barrel: with more measurements than unknowns
//! (exit speed, launch angle and spin for z and D) its χ² is at most [`MAX_CHI2_PER_DOF`] per degree of
//! freedom (9: a 3σ miss on the one degree, which tracker noise alone gives 0.27 % of balls), and its σ_z is
//! at most [`MAX_Z_SIGMA_SHARE`] of the barrel searched (half: a ±1σ interval no wider than the barrel). A
//! swing none of whose solutions passes is not reproducible ([`Outcome::NotReproducible`]), with the reason
//! and the closest fit's numbers (model against measured, in σ), unless its exit speed is above the largest
//! the model gives (too fast, as without spin). Least squares always finds a closest fit; without this check a
//! 140-mph ball off a 40-mph pitch, with its spin, was "located" at χ² ≈ 1,900 with a model exit speed 19 m/s
//! short, and a ball launched at 89.9° at z = 0.70 ± 26 m. With as many measurements as unknowns a solution
//! reproduces them exactly (or is not one) and only σ_z is checked.
//!
//! **Side.** Handle or end side of the sweet spot at the solution's undercut, located to about 20 µm: a
//! solution on the sweet spot itself (a ball hit about as hard as the bat allows) has no meaningful side.
//!
//! **Which solution.** With three measurements for two unknowns the solutions' χ² = Σ r² differ, and one with
//! a χ² lower by more than 1 is favoured; with as many measurements as unknowns every solution reproduces
//! them exactly and none is favoured.
//!
//! **Too fast.** A measured exit speed above the largest the model gives over the barrel (at the swing's D,
//! and over the undercuts tried when D is free) is reported with the excess: no impact point explains it —
//! a check on the ball (COR), the bat, or the assumed bat speed.
//!
//! **Bat speed (`fit_bat_speed`, `locate --fit-bat-speed`).** TrackMan (and any export without a bat speed)
//! leaves the bat's speed to the batter model, and `import` marks it assumed in the bag's side table
//! ([`ROWS_TABLE`], column `assumed`). For such a swing with exit speed, launch angle and spin all measured,
//! a third unknown is fitted with z and D: a scale s on the swing's bat speeds, `bat_cm_speed` and
//! `bat_angular_speed` together (the batter's effort; their ratio, so the pivot [`sweetspot_physics::batter`]
//! places, is kept). Three measurements, three unknowns: Levenberg–Marquardt in (z, D, s) from each
//! two-unknown solution at s = 1 (from either side of the sweet spot at a faster bat for a too-fast swing)
//! and from 5 cm either side of the sweet spot at s = 0.85 and 1.15, each kept on its side of the sweet spot, and a solution reproduces all three measurements (χ² < 10⁻⁶);
//! there are usually two, one either side, at different bat speeds, and none is favoured. Cov(z, D, s) =
//! (JᵀJ)⁻¹ of the weighted residuals, i.e. (JᵀWJ)⁻¹ of the raw ones. The spin is what separates s from z
//! (dω/ds ≈ 0.4 ω while the exit speed trades z against s), so at a tracker's 100 rpm σ(s) is about 10–25 %
//! for a ball with 2000+ rpm and grows without bound as the spin vanishes or the solution nears the sweet
//! spot: a solution with σ(s) > [`MAX_SCALE_SIGMA`] or σ_z > [`MAX_FIT_Z_SIGMA`] is reported as not separable
//! rather than as numbers. A swing whose bat speed was measured, or a bag without the side table, is not
//! fitted, and says so.
//!
//! **Progress.** [`locate_bag_with_progress`] reports each swing done, for a progress bar or line.
//!
//! **Without a bag.** [`locate_imported`] locates an export's swings as [`crate::import::import_table`] builds
//! them in memory, with the bat, ball and settings `import` would write: the bag path and the in-memory one
//! meet in [`locate_recorded`], so they answer alike.
//!
//! **Squared up.** A located swing is squared up when its favoured solution (every solution, when none is
//! favoured) lies within ±2 cm ([`SQUARED_UP`]) of the sweet spot z* at its undercut.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

mod bat_speed;
pub mod figure;
pub mod text;

use bat_speed::fit_bat_speed;
pub use bat_speed::{BatSpeedFit, BatSpeedSolution, MAX_FIT_Z_SIGMA, MAX_SCALE_SIGMA};

use crate::calibrate::{problem_bat, read_inputs, CalibrateError, RecordedInputs};
use crate::import::{ImportOptions, ImportedSwings, ROWS_TABLE};
use sweetspot_model::convert::{ball_from_params, swing_input, wrapped_difference, BallModel};
use sweetspot_model::engine::SwingInput;
use sweetspot_model::files::echo;
use sweetspot_msgs::sweetspot_msgs::msg::Swing;
use sweetspot_physics::oblique::{collide_oblique, rpm_to_rad_per_s, ObliqueImpact, TangentialContact};
use sweetspot_physics::oblique3d::{collide_spatial, SpatialImpact};
use sweetspot_physics::{collide, Ball, Bat, CollisionOptions, ModeSet, PhysicsError};

/// Grid points along the barrel half that bracket the exit-speed roots (3.5 cm apart on an 84-cm bat; v(z)
/// has one maximum there, so the grid only has to find it, and the maximum is inserted before bracketing).
pub const GRID_POINTS: usize = 13;
/// Half-width of the window searched for the sweet spot at another undercut, as a share of the search range.
const PEAK_WINDOW: f64 = 0.05;
/// Half-width of the window searched first, m: the sweet spot moves by micrometres per millimetre of
/// undercut, so it nearly always lies within this of the guess; when the maximum found sits on this window's
/// edge it lies outside, and [`PEAK_WINDOW`] is searched.
const NARROW_WINDOW: f64 = 0.005;
/// The sweet spot is located to about this, m (its place decides the side and "squared up" of a solution at
/// the millimetre; the exit speed there is flat to 10⁻⁶ of itself over it).
const PEAK_TOLERANCE: f64 = 2e-5;
/// The peak at the swing's undercut is located to this when it only brackets roots and guesses where the
/// sweet spot at the solution's undercut lies, m.
const GUESS_TOLERANCE: f64 = 2e-4;
/// Half-width of the "squared up" band around the sweet spot, m.
pub const SQUARED_UP: f64 = 0.02;
/// Impact points are searched from this fraction of the bat's length to its end.
pub const SEARCH_FROM: f64 = 0.5;
/// Gap kept from the barrel end, m.
pub const END_GAP: f64 = 0.005;

/// How to locate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocateOptions {
    /// Exit-speed accuracy σ_v, m/s.
    pub exit_speed_sigma: f64,
    /// Launch-angle accuracy σ_θ, rad.
    pub launch_angle_sigma: f64,
    /// Spin accuracy σ_ω, rad/s.
    pub spin_sigma: f64,
    /// Also fit the bat speed of swings whose bat speed the import assumed (see the module docs).
    pub fit_bat_speed: bool,
}

impl Default for LocateOptions {
    fn default() -> Self {
        LocateOptions {
            exit_speed_sigma: 0.45,
            launch_angle_sigma: 1f64.to_radians(),
            spin_sigma: rpm_to_rad_per_s(100.0),
            fit_bat_speed: false,
        }
    }
}

/// Which side of the sweet spot a solution lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Between the hands and the sweet spot.
    Handle,
    /// Between the sweet spot and the barrel end.
    End,
}

/// One (z, D) that reproduces the measurements.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Solution {
    /// Impact point, m from the knob.
    pub impact_z: f64,
    /// Its standard uncertainty, m.
    pub impact_z_sigma: f64,
    /// Undercut, m.
    pub undercut: f64,
    /// Its standard uncertainty, m (0 when D was not fitted).
    pub undercut_sigma: f64,
    /// Whether D was fitted (launch angle measured) or kept at the swing's value.
    pub undercut_fitted: bool,
    /// Side of the sweet spot.
    pub side: Side,
    /// The sweet spot at this undercut, m from the knob.
    pub sweet_spot_z: f64,
    /// χ² = Σ of the squared weighted residuals at the solution.
    pub chi2: f64,
    /// Model exit speed, launch angle, spin at the solution (m/s, rad, rad/s).
    pub model: [f64; 3],
    /// The ball's direction at the solution, for a swing in three dimensions or with a measured spray angle
    /// or spin axis; absent from JSON otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub direction: Option<Direction>,
}

/// Where the model sends the ball at a solution, and how far that is from what the tracker measured.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Direction {
    /// Model spray angle, rad, positive toward right field.
    pub spray_angle: f64,
    /// Model spin axis (TrackMan's HitSpinAxis), rad in [0, 2π).
    pub spin_axis: f64,
    /// Measured − model spray angle, rad; NaN (null in JSON) when not measured.
    pub spray_angle_residual: f64,
    /// Measured − model spin axis wrapped into (−π, π], rad; NaN (null in JSON) when not measured.
    pub spin_axis_residual: f64,
}

/// What was found for one swing.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "verdict", rename_all = "snake_case")]
pub enum Outcome {
    /// At least one solution.
    Located {
        /// Every solution, handle side first.
        solutions: Vec<Solution>,
        /// Index of the favoured solution, if the measurements favour one.
        favoured: Option<usize>,
        /// Whether the swing was squared up (see the module docs).
        squared_up: bool,
    },
    /// The exit speed is above what the sweet spot gives.
    TooFast {
        /// The largest exit speed the model gives, m/s.
        max_exit_speed: f64,
        /// Measured minus that, m/s.
        excess: f64,
        /// Where the largest is, m from the knob.
        sweet_spot_z: f64,
    },
    /// The fits found do not reproduce the measurements within tracker accuracy, or do not place the ball on
    /// the barrel (see the module docs, "Located").
    NotReproducible {
        /// Why, with the closest fit's numbers.
        reason: String,
        /// The fits found, handle side first: none is located.
        solutions: Vec<Solution>,
    },
    /// No exit speed measured.
    NotMeasured,
    /// The swing cannot be simulated (unknown bat, bad inputs) or the search failed.
    Failed {
        /// Why.
        reason: String,
    },
}

/// One swing's result.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Located {
    /// The swing.
    pub swing_id: u64,
    /// Its bat.
    pub bat_id: String,
    /// Measured exit speed (m/s), launch angle (rad) and spin (rad/s); NaN = not measured (null in JSON).
    pub measured: [f64; 3],
    /// Measured spray angle and spin axis (rad; NaN = not measured, null in JSON), for a swing whose
    /// solutions carry a [`Direction`]; absent from JSON otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured_direction: Option<[f64; 2]>,
    /// The result.
    #[serde(flatten)]
    pub outcome: Outcome,
    /// The bat-speed fit, when asked for (`LocateOptions::fit_bat_speed`); absent from JSON otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bat_speed_fit: Option<BatSpeedFit>,
}

/// Every swing of a bag.
#[derive(Debug, Clone, serde::Serialize)]
pub struct LocateReport {
    /// Per swing, in time order.
    pub swings: Vec<Located>,
    /// Swings located.
    pub located: usize,
    /// Swings faster than the sweet spot allows.
    pub too_fast: usize,
    /// Swings whose fits do not reproduce the measurements within tracker accuracy, or do not place the
    /// ball on the barrel ([`Outcome::NotReproducible`]).
    pub not_reproducible: usize,
    /// Swings whose bat speed was fitted, when asked for; absent from JSON otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bat_speed_fitted: Option<usize>,
    /// Share of located swings squared up (within ±2 cm of the sweet spot), NaN without any.
    pub squared_up_share: f64,
    /// Collisions run: (with the search's options, with the node's), for the bench.
    #[serde(skip)]
    pub collisions: (usize, usize),
    /// Each bat's outline, by bat id: (z from the knob, outer radius) in m, for the figure.
    #[serde(skip)]
    pub outlines: BTreeMap<String, Vec<(f64, f64)>>,
}

/// Points of a bat's outline drawn in the figure.
const OUTLINE_POINTS: usize = 201;

/// (z, outer radius) along `bat`, m, at [`OUTLINE_POINTS`] even steps from knob to end.
fn outline(bat: &Bat) -> Vec<(f64, f64)> {
    let length = bat.length();
    (0..OUTLINE_POINTS)
        .map(|i| {
            let z = length * i as f64 / (OUTLINE_POINTS - 1) as f64;
            (z, bat.radii_at(z).0)
        })
        .collect()
}

/// A bat ready to collide.
struct PreparedBat {
    bat: Bat,
    modes: ModeSet,
    /// The node's collision options: every reported number comes from these.
    options: CollisionOptions,
    /// The search's: [`search_options`].
    search: CollisionOptions,
    /// Collisions run with `search`, and with `options`.
    counts: [AtomicUsize; 2],
}

impl PreparedBat {
    fn new(bat: Bat, modes: ModeSet, options: CollisionOptions) -> PreparedBat {
        let search = search_options(&bat, &modes, options);
        PreparedBat { bat, modes, options, search, counts: Default::default() }
    }
}

/// Largest factor by which the search lengthens the time step.
const SEARCH_STEP_FACTOR: usize = 4;

/// The collision options the search for a solution runs with: `options` with the time step lengthened up to
/// [`SEARCH_STEP_FACTOR`] times, as far as RK4 stays stable for every mode and for the wall's hoop mode over
/// the barrel half. The search (root brackets, the launch-angle start, Levenberg–Marquardt to near
/// convergence, the sweet spot at the solution's undercut) makes ~90 % of a swing's collisions, and its
/// answers only have to lie close to the node's: on the R161 at 4 × 5 µs the exit speed moves by ~10⁻⁴ m/s and
/// the launch angle by ~10⁻⁴ °, a few ten-thousandths of the trackers' σ, so Levenberg–Marquardt finishes
/// with `options` in one or two steps and every reported number is the node's model.
fn search_options(bat: &Bat, modes: &ModeSet, options: CollisionOptions) -> CollisionOptions {
    let (lo, hi) = (SEARCH_FROM * bat.length(), bat.length() - END_GAP);
    for factor in (2..=SEARCH_STEP_FACTOR).rev() {
        let candidate = CollisionOptions { time_step: options.time_step * factor as f64, ..options };
        let stable = candidate.validate(modes).is_ok()
            && (0..=64).all(|i| {
                let z = lo + (hi - lo) * i as f64 / 64.0;
                modes.hoop_at(z).is_none_or(|hoop| candidate.validate_hoop(&hoop, z).is_ok())
            });
        if stable {
            return candidate;
        }
    }
    options
}

/// The model of one swing with z and D free.
struct SwingModel<'a> {
    bat: &'a PreparedBat,
    /// The collision options this model integrates with (the bat's `options` or its `search`).
    options: &'a CollisionOptions,
    ball: Ball,
    contact: TangentialContact,
    input: SwingInput,
}

/// The model's exit speed, launch angle and spin (as the tracker's is compared), and the ball's direction.
#[derive(Debug, Clone, Copy)]
struct Prediction {
    /// Exit speed (m/s), launch angle (rad), spin (rad/s).
    values: [f64; 3],
    /// Spray angle, rad, positive toward right field.
    spray_angle: f64,
    /// Spin axis (TrackMan's HitSpinAxis), rad.
    spin_axis: f64,
}

impl Prediction {
    /// A planar swing's: toward centre field, spin about the horizontal axis across the flight.
    fn planar(values: [f64; 3]) -> Prediction {
        let spin_axis = if values[2] >= 0.0 { std::f64::consts::PI } else { 0.0 };
        Prediction { values, spray_angle: 0.0, spin_axis }
    }
}

/// A Levenberg–Marquardt solution: (z, D), Cov(z, D), and the model's exit speed, launch angle and spin there.
struct Fit {
    z: f64,
    d: f64,
    cov: [[f64; 2]; 2],
    prediction: [f64; 3],
    /// Jacobian of the weighted residuals (rows: the measured quantities; columns: z, D) the fit ended with.
    jacobian: Vec<[f64; 2]>,
}

/// Levenberg–Marquardt stops the search's fit when χ² falls below the first (the residuals at 10⁻⁴ σ) or a
/// step gains less than the second share of χ²: the finish with the node's options starts there.
const SEARCH_CONVERGED: (f64, f64) = (1e-8, 1e-6);
/// …and the finish at these (the residuals at 10⁻⁶ σ, sub-µm/s in exit speed; a solution needs χ² ≤ 10⁻⁶
/// to count as reproducing the measurements).
const FINAL_CONVERGED: (f64, f64) = (1e-12, 1e-8);

impl SwingModel<'_> {
    /// The same swing integrated with the bat's search options.
    fn searching(&self) -> SwingModel<'_> {
        SwingModel { options: &self.bat.search, ..*self }
    }

    /// Exit speed, launch angle and spin at impact point `z` and undercut `d`.
    fn predict(&self, z: f64, d: f64) -> Result<[f64; 3], PhysicsError> {
        self.predict_scaled(z, d, 1.0)
    }

    /// Exit speed, launch angle and spin at impact point `z`, undercut `d` and the swing's bat speeds (centre
    /// of mass and angular together, so the pivot stays) times `scale`.
    fn predict_scaled(&self, z: f64, d: f64, scale: f64) -> Result<[f64; 3], PhysicsError> {
        self.predict_full(z, d, scale).map(|p| p.values)
    }

    /// Whether the swing's solutions carry a [`Direction`]: a swing in three dimensions, or one whose spray
    /// angle or spin axis was measured.
    fn reports_direction(&self) -> bool {
        !self.is_planar() || self.input.measured_spray_angle.is_finite() || self.input.measured_spin_axis.is_finite()
    }

    /// Whether the swing lies in one vertical plane (level bat, path toward centre field): the planar model's.
    fn is_planar(&self) -> bool {
        self.input.bat_tilt == 0.0 && self.input.swing_direction == 0.0
    }

    /// [`Self::predict_scaled`] with the ball's spray angle and spin axis. A planar swing runs the planar
    /// models (head-on or oblique) exactly as before; one with a tilted bat or a path off centre runs the
    /// 3-D collision, and its spin is compared like for like: with a measured spin axis the tracker's is a
    /// radar's total spin, whose backspin part total × −cos(axis) includes the gyro spin's share, so the
    /// model's is formed the same way from its own total and axis.
    fn predict_full(&self, z: f64, d: f64, scale: f64) -> Result<Prediction, PhysicsError> {
        let searching = std::ptr::eq(self.options, &self.bat.search);
        self.bat.counts[usize::from(!searching)].fetch_add(1, Ordering::Relaxed);
        let mut input = self.input;
        input.impact.impact_z = z;
        input.undercut = d;
        // × 1.0 is exact: the unscaled swing is the recorded one bit for bit.
        input.impact.bat_cm_speed *= scale;
        input.impact.bat_angular_speed *= scale;
        if input.is_head_on() {
            let r = collide(&self.bat.modes, &self.ball, &input.impact, self.options)?;
            return Ok(Prediction::planar([r.exit_speed, 0.0, 0.0]));
        }
        let oblique = ObliqueImpact {
            impact: input.impact,
            barrel_radius: self.bat.bat.radii_at(z).0,
            undercut: d,
            attack_angle: input.attack_angle,
            pitch_angle: input.pitch_angle,
            pitch_spin: input.pitch_spin,
        };
        if self.is_planar() {
            let r = collide_oblique(&self.bat.modes, &self.ball, &oblique, &self.contact, self.options)?;
            return Ok(Prediction::planar([r.exit_speed, r.launch_angle, r.spin]));
        }
        let spatial = SpatialImpact {
            oblique,
            bat_tilt: input.bat_tilt,
            swing_direction: input.swing_direction,
            batter_side: input.batter_side,
        };
        let r = collide_spatial(&self.bat.modes, &self.ball, &spatial, &self.contact, self.options)?;
        let spin = if input.measured_spin_axis.is_finite() { -r.total_spin * r.spin_axis.cos() } else { r.backspin };
        Ok(Prediction {
            values: [r.exit_speed, r.launch_angle, spin],
            spray_angle: r.spray_angle,
            spin_axis: r.spin_axis,
        })
    }

    /// The ball's direction at (z, d) with the node's options, against the measured one.
    fn direction(&self, z: f64, d: f64) -> Option<Direction> {
        let node = SwingModel { options: &self.bat.options, ..*self };
        let p = node.predict_full(z, d, 1.0).ok()?;
        Some(Direction {
            spray_angle: p.spray_angle,
            spin_axis: p.spin_axis,
            spray_angle_residual: self.input.measured_spray_angle - p.spray_angle,
            spin_axis_residual: wrapped_difference(self.input.measured_spin_axis, p.spin_axis),
        })
    }

    /// `outcome` with each solution's [`Direction`], for a swing that [reports one](Self::reports_direction).
    fn with_direction(&self, outcome: Outcome) -> Outcome {
        if !self.reports_direction() {
            return outcome;
        }
        match outcome {
            Outcome::Located { mut solutions, favoured, squared_up } => {
                self.fill_direction(&mut solutions);
                Outcome::Located { solutions, favoured, squared_up }
            }
            Outcome::NotReproducible { reason, mut solutions } => {
                self.fill_direction(&mut solutions);
                Outcome::NotReproducible { reason, solutions }
            }
            other => other,
        }
    }

    fn fill_direction(&self, solutions: &mut [Solution]) {
        for s in solutions {
            s.direction = self.direction(s.impact_z, s.undercut);
        }
    }

    fn speed(&self, z: f64, d: f64) -> f64 {
        self.predict(z, d).map_or(f64::NAN, |p| p[0])
    }

    /// Largest |D| tried at `z`, m: 90 % of ball radius + barrel radius.
    fn reach(&self, z: f64) -> f64 {
        0.9 * (self.ball.radius + self.bat.bat.radii_at(z).0)
    }

    fn range(&self) -> (f64, f64) {
        let length = self.bat.bat.length();
        (SEARCH_FROM * length, length - END_GAP)
    }

    /// The sweet spot at undercut `d` near `guess` (the sweet spot at a nearby undercut): the maximum of v
    /// within [`NARROW_WINDOW`] of it, or within [`PEAK_WINDOW`] of the search range when it lies outside.
    fn sweet_spot_near(&self, d: f64, guess: f64) -> (f64, f64) {
        let (lo, hi) = self.range();
        let window = |h: f64| ((guess - h).max(lo), (guess + h).min(hi));
        let start = guess.clamp(lo, hi);
        let start = (start, self.speed(start, d));
        let (a, b) = window(NARROW_WINDOW);
        let narrow = self.brent_max(a, b, start, d, PEAK_TOLERANCE);
        // Brent's last point lies within about 2 tolerances of an edge only when the maximum is beyond it (or
        // the edge is the search range's own, where the wide window ends too).
        let edge = 3.0 * PEAK_TOLERANCE;
        if (narrow.0 - a > edge || a == lo) && (b - narrow.0 > edge || b == hi) {
            return narrow;
        }
        let (a, b) = window(PEAK_WINDOW * (hi - lo));
        self.brent_max(a, b, start, d, PEAK_TOLERANCE)
    }

    /// The maximum of v(·, d) on [a, b] (v unimodal there) from `start` = (z, v(z)) inside, by Brent's method:
    /// parabolic steps through the three best points, golden sections when a parabola misbehaves. A smooth
    /// peak takes about a third of the evaluations golden section alone needs for the same precision.
    /// `tolerance` (m) is the precision in z.
    fn brent_max(&self, mut a: f64, mut b: f64, start: (f64, f64), d: f64, tolerance: f64) -> (f64, f64) {
        const GOLD: f64 = 0.381_966_011_250_105_1; // (3 − √5)/2
                                                   // Minimise −v; a failed collision counts as the worst value so the search moves away from it.
        let g = |z: f64| {
            let v = self.speed(z, d);
            if v.is_finite() {
                -v
            } else {
                f64::INFINITY
            }
        };
        let (mut x, mut fx) = (start.0, if start.1.is_finite() { -start.1 } else { f64::INFINITY });
        let (mut w, mut fw, mut v, mut fv) = (x, fx, x, fx);
        let (mut e, mut step) = (0.0f64, 0.0f64);
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            let tol1 = 1e-10 * x.abs() + tolerance;
            let tol2 = 2.0 * tol1;
            if (x - m).abs() <= tol2 - 0.5 * (b - a) {
                break;
            }
            let mut golden = true;
            if e.abs() > tol1 {
                let r = (x - w) * (fx - fv);
                let mut q = (x - v) * (fx - fw);
                let mut p = (x - v) * q - (x - w) * r;
                q = 2.0 * (q - r);
                if q > 0.0 {
                    p = -p;
                }
                q = q.abs();
                let previous = e;
                e = step;
                if p.abs() < (0.5 * q * previous).abs() && p > q * (a - x) && p < q * (b - x) {
                    step = p / q;
                    let u = x + step;
                    if u - a < tol2 || b - u < tol2 {
                        step = tol1.copysign(m - x);
                    }
                    golden = false;
                }
            }
            if golden {
                e = if x >= m { a - x } else { b - x };
                step = GOLD * e;
            }
            let u = if step.abs() >= tol1 { x + step } else { x + tol1.copysign(step) };
            let fu = g(u);
            if fu <= fx {
                if u >= x {
                    a = x;
                } else {
                    b = x;
                }
                (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
            } else {
                if u < x {
                    a = u;
                } else {
                    b = u;
                }
                if fu <= fw || w == x {
                    (v, fv, w, fw) = (w, fw, u, fu);
                } else if fu <= fv || v == x || v == w {
                    (v, fv) = (u, fu);
                }
            }
        }
        (x, if fx.is_finite() { -fx } else { f64::NAN })
    }

    fn refine_peak(&self, grid: &[f64], speeds: &[f64], d: f64, tolerance: f64) -> (f64, f64) {
        let best = (0..grid.len()).filter(|&i| speeds[i].is_finite()).max_by(|&a, &b| speeds[a].total_cmp(&speeds[b]));
        let Some(best) = best else { return (f64::NAN, f64::NAN) };
        let (a, b) = (grid[best.saturating_sub(1)], grid[(best + 1).min(grid.len() - 1)]);
        self.brent_max(a, b, (grid[best], speeds[best]), d, tolerance)
    }

    /// Every z in the search range with v(z, d) = target, by grid bracketing and regula falsi, each to
    /// |v − target| < `tolerance` (m/s); with the peak, located to `peak_tolerance` (m).
    fn speed_roots(&self, target: f64, d: f64, tolerance: f64, peak_tolerance: f64) -> (Vec<f64>, (f64, f64)) {
        let (lo, hi) = self.range();
        let mut grid: Vec<f64> =
            (0..GRID_POINTS).map(|i| lo + (hi - lo) * i as f64 / (GRID_POINTS - 1) as f64).collect();
        let mut speeds: Vec<f64> = grid.iter().map(|&z| self.speed(z, d)).collect();
        let peak = self.refine_peak(&grid, &speeds, d, peak_tolerance);
        if peak.0.is_finite() {
            let at = grid.partition_point(|&z| z < peak.0);
            grid.insert(at, peak.0);
            speeds.insert(at, peak.1);
        }
        let mut roots = Vec::new();
        for i in 1..grid.len() {
            let (fa, fb) = (speeds[i - 1] - target, speeds[i] - target);
            if !(fa.is_finite() && fb.is_finite()) || fa.signum() == fb.signum() && fb != 0.0 {
                continue;
            }
            // Regula falsi with the Illinois modification: superlinear, and the bracket is never lost.
            let (mut a, mut b, mut f_a, mut f_b) = (grid[i - 1], grid[i], fa, fb);
            let mut side = 0i8;
            let mut root = 0.5 * (a + b);
            for _ in 0..60 {
                if f_a == f_b {
                    break;
                }
                root = (a * f_b - b * f_a) / (f_b - f_a);
                let f = self.speed(root, d) - target;
                if f == 0.0 || (b - a) < 1e-9 || !f.is_finite() {
                    break;
                }
                if f.signum() == f_b.signum() {
                    b = root;
                    f_b = f;
                    if side == -1 {
                        f_a *= 0.5;
                    }
                    side = -1;
                } else {
                    a = root;
                    f_a = f;
                    if side == 1 {
                        f_b *= 0.5;
                    }
                    side = 1;
                }
                if f.abs() < tolerance {
                    break;
                }
            }
            roots.push(root);
        }
        (roots, peak)
    }

    /// The undercut near which the launch angle at `z` is `target`, rad: secant steps from `d0` and
    /// `d0` + 5 mm, kept within reach (the launch angle rises with the undercut); a start for [`Self::fit`],
    /// which refines z and D together.
    fn undercut_for_launch_angle(&self, z: f64, d0: f64, target: f64) -> f64 {
        let reach = self.reach(z);
        let theta = |d: f64| self.predict(z, d).map_or(f64::NAN, |p| p[1] - target);
        let mut a = d0.clamp(-reach, reach);
        let mut b = if a + 0.005 <= reach { a + 0.005 } else { a - 0.005 };
        let (mut fa, mut fb) = (theta(a), theta(b));
        for _ in 0..4 {
            if !(fa.is_finite() && fb.is_finite()) || fa == fb {
                break;
            }
            let next = (b - fb * (b - a) / (fb - fa)).clamp(-reach, reach);
            if (next - b).abs() < 1e-4 {
                return next;
            }
            (a, fa) = (b, fb);
            b = next;
            fb = theta(b);
        }
        if fb.is_finite() {
            b
        } else if fa.is_finite() {
            a
        } else {
            d0
        }
    }

    /// Weighted residuals of the measured quantities at (z, d).
    fn residuals(&self, z: f64, d: f64, measured: &[f64; 3], sigma: &[f64; 3]) -> Option<Vec<f64>> {
        self.evaluate(z, d, measured, sigma).map(|(r, _)| r)
    }

    /// Weighted residuals of the measured quantities at (z, d), and the prediction they come from.
    fn evaluate(&self, z: f64, d: f64, measured: &[f64; 3], sigma: &[f64; 3]) -> Option<(Vec<f64>, [f64; 3])> {
        let p = self.predict(z, d).ok()?;
        Some(((0..3).filter(|&k| measured[k].is_finite()).map(|k| (p[k] - measured[k]) / sigma[k]).collect(), p))
    }

    /// Levenberg–Marquardt in (z, D) from `start`, z kept in the search range and |D| within reach, until χ²
    /// falls below `converged.0`, the step below 10 nm, or a step gains less than `converged.1` of χ² (with
    /// more measurements than unknowns χ² keeps a minimum above 0; a Gauss–Newton step's gain is about what
    /// is left to gain before it, and far more than what is left after it). With `exact_covariance` the covariance is that of
    /// the Jacobian at the solution, else of the last one computed (at most a step away).
    /// `jacobian_at_start`, when given, stands in for the first Jacobian (the search's, from its own fit: it
    /// differs from this model's by ~10⁻⁵ of itself, so one step from the search's solution converges).
    fn fit(
        &self,
        start: (f64, f64),
        jacobian_at_start: Option<Vec<[f64; 2]>>,
        measured: &[f64; 3],
        sigma: &[f64; 3],
        converged: (f64, f64),
        exact_covariance: bool,
    ) -> Option<Fit> {
        let (lo, hi) = self.range();
        let clamp = |z: f64, d: f64| {
            let z = z.clamp(lo, hi);
            let reach = self.reach(z);
            (z, d.clamp(-reach, reach))
        };
        let (mut z, mut d) = clamp(start.0, start.1);
        let (mut r, mut prediction) = self.evaluate(z, d, measured, sigma)?;
        let cost = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>();
        let mut lambda = 1e-3;
        let (hz, hd) = (1e-5, 1e-6);
        let jacobian = |z: f64, d: f64, r: &[f64]| -> Option<Vec<[f64; 2]>> {
            let rz = self.residuals(z + hz, d, measured, sigma)?;
            let rd = self.residuals(z, d + hd, measured, sigma)?;
            Some((0..r.len()).map(|i| [(rz[i] - r[i]) / hz, (rd[i] - r[i]) / hd]).collect())
        };
        // Whether `jac` was computed at (z, d).
        let mut fresh = false;
        let mut jac = match jacobian_at_start {
            Some(j) if j.len() == r.len() => j,
            _ => {
                fresh = true;
                jacobian(z, d, &r)?
            }
        };
        for _ in 0..100 {
            if cost(&r) < converged.0 {
                break;
            }
            let a = normal2(&jac);
            let mut g = [0.0; 2];
            for (row, ri) in jac.iter().zip(&r) {
                for p in 0..2 {
                    g[p] += row[p] * ri;
                }
            }
            let (step_z, step_d) = damped_step(&a, &g, lambda)?;
            let (nz, nd) = clamp(z + step_z, d + step_d);
            match self.evaluate(nz, nd, measured, sigma) {
                Some((nr, np)) if cost(&nr) < cost(&r) => {
                    let moved = (nz - z).abs().max((nd - d).abs());
                    let gained = cost(&r) - cost(&nr);
                    z = nz;
                    d = nd;
                    r = nr;
                    prediction = np;
                    fresh = false;
                    lambda = (lambda * 0.3).max(1e-9);
                    if moved < 1e-8 || cost(&r) < converged.0 || gained <= converged.1 * cost(&r) {
                        break;
                    }
                    jac = jacobian(z, d, &r)?;
                    fresh = true;
                }
                _ => {
                    lambda *= 10.0;
                    if lambda > 1e10 {
                        break;
                    }
                }
            }
        }
        if exact_covariance && !fresh {
            jac = jacobian(z, d, &r)?;
        }
        Some(Fit { z, d, cov: covariance2(&jac), prediction, jacobian: jac })
    }
}

/// The Levenberg–Marquardt step −(A + λ·diag A)⁻¹ g for the normal matrix A = JᵀJ and gradient g = Jᵀr of two
/// unknowns; None when the damped matrix is singular.
fn damped_step(a: &[[f64; 2]; 2], g: &[f64; 2], lambda: f64) -> Option<(f64, f64)> {
    let damped = [[a[0][0] * (1.0 + lambda), a[0][1]], [a[1][0], a[1][1] * (1.0 + lambda)]];
    let det = damped[0][0] * damped[1][1] - damped[0][1] * damped[1][0];
    if det == 0.0 || det.is_nan() {
        return None;
    }
    Some((-(damped[1][1] * g[0] - damped[0][1] * g[1]) / det, -(damped[0][0] * g[1] - damped[1][0] * g[0]) / det))
}

/// (JᵀJ)⁻¹ of a Jacobian of weighted residuals with two columns: the covariance of the two unknowns (infinite
/// when JᵀJ is singular).
fn covariance2(jac: &[[f64; 2]]) -> [[f64; 2]; 2] {
    let a = normal2(jac);
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    if det.abs() > 0.0 {
        [[a[1][1] / det, -a[0][1] / det], [-a[1][0] / det, a[0][0] / det]]
    } else {
        [[f64::INFINITY; 2]; 2]
    }
}

/// JᵀJ of a Jacobian with two columns.
fn normal2(jac: &[[f64; 2]]) -> [[f64; 2]; 2] {
    let mut a = [[0.0; 2]; 2];
    for row in jac {
        for p in 0..2 {
            for q in 0..2 {
                a[p][q] += row[p] * row[q];
            }
        }
    }
    a
}

/// Largest χ² per degree of freedom of a located solution, when there are more measurements than unknowns
/// (exit speed, launch angle and spin for z and D: one degree of freedom). A model that reproduces a ball
/// within the trackers' accuracy leaves χ² distributed as χ² with that many degrees of freedom, about 1 per
/// degree; with one, χ² > 9 (a residual past 3σ) happens by tracker noise alone for 0.27 % of balls, so a
/// larger χ² says the model does not reproduce the ball.
pub const MAX_CHI2_PER_DOF: f64 = 9.0;
/// Largest standard uncertainty of a located impact point, as a share of the barrel searched (L/2 to
/// L − [`END_GAP`], 0.415 m on an 84-cm bat): a ±1σ interval no wider than the barrel itself. A wider one
/// says nothing the bat's length does not: the measurements do not place the ball on the barrel (a linearised
/// σ that large is where the exit speed barely changes with z — at the sweet spot — or the undercut barely
/// changes the launch angle).
pub const MAX_Z_SIGMA_SHARE: f64 = 0.5;

/// Why `solution` is not located, if it is not: it misses the measurements by more than [`MAX_CHI2_PER_DOF`]
/// allows (with `unknowns` fitted), or its impact point is uncertain beyond [`MAX_Z_SIGMA_SHARE`] of the barrel.
fn unreproduced(
    solution: &Solution,
    model: &SwingModel<'_>,
    measured: &[f64; 3],
    sigma: &[f64; 3],
    unknowns: usize,
) -> Option<String> {
    // With z alone only the exit speed is fitted; with z and D every measured quantity.
    let used: Vec<usize> = if unknowns == 1 { vec![0] } else { (0..3).filter(|&k| measured[k].is_finite()).collect() };
    let dof = used.len().saturating_sub(unknowns);
    let at = format!("z = {:.3} m, D = {:+.1} mm", solution.impact_z, solution.undercut * 1e3);
    // A NaN χ² or σ is no fit: both tests let only a number within the bound pass.
    let within = |value: f64, bound: f64| value.is_finite() && value <= bound;
    if dof > 0 && !within(solution.chi2, MAX_CHI2_PER_DOF * dof as f64) {
        let names = ["exit speed", "launch angle", "spin"];
        let show = |k: usize, v: f64| match k {
            0 => format!("{v:.1} m/s"),
            1 => format!("{:.1}°", v.to_degrees()),
            _ => format!("{:.0} rpm", v * 60.0 / (2.0 * std::f64::consts::PI)),
        };
        let misses: Vec<String> = used
            .iter()
            .map(|&k| {
                format!(
                    "{} {} against {} measured ({:+.1}σ)",
                    names[k],
                    show(k, solution.model[k]),
                    show(k, measured[k]),
                    (solution.model[k] - measured[k]) / sigma[k]
                )
            })
            .collect();
        return Some(format!(
            "the closest fit ({at}) misses the measurements by χ² = {:.1} on {dof} degree(s) of freedom, more \
             than the {:.0} per degree tracker accuracy allows: {}",
            solution.chi2,
            MAX_CHI2_PER_DOF,
            misses.join(", ")
        ));
    }
    let (lo, hi) = model.range();
    let bound = MAX_Z_SIGMA_SHARE * (hi - lo);
    if !within(solution.impact_z_sigma, bound) {
        return Some(format!(
            "at {at} the impact point is uncertain by σ = {:.3} m, more than half the barrel searched ({bound:.3} \
             m): the measurements do not place the ball on the bat",
            solution.impact_z_sigma
        ));
    }
    None
}

/// The solutions that are located, and for a swing none of whose solutions is, the outcome that says why
/// (the reason of the closest, every solution listed).
fn sort_out(
    solutions: Vec<Solution>,
    model: &SwingModel<'_>,
    measured: &[f64; 3],
    sigma: &[f64; 3],
    unknowns: usize,
) -> (Vec<Solution>, Option<Outcome>) {
    let mut kept = Vec::new();
    let mut refused: Vec<(Solution, String)> = Vec::new();
    for s in solutions {
        match unreproduced(&s, model, measured, sigma, unknowns) {
            None => kept.push(s),
            Some(reason) => refused.push((s, reason)),
        }
    }
    if !kept.is_empty() || refused.is_empty() {
        return (kept, None);
    }
    refused.sort_by(|a, b| a.0.chi2.total_cmp(&b.0.chi2));
    let reason = refused[0].1.clone();
    let mut solutions: Vec<Solution> = refused.into_iter().map(|(s, _)| s).collect();
    solutions.sort_by(|a, b| a.impact_z.total_cmp(&b.impact_z));
    (kept, Some(Outcome::NotReproducible { reason, solutions }))
}

/// The measured exit speed, launch angle and backspin of a swing (a radar's total spin times −cos of its
/// measured axis: [`SwingInput::measured_backspin`]); NaN = not measured.
fn measured_of(swing: &Swing) -> [f64; 3] {
    [swing.measured_exit_speed, swing.measured_launch_angle, swing_input(swing).measured_backspin()]
}

/// Locates one swing.
fn locate_swing(model: &SwingModel<'_>, swing: &Swing, options: &LocateOptions) -> Outcome {
    let measured = measured_of(swing);
    let sigma = [options.exit_speed_sigma, options.launch_angle_sigma, options.spin_sigma];
    if !measured[0].is_finite() {
        return Outcome::NotMeasured;
    }
    let d0 = if swing.undercut.is_finite() { swing.undercut } else { 0.0 };
    let free_d = measured[1].is_finite();
    // A root is the answer when only z is free, found with the node's options; with D free it is where the
    // search starts (with the search's options), and 1 mm/s (tens of µm in z) is start enough.
    let (roots, peak) = if free_d {
        model.searching().speed_roots(measured[0], d0, 1e-3, GUESS_TOLERANCE)
    } else {
        model.speed_roots(measured[0], d0, 1e-12, PEAK_TOLERANCE)
    };
    if !peak.1.is_finite() {
        return Outcome::Failed { reason: "the model gives no exit speed anywhere on the barrel".into() };
    }
    let problem = Problem { model, measured, sigma, d0 };
    let solutions = if free_d { problem.with_undercut(&roots, peak) } else { problem.along_barrel(roots, peak) };
    match solutions {
        Ok(solutions) => located(solutions),
        Err(outcome) => outcome,
    }
}

/// One swing's measurements against the model: what [`locate_swing`]'s two searches share.
struct Problem<'m, 'a> {
    model: &'m SwingModel<'a>,
    /// Measured exit speed, launch angle and backspin ([`measured_of`]).
    measured: [f64; 3],
    /// Their accuracies.
    sigma: [f64; 3],
    /// The swing's undercut (0 if not given), m.
    d0: f64,
}

impl Problem<'_, '_> {
    /// z alone, at the swing's undercut: each root of v(z) = v_m (`roots`, with the sweet spot `peak` = (z*,
    /// v*)) is a solution; the located ones, or the outcome that says why there is none.
    fn along_barrel(&self, roots: Vec<f64>, (peak_z, peak_v): (f64, f64)) -> Result<Vec<Solution>, Outcome> {
        let (model, measured, sigma, d0) = (self.model, &self.measured, &self.sigma, self.d0);
        if roots.is_empty() {
            return Err(Outcome::TooFast {
                max_exit_speed: peak_v,
                excess: measured[0] - peak_v,
                sweet_spot_z: peak_z,
            });
        }
        let mut solutions = Vec::new();
        for z in roots {
            let h = 1e-4;
            let slope = (model.speed(z + h, d0) - model.speed(z - h, d0)) / (2.0 * h);
            let p = model.predict(z, d0).unwrap_or([f64::NAN; 3]);
            solutions.push(Solution {
                impact_z: z,
                impact_z_sigma: sigma[0] / slope.abs(),
                undercut: d0,
                undercut_sigma: 0.0,
                undercut_fitted: false,
                side: if z < peak_z { Side::Handle } else { Side::End },
                sweet_spot_z: peak_z,
                chi2: ((p[0] - measured[0]) / sigma[0]).powi(2),
                model: p,
                direction: None,
            });
        }
        let (kept, unreproduced) = sort_out(solutions, model, measured, sigma, 1);
        match unreproduced {
            Some(outcome) => Err(outcome),
            None => Ok(kept),
        }
    }

    /// z and D together, from each root of the search's v(z) = v_m at the swing's undercut (or the sweet spot
    /// `peak` when there is none): the located solutions, or the outcome that says why there is none.
    fn with_undercut(&self, roots: &[f64], (peak_z, peak_v): (f64, f64)) -> Result<Vec<Solution>, Outcome> {
        let (model, measured, sigma) = (self.model, &self.measured, &self.sigma);
        let search = model.searching();
        // Starting undercuts: at each root, the one that gives the measured launch angle (secant steps); with
        // no root at the swing's undercut (faster than its sweet spot), the undercuts across the reach at the
        // sweet spot, which also give the largest exit speed any undercut tried reaches.
        let starts: Vec<f64> = if roots.is_empty() { vec![peak_z] } else { roots.to_vec() };
        // The fastest (v, z, D) the search saw, for the report of a ball too fast for any of them.
        let mut fastest = (peak_v, peak_z, self.d0);
        // The closest miss (χ², z, D), for the report when nothing reproduces the measurements.
        let mut closest: Option<(f64, f64, f64)> = None;
        let mut solutions: Vec<Solution> = Vec::new();
        for &z in &starts {
            let start_d = if roots.is_empty() {
                self.fastest_undercut(&search, z, &mut fastest)
            } else {
                search.undercut_for_launch_angle(z, self.d0, measured[1])
            };
            let Some((fit, chi2)) = self.fit_from(&search, (z, start_d), &mut closest) else { continue };
            if solutions.iter().any(|s| (s.impact_z - fit.z).abs() < 1e-3 && (s.undercut - fit.d).abs() < 1e-3) {
                continue;
            }
            // The search's sweet spot: its exit speed differs from the node's by a smooth ~10⁻⁴ m/s, which
            // moves the peak by under a µm, well inside PEAK_TOLERANCE (the unit tests below compare them).
            let (sweet, _) = search.sweet_spot_near(fit.d, peak_z);
            solutions.push(Solution {
                impact_z: fit.z,
                impact_z_sigma: fit.cov[0][0].sqrt(),
                undercut: fit.d,
                undercut_sigma: fit.cov[1][1].sqrt(),
                undercut_fitted: true,
                side: if fit.z < sweet { Side::Handle } else { Side::End },
                sweet_spot_z: sweet,
                chi2,
                model: fit.prediction,
                direction: None,
            });
        }
        let (kept, unreproduced) = sort_out(solutions, model, measured, sigma, 2);
        if !kept.is_empty() {
            return Ok(kept);
        }
        // The sweet spot at the fastest undercut the search found, with the node's options (a rare case:
        // the search's sweet spot is located only to GUESS_TOLERANCE).
        let (_, guess_z, fastest_d) = fastest;
        let (max_z, max_v) = model.sweet_spot_near(fastest_d, guess_z);
        let (max_z, max_v) = if max_v.is_finite() { (max_z, max_v) } else { (guess_z, fastest.0) };
        if measured[0] > max_v {
            return Err(Outcome::TooFast { max_exit_speed: max_v, excess: measured[0] - max_v, sweet_spot_z: max_z });
        }
        if let Some(outcome) = unreproduced {
            return Err(outcome);
        }
        let closest = closest.map_or(String::new(), |(chi2, z, d)| {
            format!(" (closest: χ² = {chi2:.2} at z = {z:.3} m, D = {:+.1} mm)", d * 1e3)
        });
        Err(Outcome::Failed {
            reason: format!("no impact point and undercut reproduce the exit speed and launch angle together{closest}"),
        })
    }

    /// The undercut across the reach at `z` whose launch angle and exit speed come closest to the measured
    /// ones (17 tried), raising `fastest` (v, z, D) to the fastest of them.
    fn fastest_undercut(&self, search: &SwingModel<'_>, z: f64, fastest: &mut (f64, f64, f64)) -> f64 {
        let (measured, sigma) = (&self.measured, &self.sigma);
        let reach = self.model.reach(z);
        let mut best = (f64::INFINITY, self.d0);
        for k in 0..=16 {
            let d = -reach + 2.0 * reach * k as f64 / 16.0;
            if let Ok(p) = search.predict(z, d) {
                if p[0] > fastest.0 {
                    *fastest = (p[0], z, d);
                }
                let miss = ((p[1] - measured[1]) / sigma[1]).abs() + ((p[0] - measured[0]) / sigma[0]).abs();
                if miss < best.0 {
                    best = (miss, d);
                }
            }
        }
        best.1
    }

    /// The search's fit from `start`, finished with the node's options (from the start itself if the search's
    /// failed), and its χ²: a solution when it reproduces the measurements as well as its degrees of freedom
    /// allow, lowering `closest` (χ², z, D) to the closest miss.
    fn fit_from(
        &self,
        search: &SwingModel<'_>,
        start: (f64, f64),
        closest: &mut Option<(f64, f64, f64)>,
    ) -> Option<(Fit, f64)> {
        let (measured, sigma) = (&self.measured, &self.sigma);
        let (near, jacobian) = match search.fit(start, None, measured, sigma, SEARCH_CONVERGED, false) {
            Some(f) => ((f.z, f.d), Some(f.jacobian)),
            None => (start, None),
        };
        let fit = self.model.fit(near, jacobian, measured, sigma, FINAL_CONVERGED, true)?;
        let r: Vec<f64> =
            (0..3).filter(|&k| measured[k].is_finite()).map(|k| (fit.prediction[k] - measured[k]) / sigma[k]).collect();
        let chi2 = r.iter().map(|x| x * x).sum::<f64>();
        // As many unknowns as measurements (or fewer): a solution reproduces them all.
        let dof_fit = r.len() <= 2;
        if chi2.is_finite() && closest.is_none_or(|(c, _, _)| chi2 < c) {
            *closest = Some((chi2, fit.z, fit.d));
        }
        if dof_fit && chi2 > 1e-6 || !chi2.is_finite() {
            return None;
        }
        Some((fit, chi2))
    }
}

/// The located outcome of `solutions` (at least one): sorted handle side first, the favoured one (if the
/// measurements favour one: χ² lower by more than 1) and whether the swing was squared up.
fn located(mut solutions: Vec<Solution>) -> Outcome {
    solutions.sort_by(|a, b| a.impact_z.total_cmp(&b.impact_z));
    let favoured = if solutions.len() == 1 {
        Some(0)
    } else {
        let mut order: Vec<usize> = (0..solutions.len()).collect();
        order.sort_by(|&a, &b| solutions[a].chi2.total_cmp(&solutions[b].chi2));
        (solutions[order[1]].chi2 - solutions[order[0]].chi2 > 1.0).then_some(order[0])
    };
    let near = |s: &Solution| (s.impact_z - s.sweet_spot_z).abs() <= SQUARED_UP;
    let squared_up = match favoured {
        Some(i) => near(&solutions[i]),
        None => solutions.iter().all(near),
    };
    Outcome::Located { solutions, favoured, squared_up }
}

/// Errors of `locate`.
#[derive(Debug, thiserror::Error)]
pub enum LocateError {
    /// Reading the bag failed.
    #[error("{0}")]
    Read(#[from] CalibrateError),
    /// Nothing to locate.
    #[error("{0}")]
    NoData(String),
    /// The import side table could not be read.
    #[error("{0}")]
    SideTable(String),
}

/// The swings whose bat speed the import assumed, from the bag's [`ROWS_TABLE`]; None without the table.
pub fn assumed_bat_speeds(bag: &Path) -> Result<Option<BTreeSet<u64>>, LocateError> {
    let path = bag.join(ROWS_TABLE);
    if !path.is_file() {
        return Ok(None);
    }
    let fail = |m: String| LocateError::SideTable(format!("'{}': {m}", path.display()));
    let mut reader = csv::Reader::from_path(&path).map_err(|e| fail(e.to_string()))?;
    let headers = reader.headers().map_err(|e| fail(e.to_string()))?.clone();
    let column = |name: &str| headers.iter().position(|h| h == name);
    let (Some(id_col), Some(assumed_col)) = (column("swing_id"), column("assumed")) else {
        return Err(fail("expected columns swing_id and assumed".into()));
    };
    let mut set = BTreeSet::new();
    for (i, record) in reader.records().enumerate() {
        let record = record.map_err(|e| fail(format!("line {}: {e}", i + 2)))?;
        let Some(id) = record.get(id_col).and_then(|t| t.parse::<u64>().ok()) else {
            return Err(fail(format!("line {}: swing_id is not a number", i + 2)));
        };
        if record.get(assumed_col).is_some_and(|a| a.split(';').any(|n| n == "bat_speed")) {
            set.insert(id);
        }
    }
    Ok(Some(set))
}

/// Locates every swing of a bag (swings in parallel).
pub fn locate_bag(path: &Path, options: &LocateOptions) -> Result<LocateReport, LocateError> {
    locate_bag_with_progress(path, options, &|_, _| {})
}

/// [`locate_bag`], calling `progress(done, total)` as each swing is done (from the worker threads).
pub fn locate_bag_with_progress(
    path: &Path,
    options: &LocateOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<LocateReport, LocateError> {
    let inputs = read_inputs(path)?;
    if inputs.swings.is_empty() {
        return Err(LocateError::NoData(format!("{}: the bag holds no Swing messages", path.display())));
    }
    // Read only when fitting, so a plain `locate` is untouched by the side table.
    let assumed = if options.fit_bat_speed { assumed_bat_speeds(path)? } else { None };
    Ok(locate_recorded(&inputs, assumed.as_ref(), options, progress))
}

/// Locates an export's swings built in memory ([`crate::import::import_table`] with `import`'s options) as
/// [`locate_bag`] locates the bag `sweetspot import` writes of them: the same bat and ball params, the
/// settings the bag names, the swings in row order, the bat speeds `import` assumed.
pub fn locate_imported(
    imported: &ImportedSwings,
    import: &ImportOptions,
    options: &LocateOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> LocateReport {
    // Log times only order the messages: the params first, then the swings as the rows came.
    let inputs = RecordedInputs {
        bats: vec![(0, import.bat_params.clone())],
        balls: vec![(1, import.ball_params.clone())],
        swings: imported.swings.iter().enumerate().map(|(i, s)| (2 + i as u64, s.swing.clone())).collect(),
        settings: crate::import::bag_settings(),
    };
    let assumed: BTreeSet<u64> =
        imported.swings.iter().filter(|s| s.assumed.bat_speed).map(|s| s.swing.swing_id).collect();
    locate_recorded(&inputs, Some(&assumed), options, progress)
}

/// Locates recorded swings against the bats and balls recorded with them (swings in parallel);
/// `assumed` names the swings whose bat speed the import assumed (None: unknown, as for a bag without the
/// side table), which [`LocateOptions::fit_bat_speed`] fits.
pub fn locate_recorded(
    inputs: &RecordedInputs,
    assumed: Option<&BTreeSet<u64>>,
    options: &LocateOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> LocateReport {
    let mut models = Models::recorded(inputs);
    let jobs = models.jobs(inputs);
    let done = AtomicUsize::new(0);
    let swings: Vec<Located> = jobs
        .par_iter()
        .map(|(swing, bat_id, ball_id)| {
            let located = models.locate(swing, bat_id, ball_id, assumed, options);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, jobs.len());
            located
        })
        .collect();
    models.report(swings, options)
}

/// The bats (prepared, or why not) and balls swings are located against, by id.
struct Models<'i> {
    inputs: &'i RecordedInputs,
    bats: BTreeMap<String, Result<PreparedBat, String>>,
    balls: BTreeMap<String, BallModel>,
}

impl<'i> Models<'i> {
    /// The recorded bats and balls (the last version of each id, as calibrate reads them), and the built-in
    /// balls, which answer to their names without params, as in the node.
    fn recorded(inputs: &'i RecordedInputs) -> Models<'i> {
        let mut models = Models { inputs, bats: BTreeMap::new(), balls: BTreeMap::new() };
        for (_, params) in &inputs.bats {
            let prepared = problem_bat(params, &inputs.settings).and_then(|pb| models.prepare(pb.bat, pb.modes));
            models.bats.insert(params.bat_id.clone(), prepared);
        }
        for name in Ball::preset_names() {
            if let Ok(ball) = Ball::preset(name) {
                models.balls.insert(name.to_string(), ball.into());
            }
        }
        for (_, params) in &inputs.balls {
            if let Ok(ball) = ball_from_params(params) {
                models.balls.insert(params.ball_id.clone(), ball);
            }
        }
        models
    }

    /// `bat` with its modes solved, at the recorded time step.
    fn prepare(&self, bat: Bat, modes: usize) -> Result<PreparedBat, String> {
        let set = ModeSet::compute(&bat, modes).map_err(|e| e.to_string())?;
        Ok(PreparedBat::new(bat, set, CollisionOptions { modes, time_step: self.inputs.settings.time_step }))
    }

    /// Every swing with the bat and ball ids in force for it (an empty id: the last params before it, else
    /// the default), preparing the preset bats swings name without params.
    fn jobs(&mut self, inputs: &'i RecordedInputs) -> Vec<(&'i Swing, String, String)> {
        let settings = &inputs.settings;
        let latest =
            |list: &[(u64, String)], t: u64| list.iter().rev().find(|(lt, _)| *lt <= t).map(|(_, id)| id.clone());
        let bat_times: Vec<(u64, String)> = inputs.bats.iter().map(|(t, p)| (*t, p.bat_id.clone())).collect();
        let ball_times: Vec<(u64, String)> = inputs.balls.iter().map(|(t, p)| (*t, p.ball_id.clone())).collect();
        let mut jobs = Vec::new();
        for (t, swing) in &inputs.swings {
            let bat_id = if swing.bat_id.is_empty() {
                latest(&bat_times, *t).unwrap_or_else(|| settings.default_bat.clone())
            } else {
                swing.bat_id.clone()
            };
            if !self.bats.contains_key(&bat_id) {
                let prepared = Bat::preset(&bat_id).map_err(|e| e.to_string()).and_then(|bat| {
                    let modes = settings.modes_for(&bat, None);
                    self.prepare(bat, modes)
                });
                self.bats.insert(bat_id.clone(), prepared);
            }
            let ball_id = if swing.ball_id.is_empty() {
                latest(&ball_times, *t).unwrap_or_else(|| settings.default_ball.clone())
            } else {
                swing.ball_id.clone()
            };
            jobs.push((swing, bat_id, ball_id));
        }
        jobs
    }

    /// Locates one swing (and fits its bat speed when asked).
    fn locate(
        &self,
        swing: &Swing,
        bat_id: &str,
        ball_id: &str,
        assumed: Option<&BTreeSet<u64>>,
        options: &LocateOptions,
    ) -> Located {
        let mut measured_direction = None;
        let (outcome, bat_speed_fit) = match (self.bats.get(bat_id), self.balls.get(ball_id)) {
            (Some(Ok(bat)), Some(ball)) => {
                let model = SwingModel {
                    bat,
                    options: &bat.options,
                    ball: ball.ball,
                    contact: ball.contact,
                    input: swing_input(swing),
                };
                let outcome = model.with_direction(locate_swing(&model, swing, options));
                measured_direction = model
                    .reports_direction()
                    .then_some([model.input.measured_spray_angle, model.input.measured_spin_axis]);
                let fit = options.fit_bat_speed.then(|| match assumed {
                    None => BatSpeedFit::NotFitted {
                        reason: "the bag has no import side table to say the bat speed was assumed".into(),
                    },
                    Some(set) if !set.contains(&swing.swing_id) => {
                        BatSpeedFit::NotFitted { reason: "the bat speed was measured, not assumed".into() }
                    }
                    Some(_) => fit_bat_speed(&model, swing, &outcome, options),
                });
                (outcome, fit)
            }
            (Some(Err(e)), _) => (Outcome::Failed { reason: format!("bat '{}': {e}", echo(bat_id)) }, None),
            (None, _) => (Outcome::Failed { reason: format!("unknown bat '{}'", echo(bat_id)) }, None),
            (_, None) => (Outcome::Failed { reason: format!("unknown ball '{}'", echo(ball_id)) }, None),
        };
        let bat_speed_fit = bat_speed_fit.or_else(|| {
            options.fit_bat_speed.then(|| BatSpeedFit::NotFitted { reason: "the swing cannot be simulated".into() })
        });
        Located {
            swing_id: swing.swing_id,
            bat_id: bat_id.to_string(),
            measured: measured_of(swing),
            measured_direction,
            outcome,
            bat_speed_fit,
        }
    }

    /// The report of the located `swings`: the counts, the bats' outlines and the collisions run.
    fn report(&self, swings: Vec<Located>, options: &LocateOptions) -> LocateReport {
        let located = swings.iter().filter(|s| matches!(s.outcome, Outcome::Located { .. })).count();
        let too_fast = swings.iter().filter(|s| matches!(s.outcome, Outcome::TooFast { .. })).count();
        let not_reproducible = swings.iter().filter(|s| matches!(s.outcome, Outcome::NotReproducible { .. })).count();
        let squared = swings.iter().filter(|s| matches!(s.outcome, Outcome::Located { squared_up: true, .. })).count();
        let squared_up_share = if located > 0 { squared as f64 / located as f64 } else { f64::NAN };
        let outlines =
            self.bats.iter().filter_map(|(id, b)| Some((id.clone(), outline(&b.as_ref().ok()?.bat)))).collect();
        let bat_speed_fitted = options
            .fit_bat_speed
            .then(|| swings.iter().filter(|s| matches!(s.bat_speed_fit, Some(BatSpeedFit::Fitted { .. }))).count());
        let collisions = self.bats.values().filter_map(|b| b.as_ref().ok()).fold((0, 0), |(s, f), b| {
            (s + b.counts[0].load(Ordering::Relaxed), f + b.counts[1].load(Ordering::Relaxed))
        });
        LocateReport {
            swings,
            located,
            too_fast,
            not_reproducible,
            bat_speed_fitted,
            squared_up_share,
            collisions,
            outlines,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sweetspot_physics::Impact;

    fn prepared(name: &str) -> PreparedBat {
        let bat = Bat::preset(name).expect("preset");
        let options = CollisionOptions::default();
        let modes = ModeSet::compute(&bat, options.modes).expect("modes");
        PreparedBat::new(bat, modes, options)
    }

    /// A game swing: 85-mph pitch descending 7°, 70-mph bat path 10° up, backspin on the pitch.
    fn game_swing(bat: &PreparedBat) -> SwingModel<'_> {
        let impact = Impact { ball_speed: 38.0, bat_cm_speed: 24.0, bat_angular_speed: 45.0, impact_z: 0.7 };
        let input = SwingInput {
            attack_angle: 10f64.to_radians(),
            pitch_angle: 7f64.to_radians(),
            pitch_spin: rpm_to_rad_per_s(2000.0),
            ..SwingInput::from(impact)
        };
        SwingModel { bat, options: &bat.options, ball: Ball::game(), contact: TangentialContact::default(), input }
    }

    #[test]
    fn the_search_lengthens_the_step_only_as_far_as_rk4_stays_stable() {
        // R161, 18 modes: mode 18 at 12.7 kHz allows 2.5/ω = 31 µs, so 4 × 5 µs = 20 µs is taken.
        let r161 = prepared("r161");
        assert_eq!(r161.search, CollisionOptions { time_step: 2e-5, ..r161.options });
        // At a 10-µs step, 4× (40 µs) and 3× (30 µs) pass that limit only as 3×: 30 µs ≤ 31 µs.
        let bat = Bat::preset("r161").expect("preset");
        let modes = ModeSet::compute(&bat, 18).expect("modes");
        let coarse = PreparedBat::new(bat, modes, CollisionOptions { modes: 18, time_step: 1e-5 });
        assert_eq!(coarse.search.time_step, 3.0 * 1e-5);
        // The aluminum bat's barrel wall has a hoop mode: every search step is checked against it too.
        let aluminum = prepared("aluminum");
        let (lo, hi) = (SEARCH_FROM * aluminum.bat.length(), aluminum.bat.length() - END_GAP);
        assert!(aluminum.search.time_step >= aluminum.options.time_step);
        assert!(aluminum.search.validate(&aluminum.modes).is_ok());
        for i in 0..=100 {
            let z = lo + (hi - lo) * i as f64 / 100.0;
            if let Some(hoop) = aluminum.modes.hoop_at(z) {
                assert!(aluminum.search.validate_hoop(&hoop, z).is_ok(), "z = {z}");
            }
        }
    }

    #[test]
    fn the_searchs_model_lies_within_a_thousandth_of_sigma_of_the_nodes_and_has_the_same_sweet_spot() {
        let r161 = prepared("r161");
        let node = game_swing(&r161);
        let search = node.searching();
        let sigma = LocateOptions::default();
        for d in [-0.01, 0.0, 0.01, 0.025] {
            for z in [0.45, 0.6, 0.7, 0.8, 0.83] {
                let (a, b) = (node.predict(z, d).expect("node"), search.predict(z, d).expect("search"));
                assert!((a[0] - b[0]).abs() < 1e-3 * sigma.exit_speed_sigma, "z {z}, D {d}: v {a:?} {b:?}");
                assert!((a[1] - b[1]).abs() < 1e-3 * sigma.launch_angle_sigma, "z {z}, D {d}: θ {a:?} {b:?}");
                assert!((a[2] - b[2]).abs() < 1e-3 * sigma.spin_sigma, "z {z}, D {d}: ω {a:?} {b:?}");
            }
            // Both peaks to 0.1 µm: the search's sweet spot is the node's within a micrometre.
            let peak = |m: &SwingModel<'_>| m.brent_max(0.65, 0.75, (0.7, m.speed(0.7, d)), d, 1e-7);
            let (zn, zs) = (peak(&node).0, peak(&search).0);
            assert!((zn - zs).abs() < 1e-6, "D {d}: sweet spot {zn} against {zs}");
        }
    }

    /// The bounds of "located" pinned: χ² = 9 on one degree of freedom passes and the next float above it
    /// does not; σ_z of half the barrel searched passes and the next float above it does not; with as many
    /// measurements as unknowns χ² is not judged.
    #[test]
    fn located_means_chi2_at_most_nine_per_degree_and_sigma_z_at_most_half_the_barrel() {
        let r161 = prepared("r161");
        let model = game_swing(&r161);
        let sigma = [0.45, 1f64.to_radians(), rpm_to_rad_per_s(100.0)];
        let measured = [40.0, 0.3, 200.0];
        let (lo, hi) = model.range();
        let half = MAX_Z_SIGMA_SHARE * (hi - lo);
        assert!((half - 0.5 * (0.5 * r161.bat.length() - END_GAP)).abs() < 1e-15);
        let solution = Solution {
            impact_z: 0.65,
            impact_z_sigma: 0.01,
            undercut: 0.01,
            undercut_sigma: 0.001,
            undercut_fitted: true,
            side: Side::Handle,
            sweet_spot_z: 0.7,
            chi2: 9.0,
            model: [40.0, 0.3, 200.0],
            direction: None,
        };
        let judge = |s: &Solution, measured: &[f64; 3], unknowns| unreproduced(s, &model, measured, &sigma, unknowns);
        assert_eq!(judge(&solution, &measured, 2), None);
        let missed = Solution { chi2: 9f64.next_up(), ..solution.clone() };
        let why = judge(&missed, &measured, 2).expect("past 3σ");
        assert!(why.contains("on 1 degree(s) of freedom"), "{why}");
        // Launch angle and exit speed only: two measurements, two unknowns, no χ² bound.
        assert_eq!(judge(&Solution { chi2: 1e3, ..solution.clone() }, &[40.0, 0.3, f64::NAN], 2), None);
        assert_eq!(judge(&Solution { impact_z_sigma: half, ..solution.clone() }, &measured, 2), None);
        let wide = Solution { impact_z_sigma: half.next_up(), ..solution.clone() };
        assert!(judge(&wide, &measured, 2).expect("wider than the barrel").contains("uncertain by σ"));
        let singular = Solution { impact_z_sigma: f64::INFINITY, ..solution };
        assert!(judge(&singular, &measured, 1).is_some());
    }

    /// An export located in memory is the bag `import` writes of it located: every number of the report the
    /// same, bit for bit (its JSON equal), with and without the bat-speed fit.
    #[test]
    fn an_export_located_in_memory_is_its_imported_bag_located() {
        use crate::import::{import_files, import_table, table::Table, ImportOptions};
        use sweetspot_model::convert::{params_from_ball, params_of_preset};
        use sweetspot_msgs::std_msgs::msg::Header;
        let bat = Bat::preset("r161").expect("preset");
        let import = ImportOptions {
            format: None,
            batter: sweetspot_physics::batter::Batter::typical(bat.mass_properties()).expect("batter"),
            bat,
            bat_params: params_of_preset("r161", "r161", Header::default()),
            ball_params: params_from_ball("mlb2024", &Ball::preset("mlb2024").expect("ball"), None, Header::default()),
            undercut: 0.0,
            map: None,
            tee: false,
        };
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data");
        let scratch = tempfile::tempdir().expect("scratch");
        for (export, fit_bat_speed) in [("statcast_search.csv", false), ("trackman_game.csv", true)] {
            let path = data.join(export);
            let options = LocateOptions { fit_bat_speed, ..LocateOptions::default() };
            let bag = scratch.path().join(export);
            import_files(std::slice::from_ref(&path), &bag, &import).expect("import");
            let from_bag = locate_bag(&bag, &options).expect("locate the bag");
            let imported = import_table(Table::open(&path).expect("open"), &path, &import).expect("in memory");
            let in_memory = locate_imported(&imported, &import, &options, &|_, _| {});
            let json = |r: &LocateReport| serde_json::to_string(r).expect("json");
            assert!(!from_bag.swings.is_empty(), "{export}");
            assert_eq!(json(&in_memory), json(&from_bag), "{export}");
            assert_eq!(in_memory.collisions, from_bag.collisions, "{export}");
            let lines: Vec<u64> = imported.swings.iter().map(|s| s.line).collect();
            let side_table = std::fs::read_to_string(bag.join(ROWS_TABLE)).expect("side table");
            let side_lines: Vec<u64> = csv::Reader::from_reader(side_table.as_bytes())
                .records()
                .map(|r| r.expect("row")[2].parse().expect("line"))
                .collect();
            assert_eq!(lines, side_lines, "{export}: each swing's line in the export");
        }
    }
}
