//! The JSON documents of the physics commands (stable snake_case fields, SI units; every field is documented
//! in docs/file-formats.md), each with its text table where it has one.

use serde::Serialize;

use super::table::{num, Table};
use crate::physics::{Ball, CollisionOptions, CollisionResult, Impact, MassProperties, SweetSpotSet};

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
    /// e0.
    pub cor: f64,
}

impl From<&Ball> for BallJson {
    fn from(b: &Ball) -> BallJson {
        BallJson { mass: b.mass, radius: b.radius, stiffness: b.stiffness, exponent: b.exponent, cor: b.cor }
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

/// The energy budget, J: the library's own type, whose serde field names are the documented JSON ones.
pub type EnergyJson = crate::physics::EnergyBudget;

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
            energy: r.energy,
            mode_energies: r
                .mode_energies
                .iter()
                .enumerate()
                .map(|(i, m)| ModeEnergyJson { mode: i + 1, frequency_hz: m.frequency, energy: m.energy })
                .collect(),
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
