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

use super::PhysicsError;

/// A ball, SI units. Loading force k1·u^α; unloading k2·u^β with β = (1+α)/e0² − 1.
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
    /// Coefficient of restitution e0 against a rigid wall, in (0, 1].
    pub cor: f64,
}

impl Default for Ball {
    /// A regulation baseball: 0.145 kg, 0.0366 m, k1 = 6.53e7 N/m^α, α = 1.84, e0 = 0.53.
    fn default() -> Self {
        Ball { mass: 0.145, radius: 0.0366, stiffness: 6.53e7, exponent: 1.84, cor: 0.53 }
    }
}

impl Ball {
    /// Names of the built-in balls.
    pub fn preset_names() -> &'static [&'static str] {
        &["baseball", "bbcor"]
    }

    /// A built-in ball by name: `baseball` ([`Ball::default`]) or `bbcor` ([`Ball::bbcor_protocol`]).
    pub fn preset(name: &str) -> Result<Ball, PhysicsError> {
        match name {
            "baseball" => Ok(Ball::default()),
            "bbcor" => Ok(Ball::bbcor_protocol()),
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
    pub fn bbcor_protocol() -> Ball {
        Ball { cor: 0.50, ..Ball::default() }
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
        Ok(())
    }

    /// Unloading exponent β = (1+α)/e0² − 1.
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
