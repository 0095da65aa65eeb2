//! The hoop (ovalling, n = 2) compliance of a hollow barrel at the impact point: the trampoline effect.
//!
//! A hollow barrel's wall flexes radially under the ball in its lowest shell mode, two waves around the
//! circumference (n = 2, "hoop mode", measured between about 1,000 and 2,500 Hz on hollow softball and
//! baseball bats: D. A. Russell, "Hoop frequency as a predictor of performance for softball bats", and
//! "Acoustics of baseball bats", Acoustics Today 2017). The wall stores part of the collision energy
//! elastically and gives it back, so less of it is lost in the ball's hysteresis.
//!
//! # The n = 2 response of a thin cylinder to a point force (semi-membrane theory)
//! Wall thickness h = r_o − r_i, mid-surface radius a = (r_o + r_i)/2, shell modulus E, density ρ,
//! Poisson's ratio ν = E/(2G) − 1 from the shell's own E and G, plate stiffness D = E h³/(12(1 − ν²)).
//! For a circumferential wave number n and an axial scale long compared with a/n, the wall deforms without
//! stretching its circumference (ε_θ = 0, w = −∂v/∂θ) and without in-plane shear (γ_zθ = 0), so with the
//! radial displacement w = W(z) cos nθ the tangential one is v = −(W/n) sin nθ and the axial one
//! u = −(a/n²) W′ cos nθ (Vlasov's semi-membrane theory; the same equation is the long-wave, low-n limit of
//! the Donnell–Mushtari equation with Morley's (n² − 1)² correction). Per unit length of barrel the energies
//! of the n-th harmonic are
//!
//!   ring bending  ½ k_f W²,  k_f = π D (n² − 1)²/a³,
//!   axial stretch ½ B W″²,   B = π E h a³/n⁴,
//!   kinetic       ½ μ Ẇ²,    μ = π a ρ h (n² + 1)/n²  (radial plus tangential motion),
//!
//! and a radial point force F at θ = 0 drives the harmonic with the whole of F. The wall's n = 2 amplitude
//! is therefore a beam of bending stiffness B on an elastic foundation k_f:
//!
//!   μ Ẅ + B W'''' + k_f W = F δ(z − z_k).
//!
//! For a uniform mode (W″ = 0) this is the thin-ring formula of a long cylinder,
//! ω_ring² = k_f/μ = E h² n² (n² − 1)² / (12 ρ (1 − ν²) a⁴ (n² + 1)), the lowest (cut-on) frequency of the
//! n = 2 family.
//!
//! # Which length of barrel takes part, and the one-degree-of-freedom model
//! A point force is answered locally: the static solution of the beam on its foundation is
//! W(z) = W₀ e^{−β|ζ|}(cos βζ + sin βζ), ζ = z − z_k, with
//!
//!   β⁴ = k_f/(4B) = 3 h²/((1 − ν²) a⁶),   1/β = a √(a/h) ((1 − ν²)/3)^{1/4},
//!
//! and W₀ = F β/(2 k_f). The wall length that takes part is of order the decay length 1/β, a √(a/h) — far
//! longer than the axisymmetric (n = 0) bending boundary layer √(a h)/(3(1 − ν²))^{1/4}, because an n = 2
//! deformation that varies along z must stretch the wall axially (u ∝ W′), a much softer constraint than
//! stretching the circumference. For a 2⅝-in alloy barrel with a 2.4-mm wall, 1/β ≈ 87 mm.
//!
//! The contact then sees one degree of freedom: k_h = F/W₀ = 2 k_f/β (the exact static point stiffness) and
//! m_h = ∫ μ W² dz / W₀² = 3μ/(2β) (the static deflection shape as the Rayleigh–Ritz mode). This pair
//! reproduces the first two terms of the wall's point receptance at low frequency exactly,
//! H(ω) = 1/k_h + ω² m_h/k_h² + O(ω⁴), which is what a contact of ~0.5–1 ms, whose force spectrum lies
//! mostly below the hoop frequency, probes. Its frequency is f_h = √(k_h/m_h)/2π = √(4/3) f_ring, 15 %
//! above the ring's cut-on frequency, as a locally loaded shell's response lies above the cut-on. The
//! effective lengths are 2/β (stiffness, k_h = k_f·2/β) and 3/(2β) (mass). The n ≥ 3 harmonics add a little
//! more static compliance (their ring compliances fall as 1/(n² − 1)²: n = 3 adds 1/8 of n = 2's for a
//! ring); they are left out, as the hoop mode is the lowest one.
//!
//! # Where it holds
//! - Thin walls: the semi-membrane assumption needs the axial scale long compared with a/n, i.e. β a ≪ n;
//!   β a = (3/(1 − ν²))^{1/4} √(h/a), which is below 0.45 for h/a ≤ 0.1. Thicker walls (h/a ≳ 0.1) are
//!   still given a hoop mode by the same formulas — its stiffness grows as h^{5/2}, so its compliance
//!   vanishes continuously as the wall thickens — but the number is then only an estimate (thin-shell theory
//!   overstates the compliance of a thick ring). For the alloy handle (h/a ≈ 0.28) the hoop compliance is
//!   ~1 % of the ball's, so the error there does not matter.
//! - A solid section (no bore) has no hoop compliance: the local deformation of a solid body under the
//!   ball belongs to the ball's measured contact law, not to a shell mode.
//! - A filled section (a bore with a [`CoreFill`], e.g. `r161-corked`'s cork) is declared rigid (no hoop
//!   mode). Russell (Acoustics Today 2017, "Do corked wood bats have a trampoline effect?") measured the
//!   (n = 2) hoop mode of a corked wood bat above 5,500 Hz, "so high that it provides absolutely no
//!   improvement in performance over a solid bat", and Nathan et al. (2011) measured a corked bat's BBCOR
//!   *below* the solid bat's. A soft core under a thin metal wall (foam-filled barrels) would instead add a
//!   foundation stiffness to k_f; no preset has one, and it is not modelled.
//! - The shell must be isotropic for E, G and ν to describe its hoop bending: we require
//!   0 ≤ ν = E/(2G) − 1 < ½. Wood is strongly anisotropic (its hoop direction runs across the grain, where
//!   the modulus is ~1/20 of the axial Y used by the beam); its E/(2G) − 1 is far above ½ (7.6 for the
//!   R161), so a wooden section gets no hoop mode, consistent with the corked-bat measurement above.
//! - The barrel is taken as locally uniform and long: the section at the impact point is used, so the
//!   taper must change the radius little over 1/β (|da/dz|/β ≪ a), and an end cap or the barrel's end
//!   within ~1/β of the impact stiffens (cap) or softens (free end) the wall in reality; neither is modelled.
//! - The bore is what the model adds: a section whose bore closes (r_i → 0) tends to a solid one, which the
//!   model treats as rigid (its local deformation under the ball belongs to the ball's measured contact
//!   law). The thin-shell formulas, taken to a solid section (h = r_o, a = r_o/2), still give a finite
//!   stiffness k_h(r_o, 0), so the wall is given only the compliance it has beyond that of a solid section of
//!   the same outer radius by the same formulas: 1/k_h(r_o, r_i) − 1/k_h(r_o, 0) = χ/k_h with the bore share
//!   χ = 1 − k_h(r_o, r_i)/k_h(r_o, 0). With k_h ∝ h^{5/2} a^{−3/2}, χ ≈ 4 r_i/r_o as the bore closes, so the
//!   results tend continuously to the solid bat's; for a real alloy barrel (h/r_o ≈ 0.07) χ = 0.9995.
//!
//! # The ball's contact patch
//! The ball does not load the wall at a point: at BBCOR speeds its contact patch wraps tens of degrees of
//! a 33-mm barrel. A load spread over the patch drives the n = 2 mode with the patch's average of the mode
//! shape, and the wall deflection the ball feels is the same average of the mode's deflection (force and
//! displacement stay power-conjugate), so with that share ψ the ball sees the mode as stiffness k_h/ψ² and
//! mass m_h/ψ² (same frequency). The patch is taken as the ball's surface flattened against the undeformed
//! barrel at a compression u_p, pressure uniform over it:
//!
//! - around the barrel, half-angle θ_p where the undeformed ball (radius R, centre at R + r_o − u_p from the
//!   bat's axis) crosses the barrel's circle: cos θ_p = (r_o² + d² − R²)/(2 r_o d), d = R + r_o − u_p; the
//!   n = 2 share of a load spread evenly over ±θ_p is S = sin 2θ_p/(2θ_p);
//! - along the barrel, half-length L_p = √(2R u_p − u_p²); the average of the static deflection shape
//!   e^{−βζ}(cos βζ + sin βζ) over |ζ| ≤ L_p is A = (1 − e^{−x} cos x)/x with x = β L_p;
//! - ψ = S·A·√χ (the bore share above enters the same way: the ball sees k_h/(S²A²χ)).
//!
//! The patch grows and shrinks with the ball's compression u: the collision couples the ball to the mode
//! through ψ(u) ([`PatchLaw`], the patch above at compression u), 1 (times √χ) at first touch and smallest at
//! the peak compression, where the force and the energy the wall stores are largest. The wall deflection the
//! ball feels is ψ(u)·W, so the compression itself solves u = δ + ψ(u)·W (δ the approach of the ball to the
//! undeformed wall), and the forces are the exact gradients of the ball's potential: the beam and the ball
//! feel F·g, the mode F·g·ψ, g = 1/(1 − ψ′(u)·W) (see [`crate::collision`]); ψ′·W is of order 1e-2.
//! Before, the patch was fixed for the whole contact at its largest extent (the rigid-wall peak,
//! [`reference_compression`], still used by [`HoopMode::under_patch`] and
//! [`crate::collision::hoop_under_ball`]): the ball then met, from its first touch, a wall of mass
//! m_h/ψ² ≈ 0.25–0.3 kg — about twice its own — which rang with most of what it stored whenever the hoop
//! period approached the contact (a 1.5-mm wall at 1.09 kHz, the `aluminum` bat's beam: 82 J kept of 122 J
//! stored, exit speed 4.3 m/s below a rigid wall; with the following patch 55 J of 146 J, 2.9 m/s above it),
//! and BBCOR fell as the hoop frequency fell from 2.0 to 1.6 kHz, against the measured trend (see
//! `tests/physics_trampoline.rs`). Treating S and A as separable (a rectangle in θ and z, rather than the
//! patch's rounded outline) and the pressure as uniform (it is higher at the centre, which raises ψ a
//! little) are the remaining approximations of the patch; a point load (ψ = √χ) is the upper bound of the
//! coupling.
//!
//! What the model still leaves out near 1.3–1.6 kHz: with the bat's beam held fixed, a single undamped n = 2
//! mode whose period nears the contact still keeps up to ~60 % of what it stored at the usual impact point
//! (1.8 mm, 1.32 kHz: 68 J of 117 J), so a swing there loses ~0.7 m/s against a rigid wall while thinner and
//! thicker walls gain; the protocol's BBCOR, the best of 13 impact points, still rises monotonically through
//! the band. The other shell harmonics and axial orders, the end cap and the taper within a decay length, and
//! the wall's damping (η ~ 1e-3, negligible) are not modelled. Built as real bats of one weight class are
//! ([`Bat::alloy_weight_matched`]: `aluminum`'s mass and swing weight, the thinner barrel made up by the
//! handle wall and an end-cap plug), whole bats swung at equal effort show no such dip: 6 in from the end the
//! wall adds 1.4 mph over a rigid bat of the same mass properties at 1.62 kHz and 14.4 mph at 1.03 kHz, the
//! exit speed flat within 0.3 % from 1.8 to 1.6 kHz and rising at every step below, down to about 1 kHz.
//! The swing losses once seen with thinner walls came from the lighter bat (see docs/physics.md, hollow bats).
//!
//! No constant in this module is tuned: k_h, m_h and f_h follow from a, h, E, G and ρ, ψ(u) from the ball's
//! radius and the barrel's geometry.

use super::lanes::{Lane4, Lanes, Portable};
use super::{Ball, Bat, CoreFill, Material, PhysicsError, Station};

/// Circumferential wave number of the hoop (ovalling) mode.
const WAVE_NUMBER: f64 = 2.0;

/// The wall's hoop (n = 2) mode at one impact point, seen by the ball as one mass on one spring, SI units.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HoopMode {
    /// Hoop stiffness k_h: radial point force per wall deflection at the impact point, N/m.
    pub stiffness: f64,
    /// Effective mass m_h of the mode at the impact point, kg.
    pub effective_mass: f64,
    /// Axial decay length 1/β of the wall's n = 2 response to a point force, m.
    pub decay_length: f64,
    /// Mid-surface radius a of the wall, m.
    pub radius: f64,
    /// Wall thickness h, m.
    pub wall_thickness: f64,
    /// Share ψ of the ball's force that drives the mode, and of the mode's deflection the ball feels
    /// (dimensionless, in (0, 1]): the bore share √χ for a point load ([`HoopMode::of_section`]), times the
    /// contact patch's share once the ball is known ([`HoopMode::under_patch`]). The ball sees the mode as
    /// stiffness k_h/ψ² and mass m_h/ψ².
    pub coupling: f64,
}

impl HoopMode {
    /// The n = 2 hoop mode of a thin isotropic cylindrical wall (see the module docs), or `None` when the
    /// section has no hoop compliance: solid (`inner_radius` = 0), filled (`filled`), or a shell material
    /// that is not isotropic (ν = E/(2G) − 1 outside [0, ½)). Radii in m.
    pub fn of_section(outer_radius: f64, inner_radius: f64, shell: &Material, filled: bool) -> Option<HoopMode> {
        let nu = poisson_ratio(shell);
        let hollow = inner_radius > 0.0 && inner_radius < outer_radius;
        if filled || !hollow || !(0.0..0.5).contains(&nu) {
            return None;
        }
        let (stiffness, effective_mass, decay_length) = thin_shell(outer_radius, inner_radius, shell, nu);
        let (solid_stiffness, _, _) = thin_shell(outer_radius, 0.0, shell, nu);
        let bore_share = 1.0 - stiffness / solid_stiffness;
        let mode = HoopMode {
            stiffness,
            effective_mass,
            decay_length,
            radius: 0.5 * (outer_radius + inner_radius),
            wall_thickness: outer_radius - inner_radius,
            coupling: bore_share.max(0.0).sqrt(),
        };
        (mode.stiffness.is_finite() && mode.stiffness > 0.0 && mode.effective_mass > 0.0 && mode.coupling > 0.0)
            .then_some(mode)
    }

    /// Outer radius of the wall, m.
    pub fn outer_radius(&self) -> f64 {
        self.radius + 0.5 * self.wall_thickness
    }

    /// This mode as a ball of radius `ball_radius` (m) loads it through its contact patch at compression
    /// `compression` (m): the coupling multiplied by the patch's share S·A (see the module docs).
    pub fn under_patch(&self, ball_radius: f64, compression: f64) -> HoopMode {
        let patch = ContactPatch::new(ball_radius, self.outer_radius(), compression);
        HoopMode { coupling: self.coupling * patch.share(self.decay_length), ..*self }
    }

    /// Stiffness the ball sees, k_h/ψ², N/m.
    pub fn stiffness_seen(&self) -> f64 {
        self.stiffness / (self.coupling * self.coupling)
    }

    /// Angular frequency ω_h = √(k_h/m_h), rad/s.
    pub fn angular_frequency(&self) -> f64 {
        (self.stiffness / self.effective_mass).sqrt()
    }

    /// Hoop frequency f_h = ω_h/2π, Hz.
    pub fn frequency_hz(&self) -> f64 {
        self.angular_frequency() / std::f64::consts::TAU
    }

    /// Checks that stiffness and effective mass are finite and positive (the error names the field).
    pub fn validate(&self) -> Result<(), PhysicsError> {
        if !(self.stiffness.is_finite() && self.stiffness > 0.0) {
            return Err(PhysicsError::out_of_range("hoop.stiffness", self.stiffness, "0 < stiffness < ∞ N/m"));
        }
        if !(self.effective_mass.is_finite() && self.effective_mass > 0.0) {
            return Err(PhysicsError::out_of_range(
                "hoop.effective_mass",
                self.effective_mass,
                "0 < effective_mass < ∞ kg",
            ));
        }
        if !(self.coupling.is_finite() && self.coupling > 0.0 && self.coupling <= 1.0) {
            return Err(PhysicsError::out_of_range("hoop.coupling", self.coupling, "0 < coupling ≤ 1"));
        }
        Ok(())
    }
}

/// Point stiffness k_h (N/m), effective mass m_h (kg) and decay length 1/β (m) of the n = 2 mode of a wall
/// between `inner_radius` and `outer_radius` (m) by the semi-membrane formulas of the module docs, for any
/// wall (also a solid one, where the formulas are only a reference for the bore share).
fn thin_shell(outer_radius: f64, inner_radius: f64, shell: &Material, nu: f64) -> (f64, f64, f64) {
    let n2 = WAVE_NUMBER * WAVE_NUMBER;
    let h = outer_radius - inner_radius;
    let a = 0.5 * (outer_radius + inner_radius);
    let e = shell.youngs_modulus;
    let d = e * h * h * h / (12.0 * (1.0 - nu * nu));
    let pi = std::f64::consts::PI;
    let foundation = pi * d * (n2 - 1.0) * (n2 - 1.0) / (a * a * a);
    let axial = pi * e * h * a * a * a / (n2 * n2);
    let line_mass = pi * a * shell.density * h * (n2 + 1.0) / n2;
    let beta = (foundation / (4.0 * axial)).sqrt().sqrt();
    (2.0 * foundation / beta, 1.5 * line_mass / beta, 1.0 / beta)
}

/// The ball's contact patch on a barrel: the ball's surface flattened against the undeformed barrel, SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPatch {
    /// Half-angle θ_p of the patch around the barrel's axis, rad.
    pub half_angle: f64,
    /// Half-length L_p of the patch along the barrel, m.
    pub half_length: f64,
}

impl ContactPatch {
    /// The patch of a ball of radius `ball_radius` compressed by `compression` against a barrel of outer
    /// radius `barrel_radius` (m): where the undeformed ball crosses the barrel's surface.
    pub fn new(ball_radius: f64, barrel_radius: f64, compression: f64) -> ContactPatch {
        let (r, b) = (ball_radius, barrel_radius);
        let u = compression.clamp(0.0, r);
        let d = r + b - u;
        let cos = ((b * b + d * d - r * r) / (2.0 * b * d)).clamp(-1.0, 1.0);
        ContactPatch { half_angle: cos.acos(), half_length: (2.0 * r * u - u * u).max(0.0).sqrt() }
    }

    /// Share S of the n = 2 mode in a load spread evenly over ±θ_p: sin 2θ_p/(2θ_p) (1 for a point).
    pub fn circumferential_share(&self) -> f64 {
        let x = 2.0 * self.half_angle;
        if x < 1e-6 {
            1.0 - x * x / 6.0
        } else {
            x.sin() / x
        }
    }

    /// Average A of the static deflection shape e^{−βζ}(cos βζ + sin βζ) over |ζ| ≤ L_p, for the decay
    /// length `decay_length` = 1/β (m): (1 − e^{−x} cos x)/x with x = β L_p (1 for a point).
    pub fn axial_share(&self, decay_length: f64) -> f64 {
        let x = self.half_length / decay_length;
        if x < 1e-6 {
            1.0 - x * x / 3.0
        } else {
            (1.0 - (-x).exp() * x.cos()) / x
        }
    }

    /// The patch's share S·A of the n = 2 mode for the decay length `decay_length` (m).
    pub fn share(&self, decay_length: f64) -> f64 {
        self.circumferential_share() * self.axial_share(decay_length)
    }
}

/// Degree of the polynomial that carries the patch's coupling ψ(u) through a collision ([`PatchLaw`]).
pub const PATCH_DEGREE: usize = 12;

/// The coupling ψ(u) of the wall's hoop mode to a ball whose contact patch follows the ball's compression u:
/// the mode's point-load coupling (the bore share √χ) times the share S·A of the patch the ball makes at u
/// ([`ContactPatch`]), carried as its Chebyshev interpolant of degree [`PATCH_DEGREE`] on [0, U] (written
/// out in powers of t = 2u/U − 1), so that ψ and its slope ψ′ cost one short polynomial per evaluation. The
/// polynomial *is* the coupling the collision uses, and its slope is its exact derivative, so the collision
/// stays conservative (see [`crate::collision`]); it differs from the patch formulas by less than
/// 1e-4 on [0, U] (tested).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PatchLaw {
    /// Coefficients of t⁰ … t^PATCH_DEGREE, each with the coefficients of the same power in the derivatives
    /// dψ/dt and d²ψ/dt² (zeros past their degrees) and a zero lane, so that one four-lane multiply–add
    /// advances the three polynomials ([`estrin_lanes`]).
    lanes: [Lanes; PATCH_DEGREE + 1],
    /// 2/U, 1/m.
    scale: f64,
    /// Upper end U of the interpolated range of compressions, m.
    pub range: f64,
}

impl PatchLaw {
    /// A coupling that does not depend on the compression: ψ(u) = `coupling` (dimensionless).
    pub fn constant(coupling: f64) -> PatchLaw {
        let mut lanes = [[0.0; 4]; PATCH_DEGREE + 1];
        lanes[0][0] = coupling;
        PatchLaw { lanes, scale: 0.0, range: f64::INFINITY }
    }

    /// The coupling of `mode` (its point-load coupling, [`HoopMode::of_section`]) to a ball of radius
    /// `ball_radius` whose patch follows its compression u, for u in [0, `range`] (m).
    pub fn following(mode: &HoopMode, ball_radius: f64, range: f64) -> PatchLaw {
        let n = PATCH_DEGREE + 1;
        let share = |t: f64| {
            let u = 0.5 * range * (t + 1.0);
            mode.coupling * ContactPatch::new(ball_radius, mode.outer_radius(), u).share(mode.decay_length)
        };
        let cosines = chebyshev_cosines();
        // Chebyshev coefficients from the values at the Chebyshev nodes.
        let values: [f64; PATCH_DEGREE + 1] = std::array::from_fn(|j| share(cosines[1][j]));
        let mut coeffs = [0.0; PATCH_DEGREE + 1];
        // T_k as powers of t, built by T_{k+1} = 2t T_k − T_{k−1}.
        let (mut previous, mut current) = ([0.0; PATCH_DEGREE + 1], [0.0; PATCH_DEGREE + 1]);
        previous[0] = 1.0;
        current[1] = 1.0;
        for k in 0..n {
            let c: f64 =
                (0..n).map(|j| values[j] * cosines[k][j]).sum::<f64>() * if k == 0 { 1.0 } else { 2.0 } / n as f64;
            let t_k = if k == 0 { previous } else { current };
            for (a, b) in coeffs.iter_mut().zip(t_k) {
                *a += c * b;
            }
            if k >= 1 {
                let mut next = [0.0; PATCH_DEGREE + 1];
                for i in 0..PATCH_DEGREE {
                    next[i + 1] = 2.0 * current[i];
                }
                for (a, b) in next.iter_mut().zip(previous) {
                    *a -= b;
                }
                (previous, current) = (current, next);
            }
        }
        let mut slopes = [0.0; PATCH_DEGREE + 1];
        for k in 0..PATCH_DEGREE {
            slopes[k] = (k + 1) as f64 * coeffs[k + 1];
        }
        let mut curvatures = [0.0; PATCH_DEGREE + 1];
        for k in 0..PATCH_DEGREE - 1 {
            curvatures[k] = (k + 1) as f64 * slopes[k + 1];
        }
        let lanes = std::array::from_fn(|k| [coeffs[k], slopes[k], curvatures[k], 0.0]);
        PatchLaw { lanes, scale: 2.0 / range, range }
    }

    /// ψ(u) and its slope dψ/du (1/m) at compression `u` (m).
    #[inline(always)]
    pub fn value_and_slope(&self, u: f64) -> (f64, f64) {
        let (value, slope, _) = self.value_slope_and_curvature(u);
        (value, slope)
    }

    /// ψ(u), dψ/du (1/m) and d²ψ/du² (1/m²) at compression `u` (m): the collision expands ψ about a
    /// predicted compression, off its critical path (see [`crate::collision`]).
    #[inline(always)]
    pub fn value_slope_and_curvature(&self, u: f64) -> (f64, f64, f64) {
        self.value_slope_and_curvature_in::<Portable>(u)
    }

    /// [`PatchLaw::value_slope_and_curvature`] on the lane arithmetic `V` (the same bits on either).
    #[inline(always)]
    pub(crate) fn value_slope_and_curvature_in<V: Lane4>(&self, u: f64) -> (f64, f64, f64) {
        let t = u * self.scale - 1.0;
        // Estrin's scheme: four levels of multiply–add instead of a chain of twelve.
        let mut lanes = [0.0; 4];
        estrin_lanes::<V>(&self.lanes, t).store(&mut lanes);
        let [value, slope, curvature, _] = lanes;
        (value, slope * self.scale, curvature * (self.scale * self.scale))
    }
}

/// cos(π k (j + ½)/n) for k, j < n = PATCH_DEGREE + 1: the Chebyshev nodes (k = 1) and the weights of the
/// coefficients' sums. They depend on n only, so they are computed once per process — by the very
/// expression and `cos` the interpolation used to call per collision, so the coefficients keep their bits
/// (the inputs pass through `black_box` so that the compiler cannot fold the `cos` calls with its own
/// arithmetic) — rather than 182 `cos` calls per collision, ~5 % of a hollow-barrel collision.
fn chebyshev_cosines() -> &'static [[f64; PATCH_DEGREE + 1]; PATCH_DEGREE + 1] {
    static TABLE: std::sync::OnceLock<[[f64; PATCH_DEGREE + 1]; PATCH_DEGREE + 1]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let n = std::hint::black_box(PATCH_DEGREE + 1);
        let pi = std::hint::black_box(std::f64::consts::PI);
        let mut table = [[0.0; PATCH_DEGREE + 1]; PATCH_DEGREE + 1];
        for (k, row) in table.iter_mut().enumerate() {
            for (j, slot) in row.iter_mut().enumerate() {
                // Row 1 is the nodes cos(π (j + ½)/n): π·1 is π exactly.
                *slot = (pi * k as f64 * (j as f64 + 0.5) / n as f64).cos();
            }
        }
        table
    })
}

/// Σ c_k t^k for four polynomials at once, lane by lane, from their PATCH_DEGREE + 1 = 13 coefficient
/// lanes `c`, by Estrin's scheme. Each lane takes exactly the operations of the one-polynomial scheme (plain
/// IEEE multiplies and adds, no fused multiply–add), so the grouping changes no bit; on AVX one register
/// carries the four.
#[inline(always)]
fn estrin_lanes<V: Lane4>(c: &[Lanes; PATCH_DEGREE + 1], t: f64) -> V {
    let t2 = t * t;
    let t4 = t2 * t2;
    let t8 = t4 * t4;
    let mul_add = |a: V, b: V, x: f64| a.add(b.mul(V::splat(x)));
    let l = |k: usize| V::load(&c[k]);
    let p = [
        mul_add(l(0), l(1), t),
        mul_add(l(2), l(3), t),
        mul_add(l(4), l(5), t),
        mul_add(l(6), l(7), t),
        mul_add(l(8), l(9), t),
        mul_add(l(10), l(11), t),
    ];
    let q = [mul_add(p[0], p[1], t2), mul_add(p[2], p[3], t2), mul_add(p[4], p[5], t2), l(12)];
    let r = [mul_add(q[0], q[1], t4), mul_add(q[2], q[3], t4)];
    mul_add(r[0], r[1], t8)
}

/// Peak compression of a ball against a wall that does not give, m: ½ μ v² = k₁ u^{α+1}/(α+1) for the
/// ball `ball`, the normal approach speed `approach_speed` (m/s) and the bat's effective mass at the impact
/// point `bat_effective_mass` (kg; infinite for a fixed wall), μ their reduced mass.
pub fn reference_compression(ball: &Ball, approach_speed: f64, bat_effective_mass: f64) -> f64 {
    let mu = if bat_effective_mass.is_finite() {
        ball.mass * bat_effective_mass / (ball.mass + bat_effective_mass)
    } else {
        ball.mass
    };
    let a1 = ball.exponent + 1.0;
    (0.5 * mu * approach_speed * approach_speed * a1 / ball.stiffness).powf(1.0 / a1)
}

/// Poisson's ratio ν = E/(2G) − 1 of an isotropic material from its Young's and shear moduli.
pub fn poisson_ratio(material: &Material) -> f64 {
    material.youngs_modulus / (2.0 * material.shear_modulus) - 1.0
}

/// The n = 2 ring (cut-on) frequency of a long thin cylinder, Hz:
/// ω² = E h² n² (n² − 1)² / (12 ρ (1 − ν²) a⁴ (n² + 1)) with n = 2, mid-surface radius `radius` and
/// wall thickness `wall_thickness` in m.
pub fn ring_frequency_hz(material: &Material, radius: f64, wall_thickness: f64) -> f64 {
    let nu = poisson_ratio(material);
    let n2 = WAVE_NUMBER * WAVE_NUMBER;
    let w2 = material.youngs_modulus * wall_thickness * wall_thickness * n2 * (n2 - 1.0) * (n2 - 1.0)
        / (12.0 * material.density * (1.0 - nu * nu) * radius.powi(4) * (n2 + 1.0));
    w2.sqrt() / std::f64::consts::TAU
}

/// What a bat's wall needs for its hoop mode anywhere along it: the profile, shell and core fill.
#[derive(Debug, Clone, PartialEq)]
pub struct HoopProfile {
    stations: Vec<Station>,
    shell: Material,
    core: Option<CoreFill>,
    /// Whether any station is hollow and the shell isotropic (else no section has a hoop mode).
    any: bool,
}

impl HoopProfile {
    /// The hoop profile of `bat`.
    pub fn of(bat: &Bat) -> HoopProfile {
        let nu = poisson_ratio(&bat.shell);
        let any = (0.0..0.5).contains(&nu) && bat.stations.iter().any(|s| s.inner_radius > 0.0);
        HoopProfile { stations: bat.stations.clone(), shell: bat.shell, core: bat.core, any }
    }

    /// The hoop mode at `z` (m from the knob), from the section there (radii linear between stations, as
    /// in [`Bat::radii_at`]); `None` for a solid, filled or non-isotropic section, or a z off the bat.
    pub fn at(&self, z: f64) -> Option<HoopMode> {
        let length = self.stations.last().map_or(0.0, |s| s.z);
        if !(self.any && z >= 0.0 && z <= length) {
            return None;
        }
        let (outer, inner) = radii_at(&self.stations, z);
        let filled = self.core.is_some_and(|c| inner > 0.0 && z >= c.z_start && z <= c.z_end);
        HoopMode::of_section(outer, inner, &self.shell, filled)
    }
}

/// Outer and inner radius at `z` within the stations' range (linear between stations), m.
fn radii_at(stations: &[Station], z: f64) -> (f64, f64) {
    let k = stations.partition_point(|s| s.z <= z);
    if k == 0 {
        return (stations[0].outer_radius, stations[0].inner_radius);
    }
    if k >= stations.len() {
        let last = stations[stations.len() - 1];
        return (last.outer_radius, last.inner_radius);
    }
    let (a, b) = (stations[k - 1], stations[k]);
    let t = (z - a.z) / (b.z - a.z);
    (a.outer_radius + t * (b.outer_radius - a.outer_radius), a.inner_radius + t * (b.inner_radius - a.inner_radius))
}

impl Bat {
    /// The wall's hoop mode at `z` (m from the knob); `None` where the section has no hoop compliance
    /// (see [`crate::hoop`]).
    pub fn hoop_at(&self, z: f64) -> Option<HoopMode> {
        HoopProfile::of(self).at(z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wood_and_cork_filled_sections_have_no_hoop_mode() {
        for name in ["r161", "torpedo", "r161-corked"] {
            let bat = Bat::preset(name).expect("preset");
            let profile = HoopProfile::of(&bat);
            for i in 0..=100 {
                let z = bat.length() * i as f64 / 100.0;
                assert_eq!(profile.at(z), None, "{name} at z = {z}");
            }
        }
        // An isotropic shell filled with a core is declared rigid too.
        let filled = HoopMode::of_section(0.033, 0.030, &Material::ALUMINUM, true);
        assert_eq!(filled, None);
        assert_eq!(HoopMode::of_section(0.033, 0.0, &Material::ALUMINUM, false), None);
    }

    #[test]
    fn the_alloy_barrel_rings_in_the_measured_hoop_band() {
        let bat = Bat::preset("aluminum").expect("preset");
        for z in [0.55, 0.62, 0.68, 0.74] {
            let hoop = bat.hoop_at(z).expect("hollow barrel");
            let f = hoop.frequency_hz();
            assert!((1000.0..2500.0).contains(&f), "z = {z}: {f} Hz");
            // The wall length taking part, 1/β = a √(a/h) ((1 − ν²)/3)^{1/4}, is a few radii for h/a ≈ 0.07.
            assert!(hoop.decay_length > 2.0 * hoop.radius && hoop.decay_length < 4.0 * hoop.radius);
        }
    }

    /// The patch's extent by brute force: points of the barrel's surface inside the undeformed ball.
    fn patch_by_sampling(ball_radius: f64, barrel_radius: f64, compression: f64) -> (f64, f64) {
        let d = ball_radius + barrel_radius - compression;
        let inside = |theta: f64, z: f64| {
            let (y, x) = (barrel_radius * theta.cos(), barrel_radius * theta.sin());
            x * x + (y - d) * (y - d) + z * z < ball_radius * ball_radius
        };
        let n = 200_000;
        let angle = (0..n).map(|i| std::f64::consts::PI * i as f64 / n as f64).take_while(|&t| inside(t, 0.0)).last();
        let length = (0..n).map(|i| ball_radius * i as f64 / n as f64).take_while(|&z| inside(0.0, z)).last();
        (angle.unwrap_or(0.0), length.unwrap_or(0.0))
    }

    #[test]
    fn the_contact_patch_is_where_the_ball_crosses_the_barrel() {
        for (r, b, u) in [(0.0366, 0.0333, 0.005), (0.0366, 0.0333, 0.017), (0.0366, 0.02, 0.01), (0.05, 0.04, 0.002)] {
            let patch = ContactPatch::new(r, b, u);
            let (angle, length) = patch_by_sampling(r, b, u);
            assert!((patch.half_angle - angle).abs() < 2e-5, "{r} {b} {u}: θ {} vs {angle}", patch.half_angle);
            assert!((patch.half_length - length).abs() < 1e-6, "{r} {b} {u}: L {} vs {length}", patch.half_length);
        }
        // On a flat wall (barrel radius → ∞) the patch is a circle: arc half-width = half-length.
        let flat = ContactPatch::new(0.0366, 1.0e4, 0.01);
        assert!((flat.half_angle * 1.0e4 - flat.half_length).abs() < 1e-4 * flat.half_length);
    }

    /// Trapezoidal average of `f` over [0, x].
    fn average(f: impl Fn(f64) -> f64, x: f64) -> f64 {
        let n = 100_000;
        let h = x / n as f64;
        let sum: f64 = (0..=n).map(|i| if i == 0 || i == n { 0.5 } else { 1.0 } * f(i as f64 * h)).sum();
        sum * h / x
    }

    #[test]
    fn the_patch_shares_are_averages_of_the_mode_shape() {
        for (r, b, u) in [(0.0366, 0.0333, 0.003), (0.0366, 0.0333, 0.017), (0.0366, 0.025, 0.03)] {
            let patch = ContactPatch::new(r, b, u);
            let around = average(|t| (2.0 * t).cos(), patch.half_angle);
            assert!((patch.circumferential_share() - around).abs() < 1e-9, "S at u = {u}");
            let decay = 0.087;
            let along = average(|z| (-z / decay).exp() * ((z / decay).cos() + (z / decay).sin()), patch.half_length);
            assert!((patch.axial_share(decay) - along).abs() < 1e-9, "A at u = {u}");
        }
        // A point (no compression) takes the whole of the mode.
        let point = ContactPatch::new(0.0366, 0.0333, 0.0);
        assert_eq!(point.share(0.087), 1.0);
    }

    #[test]
    fn the_bore_share_closes_with_the_bore() {
        let al = Material::ALUMINUM;
        let outer = 0.0333375;
        // Thin walls: the bore carries (nearly) all of the compliance.
        let thin = HoopMode::of_section(outer, outer - 0.0024, &al, false).expect("hollow");
        assert!(thin.coupling > 0.999 && thin.coupling < 1.0, "{}", thin.coupling);
        // A closing bore: χ = ψ² → 4 r_i/r_o (k_h ∝ h^{5/2} a^{−3/2} expanded to first order in r_i/r_o).
        for ratio in [1e-3, 1e-4, 1e-5] {
            let mode = HoopMode::of_section(outer, ratio * outer, &al, false).expect("hollow");
            let chi = mode.coupling * mode.coupling;
            assert!(((chi - 4.0 * ratio) / (4.0 * ratio)).abs() < 5.0 * ratio, "r_i/r_o = {ratio}: χ = {chi}");
        }
    }

    #[test]
    fn the_reference_compression_of_a_linear_ball_is_the_oscillators_amplitude() {
        // α = 1: ½ μ v² = ½ k u², u = v √(μ/k).
        let ball = Ball { stiffness: 2.0e6, exponent: 1.0, ..Ball::default() };
        let v = 40.0;
        let fixed = reference_compression(&ball, v, f64::INFINITY);
        assert!((fixed - v * (ball.mass / ball.stiffness).sqrt()).abs() < 1e-15);
        let mu = ball.mass * 0.6 / (ball.mass + 0.6);
        let free = reference_compression(&ball, v, 0.6);
        assert!((free - v * (mu / ball.stiffness).sqrt()).abs() < 1e-15);
    }
}
