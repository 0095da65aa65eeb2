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
        if u <= 0.0 {
            0.0
        } else if u >= self.um {
            self.k1 * u.powf(self.alpha)
        } else {
            self.k2 * u.powf(self.beta)
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

/// Per-call buffers: everything the step loop touches, allocated once.
struct Work {
    phi: Vec<f64>,
    w2: Vec<f64>,
    q: Vec<f64>,
    p: Vec<f64>,
    qs: Vec<f64>,
    ps: Vec<f64>,
    acc_q: Vec<f64>,
    acc_p: Vec<f64>,
    // Saved start-of-step state for partial steps.
    q0: Vec<f64>,
    p0: Vec<f64>,
}

impl Work {
    /// Compression and its rate for the modal state (q, p) and ball state.
    #[inline(always)]
    fn u_and_rate(phi: &[f64], q: &[f64], p: &[f64], sc: &Scalars) -> (f64, f64) {
        let mut y = 0.0;
        let mut yd = 0.0;
        for k in 0..phi.len() {
            y += phi[k] * q[k];
            yd += phi[k] * p[k];
        }
        (y - sc.s, yd - sc.v)
    }

    /// One RK4 step of length h from (self.q, self.p, sc); returns the new scalars and the force at the start.
    #[inline(always)]
    fn step(&mut self, sc: &Scalars, h: f64, law: &ForceLaw, inv_mass: f64) -> (Scalars, f64) {
        let n = self.phi.len();
        let (phi, w2) = (&self.phi[..n], &self.w2[..n]);
        let (q, p) = (&mut self.q[..n], &mut self.p[..n]);
        let (qs, ps) = (&mut self.qs[..n], &mut self.ps[..n]);
        let (acc_q, acc_p) = (&mut self.acc_q[..n], &mut self.acc_p[..n]);

        // Stage 1 at the start.
        let (mut u, mut ud) = Self::u_and_rate(phi, q, p, sc);
        let f1 = law.force(u);
        let mut f = f1;
        let mut v_st = sc.v;
        let mut acc_fu = f * ud;
        let mut acc_f = f;
        let mut acc_v = sc.v;
        for k in 0..n {
            qs[k] = q[k];
            ps[k] = p[k];
            acc_q[k] = p[k];
            acc_p[k] = q[k];
        }
        // Stages 2, 3, 4: coefficient a of the increment, weight c in the final sum.
        for &(a, c) in &[(0.5, 2.0), (0.5, 2.0), (1.0, 1.0)] {
            let ah = a * h;
            let mut y = 0.0;
            let mut yd = 0.0;
            for k in 0..n {
                let qn = q[k] + ah * ps[k];
                let pn = p[k] - ah * (w2[k] * qs[k] + f * phi[k]);
                acc_q[k] += c * pn;
                acc_p[k] += c * qn;
                y += phi[k] * qn;
                yd += phi[k] * pn;
                qs[k] = qn;
                ps[k] = pn;
            }
            let s_new = sc.s + ah * v_st;
            let v_new = sc.v + ah * f * inv_mass;
            v_st = v_new;
            u = y - s_new;
            ud = yd - v_st;
            f = law.force(u);
            acc_f += c * f;
            acc_v += c * v_st;
            acc_fu += c * f * ud;
        }
        let h6 = h / 6.0;
        // acc_q holds Σc·p_stage (dq), acc_p holds Σc·q_stage; dp = −ω²q − Fφ.
        for k in 0..n {
            q[k] += h6 * acc_q[k];
            p[k] -= h6 * (w2[k] * acc_p[k] + acc_f * phi[k]);
        }
        let next = Scalars { s: sc.s + h6 * acc_v, v: sc.v + h6 * acc_f * inv_mass, w: sc.w + h6 * acc_fu };
        (next, f1)
    }

    fn save(&mut self) {
        self.q0.copy_from_slice(&self.q);
        self.p0.copy_from_slice(&self.p);
    }

    fn restore(&mut self) {
        self.q.copy_from_slice(&self.q0);
        self.p.copy_from_slice(&self.p0);
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
fn locate(work: &mut Work, start: &Scalars, h: f64, law: &ForceLaw, inv_mass: f64, event: Event, g_start: f64, g_end: f64) -> (f64, Scalars) {
    let value = |work: &mut Work, tau: f64| -> Scalars {
        work.restore();
        work.step(start, tau, law, inv_mass).0
    };
    let g_of = |work: &Work, sc: &Scalars| {
        let (u, ud) = Work::u_and_rate(&work.phi, &work.q, &work.p, sc);
        match event {
            Event::Peak => ud,
            Event::Separation => u,
        }
    };
    let (mut a, mut ga) = (0.0, g_start);
    let (mut b, mut gb) = (h, g_end);
    let mut side = 0i8;
    let mut best = (h, None::<Scalars>);
    for _ in 0..60 {
        let tau = if (ga - gb) != 0.0 { (a * gb - b * ga) / (gb - ga) } else { 0.5 * (a + b) };
        let tau = if tau > a && tau < b { tau } else { 0.5 * (a + b) };
        let sc = value(work, tau);
        let g = g_of(work, &sc);
        best = (tau, Some(sc));
        if g == 0.0 || (b - a) <= 1e-13 * h {
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
        if (b - a) <= 1e-12 * h {
            break;
        }
    }
    // Make sure the stored state is the one at the returned τ.
    let tau = best.0;
    let sc = match best.1 {
        Some(sc) => sc,
        None => value(work, tau),
    };
    if event == Event::Separation {
        // Leave the state where u ≤ 0 is guaranteed to the rounding of the root.
        let _ = g_end;
    }
    (tau, sc)
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
    let mut work = Work {
        phi,
        w2,
        q,
        p,
        qs: vec![0.0; nm],
        ps: vec![0.0; nm],
        acc_q: vec![0.0; nm],
        acc_p: vec![0.0; nm],
        q0: vec![0.0; nm],
        p0: vec![0.0; nm],
    };
    let inv_mass = 1.0 / ball.mass;
    let beta = ball.unloading_exponent();
    let mut law = ForceLaw { k1: ball.stiffness, alpha: ball.exponent, k2: 0.0, beta, um: 0.0 };
    let initial_energy = 0.5 * ball.mass * impact.ball_speed.powi(2)
        + 0.5 * (work.p[0] * work.p[0] + work.p[1] * work.p[1]);

    let h = options.time_step;
    let mut sc = Scalars { s: 0.0, v: -impact.ball_speed, w: 0.0 };
    let mut t = 0.0;
    let mut peak_force: f64 = 0.0;
    let mut just_peaked = false;
    let max_steps = (MAX_CONTACT_TIME / h).ceil() as usize + 1;
    let mut separated = false;
    for _ in 0..max_steps {
        let (u0, ud0) = Work::u_and_rate(&work.phi, &work.q, &work.p, &sc);
        let loading = u0 >= law.um && ud0 > 0.0 && !just_peaked;
        just_peaked = false;
        work.save();
        let start = sc;
        let (next, f_start) = work.step(&start, h, &law, inv_mass);
        peak_force = peak_force.max(f_start);
        let (u1, ud1) = Work::u_and_rate(&work.phi, &work.q, &work.p, &next);
        if !(u1.is_finite() && ud1.is_finite() && next.v.is_finite()) {
            return Err(PhysicsError::Numerical(format!("non-finite state at t = {t:e} s")));
        }
        if loading && ud1 <= 0.0 && u1 > 0.0 {
            // Maximum compression inside this step: stop exactly there and switch to unloading.
            let (tau, sc_peak) = locate(&mut work, &start, h, &law, inv_mass, Event::Peak, ud0, ud1);
            let (u_peak, _) = Work::u_and_rate(&work.phi, &work.q, &work.p, &sc_peak);
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
        if u1 <= 0.0 && t + h > 0.0 && law.um > 0.0 {
            let (tau, sc_sep) = locate(&mut work, &start, h, &law, inv_mass, Event::Separation, u0, u1);
            t += tau;
            sc = sc_sep;
            separated = true;
            break;
        }
        t += h;
        sc = next;
        if u1 > law.um {
            law.um = u1;
            law.k2 = ball.unloading_stiffness(u1);
        }
    }
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
    Ok(result)
}
