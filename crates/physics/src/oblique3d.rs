//! The batted ball in three dimensions: a tilted bat swung in any horizontal direction, giving the exit
//! velocity vector (speed, launch angle, spray angle) and the spin vector (backspin, sidespin, gyro spin).
//!
//! # Frame and conventions
//! The **field frame** is right-handed: x̂ **forward** (from home plate toward the pitcher and centre field),
//! ŷ **left** (toward the third-base / left-field side), ẑ **up**. The geometry is that of a right-handed
//! batter, whose barrel points to the first-base side (−ŷ) when the bat is square to the pitch; a
//! left-handed batter's swing is its mirror image in the x–z plane ([`BatterSide::Left`] reflects the inputs
//! and the answer, so every angle below keeps its field meaning for both).
//! Angles are in radians, angular velocities in rad/s, speeds in m/s.
//! - The pitch arrives from the pitcher along −x̂, descending by the pitch angle θ: v = −v_ball (cos θ, 0, sin θ).
//!   Its spin is backspin about the horizontal axis across its path, `pitch_spin` (positive for backspin
//!   relative to its travel): ω_in = pitch_spin ŷ.
//! - The bat's **path** p̂ (the direction its impact point moves) rises by the attack angle α and points
//!   `swing_direction` δ to the right of centre field (toward the first-base side, as trackers measure the
//!   spray angle): p̂ = (cos α cos δ, −cos α sin δ, sin α).
//! - The bat's **long axis** â (knob → barrel) is perpendicular to its path, as for any bat turning about an
//!   axis across its length, and falls by the **tilt** ψ below the horizontal (barrel below the hands:
//!   positive): â = (cos ψ sin χ, −cos ψ cos χ, −sin ψ) with sin(χ + δ) = tan ψ tan α, which needs
//!   |ψ| + |α| < 90°. For ψ = δ = 0 it is ê = −ŷ, the planar model's bat axis.
//! - "Up" in the impact plane (the plane through the impact point perpendicular to â) is q̂ = â × p̂, and the
//!   **line of centres** is n̂ = cos φ p̂ + sin φ q̂ with sin φ = D/(R + R_k): the undercut D is the offset of
//!   the ball's centre from the bat's path, perpendicular to the bat, measured along q̂ (positive "above").
//!   The tangent plane at the contact is spanned by t̂ = â × n̂ (around the bat) and â (along it).
//! - Outputs: the exit velocity v′ gives the exit speed |v′|, the **launch angle** (above the horizontal) and the
//!   **spray angle** (horizontal, positive toward the right-field / first-base side, as TrackMan's Direction).
//!   The spin vector ω′ is split along the ball's flight v̂: **backspin** about b̂ = ĥ × ẑ (ĥ the horizontal
//!   heading; positive lifts the ball), **sidespin** about ŵ = b̂ × v̂ (positive curves the ball toward the
//!   left-field side, a right-handed batter's hook) and **gyro spin** along v̂ (no Magnus force). The
//!   **total spin** |ω′| is what a radar reports. The **spin axis** is TrackMan's HitSpinAxis: the direction of
//!   the Magnus force ω′ × v̂ seen from behind the plate, 180° for pure backspin, 0° for pure topspin, 90° for
//!   pure hook (toward left field) and 270° for pure slice: atan2(sidespin, −backspin) in [0°, 360°).
//!
//! # Model
//! The same impulsive contact as the planar model ([`super::oblique`]), with the tangential slip a vector:
//!
//! **Normal** — the flexible modal collision along n̂, driven by the normal approach of ball and bat:
//! ball speed −v·n̂, bat motion (V_cm, ω) scaled by p̂·n̂ = cos φ.
//!
//! **Tangential** — the slip of the contact points s = P_t (v − V_k p̂ − R ω_in × n̂) (P_t removes the n̂
//! part, V_k is the bat's speed at the impact point) has a component s_t around the bat and s_a along it. An
//! impulse J = J_t t̂ + J_a â on the ball at the contact point (−J on the bat at the same point) changes the
//! slip by W J with the diagonal inverse mass W = diag(w_t, w_a):
//!
//!   w_t = 1/m + R²/I_ball + 1/M_eff(z_k) + R_k²/I_axial   (as in the planar model: the bat recoils across
//!                                                          its path and rolls about its axis)
//!   w_a = 1/m + R²/I_ball + 1/M + R_k²/I_cm                (the bat slides along its axis and turns about t̂:
//!                                                          the force along â acts R_k off the axis)
//!
//! (derivation: the bat's velocity change at r = (z_k − z_cm) â + R_k n̂ under −J is J/M + I⁻¹(r × J) × r
//! with I = diag(I_cm, I_cm, I_axial); its â and t̂ parts are the two lines above, and its n̂ part,
//! −R_k (z_k − z_cm) J_a/I_cm, is neglected: it couples the tangential impulse into the normal collision by
//! under 0.2 % of the normal inverse mass for |J_a| ≤ μ J_n.)
//! The ball grips and returns part of its stretch, s′ = −e_T s, i.e. J = −(1 + e_T) W⁻¹ s, unless that
//! exceeds Coulomb friction, |J| > μ J_n; then the ball slides throughout and J = −μ J_n ŝ, opposing the slip
//! it arrived with. (For an isotropic W — a fixed cylinder — sliding keeps the slip's direction and this is
//! exact; for the R161, w_a/w_t ≈ 0.9 and the slip turns little while it slides.) The compliant law
//! ([`super::oblique::TangentialContact::stiffness_ratio`]) runs one tangential spring per direction,
//! k_t = (dF_n/du)/η², with one Coulomb cap on the force's magnitude.
//!
//! The outgoing ball: v′ = (normal exit speed) n̂ + P_t v + J/m, ω′ = ω_in − R n̂ × J / I_ball.
//!
//! **The planar model is the special case** ψ = δ = 0 (the pitch then lies in the impact plane): there s_a = 0,
//! J_a = 0 and every number is the planar one. That case is computed by [`collide_oblique`] itself, so an old
//! swing's answer stays bit for bit; tests check that the general path agrees with it to rounding.
//!
//! # What the model leaves out
//! - The bat's own rotation moves the contact point along the bat: the barrel's surface facing the ball sits
//!   R_k ahead of its axis, so the swing's angular velocity ω carries it toward the pivot at ω R_k cos φ
//!   (~1.5 m/s for ω = 45 rad/s). The planar model's bat velocity is the axis's (V_cm + ω (z − z_cm)) and this
//!   model keeps it, so that the planar swings stay exact; the term would add an axial slip of that size
//!   (roughly 300–400 rpm of sidespin while the ball grips). Named here so it can be added when data separate it.
//! - The pitch's spin is pure backspin about the horizontal axis across its path (no pitch spin axis tilt or
//!   gyro component); its horizontal approach angle is 0.
//! - As in the planar model: impulsive contact, a tangentially rigid bat, constant e_T.

use nalgebra::Vector3;

use super::collision::{collide, collide_observed, CollisionOptions, CollisionResult, ContactObserver, Impact};
use super::oblique::{
    axial_moment_of_inertia, check_approach, collide_oblique, grip_step, tangential_inverse_mass, ObliqueImpact,
    ObliqueResult, TangentialContact,
};
use super::{Ball, ModeSet, PhysicsError};

/// Largest |bat tilt| and |swing direction| accepted, rad (80°).
const MAX_ANGLE: f64 = 80.0 * std::f64::consts::PI / 180.0;

/// Which side of the plate the batter stands on: which way the barrel points.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BatterSide {
    /// A right-handed batter: the barrel points to the first-base side.
    #[default]
    Right,
    /// A left-handed batter: the barrel points to the third-base side (the mirror image).
    Left,
}

/// One swing in three dimensions: the planar swing plus the bat's tilt, its path's horizontal direction and
/// the batter's side.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SpatialImpact {
    /// The planar swing: speeds, impact point, barrel radius, undercut, attack and pitch angles, pitch spin.
    pub oblique: ObliqueImpact,
    /// Tilt ψ of the bat's long axis below the horizontal at contact (barrel below the hands positive), rad.
    pub bat_tilt: f64,
    /// Horizontal direction δ of the bat's path at the impact point, rad, positive toward the right-field
    /// (first-base) side: the tracker's attack direction in the field frame.
    pub swing_direction: f64,
    /// The batter's side.
    pub batter_side: BatterSide,
}

impl SpatialImpact {
    /// The planar swing `oblique` with a level bat swung toward centre field by a right-handed batter.
    pub fn planar(oblique: ObliqueImpact) -> SpatialImpact {
        SpatialImpact { oblique, bat_tilt: 0.0, swing_direction: 0.0, batter_side: BatterSide::Right }
    }

    /// True when the swing lies in one vertical plane (ψ = δ = 0): the planar model's case.
    pub fn is_planar(&self) -> bool {
        self.bat_tilt == 0.0 && self.swing_direction == 0.0
    }

    /// Checks the spatial fields (the planar ones are checked by [`collide_oblique`]).
    pub fn validate(&self) -> Result<(), PhysicsError> {
        for (field, v) in [("bat_tilt", self.bat_tilt), ("swing_direction", self.swing_direction)] {
            if !(v.is_finite() && v.abs() <= MAX_ANGLE) {
                return Err(PhysicsError::out_of_range(field, v, format!("|{field}| ≤ {MAX_ANGLE:.4} rad (80°)")));
            }
        }
        let reach = self.bat_tilt.abs() + self.oblique.attack_angle.abs();
        if !(reach < 0.5 * std::f64::consts::PI - 1e-6) {
            return Err(PhysicsError::out_of_range(
                "bat_tilt",
                self.bat_tilt,
                "|bat_tilt| + |attack_angle| < 90° (a bat perpendicular to its path cannot be tilted further)",
            ));
        }
        Ok(())
    }
}

/// The contact geometry as unit vectors in the field frame (right-handed batter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactFrame {
    /// Bat's long axis â, knob → barrel.
    pub axis: Vector3<f64>,
    /// Bat's path p̂ at the impact point (perpendicular to `axis`).
    pub path: Vector3<f64>,
    /// Line of centres n̂, from the bat's axis to the ball's centre (perpendicular to `axis`).
    pub normal: Vector3<f64>,
}

impl ContactFrame {
    /// The frame of a right-handed batter's swing: attack α, direction δ, tilt ψ (rad), line of centres φ
    /// above the path (rad). Needs |ψ| + |α| < 90°.
    pub fn new(attack: f64, direction: f64, tilt: f64, phi: f64) -> ContactFrame {
        let (sa, ca) = attack.sin_cos();
        let (sd, cd) = direction.sin_cos();
        let (sp, cp) = tilt.sin_cos();
        let path = Vector3::new(ca * cd, -ca * sd, sa);
        let chi = (tilt.tan() * attack.tan()).clamp(-1.0, 1.0).asin() - direction;
        let (sc, cc) = chi.sin_cos();
        let axis = Vector3::new(cp * sc, -cp * cc, -sp);
        let up = axis.cross(&path);
        let (sf, cf) = phi.sin_cos();
        ContactFrame { axis, path, normal: path * cf + up * sf }
    }

    /// The tangent around the bat, t̂ = â × n̂.
    pub fn around(&self) -> Vector3<f64> {
        self.axis.cross(&self.normal)
    }
}

/// Everything the contact needs besides the bat's modes and the ball: the incoming ball's velocity and spin,
/// the frame, the bat's speeds along its path, the impact point and the barrel's radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialContact {
    /// Incoming ball velocity, m/s (field frame).
    pub ball_velocity: Vector3<f64>,
    /// Incoming ball spin, rad/s (field frame).
    pub ball_spin: Vector3<f64>,
    /// The contact's geometry.
    pub frame: ContactFrame,
    /// Bat CM speed along its path, m/s.
    pub bat_cm_speed: f64,
    /// Bat angular speed about its CM (barrel leading positive), rad/s.
    pub bat_angular_speed: f64,
    /// Impact point, m from the knob.
    pub impact_z: f64,
    /// Barrel radius at the impact point, m.
    pub barrel_radius: f64,
}

/// Outcome of a collision in three dimensions, SI units, field frame (conventions in the module docs).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SpatialResult {
    /// Ball exit speed, m/s.
    pub exit_speed: f64,
    /// Launch angle above the horizontal, rad, in [−π/2, π/2] (a planar swing keeps the planar model's
    /// angle from the forward direction, above π/2 for a ball popped up behind the plate).
    pub launch_angle: f64,
    /// Spray angle, rad, positive toward the right-field (first-base) side, in (−π, π].
    pub spray_angle: f64,
    /// Backspin, rad/s (about the horizontal axis across the flight; positive lifts).
    pub backspin: f64,
    /// Sidespin, rad/s (positive curves the ball toward the left-field side).
    pub sidespin: f64,
    /// Gyro spin, rad/s (along the flight, right-handed about it).
    pub gyro_spin: f64,
    /// Total spin |ω′|, rad/s: what a radar reports.
    pub total_spin: f64,
    /// Spin axis, rad in [0, 2π): TrackMan's HitSpinAxis (π = pure backspin, π/2 = pure hook).
    pub spin_axis: f64,
    /// Exit velocity (forward, left, up), m/s.
    pub velocity: [f64; 3],
    /// Spin vector (forward, left, up), rad/s.
    pub spin_vector: [f64; 3],
    /// Slip of the contact points before contact (forward, left, up), m/s.
    pub slip_before: [f64; 3],
    /// Tangential impulse on the ball (forward, left, up), N·s.
    pub tangential_impulse: [f64; 3],
    /// True when friction bound: the ball slid throughout the contact.
    pub sliding: bool,
    /// Outgoing ball velocity along the line of centres (away from the bat), m/s.
    pub normal_exit_speed: f64,
    /// Outgoing ball velocity along the tangent around the bat t̂, m/s.
    pub tangential_exit_speed: f64,
    /// The approach along the line of centres that drove the normal collision.
    pub normal_impact: Impact,
    /// The normal collision along the line of centres.
    pub normal: CollisionResult,
}

impl SpatialResult {
    /// The answer of the planar swing `oblique` in the field frame (bat axis ê = −ŷ).
    fn from_planar(planar: &ObliqueResult, oblique: &ObliqueImpact) -> SpatialResult {
        let (forward, up) = planar.velocity();
        let beta = planar.line_of_centres_angle;
        let (sb, cb) = beta.sin_cos();
        // t̂ = (−sin β, 0, cos β); the slip and impulse lie along it.
        let along_t = |x: f64| [-x * sb, 0.0, x * cb];
        SpatialResult {
            exit_speed: planar.exit_speed,
            launch_angle: planar.launch_angle,
            spray_angle: 0.0,
            backspin: planar.spin,
            sidespin: 0.0,
            gyro_spin: 0.0,
            total_spin: planar.spin.abs(),
            spin_axis: if planar.spin >= 0.0 { std::f64::consts::PI } else { 0.0 },
            velocity: [forward, 0.0, up],
            spin_vector: [0.0, -planar.spin, 0.0],
            slip_before: along_t(planar.slip_before),
            tangential_impulse: along_t(planar.tangential_impulse),
            sliding: planar.sliding,
            normal_exit_speed: planar.normal_exit_speed,
            tangential_exit_speed: planar.tangential_exit_speed,
            normal_impact: planar_normal_impact(oblique, beta),
            normal: planar.normal.clone(),
        }
    }

    /// Reflects the answer in the x–z plane (a left-handed batter's mirror image).
    fn mirrored(mut self) -> SpatialResult {
        let flip = |v: &mut [f64; 3]| v[1] = -v[1];
        flip(&mut self.velocity);
        flip(&mut self.slip_before);
        flip(&mut self.tangential_impulse);
        // Spin is an axial vector: under a reflection in the x–z plane its y part stays and x, z change sign.
        self.spin_vector = [-self.spin_vector[0], self.spin_vector[1], -self.spin_vector[2]];
        self.spray_angle = -self.spray_angle;
        self.sidespin = -self.sidespin;
        self.gyro_spin = -self.gyro_spin;
        self.spin_axis = wrap_angle(-self.spin_axis);
        self
    }
}

/// The approach along the line of centres (at `beta` above the horizontal) that the planar model's normal
/// collision is driven by: the ball's speed times cos(β − θ), the bat's motion times cos φ with φ = β − α.
fn planar_normal_impact(oblique: &ObliqueImpact, beta: f64) -> Impact {
    let cos_phi = (beta - oblique.attack_angle).cos();
    let i = &oblique.impact;
    Impact {
        ball_speed: i.ball_speed * (beta - oblique.pitch_angle).cos(),
        bat_cm_speed: i.bat_cm_speed * cos_phi,
        bat_angular_speed: i.bat_angular_speed * cos_phi,
        impact_z: i.impact_z,
    }
}

/// `angle` wrapped into [0, 2π), rad.
fn wrap_angle(angle: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let wrapped = angle.rem_euclid(tau);
    if wrapped >= tau {
        0.0
    } else {
        wrapped
    }
}

/// The direction of a batted ball's flight and its spin split along it (conventions in the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flight {
    /// Spray angle, rad, positive toward the right-field side.
    pub spray: f64,
    /// Launch angle above the horizontal, rad.
    pub launch: f64,
    /// Backspin, rad/s.
    pub backspin: f64,
    /// Sidespin, rad/s, positive toward the left-field side.
    pub sidespin: f64,
    /// Gyro spin along the flight, rad/s.
    pub gyro: f64,
    /// Total spin, rad/s.
    pub total: f64,
    /// TrackMan's spin axis, rad in [0, 2π).
    pub axis: f64,
}

/// The flight of a ball leaving with velocity `v` (m/s) and spin `w` (rad/s), both in the field frame.
pub fn flight_components(v: &Vector3<f64>, w: &Vector3<f64>) -> Flight {
    let horizontal = v.x.hypot(v.y);
    let launch = v.z.atan2(horizontal);
    let spray = (-v.y).atan2(v.x);
    let heading = if horizontal > 0.0 { Vector3::new(v.x / horizontal, v.y / horizontal, 0.0) } else { Vector3::x() };
    let flight = v.normalize();
    let back_axis = heading.cross(&Vector3::z());
    let side_axis = back_axis.cross(&flight);
    let (back, side, gyro) = (w.dot(&back_axis), w.dot(&side_axis), w.dot(&flight));
    Flight { spray, launch, backspin: back, sidespin: side, gyro, total: w.norm(), axis: wrap_angle(side.atan2(-back)) }
}

/// The two-direction compliant tangential contact: one spring per tangent direction (k_t = k_n/η²), each
/// with its own inverse mass, sharing one Coulomb cap |g| ≤ μ F_n. The planar [`super::oblique::CompliantTangent`]
/// is its one-direction case.
#[derive(Debug, Clone, Copy)]
struct CompliantTangent2 {
    inverse_mass: [f64; 2],
    stiffness_ratio: f64,
    friction: f64,
    slip: [f64; 2],
    force: [f64; 2],
    gripped: bool,
}

impl ContactObserver for CompliantTangent2 {
    fn step(&mut self, dt: f64, start: (f64, f64), end: (f64, f64)) {
        let k = 0.5 * (start.1 + end.1) / self.stiffness_ratio;
        let next = [0, 1].map(|i| grip_step(self.slip[i], self.force[i], k, self.inverse_mass[i], dt));
        let cap = self.friction * end.0;
        let magnitude = next[0].1.hypot(next[1].1);
        if magnitude <= cap {
            for i in 0..2 {
                (self.slip[i], self.force[i]) = next[i];
            }
            self.gripped = true;
            return;
        }
        // Sliding: the force is held at μ F_n along the direction the springs pull.
        for i in 0..2 {
            let force = if magnitude > 0.0 { cap * next[i].1 / magnitude } else { 0.0 };
            self.slip[i] -= self.inverse_mass[i] * 0.5 * (self.force[i] + force) * dt;
            self.force[i] = force;
        }
    }
}

/// A collision in three dimensions (model and conventions in the module docs). A planar swing (ψ = δ = 0) is
/// answered by [`collide_oblique`] itself.
pub fn collide_spatial(
    modes: &ModeSet,
    ball: &Ball,
    impact: &SpatialImpact,
    contact: &TangentialContact,
    options: &CollisionOptions,
) -> Result<SpatialResult, PhysicsError> {
    impact.validate()?;
    let oblique = &impact.oblique;
    let mirrored = impact.batter_side == BatterSide::Left;
    // A left-handed swing is the right-handed swing reflected: the direction changes sign, the rest stays.
    let direction = if mirrored { -impact.swing_direction } else { impact.swing_direction };
    let result = if impact.bat_tilt == 0.0 && direction == 0.0 {
        SpatialResult::from_planar(&collide_oblique(modes, ball, oblique, contact, options)?, oblique)
    } else {
        ball.validate()?;
        oblique.validate(ball.radius)?;
        contact.validate()?;
        let phi = (oblique.undercut / (ball.radius + oblique.barrel_radius)).asin();
        let frame = ContactFrame::new(oblique.attack_angle, direction, impact.bat_tilt, phi);
        let (sp, cp) = oblique.pitch_angle.sin_cos();
        let spatial = SpatialContact {
            ball_velocity: Vector3::new(-cp, 0.0, -sp) * oblique.impact.ball_speed,
            ball_spin: Vector3::new(0.0, oblique.pitch_spin, 0.0),
            frame,
            bat_cm_speed: oblique.impact.bat_cm_speed,
            bat_angular_speed: oblique.impact.bat_angular_speed,
            impact_z: oblique.impact.impact_z,
            barrel_radius: oblique.barrel_radius,
        };
        collide_vectors(modes, ball, &spatial, contact, options)?
    };
    Ok(if mirrored { result.mirrored() } else { result })
}

/// The collision of [`collide_spatial`] for any contact given as vectors: the general path, valid in any
/// rotated frame (a test rotates it).
pub fn collide_vectors(
    modes: &ModeSet,
    ball: &Ball,
    c: &SpatialContact,
    contact: &TangentialContact,
    options: &CollisionOptions,
) -> Result<SpatialResult, PhysicsError> {
    let mp = modes.mass_properties();
    let (n, a) = (c.frame.normal, c.frame.axis);
    let t = c.frame.around();
    let cos_phi = c.frame.path.dot(&n);
    let normal_impact = Impact {
        ball_speed: -c.ball_velocity.dot(&n),
        bat_cm_speed: c.bat_cm_speed * cos_phi,
        bat_angular_speed: c.bat_angular_speed * cos_phi,
        impact_z: c.impact_z,
    };
    check_approach(&mp, &normal_impact)?;
    let bat_speed = c.bat_cm_speed + c.bat_angular_speed * (c.impact_z - mp.center_of_mass);
    let relative = c.ball_velocity - c.frame.path * bat_speed - c.ball_spin.cross(&n) * ball.radius;
    let slip = [relative.dot(&t), relative.dot(&a)];

    let ball_inertia = contact.ball_inertia_ratio * ball.mass * ball.radius * ball.radius;
    let rk = c.barrel_radius;
    let inverse_mass = [
        tangential_inverse_mass(
            ball.mass,
            ball.radius,
            ball_inertia,
            mp.effective_mass_at(c.impact_z),
            rk,
            axial_moment_of_inertia(modes),
        ),
        tangential_inverse_mass(ball.mass, ball.radius, ball_inertia, mp.mass, rk, mp.moment_of_inertia),
    ];
    let (normal, impulse, sliding) =
        normal_and_tangential(modes, ball, &normal_impact, options, contact, slip, inverse_mass)?;
    let j = t * impulse[0] + a * impulse[1];
    let v_tangential = c.ball_velocity - n * c.ball_velocity.dot(&n);
    let velocity = n * normal.exit_speed + v_tangential + j / ball.mass;
    let spin = c.ball_spin - n.cross(&j) * (ball.radius / ball_inertia);
    let flight = flight_components(&velocity, &spin);
    let result = SpatialResult {
        exit_speed: velocity.norm(),
        launch_angle: flight.launch,
        spray_angle: flight.spray,
        backspin: flight.backspin,
        sidespin: flight.sidespin,
        gyro_spin: flight.gyro,
        total_spin: flight.total,
        spin_axis: flight.axis,
        velocity: velocity.into(),
        spin_vector: spin.into(),
        slip_before: (t * slip[0] + a * slip[1]).into(),
        tangential_impulse: j.into(),
        sliding,
        normal_exit_speed: normal.exit_speed,
        tangential_exit_speed: velocity.dot(&t),
        normal_impact,
        normal,
    };
    if !(result.exit_speed.is_finite() && result.total_spin.is_finite() && result.spin_axis.is_finite()) {
        return Err(PhysicsError::Numerical("spatial collision produced a non-finite result".into()));
    }
    Ok(result)
}

/// The normal collision and the tangential impulse (around, along the bat; N·s) it carries for a slip
/// (around, along; m/s) with inverse masses (1/kg): impulsive under a constant e_T, or integrated through the
/// contact with a compliant tangent. The flag says whether the ball slid.
fn normal_and_tangential(
    modes: &ModeSet,
    ball: &Ball,
    normal_impact: &Impact,
    options: &CollisionOptions,
    contact: &TangentialContact,
    slip: [f64; 2],
    inverse_mass: [f64; 2],
) -> Result<(CollisionResult, [f64; 2], bool), PhysicsError> {
    Ok(match contact.stiffness_ratio {
        None => {
            let normal = collide(modes, ball, normal_impact, options)?;
            let (impulse, sliding) = grip_or_slide(slip, inverse_mass, normal.impulse, contact);
            (normal, impulse, sliding)
        }
        Some(eta2) => {
            let mut tangent = CompliantTangent2 {
                inverse_mass,
                stiffness_ratio: eta2,
                friction: contact.friction,
                slip,
                force: [0.0; 2],
                gripped: false,
            };
            let normal = collide_observed(modes, ball, normal_impact, options, &mut tangent)?;
            let impulse = [0, 1].map(|i| (tangent.slip[i] - slip[i]) / inverse_mass[i]);
            (normal, impulse, !tangent.gripped)
        }
    })
}

/// The tangential impulse (around, along the bat), N·s, for a slip (around, along) in m/s with inverse
/// masses (w_t, w_a) in 1/kg under a normal impulse `normal_impulse` N·s: the gripping −(1 + e_T) W⁻¹ s, or
/// μ J_n against the slip when that exceeds friction. Returns the impulse and whether the ball slid.
pub fn grip_or_slide(
    slip: [f64; 2],
    inverse_mass: [f64; 2],
    normal_impulse: f64,
    contact: &TangentialContact,
) -> ([f64; 2], bool) {
    let grip = [0, 1].map(|i| -(1.0 + contact.tangential_cor) * slip[i] / inverse_mass[i]);
    let cap = contact.friction * normal_impulse.max(0.0);
    if grip[0].hypot(grip[1]) <= cap {
        return (grip, false);
    }
    let speed = slip[0].hypot(slip[1]);
    if speed == 0.0 {
        return ([0.0; 2], true);
    }
    ([-cap * slip[0] / speed, -cap * slip[1] / speed], true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Bat, Material, Station};
    use nalgebra::Rotation3;

    fn r161() -> ModeSet {
        ModeSet::compute(&Bat::preset("r161").expect("r161"), 8).expect("modes")
    }

    fn swing(undercut: f64, attack_deg: f64) -> ObliqueImpact {
        let impact = Impact { ball_speed: 38.0, bat_cm_speed: 22.0, bat_angular_speed: 48.0, impact_z: 0.70 };
        ObliqueImpact {
            undercut,
            attack_angle: attack_deg.to_radians(),
            pitch_angle: 6f64.to_radians(),
            pitch_spin: 230.0,
            ..ObliqueImpact::head_on(impact, 0.0325)
        }
    }

    const OPTS: CollisionOptions = CollisionOptions { modes: 8, time_step: 2e-6 };

    /// The general path for a planar swing (bypassing the planar delegation).
    fn general(modes: &ModeSet, ball: &Ball, o: &ObliqueImpact, contact: &TangentialContact) -> SpatialResult {
        let phi = (o.undercut / (ball.radius + o.barrel_radius)).asin();
        let (sp, cp) = o.pitch_angle.sin_cos();
        let c = SpatialContact {
            ball_velocity: Vector3::new(-cp, 0.0, -sp) * o.impact.ball_speed,
            ball_spin: Vector3::new(0.0, o.pitch_spin, 0.0),
            frame: ContactFrame::new(o.attack_angle, 0.0, 0.0, phi),
            bat_cm_speed: o.impact.bat_cm_speed,
            bat_angular_speed: o.impact.bat_angular_speed,
            impact_z: o.impact.impact_z,
            barrel_radius: o.barrel_radius,
        };
        collide_vectors(modes, ball, &c, contact, &OPTS).expect("collides")
    }

    #[test]
    fn a_level_square_swing_is_the_planar_model_bit_for_bit_and_the_general_path_agrees() {
        let modes = r161();
        let ball = Ball::default();
        for (undercut, attack) in [(0.0, 0.0), (0.012, 8.0), (-0.02, 12.0), (0.055, 10.0)] {
            let o = swing(undercut, attack);
            for contact in
                [TangentialContact::default(), TangentialContact { stiffness_ratio: Some(4.75), ..Default::default() }]
            {
                let planar = collide_oblique(&modes, &ball, &o, &contact, &OPTS).expect("planar");
                let spatial =
                    collide_spatial(&modes, &ball, &SpatialImpact::planar(o), &contact, &OPTS).expect("spatial");
                assert_eq!(spatial.exit_speed.to_bits(), planar.exit_speed.to_bits());
                assert_eq!(spatial.launch_angle.to_bits(), planar.launch_angle.to_bits());
                assert_eq!(spatial.backspin.to_bits(), planar.spin.to_bits());
                assert_eq!((spatial.spray_angle, spatial.sidespin, spatial.gyro_spin), (0.0, 0.0, 0.0));
                let g = general(&modes, &ball, &o, &contact);
                let close = |x: f64, y: f64, what: &str| {
                    assert!((x - y).abs() <= 1e-9 * (1.0 + y.abs()), "{what}: general {x} vs planar {y}")
                };
                close(g.exit_speed, planar.exit_speed, "exit speed");
                // Compare the velocity, not the angles: a ball popped up behind the plate has a planar launch
                // angle above 90° where the spatial one reads 180° − that with a spray of 180°.
                let (forward, up) = planar.velocity();
                close(g.velocity[0], forward, "forward velocity");
                close(g.velocity[2], up, "upward velocity");
                assert!(g.velocity[1].abs() < 1e-12);
                // The spin vector: ê = −ŷ carries the planar spin (backspin relative to the flight flips for a
                // ball going backward).
                close(g.spin_vector[1], -planar.spin, "spin about the bat");
                close(g.total_spin, planar.spin.abs(), "total spin");
                assert!(g.sidespin.abs() < 1e-9 && g.gyro_spin.abs() < 1e-9);
                assert_eq!(g.sliding, planar.sliding);
            }
        }
    }

    #[test]
    fn a_tilted_bat_meeting_a_level_pitch_without_spin_is_the_planar_answer_rolled_by_the_tilt() {
        // Pitch along −x̂, level bat path (α = θ = 0), no pitch spin: the whole scene is the planar one rolled
        // by ψ about x̂, so the exit velocity and spin are the planar ones rolled by ψ (computed by the planar
        // code, a separate path).
        let modes = r161();
        let ball = Ball::default();
        for undercut in [0.0, 0.02, -0.03, 0.06] {
            let o = ObliqueImpact { pitch_spin: 0.0, pitch_angle: 0.0, ..swing(undercut, 0.0) };
            let planar = collide_oblique(&modes, &ball, &o, &TangentialContact::default(), &OPTS).expect("planar");
            for tilt_deg in [10.0, 32.0, -20.0] {
                let tilt = f64::to_radians(tilt_deg);
                let s = SpatialImpact { bat_tilt: tilt, ..SpatialImpact::planar(o) };
                let r = collide_spatial(&modes, &ball, &s, &TangentialContact::default(), &OPTS).expect("spatial");
                let roll = Rotation3::from_axis_angle(&Vector3::x_axis(), tilt);
                let (forward, up) = planar.velocity();
                let v = roll * Vector3::new(forward, 0.0, up);
                let w = roll * Vector3::new(0.0, -planar.spin, 0.0);
                for i in 0..3 {
                    assert!((r.velocity[i] - v[i]).abs() < 1e-9, "tilt {tilt_deg}: v {:?} vs {v:?}", r.velocity);
                    assert!((r.spin_vector[i] - w[i]).abs() < 1e-7, "tilt {tilt_deg}: ω {:?} vs {w:?}", r.spin_vector);
                }
            }
        }
    }

    #[test]
    fn rotating_every_input_vector_rotates_the_answer() {
        let modes = r161();
        let ball = Ball::default();
        let frame = ContactFrame::new(0.2, -0.3, 0.5, 0.4);
        let base = SpatialContact {
            ball_velocity: Vector3::new(-37.0, 2.0, -4.0),
            ball_spin: Vector3::new(30.0, 200.0, -50.0),
            frame,
            bat_cm_speed: 20.0,
            bat_angular_speed: 45.0,
            impact_z: 0.69,
            barrel_radius: 0.0325,
        };
        let contact = TangentialContact::default();
        let r0 = collide_vectors(&modes, &ball, &base, &contact, &OPTS).expect("base");
        let rotation = Rotation3::from_euler_angles(0.7, -1.1, 2.3);
        let turned = SpatialContact {
            ball_velocity: rotation * base.ball_velocity,
            ball_spin: rotation * base.ball_spin,
            frame: ContactFrame {
                axis: rotation * frame.axis,
                path: rotation * frame.path,
                normal: rotation * frame.normal,
            },
            ..base
        };
        let r1 = collide_vectors(&modes, &ball, &turned, &contact, &OPTS).expect("turned");
        let v0 = rotation * Vector3::from(r0.velocity);
        let w0 = rotation * Vector3::from(r0.spin_vector);
        for i in 0..3 {
            assert!((r1.velocity[i] - v0[i]).abs() < 1e-9, "{:?} vs {v0:?}", r1.velocity);
            assert!((r1.spin_vector[i] - w0[i]).abs() < 1e-7, "{:?} vs {w0:?}", r1.spin_vector);
        }
        assert!((r1.total_spin - r0.total_spin).abs() < 1e-7);
        assert_eq!(r1.sliding, r0.sliding);
    }

    /// A heavy, stiff cylinder (~150 kg).
    fn heavy_cylinder() -> ModeSet {
        let heavy = Material { density: 1.0e5, youngs_modulus: 1.0e13, shear_modulus: 1.0e13 };
        let stations = vec![
            Station { z: 0.0, outer_radius: 0.04, inner_radius: 0.0 },
            Station { z: 0.3, outer_radius: 0.04, inner_radius: 0.0 },
        ];
        let bat = Bat::new("heavy cylinder", stations, heavy, None, 0.015).expect("cylinder");
        ModeSet::compute(&bat, 2).expect("modes")
    }

    /// The velocity change of a free rigid bat's surface point `lever` (from its centre of mass) under the
    /// impulse `impulse` there: Newton–Euler with the full inertia tensor (I_axial about `axis`, I_cm across).
    fn bat_point_kick(modes: &ModeSet, axis: Vector3<f64>, lever: Vector3<f64>, impulse: Vector3<f64>) -> Vector3<f64> {
        let mp = modes.mass_properties();
        let i_axial = axial_moment_of_inertia(modes);
        let l = lever.cross(&impulse);
        let dw = axis * (l.dot(&axis) / i_axial) + (l - axis * l.dot(&axis)) / mp.moment_of_inertia;
        impulse / mp.mass + dw.cross(&lever)
    }

    #[test]
    fn gripping_and_sliding_in_three_dimensions_follow_the_rigid_body_closed_forms() {
        // A spinning ball meets a heavy cylinder at rest, at its centre of mass, with a slip that has parts
        // around and along the axis. From the answer alone (the ball's v′ and ω′, the bat's response from
        // Newton–Euler): gripping, the contact points' relative velocity after contact is −e_T times the slip
        // before (Cross's tangential COR, in both directions at once); sliding, the tangential impulse is μ J_n
        // against the slip; and always the ball's angular momentum about the contact point is conserved.
        let modes = heavy_cylinder();
        let mp = modes.mass_properties();
        let ball = Ball::default();
        let opts = CollisionOptions { modes: 0, time_step: 1e-6 };
        let frame = ContactFrame::new(0.0, 0.0, 0.6, 0.3);
        let (n, a, rk) = (frame.normal, frame.axis, 0.04);
        let incoming = -n * 30.0 + a * 4.0 + frame.around() * 2.0;
        let spin_in = Vector3::new(40.0, -120.0, 60.0);
        let c = SpatialContact {
            ball_velocity: incoming,
            ball_spin: spin_in,
            frame,
            bat_cm_speed: 0.0,
            bat_angular_speed: 0.0,
            impact_z: mp.center_of_mass,
            barrel_radius: rk,
        };
        let tangential = |u: Vector3<f64>| u - n * u.dot(&n);
        let ball_point = |v: Vector3<f64>, w: Vector3<f64>| v - w.cross(&n) * ball.radius;
        let slip = tangential(ball_point(incoming, spin_in));
        let inertia = TangentialContact::default().ball_inertia_ratio * ball.mass * ball.radius * ball.radius;
        let about_contact = |v: Vector3<f64>, w: Vector3<f64>| w * inertia + (n * ball.radius).cross(&(v * ball.mass));
        for (e_t, mu) in [(0.405, 5.0), (0.0, 5.0), (1.0, 5.0), (0.405, 0.05)] {
            let contact = TangentialContact { tangential_cor: e_t, friction: mu, ..TangentialContact::default() };
            let r = collide_vectors(&modes, &ball, &c, &contact, &opts).expect("collides");
            let (v1, w1) = (Vector3::from(r.velocity), Vector3::from(r.spin_vector));
            let impulse = (v1 - incoming) * ball.mass;
            let bat_point = bat_point_kick(&modes, a, n * rk, -impulse);
            let after = tangential(ball_point(v1, w1) - bat_point);
            let j_t = tangential(impulse);
            let j_n = impulse.dot(&n);
            if mu > 1.0 {
                assert!(!r.sliding);
                assert!((after + slip * e_t).norm() < 1e-9 * slip.norm(), "e_T {e_t}: {after:?} vs {:?}", -slip * e_t);
            } else {
                assert!(r.sliding);
                assert!((j_t.norm() - mu * j_n).abs() < 1e-9 * j_n, "|J_t| {} vs μ J_n {}", j_t.norm(), mu * j_n);
                assert!((j_t.normalize() + slip.normalize()).norm() < 1e-9, "friction against the slip");
            }
            let dl = about_contact(v1, w1) - about_contact(incoming, spin_in);
            assert!(dl.norm() < 1e-9, "ΔL about the contact point {dl:?}");
        }
    }

    #[test]
    fn a_free_rigid_bat_conserves_momentum_and_an_elastic_grip_conserves_energy() {
        // A rigid bat (no vibrational modes), an elastic linear ball (e0 = 1) and e_T = 1, hit at the bat's
        // centre of mass so that the neglected normal–tangential coupling vanishes: the bat's response,
        // computed here from Newton–Euler with its full inertia tensor, must conserve momentum, angular
        // momentum and kinetic energy with the ball's answer.
        let modes = r161();
        let mp = modes.mass_properties();
        let i_axial = axial_moment_of_inertia(&modes);
        let ball = Ball { exponent: 1.0, cor: 1.0, stiffness: 2e6, cor_speed_exponent: 0.0, ..Ball::default() };
        let opts = CollisionOptions { modes: 0, time_step: 2e-7 };
        let frame = ContactFrame::new(0.15, 0.2, 0.5, 0.35);
        let (n, a, rk) = (frame.normal, frame.axis, 0.03);
        let c = SpatialContact {
            ball_velocity: Vector3::new(-35.0, 1.0, -3.5),
            ball_spin: Vector3::new(0.0, 200.0, 0.0),
            frame,
            bat_cm_speed: 25.0,
            bat_angular_speed: 0.0,
            impact_z: mp.center_of_mass,
            barrel_radius: rk,
        };
        let contact = TangentialContact { tangential_cor: 1.0, friction: 10.0, ..TangentialContact::default() };
        let r = collide_vectors(&modes, &ball, &c, &contact, &opts).expect("collides");
        assert!(!r.sliding);
        // Total impulse on the ball, from its momentum change; the bat takes its opposite at the contact.
        let v1 = Vector3::from(r.velocity);
        let w1 = Vector3::from(r.spin_vector);
        let impulse = (v1 - c.ball_velocity) * ball.mass;
        let lever = n * rk;
        let bat_v0 = frame.path * c.bat_cm_speed;
        let bat_v1 = bat_v0 - impulse / mp.mass;
        let l = lever.cross(&(-impulse));
        let bat_w1 = a * (l.dot(&a) / i_axial) + (l - a * l.dot(&a)) / mp.moment_of_inertia;
        let inertia = contact.ball_inertia_ratio * ball.mass * ball.radius * ball.radius;
        let energy = |v: Vector3<f64>, w: Vector3<f64>, bv: Vector3<f64>, bw: Vector3<f64>| {
            let bat_rot = bw.dot(&a).powi(2) * i_axial + (bw - a * bw.dot(&a)).norm_squared() * mp.moment_of_inertia;
            0.5 * (ball.mass * v.norm_squared() + inertia * w.norm_squared() + mp.mass * bv.norm_squared() + bat_rot)
        };
        let before = energy(c.ball_velocity, c.ball_spin, bat_v0, Vector3::zeros());
        let after = energy(v1, w1, bat_v1, bat_w1);
        assert!((after - before).abs() < 2e-4 * before, "energy {before} → {after}");
        // The ball's spin change is the moment of the tangential impulse about its centre.
        let j_t = impulse - n * impulse.dot(&n);
        let dw = (-n * ball.radius).cross(&j_t) / inertia;
        assert!(((w1 - c.ball_spin) - dw).norm() < 1e-6 * dw.norm());
    }

    #[test]
    fn a_left_handed_swing_is_the_mirror_image() {
        let modes = r161();
        let ball = Ball::default();
        let right = SpatialImpact { bat_tilt: 0.5, swing_direction: -0.25, ..SpatialImpact::planar(swing(0.02, 10.0)) };
        let left = SpatialImpact { swing_direction: 0.25, batter_side: BatterSide::Left, ..right };
        let contact = TangentialContact::default();
        let r = collide_spatial(&modes, &ball, &right, &contact, &OPTS).expect("right");
        let l = collide_spatial(&modes, &ball, &left, &contact, &OPTS).expect("left");
        assert_eq!(l.exit_speed, r.exit_speed);
        assert_eq!(l.launch_angle, r.launch_angle);
        assert_eq!(l.spray_angle, -r.spray_angle);
        assert_eq!((l.backspin, l.sidespin), (r.backspin, -r.sidespin));
        assert!((l.spin_axis - (std::f64::consts::TAU - r.spin_axis)).abs() < 1e-12);
    }

    #[test]
    fn spin_components_and_the_trackman_axis_of_hand_made_spins() {
        let v = Vector3::new(30.0, 0.0, 30.0 * 20f64.to_radians().tan());
        // Backspin lifts: ω along ĥ × ẑ = −ŷ for a ball flying along +x̂.
        let f = flight_components(&v, &Vector3::new(0.0, -100.0, 0.0));
        assert_eq!(f.spray, 0.0);
        assert!((f.backspin - 100.0).abs() < 1e-12 && f.sidespin.abs() < 1e-12 && f.gyro.abs() < 1e-12);
        assert_eq!(f.total, 100.0);
        assert!((f.axis.to_degrees() - 180.0).abs() < 1e-9);
        // A spin about the vertical (counter-clockwise from above) pushes the ball toward +ŷ, left field: a
        // hook, axis 90°-ish (the flight rises 20°, so part of it is gyro).
        let f = flight_components(&v, &Vector3::new(0.0, 0.0, 100.0));
        assert!(f.backspin.abs() < 1e-12 && (f.sidespin - 100.0 * 20f64.to_radians().cos()).abs() < 1e-9);
        assert!((f.gyro - 100.0 * 20f64.to_radians().sin()).abs() < 1e-9);
        assert!((f.axis.to_degrees() - 90.0).abs() < 1e-9);
        // Toward the right field (−ŷ): positive spray.
        let f = flight_components(&Vector3::new(10.0, -10.0, 0.0), &Vector3::zeros());
        assert!((f.spray.to_degrees() - 45.0).abs() < 1e-12);
    }

    #[test]
    fn the_bat_axis_is_perpendicular_to_its_path_and_tilted_as_asked() {
        for (attack, direction, tilt) in [(0.2, 0.3, 0.5), (-0.1, -0.4, 0.9), (0.3, 0.0, -0.4)] {
            let f = ContactFrame::new(attack, direction, tilt, 0.2);
            assert!(f.axis.dot(&f.path).abs() < 1e-15 && f.axis.dot(&f.normal).abs() < 1e-15);
            assert!((f.axis.z + f64::sin(tilt)).abs() < 1e-15, "barrel below the hands by the tilt");
            assert!((f.path.z - f64::sin(attack)).abs() < 1e-15);
            assert!((f.axis.norm() - 1.0).abs() < 1e-15 && (f.normal.norm() - 1.0).abs() < 1e-15);
        }
        let err = SpatialImpact { bat_tilt: 1.2, ..SpatialImpact::planar(swing(0.0, 30.0)) }.validate().unwrap_err();
        assert!(matches!(err, PhysicsError::OutOfRange { ref field, .. } if field == "bat_tilt"), "{err}");
    }
}
