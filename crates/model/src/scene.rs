//! The swing drawn: one `visualization_msgs/MarkerArray` per answered swing (topic `swing_scene`), built from
//! the answer, the bat's profile and the modes' amplitudes after contact. Pure: no I/O, no clock.
//!
//! # Frame `bat`
//! Origin at the knob; **x** forward (horizontal, from the batter toward the pitcher), **y** up and **z**
//! toward the first-base side (x × y = z, right-handed): the field frame of [`sweetspot_physics::oblique3d`]
//! (forward, left, up) as (x, z, −y). A level bat swung square by a right-handed batter lies along z, from
//! the knob (z = 0) to the barrel end (m, as `BatParams.station_z`), and x, y are the impact plane's f̂ and û
//! of [`sweetspot_physics::oblique`]. Every marker is in this frame, stamped with the swing's stamp, and replaces
//! the previous swing's marker of the same ns and id.
//!
//! # The bat in three dimensions
//! A swing with `bat_tilt` ψ, `swing_direction` δ or a left-handed batter draws the bat where the 3-D model
//! ([`sweetspot_physics::oblique3d`]) puts it: its long axis â = (−cos ψ sin δ′, −sin ψ, cos ψ cos δ′) for a level
//! path (in general the model's â, perpendicular to the path), δ′ the direction of the right-handed swing
//! whose mirror image it is. The markers below are drawn in the bat's own axes — f̂ the horizontal across the
//! bat (ẑ × â, normalised), û = â × f̂ and â, each a field vector — and placed by them; the ball sits on the
//! model's line of centres, at the angle β from f̂ in the plane across the bat. A left-handed batter's scene is
//! the mirror image (z → −z) of the right-handed swing at −δ. The arrows are drawn from the answer in the field
//! frame. The level, square right-handed swing is drawn exactly as the planar scene always was.
//!
//! # Markers (namespace, id)
//! - `bat_outline` 0 and 1: LINE_STRIPs of the bat's silhouette in the x–z and y–z planes: the outer radius
//!   at every profile station, out along +x (+y) from knob to barrel end and back along −x (−y), closed.
//! - `ball` 0: SPHERE of the ball's diameter at contact: at impact_z, its centre R + R_k from the axis along
//!   the line of centres, β = attack_angle + asin(undercut / (R + R_k)) above x (β = 0 head-on).
//! - `exit_velocity` 0: ARROW from the ball's centre at the answer's launch angle above x, in the x–y plane,
//!   [`ARROW_METRES_PER_MPS`] m long per m/s of exit speed.
//! - `deflection x20` 0: LINE_STRIP of the bat's centre line after contact, exaggerated [`DEFLECTION_SCALE`]
//!   times, at every slice centre of the modal model (plus the two ends): S·d(z)·n̂ + z·ẑ, n̂ = (cos β, sin β).
//!   d(z) = Σₙ aₙ Yₙ(z) over the integrated vibrational modes, Yₙ the mass-normalised shape and aₙ the mode's
//!   ringing amplitude after the ball has left, |aₙ| = √(2 Eₙ)/ωₙ (Eₙ, ωₙ = 2π fₙ of ModalEnergies), signed as
//!   the ball's push drives it: aₙ Yₙ(impact_z) ≤ 0, each mode swinging first away from the ball under the
//!   impact point. It is each mode at its peak (the impulse response's phase), not one instant of the motion.
//! - `label` 0: TEXT_VIEW_FACING above the ball, four short lines [`TEXT_LINE_HEIGHT`] tall: swing and bat,
//!   impact point, exit speed and launch angle, and the exaggeration.
//! - `spin_axis` 0: ARROW through the ball's centre along the spin vector ω (right-hand rule: the arrow
//!   points along the axis the ball turns about, counter-clockwise seen from its head), centred on the ball,
//!   [`SPIN_ARROW_METRES_PER_RPM`] m long per rpm of total spin. ω = backspin b̂ + sidespin ŵ + gyro v̂ from
//!   the answer (b̂ = ĥ × ẑ, ŵ = b̂ × v̂, v̂ the exit direction at launch and spray angle, ĥ its heading).
//! - `spin_axis` 1: TEXT_VIEW_FACING beyond the arrow's head: total spin in rpm and the spin axis as
//!   TrackMan's HitSpinAxis in degrees and on the clock face ([`spin_axis_clock`]).

use nalgebra::{Matrix3, Vector3 as Vec3};
use sweetspot_msgs::builtin_interfaces::msg::Duration;
use sweetspot_msgs::geometry_msgs::msg::{Point, Pose, Quaternion, Vector3};
use sweetspot_msgs::std_msgs::msg::{ColorRGBA, Header};
use sweetspot_msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies};
use sweetspot_msgs::visualization_msgs::msg::{Marker, MarkerArray};
use sweetspot_physics::oblique3d::ContactFrame;
use sweetspot_physics::{Bat, BatterSide, ModeSet};

/// Frame id of every marker.
pub const FRAME_ID: &str = "bat";
/// How many times the bat's deflection is exaggerated in the drawing.
pub const DEFLECTION_SCALE: f64 = 20.0;
/// Namespace of the deflection marker (states the exaggeration).
pub const DEFLECTION_NS: &str = "deflection x20";
/// Length of the exit-velocity arrow per m/s of exit speed, m (40 m/s → 0.4 m).
pub const ARROW_METRES_PER_MPS: f64 = 0.01;
/// Width of the outline and deflection lines, m.
pub const LINE_WIDTH: f64 = 0.002;
/// Length of the spin arrow per rpm of total spin, m (2,000 rpm → 0.2 m, the size of the exit arrow).
pub const SPIN_ARROW_METRES_PER_RPM: f64 = 1e-4;
/// Height of a line of the scene's labels, m: ~15 px in a 3D panel a few hundred pixels tall framing the bat.
pub const TEXT_LINE_HEIGHT: f64 = 0.04;
/// Namespace of the spin arrow and its label.
pub const SPIN_NS: &str = "spin_axis";

/// What a scene is drawn from.
#[derive(Debug, Clone, Copy)]
pub struct SceneInput<'a> {
    /// The swing's answer (status OK): impact_z, exit speed, launch angle, header.
    pub answer: &'a ExitVelocity,
    /// Its ModalEnergies: energy and frequency of each integrated vibrational mode.
    pub energies: &'a ModalEnergies,
    /// The bat (its profile).
    pub bat: &'a Bat,
    /// The bat's modes (their shapes).
    pub modes: &'a ModeSet,
    /// The ball's radius, m.
    pub ball_radius: f64,
    /// The swing's undercut, m (0 head-on).
    pub undercut: f64,
    /// The swing's attack angle, rad (0 head-on).
    pub attack_angle: f64,
    /// The bat's tilt below the horizontal at contact (barrel below the hands positive), rad (0 level).
    pub bat_tilt: f64,
    /// The horizontal direction of the bat's path, rad, positive toward right field (0 toward centre field).
    pub swing_direction: f64,
    /// The batter's side.
    pub batter_side: BatterSide,
}

/// A field-frame vector (forward, left, up) in frame `bat` (forward, up, first-base side).
pub fn field_to_scene(v: Vec3<f64>) -> Vec3<f64> {
    Vec3::new(v.x, v.z, -v.y)
}

/// Where the bat lies: the angle β of the line of centres from f̂ in the plane across the bat, and the map
/// from the bat's own axes (f̂, û, â) to frame `bat`, `None` for the level, square right-handed bat (whose own
/// axes are the frame's, so its scene is drawn with no arithmetic on top of the planar one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// The line of centres' angle from f̂ toward û, rad.
    pub beta: f64,
    /// Columns: f̂, û, â in frame `bat` (mirrored for a left-handed batter).
    pub axes: Option<Matrix3<f64>>,
}

/// The bat's placement for `input` (see the module docs).
pub fn placement(input: &SceneInput<'_>) -> Placement {
    let left = input.batter_side == BatterSide::Left;
    if input.bat_tilt == 0.0 && input.swing_direction == 0.0 && !left {
        return Placement { beta: line_of_centres_angle(input), axes: None };
    }
    let reach = input.ball_radius + input.bat.radii_at(input.answer.impact_z).0;
    let phi = (input.undercut / reach).asin();
    // A left-handed swing is the mirror image of the right-handed one in the opposite direction.
    let direction = if left { -input.swing_direction } else { input.swing_direction };
    let frame = ContactFrame::new(input.attack_angle, direction, input.bat_tilt, phi);
    let axis = frame.axis;
    let across = Vec3::z().cross(&axis).normalize();
    let up = axis.cross(&across);
    let beta = frame.normal.dot(&up).atan2(frame.normal.dot(&across));
    let mirror = |v: Vec3<f64>| if left { Vec3::new(v.x, v.y, -v.z) } else { v };
    let column = |v: Vec3<f64>| mirror(field_to_scene(v));
    Placement { beta, axes: Some(Matrix3::from_columns(&[column(across), column(up), column(axis)])) }
}

/// The answer's exit direction v̂ in the field frame, from its launch and spray angles (spray positive toward
/// right field; an answer without a spray angle, recorded before the 3-D fields, flies toward centre field).
pub fn exit_direction(answer: &ExitVelocity) -> Vec3<f64> {
    let spray = finite_or_zero(answer.spray_angle);
    let (sl, cl) = answer.launch_angle.sin_cos();
    let (ss, cs) = spray.sin_cos();
    Vec3::new(cl * cs, -cl * ss, sl)
}

/// The answer's spin vector ω in the field frame, rad/s, from its backspin, sidespin and gyro spin (their
/// axes in the module docs of [`sweetspot_physics::oblique3d`]).
pub fn spin_vector(answer: &ExitVelocity) -> Vec3<f64> {
    let flight = exit_direction(answer);
    let heading = Vec3::new(flight.x, flight.y, 0.0);
    let heading = if heading.norm() > 0.0 { heading.normalize() } else { Vec3::x() };
    let back_axis = heading.cross(&Vec3::z());
    let side_axis = back_axis.cross(&flight);
    back_axis * finite_or_zero(answer.spin)
        + side_axis * finite_or_zero(answer.sidespin)
        + flight * finite_or_zero(answer.gyro_spin)
}

/// The spin axis on a tracker's clock face, "h:mm": TrackMan's HitSpinAxis a (deg) at (a/30 + 6) o'clock, so
/// 180° (pure backspin) is 12:00, 90° (hook toward left field) 9:00, 270° (slice) 3:00, 0° (topspin) 6:00 —
/// the mapping of TrackMan's pitch Tilt to its SpinAxis, as seen from behind the plate.
pub fn spin_axis_clock(axis_deg: f64) -> String {
    let minutes = ((axis_deg / 30.0 + 6.0) * 60.0).round().rem_euclid(720.0) as i64;
    let hours = match minutes / 60 {
        0 => 12,
        h => h,
    };
    format!("{hours}:{:02}", minutes % 60)
}

fn finite_or_zero(v: f64) -> f64 {
    if v.is_finite() {
        v
    } else {
        0.0
    }
}

fn placed(axes: &Option<Matrix3<f64>>, p: Point) -> Point {
    match axes {
        None => p,
        Some(m) => {
            let v = m * Vec3::new(p.x, p.y, p.z);
            point(v.x, v.y, v.z)
        }
    }
}

/// The line of centres' angle above x: β = attack_angle + asin(undercut / (R + R_k)).
pub fn line_of_centres_angle(input: &SceneInput<'_>) -> f64 {
    let reach = input.ball_radius + input.bat.radii_at(input.answer.impact_z).0;
    input.attack_angle + (input.undercut / reach).asin()
}

/// Signed ringing amplitude aₙ of each vibrational mode in `energies` (unit modal mass, m·√kg).
pub fn mode_amplitudes(input: &SceneInput<'_>) -> Vec<f64> {
    let z = input.answer.impact_z;
    input
        .energies
        .energy
        .iter()
        .zip(&input.energies.frequency)
        .enumerate()
        .map(|(n, (&e, &f))| {
            let omega = std::f64::consts::TAU * f;
            let size = if omega > 0.0 && e > 0.0 { (2.0 * e).sqrt() / omega } else { 0.0 };
            let under_ball = input.modes.shape_at(n + 2, z);
            if under_ball > 0.0 {
                -size
            } else {
                size
            }
        })
        .collect()
}

/// The bat's deflection d(z) = Σ aₙ Yₙ(z) after contact (m, not exaggerated) at the points the scene draws it:
/// (z, d) at z = 0, every slice centre and the barrel end.
pub fn deflection(input: &SceneInput<'_>) -> Vec<(f64, f64)> {
    let amplitudes = mode_amplitudes(input);
    let mut zs = vec![0.0];
    zs.extend(input.modes.slices().iter().map(|s| s.z));
    zs.push(input.modes.length());
    zs.into_iter()
        .map(|z| (z, amplitudes.iter().enumerate().map(|(n, a)| a * input.modes.shape_at(n + 2, z)).sum()))
        .collect()
}

fn point(x: f64, y: f64, z: f64) -> Point {
    Point { x, y, z }
}

fn color(r: f32, g: f32, b: f32, a: f32) -> ColorRGBA {
    ColorRGBA { r, g, b, a }
}

fn marker(header: &Header, ns: &str, id: i32, kind: i32, scale: Vector3, color: ColorRGBA) -> Marker {
    Marker {
        header: header.clone(),
        ns: ns.to_string(),
        id,
        r#type: kind,
        action: Marker::ADD,
        pose: Pose { position: point(0.0, 0.0, 0.0), orientation: Quaternion::default() },
        scale,
        color,
        lifetime: Duration { sec: 0, nanosec: 0 },
        ..Marker::default()
    }
}

/// The scene of one answered swing (see the module docs for what each marker is).
pub fn swing_scene(input: &SceneInput<'_>) -> MarkerArray {
    let answer = input.answer;
    let header = Header { stamp: answer.header.stamp.clone(), frame_id: FRAME_ID.to_string() };
    let line = Vector3 { x: LINE_WIDTH, y: 0.0, z: 0.0 };
    let Placement { beta, axes } = placement(input);
    let z_k = answer.impact_z;
    let reach = input.ball_radius + input.bat.radii_at(z_k).0;
    let centre = placed(&axes, point(reach * beta.cos(), reach * beta.sin(), z_k));

    let mut markers = Vec::with_capacity(8);
    for (id, along_x) in [(0, true), (1, false)] {
        let at = |r: f64, z: f64| placed(&axes, if along_x { point(r, 0.0, z) } else { point(0.0, r, z) });
        let stations = &input.bat.stations;
        let mut m = marker(&header, "bat_outline", id, Marker::LINE_STRIP, line.clone(), color(0.8, 0.6, 0.3, 1.0));
        m.points = stations
            .iter()
            .map(|s| at(s.outer_radius, s.z))
            .chain(stations.iter().rev().map(|s| at(-s.outer_radius, s.z)))
            .chain(stations.first().map(|s| at(s.outer_radius, s.z)))
            .collect();
        markers.push(m);
    }

    let d = 2.0 * input.ball_radius;
    let mut ball =
        marker(&header, "ball", 0, Marker::SPHERE, Vector3 { x: d, y: d, z: d }, color(0.95, 0.95, 0.9, 0.9));
    ball.pose.position = centre.clone();
    markers.push(ball);

    let length = ARROW_METRES_PER_MPS * answer.exit_speed;
    let head = Vector3 { x: 0.008, y: 0.016, z: 0.03 };
    let mut arrow = marker(&header, "exit_velocity", 0, Marker::ARROW, head.clone(), color(0.2, 0.8, 0.2, 1.0));
    let tip = match axes {
        None => {
            let (sin, cos) = answer.launch_angle.sin_cos();
            point(centre.x + length * cos, centre.y + length * sin, centre.z)
        }
        Some(_) => offset(&centre, field_to_scene(exit_direction(answer)) * length),
    };
    arrow.points = vec![centre.clone(), tip];
    markers.push(arrow);

    let (sin_b, cos_b) = beta.sin_cos();
    let mut bent = marker(&header, DEFLECTION_NS, 0, Marker::LINE_STRIP, line, color(0.9, 0.2, 0.2, 1.0));
    bent.points = deflection(input)
        .into_iter()
        .map(|(z, d)| placed(&axes, point(DEFLECTION_SCALE * d * cos_b, DEFLECTION_SCALE * d * sin_b, z)))
        .collect();
    markers.push(bent);

    let text_size = Vector3 { x: 0.0, y: 0.0, z: TEXT_LINE_HEIGHT };
    let mut label = marker(&header, "label", 0, Marker::TEXT_VIEW_FACING, text_size.clone(), color(1.0, 1.0, 1.0, 1.0));
    label.pose.position = point(centre.x, centre.y + 0.1, centre.z);
    // Short lines rather than one: at a readable height one 70-character line would be wider than the view.
    label.text = format!(
        "swing {} · {}\nz = {:.3} m\n{:.1} m/s at {:.1}°\ndeflection ×{}",
        answer.swing_id,
        answer.bat_id,
        z_k,
        answer.exit_speed,
        answer.launch_angle.to_degrees(),
        DEFLECTION_SCALE
    );
    markers.push(label);
    markers.extend(spin_markers(&header, answer, &centre, head, text_size));
    MarkerArray { markers }
}

fn offset(p: &Point, v: Vec3<f64>) -> Point {
    point(p.x + v.x, p.y + v.y, p.z + v.z)
}

/// The spin arrow through the ball at `centre` and its label (`spin_axis` 0 and 1).
fn spin_markers(header: &Header, answer: &ExitVelocity, centre: &Point, head: Vector3, text: Vector3) -> [Marker; 2] {
    let metres_per_rad_s = SPIN_ARROW_METRES_PER_RPM * 60.0 / std::f64::consts::TAU;
    let half = field_to_scene(spin_vector(answer)) * (0.5 * metres_per_rad_s);
    let mut arrow = marker(header, SPIN_NS, 0, Marker::ARROW, head, color(0.2, 0.5, 1.0, 1.0));
    arrow.points = vec![offset(centre, -half), offset(centre, half)];
    let mut label = marker(header, SPIN_NS, 1, Marker::TEXT_VIEW_FACING, text, color(0.6, 0.8, 1.0, 1.0));
    label.pose.position = offset(centre, half + Vec3::new(0.0, 0.04, 0.0));
    let rpm = finite_or_zero(answer.total_spin) * 60.0 / std::f64::consts::TAU;
    label.text = if answer.spin_axis.is_finite() {
        let axis = answer.spin_axis.to_degrees();
        format!("{rpm:.0} rpm · axis {axis:.0}° ({})", spin_axis_clock(axis))
    } else {
        format!("{rpm:.0} rpm")
    };
    [arrow, label]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::convert;
    use crate::engine::{compute, plan_swing, Registry};
    use crate::settings::ModelSettings;
    use sweetspot_msgs::sweetspot_msgs::msg::Swing;
    use sweetspot_physics::bat::{Material, Station};

    /// Answer, energies, bat and modes of `swing` on a registry holding `bat` (when given) as "b".
    fn answered(
        swing: &Swing,
        bat: Option<(Bat, usize)>,
    ) -> (ExitVelocity, ModalEnergies, std::sync::Arc<crate::engine::BatEntry>, f64) {
        let settings = ModelSettings::default();
        let mut registry = Registry::new();
        if let Some((bat, modes)) = bat {
            registry.set_bat(crate::engine::BatEntry::new("b", bat, Some(modes), &settings));
        }
        let (plan, _) = plan_swing(&mut registry, &settings, &swing.bat_id, "", convert::swing_input(swing));
        let crate::engine::Plan::Collide { bat, ball, .. } = &plan else { panic!("{plan:?}") };
        let (entry, radius) = (std::sync::Arc::clone(bat), ball.radius);
        let computed = compute(&plan, &()).unwrap();
        let ev = convert::exit_velocity(swing, plan.bat_id(), plan.ball_id(), &Ok(computed.clone()));
        let me = convert::modal_energies(swing, plan.bat_id(), &computed);
        (ev, me, entry, radius)
    }

    fn swing(bat_id: &str, undercut: f64, attack: f64) -> Swing {
        Swing {
            swing_id: 3,
            bat_id: bat_id.into(),
            ball_speed: 40.0,
            bat_cm_speed: 20.0,
            bat_angular_speed: 50.0,
            impact_z: 0.68,
            measured_exit_speed: f64::NAN,
            undercut,
            attack_angle: attack,
            measured_launch_angle: f64::NAN,
            measured_spin: f64::NAN,
            ..Swing::default()
        }
    }

    fn scene_of(s: &Swing, bat: Option<(Bat, usize)>) -> (MarkerArray, ExitVelocity, ModalEnergies, Bat) {
        let (ev, me, entry, radius) = answered(s, bat);
        let modes = entry.modes(&()).unwrap();
        let input = SceneInput {
            answer: &ev,
            energies: &me,
            bat: &entry.bat,
            modes: &modes,
            ball_radius: radius,
            undercut: s.undercut,
            attack_angle: s.attack_angle,
            bat_tilt: s.bat_tilt,
            swing_direction: s.swing_direction,
            batter_side: if s.batter_side == Swing::BATTER_LEFT { BatterSide::Left } else { BatterSide::Right },
        };
        (swing_scene(&input), ev, me, entry.bat.clone())
    }

    fn find<'a>(scene: &'a MarkerArray, ns: &str, id: i32) -> &'a Marker {
        scene.markers.iter().find(|m| m.ns == ns && m.id == id).unwrap_or_else(|| panic!("{ns} {id}"))
    }

    /// The R161's profile as its data file lists it: the diameter in mm of each 1-cm slice, as radii in m.
    fn r161_file_radii_m() -> Vec<f64> {
        let text = include_str!("../../physics/src/data/r161.dat");
        text.lines()
            .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
            .filter_map(|l| l.split_whitespace().nth(1).and_then(|d| d.parse::<f64>().ok()))
            .map(|diameter_mm| diameter_mm / 2000.0)
            .collect()
    }

    #[test]
    fn the_outline_has_the_profiles_radius_at_every_station() {
        let (scene, ..) = scene_of(&swing("r161", 0.0, 0.0), None);
        let file = r161_file_radii_m();
        assert!(file.len() > 50, "{} rows", file.len());
        for (id, axis) in [(0, 0usize), (1, 1)] {
            let outline = find(&scene, "bat_outline", id);
            assert_eq!(outline.header.frame_id, "bat");
            assert_eq!(outline.r#type, Marker::LINE_STRIP);
            let n = (outline.points.len() - 1) / 2;
            // The outward half, knob to barrel end: the file's radii (its slice centres), with the knob's and
            // the barrel end's repeated at z = 0 and z = length.
            let radius = |p: &Point| if axis == 0 { p.x } else { p.y };
            let out: Vec<f64> = outline.points[..n].iter().map(radius).collect();
            assert_eq!(out.len(), file.len() + 2);
            assert_eq!((outline.points[0].z, out[0], out[n - 1]), (0.0, file[0], file[file.len() - 1]));
            for (i, r) in file.iter().enumerate() {
                assert!((out[i + 1] - r).abs() < 1e-15, "station {}: {} vs {r}", i + 1, out[i + 1]);
                let z = outline.points[i + 1].z;
                assert!((z - (i as f64 + 0.5) * 0.01).abs() < 1e-12, "1-cm slices: station {} at {z}", i + 1);
            }
            // Back along the other side, and closed.
            let back: Vec<f64> = outline.points[n..2 * n].iter().rev().map(|p| -radius(p)).collect();
            assert_eq!(back, out);
            assert_eq!(outline.points[2 * n], outline.points[0]);
        }
    }

    #[test]
    fn the_arrow_leaves_the_ball_at_the_answers_launch_angle_and_the_ball_touches_the_barrel() {
        for (undercut, attack) in [(0.0, 0.0), (0.015, 0.14), (-0.01, 0.1)] {
            let (scene, ev, _, bat) = scene_of(&swing("r161", undercut, attack), None);
            let arrow = find(&scene, "exit_velocity", 0);
            let [a, b] = [&arrow.points[0], &arrow.points[1]];
            let angle = (b.y - a.y).atan2(b.x - a.x);
            assert!((angle - ev.launch_angle).abs() < 1e-12, "{angle} vs {}", ev.launch_angle);
            assert_eq!(b.z, a.z);
            let length = ((b.x - a.x).powi(2) + (b.y - a.y).powi(2)).sqrt();
            assert!((length - 0.01 * ev.exit_speed).abs() < 1e-12);
            // The ball: centre R + R_k from the axis at impact_z, D from the bat's path (direction attack).
            let ball = find(&scene, "ball", 0);
            let c = &ball.pose.position;
            assert_eq!((c.x, c.y, c.z), (a.x, a.y, a.z));
            assert_eq!(c.z, 0.68);
            let (r, rk) = (ball.scale.x / 2.0, bat.radii_at(0.68).0);
            assert!(((c.x * c.x + c.y * c.y).sqrt() - (r + rk)).abs() < 1e-12);
            let offset_from_path = -c.x * attack.sin() + c.y * attack.cos();
            assert!((offset_from_path - undercut).abs() < 1e-12, "{offset_from_path} vs {undercut}");
        }
        let (scene, ev, ..) = scene_of(&swing("r161", 0.0, 0.0), None);
        assert_eq!(ev.launch_angle, 0.0);
        assert!(find(&scene, "label", 0).text.contains("×20"));
        // What docs/node.md says a scene costs on the R161: ~12 KB, some 45 answers.
        let (bytes, answer) =
            (sweetspot_msgs::encode_cdr(&scene).unwrap().len(), sweetspot_msgs::encode_cdr(&ev).unwrap().len());
        assert!((10_000..14_000).contains(&bytes) && (35..55).contains(&(bytes / answer)), "{bytes} B, {answer} B");
    }

    /// A slender uniform solid cylinder of wood, 0.84 m × 15 mm radius (shear and rotary inertia, which the
    /// Euler–Bernoulli closed form leaves out, move its first mode by ~(β r)² ≈ 0.5 %).
    fn cylinder() -> Bat {
        let station = |z: f64| Station { z, outer_radius: 0.015, inner_radius: 0.0 };
        Bat::new("cylinder", vec![station(0.0), station(0.84)], Material::R161_WOOD, None, 0.005).unwrap()
    }

    #[test]
    fn one_mode_deflects_as_the_free_free_beams_first_mode_with_the_energy_it_holds() {
        let (scene, _, me, _) = scene_of(&swing("b", 0.0, 0.0), Some((cylinder(), 1)));
        assert_eq!(me.energy.len(), 1);
        let bent = find(&scene, DEFLECTION_NS, 0);
        let d: Vec<(f64, f64)> = bent.points.iter().map(|p| (p.z, p.x / DEFLECTION_SCALE)).collect();
        assert!(bent.points.iter().all(|p| p.y == 0.0), "head-on: in the x–z plane");
        // Shape: Euler–Bernoulli free–free mode 1, β L = 4.730041, σ = 0.982502 (textbook closed form).
        let (l, bl, sigma) = (0.84, 4.730040745, 0.982502215);
        let shape = |z: f64| {
            let x = bl * z / l;
            x.cosh() + x.cos() - sigma * (x.sinh() + x.sin())
        };
        let (z0, d0) = d[d.len() / 2 + 10];
        for &(z, dz) in &d[1..d.len() - 1] {
            let want = d0 * shape(z) / shape(z0);
            assert!((dz - want).abs() < 0.02 * d0.abs().max(d[1].1.abs()), "z = {z}: {dz} vs {want}");
        }
        // Energy: ∫ ρ A d² dz = a² = 2E/ω² for the mass-normalised shape (rotary inertia, ~(βr)², left out).
        let rho_a = Material::R161_WOOD.density * std::f64::consts::PI * 0.015 * 0.015;
        let inner = &d[1..d.len() - 1];
        let dz = l / inner.len() as f64;
        let integral: f64 = inner.iter().map(|(_, v)| rho_a * v * v * dz).sum();
        let omega = std::f64::consts::TAU * me.frequency[0];
        let a2 = 2.0 * me.energy[0] / (omega * omega);
        assert!((integral / a2 - 1.0).abs() < 0.03, "{integral} vs {a2}");
        // The bat swings first away from the ball under the impact point.
        let at_impact = inner.iter().min_by(|a, b| (a.0 - 0.68).abs().total_cmp(&(b.0 - 0.68).abs())).unwrap();
        assert!(at_impact.1 < 0.0, "{at_impact:?}");
    }

    #[test]
    fn all_modes_together_hold_the_energy_each_mode_holds() {
        // M-orthogonal shapes: ∫ ρA d² dz = Σ aₙ² = Σ 2Eₙ/ωₙ² (rotary inertia left out, as above); ρA from
        // the R161's data file.
        let (scene, _, me, _) = scene_of(&swing("r161", 0.0, 0.0), None);
        assert!(me.energy.len() >= 10);
        let bent = find(&scene, DEFLECTION_NS, 0);
        let radii = r161_file_radii_m();
        let inner = &bent.points[1..bent.points.len() - 1];
        assert_eq!(inner.len(), radii.len(), "one point per 1-cm slice");
        let rho = Material::R161_WOOD.density;
        let integral: f64 = inner
            .iter()
            .zip(&radii)
            .map(|(p, r)| rho * std::f64::consts::PI * r * r * (p.x / DEFLECTION_SCALE).powi(2) * 0.01)
            .sum();
        let want: f64 =
            me.energy.iter().zip(&me.frequency).map(|(e, f)| 2.0 * e / (std::f64::consts::TAU * f).powi(2)).sum();
        assert!((integral / want - 1.0).abs() < 0.05, "{integral} vs {want}");
        assert!(inner.iter().any(|p| (p.x / DEFLECTION_SCALE).abs() > 1e-4), "a hard hit rings by ≥ 0.1 mm");
    }
}
