//! Bat geometry, materials and mass properties; built-in presets.

use super::PhysicsError;

/// An isotropic material: density (kg/m³), Young's modulus (Pa), shear modulus (Pa).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    /// Density, kg/m³.
    pub density: f64,
    /// Young's modulus Y, Pa.
    pub youngs_modulus: f64,
    /// Shear modulus S (G), Pa.
    pub shear_modulus: f64,
}

/// One profile station: position from the knob and the radii there, m.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Station {
    /// Distance from the knob, m.
    pub z: f64,
    /// Outer radius, m.
    pub outer_radius: f64,
    /// Inner (bore) radius, m; 0 for a solid section.
    pub inner_radius: f64,
}

/// A fill of the bore between `z_start` and `z_end` (m from the knob) with another material (e.g. cork).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CoreFill {
    /// The fill material.
    pub material: Material,
    /// Start of the filled range, m from the knob.
    pub z_start: f64,
    /// End of the filled range, m from the knob.
    pub z_end: f64,
}

/// A bat: a radius profile, a shell material, an optional core fill and the slice length used to discretise it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Bat {
    /// Human-readable name (preset name or file stem).
    pub name: String,
    /// Profile stations, z strictly increasing, first at the knob.
    pub stations: Vec<Station>,
    /// Shell material (the whole bat for a solid wood bat).
    pub shell: Material,
    /// Optional fill of the bore.
    pub core: Option<CoreFill>,
    /// Slice thickness Δz used for the beam model, m.
    pub slice_length: f64,
}

/// Rigid-body mass properties of a bat, SI units.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MassProperties {
    /// Mass, kg.
    pub mass: f64,
    /// Length, m.
    pub length: f64,
    /// Centre of mass, m from the knob.
    pub center_of_mass: f64,
    /// Moment of inertia about the centre of mass (axis normal to the swing plane), kg·m².
    pub moment_of_inertia: f64,
    /// Radius of gyration about the centre of mass, m.
    pub radius_of_gyration: f64,
}

impl MassProperties {
    /// Moment of inertia about a pivot at `pivot_z` (m from the knob), kg·m².
    pub fn moment_about(&self, pivot_z: f64) -> f64 {
        let d = self.center_of_mass - pivot_z;
        self.moment_of_inertia + self.mass * d * d
    }

    /// Centre of percussion for a pivot at `pivot_z`, m from the knob.
    pub fn center_of_percussion(&self, pivot_z: f64) -> f64 {
        let d = self.center_of_mass - pivot_z;
        pivot_z + self.moment_about(pivot_z) / (self.mass * d)
    }
}

impl Bat {
    /// Builds and validates a bat.
    pub fn new(
        name: impl Into<String>,
        stations: Vec<Station>,
        shell: Material,
        core: Option<CoreFill>,
        slice_length: f64,
    ) -> Result<Bat, PhysicsError> {
        let bat = Bat {
            name: name.into(),
            stations,
            shell,
            core,
            slice_length,
        };
        bat.validate()?;
        Ok(bat)
    }

    /// Checks every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        todo!("physics: validate bat")
    }

    /// Names of the built-in presets.
    pub fn preset_names() -> &'static [&'static str] {
        todo!("physics: preset names")
    }

    /// A built-in preset by name (see [`Bat::preset_names`]).
    pub fn preset(name: &str) -> Result<Bat, PhysicsError> {
        let _ = name;
        todo!("physics: presets")
    }

    /// Length of the bat, m.
    pub fn length(&self) -> f64 {
        todo!("physics: length")
    }

    /// Rigid-body mass properties.
    pub fn mass_properties(&self) -> MassProperties {
        todo!("physics: mass properties")
    }
}
