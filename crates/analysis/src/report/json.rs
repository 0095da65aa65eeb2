//! The JSON documents of the physics commands (stable snake_case fields, SI units; every field is documented
//! in docs/file-formats.md), each with its text table where it has one.

use serde::Serialize;

use super::table::{num, Table};
use sweetspot_physics::hoop::HoopMode;
use sweetspot_physics::oblique::{rad_per_s_to_rpm, ObliqueResult, TangentialContact};
use sweetspot_physics::oblique3d::{BatterSide, SpatialResult};
use sweetspot_physics::{Ball, CollisionOptions, CollisionResult, EnergyBudget, Impact, MassProperties, SweetSpotSet};

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
    /// Tilt of the bat's long axis below the horizontal, degrees (barrel below the hands positive).
    pub bat_tilt_deg: f64,
    /// Horizontal direction of the bat's path, degrees, positive toward the right-field side.
    pub swing_direction_deg: f64,
    /// The batter's side.
    pub batter_side: BatterSide,
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
            bat_tilt_deg: 0.0,
            swing_direction_deg: 0.0,
            batter_side: BatterSide::Right,
            tangential_cor: contact.tangential_cor,
            friction: contact.friction,
            ball_inertia_ratio: contact.ball_inertia_ratio,
            tangential_stiffness_ratio: contact.stiffness_ratio,
        }
    }

    /// These inputs with the bat's tilt and the swing's direction (rad) and the batter's side.
    pub fn with_spatial(self, bat_tilt: f64, swing_direction: f64, batter_side: BatterSide) -> ObliqueInputsJson {
        ObliqueInputsJson {
            bat_tilt_deg: plus_zero(bat_tilt.to_degrees()),
            swing_direction_deg: plus_zero(swing_direction.to_degrees()),
            batter_side,
            ..self
        }
    }
}

/// `v` with −0 written as 0 (a mirrored zero is no direction).
fn plus_zero(v: f64) -> f64 {
    v + 0.0
}

/// The batted ball's flight as trackers report it: spray angle, spin split along the flight, total spin and
/// spin axis (conventions in [`sweetspot_physics::oblique3d`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlightJson {
    /// Spray angle, degrees, positive toward the right-field (first-base) side.
    pub spray_angle_deg: f64,
    /// Backspin, rpm (about the horizontal axis across the flight; positive lifts).
    pub backspin_rpm: f64,
    /// Sidespin, rpm (positive curves the ball toward the left-field side).
    pub sidespin_rpm: f64,
    /// Gyro spin along the flight, rpm.
    pub gyro_spin_rpm: f64,
    /// Total spin, rpm: what a radar reports.
    pub total_spin_rpm: f64,
    /// Spin axis, degrees in [0, 360): TrackMan's HitSpinAxis (180 = pure backspin, 90 = pure hook).
    pub spin_axis_deg: f64,
}

impl FlightJson {
    /// From the library's three-dimensional result.
    pub fn new(r: &SpatialResult) -> FlightJson {
        FlightJson {
            spray_angle_deg: plus_zero(r.spray_angle.to_degrees()),
            backspin_rpm: plus_zero(rad_per_s_to_rpm(r.backspin)),
            sidespin_rpm: plus_zero(rad_per_s_to_rpm(r.sidespin)),
            gyro_spin_rpm: plus_zero(rad_per_s_to_rpm(r.gyro_spin)),
            total_spin_rpm: rad_per_s_to_rpm(r.total_spin),
            spin_axis_deg: plus_zero(r.spin_axis.to_degrees()),
        }
    }

    /// The flight of a planar swing's ball: straight away, its spin all backspin (or topspin) — what
    /// [`sweetspot_physics::collide_spatial`] answers for a level square swing.
    pub fn planar(r: &ObliqueResult) -> FlightJson {
        let axis = if r.spin >= 0.0 { std::f64::consts::PI } else { 0.0 };
        FlightJson {
            spray_angle_deg: 0.0,
            backspin_rpm: r.spin_rpm(),
            sidespin_rpm: 0.0,
            gyro_spin_rpm: 0.0,
            total_spin_rpm: rad_per_s_to_rpm(r.spin.abs()),
            spin_axis_deg: axis.to_degrees(),
        }
    }
}

/// The batted ball of an oblique collision: speed, launch angle and spin, and their parts. The parts defined in
/// the vertical plane of a planar swing (tangential speed, line of centres, slips, the bat's motion after) are
/// left out for a three-dimensional one.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ObliqueJson {
    /// Barrel radius at the impact point, m.
    pub barrel_radius: f64,
    /// Ball exit speed (magnitude of the outgoing velocity), m/s.
    pub exit_speed: f64,
    /// Launch angle above the horizontal, degrees.
    pub launch_angle_deg: f64,
    /// Outgoing backspin, rpm, topspin negative (for a planar swing, the spin about the bat's axis).
    pub spin_rpm: f64,
    /// Spray angle, spin components, total spin and spin axis.
    #[serde(flatten)]
    pub flight: FlightJson,
    /// Outgoing velocity along the line of centres (away from the bat), m/s.
    pub normal_exit_speed: f64,
    /// Outgoing velocity along the tangent, m/s (planar swings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_exit_speed: Option<f64>,
    /// True when the ball slid throughout the contact (the friction cap bound).
    pub sliding: bool,
    /// Angle of the line of centres above the horizontal, degrees (planar swings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line_of_centres_angle_deg: Option<f64>,
    /// Tangential impulse on the ball, N·s (planar swings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_impulse: Option<f64>,
    /// Slip of the contact points before contact, m/s (planar swings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slip_before: Option<f64>,
    /// Slip after contact, m/s (planar swings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slip_after: Option<f64>,
    /// Bat CM velocity along the tangent after separation, m/s (planar swings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bat_cm_tangential_speed_after: Option<f64>,
    /// Bat angular speed in the plane of its axis and the tangent after separation, rad/s (planar swings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bat_tangential_angular_speed_after: Option<f64>,
    /// Bat roll rate about its own axis after separation, rad/s (planar swings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bat_roll_rate_after: Option<f64>,
}

impl ObliqueJson {
    /// From the library's oblique result on a barrel of radius `barrel_radius` (m).
    pub fn new(r: &ObliqueResult, barrel_radius: f64) -> ObliqueJson {
        ObliqueJson {
            barrel_radius,
            exit_speed: r.exit_speed,
            launch_angle_deg: r.launch_angle_deg(),
            spin_rpm: r.spin_rpm(),
            flight: FlightJson::planar(r),
            normal_exit_speed: r.normal_exit_speed,
            tangential_exit_speed: Some(r.tangential_exit_speed),
            sliding: r.sliding,
            line_of_centres_angle_deg: Some(r.line_of_centres_angle.to_degrees()),
            tangential_impulse: Some(r.tangential_impulse),
            slip_before: Some(r.slip_before),
            slip_after: Some(r.slip_after),
            bat_cm_tangential_speed_after: Some(r.bat_cm_tangential_speed_after),
            bat_tangential_angular_speed_after: Some(r.bat_tangential_angular_speed_after),
            bat_roll_rate_after: Some(r.bat_roll_rate_after),
        }
    }

    /// From the library's three-dimensional result on a barrel of radius `barrel_radius` (m).
    pub fn spatial(r: &SpatialResult, barrel_radius: f64) -> ObliqueJson {
        let flight = FlightJson::new(r);
        ObliqueJson {
            barrel_radius,
            exit_speed: r.exit_speed,
            launch_angle_deg: r.launch_angle.to_degrees(),
            spin_rpm: flight.backspin_rpm,
            flight,
            normal_exit_speed: r.normal.exit_speed,
            tangential_exit_speed: None,
            sliding: r.sliding,
            line_of_centres_angle_deg: None,
            tangential_impulse: None,
            slip_before: None,
            slip_after: None,
            bat_cm_tangential_speed_after: None,
            bat_tangential_angular_speed_after: None,
            bat_roll_rate_after: None,
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

    /// From a library three-dimensional result at `impact_z` on a barrel of radius `barrel_radius` (m).
    pub fn spatial(impact_z: f64, r: &SpatialResult, barrel_radius: f64) -> CollisionJson {
        CollisionJson {
            oblique: Some(ObliqueJson::spatial(r, barrel_radius)),
            ..CollisionJson::new(impact_z, &r.normal)
        }
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
