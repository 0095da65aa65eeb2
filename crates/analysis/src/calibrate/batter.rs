//! Calibration of a batter: the reference swing and the exponent n of v ∝ I^(−n) ([`sweetspot_physics::batter`])
//! fitted to the bat speeds a rig measured with several bats.
//!
//! **The data.** Every Swing of a recorded session carries the bat's centre-of-mass speed V and angular speed
//! ω the rig measured (the node's inputs). The bat speed at the batter's usual impact point — the same
//! distance d from the barrel end on every bat (6 in by default, [`DEFAULT_IMPACT_FROM_BARREL_END`]) — is
//! v_i = V_i + ω_i (L_b − d − z_cm,b), with the length L_b and centre of mass z_cm,b of the swing's bat b.
//! Bats are resolved as the exit-speed calibration resolves them ([`super::problem_from_inputs`]: recorded
//! BatParams by the node's rules, preset names, an empty bat_id = the latest accepted BatParams or else the
//! recorded default bat), and each bat's swing weight I_b is its moment of inertia about the 6-in pivot
//! ([`swing_weight`]). Swings need no measured exit speed. Every swing in the bag is taken as a measurement:
//! the fit cannot tell a rig's measured swing from one a publisher commanded.
//!
//! **The fit.** With the reference bat r (named by the user, else the bat of the session's first swing),
//! x_b = ln(I_b/I_r) and y_b = ln v̄_b (the log of bat b's mean bat speed over its n_b swings), weighted least
//! squares with weights n_b fits y_b = ln v_ref − n·x_b: the batter's speed v_ref with the reference bat and the
//! exponent n. Weighting by n_b makes it the least-squares line through all swings, each swing's scatter
//! about its bat's mean (the batter's effort varying from swing to swing, and the sensors' noise) taken as
//! the same relative amount on every bat. The residual variance of ln v pools the scatter within each bat
//! and that of the bats' means about the line:
//! s² = [Σ_i (ln v_i − m_b)² + Σ_b n_b (y_b − ŷ_b)²] / (N − 2), m_b the mean of ln v_i over bat b's swings.
//! Then σ(n)² = s²/S_xx and σ(ln v_ref)² = s² (1/N + x̄²/S_xx), with x̄ = Σ n_b x_b / N and
//! S_xx = Σ n_b (x_b − x̄)²; σ(v_ref) = v_ref·σ(ln v_ref) (linearised, 1σ). The fit needs bats of at least two
//! distinct swing weights and at least three swings.
//!
//! **The pivot.** The batter model keeps the swing's instantaneous centre z_p (m from the knob) on every bat
//! ([`SwingShape::SamePivot`]). The speed at the knob u_i = V_i − ω_i z_cm,b of a swing turning about z_p is
//! −ω_i z_p, so z_p = −Σ u_i ω_i / Σ ω_i² (least squares through the origin) with
//! σ(z_p)² = [Σ (u_i + ω_i z_p)² / (N − 1)] / Σ ω_i².
//!
//! The sans-IO part ([`batter_data_from_inputs`], [`fit_batter`]) is pure; [`batter_fit_from_bag`] reads a bag.

// Negated comparisons (`!(a < b)`) are deliberate: they also reject NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use super::{problem_bat, read_inputs, CalibrateError, RecordedInputs};
use crate::report::table::{num, Table};
use sweetspot_physics::batter::{
    swing_weight, Batter, ReferenceSwing, SwingShape, DEFAULT_IMPACT_FROM_BARREL_END, DEFAULT_SWING_LENGTH,
};
use sweetspot_physics::{Bat, MassProperties};

/// Two swing weights closer than this relative amount count as the same.
pub const SAME_SWING_WEIGHT: f64 = 1e-9;

/// How to fit a batter.
#[derive(Debug, Clone, PartialEq)]
pub struct BatterFitOptions {
    /// The bat_id whose swing is the batter's reference (None: the bat of the session's first swing).
    pub reference_bat: Option<String>,
    /// Distance of the batter's usual impact point from the barrel end, m (where bat speed is evaluated).
    pub impact_from_barrel_end: f64,
    /// Arc length of the usual impact point from the start of the swing to contact, m (written to the
    /// batter; the bag does not measure it).
    pub swing_length: f64,
}

impl Default for BatterFitOptions {
    fn default() -> Self {
        BatterFitOptions {
            reference_bat: None,
            impact_from_barrel_end: DEFAULT_IMPACT_FROM_BARREL_END,
            swing_length: DEFAULT_SWING_LENGTH,
        }
    }
}

/// A bat of the session.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionBat {
    /// The bat.
    pub bat: Bat,
    /// The preset it is, when it is one (announced by preset name or named directly by the swing).
    pub preset: Option<String>,
}

/// One swing's measured bat motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredSwing {
    /// The swing's id.
    pub swing_id: u64,
    /// Bat centre-of-mass speed toward the ball, m/s.
    pub bat_cm_speed: f64,
    /// Bat angular speed, rad/s, positive when the barrel leads.
    pub bat_angular_speed: f64,
}

/// The swings of a session grouped by bat, in session order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BatterData {
    /// Bats by bat_id.
    pub bats: BTreeMap<String, SessionBat>,
    /// (bat_id, swing) in session order.
    pub swings: Vec<(String, MeasuredSwing)>,
    /// Inputs left out, with the reason.
    pub skipped: Vec<String>,
}

/// A fitted value and its standard uncertainty.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Estimate {
    /// The value.
    pub value: f64,
    /// Standard uncertainty (1σ).
    pub std_error: f64,
}

/// One bat of the fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BatterFitBat {
    /// The bat_id.
    pub bat_id: String,
    /// The preset it is (None: a bat described by the session's BatParams).
    pub preset: Option<String>,
    /// Swing weight (moment of inertia about the 6-in pivot), kg·m².
    pub swing_weight: f64,
    /// Swings used.
    pub swings: usize,
    /// Mean measured bat speed at the usual impact point, m/s.
    pub mean_bat_speed: f64,
    /// Standard uncertainty of that mean from the pooled scatter, m/s.
    pub mean_std_error: f64,
    /// Bat speed the fitted batter gives this bat, m/s.
    pub fitted_bat_speed: f64,
    /// Mean measured − fitted, m/s.
    pub residual: f64,
}

/// A fitted batter.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BatterFit {
    /// The reference bat's bat_id.
    pub reference_bat: String,
    /// The preset the reference bat is (None: a bat described by the session's BatParams).
    pub reference_preset: Option<String>,
    /// The reference bat.
    #[serde(skip)]
    pub reference: Bat,
    /// Swing weight of the reference bat, kg·m².
    pub reference_swing_weight: f64,
    /// Exponent n of v ∝ I^(−n), dimensionless.
    pub exponent: Estimate,
    /// Bat speed at the usual impact point of the reference bat, m/s.
    pub bat_speed: Estimate,
    /// Instantaneous centre of the swing, m from the knob.
    pub pivot_z: Estimate,
    /// Distance of the usual impact point from the barrel end, m.
    pub impact_from_barrel_end: f64,
    /// Arc length of the usual impact point from the start of the swing to contact, m (not fitted).
    pub swing_length: f64,
    /// Swings used.
    pub swings: usize,
    /// Degrees of freedom N − 2.
    pub dof: usize,
    /// Residual standard deviation s of ln v (a relative scatter of bat speed).
    pub log_speed_sigma: f64,
    /// The bats, by swing weight, heaviest first.
    pub bats: Vec<BatterFitBat>,
    /// Inputs left out, with the reason.
    pub skipped: Vec<String>,
}

/// The keys of the batter file `sweetspot compare --batter` reads (its `BatterSpec`), all written.
#[derive(Serialize)]
struct BatterFileKeys<'a> {
    reference_bat: &'a str,
    bat_speed: f64,
    impact_from_barrel_end: f64,
    pivot_z: f64,
    exponent: f64,
    swing_length: f64,
    shape: SwingShape,
}

impl BatterFit {
    /// The fitted batter (same-pivot swing shape); an error when the fitted values are outside the batter
    /// model's ranges (e.g. an exponent outside 0…0.5).
    pub fn batter(&self) -> Result<Batter, CalibrateError> {
        let physics = |source| CalibrateError::Physics {
            context: "the fitted batter is outside the batter model".into(),
            source,
        };
        let props = self.reference.mass_properties();
        let reference = ReferenceSwing::from_speed_at(
            props,
            self.bat_speed.value,
            props.length - self.impact_from_barrel_end,
            self.pivot_z.value,
        )
        .map_err(physics)?;
        Batter::new(
            reference,
            self.exponent.value,
            self.impact_from_barrel_end,
            self.swing_length,
            SwingShape::SamePivot,
        )
        .map_err(physics)
    }

    /// The batter file (TOML, the format of `sweetspot compare --batter`) with the reference bat written as
    /// `reference_bat` (a preset name, or a bat file relative to the batter file) and the fit's uncertainties
    /// in its comments; `source` names the session in the comment.
    pub fn batter_toml(&self, reference_bat: &str, source: &str) -> Result<String, CalibrateError> {
        self.batter()?;
        let keys = BatterFileKeys {
            reference_bat,
            bat_speed: self.bat_speed.value,
            impact_from_barrel_end: self.impact_from_barrel_end,
            pivot_z: self.pivot_z.value,
            exponent: self.exponent.value,
            swing_length: self.swing_length,
            shape: SwingShape::SamePivot,
        };
        let body = toml::to_string(&keys)
            .map_err(|e| CalibrateError::NoData(format!("the batter file cannot be written: {e}")))?;
        let comment = source.replace(['\n', '\r'], " ");
        Ok(format!(
            "# Batter fitted by `sweetspot calibrate --fit-batter` from {comment}: {} swings with {} bats.\n\
             # exponent = {} ± {}, bat_speed = {} ± {} m/s, pivot_z = {} ± {} m (1σ); swing_length is not fitted.\n{body}",
            self.swings,
            self.bats.len(),
            num(self.exponent.value, 4),
            num(self.exponent.std_error, 2),
            num(self.bat_speed.value, 5),
            num(self.bat_speed.std_error, 2),
            num(self.pivot_z.value, 4),
            num(self.pivot_z.std_error, 2),
        ))
    }
}

/// The session's swings with their bats, resolved as [`super::problem_from_inputs`] resolves them.
pub fn batter_data_from_inputs(inputs: &RecordedInputs) -> BatterData {
    let settings = &inputs.settings;
    let mut data = BatterData::default();
    let mut bat_times: Vec<(u64, String)> = Vec::new();
    for (t, params) in &inputs.bats {
        match problem_bat(params, settings) {
            Ok(problem) => {
                let preset = (!params.preset.is_empty()).then(|| params.preset.clone());
                data.bats.insert(params.bat_id.clone(), SessionBat { bat: problem.bat, preset });
                bat_times.push((*t, params.bat_id.clone()));
            }
            Err(reason) => data.skipped.push(reason),
        }
    }
    for (t, swing) in &inputs.swings {
        let bat_id = if swing.bat_id.is_empty() {
            bat_times
                .iter()
                .rev()
                .find(|(bt, _)| bt <= t)
                .map(|(_, id)| id.clone())
                .unwrap_or_else(|| settings.default_bat.clone())
        } else {
            swing.bat_id.clone()
        };
        if !data.bats.contains_key(&bat_id) {
            match Bat::preset(&bat_id) {
                Ok(bat) => {
                    data.bats.insert(bat_id.clone(), SessionBat { bat, preset: Some(bat_id.clone()) });
                }
                Err(_) => {
                    data.skipped.push(format!("swing {}: unknown bat '{bat_id}'", swing.swing_id));
                    continue;
                }
            }
        }
        let measured = MeasuredSwing {
            swing_id: swing.swing_id,
            bat_cm_speed: swing.bat_cm_speed,
            bat_angular_speed: swing.bat_angular_speed,
        };
        data.swings.push((bat_id, measured));
    }
    data
}

/// One usable swing: its bat's index, ln v at the usual impact point, and the knob speed and ω.
struct Sample {
    bat: usize,
    log_speed: f64,
    knob_speed: f64,
    angular_speed: f64,
}

/// Fits the batter to `data` (see the module docs).
pub fn fit_batter(data: &BatterData, options: &BatterFitOptions) -> Result<BatterFit, CalibrateError> {
    let d = options.impact_from_barrel_end;
    if !(d.is_finite() && d >= 0.0) {
        return Err(CalibrateError::NoData(format!(
            "impact_from_barrel_end = {d} m is out of range: expected a finite distance ≥ 0 m"
        )));
    }
    let mut skipped = data.skipped.clone();
    let mass_properties: BTreeMap<&str, MassProperties> =
        data.bats.iter().map(|(id, b)| (id.as_str(), b.bat.mass_properties())).collect();
    let (order, samples) = usable_samples(data, d, &mass_properties, &mut skipped);
    if samples.is_empty() {
        return Err(CalibrateError::NoData(
            "the bag holds no swing with a usable bat speed (no Swing messages, or none with a known bat)".into(),
        ));
    }
    let reference_id = reference_bat_id(options, &order)?;
    let reference = &data.bats[&reference_id];
    let reference_weight = swing_weight(&mass_properties[reference_id.as_str()]);
    let weights: Vec<f64> = order.iter().map(|id| swing_weight(&mass_properties[*id])).collect();
    let n_total = samples.len();
    check_swing_weights_spread(&order, &weights, n_total)?;
    let law = SpeedLaw::fit(&samples, &weights, reference_weight)?;
    let pivot_z = fit_pivot(&samples)?;
    let mut fit_bats = law.bats(data, &order, &weights);
    fit_bats.sort_by(|a, b| b.swing_weight.total_cmp(&a.swing_weight));
    let bat_speed = law.intercept.exp();
    Ok(BatterFit {
        reference_bat: reference_id,
        reference_preset: reference.preset.clone(),
        reference: reference.bat.clone(),
        reference_swing_weight: reference_weight,
        exponent: Estimate { value: -law.slope, std_error: law.slope_error },
        bat_speed: Estimate { value: bat_speed, std_error: bat_speed * law.intercept_error },
        pivot_z,
        impact_from_barrel_end: d,
        swing_length: options.swing_length,
        swings: n_total,
        dof: law.dof,
        log_speed_sigma: law.s2.sqrt(),
        bats: fit_bats,
        skipped,
    })
}

/// The swings whose bat speed at the usual impact point (`d` from the barrel end) is usable, and the bats
/// in order of their first usable swing (samples refer to them by index); others are noted in `skipped`.
fn usable_samples<'a>(
    data: &'a BatterData,
    d: f64,
    mass_properties: &BTreeMap<&str, MassProperties>,
    skipped: &mut Vec<String>,
) -> (Vec<&'a str>, Vec<Sample>) {
    let mut order: Vec<&str> = Vec::new();
    let mut samples: Vec<Sample> = Vec::new();
    for (bat_id, swing) in &data.swings {
        let Some(&props) = mass_properties.get(bat_id.as_str()) else {
            skipped.push(format!("swing {}: unknown bat '{bat_id}'", swing.swing_id));
            continue;
        };
        let usual_z = props.length - d;
        let (v_cm, omega) = (swing.bat_cm_speed, swing.bat_angular_speed);
        let speed = v_cm + omega * (usual_z - props.center_of_mass);
        if !(usual_z > 0.0) {
            skipped.push(format!(
                "swing {}: bat '{bat_id}' ({} m) is shorter than the usual impact point's {d} m from the barrel end",
                swing.swing_id, props.length
            ));
            continue;
        }
        if !(speed.is_finite() && speed > 0.0) {
            skipped.push(format!(
                "swing {}: bat speed {speed} m/s at the usual impact point is not a positive speed",
                swing.swing_id
            ));
            continue;
        }
        let index = match order.iter().position(|b| b == bat_id) {
            Some(i) => i,
            None => {
                order.push(bat_id.as_str());
                order.len() - 1
            }
        };
        samples.push(Sample {
            bat: index,
            log_speed: speed.ln(),
            knob_speed: v_cm - omega * props.center_of_mass,
            angular_speed: omega,
        });
    }
    (order, samples)
}

/// The reference bat: the one asked for (it must have been swung), else the first bat swung.
fn reference_bat_id(options: &BatterFitOptions, order: &[&str]) -> Result<String, CalibrateError> {
    match &options.reference_bat {
        Some(id) => {
            if !order.contains(&id.as_str()) {
                return Err(CalibrateError::NoData(format!(
                    "reference bat '{id}' has no usable swing in this session (bats swung: {})",
                    order.join(", ")
                )));
            }
            Ok(id.clone())
        }
        None => Ok(order[0].to_string()),
    }
}

/// The exponent needs two different swing weights, and its uncertainty three swings.
fn check_swing_weights_spread(order: &[&str], weights: &[f64], n_total: usize) -> Result<(), CalibrateError> {
    let distinct = {
        let mut sorted = weights.to_vec();
        sorted.sort_by(f64::total_cmp);
        sorted.dedup_by(|a, b| (*a - *b).abs() <= SAME_SWING_WEIGHT * b.abs());
        sorted.len()
    };
    if distinct < 2 {
        let bats: Vec<String> =
            order.iter().zip(weights).map(|(id, w)| format!("'{id}' ({} kg·m²)", num(*w, 4))).collect();
        return Err(CalibrateError::NoData(format!(
            "fitting a batter needs swings with bats of at least two different swing weights; this session's \
             {n_total} usable swing(s) used only {}: one swing weight, so the exponent n of v ∝ I^(−n) is not \
             determined (record a session that swings several bats)",
            bats.join(", ")
        )));
    }
    if n_total < 3 {
        return Err(CalibrateError::NoData(format!(
            "fitting a batter's speed and exponent needs at least 3 swings to estimate their uncertainty; the \
             session has {n_total}"
        )));
    }
    Ok(())
}

/// The fitted line ln v̄_b = intercept + slope · ln(I_b/I_ref) through the bats' mean speeds, weighted by
/// their swings, with s² pooling the scatter within bats and about the line.
struct SpeedLaw {
    count: Vec<usize>,
    mean_speed: Vec<f64>,
    /// ln(I_b/I_ref) of each bat.
    x: Vec<f64>,
    slope: f64,
    intercept: f64,
    s2: f64,
    slope_error: f64,
    intercept_error: f64,
    dof: usize,
}

impl SpeedLaw {
    fn fit(samples: &[Sample], weights: &[f64], reference_weight: f64) -> Result<SpeedLaw, CalibrateError> {
        let n_total = samples.len();
        let bats = weights.len();
        let mut count = vec![0usize; bats];
        let mut speed_sum = vec![0.0; bats];
        let mut log_sum = vec![0.0; bats];
        for s in samples {
            count[s.bat] += 1;
            speed_sum[s.bat] += s.log_speed.exp();
            log_sum[s.bat] += s.log_speed;
        }
        let mean_speed: Vec<f64> = (0..bats).map(|b| speed_sum[b] / count[b] as f64).collect();
        let mean_log: Vec<f64> = (0..bats).map(|b| log_sum[b] / count[b] as f64).collect();
        let x: Vec<f64> = weights.iter().map(|w| (w / reference_weight).ln()).collect();
        let y: Vec<f64> = mean_speed.iter().map(|v| v.ln()).collect();
        let total = n_total as f64;
        let x_mean = (0..bats).map(|b| count[b] as f64 * x[b]).sum::<f64>() / total;
        let y_mean = (0..bats).map(|b| count[b] as f64 * y[b]).sum::<f64>() / total;
        let sxx: f64 = (0..bats).map(|b| count[b] as f64 * (x[b] - x_mean).powi(2)).sum();
        let sxy: f64 = (0..bats).map(|b| count[b] as f64 * (x[b] - x_mean) * (y[b] - y_mean)).sum();
        if !(sxx > 0.0) {
            return Err(CalibrateError::Degenerate("the swing weights do not spread (S_xx = 0)".into()));
        }
        let slope = sxy / sxx;
        let intercept = y_mean - slope * x_mean;
        let within: f64 = samples.iter().map(|s| (s.log_speed - mean_log[s.bat]).powi(2)).sum();
        let between: f64 = (0..bats).map(|b| count[b] as f64 * (y[b] - intercept - slope * x[b]).powi(2)).sum();
        let dof = n_total - 2;
        let s2 = (within + between) / dof as f64;
        Ok(SpeedLaw {
            slope_error: (s2 / sxx).sqrt(),
            intercept_error: (s2 * (1.0 / total + x_mean * x_mean / sxx)).sqrt(),
            count,
            mean_speed,
            x,
            slope,
            intercept,
            s2,
            dof,
        })
    }

    /// Each bat's mean speed against the line's, in the order of `order`.
    fn bats(&self, data: &BatterData, order: &[&str], weights: &[f64]) -> Vec<BatterFitBat> {
        (0..order.len())
            .map(|b| {
                let fitted = (self.intercept + self.slope * self.x[b]).exp();
                BatterFitBat {
                    bat_id: order[b].to_string(),
                    preset: data.bats[order[b]].preset.clone(),
                    swing_weight: weights[b],
                    swings: self.count[b],
                    mean_bat_speed: self.mean_speed[b],
                    mean_std_error: self.mean_speed[b] * (self.s2 / self.count[b] as f64).sqrt(),
                    fitted_bat_speed: fitted,
                    residual: self.mean_speed[b] - fitted,
                }
            })
            .collect()
    }
}

/// The swing's pivot: the z where the knob speed and ω cancel, v_knob + ω z = 0, by least squares.
fn fit_pivot(samples: &[Sample]) -> Result<Estimate, CalibrateError> {
    let omega2: f64 = samples.iter().map(|s| s.angular_speed * s.angular_speed).sum();
    if !(omega2 > 0.0) {
        return Err(CalibrateError::Degenerate("every swing has ω = 0: the swing's pivot is not determined".into()));
    }
    let pivot = -samples.iter().map(|s| s.knob_speed * s.angular_speed).sum::<f64>() / omega2;
    let pivot_ss: f64 = samples.iter().map(|s| (s.knob_speed + s.angular_speed * pivot).powi(2)).sum();
    let pivot_error = (pivot_ss / (samples.len() - 1) as f64 / omega2).sqrt();
    Ok(Estimate { value: pivot, std_error: pivot_error })
}

/// Reads a bag and fits its batter (see [`fit_batter`]).
pub fn batter_fit_from_bag(path: &Path, options: &BatterFitOptions) -> Result<BatterFit, CalibrateError> {
    fit_batter(&batter_data_from_inputs(&read_inputs(path)?), options)
}

/// The human-readable report of a batter fit.
pub fn render_batter_fit(fit: &BatterFit) -> String {
    let mut out = format!(
        "Batter fit: {} swings with {} bats; bat speed {} m from the barrel end against swing weight about the \
         6-in pivot, v = v_ref·(I/I_ref)^(−n), reference bat '{}' ({} kg·m²)\n\n",
        fit.swings,
        fit.bats.len(),
        num(fit.impact_from_barrel_end, 4),
        fit.reference_bat,
        num(fit.reference_swing_weight, 4),
    );
    if !fit.skipped.is_empty() {
        out.push_str(&format!("left out {} input(s):\n", fit.skipped.len()));
        for reason in fit.skipped.iter().take(10) {
            out.push_str(&format!("  {reason}\n"));
        }
        if fit.skipped.len() > 10 {
            out.push_str(&format!("  … and {} more\n", fit.skipped.len() - 10));
        }
        out.push('\n');
    }
    let mut t = Table::new(["parameter", "fitted", "± 1σ", "unit"]);
    for (name, e, unit) in [
        ("exponent n", fit.exponent, ""),
        ("bat_speed v_ref", fit.bat_speed, "m/s"),
        ("pivot_z", fit.pivot_z, "m from the knob"),
    ] {
        t.row([name.to_string(), num(e.value, 5), num(e.std_error, 2), unit.to_string()]);
    }
    out.push_str(&t.render());
    out.push_str(&format!(
        "\nscatter of ln v about the fit: s = {} on {} degrees of freedom\n\n",
        num(fit.log_speed_sigma, 3),
        fit.dof
    ));
    let mut t = Table::new([
        "bat",
        "swing weight (kg·m²)",
        "swings",
        "mean bat speed (m/s)",
        "± 1σ",
        "fitted (m/s)",
        "residual (m/s)",
    ]);
    for b in &fit.bats {
        t.row([
            b.bat_id.clone(),
            num(b.swing_weight, 4),
            b.swings.to_string(),
            num(b.mean_bat_speed, 5),
            num(b.mean_std_error, 2),
            num(b.fitted_bat_speed, 5),
            num(b.residual, 3),
        ]);
    }
    out.push_str(&t.render());
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use sweetspot_msgs::sweetspot_msgs::msg::Swing;

    fn swing(id: u64, bat_id: &str, v_cm: f64, omega: f64) -> (u64, Swing) {
        let s = Swing {
            swing_id: id,
            bat_id: bat_id.into(),
            bat_cm_speed: v_cm,
            bat_angular_speed: omega,
            measured_exit_speed: f64::NAN,
            ..Swing::default()
        };
        (id, s)
    }

    /// Two bats, speeds exactly on v = 30·(I/I_ref)^(−0.3) about the knob: the straight line through two
    /// points is recovered to rounding, with a zero residual.
    #[test]
    fn two_exact_bats_give_the_power_law_through_them() {
        let (r161, aluminum) = (Bat::preset("r161").unwrap(), Bat::preset("aluminum").unwrap());
        let speed_of = |bat: &Bat, v: f64| {
            let p = bat.mass_properties();
            let omega = v / (p.length - DEFAULT_IMPACT_FROM_BARREL_END);
            (omega * p.center_of_mass, omega)
        };
        let ratio = (swing_weight(&aluminum.mass_properties()) / swing_weight(&r161.mass_properties())).powf(-0.3);
        let (a, b) = (speed_of(&r161, 30.0), speed_of(&aluminum, 30.0 * ratio));
        let inputs = RecordedInputs {
            swings: vec![swing(1, "r161", a.0, a.1), swing(2, "aluminum", b.0, b.1), swing(3, "r161", a.0, a.1)],
            ..RecordedInputs::default()
        };
        let fit = fit_batter(&batter_data_from_inputs(&inputs), &BatterFitOptions::default()).unwrap();
        assert_eq!(fit.reference_bat, "r161");
        assert!((fit.exponent.value - 0.3).abs() < 1e-12, "{:?}", fit.exponent);
        assert!((fit.bat_speed.value - 30.0).abs() < 1e-10, "{:?}", fit.bat_speed);
        assert!(fit.pivot_z.value.abs() < 1e-12, "{:?}", fit.pivot_z);
        assert!(fit.exponent.std_error < 1e-10);
    }

    #[test]
    fn bats_of_one_swing_weight_are_refused_naming_why() {
        // The r161 by name and as the recorded default bat (empty bat_id): one swing weight.
        let inputs = RecordedInputs {
            swings: vec![swing(1, "r161", 26.0, 46.0), swing(2, "", 26.0, 46.0), swing(3, "nosuch", 1.0, 1.0)],
            ..RecordedInputs::default()
        };
        let data = batter_data_from_inputs(&inputs);
        assert_eq!(data.skipped, vec!["swing 3: unknown bat 'nosuch'".to_string()]);
        let err = fit_batter(&data, &BatterFitOptions::default()).unwrap_err().to_string();
        assert!(err.contains("at least two different swing weights") && err.contains("'r161'"), "{err}");
        let named = BatterFitOptions { reference_bat: Some("torpedo".into()), ..BatterFitOptions::default() };
        let err = fit_batter(&data, &named).unwrap_err().to_string();
        assert!(err.contains("reference bat 'torpedo'"), "{err}");
    }
}
