//! The JSON documents of the physics commands (stable snake_case fields, SI units; every field is documented
//! in docs/file-formats.md), each with its text table where it has one.

use serde::Serialize;

use super::table::{num, Table};
use crate::physics::hoop::HoopMode;
use crate::physics::oblique::{rad_per_s_to_rpm, ObliqueResult, TangentialContact};
use crate::physics::{Ball, CollisionOptions, CollisionResult, EnergyBudget, Impact, MassProperties, SweetSpotSet};

/// Pivot used for the moment of inertia and the centre of percussion: 6 in (0.1524 m) from the knob.
pub const PIVOT_Z: f64 = 0.1524;

/// Mass properties of a bat, SI units.
#[derive(Debug, Clone, Serialize)]
pub struct BatJson {
    /// Bat name.
    pub name: String,
    /// kg.
    pub mass: f64,
    /// m.
    pub length: f64,
    /// m from the knob.
    pub center_of_mass: f64,
    /// kg·m², about the centre of mass.
    pub moment_of_inertia: f64,
    /// m.
    pub radius_of_gyration: f64,
    /// The pivot used below, m from the knob.
    pub pivot_z: f64,
    /// kg·m², about the pivot.
    pub moment_about_pivot: f64,
    /// m from the knob, for the pivot.
    pub center_of_percussion: f64,
}

impl BatJson {
    /// From a bat's name and mass properties.
    pub fn new(name: &str, props: &MassProperties) -> BatJson {
        BatJson {
            name: name.to_string(),
            mass: props.mass,
            length: props.length,
            center_of_mass: props.center_of_mass,
            moment_of_inertia: props.moment_of_inertia,
            radius_of_gyration: props.radius_of_gyration,
            pivot_z: PIVOT_Z,
            moment_about_pivot: props.moment_about(PIVOT_Z),
            center_of_percussion: props.center_of_percussion(PIVOT_Z),
        }
    }

    /// Key/value rows for a table.
    pub fn table(&self) -> Table {
        let mut t = Table::new(["bat", self.name.as_str()]);
        t.row(["mass (kg)".to_string(), num(self.mass, 4)]);
        t.row(["length (m)".to_string(), num(self.length, 4)]);
        t.row(["centre of mass (m from knob)".to_string(), num(self.center_of_mass, 4)]);
        t.row(["moment of inertia about CM (kg·m²)".to_string(), num(self.moment_of_inertia, 4)]);
        t.row(["radius of gyration (m)".to_string(), num(self.radius_of_gyration, 4)]);
        t.row([format!("moment about pivot at {} m (kg·m²)", self.pivot_z), num(self.moment_about_pivot, 4)]);
        t.row([format!("centre of percussion, pivot {} m (m)", self.pivot_z), num(self.center_of_percussion, 4)]);
        t
    }
}

/// The ball, SI units.
#[derive(Debug, Clone, Serialize)]
pub struct BallJson {
    /// kg.
    pub mass: f64,
    /// m.
    pub radius: f64,
    /// k1, N/m^α.
    pub stiffness: f64,
    /// α.
    pub exponent: f64,
    /// e0 (at `cor_reference_speed` for a ball with a speed law).
    pub cor: f64,
    /// p of e0 ∝ v^(−p); left out for a constant-COR ball.
    #[serde(skip_serializing_if = "is_zero")]
    pub cor_speed_exponent: f64,
    /// m/s; left out for a constant-COR ball.
    #[serde(skip_serializing_if = "is_zero")]
    pub cor_reference_speed: f64,
}

/// Whether `v` is 0 (a constant-COR ball's document keeps exactly its former fields).
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl From<&Ball> for BallJson {
    fn from(b: &Ball) -> BallJson {
        let law = b.cor_speed_exponent != 0.0;
        BallJson {
            mass: b.mass,
            radius: b.radius,
            stiffness: b.stiffness,
            exponent: b.exponent,
            cor: b.cor,
            cor_speed_exponent: b.cor_speed_exponent,
            cor_reference_speed: if law { b.cor_reference_speed } else { 0.0 },
        }
    }
}

/// The numerical options.
#[derive(Debug, Clone, Serialize)]
pub struct OptionsJson {
    /// Vibrational modes integrated.
    pub modes: usize,
    /// RK4 step, s.
    pub time_step: f64,
}

impl From<&CollisionOptions> for OptionsJson {
    fn from(o: &CollisionOptions) -> OptionsJson {
        OptionsJson { modes: o.modes, time_step: o.time_step }
    }
}

/// The swing, SI units.
#[derive(Debug, Clone, Serialize)]
pub struct SwingJson {
    /// m/s toward the bat.
    pub ball_speed: f64,
    /// m/s toward the ball.
    pub bat_cm_speed: f64,
    /// rad/s, positive when the barrel leads.
    pub bat_angular_speed: f64,
}

impl From<&Impact> for SwingJson {
    fn from(i: &Impact) -> SwingJson {
        SwingJson { ball_speed: i.ball_speed, bat_cm_speed: i.bat_cm_speed, bat_angular_speed: i.bat_angular_speed }
    }
}

/// Energy left in one vibrational mode.
#[derive(Debug, Clone, Serialize)]
pub struct ModeEnergyJson {
    /// 1-based mode number.
    pub mode: usize,
    /// Hz.
    pub frequency_hz: f64,
    /// J.
    pub energy: f64,
}

/// The energy budget, J: the library's [`EnergyBudget`] with the same field names, the wall's hoop energies
/// present only for a collision with a hoop mode (a hollow section), so a solid bat's document is unchanged.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnergyJson {
    /// Total kinetic energy before contact, J.
    pub initial: f64,
    /// Ball kinetic energy after separation, J.
    pub ball: f64,
    /// Bat rigid-body kinetic energy after separation, J.
    pub bat_rigid: f64,
    /// Vibrational energy of the bat after separation, J.
    pub vibration: f64,
    /// Energy dissipated by the ball's hysteresis, J.
    pub hysteresis_loss: f64,
    /// Energy left in the wall's hoop mode after separation, J (hollow sections only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hoop: Option<f64>,
    /// Energy the ball put into the wall during contact, J (hollow sections only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hoop_stored: Option<f64>,
    /// Energy the wall gave back during contact, J (hollow sections only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hoop_returned: Option<f64>,
    /// initial − (ball + bat_rigid + vibration + hoop + hysteresis_loss), J.
    pub residual: f64,
}

impl EnergyJson {
    /// From the library's budget; `hollow` when the collision had a hoop mode.
    pub fn new(e: &EnergyBudget, hollow: bool) -> EnergyJson {
        let wall = |v: f64| hollow.then_some(v);
        EnergyJson {
            initial: e.initial,
            ball: e.ball,
            bat_rigid: e.bat_rigid,
            vibration: e.vibration,
            hysteresis_loss: e.hysteresis_loss,
            hoop: wall(e.hoop),
            hoop_stored: wall(e.hoop_stored),
            hoop_returned: wall(e.hoop_returned),
            residual: e.residual,
        }
    }
}

/// The wall's hoop (n = 2) mode at the impact point of a hollow section, SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HoopJson {
    /// Hoop frequency f_h, Hz.
    pub frequency_hz: f64,
    /// Hoop stiffness k_h, N/m.
    pub stiffness: f64,
    /// Effective mass m_h, kg.
    pub effective_mass: f64,
    /// Axial decay length 1/β of the wall's response, m.
    pub decay_length: f64,
    /// Mid-surface radius of the wall, m.
    pub radius: f64,
    /// Wall thickness, m.
    pub wall_thickness: f64,
    /// Share of the ball's force that drives the mode (1 for a point load on a thin wall).
    pub coupling: f64,
}

impl From<&HoopMode> for HoopJson {
    fn from(h: &HoopMode) -> HoopJson {
        HoopJson {
            frequency_hz: h.frequency_hz(),
            stiffness: h.stiffness,
            effective_mass: h.effective_mass,
            decay_length: h.decay_length,
            radius: h.radius,
            wall_thickness: h.wall_thickness,
            coupling: h.coupling,
        }
    }
}

/// The oblique inputs of a run: undercut in m, angles in degrees, spin in rpm, and the tangential contact.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ObliqueInputsJson {
    /// Undercut D, m (ball centre above the bat's path positive).
    pub undercut: f64,
    /// Attack angle of the bat's path above the horizontal, degrees.
    pub attack_angle_deg: f64,
    /// Descent angle of the pitch below the horizontal, degrees.
    pub pitch_angle_deg: f64,
    /// Pitch spin about the bat's axis, rpm, backspin positive.
    pub pitch_spin_rpm: f64,
    /// Tangential coefficient of restitution e_T.
    pub tangential_cor: f64,
    /// Coulomb friction coefficient μ.
    pub friction: f64,
    /// The ball's moment of inertia as a fraction of m R².
    pub ball_inertia_ratio: f64,
    /// η² = k_n/k_t of the compliant tangential law, when it replaces the constant e_T.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_stiffness_ratio: Option<f64>,
}

impl ObliqueInputsJson {
    /// From SI inputs: undercut m, angles rad, spin rad/s.
    pub fn new(
        undercut: f64,
        attack_angle: f64,
        pitch_angle: f64,
        pitch_spin: f64,
        contact: &TangentialContact,
    ) -> ObliqueInputsJson {
        ObliqueInputsJson {
            undercut,
            attack_angle_deg: attack_angle.to_degrees(),
            pitch_angle_deg: pitch_angle.to_degrees(),
            pitch_spin_rpm: rad_per_s_to_rpm(pitch_spin),
            tangential_cor: contact.tangential_cor,
            friction: contact.friction,
            ball_inertia_ratio: contact.ball_inertia_ratio,
            tangential_stiffness_ratio: contact.stiffness_ratio,
        }
    }
}

/// The batted ball of an oblique collision: speed, launch angle and spin, and their parts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ObliqueJson {
    /// Barrel radius at the impact point, m.
    pub barrel_radius: f64,
    /// Ball exit speed (magnitude of the outgoing velocity), m/s.
    pub exit_speed: f64,
    /// Launch angle above the horizontal, degrees.
    pub launch_angle_deg: f64,
    /// Outgoing spin about the bat's axis, rpm, backspin positive.
    pub spin_rpm: f64,
    /// Outgoing velocity along the line of centres (away from the bat), m/s.
    pub normal_exit_speed: f64,
    /// Outgoing velocity along the tangent, m/s.
    pub tangential_exit_speed: f64,
    /// True when the ball slid throughout the contact (the friction cap bound).
    pub sliding: bool,
    /// Angle of the line of centres above the horizontal, degrees.
    pub line_of_centres_angle_deg: f64,
    /// Tangential impulse on the ball, N·s.
    pub tangential_impulse: f64,
    /// Slip of the contact points before contact, m/s.
    pub slip_before: f64,
    /// Slip after contact, m/s.
    pub slip_after: f64,
    /// Bat CM velocity along the tangent after separation, m/s.
    pub bat_cm_tangential_speed_after: f64,
    /// Bat angular speed in the plane of its axis and the tangent after separation, rad/s.
    pub bat_tangential_angular_speed_after: f64,
    /// Bat roll rate about its own axis after separation, rad/s.
    pub bat_roll_rate_after: f64,
}

impl ObliqueJson {
    /// From the library's oblique result on a barrel of radius `barrel_radius` (m).
    pub fn new(r: &ObliqueResult, barrel_radius: f64) -> ObliqueJson {
        ObliqueJson {
            barrel_radius,
            exit_speed: r.exit_speed,
            launch_angle_deg: r.launch_angle_deg(),
            spin_rpm: r.spin_rpm(),
            normal_exit_speed: r.normal_exit_speed,
            tangential_exit_speed: r.tangential_exit_speed,
            sliding: r.sliding,
            line_of_centres_angle_deg: r.line_of_centres_angle.to_degrees(),
            tangential_impulse: r.tangential_impulse,
            slip_before: r.slip_before,
            slip_after: r.slip_after,
            bat_cm_tangential_speed_after: r.bat_cm_tangential_speed_after,
            bat_tangential_angular_speed_after: r.bat_tangential_angular_speed_after,
            bat_roll_rate_after: r.bat_roll_rate_after,
        }
    }
}

/// One collision, SI units.
///
/// Not `impact_z` + `#[serde(flatten)] CollisionResult`: the documented JSON (docs/file-formats.md, pinned by
/// tests/cli_json.rs) numbers the modes from 1 and names their frequency `frequency_hz`, and leaves out the
/// bat's speeds after separation, so serialising the library's type as is would change the interface.
#[derive(Debug, Clone, Serialize)]
pub struct CollisionJson {
    /// m from the knob.
    pub impact_z: f64,
    /// m/s away from the bat.
    pub exit_speed: f64,
    /// m/s, closed-form rigid bat with the ball's e0.
    pub rigid_exit_speed: f64,
    /// e_eff.
    pub effective_cor: f64,
    /// e_A.
    pub collision_efficiency: f64,
    /// s.
    pub contact_time: f64,
    /// N.
    pub peak_force: f64,
    /// N·s.
    pub impulse: f64,
    /// m.
    pub max_compression: f64,
    /// Energy budget.
    pub energy: EnergyJson,
    /// Per-mode energies.
    pub mode_energies: Vec<ModeEnergyJson>,
    /// The wall's hoop mode at the impact point (hollow sections only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hoop: Option<HoopJson>,
    /// The batted ball of an oblique run (absent for a head-on run, whose fields above are the whole
    /// answer). In an oblique run the fields above are the collision along the line of centres.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub oblique: Option<ObliqueJson>,
}

impl CollisionJson {
    /// From a library result at `impact_z`.
    pub fn new(impact_z: f64, r: &CollisionResult) -> CollisionJson {
        CollisionJson {
            impact_z,
            exit_speed: r.exit_speed,
            rigid_exit_speed: r.rigid_exit_speed,
            effective_cor: r.effective_cor,
            collision_efficiency: r.collision_efficiency,
            contact_time: r.contact_time,
            peak_force: r.peak_force,
            impulse: r.impulse,
            max_compression: r.max_compression,
            energy: EnergyJson::new(&r.energy, r.hoop.is_some()),
            mode_energies: r
                .mode_energies
                .iter()
                .enumerate()
                .map(|(i, m)| ModeEnergyJson { mode: i + 1, frequency_hz: m.frequency, energy: m.energy })
                .collect(),
            hoop: r.hoop.as_ref().map(HoopJson::from),
            oblique: None,
        }
    }

    /// From a library oblique result at `impact_z` on a barrel of radius `barrel_radius` (m): the normal
    /// collision's fields and the batted ball.
    pub fn oblique(impact_z: f64, r: &ObliqueResult, barrel_radius: f64) -> CollisionJson {
        CollisionJson { oblique: Some(ObliqueJson::new(r, barrel_radius)), ..CollisionJson::new(impact_z, &r.normal) }
    }
}

/// The sweet-spot set, m from the knob (and the best exit speed, m/s): the library's [`SweetSpotSet`],
/// serialized as is (its serde field names are the documented JSON ones), plus the text table.
#[derive(Debug, Clone, Serialize)]
#[serde(transparent)]
pub struct SweetSpotsJson(pub SweetSpotSet);

impl From<&SweetSpotSet> for SweetSpotsJson {
    fn from(s: &SweetSpotSet) -> SweetSpotsJson {
        SweetSpotsJson(s.clone())
    }
}

impl std::ops::Deref for SweetSpotsJson {
    type Target = SweetSpotSet;
    fn deref(&self) -> &SweetSpotSet {
        &self.0
    }
}

impl SweetSpotsJson {
    /// Key/value table.
    pub fn table(&self) -> Table {
        let mut t = Table::new(["sweet spot", "z (m from knob)"]);
        t.row([format!("maximum exit speed ({} m/s)", num(self.max_exit_speed, 4)), num(self.max_exit_speed_z, 4)]);
        t.row(["closed-form rigid optimum".to_string(), num(self.rigid_optimum_z, 4)]);
        t.row(["node of mode 1".to_string(), num(self.node1_z, 4)]);
        t.row(["node of mode 2".to_string(), num(self.node2_z, 4)]);
        t.row([format!("centre of percussion (pivot {PIVOT_Z} m)"), num(self.center_of_percussion_z, 4)]);
        t
    }
}
