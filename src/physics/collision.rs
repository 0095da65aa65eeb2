//! Ball–bat collision in modal space: fixed-step RK4 from first contact to separation.
//!
//! Axis: y points from the bat toward the incoming ball, so the ball starts with velocity −ball_speed and
//! leaves with +exit_speed. Modal amplitudes q_n (unit modal mass) of the translation, the rotation and the
//! first n vibrational modes, the ball offset s (ball centre minus its position at first contact) and its
//! velocity v obey
//!   q̈_n + ω_n² q_n = −F·Y_n(z_k),   m_ball·s̈ = +F,   u = Σ Y_n(z_k) q_n − s,   F = F(u) ≥ 0 while u > 0,
//! where Y_n(z_k) is mode n's displacement interpolated linearly between the two slice centres around the
//! impact point (the same weights spread the force onto those slices, so force and displacement stay
//! power-conjugate and the energy budget closes exactly). The work done on the ball, W = ∫F·u̇ dt, is an
//! extra state; at separation it equals the hysteresis loss.
//!
//! RK4 runs with the fixed step `time_step`; within a step in which the compression rate u̇ changes sign on
//! the loading curve, the step is repeated with the root of u̇ (maximum compression) as its length, so the
//! switch to the unloading curve happens exactly at u_m. Separation (u = 0) is located the same way; the
//! state at that instant gives the results. The bat is rigid-body moving and not vibrating at t = 0.

use super::rigid;
use super::{Ball, ModeSet, PhysicsError};

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

/// Initial conditions of one collision (conventions in the module docs of [`crate::physics`]).
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
        CollisionOptions {
            modes: 18,
            time_step: 5e-6,
        }
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
            return Err(PhysicsError::out_of_range("time_step", self.time_step, format!("{lo:e} ≤ time_step ≤ {hi:e} s")));
        }
        if self.modes > 0 {
            let omega_max = modes.vibrational_modes()[self.modes - 1].angular_frequency;
            let limit = MAX_OMEGA_STEP / omega_max;
            if self.time_step > limit {
                return Err(PhysicsError::out_of_range(
                    "time_step",
                    self.time_step,
                    format!("≤ {limit:.3e} s (RK4 stability for mode {} at {:.0} Hz)", self.modes, omega_max / std::f64::consts::TAU),
                ));
            }
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
    /// initial − (ball + bat_rigid + vibration + hysteresis_loss), J.
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
}

/// The frozen force law of one step: loading k1·u^α at or beyond `um`, unloading k2·u^β below it.
#[derive(Clone, Copy)]
struct ForceLaw {
    k1: f64,
    alpha: f64,
    k2: f64,
    beta: f64,
    um: f64,
}

impl ForceLaw {
    #[inline(always)]
    fn force(&self, u: f64) -> f64 {
        // exp(α ln u) rather than powf: same accuracy here (|α ln u| < 100, relative error < 1e-13) and a
        // shorter latency on the step's critical path.
        if u <= 0.0 {
            0.0
        } else if u >= self.um {
            self.k1 * (self.alpha * u.ln()).exp()
        } else {
            self.k2 * (self.beta * u.ln()).exp()
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
    /// Work done on the ball, J.
    w: f64,
}

/// Per-mode RK4 propagation coefficients for one step length h (see [`Work::step`]).
struct StepCoeffs {
    h: f64,
    cqq: Vec<f64>,
    cqp: Vec<f64>,
    cpq: Vec<f64>,
}

impl StepCoeffs {
    fn new(n: usize) -> StepCoeffs {
        StepCoeffs {
            h: 0.0,
            cqq: vec![0.0; n],
            cqp: vec![0.0; n],
            cpq: vec![0.0; n],
        }
    }

    fn set(&mut self, h: f64, w2: &[f64]) {
        self.h = h;
        let (h2, h3, h4) = (h * h, h * h * h, h * h * h * h);
        // The p–p coefficient equals the q–q one; the force terms' ω²-parts use φω² (pw1) times scalars.
        for k in 0..w2.len() {
            let w = w2[k];
            self.cqq[k] = 1.0 - 0.5 * h2 * w + h4 * w * w / 24.0;
            self.cqp[k] = h - h3 * w / 6.0;
            self.cpq[k] = -h * w + h3 * w * w / 6.0;
        }
    }
}

/// Per-call buffers: everything the step loop touches, allocated once.
struct Work {
    /// Mode shapes at the impact point Y_n(z_k), m per unit amplitude.
    phi: Vec<f64>,
    /// ω_n², 1/s².
    w2: Vec<f64>,
    /// φ·ω² and φ·ω⁴, for the stage projections.
    pw1: Vec<f64>,
    pw2: Vec<f64>,
    /// Σφ² and Σφ²ω².
    c0: f64,
    c1: f64,
    q: Vec<f64>,
    p: Vec<f64>,
    /// The state at the end of the step just taken (double buffer, swapped in by `accept`).
    q_next: Vec<f64>,
    p_next: Vec<f64>,
    /// Projections (Σφq, Σφp, Σφω²q, Σφω²p, Σφω⁴q) of the current state, kept up to date by every update.
    proj: [f64; 5],
    proj_next: [f64; 5],
    full: StepCoeffs,
    partial: StepCoeffs,
}

impl Work {
    fn new(phi: Vec<f64>, w2: Vec<f64>, q: Vec<f64>, p: Vec<f64>, h: f64) -> Work {
        let n = phi.len();
        let pw1: Vec<f64> = (0..n).map(|k| phi[k] * w2[k]).collect();
        let pw2: Vec<f64> = (0..n).map(|k| phi[k] * w2[k] * w2[k]).collect();
        let c0 = phi.iter().map(|f| f * f).sum();
        let c1 = (0..n).map(|k| phi[k] * phi[k] * w2[k]).sum();
        let mut full = StepCoeffs::new(n);
        full.set(h, &w2);
        let mut work = Work {
            pw1,
            pw2,
            c0,
            c1,
            q_next: vec![0.0; n],
            p_next: vec![0.0; n],
            proj: [0.0; 5],
            proj_next: [0.0; 5],
            full,
            partial: StepCoeffs::new(n),
            phi,
            w2,
            q,
            p,
        };
        work.project();
        work
    }

    /// Recomputes the cached projections from scratch.
    fn project(&mut self) {
        let mut proj = [0.0; 5];
        for k in 0..self.phi.len() {
            proj[0] += self.phi[k] * self.q[k];
            proj[1] += self.phi[k] * self.p[k];
            proj[2] += self.pw1[k] * self.q[k];
            proj[3] += self.pw1[k] * self.p[k];
            proj[4] += self.pw2[k] * self.q[k];
        }
        self.proj = proj;
    }

    /// Compression and its rate for the current modal state and ball state `sc`.
    #[inline(always)]
    fn u_and_rate(&self, sc: &Scalars) -> (f64, f64) {
        (self.proj[0] - sc.s, self.proj[1] - sc.v)
    }

    /// One classical RK4 step of length `partial.h` (if `use_partial`) or the full step, from the current
    /// state; returns the new scalars and the force at the start.
    ///
    /// The modal equations are linear between force evaluations, so RK4's four stages are written out in
    /// closed form: the stage displacements and velocities at the impact point need only five projections
    /// (Σφq, Σφp, Σφω²q, Σφω²p, Σφω⁴q) and the final update per mode is
    ///   q' = (1 − h²ω²/2 + h⁴ω⁴/24) q + (h − h³ω²/6) p − φ h²/6 (F1+F2+F3) + φ ω² h⁴/24 F1,
    ///   p' = (−hω² + h³ω⁴/6) q + (1 − h²ω²/2 + h⁴ω⁴/24) p − φ h/6 (F1+2F2+2F3+F4) + φ ω² h³/12 (F1+F2),
    /// which is algebraically identical to the four-stage RK4 step for q̈ + ω²q = −Fφ.
    #[inline(always)]
    fn step(&mut self, sc: &Scalars, use_partial: bool, law: &ForceLaw, inv_mass: f64) -> (Scalars, f64) {
        let n = self.phi.len();
        let c = if use_partial { &self.partial } else { &self.full };
        let (phi, pw1, pw2) = (&self.phi[..n], &self.pw1[..n], &self.pw2[..n]);
        let (q, p) = (&self.q[..n], &self.p[..n]);
        let (qo, po) = (&mut self.q_next[..n], &mut self.p_next[..n]);
        let [a0, b0, a1, b1, a2] = self.proj;
        let (c0, c1) = (self.c0, self.c1);
        let h = c.h;
        let a = 0.5 * h;
        let (s, v) = (sc.s, sc.v);
        // Stage 1.
        let f1 = law.force(a0 - s);
        let ud1 = b0 - v;
        // Stage 2.
        let u2 = a0 + a * b0 - (s + a * v);
        let ud2 = b0 - a * a1 - a * f1 * c0 - (v + a * f1 * inv_mass);
        let f2 = law.force(u2);
        // Stage 3.
        let u3 = a0 + a * b0 - a * a * (a1 + f1 * c0) - (s + a * v + a * a * f1 * inv_mass);
        let ud3 = b0 - a * a1 - a * a * b1 - a * f2 * c0 - (v + a * f2 * inv_mass);
        let f3 = law.force(u3);
        // Stage 4.
        let u4 = a0 + h * b0 - h * a * a1 - h * a * a * b1 - h * a * f2 * c0 - (s + h * v + h * a * f2 * inv_mass);
        let ud4 = b0 - h * a1 - h * a * b1 + h * a * a * a2 + h * a * a * f1 * c1 - h * f3 * c0 - (v + h * f3 * inv_mass);
        let f4 = law.force(u4);

        let fq = -h * h / 6.0 * (f1 + f2 + f3);
        let sum_f = f1 + 2.0 * f2 + 2.0 * f3 + f4;
        let fp = -h / 6.0 * sum_f;
        let f12 = f1 + f2;
        let (cqq, cqp, cpq) = (&c.cqq[..n], &c.cqp[..n], &c.cpq[..n]);
        // φ ω² h⁴/24 F1 and φ ω² h³/12 (F1+F2) as pw1 times scalars.
        let gq = h * h * h * h / 24.0 * f1;
        let gp = h * h * h / 12.0 * f12;
        // Update every mode and, in the same pass, the projections of the new state (two partial sums per
        // projection to shorten the floating-point dependency chain).
        let (mut y0, mut yd0, mut y1, mut yd1, mut yy0) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let (mut y0b, mut yd0b, mut y1b, mut yd1b, mut yy0b) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let pairs = n / 2;
        for j in 0..pairs {
            let k = 2 * j;
            let (qk, pk) = (q[k], p[k]);
            let qn = cqq[k] * qk + cqp[k] * pk + phi[k] * fq + pw1[k] * gq;
            let pn = cpq[k] * qk + cqq[k] * pk + phi[k] * fp + pw1[k] * gp;
            qo[k] = qn;
            po[k] = pn;
            y0 += phi[k] * qn;
            yd0 += phi[k] * pn;
            y1 += pw1[k] * qn;
            yd1 += pw1[k] * pn;
            yy0 += pw2[k] * qn;
            let k = k + 1;
            let (qk, pk) = (q[k], p[k]);
            let qn = cqq[k] * qk + cqp[k] * pk + phi[k] * fq + pw1[k] * gq;
            let pn = cpq[k] * qk + cqq[k] * pk + phi[k] * fp + pw1[k] * gp;
            qo[k] = qn;
            po[k] = pn;
            y0b += phi[k] * qn;
            yd0b += phi[k] * pn;
            y1b += pw1[k] * qn;
            yd1b += pw1[k] * pn;
            yy0b += pw2[k] * qn;
        }
        if n % 2 == 1 {
            let k = n - 1;
            let (qk, pk) = (q[k], p[k]);
            let qn = cqq[k] * qk + cqp[k] * pk + phi[k] * fq + pw1[k] * gq;
            let pn = cpq[k] * qk + cqq[k] * pk + phi[k] * fp + pw1[k] * gp;
            qo[k] = qn;
            po[k] = pn;
            y0 += phi[k] * qn;
            yd0 += phi[k] * pn;
            y1 += pw1[k] * qn;
            yd1 += pw1[k] * pn;
            yy0 += pw2[k] * qn;
        }
        self.proj_next = [y0 + y0b, yd0 + yd0b, y1 + y1b, yd1 + yd1b, yy0 + yy0b];
        let next = Scalars {
            s: s + h * v + h * h / 6.0 * (f1 + f2 + f3) * inv_mass,
            v: v + h / 6.0 * sum_f * inv_mass,
            w: sc.w + h / 6.0 * (f1 * ud1 + 2.0 * f2 * ud2 + 2.0 * f3 * ud3 + f4 * ud4),
        };
        (next, f1)
    }

    /// Compression and its rate at the end of the step just taken.
    #[inline(always)]
    fn next_u_and_rate(&self, sc: &Scalars) -> (f64, f64) {
        (self.proj_next[0] - sc.s, self.proj_next[1] - sc.v)
    }

    /// Makes the end of the step just taken the current state.
    #[inline(always)]
    fn accept(&mut self) {
        std::mem::swap(&mut self.q, &mut self.q_next);
        std::mem::swap(&mut self.p, &mut self.p_next);
        self.proj = self.proj_next;
    }
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
fn locate(work: &mut Work, start: &Scalars, h: f64, law: &ForceLaw, inv_mass: f64, event: Event, g_start: f64, g_end: f64) -> (f64, Scalars) {
    let value = |work: &mut Work, tau: f64| -> Scalars {
        let Work { partial, w2, .. } = work;
        partial.set(tau, w2);
        work.step(start, true, law, inv_mass).0
    };
    let g_of = |work: &Work, sc: &Scalars| {
        let (u, ud) = work.next_u_and_rate(sc);
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

/// State at the end of contact.
#[derive(Clone, Copy)]
struct Contact {
    scalars: Scalars,
    time: f64,
    peak_force: f64,
    separated: bool,
}

/// The fixed-step RK4 loop from first contact to separation (see the module docs).
fn integrate(work: &mut Work, law: &mut ForceLaw, ball: &Ball, ball_speed: f64, h: f64) -> Result<Contact, PhysicsError> {
    let inv_mass = 1.0 / ball.mass;
    let mut sc = Scalars { s: 0.0, v: -ball_speed, w: 0.0 };
    let mut t = 0.0;
    let mut peak_force: f64 = 0.0;
    let mut just_peaked = false;
    let max_steps = (MAX_CONTACT_TIME / h).ceil() as usize + 1;
    let mut separated = false;
    for _ in 0..max_steps {
        let (u0, ud0) = work.u_and_rate(&sc);
        let loading = u0 >= law.um && ud0 > 0.0 && !just_peaked;
        just_peaked = false;
        let start = sc;
        let (next, f_start) = work.step(&start, false, law, inv_mass);
        peak_force = peak_force.max(f_start);
        let (u1, ud1) = work.next_u_and_rate(&next);
        if !(u1.is_finite() && ud1.is_finite() && next.v.is_finite()) {
            return Err(PhysicsError::Numerical(format!("non-finite state at t = {t:e} s")));
        }
        if loading && ud1 <= 0.0 && u1 > 0.0 {
            // Maximum compression inside this step: stop exactly there and switch to unloading.
            let (tau, sc_peak) = locate(work, &start, h, law, inv_mass, Event::Peak, ud0, ud1);
            let (u_peak, _) = work.next_u_and_rate(&sc_peak);
            work.accept();
            t += tau;
            sc = sc_peak;
            if u_peak > law.um {
                law.um = u_peak;
                law.k2 = ball.unloading_stiffness(u_peak);
            }
            peak_force = peak_force.max(law.force(u_peak));
            just_peaked = true;
            continue;
        }
        if u1 <= 0.0 && law.um > 0.0 {
            // Separation inside this step (u̇ < 0 here, so u crossed zero from above).
            let (tau, sc_sep) = locate(work, &start, h, law, inv_mass, Event::Separation, u0, u1);
            work.accept();
            t += tau;
            sc = sc_sep;
            separated = true;
            break;
        }
        work.accept();
        t += h;
        sc = next;
        if u1 > law.um {
            law.um = u1;
            law.k2 = ball.unloading_stiffness(u1);
        }
    }
    Ok(Contact { scalars: sc, time: t, peak_force, separated })
}

/// Runs one collision of `ball` with the bat described by `modes`.
pub fn collide(
    modes: &ModeSet,
    ball: &Ball,
    impact: &Impact,
    options: &CollisionOptions,
) -> Result<CollisionResult, PhysicsError> {
    ball.validate()?;
    impact.validate(modes)?;
    options.validate(modes)?;
    let mp = modes.mass_properties();
    let nm = 2 + options.modes;
    let z = impact.impact_z;

    let all = &modes.all_modes()[..nm];
    let phi: Vec<f64> = (0..nm).map(|k| modes.shape_at(k, z)).collect();
    let w2: Vec<f64> = all.iter().map(|m| m.angular_frequency * m.angular_frequency).collect();
    let q = vec![0.0; nm];
    let mut p = vec![0.0; nm];
    // Rigid initial velocities: ẏ = V + ω (z − z_cm) = p_0/√M + p_1 (z − z_cm)/√I.
    p[0] = impact.bat_cm_speed * mp.mass.sqrt();
    p[1] = impact.bat_angular_speed * mp.moment_of_inertia.sqrt();
    let h = options.time_step;
    let mut work = Work::new(phi, w2, q, p, h);
    let beta = ball.unloading_exponent();
    let mut law = ForceLaw { k1: ball.stiffness, alpha: ball.exponent, k2: 0.0, beta, um: 0.0 };
    let initial_energy = 0.5 * ball.mass * impact.ball_speed.powi(2)
        + 0.5 * (work.p[0] * work.p[0] + work.p[1] * work.p[1]);

    let contact = integrate(&mut work, &mut law, ball, impact.ball_speed, h)?;
    let Contact { scalars: sc, time: t, peak_force, separated } = contact;
    if !separated {
        return Err(PhysicsError::Numerical(format!(
            "ball and bat did not separate within {MAX_CONTACT_TIME} s (impact_z = {z} m)"
        )));
    }

    let p = &work.p;
    let q = &work.q;
    let exit_speed = sc.v;
    let bat_rigid = 0.5 * (p[0] * p[0] + p[1] * p[1]);
    let mode_energies: Vec<ModeEnergy> = (2..nm)
        .map(|k| ModeEnergy {
            frequency: all[k].angular_frequency / std::f64::consts::TAU,
            energy: 0.5 * (p[k] * p[k] + work.w2[k] * q[k] * q[k]),
        })
        .collect();
    let vibration: f64 = mode_energies.iter().map(|m| m.energy).sum();
    let ball_energy = 0.5 * ball.mass * exit_speed * exit_speed;
    let residual = initial_energy - (ball_energy + bat_rigid + vibration + sc.w);
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
            hysteresis_loss: sc.w,
            residual,
        },
        bat_cm_speed_after: p[0] / mp.mass.sqrt(),
        bat_angular_speed_after: p[1] / mp.moment_of_inertia.sqrt(),
    };
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
            options.time_step, relative_residual
        )));
    }
    Ok(result)
}
