//! The ball: a nonlinear hysteretic spring (loading k1·u^α, unloading k2·u^β).
//!
//! u is the compression of the ball's radius (m). While the compression grows beyond its running maximum
//! u_m the force follows the loading curve F = k1·u^α. Below u_m it follows the unloading curve
//! F = k2·u^β, β = (1+α)/e0² − 1, with k2 = k1·u_m^(α−β) so the two curves meet at u_m (continuity);
//! the loading work k1·u_m^(1+α)/(1+α) is then returned as k2·u_m^(1+β)/(1+β) = e0² of it.
//!
//! **If the compression peaks twice** (the bat surface vibrates during contact): while u < u_m both
//! reloading and unloading follow the unloading curve k2·u^β, which is elastic (no further loss); if u
//! exceeds u_m the ball is back on the virgin loading curve, and u_m (and with it k2) grows to the new
//! maximum. The loss is thus always the area between the curves up to the largest compression reached.
//!
//! # e0 as a function of impact speed
//! A real ball is less lively the harder it is hit (a viscoelastic ball: Shenoy, Smith & Axtell, Compos.
//! Struct. 52, 397 (2001); the Sports Science Laboratory's cylindrical COR at bat speeds is lower than the
//! 60-mph wall COR). The ball carries that as a measured law, linear in the normal approach speed v of ball
//! and bat surface at first contact and clamped to the range a COR can have:
//!   e0(v) = clamp(cor + cor_slope·(v − cor_reference_speed), 0.05, 1).
//! A collision takes e0 at its own v ([`Ball::at_approach_speed`]), and β, k2 and the hysteresis loss follow
//! from that e0 exactly as above, so the loss stays (1 − e0(v)²) of the loading work and the energy budget
//! stays exact. `cor_slope = 0` (the default) is the constant-COR ball, unchanged bit for bit. Linear is the
//! simplest form that falls with speed; no published COR-against-speed table for baseballs was found to
//! support a curve (`validation/ball_cor.toml` lists what was and was not found).

use super::PhysicsError;

/// A ball, SI units. Loading force k1·u^α; unloading k2·u^β with β = (1+α)/e0² − 1, e0 taken at the
/// collision's normal approach speed (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Ball {
    /// Mass, kg.
    pub mass: f64,
    /// Radius, m.
    pub radius: f64,
    /// Loading stiffness k1, N/m^α.
    pub stiffness: f64,
    /// Loading exponent α, dimensionless.
    pub exponent: f64,
    /// Coefficient of restitution e0 against a rigid wall at the approach speed `cor_reference_speed`, in (0, 1]
    /// (at every speed when `cor_slope` is 0).
    pub cor: f64,
    /// Change of e0 per m/s of normal approach speed, s/m (0 = constant COR; negative: less lively at speed).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub cor_slope: f64,
    /// Normal approach speed at which e0 = `cor`, m/s (used only when `cor_slope` ≠ 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub cor_reference_speed: f64,
}

/// Whether `v` is 0 (serde: a constant-COR ball writes no speed-law fields, as before they existed).
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// Largest |cor_slope| accepted, s/m: e0 moving by 0.02 per m/s would span its whole range within 50 m/s.
pub const MAX_COR_SLOPE: f64 = 0.02;
/// Metres per second in one foot per second.
const FT_PER_S: f64 = 0.3048;

/// MLB's specification speed for the ball's COR, m/s: 85 ft/s (about 58 mph) against an ash slab.
pub const MLB_COR_SPEED: f64 = 85.0 * FT_PER_S;
/// Nominal e0 of the MLB ball at [`MLB_COR_SPEED`]: 0.546, the middle of the specified 0.514–0.578
/// (0.546 ± 0.032: R. S. Lakes, Viscoelastic Materials (2009), baseball example; 54.6 % rebound from a wooden
/// target, Sports Illustrated, 13 June 1977; 0.514–0.578, D. Ropeik, MSNBC 2003).
pub const MLB_COR: f64 = 0.546;
/// Slope of e0 with approach speed for the game ball, s/m: Nathan's low- and high-speed cases as quoted in
/// issue 22 (e0 = 0.66 at 1 m/s, 0.50 near 60 m/s), (0.50 − 0.66)/(60 − 1). No measured slope for baseballs
/// was found (see `validation/ball_cor.toml`); `sweetspot calibrate --fit-cor-slope` measures one from sessions
/// at several pitch speeds.
pub const GAME_BALL_COR_SLOPE: f64 = (0.50 - 0.66) / (60.0 - 1.0);

impl Default for Ball {
    /// A regulation baseball: 0.145 kg, 0.0366 m, k1 = 6.53e7 N/m^α, α = 1.84, e0 = 0.53.
    fn default() -> Self {
        Ball {
            mass: 0.145,
            radius: 0.0366,
            stiffness: 6.53e7,
            exponent: 1.84,
            cor: 0.53,
            cor_slope: 0.0,
            cor_reference_speed: 0.0,
        }
    }
}

impl Ball {
    /// Names of the built-in balls.
    pub fn preset_names() -> &'static [&'static str] {
        &["baseball", "bbcor", "mlb"]
    }

    /// A built-in ball by name: `baseball` ([`Ball::default`]), `bbcor` ([`Ball::bbcor_protocol`]) or `mlb`
    /// ([`Ball::mlb`]).
    pub fn preset(name: &str) -> Result<Ball, PhysicsError> {
        match name {
            "baseball" => Ok(Ball::default()),
            "bbcor" => Ok(Ball::bbcor_protocol()),
            "mlb" => Ok(Ball::mlb()),
            _ => {
                Err(PhysicsError::UnknownBallPreset { name: name.to_string(), known: Ball::preset_names().join(", ") })
            }
        }
    }

    /// The ball we use for the BBCOR / BESR protocols: the default baseball with e0 = 0.50.
    ///
    /// ASTM F2219 tests with certified lab balls whose rigid-wall COR (ASTM F1887, 60 mph) is specified
    /// separately from game balls; we assume a nominal 0.50 (the stiffness law is kept from the game ball,
    /// since the standard fixes no force law). This is a modelling assumption, not a value from the standard.
    ///
    /// The test only ever runs at one approach speed (136 mph against a bat at rest; BESR's 70 + 66 mph is the
    /// same 60.8 m/s), so this ball is constant-COR: 0.50 is its e0 *at 136 mph*. That value is supported by
    /// the NCAA's statement (16 Sep 2008) that the 0.50 limit sits "slightly higher than the best available
    /// wood bats": a wood bat at its best point scores e0 less a little vibration (the R161: 0.498), so the
    /// test ball's e0 at 136 mph is about 0.50. Its COR at F1887's 60 mph is not known here (not found); with
    /// the game ball's slope it would be 0.50 − [`GAME_BALL_COR_SLOPE`]·(60.8 − 26.8 m/s) ≈ 0.59.
    pub fn bbcor_protocol() -> Ball {
        Ball { cor: 0.50, ..Ball::default() }
    }

    /// `mlb`: the MLB game ball with e0 falling with impact speed: [`MLB_COR`] = 0.546 at [`MLB_COR_SPEED`]
    /// (85 ft/s, the specification's speed; its 0.514–0.578 band is met by construction) and
    /// [`GAME_BALL_COR_SLOPE`] ≈ −0.0027 per m/s, so e0 ≈ 0.49 at 45 m/s (a pitch met by a slow swing) and
    /// ≈ 0.42 at 72 m/s (a 40-m/s pitch on a 32-m/s sweet spot). Mass, radius and force law are the default
    /// ball's.
    ///
    /// The specification is measured against a slab of northern white ash, not a rigid wall. The model
    /// treats a wood bat's surface as locally rigid (the ball's law carries every contact loss), so the e0
    /// that makes a wood bat behave right is the one measured against ash: the ash-slab number is used as is,
    /// and a "rigid-wall" correction would count the wood's local give twice. Against an alloy barrel, whose
    /// surface gives less, the true rigid-wall e0 would be slightly lower; the difference is not known here.
    pub fn mlb() -> Ball {
        Ball {
            cor: MLB_COR,
            cor_slope: GAME_BALL_COR_SLOPE,
            cor_reference_speed: MLB_COR_SPEED,
            ..Ball::default()
        }
    }

    /// e0 at the normal approach speed `approach_speed` (m/s): `cor` itself for a constant-COR ball, else
    /// cor + cor_slope·(v − cor_reference_speed) clamped to [0.05, 1].
    pub fn cor_at(&self, approach_speed: f64) -> f64 {
        if self.cor_slope == 0.0 {
            return self.cor;
        }
        (self.cor + self.cor_slope * (approach_speed - self.cor_reference_speed)).clamp(0.05, 1.0)
    }

    /// The constant-COR ball one collision at normal approach speed `approach_speed` (m/s) sees: e0 =
    /// [`Ball::cor_at`]; a constant-COR ball is returned as it is (bit for bit).
    pub fn at_approach_speed(&self, approach_speed: f64) -> Ball {
        if self.cor_slope == 0.0 {
            return *self;
        }
        Ball { cor: self.cor_at(approach_speed), cor_slope: 0.0, cor_reference_speed: 0.0, ..*self }
    }

    /// Checks every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        let check = |field: &str, v: f64, ok: bool, allowed: &str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(PhysicsError::out_of_range(format!("ball.{field}"), v, allowed))
            }
        };
        check("mass", self.mass, self.mass >= 1e-3 && self.mass <= 10.0, "1e-3 ≤ mass ≤ 10 kg")?;
        check("radius", self.radius, self.radius >= 1e-3 && self.radius <= 0.5, "1e-3 ≤ radius ≤ 0.5 m")?;
        check("stiffness", self.stiffness, self.stiffness >= 1.0 && self.stiffness <= 1e15, "1 ≤ k1 ≤ 1e15 N/m^α")?;
        check("exponent", self.exponent, self.exponent >= 1.0 && self.exponent <= 4.0, "1 ≤ α ≤ 4")?;
        check(
            "cor",
            self.cor,
            self.cor >= 0.05 && self.cor <= 1.0,
            "0.05 ≤ e0 ≤ 1 (e0 in (0, 1]; below 0.05 the unloading exponent exceeds 1000)",
        )?;
        check(
            "cor_slope",
            self.cor_slope,
            self.cor_slope.abs() <= MAX_COR_SLOPE,
            "−0.02 ≤ cor_slope ≤ 0.02 s/m (0 = constant COR)",
        )?;
        check(
            "cor_reference_speed",
            self.cor_reference_speed,
            (0.0..=300.0).contains(&self.cor_reference_speed),
            "0 ≤ cor_reference_speed ≤ 300 m/s",
        )?;
        Ok(())
    }

    /// Unloading exponent β = (1+α)/e0² − 1 (e0 = `cor`; a collision resolves e0 at its speed first).
    pub fn unloading_exponent(&self) -> f64 {
        (1.0 + self.exponent) / (self.cor * self.cor) - 1.0
    }

    /// Unloading stiffness k2 = k1·u_m^(α−β) for a maximum compression `max_compression` (m), N/m^β.
    pub fn unloading_stiffness(&self, max_compression: f64) -> f64 {
        self.stiffness * max_compression.powf(self.exponent - self.unloading_exponent())
    }

    /// Energy dissipated by a contact whose largest compression was `max_compression` (m) and which ends at
    /// u = 0, J: the loading work k1·u_m^(α+1)/(α+1) less the unloading work k2·u_m^(β+1)/(β+1), i.e.
    /// (1 − e0²) of the loading work.
    ///
    /// It depends on u_m only, whatever the path: below u_m the ball follows the unloading curve, which is
    /// elastic (F du is exact there), so an intermediate unloading and reloading returns what it took, and
    /// loading beyond an earlier peak moves along the one loading curve.
    pub fn hysteresis_loss(&self, max_compression: f64) -> f64 {
        if !(max_compression > 0.0) {
            return 0.0;
        }
        let alpha = self.exponent;
        let loading_work = self.stiffness * max_compression.powf(alpha + 1.0) / (alpha + 1.0);
        loading_work * (1.0 - self.cor * self.cor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_speed_law_is_linear_clamped_and_a_zero_slope_is_the_ball_itself() {
        let ball = Ball { cor: 0.5, cor_slope: -0.01, cor_reference_speed: 30.0, ..Ball::default() };
        // 0.5 − 0.01·(40 − 30) = 0.4; far below and above, the clamp to a COR's range.
        assert!((ball.cor_at(40.0) - 0.4).abs() < 1e-15);
        assert_eq!(ball.cor_at(200.0), 0.05);
        assert_eq!(Ball { cor_slope: 0.01, ..ball }.cor_at(200.0), 1.0);
        let resolved = ball.at_approach_speed(40.0);
        assert_eq!((resolved.cor_slope, resolved.cor_reference_speed), (0.0, 0.0));
        assert!(resolved.validate().is_ok());
        let constant = Ball::default();
        assert_eq!(constant.at_approach_speed(1e3), constant);
        assert_eq!(constant.cor_at(f64::NAN).to_bits(), constant.cor.to_bits());
    }

    #[test]
    fn bad_speed_laws_are_refused_naming_the_field() {
        for (ball, field) in [
            (Ball { cor_slope: 0.03, ..Ball::default() }, "cor_slope"),
            (Ball { cor_slope: f64::NAN, ..Ball::default() }, "cor_slope"),
            (Ball { cor_reference_speed: 301.0, ..Ball::default() }, "cor_reference_speed"),
            (Ball { cor_reference_speed: -1.0, ..Ball::default() }, "cor_reference_speed"),
        ] {
            let e = ball.validate().unwrap_err().to_string();
            assert!(e.contains(field), "{e}");
        }
        assert!(Ball::mlb().validate().is_ok());
        assert_eq!(Ball::preset_names().len(), 3);
        for name in Ball::preset_names() {
            assert!(Ball::preset(name).unwrap().validate().is_ok(), "{name}");
        }
    }

    #[test]
    fn a_constant_ball_serialises_as_before_and_reads_without_the_new_fields() {
        let json = serde_json::to_string(&Ball::default()).unwrap();
        assert!(!json.contains("cor_slope") && !json.contains("cor_reference_speed"), "{json}");
        let back: Ball = serde_json::from_str(&json).unwrap();
        assert_eq!(back, Ball::default());
        let mlb: Ball = serde_json::from_str(&serde_json::to_string(&Ball::mlb()).unwrap()).unwrap();
        assert_eq!(mlb, Ball::mlb());
    }
}
