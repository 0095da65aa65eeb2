//! Pure, synchronous bat–ball physics in SI units: no I/O, no async, no ROS types.
//!
//! Conventions (used everywhere in sweetspot):
//! - `z` is measured in metres from the knob (handle end) along the bat's long axis;
//! - ball speed is positive toward the bat;
//! - bat centre-of-mass speed is positive toward the ball;
//! - bat angular speed (rad/s) is positive when the barrel end moves faster (toward the ball) than the handle;
//! - exit speed is positive away from the bat.
//!
//! Pipeline: [`bat::Bat`] → [`modes::ModeSet`] (computed once per bat) → [`collision::collide`] with a
//! [`ball::Ball`] and an [`collision::Impact`] → [`collision::CollisionResult`]; [`metrics`] builds sweet
//! spots, BBCOR/BESR and sweeps on top, and [`rigid`] holds the closed-form rigid-bat (Brody) model.
//!
//! # The discrete Timoshenko beam (energy method)
//! The bat is cut into N slices of thickness Δz (see [`bat`]); slice i has centre z_i, mass
//! m_i = Δz·Σρ·A, rotary inertia J_i = Δz·Σρ·I, and the section stiffnesses (YI)_i = ΣY·I, (SA)_i = ΣS·A
//! (sums over shell and core). Its coordinates are the transverse displacement y_i of the centre and the
//! rotation φ_i of the section (φ = dy/dz in pure bending). The kinetic energy is
//! T = ½ Σ m_i ẏ_i² + ½ Σ J_i φ̇_i², so **M = diag(m_1 … m_N, J_1 … J_N)** is diagonal. Neighbouring slices
//! are joined by N − 1 links; link i (between slices i and i+1) stores
//!
//!   V_i = ½ (YI)_l Δz ((φ_{i+1} − φ_i)/Δz)²  +  ½ (SA)_l Δz ((y_{i+1} − y_i)/Δz − (φ_i + φ_{i+1})/2)²,
//!
//! bending plus shear (no shear coefficient), and **K = ∂²V/∂x²** is symmetric by construction. Both strains
//! vanish exactly for a rigid translation (y_i = c, φ_i = 0) and a rigid rotation (y_i = θ z_i, φ_i = θ), and
//! for nothing else (each link removes two independent combinations), so K's null space is exactly the two
//! rigid modes — the free–free boundary conditions need no extra equations. The link properties (YI)_l,
//! (SA)_l are those of the knob-side slice i by default ([`modes::LinkRule::KnobSide`]): comparing with Nathan's
//! own matrix `tests/data/H_matrix_Alan.csv` entry by entry shows that this is his convention, with no shear
//! coefficient and with his rotation Φ_i = −φ_i Δz (e.g. H(1,1) = −S/(ρΔz²), H(1,85) = +S/(2ρΔz²)); the test
//! `stiffness_matrix_reproduces_nathans_h_matrix_entry_by_entry` checks all 996 stored entries. We keep it
//! as the default because Nathan's Y and S for the R161 were chosen with that discretisation; it is first
//! order in Δz for a tapered bat, and [`modes::LinkRule::Mean`] (the mean of both slices) is the second-order
//! alternative (≈ 1.4 % higher first frequency for the R161 at Δz = 1 cm).
//!
//! Normal modes solve K v = ω² M v. We diagonalise the symmetric A = M^{-1/2} K M^{-1/2} (real ω², orthonormal
//! x, v = M^{-1/2} x is M-orthonormal). A is banded (half-bandwidth 3 with y and φ interleaved): its lowest
//! eigenvalues come from a band-to-tridiagonal reduction and Sturm bisection, and each kept mode's vector
//! from inverse iteration on the banded pencil K − λM (nalgebra's full dense decomposition is the
//! alternative, see [`modes::EigenSolver`]; a test checks that both agree). The two zero modes are replaced
//! by the exact, mass-normalised rigid modes (translation y = 1/√M; rotation about the CM y = (z − z_cm)/√I, φ = 1/√I, with M = Σm,
//! I = Σm (z − z_cm)² + ΣJ); the vibrational modes are M-orthogonalised against them and renormalised, and
//! ω² is the Rayleigh quotient. Every mode has unit modal mass: Σ m y² + Σ J φ² = 1.
//!
//! # The collision in modal space
//! The ball (mass m, radius R) meets the bat at z_k. With y pointing from the bat toward the incoming ball,
//! x = Σ_n q_n v_n, unit modal masses and the force F ≥ 0 pushing the bat surface at z_k in −y,
//! Lagrange's equations give, for the two rigid modes and the first n vibrational modes,
//!
//!   q̈_n + ω_n² q_n = −F · Y_n(z_k),      m s̈ = +F,      u = Σ_n Y_n(z_k) q_n − s,
//!
//! where s is the ball centre's displacement from first contact, u the compression (F(u) only while u > 0,
//! see [`ball`]) and Y_n(z_k) the mode's displacement at z_k (linear between slice centres, so the generalised
//! force and the contact displacement are power-conjugate). At t = 0: u = 0, q = 0, q̇_0 = V_cm √M,
//! q̇_1 = ω √I, q̇_n = 0 for vibrations, ṡ = −v_ball. Vibrational modes carry no momentum or angular momentum
//! (M-orthogonal to the rigid ones), so the bat's CM speed after contact is q̇_0/√M and its angular speed
//! q̇_1/√I.
//!
//! # Energy budget
//! E = ½ m ṡ² + Σ_n ½ (q̇_n² + ω_n² q_n²) + W, with Ẇ = F u̇, is an exact invariant of these equations; at
//! separation (u = 0) W is the energy the ball's hysteresis dissipated. W needs no integration: below the
//! peak compression u_m the ball follows the unloading curve, which is elastic, so W = ∮F du depends on u_m
//! only, W = (1 − e0²)·k1 u_m^(α+1)/(α+1) ([`Ball::hysteresis_loss`]; a compression that peaks twice gives the
//! same with the higher peak). We report `initial − (ball + bat rigid + vibration + W)` as the residual: the
//! energy error of the RK4 integration itself. Energy in vibrational mode n after separation:
//! ½ (q̇_n² + ω_n² q_n²).
//!
//! # Closed forms (Nathan eqs. 24–27)
//! R0 = m/M·(1 + ((z_k − z_cm)/r_γ)²), v_f = (e − R0)/(1 + R0)·v_ball + (1 + e)/(1 + R0)·v_bat with
//! v_bat = V_cm + ω (z_k − z_cm); the rigid exit speed uses e = e0, and e_eff is eq. 27 solved for e:
//! e_eff = (v_f (1 + R0) + R0 v_ball − v_bat)/(v_ball + v_bat). Collision efficiency
//! e_A = (v_f − v_bat)/(v_ball + v_bat).
//!
//! # Misprints in the seed paper (MCM 2010 team 6406), corrected here
//! - Eq. 5 is printed as an expression, ω_i b² − 2 v_i b − ω_i I (M+m)/(m M), without "= 0". With "= 0" it
//!   is the stationarity condition of eq. 4 in the seed's frame (v_i the ball's velocity relative to the bat's
//!   CM, ω_i of the opposite sense, so v_i/ω_i < 0), and eq. 6 (+ root) is then its maximum. In our
//!   conventions (c = v_ball + V_cm > 0, ω > 0 when the barrel leads) the same optimum reads
//!   ω b² + 2 c b − ω K = 0, b* = −c/ω + √((c/ω)² + K), K = I (M + m)/(m M), computed in [`rigid`] as
//!   ω K/(c + √(c² + ω² K)) so that ω = 0 gives b* = 0 (the seed's own remark after eq. 4).
//! - The small-ω expansion after eq. 6, b ≈ (r + 1) ω_i k²/v_i (r = M/m), misses a factor ½: expanding the
//!   root gives b ≈ (r + 1) ω k²/(2 c).
//! - Eqs. 7 and 8 (the slice equations of motion) are garbled: "y_{i+}", "y_{i+1} − y_i − 1", and
//!   "(y_i + y_{i−1} + Φ_{i−1})" where differences are meant, with a broken bracket structure. We do not
//!   transcribe them; K comes from the energy above and is verified against Nathan's matrix.
//! - Eqs. 11, 12 and 18 project with Σ A_i y_mi y_ni Δz = Ā δ_mn, which leaves out the rotary-inertia
//!   terms (J_i φ_mi φ_ni) of the Timoshenko mass matrix; the modes are orthogonal only with them, so we use
//!   the full M-orthonormality (unit modal mass).
//! - Eq. 17 reads "y_i t = Σ a_n(t) y_ni" for y_i(t). Eqs. 19–20 disagree in sign: with
//!   u = R − (y_ball − y_k) the ball sits on the +y side, so the force on it is +F, not −F (eq. 19 as printed
//!   would pull the ball into the bat).
//! - Eq. 21 reads "ȧ_n² τ" for ȧ_n(τ)²; eq. 23's g(ω_n) reads "|∫ (t) e_{iω_n t dt}|²" for
//!   |∫ 𝓕(t) e^{iω_n t} dt|².
//! - "Calculation by Energy Conservation" (§6.4) lists the energy lost in the ball as compression plus
//!   expansion work: it is the hysteresis loop area ∮F du = (1 − e0²) of the loading work.
//! - Figure 6 uses v_ball = 8 m/s, v_bat = 4 m/s (the bat speed at the impact point in eq. 27), not a
//!   realistic swing; [`rigid::SEED_FIG6_BALL_SPEED`] and [`rigid::SEED_FIG6_BAT_SPEED`] reproduce it.

// `!(x > 0.0)` is how the validators reject NaN along with the out-of-range values; index loops mirror
// the matrix notation of the derivation.
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

pub mod ball;
pub mod bat;
pub mod batter;
pub mod collision;
pub mod error;
pub mod hoop;
mod lanes;
pub mod metrics;
pub mod modes;
pub mod oblique;
pub mod oblique3d;
pub mod rigid;
pub mod units;

pub use ball::Ball;
pub use bat::{Bat, CoreFill, MassProperties, Material, Slice, Station};
pub use collision::{
    collide, collide_observed, collide_with_hoop, collide_with_patch, hoop_under_ball, CollisionOptions,
    CollisionResult, ContactObserver, EnergyBudget, Impact, ModeEnergy,
};
pub use error::PhysicsError;
pub use hoop::{HoopMode, PatchLaw};
pub use metrics::{BbcorReport, BesrReport, SweepPoint, SweetSpotSet};
pub use modes::{BeamMatrices, EigenSolver, LinkRule, Mode, ModeSet};
pub use oblique::{collide_oblique, ObliqueImpact, ObliqueResult, TangentialContact};
pub use oblique3d::{collide_spatial, BatterSide, SpatialImpact, SpatialResult};
pub use rigid::RigidBat;
