//! The model side of each validation row: every case simulates the measurement's conditions through the public
//! physics API and the presets only (`Bat::preset`, `Ball::preset`, `collide`, `collide_oblique`, `metrics`,
//! `batter`), so a change of the ball, the spin or the trampoline flows into the rows without edits here.
//!
//! Swings: "the average MLB swing" is [`Batter::typical`] on the R161 (Statcast's 71.5 mph 6 in from the head,
//! turning about the knob); another bat is swung by that batter at equal effort ([`Batter::predict`]).
//! A tee test turns the bat about its knob at the stated speed of the impact point, 6 in from the barrel end.
//! A rigid, immovable wall or cylinder is a solid cylinder of 10⁵ kg/m³ and 10¹³ Pa integrated with its rigid
//! modes only (no vibration): its recoil factor m/M is below 10⁻⁴.

use std::sync::{Arc, Mutex, OnceLock};

use rayon::prelude::*;

use sweetspot_physics::batter::{Batter, ReferenceSwing};
use sweetspot_physics::metrics::{bbcor_report, besr_scan, linspace, sweep, sweet_spots};
use sweetspot_physics::oblique::{rad_per_s_to_rpm, rpm_to_rad_per_s, ObliqueImpact, TangentialContact};
use sweetspot_physics::oblique3d::{collide_spatial, SpatialImpact};
use sweetspot_physics::{
    collide, collide_oblique, Ball, Bat, CollisionOptions, CollisionResult, Impact, Material, ModeSet, PhysicsError,
    Station,
};

use super::trackman::PitchMedians;
use super::ValidateError;

pub use sweetspot_physics::units::{INCH, MPH};
/// The usual impact point and the swing's reference point: 6 in from the barrel end, m.
pub const SIX_INCHES: f64 = 6.0 * INCH;

/// What a case computed: the number compared, and a short account of where and how.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseValue {
    /// The model's number in the case's unit; `None` when the model has no such output here.
    pub value: Option<f64>,
    /// Where and how it was computed.
    pub detail: String,
}

/// One point of a model curve used in figures (x, y).
pub type Curve = Vec<(f64, f64)>;

/// The BPF of one alloy wall.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BpfPoint {
    /// Barrel wall, m.
    pub wall: f64,
    /// Hoop frequency 6 in from the barrel end, Hz.
    pub hoop_hz: f64,
    /// BBCOR at the BPF test speed (best spot 3–9 in from the end).
    pub bbcor: f64,
    /// BPF = BBCOR / the ball's COR against a rigid wall at the same speed.
    pub bpf: f64,
    /// Exit speed of the game ball, m/s, hit 6 in from the end by the average MLB batter swinging this bat at
    /// equal effort, pitch at [`SWING_PITCH_SPEED`].
    pub swing_exit_speed: f64,
}

/// A swing at equal effort with one alloy wall, the bat held at `aluminum`'s mass and swing weight
/// ([`Bat::alloy_weight_matched`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SwingPoint {
    /// Barrel wall, m.
    pub wall: f64,
    /// Hoop frequency 6 in from the barrel end, Hz.
    pub hoop_hz: f64,
    /// Exit speed of the game ball hit 6 in from the end by the average MLB batter at equal effort, m/s.
    pub exit_speed: f64,
    /// The same swing's exit speed on a rigid bat of the same mass properties (the closed form), m/s: the
    /// exit speed less the wall's and the beam's share.
    pub rigid_exit_speed: f64,
}

/// Pitch speed of the swings in the BPF sweep, m/s (89.5 mph).
pub const SWING_PITCH_SPEED: f64 = 40.0;

/// The best point of a bat in the cage comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CagePoint {
    /// Largest exit speed, m/s.
    pub best_exit_speed: f64,
    /// Its distance from the barrel end, m.
    pub best_from_end: f64,
}

/// The model laboratory: collision options and results shared by several rows (computed once).
pub struct Lab {
    /// Numerical options of every collision with a real bat.
    pub options: CollisionOptions,
    /// The `Ball::preset` of the game ball (every game swing, tee test and the game ball's rows).
    pub game_ball: String,
    /// The tangential contact law of every oblique row (the default law unless `sweetspot validate` is told
    /// otherwise).
    pub contact: TangentialContact,
    bpf: Memo<(String, u64), Vec<BpfPoint>>,
    cage: Memo<(String, String, u64), CageComparison>,
    /// The weight-matched swing curve (takes no arguments, so one result).
    matched: OnceLock<Vec<SwingPoint>>,
}

/// One spatial game swing at a launch angle: the swing's speed scale and what the ball does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialGamePoint {
    /// The swing's speed as a multiple of the average MLB swing.
    pub scale: f64,
    /// Launch angle, deg.
    pub launch_deg: f64,
    /// Exit speed, mph.
    pub exit_speed_mph: f64,
    /// Total spin, rpm (what a radar reports).
    pub total_spin_rpm: f64,
    /// Backspin, rpm.
    pub backspin_rpm: f64,
    /// Sidespin, rpm (positive toward the left-field side).
    pub sidespin_rpm: f64,
    /// Spray angle, deg (positive toward right field).
    pub spray_deg: f64,
    /// The swing's direction, deg (positive toward right field).
    pub direction_deg: f64,
}

impl SpatialGamePoint {
    /// The point at spray angle `spray` deg, interpolated linearly between the points (sorted by spray) that
    /// bracket it; `None` outside their range.
    pub fn at_spray(points: &[SpatialGamePoint], spray: f64) -> Option<SpatialGamePoint> {
        points.windows(2).find_map(|w| {
            let (p0, p1) = (w[0], w[1]);
            (p0.spray_deg <= spray && spray <= p1.spray_deg && p1.spray_deg > p0.spray_deg).then(|| {
                let t = (spray - p0.spray_deg) / (p1.spray_deg - p0.spray_deg);
                let mix = |a: f64, b: f64| a + (b - a) * t;
                SpatialGamePoint {
                    scale: p0.scale,
                    launch_deg: p0.launch_deg,
                    exit_speed_mph: mix(p0.exit_speed_mph, p1.exit_speed_mph),
                    total_spin_rpm: mix(p0.total_spin_rpm, p1.total_spin_rpm),
                    backspin_rpm: mix(p0.backspin_rpm, p1.backspin_rpm),
                    sidespin_rpm: mix(p0.sidespin_rpm, p1.sidespin_rpm),
                    spray_deg: spray,
                    direction_deg: mix(p0.direction_deg, p1.direction_deg),
                }
            })
        })
    }
}

/// The cage comparison of a wood and a metal bat: their best points, then their exit-speed curves.
pub type CageComparison = (CagePoint, CagePoint, Curve, Curve);

/// Results computed once per distinct arguments (several rows and figures share one BPF sweep or cage
/// comparison; a call with other arguments computes its own).
struct Memo<K, V> {
    done: Mutex<Vec<(K, Arc<V>)>>,
}

impl<K: PartialEq, V> Default for Memo<K, V> {
    fn default() -> Self {
        Memo { done: Mutex::new(Vec::new()) }
    }
}

impl<K: PartialEq, V> Memo<K, V> {
    /// The result for `key`: the one computed before, or `compute`'s (kept unless it failed). Computed
    /// outside the lock (it runs in parallel itself); a result another thread kept first wins.
    fn get_or_try<E>(&self, key: K, compute: impl FnOnce() -> Result<V, E>) -> Result<Arc<V>, E> {
        let find = |done: &[(K, Arc<V>)], key: &K| done.iter().find(|(k, _)| k == key).map(|(_, v)| Arc::clone(v));
        if let Some(v) = find(&self.done.lock().unwrap_or_else(|e| e.into_inner()), &key) {
            return Ok(v);
        }
        let value = Arc::new(compute()?);
        let mut done = self.done.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(v) = find(&done, &key) {
            return Ok(v);
        }
        done.push((key, Arc::clone(&value)));
        Ok(value)
    }
}

fn physics(case: &str) -> impl Fn(PhysicsError) -> ValidateError + '_ {
    move |source| ValidateError::Physics { case: case.to_string(), source }
}

fn modes_of(bat: &Bat, options: &CollisionOptions) -> Result<ModeSet, PhysicsError> {
    ModeSet::compute(bat, options.modes.max(2))
}

/// An immovable rigid cylinder of `radius` and `length` (m): 10⁵ kg/m³, 10¹³ Pa.
fn rigid_cylinder(radius: f64, length: f64) -> Result<ModeSet, PhysicsError> {
    let heavy = Material { density: 1.0e5, youngs_modulus: 1.0e13, shear_modulus: 1.0e13 };
    let stations = vec![
        Station { z: 0.0, outer_radius: radius, inner_radius: 0.0 },
        Station { z: length, outer_radius: radius, inner_radius: 0.0 },
    ];
    let bat = Bat::new("rigid cylinder", stations, heavy, None, length / 20.0)?;
    ModeSet::compute(&bat, 2)
}

/// Rigid-modes-only options with `time_step` (the immovable bodies have no vibration to integrate).
fn rigid_options(time_step: f64) -> CollisionOptions {
    CollisionOptions { modes: 0, time_step }
}

/// The ball's COR against an immovable rigid wall at `speed` (m/s): the effective COR of a head-on impact at
/// the centre of a massive rigid cylinder.
pub fn wall_cor(ball: &Ball, speed: f64, time_step: f64) -> Result<f64, PhysicsError> {
    let wall = rigid_cylinder(0.2, 0.3)?;
    let cm = wall.mass_properties().center_of_mass;
    let impact = Impact { ball_speed: speed, bat_cm_speed: 0.0, bat_angular_speed: 0.0, impact_z: cm };
    Ok(collide(&wall, ball, &impact, &rigid_options(time_step))?.effective_cor)
}

/// Largest effective COR of a bat at rest hit at `speed` (m/s), over 3–9 in from the barrel end in 0.5-in steps.
fn best_cor_at_rest(modes: &ModeSet, ball: &Ball, speed: f64, options: &CollisionOptions) -> Result<f64, PhysicsError> {
    let length = modes.length();
    (0..13)
        .map(|i| length - (9.0 - 0.5 * i as f64) * INCH)
        .map(|impact_z| {
            let impact = Impact { ball_speed: speed, bat_cm_speed: 0.0, bat_angular_speed: 0.0, impact_z };
            collide(modes, ball, &impact, options).map(|r| r.effective_cor)
        })
        .try_fold(f64::NEG_INFINITY, |best, cor| cor.map(|c| best.max(c)))
}

impl Lab {
    /// A laboratory running collisions with `options`, the game ball being the `game_ball` preset.
    pub fn new(options: CollisionOptions, game_ball: &str) -> Lab {
        Lab {
            options,
            game_ball: game_ball.to_string(),
            contact: TangentialContact::default(),
            bpf: Memo::default(),
            cage: Memo::default(),
            matched: OnceLock::new(),
        }
    }

    fn bat(&self, case: &str, name: &str) -> Result<(Bat, ModeSet), ValidateError> {
        let bat = Bat::preset(name).map_err(physics(case))?;
        let modes = modes_of(&bat, &self.options).map_err(physics(case))?;
        Ok((bat, modes))
    }

    fn ball(&self, case: &str, name: &str) -> Result<Ball, ValidateError> {
        Ball::preset(name).map_err(physics(case))
    }

    /// The average MLB swing given to `modes`' bat at equal effort (the R161 is the reference bat).
    fn typical_swing(
        &self,
        case: &str,
        modes: &ModeSet,
    ) -> Result<sweetspot_physics::batter::SwingPrediction, ValidateError> {
        let (_, reference) = self.bat(case, "r161")?;
        let batter = Batter::typical(reference.mass_properties()).map_err(physics(case))?;
        batter.predict(&modes.mass_properties()).map_err(physics(case))
    }

    /// Collision efficiency e_A at the point of largest exit speed of `bat`, average MLB swing, pitch at
    /// `pitch_speed` m/s.
    pub fn collision_efficiency_sweet_spot(&self, bat: &str, pitch_speed: f64) -> Result<CaseValue, ValidateError> {
        let best = self.best_point_swing("collision_efficiency_sweet_spot", bat, pitch_speed)?;
        Ok(CaseValue { value: Some(best.result.collision_efficiency), detail: best.detail(bat, "") })
    }

    /// Statcast's collision efficiency at the point of largest exit speed: q = (v_exit − v_bat)/(v_pitch + v_bat)
    /// with v_bat the bat's speed 6 in from the head (where Statcast measures it), not at the impact point.
    pub fn statcast_q_sweet_spot(&self, bat: &str, pitch_speed: f64) -> Result<CaseValue, ValidateError> {
        let best = self.best_point_swing("statcast_q_sweet_spot", bat, pitch_speed)?;
        let q = (best.result.exit_speed - best.bat_speed) / (pitch_speed + best.bat_speed);
        Ok(CaseValue { value: Some(q), detail: best.detail(bat, " (Statcast's point)") })
    }

    /// Statcast's q at the point of largest exit speed of the R161 swung about its knob at `bat_speed` m/s 6 in
    /// from the head (where Statcast measures it) against a pitch of `pitch_speed` m/s, with `ball`:
    /// q = (v_exit − v_bat)/(v_pitch + v_bat), and the point's distance from the barrel end, m.
    pub fn statcast_q_max_with(
        &self,
        ball: &Ball,
        bat_speed: f64,
        pitch_speed: f64,
    ) -> Result<(f64, f64), ValidateError> {
        let case = "statcast_q_envelope";
        let (_, modes) = self.bat(case, "r161")?;
        crate::calibrate::statcast::statcast_q_max(&modes, ball, bat_speed, pitch_speed, &self.options)
            .map_err(physics(case))
    }

    /// [`Lab::statcast_q_max_with`] with the game ball.
    pub fn statcast_q_max(&self, bat_speed: f64, pitch_speed: f64) -> Result<CaseValue, ValidateError> {
        let ball = self.ball("statcast_q_envelope", &self.game_ball)?;
        let (q, from_end) = self.statcast_q_max_with(&ball, bat_speed, pitch_speed)?;
        Ok(CaseValue {
            value: Some(q),
            detail: format!(
                "R161 about the knob at {:.1} mph 6 in from the head, `{}` ball, pitch {:.1} mph, best point {:.2} in \
                 from the end",
                bat_speed / MPH,
                self.game_ball,
                pitch_speed / MPH,
                from_end / INCH
            ),
        })
    }

    /// Exit speed against launch − attack angle, as Statcast bins it: the R161 swung about its knob at `bat_speed`
    /// m/s 6 in from the head along a path rising `attack_deg`, struck at its head-on point of largest exit
    /// speed by the game ball at `pitch_speed` m/s descending `descent_deg` with `pitch_spin_rpm` of backspin,
    /// the undercut scanned over ±95 % of the reach (ball + barrel radius). Returns (launch − attack deg, exit
    /// speed mph) in order of undercut, and the point's distance from the barrel end, m.
    pub fn undercut_curve(
        &self,
        bat_speed: f64,
        pitch_speed: f64,
        attack_deg: f64,
        descent_deg: f64,
        pitch_spin_rpm: f64,
    ) -> Result<(Vec<(f64, f64)>, f64), ValidateError> {
        let case = "statcast_exit_undercut";
        let (b, modes) = self.bat(case, "r161")?;
        let ball = self.ball(case, &self.game_ball)?;
        let z6 = modes.length() - SIX_INCHES;
        let swing =
            ReferenceSwing::from_speed_at(modes.mass_properties(), bat_speed, z6, 0.0).map_err(physics(case))?;
        let template = Impact {
            ball_speed: pitch_speed,
            bat_cm_speed: swing.bat_cm_speed,
            bat_angular_speed: swing.bat_angular_speed,
            impact_z: z6,
        };
        let spots = sweet_spots(&modes, &ball, &template, &self.options).map_err(physics(case))?;
        let impact = Impact { impact_z: spots.max_exit_speed_z, ..template };
        let barrel_radius = b.radii_at(impact.impact_z).0;
        let reach = ball.radius + barrel_radius;
        let curve = linspace(-0.95 * reach, 0.95 * reach, 97)
            .par_iter()
            .map(|&undercut| {
                let oblique = ObliqueImpact {
                    undercut,
                    attack_angle: attack_deg.to_radians(),
                    pitch_angle: descent_deg.to_radians(),
                    pitch_spin: rpm_to_rad_per_s(pitch_spin_rpm),
                    ..ObliqueImpact::head_on(impact, barrel_radius)
                };
                collide_oblique(&modes, &ball, &oblique, &self.contact, &self.options)
                    .map(|r| (r.launch_angle_deg() - attack_deg, r.exit_speed / MPH))
                    .map_err(physics(case))
            })
            .collect::<Result<_, _>>()?;
        Ok((curve, modes.length() - impact.impact_z))
    }

    /// The average MLB swing of `bat` at a pitch of `pitch_speed` m/s, struck at its point of largest exit speed.
    fn best_point_swing(&self, case: &str, bat: &str, pitch_speed: f64) -> Result<BestPoint, ValidateError> {
        let (_, modes) = self.bat(case, bat)?;
        let ball = self.ball(case, &self.game_ball)?;
        let swing = self.typical_swing(case, &modes)?;
        let template = swing.impact(pitch_speed);
        let spots = sweet_spots(&modes, &ball, &template, &self.options).map_err(physics(case))?;
        let impact = Impact { impact_z: spots.max_exit_speed_z, ..template };
        let result = collide(&modes, &ball, &impact, &self.options).map_err(physics(case))?;
        Ok(BestPoint { result, bat_speed: swing.bat_speed, from_end: modes.length() - spots.max_exit_speed_z })
    }

    /// The ball's COR against a rigid wall at `speed` m/s.
    pub fn ball_wall_cor(&self, ball: &str, speed: f64) -> Result<CaseValue, ValidateError> {
        let case = "ball_wall_cor";
        let b = self.ball(case, ball)?;
        let cor = wall_cor(&b, speed, self.options.time_step).map_err(physics(case))?;
        Ok(CaseValue {
            value: Some(cor),
            detail: format!("`{ball}` ball at {speed:.2} m/s ({:.1} mph) on a rigid wall", speed / MPH),
        })
    }

    /// BBCOR of `bat` with the `ball` preset.
    pub fn bbcor(&self, bat: &str, ball: &str) -> Result<CaseValue, ValidateError> {
        let case = "bbcor";
        let (_, modes) = self.bat(case, bat)?;
        let b = self.ball(case, ball)?;
        let r = bbcor_report(&modes, &b, &self.options).map_err(physics(case))?;
        Ok(CaseValue {
            value: Some(r.bbcor),
            detail: format!(
                "{bat}, `{ball}` ball, best spot {:.2} in from the end",
                (modes.length() - r.impact_z) / INCH
            ),
        })
    }

    /// Largest exit speed (mph) of `bat` in the NCAA's BESR test with the `ball` preset ([`besr_scan`]).
    pub fn besr_max_exit_mph(&self, bat: &str, ball: &str) -> Result<CaseValue, ValidateError> {
        let case = "besr_max_exit_mph";
        let (_, modes) = self.bat(case, bat)?;
        let b = self.ball(case, ball)?;
        let r = besr_scan(&modes, &b, &self.options).map_err(physics(case))?;
        Ok(CaseValue {
            value: Some(r.exit_speed / MPH),
            detail: format!(
                "{bat}, `{ball}` ball at 70 mph, bat 66 mph 6 in from the end about the 6-in pivot, best point {:.2} in \
                 from the end, BESR {:.4}",
                (modes.length() - r.impact_z) / INCH,
                r.besr
            ),
        })
    }

    /// First bending frequency of `bat`, Hz.
    pub fn first_mode_hz(&self, bat: &str) -> Result<CaseValue, ValidateError> {
        let (_, modes) = self.bat("first_mode_hz", bat)?;
        Ok(CaseValue { value: modes.frequencies_hz().first().copied(), detail: format!("{bat}, free-free") })
    }

    /// Node of the first bending mode nearest the barrel end, inches from the end.
    pub fn first_node_from_end_in(&self, bat: &str) -> Result<CaseValue, ValidateError> {
        let (_, modes) = self.bat("first_node_from_end_in", bat)?;
        let node = modes.nodes(1).into_iter().fold(f64::NAN, f64::max);
        let value = node.is_finite().then(|| (modes.length() - node) / INCH);
        Ok(CaseValue { value, detail: format!("{bat}, node at z = {node:.3} m") })
    }

    /// Hoop frequency of `bat` at `from_end` m from the barrel end, Hz (`None` for a solid section).
    pub fn hoop_frequency_hz(&self, bat: &str, from_end: f64) -> Result<CaseValue, ValidateError> {
        let (_, modes) = self.bat("hoop_frequency_hz", bat)?;
        let z = modes.length() - from_end;
        Ok(CaseValue {
            value: modes.hoop_frequency_at(z),
            detail: format!("{bat}, {:.1} in from the end", from_end / INCH),
        })
    }

    /// Launch angle (deg) and spin (rpm) of `bat` swung about its knob at `bat_speed` (m/s) at the point 6 in
    /// from its end into a ball at rest, over undercuts across the ball.
    pub fn tee_curve(&self, bat: &str, bat_speed: f64) -> Result<Curve, ValidateError> {
        let case = "tee_max_spin_rpm";
        let (b, modes) = self.bat(case, bat)?;
        let ball = self.ball(case, &self.game_ball)?;
        let z = modes.length() - SIX_INCHES;
        let swing = ReferenceSwing::from_speed_at(modes.mass_properties(), bat_speed, z, 0.0).map_err(physics(case))?;
        let impact = Impact {
            ball_speed: 0.0,
            bat_cm_speed: swing.bat_cm_speed,
            bat_angular_speed: swing.bat_angular_speed,
            impact_z: z,
        };
        let rk = b.radii_at(z).0;
        self.oblique_scan(case, &modes, &ball, impact, rk, 0.0, 0.0, 0.0)
    }

    /// (launch deg, spin rpm) over undercuts from 0 to 95 % of the reach (ball + barrel radius), in order.
    #[allow(clippy::too_many_arguments)]
    fn oblique_scan(
        &self,
        case: &str,
        modes: &ModeSet,
        ball: &Ball,
        impact: Impact,
        barrel_radius: f64,
        attack: f64,
        pitch_angle: f64,
        pitch_spin: f64,
    ) -> Result<Curve, ValidateError> {
        let points = self.oblique_points(case, modes, ball, impact, barrel_radius, attack, pitch_angle, pitch_spin)?;
        Ok(points.into_iter().map(|(launch, spin, _)| (launch, spin)).collect())
    }

    /// [`Lab::oblique_scan`] with each point's exit speed: (launch deg, spin rpm, exit speed mph).
    #[allow(clippy::too_many_arguments)]
    fn oblique_points(
        &self,
        case: &str,
        modes: &ModeSet,
        ball: &Ball,
        impact: Impact,
        barrel_radius: f64,
        attack: f64,
        pitch_angle: f64,
        pitch_spin: f64,
    ) -> Result<Vec<(f64, f64, f64)>, ValidateError> {
        let reach = ball.radius + barrel_radius;
        linspace(0.0, 0.95 * reach, 77)
            .par_iter()
            .map(|&undercut| {
                let oblique = ObliqueImpact {
                    undercut,
                    attack_angle: attack,
                    pitch_angle,
                    pitch_spin,
                    ..ObliqueImpact::head_on(impact, barrel_radius)
                };
                collide_oblique(modes, ball, &oblique, &self.contact, &self.options)
                    .map(|r| (r.launch_angle_deg(), r.spin_rpm(), r.exit_speed / MPH))
                    .map_err(physics(case))
            })
            .collect()
    }

    /// Largest spin (rpm) at launch angles 0…`max_launch` deg in a tee test at `bat_speed` m/s.
    pub fn tee_max_spin_rpm(&self, bat: &str, bat_speed: f64, max_launch: f64) -> Result<CaseValue, ValidateError> {
        let curve = self.tee_curve(bat, bat_speed)?;
        let best = curve.iter().filter(|(launch, _)| (0.0..=max_launch).contains(launch)).fold(
            None,
            |acc: Option<(f64, f64)>, &(l, s)| match acc {
                Some((_, best)) if best >= s => acc,
                _ => Some((l, s)),
            },
        );
        Ok(CaseValue {
            value: best.map(|(_, s)| s),
            detail: match best {
                Some((l, _)) => format!("{bat}, {:.0} mph, largest at {l:.1}° launch", bat_speed / MPH),
                None => format!("{bat}: no launch angle in 0–{max_launch}°"),
            },
        })
    }

    /// Launch angle and spin of the game swing (R161, average MLB swing rising `attack` deg) against `pitch`,
    /// over undercuts: the swing the TrackMan rows are compared with.
    pub fn game_curve(&self, pitch: &PitchMedians, attack_deg: f64) -> Result<Curve, ValidateError> {
        let case = "game_spin_rpm";
        let (b, modes) = self.bat(case, "r161")?;
        let ball = self.ball(case, &self.game_ball)?;
        let swing = self.typical_swing(case, &modes)?;
        let impact = swing.impact(pitch.zone_speed_mph * MPH);
        let rk = b.radii_at(impact.impact_z).0;
        self.oblique_scan(
            case,
            &modes,
            &ball,
            impact,
            rk,
            attack_deg.to_radians(),
            (-pitch.vert_appr_angle_deg).to_radians(),
            rpm_to_rad_per_s(pitch.spin_rpm),
        )
    }

    /// Spin (rpm) of the game swing launched at `launch` deg (interpolated along the undercut scan at the first
    /// crossing), or `None` if the swing never launches there. With `exit_speed_mph` (the measured bin's median
    /// exit speed) the typical swing's speed is scaled — centre-of-mass and angular speed alike, the same
    /// batter swinging harder or softer — until the ball launched at `launch` leaves at that speed: the
    /// exports carry no bat data, and batted-ball spin grows with exit speed at a given launch angle, so an
    /// MLB-average swing against summer-collegiate balls would compare different conditions.
    pub fn game_spin_rpm(
        &self,
        pitch: &PitchMedians,
        attack_deg: f64,
        launch: f64,
        exit_speed_mph: Option<f64>,
    ) -> Result<CaseValue, ValidateError> {
        let describe = |scale: f64, exit: Option<f64>| {
            let exit = exit.map(|e| format!(", exit {e:.1} mph")).unwrap_or_default();
            format!(
                "R161, swing rising {attack_deg}° at {scale:.3}× the average MLB swing{exit}, pitch {:.1} mph \
                 descending {:.1}° with {:.0} rpm backspin",
                pitch.zone_speed_mph, -pitch.vert_appr_angle_deg, pitch.spin_rpm
            )
        };
        let Some(target) = exit_speed_mph else {
            let point = self.game_point(pitch, attack_deg, launch, 1.0)?;
            return Ok(CaseValue { value: point.map(|p| p.0), detail: describe(1.0, point.map(|p| p.1)) });
        };
        // The exit speed at a given launch angle rises with the swing's speed: bisect on the scale.
        let (mut lo, mut hi) = (0.3, 1.5);
        let mut found = None;
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            match self.game_point(pitch, attack_deg, launch, mid)? {
                Some((spin, exit)) => {
                    found = Some((mid, spin, exit));
                    if exit < target {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                // Too slow a swing cannot lift the ball to `launch`: go faster.
                None => lo = mid,
            }
        }
        match found {
            Some((scale, spin, exit)) if (exit - target).abs() < 0.05 => {
                Ok(CaseValue { value: Some(spin), detail: describe(scale, Some(exit)) })
            }
            _ => Ok(CaseValue {
                value: None,
                detail: format!("no swing of 0.3–1.5× the average launches at {launch}° with {target:.1} mph"),
            }),
        }
    }

    /// The R161, the game ball and the average MLB swing scaled by `scale` (centre-of-mass and angular speed
    /// alike) against `pitch`, at the swing's impact point.
    fn scaled_game_swing(
        &self,
        case: &str,
        pitch: &PitchMedians,
        scale: f64,
    ) -> Result<(Bat, ModeSet, Ball, Impact), ValidateError> {
        let (b, modes) = self.bat(case, "r161")?;
        let ball = self.ball(case, &self.game_ball)?;
        let swing = self.typical_swing(case, &modes)?;
        let typical = swing.impact(pitch.zone_speed_mph * MPH);
        let impact = Impact {
            bat_cm_speed: scale * typical.bat_cm_speed,
            bat_angular_speed: scale * typical.bat_angular_speed,
            ..typical
        };
        Ok((b, modes, ball, impact))
    }

    /// (spin rpm, exit speed mph) of the typical swing scaled by `scale` launched at `launch` deg (interpolated
    /// along the undercut scan at the first crossing), or `None` if it never launches there.
    fn game_point(
        &self,
        pitch: &PitchMedians,
        attack_deg: f64,
        launch: f64,
        scale: f64,
    ) -> Result<Option<(f64, f64)>, ValidateError> {
        let case = "game_spin_rpm";
        let (b, modes, ball, impact) = self.scaled_game_swing(case, pitch, scale)?;
        let scan = self.oblique_points(
            case,
            &modes,
            &ball,
            impact,
            b.radii_at(impact.impact_z).0,
            attack_deg.to_radians(),
            (-pitch.vert_appr_angle_deg).to_radians(),
            rpm_to_rad_per_s(pitch.spin_rpm),
        )?;
        Ok(scan.windows(2).find_map(|w| {
            let ((l0, s0, e0), (l1, s1, e1)) = (w[0], w[1]);
            ((l0 - launch) * (l1 - launch) <= 0.0 && l1 != l0).then(|| {
                let t = (launch - l0) / (l1 - l0);
                (s0 + (s1 - s0) * t, e0 + (e1 - e0) * t)
            })
        }))
    }

    /// The game swing in three dimensions launched at `launch` deg, over swing directions: the R161 swung by
    /// a right-handed batter along a path rising `attack_deg` with the bat tilted `tilt_deg` (barrel below the
    /// hands), against `pitch`; its speed scaled (centre-of-mass and angular speed alike, as
    /// [`Lab::game_spin_rpm`]) until the ball launched at `launch` by a swing toward centre field leaves at
    /// `exit_speed_mph`; then the swing's direction scanned from −50° to 45° (the undercut set each time so
    /// the ball launches at `launch`). Returns the points in order of spray angle, or `None` if no swing of
    /// 0.3–1.5× the average launches there at that speed.
    pub fn spatial_spray_scan(
        &self,
        pitch: &PitchMedians,
        attack_deg: f64,
        tilt_deg: f64,
        launch: f64,
        exit_speed_mph: f64,
    ) -> Result<Option<Vec<SpatialGamePoint>>, ValidateError> {
        let (mut lo, mut hi) = (0.3, 1.5);
        let mut found = None;
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            match self.spatial_game_point(pitch, attack_deg, tilt_deg, 0.0, launch, mid)? {
                Some(point) => {
                    if point.exit_speed_mph < exit_speed_mph {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                    found = Some(point);
                }
                None => lo = mid,
            }
        }
        let Some(scale) = found.filter(|p| (p.exit_speed_mph - exit_speed_mph).abs() < 0.05).map(|p| p.scale) else {
            return Ok(None);
        };
        let mut points = Vec::new();
        for direction in linspace(-50.0, 45.0, 39) {
            if let Some(point) = self.spatial_game_point(pitch, attack_deg, tilt_deg, direction, launch, scale)? {
                points.push(point);
            }
        }
        points.sort_by(|a, b| a.spray_deg.total_cmp(&b.spray_deg));
        Ok(Some(points))
    }

    /// The spatial game swing scaled by `scale`, launched at `launch` deg (interpolated along the undercut
    /// scan at the first crossing), or `None` if it never launches there.
    fn spatial_game_point(
        &self,
        pitch: &PitchMedians,
        attack_deg: f64,
        tilt_deg: f64,
        direction_deg: f64,
        launch: f64,
        scale: f64,
    ) -> Result<Option<SpatialGamePoint>, ValidateError> {
        let case = "radar_spin_rpm";
        let (b, modes, ball, impact) = self.scaled_game_swing(case, pitch, scale)?;
        let barrel_radius = b.radii_at(impact.impact_z).0;
        let reach = ball.radius + barrel_radius;
        let points: Vec<SpatialGamePoint> = linspace(0.0, 0.95 * reach, 77)
            .par_iter()
            .map(|&undercut| {
                let oblique = ObliqueImpact {
                    undercut,
                    attack_angle: attack_deg.to_radians(),
                    pitch_angle: (-pitch.vert_appr_angle_deg).to_radians(),
                    pitch_spin: rpm_to_rad_per_s(pitch.spin_rpm),
                    ..ObliqueImpact::head_on(impact, barrel_radius)
                };
                let spatial = SpatialImpact {
                    bat_tilt: tilt_deg.to_radians(),
                    swing_direction: direction_deg.to_radians(),
                    ..SpatialImpact::planar(oblique)
                };
                collide_spatial(&modes, &ball, &spatial, &self.contact, &self.options)
                    .map(|r| SpatialGamePoint {
                        scale,
                        launch_deg: r.launch_angle.to_degrees(),
                        exit_speed_mph: r.exit_speed / MPH,
                        total_spin_rpm: rad_per_s_to_rpm(r.total_spin),
                        backspin_rpm: rad_per_s_to_rpm(r.backspin),
                        sidespin_rpm: rad_per_s_to_rpm(r.sidespin),
                        spray_deg: r.spray_angle.to_degrees(),
                        direction_deg,
                    })
                    .map_err(physics(case))
            })
            .collect::<Result<_, _>>()?;
        Ok(points.windows(2).find_map(|w| {
            let (p0, p1) = (w[0], w[1]);
            ((p0.launch_deg - launch) * (p1.launch_deg - launch) <= 0.0 && p1.launch_deg != p0.launch_deg).then(|| {
                let t = (launch - p0.launch_deg) / (p1.launch_deg - p0.launch_deg);
                let mix = |a: f64, b: f64| a + (b - a) * t;
                SpatialGamePoint {
                    scale,
                    launch_deg: launch,
                    exit_speed_mph: mix(p0.exit_speed_mph, p1.exit_speed_mph),
                    total_spin_rpm: mix(p0.total_spin_rpm, p1.total_spin_rpm),
                    backspin_rpm: mix(p0.backspin_rpm, p1.backspin_rpm),
                    sidespin_rpm: mix(p0.sidespin_rpm, p1.sidespin_rpm),
                    spray_deg: mix(p0.spray_deg, p1.spray_deg),
                    direction_deg,
                }
            })
        }))
    }

    /// dΩ_out/dΩ_in for a ball at `ball_speed` m/s on an immovable cylinder of `radius` m, line of centres
    /// `line_deg` from the ball's path, incoming spin ±`spin_rpm`.
    pub fn spin_transfer_fixed_cylinder(
        &self,
        ball_speed: f64,
        radius: f64,
        line_deg: f64,
        spin_rpm: f64,
    ) -> Result<CaseValue, ValidateError> {
        let case = "spin_transfer_fixed_cylinder";
        let ball = self.ball(case, &self.game_ball)?;
        let cylinder = rigid_cylinder(radius, 1.0).map_err(physics(case))?;
        let cm = cylinder.mass_properties().center_of_mass;
        let impact = Impact { ball_speed, bat_cm_speed: 0.0, bat_angular_speed: 0.0, impact_z: cm };
        let undercut = (ball.radius + radius) * line_deg.to_radians().sin();
        let spin_out = |pitch_spin: f64| {
            let oblique = ObliqueImpact { undercut, pitch_spin, ..ObliqueImpact::head_on(impact, radius) };
            collide_oblique(&cylinder, &ball, &oblique, &self.contact, &rigid_options(self.options.time_step))
                .map(|r| r.spin)
                .map_err(physics(case))
        };
        let w = rpm_to_rad_per_s(spin_rpm);
        let slope = (spin_out(w)? - spin_out(-w)?) / (2.0 * w);
        Ok(CaseValue {
            value: Some(slope),
            detail: format!("{:.0} mph, cylinder radius {:.2} in, ±{spin_rpm:.0} rpm", ball_speed / MPH, radius / INCH),
        })
    }

    /// BPF against hoop frequency for the `aluminum` profile with its wall varied from 1.2 to 4 mm, `ball` at
    /// `speed` m/s (computed once per ball and speed).
    pub fn bpf_curve(&self, ball: &str, speed: f64) -> Result<Arc<Vec<BpfPoint>>, ValidateError> {
        self.bpf.get_or_try((ball.to_string(), speed.to_bits()), || self.compute_bpf_curve(ball, speed))
    }

    fn compute_bpf_curve(&self, ball: &str, speed: f64) -> Result<Vec<BpfPoint>, ValidateError> {
        let case = "bpf_hoop_trend";
        let b = self.ball(case, ball)?;
        let ball_cor = wall_cor(&b, speed, self.options.time_step).map_err(physics(case))?;
        let game_ball = self.ball(case, &self.game_ball)?;
        let (_, reference) = self.bat(case, "r161")?;
        let batter = Batter::typical(reference.mass_properties()).map_err(physics(case))?;
        let walls = linspace(1.2e-3, 4.0e-3, 29);
        let points: Vec<BpfPoint> = walls
            .par_iter()
            .map(|&wall| {
                let bat = Bat::alloy_profile("alloy", wall)?;
                let modes = modes_of(&bat, &self.options)?;
                let hoop_hz = modes.hoop_frequency_at(modes.length() - SIX_INCHES).unwrap_or(f64::NAN);
                let bbcor = best_cor_at_rest(&modes, &b, speed, &self.options)?;
                let swing = batter.predict(&modes.mass_properties())?;
                let swing_exit_speed =
                    collide(&modes, &game_ball, &swing.impact(SWING_PITCH_SPEED), &self.options)?.exit_speed;
                Ok(BpfPoint { wall, hoop_hz, bbcor, bpf: bbcor / ball_cor, swing_exit_speed })
            })
            .collect::<Result<_, PhysicsError>>()
            .map_err(physics(case))?;
        Ok(points)
    }

    /// Exit speed at equal effort against hoop frequency for alloy walls from 1.2 mm to `aluminum`'s own, each
    /// bat built to `aluminum`'s mass and swing weight by its handle wall and end-cap plug
    /// ([`Bat::alloy_weight_matched`]), game ball, pitch at [`SWING_PITCH_SPEED`], impact 6 in from the end
    /// (computed once).
    pub fn matched_swing_curve(&self) -> Result<&[SwingPoint], ValidateError> {
        if let Some(points) = self.matched.get() {
            return Ok(points);
        }
        let case = "swing_exit_hoop_trend";
        let game_ball = self.ball(case, &self.game_ball)?;
        let (_, reference) = self.bat(case, "r161")?;
        let batter = Batter::typical(reference.mass_properties()).map_err(physics(case))?;
        let walls = linspace(1.2e-3, sweetspot_physics::bat::ALUMINUM_BARREL_WALL, 24);
        let points: Vec<SwingPoint> = walls
            .par_iter()
            .map(|&wall| {
                let bat = Bat::alloy_weight_matched("alloy", wall)?;
                let modes = modes_of(&bat, &self.options)?;
                let hoop_hz = modes.hoop_frequency_at(modes.length() - SIX_INCHES).unwrap_or(f64::NAN);
                let swing = batter.predict(&modes.mass_properties())?;
                let r = collide(&modes, &game_ball, &swing.impact(SWING_PITCH_SPEED), &self.options)?;
                Ok(SwingPoint { wall, hoop_hz, exit_speed: r.exit_speed, rigid_exit_speed: r.rigid_exit_speed })
            })
            .collect::<Result<_, PhysicsError>>()
            .map_err(physics(case))?;
        Ok(self.matched.get_or_init(|| points))
    }

    /// The cage comparison at equal effort: best exit speed and where, and exit speed against the distance from
    /// the barrel end (in, mph), for `wood` and `metal` at `pitch_speed` m/s (computed once per bats and speed).
    pub fn cage(&self, wood: &str, metal: &str, pitch_speed: f64) -> Result<Arc<CageComparison>, ValidateError> {
        let key = (wood.to_string(), metal.to_string(), pitch_speed.to_bits());
        self.cage.get_or_try(key, || self.compute_cage(wood, metal, pitch_speed))
    }

    fn compute_cage(&self, wood: &str, metal: &str, pitch_speed: f64) -> Result<CageComparison, ValidateError> {
        let case = "cage";
        let ball = self.ball(case, &self.game_ball)?;
        let one = |name: &str| -> Result<(CagePoint, Curve), ValidateError> {
            let (_, modes) = self.bat(case, name)?;
            let swing = self.typical_swing(case, &modes)?;
            let template = swing.impact(pitch_speed);
            let spots = sweet_spots(&modes, &ball, &template, &self.options).map_err(physics(case))?;
            let length = modes.length();
            let zs: Vec<f64> = linspace(0.5 * INCH, 12.0 * INCH, 47).into_iter().map(|d| length - d).collect();
            let points = sweep(&modes, &ball, &template, &zs, &self.options).map_err(physics(case))?;
            let curve = points.iter().map(|p| ((length - p.impact_z) / INCH, p.result.exit_speed / MPH)).collect();
            Ok((
                CagePoint { best_exit_speed: spots.max_exit_speed, best_from_end: length - spots.max_exit_speed_z },
                curve,
            ))
        };
        let (w, wc) = one(wood)?;
        let (m, mc) = one(metal)?;
        Ok((w, m, wc, mc))
    }

    /// Best exit speed of `metal` minus `wood` at equal effort, mph.
    pub fn cage_exit_difference_mph(
        &self,
        wood: &str,
        metal: &str,
        pitch_speed: f64,
    ) -> Result<CaseValue, ValidateError> {
        let cage = self.cage(wood, metal, pitch_speed)?;
        let (w, m, _, _) = &*cage;
        Ok(CaseValue {
            value: Some((m.best_exit_speed - w.best_exit_speed) / MPH),
            detail: format!(
                "best exit {metal} {:.1} mph, {wood} {:.1} mph, {:.1} mph pitch",
                m.best_exit_speed / MPH,
                w.best_exit_speed / MPH,
                pitch_speed / MPH
            ),
        })
    }

    /// Distance of the best point from the barrel end, `metal` minus `wood`, inches.
    pub fn sweet_spot_shift_in(&self, wood: &str, metal: &str, pitch_speed: f64) -> Result<CaseValue, ValidateError> {
        let cage = self.cage(wood, metal, pitch_speed)?;
        let (w, m, _, _) = &*cage;
        Ok(CaseValue {
            value: Some((m.best_from_end - w.best_from_end) / INCH),
            detail: format!(
                "best point {metal} {:.2} in, {wood} {:.2} in from the end",
                m.best_from_end / INCH,
                w.best_from_end / INCH
            ),
        })
    }

    /// Contact time (ms) of the average MLB swing on `bat` at `from_end` m from the end, pitch `pitch_speed` m/s.
    pub fn contact_time_ms(&self, bat: &str, pitch_speed: f64, from_end: f64) -> Result<CaseValue, ValidateError> {
        let case = "contact_time_ms";
        let (_, modes) = self.bat(case, bat)?;
        let ball = self.ball(case, &self.game_ball)?;
        let swing = self.typical_swing(case, &modes)?;
        let impact = swing.impact_at(pitch_speed, modes.length() - from_end);
        let r = collide(&modes, &ball, &impact, &self.options).map_err(physics(case))?;
        Ok(CaseValue {
            value: Some(r.contact_time * 1e3),
            detail: format!("{bat}, {:.1} in from the end, exit {:.1} mph", from_end / INCH, r.exit_speed / MPH),
        })
    }
}

/// Spearman's rank correlation of the pairs (no ties expected; ties take their order of appearance), or `None`
/// with fewer than 3 pairs.
pub fn rank_correlation(pairs: &[(f64, f64)]) -> Option<f64> {
    let n = pairs.len();
    if n < 3 {
        return None;
    }
    let ranks = |key: fn(&(f64, f64)) -> f64| {
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| key(&pairs[a]).total_cmp(&key(&pairs[b])));
        let mut r = vec![0.0; n];
        for (rank, &i) in order.iter().enumerate() {
            r[i] = rank as f64;
        }
        r
    };
    let (rx, ry) = (ranks(|p| p.0), ranks(|p| p.1));
    let d2: f64 = rx.iter().zip(&ry).map(|(a, b)| (a - b) * (a - b)).sum();
    let n = n as f64;
    Some(1.0 - 6.0 * d2 / (n * (n * n - 1.0)))
}

/// One collision at a bat's point of largest exit speed ([`Lab::best_point_swing`]).
struct BestPoint {
    /// The collision there.
    result: CollisionResult,
    /// The swing's bat speed 6 in from the barrel end, m/s.
    bat_speed: f64,
    /// The point's distance from the barrel end, m.
    from_end: f64,
}

impl BestPoint {
    /// How the model got the number, for the row's detail line.
    fn detail(&self, bat: &str, note: &str) -> String {
        format!(
            "{bat}, bat {:.1} mph at 6 in from the end{note}, best point {:.2} in from the end, exit {:.1} mph",
            self.bat_speed / MPH,
            self.from_end / INCH,
            self.result.exit_speed / MPH
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_memo_computes_once_per_key_and_keeps_no_failure() {
        let memo: Memo<u32, u32> = Memo::default();
        let calls = std::cell::Cell::new(0);
        let square = |k: u32| {
            calls.set(calls.get() + 1);
            Ok::<u32, ()>(k * k)
        };
        assert_eq!(*memo.get_or_try(3, || square(3)).unwrap(), 9);
        assert_eq!(*memo.get_or_try(4, || square(4)).unwrap(), 16, "another key computes its own");
        assert_eq!(*memo.get_or_try(3, || square(3)).unwrap(), 9);
        assert_eq!(calls.get(), 2, "a key seen before is not computed again");
        assert_eq!(memo.get_or_try(5, || Err::<u32, ()>(())), Err(()));
        assert_eq!(*memo.get_or_try(5, || square(5)).unwrap(), 25, "a failure is not kept");
    }

    #[test]
    fn the_cage_comparison_follows_its_pitch_speed_on_a_second_call() {
        let lab = Lab::new(CollisionOptions::default(), "mlb");
        let slow = lab.cage("r161", "aluminum", 30.0).unwrap();
        let fast = lab.cage("r161", "aluminum", 40.0).unwrap();
        // A faster pitch leaves the same bat faster (more ball speed to bounce back).
        assert!(fast.0.best_exit_speed > slow.0.best_exit_speed, "{:?} vs {:?}", fast.0, slow.0);
        assert!(Arc::ptr_eq(&slow, &lab.cage("r161", "aluminum", 30.0).unwrap()), "computed once");
    }

    #[test]
    fn rank_correlation_of_monotone_data_is_plus_or_minus_one() {
        let up = [(1.0, 10.0), (2.0, 20.0), (3.0, 25.0), (4.0, 40.0)];
        let down = [(1.0, 4.0), (2.0, 3.0), (3.0, 2.0), (4.0, 1.0)];
        assert_eq!(rank_correlation(&up), Some(1.0));
        assert_eq!(rank_correlation(&down), Some(-1.0));
        assert_eq!(rank_correlation(&up[..2]), None);
    }

    #[test]
    fn a_constant_cor_ball_rebounds_from_the_rigid_wall_with_its_own_cor() {
        // Closed form: a rigid, immovable wall returns e0 exactly (recoil m/M < 1e-4 of the 3.8-t cylinder).
        let ball = Ball { cor: 0.6, ..Ball::default() };
        let cor = wall_cor(&ball, 25.0, 5e-6).unwrap();
        assert!((cor - 0.6).abs() < 2e-3, "{cor}");
    }
}
