//! The rigid-bat (Brody) model: closed-form exit speed and its optimum impact point.
//!
//! With R = m_ball/M·(1 + ((z − z_cm)/r_γ)²) (Nathan eq. 24) and the bat speed at the impact point
//! v_bat = V_cm + ω (z − z_cm), momentum, angular momentum and the COR e give (Nathan eq. 25/27)
//! v_f = (e − R)/(1 + R)·v_ball + (1 + e)/(1 + R)·v_bat.
//!
//! **Optimum (the seed's eq. 5/6, re-derived).** Write b = z − z_cm, c = v_ball + V_cm (approach speed at the
//! CM) and K = I (M + m)/(m M). Then v_f = −v_ball + (1+e)(c + ω b)/(1 + m/M + m b²/I), and dv_f/db = 0 gives
//! ω b² + 2 c b − ω K = 0. The maximum is the root with c + ω b > 0:
//! b* = ω K / (c + √(c² + ω² K)) (= −c/ω + √((c/ω)² + K) for ω ≠ 0; b* = 0 for ω = 0).
//! The seed prints eq. 5 without "= 0" (in its frame v_i/ω_i < 0, and its eq. 6 with the + root is this optimum).

use super::{Impact, MassProperties, PhysicsError};

/// A bat reduced to rigid-body parameters plus an effective COR (the seed's Tables 1 and 2).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RigidBat {
    /// Name.
    pub name: String,
    /// Mass, kg.
    pub mass: f64,
    /// Length, m.
    pub length: f64,
    /// Centre of mass, m from the knob.
    pub center_of_mass: f64,
    /// Moment of inertia about the centre of mass, kg·m².
    pub moment_of_inertia: f64,
    /// Effective COR used in the closed form.
    pub effective_cor: f64,
}

/// Ball speed of the seed's Figure 6, m/s.
pub const SEED_FIG6_BALL_SPEED: f64 = 8.0;
/// Bat speed (at the impact point) of the seed's Figure 6, m/s.
pub const SEED_FIG6_BAT_SPEED: f64 = 4.0;

impl RigidBat {
    /// Names of the seed's rigid-parameter bats.
    pub fn preset_names() -> &'static [&'static str] {
        &["seed-table1-normal", "seed-table1-corked", "seed-table2-wood", "seed-table2-aluminum"]
    }

    /// A seed table bat by name. Table 1 (normal / corked, from Brody via the seed): 0.846 kg, 0.84 m,
    /// CM 0.51 m, I 0.047 kg·m², e_eff 0.40 / 0.800 kg, 0.84 m, CM 0.40 m, I 0.040 kg·m², e_eff 0.40.
    /// Table 2: wood = Table 1 normal; aluminum 0.825 kg, 0.81 m, CM 0.46 m, I 0.046 kg·m², e_eff 0.58.
    pub fn preset(name: &str) -> Result<RigidBat, PhysicsError> {
        let make = |mass, length, cm, i, e| RigidBat {
            name: name.to_string(),
            mass,
            length,
            center_of_mass: cm,
            moment_of_inertia: i,
            effective_cor: e,
        };
        match name {
            "seed-table1-normal" | "seed-table2-wood" => Ok(make(0.846, 0.84, 0.51, 0.047, 0.40)),
            "seed-table1-corked" => Ok(make(0.800, 0.84, 0.40, 0.040, 0.40)),
            "seed-table2-aluminum" => Ok(make(0.825, 0.81, 0.46, 0.046, 0.58)),
            _ => Err(PhysicsError::UnknownPreset { name: name.to_string(), known: Self::preset_names().join(", ") }),
        }
    }

    /// Checks every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        let check = |field: &str, v: f64, ok: bool, allowed: &str| {
            if v.is_finite() && ok {
                Ok(())
            } else {
                Err(PhysicsError::out_of_range(field, v, allowed))
            }
        };
        check("mass", self.mass, self.mass > 0.0, "mass > 0 kg")?;
        check("length", self.length, self.length > 0.0, "length > 0 m")?;
        check(
            "center_of_mass",
            self.center_of_mass,
            (0.0..=self.length).contains(&self.center_of_mass),
            "0 ≤ z_cm ≤ length",
        )?;
        check("moment_of_inertia", self.moment_of_inertia, self.moment_of_inertia > 0.0, "I > 0 kg·m²")?;
        check("effective_cor", self.effective_cor, self.effective_cor > 0.0 && self.effective_cor <= 1.0, "0 < e ≤ 1")?;
        Ok(())
    }

    /// Mass properties of this rigid bat.
    pub fn mass_properties(&self) -> MassProperties {
        MassProperties::from_totals(self.mass, self.length, self.center_of_mass, self.moment_of_inertia)
    }

    /// Exit speed (m/s) of a ball of `ball_mass` (kg) for `impact`, with this bat's effective COR.
    pub fn exit_speed(&self, ball_mass: f64, impact: &Impact) -> f64 {
        exit_speed(&self.mass_properties(), ball_mass, self.effective_cor, impact)
    }

    /// Exit speed (m/s) when the bat speed *at the impact point* is given directly (the seed's Fig. 5/6 use).
    pub fn exit_speed_at(&self, ball_mass: f64, ball_speed: f64, bat_speed_at_impact: f64, impact_z: f64) -> f64 {
        let r = recoil_factor(&self.mass_properties(), ball_mass, impact_z);
        exit_speed_from_recoil(r, self.effective_cor, ball_speed, bat_speed_at_impact)
    }

    /// The seed's rigid optimum impact point for this bat (m from the knob).
    pub fn optimum_impact_z(&self, ball_mass: f64, impact: &Impact) -> f64 {
        optimum_impact_z(&self.mass_properties(), ball_mass, impact)
    }
}

/// R0 = m_ball/M·(1 + ((z − z_cm)/r_γ)²), dimensionless (Nathan eq. 24).
pub fn recoil_factor(mp: &MassProperties, ball_mass: f64, impact_z: f64) -> f64 {
    let b = (impact_z - mp.center_of_mass) / mp.radius_of_gyration;
    ball_mass / mp.mass * (1.0 + b * b)
}

/// Speed of the bat at `impact_z` toward the ball, m/s: V_cm + ω (z − z_cm).
pub fn bat_speed_at(mp: &MassProperties, impact: &Impact) -> f64 {
    impact.bat_cm_speed + impact.bat_angular_speed * (impact.impact_z - mp.center_of_mass)
}

/// v_f = (e − R)/(1 + R)·v_ball + (1 + e)/(1 + R)·v_bat, m/s (Nathan eq. 25/27).
pub fn exit_speed_from_recoil(recoil: f64, cor: f64, ball_speed: f64, bat_speed_at_impact: f64) -> f64 {
    ((cor - recoil) * ball_speed + (1.0 + cor) * bat_speed_at_impact) / (1.0 + recoil)
}

/// Closed-form rigid-bat exit speed, m/s, for a free rigid bat with mass properties `mp` and COR `cor`.
pub fn exit_speed(mp: &MassProperties, ball_mass: f64, cor: f64, impact: &Impact) -> f64 {
    let r = recoil_factor(mp, ball_mass, impact.impact_z);
    exit_speed_from_recoil(r, cor, impact.ball_speed, bat_speed_at(mp, impact))
}

/// Effective COR solved from eq. 27 for an exit speed `exit_speed` (m/s).
pub fn effective_cor(mp: &MassProperties, ball_mass: f64, impact: &Impact, exit_speed: f64) -> f64 {
    let r = recoil_factor(mp, ball_mass, impact.impact_z);
    let vbat = bat_speed_at(mp, impact);
    (exit_speed * (1.0 + r) + r * impact.ball_speed - vbat) / (impact.ball_speed + vbat)
}

/// The seed's rigid optimum: z (m from the knob) maximising the rigid exit speed for the swing `impact`
/// (its impact_z is ignored). Independent of the COR; see the module docs for the derivation.
pub fn optimum_impact_z(mp: &MassProperties, ball_mass: f64, impact: &Impact) -> f64 {
    let c = impact.ball_speed + impact.bat_cm_speed;
    let w = impact.bat_angular_speed;
    let k = mp.moment_of_inertia * (mp.mass + ball_mass) / (ball_mass * mp.mass);
    let b = w * k / (c + (c * c + w * w * k).sqrt());
    // Only a ball and bat that do not approach (c ≤ 0 and ω = 0) make this 0/0; the CM is then as good as any.
    mp.center_of_mass + if b.is_finite() { b } else { 0.0 }
}
