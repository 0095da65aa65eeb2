//! The batter: how fast the same effort swings a different bat, and how much time a faster swing buys.
//!
//! # Swing weight
//! The swing weight of a bat is its moment of inertia about an axis 6 in (0.1524 m) from the knob, normal to
//! the swing plane: the pivot of the industry's pendulum test (ASTM F2398, "Standard Test Method for
//! Measuring Moment of Inertia and Center of Percussion of a Baseball or Softball Bat", whose pivot point is
//! 6 in. (152 mm) from the knob end) and of the BBCOR/BESR stands ([`super::metrics::PIVOT_Z`]).
//! I_knob = I_cm + M (z_cm − 0.1524 m)² ([`swing_weight`]).
//!
//! # Swing speed against swing weight (the power law)
//! At maximum effort, the bat speed v of one player falls with the swing weight I as v = C·I^(−n), C a
//! constant of the player, n a constant of the population:
//! - Cross & Bower, "Effects of swing-weight on swing speed and racket power", J. Sports Sci. 24(1), 23–30
//!   (2006): four male students, six rods (three of equal mass whose swing weight differed by large factors,
//!   three of equal swing weight and different mass): **n = 0.27** for I₀ > 0.03 kg·m², C different for
//!   each participant; swing speed nearly independent of mass at fixed swing weight. They quote earlier
//!   results of **n = 0.25 for softball bats** and n = 0.26 for golf clubs.
//! - Fleisig et al. (Sports Eng. 5, 2002), Koenig et al. (Sports Eng. 7, 2004) and Smith, Broker & Nathan
//!   (2003) measured bat speed against bat mass properties for baseball and softball players and found the
//!   moment of inertia, not the mass, to govern it; the exponents they fitted could not be read from the
//!   sources available to this project and are not transcribed here.
//!
//! [`DEFAULT_EXPONENT`] is 0.25 (the softball-bat value quoted by Cross & Bower, the closest population to
//! batters that could be verified); the published values span 0.25–0.27. The model accepts
//! [`EXPONENT_RANGE`] = 0…0.5: n = 0 is a batter whose bat speed ignores the bat (sweetspot's equal-speed
//! comparison), n = ½ is the limit where the batter gives the bat a fixed kinetic energy ½Iω² and none of it
//! goes into his own moving segments; measured players lie between.
//!
//! # The swing's shape
//! A batter is one reference swing (bat centre-of-mass speed V and angular speed ω, measured with a known
//! bat) plus n. For another bat the speed ratio is s = (I_new/I_ref)^(−n) and the swing keeps its shape
//! ([`SwingShape`]):
//! - [`SwingShape::SamePivot`] (default): the bat turns about the same instantaneous centre z_p (m from the
//!   knob, set by the batter's hands and body), and the speed at the batter's usual impact point — the same
//!   distance from the barrel end on every bat — is s times the reference speed there. With v_ref the
//!   reference speed at the reference impact point and δ the shift of the impact point along the bat,
//!   k = s·v_ref/(v_ref + ω_ref δ), ω = k ω_ref, V = k (V_ref + ω_ref (z_cm,new − z_cm,ref)).
//! - [`SwingShape::SameRatio`]: the ratio ω/V is kept, V = s V_ref, ω = s ω_ref; with n = 0 this is exactly
//!   today's equal-speed comparison (the same V and ω for every bat).
//!
//! # Time the batter gains
//! Assumptions: the batter's usual impact point travels an arc of fixed length S (m) from the start of the
//! forward swing to contact with every bat; the same effort gives every bat the same time profile of speed
//! along that arc, only faster or slower (a constant-effort arc); and that profile is uniform acceleration
//! from rest, so the mean speed is half the speed at contact. The swing then lasts T = 2 S / v
//! ([`swing_time`]); a bat swung faster lasts ΔT = T_ref − T less, which is how much later the batter can
//! start the swing for the same contact ([`reaction_time_gained`]), and the pitch travels v_pitch·ΔT
//! meanwhile ([`pitch_travel`]). [`DEFAULT_SWING_LENGTH`] is Statcast's MLB average swing length, 7.3 ft
//! (2.23 m): "the sum distance traveled by the head of the bat in XYZ space from the start of data until
//! contact point" (MLB bat tracking, 2024; the bat head travels a little farther than the impact point
//! 6 in below it, which we neglect). With [`DEFAULT_REFERENCE_SPEED`] (Statcast's 2024 MLB average bat speed
//! 71.5 mph, measured 6 in from the head) this gives T ≈ 0.14 s.

use serde::{Deserialize, Serialize};

use super::metrics::PIVOT_Z;
use super::units::{FOOT, INCH, MPH};
use super::{Impact, MassProperties, PhysicsError};

/// Pivot of the swing-weight measurement, m from the knob (6 in, ASTM F2398).
pub const SWING_WEIGHT_PIVOT_Z: f64 = PIVOT_Z;
/// Default exponent n of v ∝ I^(−n) (softball bats, quoted by Cross & Bower 2006).
pub const DEFAULT_EXPONENT: f64 = 0.25;
/// Accepted exponents n, inclusive: 0 (bat speed ignores the bat) to ½ (fixed kinetic energy of the bat).
pub const EXPONENT_RANGE: (f64, f64) = (0.0, 0.5);
/// Default reference bat speed at the impact point, m/s (Statcast 2024 MLB average, 71.5 mph).
pub const DEFAULT_REFERENCE_SPEED: f64 = 71.5 * MPH;
/// Default distance of the batter's usual impact point from the barrel end, m (6 in, Statcast's sweet spot).
pub const DEFAULT_IMPACT_FROM_BARREL_END: f64 = 6.0 * INCH;
/// Default instantaneous centre of the swing at contact, m from the knob: the knob (the hands).
pub const DEFAULT_PIVOT_Z: f64 = 0.0;
/// Default arc length travelled by the impact point from the start of the swing to contact, m (7.3 ft).
pub const DEFAULT_SWING_LENGTH: f64 = 7.3 * FOOT;
/// Ratio of the speed at contact to the mean speed along the arc (uniform acceleration from rest).
pub const ARC_SPEED_RATIO: f64 = 2.0;
/// Largest bat speed accepted anywhere in the batter model, m/s (well above any human swing).
pub const MAX_BAT_SPEED: f64 = 100.0;

/// How the swing keeps its shape when the batter changes bats.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SwingShape {
    /// The same instantaneous centre of rotation; the speed at the usual impact point scales with s.
    #[default]
    SamePivot,
    /// The same ratio of angular to centre-of-mass speed; both scale with s.
    SameRatio,
}

/// A swing measured with a known bat: the reference of a [`Batter`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ReferenceSwing {
    /// Mass properties of the bat the swing was measured with.
    pub bat: MassProperties,
    /// Bat centre-of-mass speed toward the ball at contact, m/s.
    pub bat_cm_speed: f64,
    /// Bat angular speed at contact, rad/s, positive when the barrel leads.
    pub bat_angular_speed: f64,
}

impl ReferenceSwing {
    /// A swing given by the bat speed `speed` (m/s) at `impact_z` (m from the knob) turning about `pivot_z`.
    pub fn from_speed_at(
        bat: MassProperties,
        speed: f64,
        impact_z: f64,
        pivot_z: f64,
    ) -> Result<ReferenceSwing, PhysicsError> {
        check_bat("reference.bat", &bat)?;
        check_speed("reference bat speed", speed)?;
        check_finite("impact_z", impact_z, "finite, m from the knob")?;
        check_finite("pivot_z", pivot_z, "finite, m from the knob")?;
        let arm = impact_z - pivot_z;
        if !(arm > 0.0) {
            return Err(PhysicsError::out_of_range(
                "pivot_z",
                pivot_z,
                format!("pivot_z < impact_z = {impact_z} m (the pivot must lie on the knob side of the impact)"),
            ));
        }
        let omega = speed / arm;
        let swing =
            ReferenceSwing { bat, bat_cm_speed: omega * (bat.center_of_mass - pivot_z), bat_angular_speed: omega };
        swing.validate()?;
        Ok(swing)
    }

    /// Bat speed at `z` (m from the knob), m/s: V + ω (z − z_cm).
    pub fn speed_at(&self, z: f64) -> f64 {
        self.bat_cm_speed + self.bat_angular_speed * (z - self.bat.center_of_mass)
    }

    /// Checks the bat and both speeds.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        check_bat("reference.bat", &self.bat)?;
        check_finite("reference.bat_cm_speed", self.bat_cm_speed, "finite, m/s")?;
        check_finite("reference.bat_angular_speed", self.bat_angular_speed, "finite, rad/s")?;
        if !(self.bat_cm_speed.abs() <= MAX_BAT_SPEED) {
            return Err(PhysicsError::out_of_range(
                "reference.bat_cm_speed",
                self.bat_cm_speed,
                format!("|V| ≤ {MAX_BAT_SPEED} m/s"),
            ));
        }
        Ok(())
    }
}

/// A batter: a reference swing, the exponent of v ∝ I^(−n), the usual impact point and the swing's arc.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Batter {
    /// The swing measured with a known bat.
    pub reference: ReferenceSwing,
    /// Exponent n of v ∝ I^(−n), dimensionless, in [`EXPONENT_RANGE`].
    pub exponent: f64,
    /// Distance of the usual impact point from the barrel end, m (the same on every bat).
    pub impact_from_barrel_end: f64,
    /// Arc length travelled by the usual impact point from the start of the swing to contact, m.
    pub swing_length: f64,
    /// How the swing keeps its shape on another bat.
    pub shape: SwingShape,
}

/// What a [`Batter`] does with one bat at the effort of the reference swing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SwingPrediction {
    /// Swing weight of the bat (moment of inertia about the 6-in pivot), kg·m².
    pub swing_weight: f64,
    /// s = (I / I_ref)^(−n): the speed ratio to the reference swing, dimensionless.
    pub speed_ratio: f64,
    /// The usual impact point on this bat, m from the knob.
    pub impact_z: f64,
    /// Bat speed at the usual impact point, m/s.
    pub bat_speed: f64,
    /// Bat centre-of-mass speed toward the ball, m/s.
    pub bat_cm_speed: f64,
    /// Bat angular speed, rad/s, positive when the barrel leads.
    pub bat_angular_speed: f64,
    /// Duration of the swing from its start to contact, s (T = 2 S / v).
    pub swing_time: f64,
}

impl SwingPrediction {
    /// The collision input for a ball at `ball_speed` (m/s) meeting this swing at `impact_z` (m from the knob).
    pub fn impact_at(&self, ball_speed: f64, impact_z: f64) -> Impact {
        Impact { ball_speed, bat_cm_speed: self.bat_cm_speed, bat_angular_speed: self.bat_angular_speed, impact_z }
    }

    /// The collision input for a ball at `ball_speed` (m/s) meeting this swing at the usual impact point.
    pub fn impact(&self, ball_speed: f64) -> Impact {
        self.impact_at(ball_speed, self.impact_z)
    }
}

impl Batter {
    /// Builds and validates a batter.
    pub fn new(
        reference: ReferenceSwing,
        exponent: f64,
        impact_from_barrel_end: f64,
        swing_length: f64,
        shape: SwingShape,
    ) -> Result<Batter, PhysicsError> {
        let batter = Batter { reference, exponent, impact_from_barrel_end, swing_length, shape };
        batter.validate()?;
        Ok(batter)
    }

    /// The average MLB batter of Statcast (71.5 mph 6 in from the head, 7.3-ft swing) swinging `bat` about
    /// its knob, with the default exponent.
    pub fn typical(bat: MassProperties) -> Result<Batter, PhysicsError> {
        check_bat("reference.bat", &bat)?;
        let impact_z = bat.length - DEFAULT_IMPACT_FROM_BARREL_END;
        let reference = ReferenceSwing::from_speed_at(bat, DEFAULT_REFERENCE_SPEED, impact_z, DEFAULT_PIVOT_Z)?;
        Batter::new(
            reference,
            DEFAULT_EXPONENT,
            DEFAULT_IMPACT_FROM_BARREL_END,
            DEFAULT_SWING_LENGTH,
            SwingShape::default(),
        )
    }

    /// Checks every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        self.reference.validate()?;
        let (lo, hi) = EXPONENT_RANGE;
        if !(self.exponent >= lo && self.exponent <= hi) {
            return Err(PhysicsError::out_of_range(
                "exponent",
                self.exponent,
                format!("{lo} ≤ n ≤ {hi} (published 0.25–0.27)"),
            ));
        }
        let length = self.reference.bat.length;
        if !(self.impact_from_barrel_end >= 0.0 && self.impact_from_barrel_end < length) {
            return Err(PhysicsError::out_of_range(
                "impact_from_barrel_end",
                self.impact_from_barrel_end,
                format!("0 ≤ d < reference bat length = {length} m"),
            ));
        }
        if !(self.swing_length > 0.0 && self.swing_length <= 10.0) {
            return Err(PhysicsError::out_of_range("swing_length", self.swing_length, "0 < S ≤ 10 m"));
        }
        let speed = self.reference_speed();
        if !(speed > 0.0 && speed <= MAX_BAT_SPEED) {
            return Err(PhysicsError::out_of_range(
                "reference bat speed at the impact point",
                speed,
                format!("0 < v ≤ {MAX_BAT_SPEED} m/s"),
            ));
        }
        Ok(())
    }

    /// The usual impact point on a bat of `length` (m), m from the knob.
    pub fn impact_z_on(&self, length: f64) -> f64 {
        length - self.impact_from_barrel_end
    }

    /// Reference bat speed at the usual impact point of the reference bat, m/s.
    pub fn reference_speed(&self) -> f64 {
        self.reference.speed_at(self.impact_z_on(self.reference.bat.length))
    }

    /// Swing weight of the reference bat, kg·m².
    pub fn reference_swing_weight(&self) -> f64 {
        swing_weight(&self.reference.bat)
    }

    /// The swing this batter gives `bat` at the reference effort (see the module docs).
    pub fn predict(&self, bat: &MassProperties) -> Result<SwingPrediction, PhysicsError> {
        self.validate()?;
        check_bat("bat", bat)?;
        let reference = &self.reference;
        let weight = swing_weight(bat);
        let ratio = speed_ratio(weight, self.reference_swing_weight(), self.exponent)?;
        let impact_z = self.impact_z_on(bat.length);
        if !(impact_z > 0.0) {
            return Err(PhysicsError::out_of_range(
                "bat length",
                bat.length,
                format!("> impact_from_barrel_end = {} m", self.impact_from_barrel_end),
            ));
        }
        let (cm_speed, angular_speed) = match self.shape {
            SwingShape::SameRatio => (ratio * reference.bat_cm_speed, ratio * reference.bat_angular_speed),
            SwingShape::SamePivot => {
                let v_ref = self.reference_speed();
                let shift = impact_z - self.impact_z_on(reference.bat.length);
                let arm_growth = v_ref + reference.bat_angular_speed * shift;
                if !(arm_growth > 0.0) {
                    return Err(PhysicsError::out_of_range(
                        "bat length",
                        bat.length,
                        "a usual impact point on the barrel side of the swing's pivot",
                    ));
                }
                let k = ratio * (v_ref / arm_growth);
                let cm_shift = bat.center_of_mass - reference.bat.center_of_mass;
                (k * (reference.bat_cm_speed + reference.bat_angular_speed * cm_shift), k * reference.bat_angular_speed)
            }
        };
        let bat_speed = cm_speed + angular_speed * (impact_z - bat.center_of_mass);
        Ok(SwingPrediction {
            swing_weight: weight,
            speed_ratio: ratio,
            impact_z,
            bat_speed,
            bat_cm_speed: cm_speed,
            bat_angular_speed: angular_speed,
            swing_time: swing_time(self.swing_length, bat_speed)?,
        })
    }
}

/// Swing weight of a bat, kg·m²: its moment of inertia about the pivot 6 in (0.1524 m) from the knob.
pub fn swing_weight(bat: &MassProperties) -> f64 {
    bat.moment_about(SWING_WEIGHT_PIVOT_Z)
}

/// s = (swing_weight / reference_swing_weight)^(−exponent), dimensionless; both weights in kg·m².
pub fn speed_ratio(swing_weight: f64, reference_swing_weight: f64, exponent: f64) -> Result<f64, PhysicsError> {
    check_positive("swing_weight", swing_weight, "I > 0 kg·m²")?;
    check_positive("reference swing_weight", reference_swing_weight, "I_ref > 0 kg·m²")?;
    let (lo, hi) = EXPONENT_RANGE;
    if !(exponent >= lo && exponent <= hi) {
        return Err(PhysicsError::out_of_range("exponent", exponent, format!("{lo} ≤ n ≤ {hi}")));
    }
    Ok((swing_weight / reference_swing_weight).powf(-exponent))
}

/// Duration of a constant-effort swing, s: T = 2 S / v for an arc of `swing_length` S (m) reaching `bat_speed`
/// v (m/s) at contact after uniform acceleration from rest.
pub fn swing_time(swing_length: f64, bat_speed: f64) -> Result<f64, PhysicsError> {
    check_positive("swing_length", swing_length, "S > 0 m")?;
    if !(bat_speed > 0.0 && bat_speed <= MAX_BAT_SPEED) {
        return Err(PhysicsError::out_of_range(
            "bat speed at the impact point",
            bat_speed,
            format!("0 < v ≤ {MAX_BAT_SPEED} m/s"),
        ));
    }
    Ok(ARC_SPEED_RATIO * swing_length / bat_speed)
}

/// How much later (s) the batter can start the swing of `other` than that of `baseline` for the same contact.
pub fn reaction_time_gained(baseline: &SwingPrediction, other: &SwingPrediction) -> f64 {
    baseline.swing_time - other.swing_time
}

/// Distance (m) a pitch at `pitch_speed` (m/s) travels during `time` (s).
pub fn pitch_travel(time: f64, pitch_speed: f64) -> Result<f64, PhysicsError> {
    check_finite("time", time, "finite, s")?;
    check_positive("pitch_speed", pitch_speed, "v_pitch > 0 m/s")?;
    Ok(pitch_speed * time)
}

fn check_finite(field: &str, value: f64, allowed: &str) -> Result<(), PhysicsError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(PhysicsError::out_of_range(field, value, allowed))
    }
}

fn check_positive(field: &str, value: f64, allowed: &str) -> Result<(), PhysicsError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(PhysicsError::out_of_range(field, value, allowed))
    }
}

fn check_speed(field: &str, value: f64) -> Result<(), PhysicsError> {
    if value.is_finite() && value > 0.0 && value <= MAX_BAT_SPEED {
        Ok(())
    } else {
        Err(PhysicsError::out_of_range(field, value, format!("0 < v ≤ {MAX_BAT_SPEED} m/s")))
    }
}

fn check_bat(field: &str, bat: &MassProperties) -> Result<(), PhysicsError> {
    check_positive(&format!("{field}.mass"), bat.mass, "M > 0 kg")?;
    check_positive(&format!("{field}.length"), bat.length, "L > 0 m")?;
    check_positive(&format!("{field}.moment_of_inertia"), bat.moment_of_inertia, "I_cm > 0 kg·m²")?;
    check_finite(&format!("{field}.center_of_mass"), bat.center_of_mass, "finite, m from the knob")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rod(mass: f64, length: f64) -> MassProperties {
        MassProperties::from_totals(mass, length, length / 2.0, mass * length * length / 12.0)
    }

    #[test]
    fn swing_weight_of_a_thin_rod_matches_the_integral_about_the_pivot() {
        // ∫₀ᴸ (M/L)(z − p)² dz = M ((L − p)³ + p³) / (3L), independent of the parallel-axis form.
        let (m, l, p): (f64, f64, f64) = (0.9, 0.84, 0.1524);
        let expected = m * ((l - p).powi(3) + p.powi(3)) / (3.0 * l);
        assert!((swing_weight(&rod(m, l)) - expected).abs() < 1e-15, "{}", swing_weight(&rod(m, l)));
    }

    #[test]
    fn same_bat_gives_the_same_swing_bit_for_bit_in_both_shapes() {
        let bat = rod(0.9, 0.84);
        let reference = ReferenceSwing { bat, bat_cm_speed: 25.0, bat_angular_speed: 45.0 };
        for shape in [SwingShape::SamePivot, SwingShape::SameRatio] {
            let batter = Batter::new(reference, 0.25, 0.1524, 2.0, shape).unwrap();
            let p = batter.predict(&bat).unwrap();
            assert_eq!(p.speed_ratio, 1.0);
            assert_eq!(p.bat_cm_speed, 25.0);
            assert_eq!(p.bat_angular_speed, 45.0);
        }
    }

    #[test]
    fn bad_inputs_are_typed_errors_naming_the_field() {
        let bat = rod(0.9, 0.84);
        let reference = ReferenceSwing { bat, bat_cm_speed: 25.0, bat_angular_speed: 45.0 };
        let field = |e: PhysicsError| match e {
            PhysicsError::OutOfRange { field, .. } => field,
            other => panic!("unexpected {other:?}"),
        };
        for n in [-0.1, 0.51, f64::NAN] {
            let e = Batter::new(reference, n, 0.1524, 2.0, SwingShape::SamePivot).unwrap_err();
            assert_eq!(field(e), "exponent");
        }
        let e = Batter::new(reference, 0.25, 0.1524, 0.0, SwingShape::SamePivot).unwrap_err();
        assert_eq!(field(e), "swing_length");
        let e = ReferenceSwing::from_speed_at(bat, -3.0, 0.69, 0.0).unwrap_err();
        assert_eq!(field(e), "reference bat speed");
        let e = ReferenceSwing::from_speed_at(bat, 30.0, 0.69, f64::NAN).unwrap_err();
        assert_eq!(field(e), "pivot_z");
        let e = swing_time(2.0, 0.0).unwrap_err();
        assert_eq!(field(e), "bat speed at the impact point");
        let e = pitch_travel(0.01, f64::NAN).unwrap_err();
        assert_eq!(field(e), "pitch_speed");
        let e = speed_ratio(0.0, 0.2, 0.25).unwrap_err();
        assert_eq!(field(e), "swing_weight");
        // A swing that moves the impact point away from the ball cannot be timed.
        let backwards = ReferenceSwing { bat, bat_cm_speed: -5.0, bat_angular_speed: 0.0 };
        assert!(Batter::new(backwards, 0.25, 0.1524, 2.0, SwingShape::SamePivot).is_err());
    }
}
