//! Bat geometry, materials and mass properties; built-in presets.
//!
//! # Profile and slicing
//! A bat is a list of [`Station`]s: z from the knob, outer radius and inner (bore) radius, the first at
//! z = 0 and the last at the barrel end (z = length). Between stations the radii vary linearly. For the beam
//! model the bat is cut into N = round(length / slice_length) slices of equal thickness Δz = length / N;
//! slice i (1-based) spans [(i−1)Δz, iΔz] and takes the section **at its centre** (i−½)Δz (midpoint rule).
//! A feature shorter than a slice is therefore resolved only to the slice. A [`CoreFill`] fills the bore of
//! every slice whose centre lies in [z_start, z_end].
//!
//! Each slice's section is a composite: the shell annulus (outer, inner radius) in the shell material plus,
//! if filled, a disc of the bore radius in the core material. Per slice:
//! mass m = Δz·Σρ·A, rotary inertia J = Δz·Σρ·I (I = π(r_o⁴ − r_i⁴)/4 about a diameter), bending stiffness
//! (YI) = ΣY·I, shear stiffness (SA) = ΣS·A (no shear coefficient, as in Nathan's model).
//!
//! # Slice tables (`r161.dat`, `torpedo.dat`)
//! Nathan's files hold one line per 1-cm slice: column 1 the slice index i (1, 2, … = cm from the knob),
//! column 2 the slice **diameter** in mm. We read slice i as the section of [(i−1)Δz, iΔz], i.e. a station at
//! its centre (i−½)Δz; stations at z = 0 and z = NΔz repeat the first and last radius so that the length is
//! NΔz and slicing at Δz reproduces the table exactly. (This reading gives the R161 0.869 kg, CM 0.561 m,
//! radius of gyration 0.229 m, in line with Nathan's published values.)

use super::units::INCH;
use super::PhysicsError;

/// Pivot of the NCAA/ASTM bat tests and of the seed's centre of percussion, m from the knob (6 in).
pub const PIVOT_Z: f64 = 6.0 * INCH;

/// Smallest and largest number of slices a bat may be cut into.
pub const SLICE_COUNT_RANGE: (usize, usize) = (4, 4000);

/// Barrel wall of the `aluminum` preset, m (solved with the handle wall and end cap for Table 2's mass
/// properties; see [`Bat::aluminum`]).
pub const ALUMINUM_BARREL_WALL: f64 = 0.002_382_977_692;

/// Barrel wall of the `bbcor-alloy` bat, m: where the model's BBCOR is 0.50 (see [`Bat::bbcor_alloy`]):
/// 12.7 mm, far thicker than a real barrel (see there why).
pub const BBCOR_ALLOY_BARREL_WALL: f64 = 0.012_696_527_053;

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

impl Material {
    /// Ash-like wood of Nathan's R161: ρ 649 kg/m³, Y 1.814e10 Pa, S 1.05e9 Pa.
    pub const R161_WOOD: Material = Material { density: 649.0, youngs_modulus: 1.814e10, shear_modulus: 1.05e9 };
    /// Wood of Nathan's torpedo bat: ρ 690 kg/m³, Y 1.65e10 Pa, S 9.0e8 Pa.
    pub const TORPEDO_WOOD: Material = Material { density: 690.0, youngs_modulus: 1.65e10, shear_modulus: 9.0e8 };
    /// Cork: ρ 200 kg/m³, E 30 MPa, G 6 MPa (typical natural cork).
    pub const CORK: Material = Material { density: 200.0, youngs_modulus: 3.0e7, shear_modulus: 6.0e6 };
    /// Aluminum alloy (7xxx-series bat alloy): ρ 2700 kg/m³, E 70 GPa, G 26 GPa.
    pub const ALUMINUM: Material = Material { density: 2700.0, youngs_modulus: 7.0e10, shear_modulus: 2.6e10 };

    /// Checks that every field is finite and physical; `field` prefixes the error's field name.
    pub fn validate(&self, field: &str) -> Result<(), PhysicsError> {
        check_range(&format!("{field}.density"), self.density, 1.0, 1.0e5, "1 ≤ density ≤ 1e5 kg/m³")?;
        check_range(&format!("{field}.youngs_modulus"), self.youngs_modulus, 1.0e3, 1.0e13, "1e3 ≤ Y ≤ 1e13 Pa")?;
        check_range(&format!("{field}.shear_modulus"), self.shear_modulus, 1.0e3, 1.0e13, "1e3 ≤ S ≤ 1e13 Pa")?;
        Ok(())
    }
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

    /// Effective mass of the free rigid bat at `z` (m from the knob), kg: M / (1 + ((z − z_cm)/r_γ)²).
    pub fn effective_mass_at(&self, z: f64) -> f64 {
        let b = (z - self.center_of_mass) / self.radius_of_gyration;
        self.mass / (1.0 + b * b)
    }

    /// Builds mass properties from totals: mass (kg), length (m), centre of mass (m), moment of inertia (kg·m²).
    pub fn from_totals(mass: f64, length: f64, center_of_mass: f64, moment_of_inertia: f64) -> MassProperties {
        MassProperties {
            mass,
            length,
            center_of_mass,
            moment_of_inertia,
            radius_of_gyration: (moment_of_inertia / mass).sqrt(),
        }
    }
}

/// The discretised section of one slice, SI units (see the module docs for the composite rule).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Slice {
    /// Centre of the slice, m from the knob.
    pub z: f64,
    /// Mass m = Δz·Σρ·A, kg.
    pub mass: f64,
    /// Rotary inertia J = Δz·Σρ·I about the slice's transverse axis, kg·m².
    pub rotary_inertia: f64,
    /// Bending stiffness (YI) = ΣY·I, N·m².
    pub bending_stiffness: f64,
    /// Shear stiffness (SA) = ΣS·A, N.
    pub shear_stiffness: f64,
}

fn check_range(field: &str, value: f64, min: f64, max: f64, allowed: &str) -> Result<(), PhysicsError> {
    if value.is_finite() && value >= min && value <= max {
        Ok(())
    } else {
        Err(PhysicsError::out_of_range(field, value, allowed))
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
        let bat = Bat { name: name.into(), stations, shell, core, slice_length };
        bat.validate()?;
        Ok(bat)
    }

    /// Checks every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        if self.stations.len() < 2 {
            return Err(PhysicsError::BadProfile(format!(
                "stations: {} given, expected at least 2 (knob and barrel end)",
                self.stations.len()
            )));
        }
        for (i, s) in self.stations.iter().enumerate() {
            check_range(&format!("stations[{i}].z"), s.z, 0.0, 3.0, "0 ≤ z ≤ 3 m")?;
            check_range(
                &format!("stations[{i}].outer_radius"),
                s.outer_radius,
                1e-4,
                0.2,
                "1e-4 ≤ outer_radius ≤ 0.2 m",
            )?;
            if !(s.inner_radius.is_finite() && s.inner_radius >= 0.0 && s.inner_radius < s.outer_radius) {
                return Err(PhysicsError::out_of_range(
                    format!("stations[{i}].inner_radius"),
                    s.inner_radius,
                    format!("0 ≤ inner_radius < outer_radius = {} m", s.outer_radius),
                ));
            }
        }
        if self.stations[0].z != 0.0 {
            return Err(PhysicsError::out_of_range(
                "stations[0].z",
                self.stations[0].z,
                "0 m (the first station is the knob)",
            ));
        }
        for i in 1..self.stations.len() {
            if self.stations[i].z <= self.stations[i - 1].z {
                return Err(PhysicsError::BadProfile(format!(
                    "stations[{i}].z = {} m is not greater than stations[{}].z = {} m: z must increase strictly",
                    self.stations[i].z,
                    i - 1,
                    self.stations[i - 1].z
                )));
            }
        }
        let length = self.length();
        check_range("length", length, 0.05, 3.0, "0.05 ≤ length (last station z) ≤ 3 m")?;
        self.shell.validate("shell")?;
        let (min_n, max_n) = SLICE_COUNT_RANGE;
        // One rule and one message for every bad slice_length (NaN, ≤ 0, too fine, too coarse): the bat must have
        // min_n…max_n slices, and N = round(length / slice_length) changes count halfway between integers.
        let n = (length / self.slice_length).round();
        if !(self.slice_length.is_finite() && self.slice_length > 0.0 && n >= min_n as f64 && n <= max_n as f64) {
            return Err(PhysicsError::out_of_range(
                "slice_length",
                self.slice_length,
                format!(
                    "{:.3e} ≤ slice_length ≤ {:.3e} m ({min_n}…{max_n} slices over the {length} m bat)",
                    length / (max_n as f64 + 0.49),
                    length / (min_n as f64 - 0.49)
                ),
            ));
        }
        if let Some(core) = &self.core {
            core.material.validate("core.material")?;
            check_range("core.z_start", core.z_start, 0.0, length, &format!("0 ≤ z_start ≤ length = {length} m"))?;
            if !(core.z_end.is_finite() && core.z_end > core.z_start && core.z_end <= length) {
                return Err(PhysicsError::out_of_range(
                    "core.z_end",
                    core.z_end,
                    format!("z_start = {} < z_end ≤ length = {length} m", core.z_start),
                ));
            }
            let filled = self.slices_raw().iter().any(|&(z, _, ri)| ri > 0.0 && z >= core.z_start && z <= core.z_end);
            if !filled {
                return Err(PhysicsError::BadProfile(format!(
                    "core: no slice centre in [{}, {}] m has a bore (inner_radius > 0) to fill",
                    core.z_start, core.z_end
                )));
            }
        }
        Ok(())
    }

    /// Names of the built-in presets.
    pub fn preset_names() -> &'static [&'static str] {
        &["r161", "r161-corked", "aluminum", "torpedo"]
    }

    /// A built-in preset by name (see [`Bat::preset_names`]; `bbcor-alloy` is built too, and joins the list
    /// once the node, rig and CLI carry the hoop mode).
    pub fn preset(name: &str) -> Result<Bat, PhysicsError> {
        match name {
            "r161" => Bat::r161(),
            "r161-corked" => Bat::r161_corked(),
            "aluminum" => Bat::aluminum(),
            "bbcor-alloy" => Bat::bbcor_alloy(),
            "torpedo" => Bat::torpedo(),
            _ => Err(PhysicsError::UnknownPreset { name: name.to_string(), known: Bat::preset_names().join(", ") }),
        }
    }

    /// `r161`: Nathan's 33-in (0.84 m) R161 wood bat. Profile: `crates/physics/src/data/r161.dat` from A. M. Nathan's
    /// web page for "Dynamics of the baseball–bat collision", Am. J. Phys. 68, 979 (2000) (84 slices of 1 cm,
    /// diameters in mm); material as used there: ρ 649 kg/m³, Y 1.814e10 Pa, S 1.05e9 Pa.
    pub fn r161() -> Result<Bat, PhysicsError> {
        Bat::from_slice_table("r161", include_str!("data/r161.dat"), Material::R161_WOOD, 0.01)
    }

    /// `r161-corked`: the R161 with a 1-in-diameter (0.0254 m), 10-in-deep (0.254 m) cavity drilled along the
    /// axis from the barrel end and filled with cork (ρ 200 kg/m³, E 30 MPa, G 6 MPa; typical values for
    /// natural cork). On the 1-cm grid the cavity is resolved as the slices whose centres lie within 0.254 m of
    /// the barrel end (the last 25 slices, 0.25 m).
    pub fn r161_corked() -> Result<Bat, PhysicsError> {
        let mut bat = Bat::r161()?;
        let length = bat.length();
        let bore_radius = 0.5 * INCH;
        let z_start = length - 10.0 * INCH;
        // Stations sit at slice centres, and slicing samples exactly there, so the bore is cut slice by slice.
        for s in bat.stations.iter_mut().filter(|s| s.z >= z_start) {
            s.inner_radius = bore_radius;
        }
        bat.name = "r161-corked".to_string();
        bat.core = Some(CoreFill { material: Material::CORK, z_start, z_end: length });
        bat.validate()?;
        Ok(bat)
    }

    /// `torpedo`: Nathan's torpedo-shaped bat (0.85 m). Profile `crates/physics/src/data/torpedo.dat` (85 slices of
    /// 1 cm, diameters in mm) from the same source as the R161; ρ 690 kg/m³, Y 1.65e10 Pa, S 9.0e8 Pa.
    pub fn torpedo() -> Result<Bat, PhysicsError> {
        Bat::from_slice_table("torpedo", include_str!("data/torpedo.dat"), Material::TORPEDO_WOOD, 0.01)
    }

    /// `aluminum`: a hollow aluminum-alloy bat (E 70 GPa, ρ 2700 kg/m³, G 26 GPa), 0.81 m long, whose
    /// mass properties match the seed's Table 2 aluminum bat (0.825 kg, CM 0.46 m from the knob,
    /// I_cm 0.046 kg·m²). Shape: a solid 1.7-in-diameter knob (first 1-cm slice); a 1-in-diameter handle up to
    /// 0.28 m; a linear taper to a 2⅝-in barrel at 0.50 m; the barrel to the end; the last slice is the
    /// end-cap rim. Three free parameters were solved offline (Newton on the slice sums, 1-cm slices) so that
    /// mass, CM and I_cm match Table 2: handle wall 3.123 mm, barrel wall 2.383 mm (linear in between along
    /// the taper), end-cap slice inner radius 29.84 mm (a 3.5-mm rim).
    ///
    /// The solved barrel wall is kept as a realistic one: 2.383 mm (0.094 in) gives h/a = 0.074 and a hoop
    /// frequency of about 1.8 kHz on the barrel ([`crate::hoop`]), inside the 1,000–2,500 Hz band
    /// measured on hollow bats (Russell); a single-wall alloy barrel a few tenths of a millimetre thinner or
    /// thicker would still be in that band.
    pub fn aluminum() -> Result<Bat, PhysicsError> {
        Bat::alloy_profile("aluminum", ALUMINUM_BARREL_WALL)
    }

    /// `bbcor-alloy`: the `aluminum` profile (same handle wall, taper, end cap and alloy) with the barrel wall
    /// thickened to [`BBCOR_ALLOY_BARREL_WALL`], the wall at which the model's BBCOR
    /// ([`crate::metrics::bbcor`], 18 modes, 5-µs steps) is 0.50, the NCAA limit. The wall was found
    /// by a root solve of the full model (hoop mode and contact patch included) over the barrel wall alone
    /// (the test `bbcor_alloy_wall_solve` in `tests/physics_trampoline.rs` re-runs it); the handle and end cap
    /// are those of `aluminum`, so the thicker barrel makes this bat heavier than Table 2's (its mass
    /// properties follow from the profile, see [`Bat::mass_properties`]).
    ///
    /// The solve lands at a 12.7-mm wall and a 2.6-kg bat — not a bat anyone swings, which is why this bat is
    /// not in [`Bat::preset_names`]. The reason is in the protocol: with the protocol ball's e0 = 0.50
    /// ([`crate::Ball::bbcor_protocol`]) a rigid, non-vibrating bat scores exactly 0.50, the beam's
    /// vibrations lower that only a little at the best point (the R161 scores 0.498), so in this model a
    /// BBCOR of 0.50 needs a wall whose trampoline is almost gone; the model's BBCOR falls below 0.51 only
    /// from a wall of about 4.3 mm on. Real BBCOR-certified alloy bats do it with thinner walls. The protocol
    /// ball's e0 at 136 mph is not the free choice it looks: the NCAA set 0.50 "slightly higher than the best
    /// available wood bats", which puts the test ball's e0 there near 0.50 (the game ball's speed law,
    /// [`crate::Ball::mlb`], gives 0.4995 and moves the wall to 10.9 mm, 2.35 kg); `aluminum`'s
    /// 2.4-mm wall would score 0.50 only with e0 = 0.46, with which the R161 would score 0.459. So the
    /// model's trampoline is too strong for certified bats (it leaves out the end cap, which stiffens the
    /// wall near the barrel's end, the wall's damping and multi-wall construction).
    pub fn bbcor_alloy() -> Result<Bat, PhysicsError> {
        Bat::alloy_profile("bbcor-alloy", BBCOR_ALLOY_BARREL_WALL)
    }

    /// The alloy profile of `aluminum` (see [`Bat::aluminum`]) with a barrel wall of `barrel_wall` m (the
    /// handle wall and end cap as solved for `aluminum`), named `name`.
    pub fn alloy_profile(name: &str, barrel_wall: f64) -> Result<Bat, PhysicsError> {
        let stations = alloy_stations(barrel_wall, ALLOY_HANDLE_WALL, 0.0)?;
        Bat::new(name, stations, Material::ALUMINUM, None, ALLOY_SLICE)
    }

    /// The alloy profile of `aluminum` with a barrel wall of `barrel_wall` m, built to `aluminum`'s mass and
    /// swing weight (moment of inertia about the 6-in pivot) as a bat maker keeps a certified model's weight
    /// and swing weight: the handle wall and a solid end-cap plug are the two free parameters (see
    /// [`Bat::alloy_weight_matched`]), named `name`. Length, mass and swing weight are those of a drop −3
    /// bat: 0.81 m (31.9 in) and 0.825 kg (29.1 oz), length in inches minus weight in ounces = 2.8.
    ///
    /// Why: a thinner barrel wall alone makes a lighter bat, which the batter swings faster but which gives
    /// the ball less effective mass; certified bats are held to a length–weight rule ("minus-3") and a lower
    /// limit on the moment of inertia, so bats compared by their hoop frequency (Nathan, Crisco, Greenwald,
    /// Russell & Smith, Sports Eng. 13, 153 (2011)) differ in their walls, not in their weight.
    ///
    /// The end-cap plug fills the bore from the barrel end inward, slice by slice, with the shell's alloy
    /// (a solid plug of `end_cap_mass` kg beyond the `aluminum` end cap's rim), so its mass sits in the
    /// beam's own slices (exact in the mass matrix, mass properties and rigid modes) and the filled slices
    /// keep no hoop mode (no bore left, or a bore plugged at the end, which is where a cap stiffens the
    /// wall). The solve is nested bisection: the handle wall for the mass at a given plug, the plug for the
    /// swing weight (monotone: moving mass from the handle to the end raises it). It exists for walls up to
    /// about `aluminum`'s own ([`ALUMINUM_BARREL_WALL`]): a thicker barrel is heavier at the barrel than
    /// `aluminum` even with the lightest handle, and is refused with [`PhysicsError::OutOfRange`].
    pub fn alloy_weight_matched(name: &str, barrel_wall: f64) -> Result<Bat, PhysicsError> {
        let target = Bat::aluminum()?.mass_properties();
        let (handle_wall, end_cap_mass) = alloy_weight_match(barrel_wall, &target)?;
        let stations = alloy_stations(barrel_wall, handle_wall, end_cap_mass)?;
        Bat::new(name, stations, Material::ALUMINUM, None, ALLOY_SLICE)
    }

    /// Parses a slice table (Nathan's `.dat` format: per line the 1-based slice index and the slice
    /// **diameter** in mm, separated by whitespace or a comma; blank lines and `#` comments ignored) into a
    /// solid bat of `material` with slices of `slice_length` m (see the module docs for the z reading).
    pub fn from_slice_table(
        name: &str,
        text: &str,
        material: Material,
        slice_length: f64,
    ) -> Result<Bat, PhysicsError> {
        if !(slice_length.is_finite() && slice_length > 0.0 && slice_length <= 0.5) {
            return Err(PhysicsError::out_of_range("slice_length", slice_length, "0 < slice_length ≤ 0.5 m"));
        }
        let mut radii = Vec::new();
        for (line_no, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let mut cols = line.split(|c: char| c.is_whitespace() || c == ',').filter(|s| !s.is_empty());
            let parse = |s: Option<&str>, what: &str| -> Result<f64, PhysicsError> {
                s.and_then(|v| v.parse::<f64>().ok()).ok_or_else(|| {
                    PhysicsError::BadProfile(format!("{name} line {}: expected {what} in '{raw}'", line_no + 1))
                })
            };
            let index = parse(cols.next(), "a slice index")?;
            let diameter_mm = parse(cols.next(), "a diameter in mm")?;
            let expected = radii.len() + 1;
            if (index - expected as f64).abs() > 1e-6 {
                return Err(PhysicsError::BadProfile(format!(
                    "{name} line {}: slice index {index}, expected {expected} (indices run 1, 2, … without gaps)",
                    line_no + 1
                )));
            }
            if !(diameter_mm.is_finite() && diameter_mm > 0.0 && diameter_mm <= 400.0) {
                return Err(PhysicsError::out_of_range(
                    format!("{name} line {} diameter", line_no + 1),
                    diameter_mm,
                    "0 < diameter ≤ 400 mm",
                ));
            }
            radii.push(diameter_mm / 2000.0);
        }
        if radii.len() < SLICE_COUNT_RANGE.0 {
            return Err(PhysicsError::BadProfile(format!(
                "{name}: {} slices, expected at least {}",
                radii.len(),
                SLICE_COUNT_RANGE.0
            )));
        }
        let n = radii.len();
        let mut stations = Vec::with_capacity(n + 2);
        stations.push(Station { z: 0.0, outer_radius: radii[0], inner_radius: 0.0 });
        for (i, &r) in radii.iter().enumerate() {
            stations.push(Station { z: (i as f64 + 0.5) * slice_length, outer_radius: r, inner_radius: 0.0 });
        }
        stations.push(Station { z: n as f64 * slice_length, outer_radius: radii[n - 1], inner_radius: 0.0 });
        Bat::new(name, stations, material, None, slice_length)
    }

    /// Length of the bat, m.
    pub fn length(&self) -> f64 {
        self.stations.last().map_or(0.0, |s| s.z)
    }

    /// Number of beam slices N = round(length / slice_length).
    pub fn slice_count(&self) -> usize {
        let n = (self.length() / self.slice_length).round();
        if n.is_finite() && n >= 1.0 {
            (n as usize).min(SLICE_COUNT_RANGE.1)
        } else {
            1
        }
    }

    /// The slice thickness actually used, length / N, m.
    pub fn actual_slice_length(&self) -> f64 {
        self.length() / self.slice_count() as f64
    }

    /// Outer and inner radius at `z` (linear between stations, clamped to the ends), m.
    pub fn radii_at(&self, z: f64) -> (f64, f64) {
        let st = &self.stations;
        let Some(first) = st.first() else { return (0.0, 0.0) };
        if z <= first.z {
            return (first.outer_radius, first.inner_radius);
        }
        let k = st.partition_point(|s| s.z <= z);
        if k >= st.len() {
            let last = st[st.len() - 1];
            return (last.outer_radius, last.inner_radius);
        }
        let (a, b) = (st[k - 1], st[k]);
        let t = (z - a.z) / (b.z - a.z);
        (a.outer_radius + t * (b.outer_radius - a.outer_radius), a.inner_radius + t * (b.inner_radius - a.inner_radius))
    }

    /// (centre z, outer radius, inner radius) of every slice.
    fn slices_raw(&self) -> Vec<(f64, f64, f64)> {
        let n = self.slice_count();
        let dz = self.actual_slice_length();
        (0..n)
            .map(|i| {
                let z = (i as f64 + 0.5) * dz;
                let (ro, ri) = self.radii_at(z);
                (z, ro, ri)
            })
            .collect()
    }

    /// The discretised slices (knob first), each with its composite section properties.
    pub fn slices(&self) -> Vec<Slice> {
        let dz = self.actual_slice_length();
        let pi = std::f64::consts::PI;
        self.slices_raw()
            .into_iter()
            .map(|(z, ro, ri)| {
                let shell_area = pi * (ro * ro - ri * ri);
                let shell_i = pi * (ro.powi(4) - ri.powi(4)) / 4.0;
                let m = &self.shell;
                let mut s = Slice {
                    z,
                    mass: m.density * shell_area * dz,
                    rotary_inertia: m.density * shell_i * dz,
                    bending_stiffness: m.youngs_modulus * shell_i,
                    shear_stiffness: m.shear_modulus * shell_area,
                };
                if let Some(core) = &self.core {
                    if ri > 0.0 && z >= core.z_start && z <= core.z_end {
                        let area = pi * ri * ri;
                        let i = pi * ri.powi(4) / 4.0;
                        let c = &core.material;
                        s.mass += c.density * area * dz;
                        s.rotary_inertia += c.density * i * dz;
                        s.bending_stiffness += c.youngs_modulus * i;
                        s.shear_stiffness += c.shear_modulus * area;
                    }
                }
                s
            })
            .collect()
    }

    /// Rigid-body mass properties, summed over the slices: M = Σm, z_cm = Σm z / M,
    /// I_cm = Σm (z − z_cm)² + ΣJ (exactly the inertia of the beam model's rigid modes).
    pub fn mass_properties(&self) -> MassProperties {
        mass_properties_of(&self.slices(), self.length())
    }
}

/// Mass properties of a set of slices (see [`Bat::mass_properties`]).
pub(crate) fn mass_properties_of(slices: &[Slice], length: f64) -> MassProperties {
    let mass: f64 = slices.iter().map(|s| s.mass).sum();
    if !(mass > 0.0) {
        return MassProperties {
            mass: 0.0,
            length,
            center_of_mass: 0.0,
            moment_of_inertia: 0.0,
            radius_of_gyration: 0.0,
        };
    }
    let zcm = slices.iter().map(|s| s.mass * s.z).sum::<f64>() / mass;
    let icm: f64 = slices.iter().map(|s| s.mass * (s.z - zcm).powi(2) + s.rotary_inertia).sum();
    MassProperties::from_totals(mass, length, zcm, icm)
}

/// Length of the alloy profile, m.
const ALLOY_LENGTH: f64 = 0.81;
/// Slice length of the alloy profile, m.
const ALLOY_SLICE: f64 = 0.01;
/// Handle wall of `aluminum`, m (solved offline with the barrel wall and end cap for Table 2's mass
/// properties; see [`Bat::aluminum`]).
const ALLOY_HANDLE_WALL: f64 = 0.003_122_543_377;
/// Outer radius of the alloy barrel, m (2⅝ in).
const ALLOY_BARREL_RADIUS: f64 = 2.625 / 2.0 * INCH;
/// Outer radius of the alloy handle, m (1 in).
const ALLOY_HANDLE_RADIUS: f64 = 0.5 * INCH;

/// Stations of the alloy profile (see [`Bat::aluminum`]) with the given barrel and handle walls (m) and a
/// solid end-cap plug of `end_cap_mass` kg of the shell alloy filling the bore from the barrel end inward.
fn alloy_stations(barrel_wall: f64, handle_wall: f64, end_cap_mass: f64) -> Result<Vec<Station>, PhysicsError> {
    const KNOB_RADIUS: f64 = 0.85 * INCH;
    const TAPER_START: f64 = 0.28;
    const TAPER_END: f64 = 0.50;
    // Solved offline (see `Bat::aluminum`); not tuned beyond Table 2's three numbers.
    const END_CAP_INNER_RADIUS: f64 = 0.029_837_307_136;
    if !(barrel_wall.is_finite() && barrel_wall > 0.0 && barrel_wall < ALLOY_BARREL_RADIUS) {
        return Err(PhysicsError::out_of_range(
            "barrel_wall",
            barrel_wall,
            format!("0 < barrel_wall < {ALLOY_BARREL_RADIUS} m (the barrel's outer radius)"),
        ));
    }
    if !(handle_wall.is_finite() && handle_wall > 0.0 && handle_wall < ALLOY_HANDLE_RADIUS) {
        return Err(PhysicsError::out_of_range(
            "handle_wall",
            handle_wall,
            format!("0 < handle_wall < {ALLOY_HANDLE_RADIUS} m (the handle's outer radius)"),
        ));
    }
    let n = (ALLOY_LENGTH / ALLOY_SLICE).round() as usize;
    let section = |z: f64| -> (f64, f64) {
        let t = ((z - TAPER_START) / (TAPER_END - TAPER_START)).clamp(0.0, 1.0);
        let outer = ALLOY_HANDLE_RADIUS + (ALLOY_BARREL_RADIUS - ALLOY_HANDLE_RADIUS) * t;
        let wall = handle_wall + (barrel_wall - handle_wall) * t;
        (outer, outer - wall)
    };
    let mut radii: Vec<(f64, f64, f64)> = (0..n)
        .map(|i| {
            let z = (i as f64 + 0.5) * ALLOY_SLICE;
            let (outer, inner) = section(z);
            if i == 0 {
                (z, KNOB_RADIUS, 0.0)
            } else if i == n - 1 {
                (z, outer, END_CAP_INNER_RADIUS.min(inner))
            } else {
                (z, outer, inner)
            }
        })
        .collect();
    // The plug: each slice from the end takes what its bore holds, ρπr_i²Δz, until the plug's mass is placed;
    // the last slice it reaches keeps the bore r with ρπ(r_i² − r²)Δz = what is left.
    let per_area = Material::ALUMINUM.density * std::f64::consts::PI * ALLOY_SLICE;
    let mut left = end_cap_mass.max(0.0);
    for slice in radii.iter_mut().rev() {
        if !(left > 0.0) {
            break;
        }
        let capacity = per_area * slice.2 * slice.2;
        if left >= capacity {
            slice.2 = 0.0;
            left -= capacity;
        } else {
            slice.2 = (slice.2 * slice.2 - left / per_area).max(0.0).sqrt();
            left = 0.0;
        }
    }
    if !end_cap_mass.is_finite() || left > 0.0 {
        return Err(PhysicsError::out_of_range("end_cap_mass", end_cap_mass, "0 ≤ end_cap_mass ≤ the bore's capacity"));
    }
    let mut stations = Vec::with_capacity(n + 2);
    let first = radii[0];
    stations.push(Station { z: 0.0, outer_radius: first.1, inner_radius: first.2 });
    stations.extend(radii.iter().map(|&(z, outer_radius, inner_radius)| Station { z, outer_radius, inner_radius }));
    let last = radii[n - 1];
    stations.push(Station { z: ALLOY_LENGTH, outer_radius: last.1, inner_radius: last.2 });
    Ok(stations)
}

/// Mass (kg) and swing weight (moment of inertia about the 6-in pivot, kg·m²) of the alloy profile.
fn alloy_inertia(barrel_wall: f64, handle_wall: f64, end_cap_mass: f64) -> Result<(f64, f64), PhysicsError> {
    let bat = Bat::new(
        "solve",
        alloy_stations(barrel_wall, handle_wall, end_cap_mass)?,
        Material::ALUMINUM,
        None,
        ALLOY_SLICE,
    )?;
    let mp = bat.mass_properties();
    Ok((mp.mass, mp.moment_about(PIVOT_Z)))
}

/// Bisection of an increasing `f` for `f(x) = target` on [lo, hi]; `None` if the target is outside.
fn bisect(
    mut lo: f64,
    mut hi: f64,
    target: f64,
    f: impl Fn(f64) -> Result<f64, PhysicsError>,
) -> Result<Option<f64>, PhysicsError> {
    // A target met at an end to rounding (the `aluminum` wall itself, with no plug) is met there.
    let slack = 1e-12 * target.abs();
    let (at_lo, at_hi) = (f(lo)?, f(hi)?);
    if at_lo > target + slack || at_hi < target - slack {
        return Ok(None);
    }
    if at_lo >= target {
        return Ok(Some(lo));
    }
    // 64 halvings take any bracket here below the rounding of its ends.
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if f(mid)? < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(Some(0.5 * (lo + hi)))
}

/// Handle wall (m) and end-cap plug mass (kg) that give the alloy profile with `barrel_wall` (m) the mass
/// and swing weight of `target` (see [`Bat::alloy_weight_matched`]).
fn alloy_weight_match(barrel_wall: f64, target: &MassProperties) -> Result<(f64, f64), PhysicsError> {
    let goal_mass = target.mass;
    let goal_weight = target.moment_about(PIVOT_Z);
    let (thinnest, thickest) = (1e-4, ALLOY_HANDLE_RADIUS - 1e-4);
    let refuse = || {
        PhysicsError::out_of_range(
            "barrel_wall",
            barrel_wall,
            format!(
                "a wall whose bat can be brought to {goal_mass:.3} kg and a swing weight of {goal_weight:.4} kg·m² \
                 by its handle wall and end-cap plug (up to about {ALUMINUM_BARREL_WALL} m)"
            ),
        )
    };
    // The handle wall giving the goal mass with a plug of `plug` kg.
    let handle_for = |plug: f64| -> Result<Option<f64>, PhysicsError> {
        bisect(thinnest, thickest, goal_mass, |h| alloy_inertia(barrel_wall, h, plug).map(|(m, _)| m))
    };
    // The largest plug the end slices hold while the mass can still be met: bounded by the goal mass itself.
    let plug_max = (goal_mass - alloy_inertia(barrel_wall, thinnest, 0.0)?.0).max(0.0);
    let weight_at = |plug: f64| -> Result<f64, PhysicsError> {
        match handle_for(plug)? {
            Some(h) => alloy_inertia(barrel_wall, h, plug).map(|(_, w)| w),
            None => Ok(f64::INFINITY),
        }
    };
    let plug = bisect(0.0, plug_max, goal_weight, weight_at)?.ok_or_else(refuse)?;
    let handle = handle_for(plug)?.ok_or_else(refuse)?;
    Ok((handle, plug))
}
