//! Ball–bat collision in modal space: fixed-step RK4 from first contact to separation.
//!
//! Axis: y points from the bat toward the incoming ball, so the ball starts with velocity −ball_speed and
//! leaves with +exit_speed. Modal amplitudes q_n (unit modal mass) of the translation, the rotation and the
//! first n vibrational modes, the ball offset s (ball centre minus its position at first contact) and its
//! velocity v obey
//!   q̈_n + ω_n² q_n = −F·Y_n(z_k),   m_ball·s̈ = +F,   u = Σ Y_n(z_k) q_n − s,   F = F(u) ≥ 0 while u > 0,
//! where Y_n(z_k) is mode n's displacement interpolated linearly between the two slice centres around the
//! impact point (the same weights spread the force onto those slices, so force and displacement stay
//! power-conjugate and the energy budget closes exactly). The energy the ball's hysteresis dissipates depends
//! on the largest compression only ([`Ball::hysteresis_loss`]), so it is not integrated: the energy budget's
//! residual is then the integration's own energy error.
//!
//! RK4 runs with the fixed step `time_step`; within a step in which the compression rate u̇ changes sign on
//! the loading curve, the step is repeated with the root of u̇ (maximum compression) as its length, so the
//! switch to the unloading curve happens exactly at u_m. Separation (u = 0) is located the same way; the
//! state at that instant gives the results. The bat is rigid-body moving and not vibrating at t = 0.
//!
//! Speed (one R161 collision takes ~200 steps): the force law is evaluated exactly, exp(γ·ln u), only at an
//! occasional expansion point; the stage forces near it come from its Taylor series, truncated where the
//! error is below the exact evaluation's own rounding ([`Anchor`]). The per-mode update runs on groups of
//! four modes, on AVX registers when the CPU has them, with bit-identical results either way
//! ([`super::lanes`]).
//!
//! # The hoop mode of a hollow barrel
//! Where the bat's wall has a hoop (n = 2 shell) mode at the impact point ([`super::hoop`]: stiffness k_h,
//! effective mass m_h), the wall's ovalling is one more mode of the bat: its amplitude q_h (unit modal mass,
//! wall deflection W = q_h/√m_h) obeys q̈_h + ω_h² q_h = −F·g·ψ/√m_h with ω_h² = k_h/m_h, where ψ(u) is the
//! share of the ball's force that drives the mode and of its deflection the ball feels, set by the ball's
//! contact patch at the current compression u ([`PatchLaw`]). The compression solves u = δ + ψ(u)·W, with
//! δ = Σ Y_n q_n − s the beam's approach as without a wall, so the ball's potential V(u) is a function of the
//! coordinates and its exact gradients are the forces: the beam modes and the ball feel F·g (g = 1/(1 − ψ′W),
//! of order 1 ± 1e-2), the wall F·g·ψ; with ψ constant (g = 1, [`collide_with_hoop`]) this is the linear
//! coupling u = Σ Y_n q_n + ψ W − s. The step loop integrates the wall as a scalar beside the ball, the
//! beam's closed-form update driven by F·g. It solves u at each RK4 stage without evaluating ψ there: the
//! stage's u and W are predicted from the two accepted step ends before the current one (cubic Hermite,
//! RK4's middle stages shifted by ∓h²ü/8), ψ, ψ′, ψ″ are evaluated at those predictions before the step's
//! forces are known, and the solve is one affine map about them, ψ and g following by Taylor's formula;
//! where the neglected terms could exceed 1e-13 m (the first steps, after a located event) it falls back to
//! Newton's method on the polynomial. Stage 3's and 4's compressions and the step end's are affine in the
//! one force they depend on and are computed in that form, so the force-to-force chain is as short as
//! without the wall. The ball
//! thus pushes on the wall (inertia m_h/ψ²), the wall deflects against the hoop spring k_h, and the hoop
//! spring rests on the beam surface at z_k: compliances add, ball ↔ wall ↔ k_h ↔ beam. The wall's inertia
//! acts in the ovalling coordinate, relative to the section's beam motion: the wall's mass is already part of
//! the beam's slices, and ovalling moves no centre of mass (the n = 2 displacement integrates to zero around
//! the circumference), so the hoop mode carries no momentum, counts no mass twice and is M-orthogonal to the
//! beam modes, exactly as a shell mode of the whole bat would be. At t = 0 the wall moves with the section
//! (q_h = q̇_h = 0).
//!
//! The wall gets no damping: a metal shell's loss factor η ~ 1e-3 would take about η·ω_h·t_c ≈ 0.7 % of the
//! energy the wall holds during a ~0.7-ms contact at 1.8 kHz, a few tenths of a joule out of the tens of
//! joules the wall takes and ~10² J in the collision — below the model's other approximations. The energy the
//! wall holds is tracked at every step end: its increases add up to [`EnergyBudget::hoop_stored`], its
//! decreases to [`EnergyBudget::hoop_returned`], and what is left after separation,
//! [`EnergyBudget::hoop`] = stored − returned, enters the budget next to the beam's vibration. Solid sections
//! (no hoop mode) take exactly the code path, and produce exactly the bits, of a bat without one.

use super::hoop::PatchLaw;
#[cfg(target_arch = "x86_64")]
use super::lanes::Avx;
use super::lanes::{Lane4, Lanes, Portable, LANES};
use super::rigid;
use super::{hoop, Ball, HoopMode, ModeSet, PhysicsError};

/// Allowed time steps, s.
pub const TIME_STEP_RANGE: (f64, f64) = (1e-8, 1e-4);

/// Largest energy residual accepted, as a fraction of the initial kinetic energy. A well-resolved collision
/// closes its budget to ~1e-9; a residual this large means the time step does not resolve the contact
/// spring (a stiff ball on a light bat), so the result is refused rather than returned wrong.
pub const MAX_ENERGY_RESIDUAL: f64 = 1e-3;
/// Contact longer than this (s) is reported as a failure to separate.
pub const MAX_CONTACT_TIME: f64 = 0.02;
/// RK4 is stable for ω·h below 2.83; we refuse steps beyond this margin for the highest integrated mode.
const MAX_OMEGA_STEP: f64 = 2.5;

/// Initial conditions of one collision (conventions in the module docs of [`crate`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Impact {
    /// Ball speed toward the bat, m/s.
    pub ball_speed: f64,
    /// Bat centre-of-mass speed toward the ball, m/s.
    pub bat_cm_speed: f64,
    /// Bat angular speed about its centre of mass, rad/s, positive when the barrel leads.
    pub bat_angular_speed: f64,
    /// Impact point, m from the knob.
    pub impact_z: f64,
}

impl Impact {
    /// Checks that every field is finite and in range for `modes` (the error names the field and range).
    pub fn validate(&self, modes: &ModeSet) -> Result<(), PhysicsError> {
        let check = |field: &str, v: f64, lim: f64, unit: &str| {
            if v.is_finite() && v.abs() <= lim {
                Ok(())
            } else {
                Err(PhysicsError::out_of_range(field, v, format!("−{lim} ≤ {field} ≤ {lim} {unit}")))
            }
        };
        check("ball_speed", self.ball_speed, 300.0, "m/s")?;
        check("bat_cm_speed", self.bat_cm_speed, 300.0, "m/s")?;
        check("bat_angular_speed", self.bat_angular_speed, 2000.0, "rad/s")?;
        let length = modes.length();
        if !(self.impact_z.is_finite() && self.impact_z >= 0.0 && self.impact_z <= length) {
            return Err(PhysicsError::ImpactOffBat { impact_z: self.impact_z, min: 0.0, max: length });
        }
        let approach = self.ball_speed + rigid::bat_speed_at(&modes.mass_properties(), self);
        if !(approach > 1e-6) {
            return Err(PhysicsError::out_of_range(
                "ball_speed + bat speed at impact_z",
                approach,
                "> 0 m/s (ball and bat must approach each other)",
            ));
        }
        Ok(())
    }
}

/// Numerical options of a collision.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CollisionOptions {
    /// Number of vibrational modes integrated (default 18).
    pub modes: usize,
    /// RK4 time step, s (default 5 µs).
    pub time_step: f64,
}

impl Default for CollisionOptions {
    fn default() -> Self {
        CollisionOptions { modes: 18, time_step: 5e-6 }
    }
}

impl CollisionOptions {
    /// Checks the options against `modes` (mode count available, time step range and RK4 stability).
    pub fn validate(&self, modes: &ModeSet) -> Result<(), PhysicsError> {
        let available = modes.vibrational_count();
        if self.modes > available {
            return Err(PhysicsError::out_of_range(
                "modes",
                self.modes as f64,
                format!("0 ≤ modes ≤ {available} (vibrational modes computed for this bat)"),
            ));
        }
        let (lo, hi) = TIME_STEP_RANGE;
        if !(self.time_step.is_finite() && self.time_step >= lo && self.time_step <= hi) {
            return Err(PhysicsError::out_of_range(
                "time_step",
                self.time_step,
                format!("{lo:e} ≤ time_step ≤ {hi:e} s"),
            ));
        }
        if self.modes > 0 {
            let omega_max = modes.vibrational_modes()[self.modes - 1].angular_frequency;
            let limit = MAX_OMEGA_STEP / omega_max;
            if self.time_step > limit {
                return Err(PhysicsError::out_of_range(
                    "time_step",
                    self.time_step,
                    format!(
                        "≤ {limit:.3e} s (RK4 stability for mode {} at {:.0} Hz)",
                        self.modes,
                        omega_max / std::f64::consts::TAU
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Checks the time step against the wall's hoop mode `hoop` at `impact_z` (RK4 stability, as for the
    /// beam modes in [`CollisionOptions::validate`]).
    pub fn validate_hoop(&self, hoop: &HoopMode, impact_z: f64) -> Result<(), PhysicsError> {
        hoop.validate()?;
        let omega = hoop.angular_frequency();
        let limit = MAX_OMEGA_STEP / omega;
        if self.time_step > limit {
            return Err(PhysicsError::out_of_range(
                "time_step",
                self.time_step,
                format!(
                    "≤ {limit:.3e} s (RK4 stability for the wall's hoop mode at {:.0} Hz at impact_z = {impact_z} m)",
                    hoop.frequency_hz()
                ),
            ));
        }
        Ok(())
    }
}

/// Energy left in one vibrational mode after separation.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ModeEnergy {
    /// Mode frequency, Hz.
    pub frequency: f64,
    /// Energy after separation, J.
    pub energy: f64,
}

/// Where the initial kinetic energy went, J.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EnergyBudget {
    /// Total kinetic energy before contact, J.
    pub initial: f64,
    /// Ball kinetic energy after separation, J.
    pub ball: f64,
    /// Bat rigid-body (translation + rotation) kinetic energy after separation, J.
    pub bat_rigid: f64,
    /// Vibrational energy of the bat after separation, J.
    pub vibration: f64,
    /// Energy dissipated by the ball's hysteresis, J.
    pub hysteresis_loss: f64,
    /// Energy left in the wall's hoop mode after separation, J (0 without one; not in JSON until the CLI's documents carry it).
    #[serde(skip)]
    pub hoop: f64,
    /// Energy the ball put into the wall's hoop mode during contact (the sum of its increases), J.
    #[serde(skip)]
    pub hoop_stored: f64,
    /// Energy the wall's hoop mode gave back during contact (the sum of its decreases), J;
    /// `hoop_stored − hoop_returned = hoop`.
    #[serde(skip)]
    pub hoop_returned: f64,
    /// initial − (ball + bat_rigid + vibration + hoop + hysteresis_loss), J.
    pub residual: f64,
}

/// Outcome of one collision, SI units.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CollisionResult {
    /// Ball exit speed away from the bat, m/s.
    pub exit_speed: f64,
    /// Exit speed from the closed-form rigid-bat formula with the ball's e0, m/s.
    pub rigid_exit_speed: f64,
    /// Effective COR e_eff of the flexible bat at this impact point.
    pub effective_cor: f64,
    /// Collision efficiency e_A = (exit_speed − bat speed at impact)/(ball_speed + bat speed at impact).
    pub collision_efficiency: f64,
    /// Contact time, s.
    pub contact_time: f64,
    /// Peak contact force, N.
    pub peak_force: f64,
    /// Impulse delivered to the ball, N·s.
    pub impulse: f64,
    /// Maximum compression of the ball, m.
    pub max_compression: f64,
    /// Energy in each integrated vibrational mode after separation.
    pub mode_energies: Vec<ModeEnergy>,
    /// The energy budget and its residual.
    pub energy: EnergyBudget,
    /// Bat centre-of-mass speed toward the ball after separation, m/s.
    pub bat_cm_speed_after: f64,
    /// Bat angular speed after separation, rad/s (positive when the barrel leads).
    pub bat_angular_speed_after: f64,
    /// The wall's hoop mode at the impact point, if the section there has one (not in JSON until the CLI's
    /// documents carry it).
    #[serde(skip)]
    pub hoop: Option<HoopMode>,
}

/// Degree of the Taylor series used for forces near an anchor (see [`Anchor`]).
const SERIES_DEGREE: usize = 15;

/// Truncation error allowed in (1 + δ)^γ: 2⁻⁵⁰ ≈ 8.9e-16, below the rounding of the exact evaluation
/// exp(γ·ln u), whose argument alone carries |γ ln u|·2⁻⁵³ ≈ 4e-15 for a ball's compressions.
const SERIES_TOLERANCE: f64 = 8.881784197001252e-16;

/// The binomial series of (1 + δ)^γ truncated after degree [`SERIES_DEGREE`], and where it is exact enough.
struct PowerSeries {
    /// C(γ, k) for k = 0..=SERIES_DEGREE.
    binomials: [f64; SERIES_DEGREE + 1],
    /// Largest |δ| for which the truncation error is below [`SERIES_TOLERANCE`] (0 when no such bound holds:
    /// γ ≥ degree + 1).
    radius: f64,
}

impl PowerSeries {
    fn new(gamma: f64) -> PowerSeries {
        let mut binomials = [0.0; SERIES_DEGREE + 1];
        let mut c = 1.0;
        for (k, slot) in binomials.iter_mut().enumerate() {
            *slot = c;
            c *= (gamma - k as f64) / (k as f64 + 1.0);
        }
        // `c` is now C(γ, K+1). For γ < K+1 the later coefficients shrink in magnitude, so the tail is
        // bounded by |C(γ, K+1)|·δ^(K+1)/(1 − δ).
        let radius = if !(gamma < SERIES_DEGREE as f64 + 1.0) {
            0.0
        } else if c == 0.0 {
            0.5
        } else {
            let d = (SERIES_TOLERANCE / c.abs()).powf(1.0 / (SERIES_DEGREE as f64 + 1.0));
            (d * (1.0 - d)).min(0.5)
        };
        PowerSeries { binomials, radius }
    }
}

/// The force law k1·u^α (loading, u ≥ `um`) / k2·u^β (unloading, u < `um`).
///
/// k2 = k1·um^(α−β) is computed lazily: while the ball is loading, `um` grows every step but no stage
/// falls below it, so computing k2 eagerly would cost a `powf` per step for nothing.
struct ForceLaw {
    k1: f64,
    alpha: f64,
    beta: f64,
    um: f64,
    /// k2 for the current `um`, or NaN when `um` moved since it was last computed.
    k2: std::cell::Cell<f64>,
    /// Series of u^α and u^β about an anchor.
    loading: PowerSeries,
    unloading: PowerSeries,
}

impl ForceLaw {
    fn new(ball: &Ball) -> ForceLaw {
        let beta = ball.unloading_exponent();
        ForceLaw {
            k1: ball.stiffness,
            alpha: ball.exponent,
            beta,
            um: 0.0,
            k2: std::cell::Cell::new(f64::NAN),
            loading: PowerSeries::new(ball.exponent),
            unloading: PowerSeries::new(beta),
        }
    }

    /// Raises the maximum compression to `um` (the unloading curve moves with it).
    #[inline(always)]
    fn set_max_compression(&mut self, um: f64) {
        self.um = um;
        self.k2.set(f64::NAN);
    }

    /// Unloading stiffness k2 for the current maximum compression, N/m^β.
    #[inline(always)]
    fn k2(&self) -> f64 {
        let k2 = self.k2.get();
        if !k2.is_nan() {
            return k2;
        }
        // Same expression as `Ball::unloading_stiffness`.
        let k2 = self.k1 * self.um.powf(self.alpha - self.beta);
        self.k2.set(k2);
        k2
    }

    /// The force (N) and the contact stiffness dF/du (N/m) at compression `u` on the loading branch
    /// (`loading`) or the unloading one, evaluated exactly; both 0 out of contact.
    fn force_and_stiffness(&self, u: f64, loading: bool) -> (f64, f64) {
        if !(u > 0.0) {
            return (0.0, 0.0);
        }
        let (k, exponent) = if loading { (self.k1, self.alpha) } else { (self.k2(), self.beta) };
        let force = k * (exponent * u.ln()).exp();
        (force, exponent * force / u)
    }

    /// The force at compression `u`, N, evaluated exactly.
    #[inline(always)]
    fn force(&self, u: f64) -> f64 {
        // exp(α ln u) rather than powf: same accuracy here (|α ln u| < 100, relative error < 1e-13) and a
        // shorter latency.
        if u <= 0.0 {
            0.0
        } else if u >= self.um {
            self.k1 * (self.alpha * u.ln()).exp()
        } else {
            self.k2() * (self.beta * u.ln()).exp()
        }
    }
}

/// The force law's Taylor series about a compression u_a where it was evaluated exactly:
/// F(u) = F(u_a)·(1 + δ)^γ = Σ C(γ, k)·F(u_a)/u_a^k·(u − u_a)^k, δ = (u − u_a)/u_a, on u_a's branch.
///
/// Compressions change by a few per cent per step, so one exact ln/exp pair serves many steps and the
/// per-stage cost is a short polynomial instead of a long-latency ln/exp chain on the step's critical path.
/// Within the served range (|δ| ≤ [`PowerSeries::radius`]) the truncation error of (1 + δ)^γ is below
/// [`SERIES_TOLERANCE`]: under the rounding of exp(γ ln u) itself, so results match the exact law to rounding
/// (tested against it).
#[derive(Clone, Copy)]
struct Anchor {
    /// Expansion point u_a, m.
    u: f64,
    /// The compressions served, [lo, hi], m (empty for an anchor that serves nothing).
    lo: f64,
    hi: f64,
    /// Branch: true for loading (k1, α), false for unloading (k2, β).
    loading: bool,
    /// Coefficients of (u − u_a)^k, N/m^k.
    coeffs: [f64; SERIES_DEGREE + 1],
}

impl Anchor {
    /// An anchor that serves nothing (every force is then evaluated exactly until a new one is set).
    const NONE: Anchor = Anchor { u: 0.0, lo: 1.0, hi: -1.0, loading: true, coeffs: [0.0; SERIES_DEGREE + 1] };

    /// Expands `law`'s loading (`loading`) or unloading branch about `u` (> 0), serving |u' − u| ≤ radius·u.
    fn at(law: &ForceLaw, u: f64, loading: bool) -> Anchor {
        let (gamma, k, series) =
            if loading { (law.alpha, law.k1, &law.loading) } else { (law.beta, law.k2(), &law.unloading) };
        // coeffs[k] = F(u_a)·C(γ, k)/u_a^k; the powers of 1/u_a do not wait for the ln/exp of F(u_a).
        let force = k * (gamma * u.ln()).exp();
        let inv_u = 1.0 / u;
        let mut coeffs = series.binomials;
        let mut power = 1.0;
        for c in coeffs.iter_mut() {
            *c *= power;
            power *= inv_u;
        }
        for c in coeffs.iter_mut() {
            *c *= force;
        }
        let reach = series.radius * u;
        // The unloading branch holds below um only (`forget_unloading` drops it when um grows); the loading
        // branch's lower end moves with um and is checked in `covers`.
        let hi = if loading { u + reach } else { (u + reach).min(law.um.next_down()) };
        Anchor { u, lo: u - reach, hi, loading, coeffs }
    }

    /// Whether the series about this anchor gives F(u) for `law` (in range and on the anchor's branch).
    #[inline(always)]
    fn covers(&self, law: &ForceLaw, u: f64) -> bool {
        u >= self.lo && u <= self.hi && (!self.loading || u >= law.um)
    }

    /// The series at `u` (Estrin's scheme: four levels of multiply–add, a short dependency chain).
    #[inline(always)]
    fn eval(&self, u: f64) -> f64 {
        let c = &self.coeffs;
        let x = u - self.u;
        let x2 = x * x;
        let x4 = x2 * x2;
        let x8 = x4 * x4;
        let p = [
            c[0] + c[1] * x,
            c[2] + c[3] * x,
            c[4] + c[5] * x,
            c[6] + c[7] * x,
            c[8] + c[9] * x,
            c[10] + c[11] * x,
            c[12] + c[13] * x,
            c[14] + c[15] * x,
        ];
        let q = [p[0] + p[1] * x2, p[2] + p[3] * x2, p[4] + p[5] * x2, p[6] + p[7] * x2];
        let r = [q[0] + q[1] * x4, q[2] + q[3] * x4];
        r[0] + r[1] * x8
    }

    /// F(u): from the series when covered, exactly otherwise.
    #[inline(always)]
    fn force(&self, law: &ForceLaw, u: f64) -> f64 {
        if self.covers(law, u) {
            self.eval(u)
        } else {
            law.force(u)
        }
    }

    /// Drops an unloading-branch anchor: called when um grows, which moves the unloading curve.
    #[inline(always)]
    fn forget_unloading(&mut self) {
        if !self.loading {
            *self = Anchor::NONE;
        }
    }

    /// Makes sure the anchor serves a step that starts at compression `u1` and is expected to end near
    /// `u_end`. A new expansion point is placed ahead of `u1` in the direction of travel, so that the served
    /// range starts at `u1` and one anchor serves as many of the following steps as possible; stages that
    /// still fall outside are evaluated exactly.
    #[inline(always)]
    fn prepare(&mut self, law: &ForceLaw, u1: f64, u_end: f64) {
        if !(u1 > 0.0) || (self.covers(law, u1) && (self.covers(law, u_end) || !(u_end > 0.0))) {
            return;
        }
        let loading = u1 >= law.um;
        let radius = if loading { law.loading.radius } else { law.unloading.radius };
        // u_a·(1 ∓ radius) = u1 puts u1 at the near end of the range [u_a(1 − radius), u_a(1 + radius)].
        let ahead = if u_end >= u1 { u1 / (1.0 - radius) } else { u1 / (1.0 + radius) };
        // Stay on u1's branch: the unloading curve ends at um.
        let anchor_u = if loading || ahead < law.um { ahead } else { u1 };
        if anchor_u == self.u && loading == self.loading {
            return;
        }
        *self = Anchor::at(law, anchor_u, loading);
        // u_a·(1 ∓ radius) may round an ulp past u1; the truncation bound is unaffected at that scale.
        self.lo = self.lo.min(u1);
        self.hi = self.hi.max(u1);
    }

    /// F at two compressions. RK4's stages come in two independent pairs (stages 1 and 2 need only the step's
    /// start, stages 3 and 4 only the forces of 1 and 2), so both lanes of one polynomial evaluation serve a
    /// pair when the anchor covers both.
    #[inline(always)]
    fn force_pair(&self, law: &ForceLaw, u: [f64; 2]) -> [f64; 2] {
        if self.covers(law, u[0]) && self.covers(law, u[1]) {
            [self.eval(u[0]), self.eval(u[1])]
        } else {
            [self.force(law, u[0]), self.force(law, u[1])]
        }
    }
}

/// The integrated state; the modal arrays live in a scratch buffer.
#[derive(Clone, Copy, Default)]
struct Scalars {
    /// Ball offset from its first-contact position, m.
    s: f64,
    /// Ball velocity, m/s.
    v: f64,
}

/// Per-mode RK4 propagation coefficients of one group of modes for one step length (see [`Work::step`]).
#[derive(Clone, Copy, Default)]
struct GroupCoeffs {
    cqq: Lanes,
    cqp: Lanes,
    cpq: Lanes,
}

/// The powers of one step length h that the step's forced part uses, computed once per step length rather
/// than per step (four divisions off the step's critical path, but on the divider it needs).
#[derive(Clone, Copy, Default)]
struct StepPowers {
    h: f64,
    /// h/6, h²/6, h³/12 and h⁴/24, each by the expression the step used to evaluate.
    h_6: f64,
    h2_6: f64,
    h3_12: f64,
    h4_24: f64,
}

impl StepPowers {
    fn new(h: f64) -> StepPowers {
        StepPowers { h, h_6: h / 6.0, h2_6: h * h / 6.0, h3_12: h * h * h / 12.0, h4_24: h * h * h * h / 24.0 }
    }
}

/// Per-mode RK4 propagation coefficients for one step length h.
struct StepCoeffs {
    powers: StepPowers,
    groups: Vec<GroupCoeffs>,
}

impl StepCoeffs {
    fn new(groups: usize) -> StepCoeffs {
        StepCoeffs { powers: StepPowers::default(), groups: vec![GroupCoeffs::default(); groups] }
    }

    fn set(&mut self, h: f64, modes: &[ModeGroup]) {
        self.powers = StepPowers::new(h);
        let (half_h2, h3_6, h4_24) = (0.5 * h * h, h * h * h / 6.0, h * h * h * h / 24.0);
        // The p–p coefficient equals the q–q one.
        for (c, m) in self.groups.iter_mut().zip(modes) {
            for (l, &w) in m.w2.iter().enumerate() {
                c.cqq[l] = 1.0 - half_h2 * w + h4_24 * w * w;
                c.cqp[l] = h - h3_6 * w;
                c.cpq[l] = -h * w + h3_6 * w * w;
            }
        }
    }
}

/// What the step loop needs of one group of [`LANES`] modes at the impact point.
#[derive(Clone, Copy, Default)]
struct ModeGroup {
    /// Mode shapes at the impact point Y_n(z_k), m per unit amplitude.
    phi: Lanes,
    /// φ·ω², for the stage projections.
    pw1: Lanes,
    /// ω_n², 1/s².
    w2: Lanes,
}

/// Modal amplitudes q and velocities p of one group of modes.
#[derive(Clone, Copy, Default)]
struct GroupState {
    q: Lanes,
    p: Lanes,
}

/// Per-call buffers: everything the step loop touches, allocated once. Modes are stored in groups of
/// [`LANES`]; a partial last group is padded with modes of zero shape and frequency, which stay at rest and
/// contribute nothing.
struct Work {
    modes: Vec<ModeGroup>,
    /// Σφ², Σφ²ω² and Σφ²ω⁴: the projections of a unit force's response.
    c0: f64,
    c1: f64,
    c2: f64,
    /// The current state and the end of the step just taken (`accept` makes the latter current), each as its
    /// force-free part plus a pending forced part: φ·fq + φω²·gq on q and φ·fp + φω²·gp on p, with
    /// [fq, fp, gq, gp] in `pending`. The next step adds the pending part while it loads the state, which
    /// saves a pass over the modes per step.
    state: [Vec<GroupState>; 2],
    pending: [[f64; 4]; 2],
    current: usize,
    /// Projections (Σφq, Σφp, Σφω²q, Σφω²p) of the current state, kept up to date by every update.
    proj: [f64; 4],
    proj_next: [f64; 4],
    full: StepCoeffs,
    partial: StepCoeffs,
    /// Expansion point of the force law for the coming stages.
    anchor: Anchor,
    /// Compression at the start of the step being taken and of the last accepted one, m.
    this_start: f64,
    previous_start: f64,
    /// The wall's hoop mode, integrated beside the ball (unused without one).
    hoop: HoopScalar,
}

/// The wall's hoop mode in the step loop: one mode of unit modal mass, integrated as a scalar beside the ball
/// because the force that drives it, F·ψ(u)·g/√m_h, is not the beam's (see the module docs).
#[derive(Clone, Default)]
struct HoopScalar {
    /// Amplitude and velocity at the current state and at the end of the step being taken, indexed like
    /// [`Work::state`].
    q: [f64; 2],
    p: [f64; 2],
    /// ω_h², 1/s².
    w2: f64,
    /// 1/√m_h: the wall's deflection at the impact point per unit amplitude, m.
    inv_root_mass: f64,
    /// The coupling ψ(u).
    law: PatchLaw,
    /// The accepted step ends that predict the compressions of the step being taken.
    history: History,
    /// ψ expanded about the compressions predicted for the step's second and third stages (both at its
    /// middle, off the path by ∓h²ü/8) and for its end (where the fourth stage also falls, off it by O(h³)).
    second: Expansion,
    third: Expansion,
    end: Expansion,
    /// Length of the step being taken, s.
    step_length: f64,
    /// The solve at the current state, (δ, w) → (u, g, ψ): the step's first stage asks for it again.
    start: std::cell::Cell<(f64, f64, (f64, f64, f64))>,
    /// The last solve's (δ, w) and result: the loop asks again for the same state (the end of a step is the
    /// start of the next), which then costs a comparison.
    memo: std::cell::Cell<(f64, f64, (f64, f64, f64))>,
    /// The last compression solved, m: where a solve that no expansion serves starts.
    last: std::cell::Cell<f64>,
}

/// Compression u, its rate u̇, wall deflection w and its rate ẇ at the last accepted step ends (m, m/s).
#[derive(Clone, Copy, Default)]
struct History {
    /// The two ends before the current state's, oldest first, and the current state's.
    older: [f64; 4],
    old: [f64; 4],
    latest: [f64; 4],
    /// Time from `older` to `old` and from `old` to `latest`, s.
    spacing: f64,
    gap: f64,
    /// How many ends were recorded (the contact's start counts as one).
    count: u32,
}

impl History {
    fn record(&mut self, node: [f64; 4], step: f64) {
        (self.older, self.old, self.latest) = (self.old, self.latest, node);
        (self.spacing, self.gap) = (self.gap, step);
        self.count += 1;
    }

    /// u and w a time `ahead` (s) past the current state, and their second derivatives (m/s²), by the cubic
    /// Hermite interpolant through the two ends before it (their values and rates). They were accepted a
    /// step or more ago, so the prediction, and the ψ evaluated there, do not wait for the step before; u is
    /// off by ~h⁴ u⁗ (~1e-8 m at a 5-µs step). `None` until three ends are known.
    #[inline(always)]
    fn predict(&self, ahead: f64) -> Option<[[f64; 2]; 2]> {
        if self.count < 3 || !(self.spacing > 0.0) {
            return None;
        }
        let span = self.spacing;
        let x = 1.0 + (self.gap + ahead) / span;
        let (x2, x3) = (x * x, x * x * x);
        let (h00, h10, h01, h11) = (2.0 * x3 - 3.0 * x2 + 1.0, x3 - 2.0 * x2 + x, 3.0 * x2 - 2.0 * x3, x3 - x2);
        let inv_span2 = 1.0 / (span * span);
        let (c00, c10, c01, c11) = (12.0 * x - 6.0, 6.0 * x - 4.0, 6.0 - 12.0 * x, 6.0 * x - 2.0);
        let (a, b) = (self.older, self.old);
        let value = |i: usize| h00 * a[i] + h10 * span * a[i + 1] + h01 * b[i] + h11 * span * b[i + 1];
        let second = |i: usize| (c00 * a[i] + c10 * span * a[i + 1] + c01 * b[i] + c11 * span * b[i + 1]) * inv_span2;
        Some([[value(0), value(2)], [second(0), second(2)]])
    }
}

/// Largest error (m) the expansion's first-order solve may leave in the compression; beyond it the solve
/// falls back to Newton's method on the polynomial itself.
const EXPANSION_TOLERANCE: f64 = 1e-13;

/// ψ expanded about a predicted compression u_p and wall deflection w_p, so that solving u = δ + ψ(u)·w near
/// them is one affine map, u = u_p + G·(δ + ψ_p·w − u_p) with G = 1/(1 − ψ′_p·w_p), and ψ, g at the solution
/// follow from the expansion without evaluating the polynomial (see [`HoopScalar::solve`]).
#[derive(Clone, Copy, Default)]
struct Expansion {
    u: f64,
    w: f64,
    psi: f64,
    slope: f64,
    curvature: f64,
    /// G, and u_p − G·u_p and G·ψ_p: u = offset + G·δ + G·ψ_p·w.
    gain: f64,
    offset: f64,
    gain_psi: f64,
    /// Whether a prediction was made (else every solve takes Newton's method).
    valid: bool,
}

impl Expansion {
    #[inline(always)]
    fn new(u: f64, w: f64, psi: f64, slope: f64, curvature: f64) -> Expansion {
        let gain = 1.0 / (1.0 - slope * w);
        Expansion { u, w, psi, slope, curvature, gain, offset: u - gain * u, gain_psi: gain * psi, valid: true }
    }

    /// Finishes a solve whose affine compression `u` was computed for the approach `delta` and deflection
    /// `w`: ψ and g = 1/(1 − ψ′(u)·w) at u from the expansion, or `None` when u lies too far from the
    /// expansion point for the first-order solve (its neglected terms, ½ψ″·w·G·(u − u_p)² and
    /// G²·ψ′_p·(w − w_p)·(u − u_p), above [`EXPANSION_TOLERANCE`]).
    #[inline(always)]
    fn finish(&self, u: f64, w: f64) -> Option<(f64, f64, f64)> {
        let (d, dw) = (u - self.u, w - self.w);
        let error = d.abs() * self.gain * (0.5 * (self.curvature * w).abs() * d.abs() + (self.slope * dw).abs());
        if !(self.valid && error <= EXPANSION_TOLERANCE) {
            return None;
        }
        let psi = self.psi + d * (self.slope + 0.5 * self.curvature * d);
        // ψ′(u)·w − ψ′_p·w_p, and g = G/(1 − G·x) to second order in G·x (~1e-7).
        let x = self.slope * dw + self.curvature * d * w;
        let y = self.gain * x;
        Some((u, self.gain + self.gain * (y + y * y), psi))
    }
}

impl HoopScalar {
    fn new(w2: f64, inv_root_mass: f64, law: PatchLaw) -> HoopScalar {
        HoopScalar {
            w2,
            inv_root_mass,
            law,
            start: std::cell::Cell::new((f64::NAN, f64::NAN, (0.0, 0.0, 0.0))),
            memo: std::cell::Cell::new((f64::NAN, f64::NAN, (0.0, 0.0, 0.0))),
            ..HoopScalar::default()
        }
    }

    /// Expands ψ about the compressions predicted for the stages of a step of length `h`: RK4's second and
    /// third stages reach the step's middle along its start's and its second stage's slopes, ∓h²ü/8
    /// (~2e-7 m) off the path, so their expansions follow from the middle's by Taylor's formula (its
    /// remainder, ψ‴·(h²ü/8)³/6, is ~1e-17); the polynomial is evaluated at the middle and the end.
    #[inline(always)]
    fn expand<V: Lane4>(&mut self, h: f64) {
        self.step_length = h;
        let (Some([middle, acc]), Some([end, _])) = (self.history.predict(0.5 * h), self.history.predict(h)) else {
            (self.second, self.third, self.end) = (Expansion::default(), Expansion::default(), Expansion::default());
            return;
        };
        let (psi, slope, curvature) = self.law.value_slope_and_curvature_in::<V>(middle[0]);
        let off = 0.125 * h * h;
        let stage = |sign: f64| {
            let (du, dw) = (sign * off * acc[0], sign * off * acc[1]);
            let psi = psi + du * (slope + 0.5 * curvature * du);
            Expansion::new(middle[0] + du, middle[1] + dw, psi, slope + curvature * du, curvature)
        };
        self.second = stage(-1.0);
        self.third = stage(1.0);
        let (psi, slope, curvature) = self.law.value_slope_and_curvature_in::<V>(end[0]);
        self.end = Expansion::new(end[0], end[1], psi, slope, curvature);
    }

    /// The compression u solving u = δ + ψ(u)·w, with g = 1/(1 − ψ′(u)·w) and ψ(u) there, for the beam's
    /// approach δ (m) and the wall's deflection w (m), near the expansion `at`: one affine map when the
    /// prediction was close (nearly always), else [`HoopScalar::newton`].
    #[inline(always)]
    fn solve(&self, at: &Expansion, delta: f64, w: f64) -> (f64, f64, f64) {
        let u = at.offset + at.gain * delta + at.gain_psi * w;
        self.finish(at, u, delta, w)
    }

    /// [`HoopScalar::solve`] for an affine compression `u` the caller computed (in a form with a shorter
    /// dependency chain) for δ = `delta` and w = `w`.
    #[inline(always)]
    fn finish(&self, at: &Expansion, u: f64, delta: f64, w: f64) -> (f64, f64, f64) {
        let solved = match at.finish(u, w) {
            Some(solved) => solved,
            None => self.newton(delta, w),
        };
        self.last.set(solved.0);
        solved
    }

    /// The solve by Newton's method on the polynomial, from the last compression solved, to convergence:
    /// ψ′·w is of order 1e-2, so each iteration gains about four digits once close.
    #[inline(never)]
    fn newton(&self, delta: f64, w: f64) -> (f64, f64, f64) {
        let mut u = self.last.get();
        let mut result = (u, 1.0, 1.0);
        for _ in 0..12 {
            let (psi, slope) = self.law.value_and_slope(u);
            let g = 1.0 / (1.0 - slope * w);
            let next = u - (u - delta - psi * w) * g;
            let step = next - u;
            result = (next, g, psi + slope * step);
            u = next;
            if step.abs() <= 1e-16 + 1e-14 * u.abs() {
                break;
            }
        }
        result
    }

    /// [`HoopScalar::solve`] for the end of the step being taken, remembered for the loop's next question.
    #[inline(always)]
    fn solve_end(&self, u: f64, delta: f64, w: f64) -> (f64, f64, f64) {
        let solved = self.finish(&self.end, u, delta, w);
        self.memo.set((delta, w, solved));
        solved
    }

    /// The solve at (δ, w) for a state the loop asks about: the remembered end of the last step taken, or
    /// the current state, or a fresh solve near the step's end.
    #[inline(always)]
    fn contact(&self, delta: f64, w: f64) -> (f64, f64, f64) {
        let (memo_delta, memo_w, memo) = self.memo.get();
        if delta == memo_delta && w == memo_w {
            return memo;
        }
        let (start_delta, start_w, start) = self.start.get();
        if delta == start_delta && w == start_w {
            return start;
        }
        let solved = self.solve(&self.end, delta, w);
        self.memo.set((delta, w, solved));
        solved
    }
}

impl Work {
    /// Buffers for modes with shapes `phi` and squared angular frequencies `w2` at the impact point, at rest
    /// except for the rigid-body modal velocities `rigid_p` (translation, rotation), for step length `h`.
    fn new(phi: &[f64], w2: &[f64], rigid_p: [f64; 2], h: f64) -> Work {
        let n = phi.len().min(w2.len());
        let groups = n.div_ceil(LANES);
        let mut modes = vec![ModeGroup::default(); groups];
        let (mut c0, mut c1, mut c2) = (0.0, 0.0, 0.0);
        for k in 0..n {
            let (m, l) = (&mut modes[k / LANES], k % LANES);
            let pw1 = phi[k] * w2[k];
            (m.phi[l], m.pw1[l], m.w2[l]) = (phi[k], pw1, w2[k]);
            c0 += phi[k] * phi[k];
            c1 += phi[k] * pw1;
            c2 += pw1 * pw1;
        }
        let mut start = vec![GroupState::default(); groups];
        if let Some(first) = start.first_mut() {
            first.p[0] = rigid_p[0];
            first.p[1] = rigid_p[1];
        }
        let mut full = StepCoeffs::new(groups);
        full.set(h, &modes);
        let mut work = Work {
            modes,
            c0,
            c1,
            c2,
            state: [start, vec![GroupState::default(); groups]],
            pending: [[0.0; 4]; 2],
            current: 0,
            proj: [0.0; 4],
            proj_next: [0.0; 4],
            full,
            partial: StepCoeffs::new(groups),
            anchor: Anchor::NONE,
            this_start: 0.0,
            previous_start: 0.0,
            hoop: HoopScalar::default(),
        };
        work.project();
        work
    }

    /// Recomputes the cached projections from scratch.
    fn project(&mut self) {
        let mut acc = [Portable::splat(0.0); 4];
        let pending = self.pending[self.current];
        for (m, x) in self.modes.iter().zip(&self.state[self.current]) {
            let (phi, pw1) = (Portable::load(&m.phi), Portable::load(&m.pw1));
            let (q, p) = with_pending(m, x, pending);
            acc[0] = acc[0].add(phi.mul(q));
            acc[1] = acc[1].add(phi.mul(p));
            acc[2] = acc[2].add(pw1.mul(q));
            acc[3] = acc[3].add(pw1.mul(p));
        }
        self.proj = [acc[0].sum(), acc[1].sum(), acc[2].sum(), acc[3].sum()];
    }

    /// Modal amplitude and velocity of mode `k` (0 = translation, 1 = rotation, then vibrational).
    fn mode_state(&self, k: usize) -> (f64, f64) {
        let (g, l) = (k / LANES, k % LANES);
        let (mut q, mut p) = ([0.0; LANES], [0.0; LANES]);
        let (q_full, p_full) =
            with_pending::<Portable>(&self.modes[g], &self.state[self.current][g], self.pending[self.current]);
        q_full.store(&mut q);
        p_full.store(&mut p);
        (q[l], p[l])
    }

    /// Modal amplitude, velocity and ω² of every mode, in mode order (the padding of the last group left out).
    fn mode_states(&self, count: usize) -> Vec<(f64, f64, f64)> {
        let pending = self.pending[self.current];
        let mut states = Vec::with_capacity(count);
        for (m, x) in self.modes.iter().zip(&self.state[self.current]) {
            let (mut q, mut p) = ([0.0; LANES], [0.0; LANES]);
            let (q_full, p_full) = with_pending::<Portable>(m, x, pending);
            q_full.store(&mut q);
            p_full.store(&mut p);
            states.extend((0..LANES).map(|l| (q[l], p[l], m.w2[l])));
        }
        states.truncate(count);
        states
    }

    /// Compression and its rate for the current modal state and ball state `sc`.
    #[inline(always)]
    fn u_and_rate<const HOOP: bool>(&self, sc: &Scalars) -> (f64, f64) {
        if HOOP {
            let c = self.current;
            self.hoop_u_and_rate(self.proj[0] - sc.s, self.proj[1] - sc.v, self.hoop.q[c], self.hoop.p[c])
        } else {
            (self.proj[0] - sc.s, self.proj[1] - sc.v)
        }
    }

    /// Compression u and its rate u̇ = g·(δ̇ + ψ ẇ) from the beam's approach δ and its rate and the hoop
    /// mode's amplitude and velocity.
    #[inline(always)]
    fn hoop_u_and_rate(&self, delta: f64, delta_rate: f64, q: f64, p: f64) -> (f64, f64) {
        let r = self.hoop.inv_root_mass;
        let (u, g, psi) = self.hoop.contact(delta, q * r);
        (u, g * (delta_rate + psi * p * r))
    }

    /// Solves the current state's compression once more (the solve is remembered) and records the state as
    /// an accepted step end for the hoop's predictions; `sc` is the current ball state.
    #[inline(always)]
    fn record_hoop(&mut self, sc: &Scalars) {
        let c = self.current;
        let (delta, rate) = (self.proj[0] - sc.s, self.proj[1] - sc.v);
        let r = self.hoop.inv_root_mass;
        let (w, w_rate) = (self.hoop.q[c] * r, self.hoop.p[c] * r);
        let (u, g, psi) = self.hoop.contact(delta, w);
        self.hoop.start.set((delta, w, (u, g, psi)));
        let step = self.hoop.step_length;
        self.hoop.history.record([u, g * (rate + psi * w_rate), w, w_rate], step);
    }

    /// The hoop mode's amplitude and velocity in the current state.
    fn hoop_state(&self) -> (f64, f64) {
        (self.hoop.q[self.current], self.hoop.p[self.current])
    }

    /// One classical RK4 step of the `partial` length (if `use_partial`) or the full step, from the current
    /// state; returns the new scalars and the force at the start.
    ///
    /// The modal equations are linear between force evaluations, so RK4's four stages are written out in
    /// closed form: the stage displacements at the impact point need only four projections
    /// (Σφq, Σφp, Σφω²q, Σφω²p) and the final update per mode is
    ///   q' = (1 − h²ω²/2 + h⁴ω⁴/24) q + (h − h³ω²/6) p − φ h²/6 (F1+F2+F3) + φ ω² h⁴/24 F1,
    ///   p' = (−hω² + h³ω⁴/6) q + (1 − h²ω²/2 + h⁴ω⁴/24) p − φ h/6 (F1+2F2+2F3+F4) + φ ω² h³/12 (F1+F2),
    /// which is algebraically identical to the four-stage RK4 step for q̈ + ω²q = −Fφ. The force-free part
    /// (the first two terms) does not depend on this step's forces, so it is computed first and the CPU
    /// overlaps it with the force evaluations, which form the step's critical path; the projections of the
    /// forced part are the precomputed sums c0…c2 times four scalars.
    #[inline(always)]
    fn step<V: Lane4, const HOOP: bool>(
        &mut self,
        sc: &Scalars,
        use_partial: bool,
        law: &ForceLaw,
        inv_mass: f64,
    ) -> (Scalars, f64) {
        let c = if use_partial { &self.partial } else { &self.full };
        let [a0, b0, a1, b1] = self.proj;
        let c0 = self.c0;
        let (from, to) = match &mut self.state {
            [first, second] if self.current == 0 => (&*first, second),
            [first, second] => (&*second, first),
        };
        let pending = self.pending[self.current];
        let [h0, h1, h2, h3] = free_propagation::<V>(c, &self.modes, from, pending, to);

        let powers = c.powers;
        let h = powers.h;
        let a = 0.5 * h;
        let (s, v) = (sc.s, sc.v);
        // Contact compliance per unit force: the bat at the impact point (Σφ²) plus the ball (1/m).
        let k = c0 + inv_mass;
        // Each stage value is written as (part known before the force) − coefficient × force, so that only
        // one multiply and one add separate a force from the next stage: the forces form the critical path.
        let d0 = a0 - s;
        let e0 = b0 - v;
        if HOOP {
            return self.step_with_hoop::<V>(powers, sc, law, inv_mass, [h0, h1, h2, h3]);
        }
        // Stages 1 and 2: compressions independent of the forces.
        let u1 = d0;
        let u2 = d0 + a * e0;
        let u_free = d0 + h * e0;
        // The last accepted step's change predicts this one's better than the force-free u_free.
        self.anchor.prepare(law, u1, u1 + (u1 - self.previous_start));
        self.this_start = u1;
        let [f1, f2] = self.anchor.force_pair(law, [u1, u2]);
        // Stages 3 and 4: compressions depending on F1 and F2 only.
        let u3 = (u2 - a * a * a1) - a * a * k * f1;
        let u4 = (u_free - h * a * a1 - h * a * a * b1) - h * a * k * f2;
        let [f3, f4] = self.anchor.force_pair(law, [u3, u4]);

        (self.finish_step(powers, sc, inv_mass, [h0, h1, h2, h3], [f1, f2, f3, f4]), f1)
    }

    /// The end of an RK4 step once its four stage forces are known: the beam's projections and the pending
    /// per-mode forcing for the next step, and the ball's position and speed.
    #[inline(always)]
    fn finish_step(
        &mut self,
        powers: StepPowers,
        sc: &Scalars,
        inv_mass: f64,
        [h0, h1, h2, h3]: [f64; 4],
        [f1, f2, f3, f4]: [f64; 4],
    ) -> Scalars {
        let (c0, c1, c2) = (self.c0, self.c1, self.c2);
        let (h, s, v) = (powers.h, sc.s, sc.v);
        // Per-mode forcing: q gets φ·fq + φω²·gq, p gets φ·fp + φω²·gp with
        // fq = −h²/6 (F1+F2+F3), fp = −h/6 (F1+2F2+2F3+F4), gq = h⁴/24 F1, gp = h³/12 (F1+F2).
        let (h2_6, h_6) = (powers.h2_6, powers.h_6);
        let f12 = f1 + f2;
        let fq = -h2_6 * f12 - h2_6 * f3;
        let fp = -h_6 * (f12 + f2) - h_6 * (2.0 * f3 + f4);
        let gq = powers.h4_24 * f1;
        let gp = powers.h3_12 * f12;
        self.proj_next = [
            (h0 + gq * c1 - h2_6 * c0 * f12) - h2_6 * c0 * f3,
            (h1 + gp * c1 - h_6 * c0 * (f12 + f2)) - h_6 * c0 * (2.0 * f3 + f4),
            h2 + fq * c1 + gq * c2,
            h3 + fp * c1 + gp * c2,
        ];
        self.pending[1 - self.current] = [fq, fp, gq, gp];
        Scalars {
            s: (s + h * v + h2_6 * inv_mass * f12) + h2_6 * inv_mass * f3,
            v: (v + h_6 * inv_mass * (f12 + f2)) + h_6 * inv_mass * (2.0 * f3 + f4),
        }
    }

    /// [`Work::step`] with the wall's hoop mode, for a step of length `powers.h` whose force-free projections
    /// are `free`. The beam's approach δ at each stage comes from the same closed form, driven by the beam's
    /// force F·g; the hoop mode takes the classical RK4 stages of q̈_h = −ω_h² q_h − F·g·ψ/√m_h; the
    /// compression at each stage solves u = δ + ψ(u)·q_h/√m_h (see the module docs).
    #[inline(always)]
    fn step_with_hoop<V: Lane4>(
        &mut self,
        powers: StepPowers,
        sc: &Scalars,
        law: &ForceLaw,
        inv_mass: f64,
        [h0, h1, h2, h3]: [f64; 4],
    ) -> (Scalars, f64) {
        let h = powers.h;
        let [a0, b0, a1, b1] = self.proj;
        let c0 = self.c0;
        let a = 0.5 * h;
        let (s, v) = (sc.s, sc.v);
        let k = c0 + inv_mass;
        let d0 = a0 - s;
        let e0 = b0 - v;
        let cur = self.current;
        let (qh, ph) = (self.hoop.q[cur], self.hoop.p[cur]);
        let (w2h, r) = (self.hoop.w2, self.hoop.inv_root_mass);
        self.hoop.expand::<V>(h);
        let (second, third, end) = (self.hoop.second, self.hoop.third, self.hoop.end);
        // Stages 1 and 2: approaches and wall amplitudes independent of the forces.
        let (q1, q2) = (qh, qh + a * ph);
        let (x1, g1, psi1) = self.hoop.contact(d0, q1 * r);
        let (x2, g2, psi2) = self.hoop.solve(&second, d0 + a * e0, q2 * r);
        let u_free = d0 + h * e0;
        self.anchor.prepare(law, x1, x1 + (x1 - self.previous_start));
        self.this_start = x1;
        let [raw1, raw2] = self.anchor.force_pair(law, [x1, x2]);
        let (f1, f2) = (raw1 * g1, raw2 * g2);
        let acc1 = -w2h * q1 - f1 * psi1 * r;
        let acc2 = -w2h * q2 - f2 * psi2 * r;
        // Stages 3 and 4. Each compression is affine in the one force it depends on, u3 = K3 − M3·F1 and
        // u4 = K4 − M4·F2 (δ and w both are), and is computed in that form: one multiply and one subtraction
        // after the force, as without the wall; δ and w separately only check the expansion.
        let (p2, p3) = (ph + a * acc1, ph + a * acc2);
        let (q3, q4) = (qh + a * p2, qh + h * p3);
        let d3_free = (d0 + a * e0) - a * a * a1;
        let d4_free = u_free - h * a * a1 - h * a * a * b1;
        let (d3, d4) = (d3_free - a * a * k * f1, d4_free - h * a * k * f2);
        let q3_free = qh + a * ph - a * a * w2h * q1;
        let q4_free = qh + h * ph - h * a * w2h * q2;
        let k3 = third.offset + third.gain * d3_free + third.gain_psi * (r * q3_free);
        let m3 = (third.gain * (a * a * k) + third.gain_psi * (a * a * r * r * psi1)) * g1;
        let k4 = end.offset + end.gain * d4_free + end.gain_psi * (r * q4_free);
        let m4 = (end.gain * (h * a * k) + end.gain_psi * (h * a * r * r * psi2)) * g2;
        let (x3, g3, psi3) = self.hoop.finish(&third, k3 - m3 * raw1, d3, q3 * r);
        let (x4, g4, psi4) = self.hoop.finish(&end, k4 - m4 * raw2, d4, q4 * r);
        let [raw3, raw4] = self.anchor.force_pair(law, [x3, x4]);
        let (f3, f4) = (raw3 * g3, raw4 * g4);
        let acc3 = -w2h * q3 - f3 * psi3 * r;
        let p4 = ph + h * acc3;
        let acc4 = -w2h * q4 - f4 * psi4 * r;
        let h_6 = powers.h_6;
        let q_end = qh + h_6 * (ph + 2.0 * p2 + 2.0 * p3 + p4);
        self.hoop.q[1 - cur] = q_end;
        self.hoop.p[1 - cur] = ph + h_6 * (acc1 + 2.0 * acc2 + 2.0 * acc3 + acc4);

        // The beam and the ball, as in `step`, with the beam's forces F·g.
        let next = self.finish_step(powers, sc, inv_mass, [h0, h1, h2, h3], [f1, f2, f3, f4]);
        // The step end's compression, affine in F3 the same way (δ and w at the end do not depend on F4).
        let delta_end = self.proj_next[0] - next.s;
        let w_end = q_end * r;
        let k_end = end.offset
            + end.gain
                * ((h0 + powers.h4_24 * f1 * self.c1 - powers.h2_6 * c0 * (f1 + f2))
                    - (s + h * v + powers.h2_6 * inv_mass * (f1 + f2)))
            + end.gain_psi * r * (qh + h_6 * (ph + 2.0 * p2 + 2.0 * p3 + ph - h * w2h * q3));
        let m_end = (end.gain * powers.h2_6 * k + end.gain_psi * h_6 * h * r * r * psi3) * g3;
        self.hoop.solve_end(k_end - m_end * raw3, delta_end, w_end);
        (next, raw1)
    }

    /// Compression and its rate at the end of the step just taken.
    #[inline(always)]
    fn next_u_and_rate<const HOOP: bool>(&self, sc: &Scalars) -> (f64, f64) {
        if HOOP {
            let n = 1 - self.current;
            self.hoop_u_and_rate(self.proj_next[0] - sc.s, self.proj_next[1] - sc.v, self.hoop.q[n], self.hoop.p[n])
        } else {
            (self.proj_next[0] - sc.s, self.proj_next[1] - sc.v)
        }
    }

    /// Makes the end of the step just taken the current state.
    #[inline(always)]
    fn accept(&mut self) {
        self.current = 1 - self.current;
        self.previous_start = self.this_start;
        self.proj = self.proj_next;
    }
}

/// A group's q and p with the pending forced part [fq, fp, gq, gp] added (see [`Work::state`]).
#[inline(always)]
fn with_pending<V: Lane4>(m: &ModeGroup, x: &GroupState, [fq, fp, gq, gp]: [f64; 4]) -> (V, V) {
    let (phi, pw1) = (V::load(&m.phi), V::load(&m.pw1));
    let q = V::load(&x.q).add(phi.mul(V::splat(fq))).add(pw1.mul(V::splat(gq)));
    let p = V::load(&x.p).add(phi.mul(V::splat(fp))).add(pw1.mul(V::splat(gp)));
    (q, p)
}

/// The force-free RK4 propagation of every mode from `from` (with its pending forced part) into `to`, and
/// the projections (Σφq, Σφp, Σφω²q, Σφω²p) of the result.
#[inline(always)]
fn free_propagation<V: Lane4>(
    c: &StepCoeffs,
    modes: &[ModeGroup],
    from: &[GroupState],
    pending: [f64; 4],
    to: &mut [GroupState],
) -> [f64; 4] {
    let n = modes.len();
    // Equal lengths up front let the compiler drop the bounds checks in the loop.
    let (coeffs, from, to) = (&c.groups[..n], &from[..n], &mut to[..n]);
    let mut acc = [V::splat(0.0); 4];
    for g in 0..n {
        let (m, c, out) = (&modes[g], &coeffs[g], &mut to[g]);
        let (phi, pw1) = (V::load(&m.phi), V::load(&m.pw1));
        let (cqq, cqp, cpq) = (V::load(&c.cqq), V::load(&c.cqp), V::load(&c.cpq));
        let (q, p) = with_pending::<V>(m, &from[g], pending);
        let qf = cqq.mul(q).add(cqp.mul(p));
        let pf = cpq.mul(q).add(cqq.mul(p));
        qf.store(&mut out.q);
        pf.store(&mut out.p);
        acc[0] = acc[0].add(phi.mul(qf));
        acc[1] = acc[1].add(phi.mul(pf));
        acc[2] = acc[2].add(pw1.mul(qf));
        acc[3] = acc[3].add(pw1.mul(pf));
    }
    [acc[0].sum(), acc[1].sum(), acc[2].sum(), acc[3].sum()]
}

/// What a located event looks for inside a step.
#[derive(Clone, Copy, PartialEq)]
enum Event {
    /// u̇ = 0 (maximum compression).
    Peak,
    /// u = 0 (separation).
    Separation,
}

/// Finds τ in (0, h] where the event function (u̇ or u) crosses zero, by Illinois regula falsi on partial
/// RK4 steps from the saved start state; leaves the state at τ and returns (τ, scalars, force at τ).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn locate<V: Lane4, const HOOP: bool>(
    work: &mut Work,
    start: &Scalars,
    h: f64,
    law: &ForceLaw,
    inv_mass: f64,
    event: Event,
    g_start: f64,
    g_end: f64,
) -> (f64, Scalars) {
    let value = |work: &mut Work, tau: f64| -> Scalars {
        let Work { partial, modes, .. } = work;
        partial.set(tau, modes);
        work.step::<V, HOOP>(start, true, law, inv_mass).0
    };
    let g_of = |work: &Work, sc: &Scalars| {
        let (u, ud) = work.next_u_and_rate::<HOOP>(sc);
        match event {
            Event::Peak => ud,
            Event::Separation => u,
        }
    };
    let (mut a, mut ga) = (0.0, g_start);
    let (mut b, mut gb) = (h, g_end);
    let mut side = 0i8;
    let mut best = (h, None::<Scalars>);
    // Converged when the event function is at rounding level of its scale at the step start, or the
    // bracket is negligible.
    let g_tol = 1e-12 * g_start.abs().max(g_end.abs());
    for _ in 0..60 {
        let tau = if (ga - gb) != 0.0 { (a * gb - b * ga) / (gb - ga) } else { 0.5 * (a + b) };
        let tau = if tau > a && tau < b { tau } else { 0.5 * (a + b) };
        let sc = value(work, tau);
        let g = g_of(work, &sc);
        best = (tau, Some(sc));
        if g.abs() <= g_tol || (b - a) <= 1e-12 * h {
            break;
        }
        if (g > 0.0) == (ga > 0.0) {
            a = tau;
            ga = g;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        } else {
            b = tau;
            gb = g;
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        }
    }
    // The next-state buffers hold the last evaluation, which is the returned one.
    let tau = best.0;
    let sc = match best.1 {
        Some(sc) => sc,
        None => value(work, tau),
    };
    (tau, sc)
}

/// Tracks the energy of the wall's hoop mode at every accepted step end.
#[derive(Clone, Copy, Default)]
struct HoopMeter {
    /// ω_h², 1/s².
    w2: f64,
    /// Energy at the last accepted step end, J.
    energy: f64,
    /// Sum of the energy's increases, J.
    stored: f64,
    /// Sum of the energy's decreases, J.
    returned: f64,
}

impl HoopMeter {
    /// Reads the hoop mode's energy from the current state and books its change.
    #[inline(always)]
    fn update(&mut self, work: &Work) {
        let (q, p) = work.hoop_state();
        let energy = 0.5 * (p * p + self.w2 * q * q);
        let change = energy - self.energy;
        if change > 0.0 {
            self.stored += change;
        } else {
            self.returned -= change;
        }
        self.energy = energy;
    }
}

/// State at the end of contact.
#[derive(Clone, Copy)]
struct Contact {
    scalars: Scalars,
    time: f64,
    peak_force: f64,
    separated: bool,
}

/// The fixed-step RK4 loop from first contact to separation, compiled for the best SIMD width this CPU has.
///
/// The loop is the same code either way and uses no fused multiply–add, so the two builds give bit-identical
/// results; only the lane operations of the per-mode update get wider. With `HOOP` the loop also books the
/// hoop mode's energy in `meter` after every accepted step (reading the state only, so the trajectory is the
/// same); without it the meter is untouched and the loop is exactly that of a bat without a hoop mode.
fn integrate<const HOOP: bool, O: ContactObserver>(
    work: &mut Work,
    law: &mut ForceLaw,
    ball: &Ball,
    ball_speed: f64,
    h: f64,
    meter: &mut HoopMeter,
    observer: &mut O,
) -> Result<Contact, PhysicsError> {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above), the only requirement of `integrate_avx2`.
        return unsafe { integrate_avx2::<HOOP, O>(work, law, ball, ball_speed, h, meter, observer) };
    }
    integrate_loop::<Portable, HOOP, O>(work, law, ball, ball_speed, h, meter, observer)
}

/// [`integrate_loop`] compiled with AVX2 enabled, its per-mode update on 256-bit registers.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn integrate_avx2<const HOOP: bool, O: ContactObserver>(
    work: &mut Work,
    law: &mut ForceLaw,
    ball: &Ball,
    ball_speed: f64,
    h: f64,
    meter: &mut HoopMeter,
    observer: &mut O,
) -> Result<Contact, PhysicsError> {
    integrate_loop::<Avx, HOOP, O>(work, law, ball, ball_speed, h, meter, observer)
}

/// The fixed-step RK4 loop from first contact to separation (see the module docs).
#[inline(always)]
fn integrate_loop<V: Lane4, const HOOP: bool, O: ContactObserver>(
    work: &mut Work,
    law: &mut ForceLaw,
    ball: &Ball,
    ball_speed: f64,
    h: f64,
    meter: &mut HoopMeter,
    observer: &mut O,
) -> Result<Contact, PhysicsError> {
    let inv_mass = 1.0 / ball.mass;
    let mut sc = Scalars { s: 0.0, v: -ball_speed };
    let mut t = 0.0;
    let mut peak_force: f64 = 0.0;
    let mut just_peaked = false;
    let max_steps = (MAX_CONTACT_TIME / h).ceil() as usize + 1;
    let mut separated = false;
    if HOOP {
        work.record_hoop(&sc);
    }
    for _ in 0..max_steps {
        let (u0, ud0) = work.u_and_rate::<HOOP>(&sc);
        let loading = u0 >= law.um && ud0 > 0.0 && !just_peaked;
        just_peaked = false;
        let observed_start = if O::ACTIVE { law.force_and_stiffness(u0, loading) } else { (0.0, 0.0) };
        let start = sc;
        let (next, f_start) = work.step::<V, HOOP>(&start, false, law, inv_mass);
        peak_force = peak_force.max(f_start);
        let (u1, ud1) = work.next_u_and_rate::<HOOP>(&next);
        if !(u1.is_finite() && ud1.is_finite() && next.v.is_finite()) {
            return Err(PhysicsError::Numerical(format!("non-finite state at t = {t:e} s")));
        }
        if loading && ud1 <= 0.0 && u1 > 0.0 {
            // Maximum compression inside this step: stop exactly there and switch to unloading.
            let (tau, sc_peak) = locate::<V, HOOP>(work, &start, h, law, inv_mass, Event::Peak, ud0, ud1);
            let (u_peak, _) = work.next_u_and_rate::<HOOP>(&sc_peak);
            if O::ACTIVE {
                observer.step(tau, observed_start, law.force_and_stiffness(u_peak, true));
            }
            accept_step::<HOOP>(work, meter);
            t += tau;
            sc = sc_peak;
            raise_max_compression(work, law, u_peak);
            peak_force = peak_force.max(law.force(u_peak));
            just_peaked = true;
            if HOOP {
                work.record_hoop(&sc);
            }
            continue;
        }
        if u1 <= 0.0 && law.um > 0.0 {
            // Separation inside this step (u̇ < 0 here, so u crossed zero from above).
            let (tau, sc_sep) = locate::<V, HOOP>(work, &start, h, law, inv_mass, Event::Separation, u0, u1);
            if O::ACTIVE {
                observer.step(tau, observed_start, (0.0, 0.0));
            }
            accept_step::<HOOP>(work, meter);
            t += tau;
            sc = sc_sep;
            separated = true;
            break;
        }
        if O::ACTIVE {
            observer.step(h, observed_start, law.force_and_stiffness(u1, loading));
        }
        accept_step::<HOOP>(work, meter);
        t += h;
        sc = next;
        raise_max_compression(work, law, u1);
        if HOOP {
            work.record_hoop(&sc);
        }
    }
    Ok(Contact { scalars: sc, time: t, peak_force, separated })
}

/// Accepts the step just taken; with a hoop mode, meters what the wall stored or gave back over it.
#[inline(always)]
fn accept_step<const HOOP: bool>(work: &mut Work, meter: &mut HoopMeter) {
    work.accept();
    if HOOP {
        meter.update(work);
    }
}

/// Makes `u` the maximum compression when it exceeds it (the unloading branch then starts from it).
#[inline(always)]
fn raise_max_compression(work: &mut Work, law: &mut ForceLaw, u: f64) {
    if u > law.um {
        law.set_max_compression(u);
        work.anchor.forget_unloading();
    }
}

/// Watches the normal contact as the step loop integrates it, for a model that rides along with it (the
/// compliant tangential contact of [`crate::oblique`]). The loop calls [`ContactObserver::step`] once
/// per step it accepts, partial steps ending at the peak compression or at separation included, with the
/// contact force and stiffness at both ends of the step on the branch (loading or unloading) the step was on.
pub trait ContactObserver {
    /// False for an observer that does nothing: the loop then skips evaluating what it would be given, and
    /// runs exactly the arithmetic, and gives exactly the bits, of an unobserved collision.
    const ACTIVE: bool = true;

    /// One step of `dt` s; `start` and `end` are (contact force N, contact stiffness dF/du N/m).
    fn step(&mut self, dt: f64, start: (f64, f64), end: (f64, f64));
}

/// No observer.
impl ContactObserver for () {
    const ACTIVE: bool = false;

    #[inline(always)]
    fn step(&mut self, _dt: f64, _start: (f64, f64), _end: (f64, f64)) {}
}

/// The step loop's buffers for `impact` on `modes` (validated) with `options`: mode shapes at the impact
/// point, and the bat's rigid motion as the initial modal velocities; with `hoop`, the wall's hoop mode is
/// one more mode after the beam's (shape ψ/√m_h, ω_h² = k_h/m_h, at rest).
fn work_for(modes: &ModeSet, impact: &Impact, options: &CollisionOptions, hoop: Option<(&HoopMode, PatchLaw)>) -> Work {
    let mp = modes.mass_properties();
    let nm = 2 + options.modes;
    let phi: Vec<f64> = (0..nm).map(|k| modes.shape_at(k, impact.impact_z)).collect();
    let w2: Vec<f64> = modes.all_modes()[..nm].iter().map(|m| m.angular_frequency * m.angular_frequency).collect();
    // Rigid initial velocities: ẏ = V + ω (z − z_cm) = p_0/√M + p_1 (z − z_cm)/√I.
    let rigid_p = [impact.bat_cm_speed * mp.mass.sqrt(), impact.bat_angular_speed * mp.moment_of_inertia.sqrt()];
    let mut work = Work::new(&phi, &w2, rigid_p, options.time_step);
    if let Some((mode, law)) = hoop {
        work.hoop = HoopScalar::new(mode.stiffness / mode.effective_mass, 1.0 / mode.effective_mass.sqrt(), law);
    }
    work
}

/// Runs one collision of `ball` with the bat described by `modes`, with the wall's hoop mode at the impact
/// point when the section there has one ([`ModeSet::hoop_at`]), loaded through a contact patch that follows
/// the ball's compression ([`collide_with_patch`]).
pub fn collide(
    modes: &ModeSet,
    ball: &Ball,
    impact: &Impact,
    options: &CollisionOptions,
) -> Result<CollisionResult, PhysicsError> {
    collide_observed(modes, ball, impact, options, &mut ())
}

/// [`collide`] with `observer` watching the contact step by step (see [`ContactObserver`]); the collision's
/// result is the same, bit for bit.
pub fn collide_observed<O: ContactObserver>(
    modes: &ModeSet,
    ball: &Ball,
    impact: &Impact,
    options: &CollisionOptions,
    observer: &mut O,
) -> Result<CollisionResult, PhysicsError> {
    impact.validate(modes)?;
    let section = modes.hoop_at(impact.impact_z);
    run_with_patch(modes, ball, impact, options, section.as_ref(), observer)
}

/// Runs one collision of `ball` with the bat described by `modes` and the wall section's hoop mode `section`
/// at the impact point (its [`HoopMode::coupling`] that of a point load, as [`HoopMode::of_section`] gives
/// it; `None`: a rigid wall there), loaded through the ball's contact patch as it grows and shrinks with the
/// ball's compression u: ψ(u) from [`PatchLaw::following`] over compressions up to
/// [`PATCH_RANGE_FACTOR`] times the reference compression ([`hoop::reference_compression`]). The result's
/// [`CollisionResult::hoop`] carries the coupling at the collision's peak compression.
pub fn collide_with_patch(
    modes: &ModeSet,
    ball: &Ball,
    impact: &Impact,
    options: &CollisionOptions,
    section: Option<&HoopMode>,
) -> Result<CollisionResult, PhysicsError> {
    run_with_patch(modes, ball, impact, options, section, &mut ())
}

/// [`collide_with_patch`] with an observer.
fn run_with_patch<O: ContactObserver>(
    modes: &ModeSet,
    ball: &Ball,
    impact: &Impact,
    options: &CollisionOptions,
    section: Option<&HoopMode>,
    observer: &mut O,
) -> Result<CollisionResult, PhysicsError> {
    impact.validate(modes)?;
    let hoop = section.map(|mode| {
        let range = PATCH_RANGE_FACTOR * reference_compression_at(modes, ball, impact);
        (mode, PatchLaw::following(mode, ball.radius, range.min(ball.radius)))
    });
    run(modes, ball, impact, options, hoop, observer)
}

/// The patch's coupling is interpolated over compressions up to this multiple of the reference compression
/// (the peak of the same impact on a rigid, non-vibrating wall, which the wall's give and the beam's
/// vibrations only lower; the collision reports a peak beyond the range as an error).
pub const PATCH_RANGE_FACTOR: f64 = 1.25;

/// The peak compression of `impact` with `ball` on the bat's rigid-body effective mass at the impact point,
/// without the wall's give ([`hoop::reference_compression`]), m.
fn reference_compression_at(modes: &ModeSet, ball: &Ball, impact: &Impact) -> f64 {
    let mp = modes.mass_properties();
    let approach = impact.ball_speed + rigid::bat_speed_at(&mp, impact);
    let arm = impact.impact_z - mp.center_of_mass;
    let bat_effective_mass = 1.0 / (1.0 / mp.mass + arm * arm / mp.moment_of_inertia);
    hoop::reference_compression(ball, approach, bat_effective_mass)
}

/// The wall's hoop mode at `impact`'s point as `ball` loads it: the section's mode ([`ModeSet::hoop_at`])
/// through the contact patch at the peak compression of the same impact without the wall
/// ([`hoop::reference_compression`] with the bat's rigid-body effective mass at the impact point); `None`
/// where the section has no hoop mode.
pub fn hoop_under_ball(modes: &ModeSet, ball: &Ball, impact: &Impact) -> Option<HoopMode> {
    let section = modes.hoop_at(impact.impact_z)?;
    Some(section.under_patch(ball.radius, reference_compression_at(modes, ball, impact)))
}

/// Runs one collision of `ball` with the bat described by `modes` and the given hoop mode at the impact
/// point (`None`: a rigid wall there, as for a solid section), whatever the bat's own wall has; the mode's
/// [`HoopMode::coupling`] is used as given, the same at every compression (a patch fixed in size).
pub fn collide_with_hoop(
    modes: &ModeSet,
    ball: &Ball,
    impact: &Impact,
    options: &CollisionOptions,
    hoop: Option<&HoopMode>,
) -> Result<CollisionResult, PhysicsError> {
    run(modes, ball, impact, options, hoop.map(|mode| (mode, PatchLaw::constant(mode.coupling))), &mut ())
}

/// One collision with the wall's hoop mode `hoop` and its coupling law, if any (see [`collide_with_hoop`]).
fn run<O: ContactObserver>(
    modes: &ModeSet,
    ball: &Ball,
    impact: &Impact,
    options: &CollisionOptions,
    hoop: Option<(&HoopMode, PatchLaw)>,
    observer: &mut O,
) -> Result<CollisionResult, PhysicsError> {
    validate_run(modes, ball, impact, options, hoop)?;
    let mp = modes.mass_properties();
    // e0 at this collision's normal approach speed (ball and bat surface at first contact): β, k2 and the
    // hysteresis loss below all follow from it. A constant-COR ball is itself, bit for bit.
    let resolved = ball.at_approach_speed(impact.ball_speed + rigid::bat_speed_at(&mp, impact));
    let ball = &resolved;
    let nm = 2 + options.modes;
    let z = impact.impact_z;

    let all = &modes.all_modes()[..nm];
    let h = options.time_step;
    let mut work = work_for(modes, impact, options, hoop);
    let mut law = ForceLaw::new(ball);
    let (_, p_translation) = work.mode_state(0);
    let (_, p_rotation) = work.mode_state(1);
    let initial_energy =
        0.5 * ball.mass * impact.ball_speed.powi(2) + 0.5 * (p_translation * p_translation + p_rotation * p_rotation);

    let mut meter = HoopMeter { w2: hoop.map_or(0.0, |(m, _)| m.stiffness / m.effective_mass), ..HoopMeter::default() };
    let contact = match hoop {
        Some(_) => integrate::<true, O>(&mut work, &mut law, ball, impact.ball_speed, h, &mut meter, observer)?,
        None => integrate::<false, O>(&mut work, &mut law, ball, impact.ball_speed, h, &mut meter, observer)?,
    };
    let Contact { scalars: sc, time: t, peak_force, separated } = contact;
    if !separated {
        return Err(PhysicsError::Numerical(format!(
            "ball and bat did not separate within {MAX_CONTACT_TIME} s (impact_z = {z} m)"
        )));
    }

    let exit_speed = sc.v;
    let BatAfter { p_translation, p_rotation, bat_rigid, mode_energies, vibration, hoop_energy } =
        BatAfter::of(&work, all, hoop, law.um)?;
    let ball_energy = 0.5 * ball.mass * exit_speed * exit_speed;
    let hysteresis_loss = ball.hysteresis_loss(law.um);
    // Without a hoop mode hoop_energy is +0.0, which leaves the sum's bits unchanged.
    let residual = initial_energy - (ball_energy + bat_rigid + vibration + hoop_energy + hysteresis_loss);
    let v_bat = rigid::bat_speed_at(&mp, impact);
    let approach = impact.ball_speed + v_bat;
    let result = CollisionResult {
        exit_speed,
        rigid_exit_speed: rigid::exit_speed(&mp, ball.mass, ball.cor, impact),
        effective_cor: rigid::effective_cor(&mp, ball.mass, impact, exit_speed),
        collision_efficiency: (exit_speed - v_bat) / approach,
        contact_time: t,
        peak_force,
        impulse: ball.mass * (exit_speed + impact.ball_speed),
        max_compression: law.um,
        mode_energies,
        energy: EnergyBudget {
            initial: initial_energy,
            ball: ball_energy,
            bat_rigid,
            vibration,
            hysteresis_loss,
            hoop: hoop_energy,
            hoop_stored: meter.stored,
            hoop_returned: meter.returned,
            residual,
        },
        bat_cm_speed_after: p_translation / mp.mass.sqrt(),
        bat_angular_speed_after: p_rotation / mp.moment_of_inertia.sqrt(),
        hoop: hoop.map(|(mode, patch)| HoopMode { coupling: patch.value_and_slope(law.um).0, ..*mode }),
    };
    check_result(&result, options.time_step)?;
    Ok(result)
}

/// Refuses a ball, impact, options or hoop mode outside their documented ranges before anything is integrated.
fn validate_run(
    modes: &ModeSet,
    ball: &Ball,
    impact: &Impact,
    options: &CollisionOptions,
    hoop: Option<(&HoopMode, PatchLaw)>,
) -> Result<(), PhysicsError> {
    ball.validate()?;
    impact.validate(modes)?;
    options.validate(modes)?;
    if let Some((mode, _)) = hoop {
        options.validate_hoop(mode, impact.impact_z)?;
    }
    Ok(())
}

/// The bat after separation: its rigid momenta (mass-normalised, √kg·m/s), rigid, vibrational and hoop energies
/// (J) and each flexible mode's share.
struct BatAfter {
    p_translation: f64,
    p_rotation: f64,
    bat_rigid: f64,
    mode_energies: Vec<ModeEnergy>,
    vibration: f64,
    hoop_energy: f64,
}

impl BatAfter {
    /// Reads the bat's state from `work` once the ball has left; `max_compression` (m) must lie within the
    /// hoop patch's coupling range.
    fn of(
        work: &Work,
        all: &[crate::Mode],
        hoop: Option<(&HoopMode, PatchLaw)>,
        max_compression: f64,
    ) -> Result<BatAfter, PhysicsError> {
        let nm = all.len();
        let states = work.mode_states(nm);
        let (p_translation, p_rotation) = (states[0].1, states[1].1);
        let bat_rigid = 0.5 * (p_translation * p_translation + p_rotation * p_rotation);
        let mode_energies: Vec<ModeEnergy> = states[2..nm]
            .iter()
            .zip(&all[2..])
            .map(|(&(q, p, w2), mode)| ModeEnergy {
                frequency: mode.angular_frequency / std::f64::consts::TAU,
                energy: 0.5 * (p * p + w2 * q * q),
            })
            .collect();
        let vibration: f64 = mode_energies.iter().map(|m| m.energy).sum();
        let hoop_energy = match hoop {
            Some((mode, patch)) => {
                if max_compression > patch.range {
                    return Err(PhysicsError::Numerical(format!(
                        "the ball's compression {:e} m left the range of the patch's coupling ({:e} m)",
                        max_compression, patch.range
                    )));
                }
                let (q, p) = work.hoop_state();
                0.5 * (p * p + mode.stiffness / mode.effective_mass * q * q)
            }
            None => 0.0,
        };
        Ok(BatAfter { p_translation, p_rotation, bat_rigid, mode_energies, vibration, hoop_energy })
    }
}

/// Refuses a result that is not finite or whose energy budget misses more than [`MAX_ENERGY_RESIDUAL`] of the
/// initial energy (a `time_step`, s, too coarse for the contact).
fn check_result(result: &CollisionResult, time_step: f64) -> Result<(), PhysicsError> {
    let finite = [
        result.exit_speed,
        result.rigid_exit_speed,
        result.effective_cor,
        result.collision_efficiency,
        result.contact_time,
        result.peak_force,
        result.energy.residual,
    ]
    .iter()
    .all(|v| v.is_finite());
    if !finite {
        return Err(PhysicsError::Numerical("collision produced a non-finite result".into()));
    }
    let relative_residual = (result.energy.residual / result.energy.initial).abs();
    if relative_residual > MAX_ENERGY_RESIDUAL {
        return Err(PhysicsError::Numerical(format!(
            "time_step = {:e} s is too coarse for this contact: the energy budget misses {:.3e} of the \
             initial energy (allowed {MAX_ENERGY_RESIDUAL:e}); use a smaller time step",
            time_step, relative_residual
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Bat;

    fn r161() -> ModeSet {
        ModeSet::compute(&Bat::preset("r161").expect("preset"), 18).expect("modes")
    }

    fn swing(impact_z: f64) -> Impact {
        Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 50.0, impact_z }
    }

    /// Everything the step loop ends with: contact scalars and every mode's (q, p), as bits.
    fn run_loop(modes: &ModeSet, ball: &Ball, impact: &Impact, law: &mut ForceLaw, avx: bool) -> Vec<u64> {
        let options = CollisionOptions::default();
        let mut work = work_for(modes, impact, &options, None);
        let h = options.time_step;
        let mut meter = HoopMeter::default();
        let contact = if avx {
            #[cfg(target_arch = "x86_64")]
            {
                assert!(std::is_x86_feature_detected!("avx2"));
                // SAFETY: AVX2 was detected just above.
                unsafe { integrate_avx2::<false, ()>(&mut work, law, ball, impact.ball_speed, h, &mut meter, &mut ()) }
            }
            #[cfg(not(target_arch = "x86_64"))]
            unreachable!()
        } else {
            integrate_loop::<Portable, false, ()>(&mut work, law, ball, impact.ball_speed, h, &mut meter, &mut ())
        };
        let contact = contact.expect("integrates");
        assert!(contact.separated);
        let mut bits = vec![contact.scalars.s, contact.scalars.v, contact.time, contact.peak_force, law.um];
        for k in 0..2 + options.modes {
            let (q, p) = work.mode_state(k);
            bits.extend([q, p]);
        }
        bits.into_iter().map(f64::to_bits).collect()
    }

    #[test]
    fn the_avx_and_portable_loops_give_identical_bits() {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            let modes = r161();
            for (z, cor) in [(0.45, 0.53), (0.69, 0.53), (0.80, 0.3), (0.62, 0.9)] {
                let ball = Ball { cor, ..Ball::default() };
                let fast = run_loop(&modes, &ball, &swing(z), &mut ForceLaw::new(&ball), true);
                let portable = run_loop(&modes, &ball, &swing(z), &mut ForceLaw::new(&ball), false);
                assert_eq!(fast, portable, "z = {z}, e0 = {cor}");
            }
            return;
        }
        eprintln!("no AVX2 on this CPU: only the portable loop exists here");
    }

    /// Forces from the series about an anchor against exp(γ ln u), over the whole served range.
    #[test]
    fn series_forces_match_the_exact_law_to_rounding() {
        for cor in [0.3, 0.45, 0.53, 0.8, 1.0] {
            let ball = Ball { cor, ..Ball::default() };
            let mut law = ForceLaw::new(&ball);
            assert!(law.loading.radius > 0.05, "e0 = {cor}");
            // β = (1+α)/e0² − 1 is 30.6 for e0 = 0.3: beyond the series, so unloading is always exact.
            let branches: &[bool] = if law.unloading.radius > 0.0 { &[true, false] } else { &[true] };
            assert_eq!(law.unloading.radius > 0.0, law.beta < SERIES_DEGREE as f64 + 1.0, "e0 = {cor}");
            for anchor_u in [1e-4, 3.7e-3, 1.8e-2] {
                for &loading in branches {
                    if !loading {
                        law.set_max_compression(anchor_u * 1.5);
                    } else {
                        law.set_max_compression(0.0);
                    }
                    let anchor = Anchor::at(&law, anchor_u, loading);
                    let gamma = if loading { law.alpha } else { law.beta };
                    for i in 0..=400 {
                        let u = anchor.lo + (anchor.hi - anchor.lo) * i as f64 / 400.0;
                        assert!(anchor.covers(&law, u), "u = {u} in [{}, {}]", anchor.lo, anchor.hi);
                        let exact = law.force(u);
                        let difference = ((anchor.eval(u) - exact) / exact).abs();
                        // exp(γ ln u) is itself only good to about |γ ln u|·2⁻⁵³, at u and at u_a alike.
                        let rounding = 2.0 * (gamma * u.ln()).abs() * f64::EPSILON + 2.0 * SERIES_TOLERANCE;
                        assert!(
                            difference < rounding,
                            "e0 = {cor}, u_a = {anchor_u}, loading = {loading}, u = {u}: {difference:e} ≥ {rounding:e}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn a_series_never_serves_beyond_its_radius_or_across_branches() {
        let ball = Ball::default();
        let mut law = ForceLaw::new(&ball);
        law.set_max_compression(0.01);
        let loading = Anchor::at(&law, 0.0105, true);
        assert!(loading.covers(&law, 0.0101) && !loading.covers(&law, 0.0099), "below um is the unloading branch");
        assert!(!loading.covers(&law, 0.0105 * (1.0 + law.loading.radius) * 1.0001));
        law.set_max_compression(0.0102);
        assert!(!loading.covers(&law, 0.0101), "the loading branch starts at the new um");
        law.set_max_compression(0.01);
        let unloading = Anchor::at(&law, 0.0095, false);
        assert!(unloading.hi < 0.01, "the unloading branch ends below um");
        let mut forgotten = unloading;
        forgotten.forget_unloading();
        assert!(!forgotten.covers(&law, 0.0095), "a larger um moves the unloading curve");
        // Integer exponents give finite series that are exact everywhere; huge ones get no series at all.
        assert_eq!(PowerSeries::new(2.0).radius, 0.5);
        assert_eq!(PowerSeries::new(40.0).radius, 0.0);
    }

    #[test]
    fn the_series_changes_results_only_at_rounding_level() {
        let modes = r161();
        for (z, cor) in [(0.45, 0.53), (0.69, 0.53), (0.80, 0.3)] {
            let ball = Ball { cor, ..Ball::default() };
            let series = run_loop(&modes, &ball, &swing(z), &mut ForceLaw::new(&ball), false);
            let mut exact_law = ForceLaw::new(&ball);
            // A zero radius serves only the expansion point itself: every other force is exp(γ ln u).
            exact_law.loading.radius = 0.0;
            exact_law.unloading.radius = 0.0;
            let exact = run_loop(&modes, &ball, &swing(z), &mut exact_law, false);
            let (series, exact): (Vec<f64>, Vec<f64>) =
                (series.into_iter().map(f64::from_bits).collect(), exact.into_iter().map(f64::from_bits).collect());
            // s, v, w, contact time, peak force, max compression: relative agreement.
            for (i, (a, b)) in series.iter().zip(&exact).take(6).enumerate() {
                assert!(((a - b) / b).abs() < 1e-11, "z = {z}, scalar {i}: {a} vs {b}");
            }
            // Modal velocities against the largest one (rigid modes), amplitudes against the largest amplitude.
            let scale_p = exact.iter().skip(7).step_by(2).fold(0.0f64, |m, v| m.max(v.abs()));
            let scale_q = exact.iter().skip(6).step_by(2).fold(0.0f64, |m, v| m.max(v.abs()));
            for (i, (a, b)) in series.iter().zip(&exact).enumerate().skip(6) {
                let scale = if i % 2 == 0 { scale_q } else { scale_p };
                assert!((a - b).abs() < 1e-11 * scale, "z = {z}, modal value {i}: {a} vs {b}");
            }
        }
    }

    /// Ball (mass m, linear elastic spring k_b) against a wall (mass m_h on a spring k_h to a rigid base):
    /// the two-mass, two-spring closed form, from its normal modes, until the ball spring goes slack.
    /// Returns (separation time, ball velocity then).
    fn two_mass_closed_form(m: f64, k_b: f64, m_h: f64, k_h: f64, v: f64) -> (f64, f64) {
        // det(K − ω² M) = 0 with K = [[k_b, −k_b], [−k_b, k_b + k_h]], M = diag(m, m_h).
        let (a, b, c) = (m * m_h, -(k_b * m_h + (k_b + k_h) * m), k_b * k_h);
        let disc = (b * b - 4.0 * a * c).sqrt();
        let omegas = [((-b - disc) / (2.0 * a)).sqrt(), ((-b + disc) / (2.0 * a)).sqrt()];
        // Mode shapes (s, x) = (1, (k_b − ω² m)/k_b); initial velocity (−v, 0), displacement 0.
        let terms: Vec<(f64, f64, f64)> = omegas
            .iter()
            .map(|&w| {
                let x = (k_b - w * w * m) / k_b;
                let modal_mass = m + m_h * x * x;
                let amplitude = m * (-v) / modal_mass / w;
                (w, x, amplitude)
            })
            .collect();
        let compression = |t: f64| terms.iter().map(|&(w, x, amp)| amp * (w * t).sin() * (x - 1.0)).sum::<f64>();
        let ball_velocity = |t: f64| terms.iter().map(|&(w, _, amp)| amp * w * (w * t).cos()).sum::<f64>();
        let dt = 1e-7;
        let mut t = dt;
        while compression(t + dt) > 0.0 {
            t += dt;
        }
        let (mut lo, mut hi) = (t, t + dt);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if compression(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let t_sep = 0.5 * (lo + hi);
        (t_sep, ball_velocity(t_sep))
    }

    #[test]
    fn the_expanded_solve_meets_the_fixed_point_found_by_bisection() {
        let section = HoopMode::of_section(0.0333, 0.0309, &crate::Material::ALUMINUM, false).expect("hollow");
        let law = PatchLaw::following(&section, 0.0366, 0.02);
        let hoop = HoopScalar::new(1.0, 1.0, law);
        for (u_p, w_p) in [(0.002, 1e-5), (0.008, 4e-4), (0.015, 1.5e-3)] {
            let (psi, slope, curvature) = law.value_slope_and_curvature(u_p);
            let at = Expansion::new(u_p, w_p, psi, slope, curvature);
            // A stage 3e-7 m and 1e-7 m from the prediction, as RK4's middle stages fall.
            let (u_true, w) = (u_p + 3e-7, w_p - 1e-7);
            let delta = u_true - law.value_and_slope(u_true).0 * w;
            let (u, g, psi_u) = hoop.solve(&at, delta, w);
            // u − ψ(u)·w − δ is increasing (ψ′·w ≪ 1): bisect it.
            let (mut lo, mut hi) = (u_true - 1e-5, u_true + 1e-5);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid - law.value_and_slope(mid).0 * w - delta > 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let exact = 0.5 * (lo + hi);
            let (psi_exact, slope_exact) = law.value_and_slope(exact);
            assert!((u - exact).abs() < 1e-15, "u {u} vs {exact}");
            assert!((psi_u - psi_exact).abs() < 1e-13, "ψ {psi_u} vs {psi_exact}");
            assert!((g - 1.0 / (1.0 - slope_exact * w)).abs() < 1e-13, "g {g}");
        }
    }

    #[test]
    fn a_linear_ball_on_a_rigidly_backed_wall_spring_matches_the_two_mass_closed_form() {
        for (k_b, m_h, k_h) in [(2.0e6, 0.1f64, 1.3e7), (2.0e6, 0.03, 2.0e6), (5.0e5, 0.2, 4.0e6)] {
            let ball = Ball { stiffness: k_b, exponent: 1.0, cor: 1.0, ..Ball::default() };
            let v = 40.0;
            let h = 1e-6;
            // Rigid modes with zero shape at the impact point: the wall's base does not move.
            let mut work = Work::new(&[0.0, 0.0], &[0.0, 0.0], [0.0, 0.0], h);
            work.hoop = HoopScalar::new(k_h / m_h, 1.0 / m_h.sqrt(), PatchLaw::constant(1.0));
            let mut law = ForceLaw::new(&ball);
            let mut meter = HoopMeter { w2: k_h / m_h, ..HoopMeter::default() };
            let contact =
                integrate::<true, ()>(&mut work, &mut law, &ball, v, h, &mut meter, &mut ()).expect("integrates");
            assert!(contact.separated);
            let (t_sep, v_sep) = two_mass_closed_form(ball.mass, k_b, m_h, k_h, v);
            assert!(((contact.time - t_sep) / t_sep).abs() < 1e-8, "contact {} vs {t_sep} s", contact.time);
            assert!(((contact.scalars.v - v_sep) / v).abs() < 1e-8, "exit {} vs {v_sep} m/s", contact.scalars.v);
            // What the wall keeps is what the ball lost (elastic ball, rigid base).
            let kept = 0.5 * ball.mass * (v * v - contact.scalars.v * contact.scalars.v);
            assert!((meter.energy - kept).abs() < 1e-8 * 0.5 * ball.mass * v * v, "{} vs {kept} J", meter.energy);
            assert!((meter.stored - meter.returned - meter.energy).abs() < 1e-9 * meter.stored);
        }
    }

    /// ∮F du along a compression path, by the trapezoidal rule on fine steps, with `law` tracking the peak.
    fn work_along(law: &mut ForceLaw, path: &[f64]) -> f64 {
        let mut work = 0.0;
        let mut u_prev = path[0];
        let mut f_prev = law.force(u_prev);
        for pair in path.windows(2) {
            let n = 20_000;
            for i in 1..=n {
                let u = pair[0] + (pair[1] - pair[0]) * i as f64 / n as f64;
                if u > law.um {
                    law.set_max_compression(u);
                }
                let f = law.force(u);
                work += 0.5 * (f + f_prev) * (u - u_prev);
                (u_prev, f_prev) = (u, f);
            }
        }
        work
    }

    #[test]
    fn the_hysteresis_loss_depends_on_the_peak_compression_only() {
        for cor in [0.3, 0.53, 0.8, 1.0] {
            let ball = Ball { cor, ..Ball::default() };
            // One load and unload, and a path whose compression peaks twice (an unload to half the first peak,
            // a reload past it, a full unload): the work done on the ball is the closed form of the last peak.
            for path in [vec![0.0, 0.012, 0.0], vec![0.0, 0.008, 0.004, 0.012, 0.0]] {
                let mut law = ForceLaw::new(&ball);
                let work = work_along(&mut law, &path);
                let closed = ball.hysteresis_loss(0.012);
                assert!(
                    (work - closed).abs() <= 1e-6 * ball.stiffness * 0.012f64.powf(ball.exponent + 1.0),
                    "e0 = {cor}, path {path:?}: ∮F du = {work} vs {closed}"
                );
            }
        }
        assert_eq!(Ball::default().hysteresis_loss(0.0), 0.0);
    }
}
