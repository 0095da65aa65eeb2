//! The live view's swing scene in three dimensions (src/model/scene.rs): a level, square swing is drawn byte
//! for byte as the planar scene was before the 3-D bat (tests/data/scene/planar_*.cdr, the CDR encoding of
//! those scenes written by the code of then, spin markers aside), a tilted and turned bat lies along the
//! hand-computed rotation of the level one, the spin arrow lies along the 3-D model's spin vector, and a
//! left-handed batter's scene is the mirror image of the right-handed one.

use nalgebra::Vector3;
use sweetspot::model::scene::{spin_axis_clock, swing_scene, SceneInput, SPIN_NS};
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::geometry_msgs::msg::Point;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies};
use sweetspot::msgs::visualization_msgs::msg::{Marker, MarkerArray};
use sweetspot::physics::collision::CollisionOptions;
use sweetspot::physics::{
    collide_spatial, Ball, Bat, BatterSide, Impact, ModeSet, ObliqueImpact, SpatialImpact, SpatialResult,
    TangentialContact,
};

/// The planar swings whose scenes are pinned: (undercut m, attack rad, exit m/s, launch rad, backspin rad/s).
const PLANAR: [(f64, f64, f64, f64, f64); 3] =
    [(0.0, 0.0, 41.5, 0.0, 0.0), (0.015, 0.14, 38.25, 0.31, 260.0), (-0.01, 0.1, 39.0, -0.12, -140.0)];

fn answer(exit_speed: f64, launch: f64, spin: f64) -> ExitVelocity {
    ExitVelocity {
        header: Header { stamp: Time { sec: 12, nanosec: 345 }, frame_id: String::new() },
        swing_id: 7,
        bat_id: "r161".into(),
        ball_id: "mlb".into(),
        impact_z: 0.68,
        exit_speed,
        launch_angle: launch,
        spin,
        spray_angle: 0.0,
        sidespin: 0.0,
        gyro_spin: 0.0,
        total_spin: spin.abs(),
        spin_axis: if spin >= 0.0 { std::f64::consts::PI } else { 0.0 },
        ..ExitVelocity::default()
    }
}

/// Six modes ringing with hand-chosen energies (J) at hand-chosen frequencies (Hz).
fn energies() -> ModalEnergies {
    ModalEnergies {
        frequency: vec![170.0, 550.0, 1100.0, 1800.0, 2600.0, 3500.0],
        energy: vec![1.2, 0.6, 0.3, 0.1, 0.05, 0.02],
        ..ModalEnergies::default()
    }
}

fn golden_path(n: usize) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/data/scene/planar_{n}.cdr"))
}

const BALL_RADIUS: f64 = 0.0366;

fn r161() -> (Bat, ModeSet) {
    let bat = Bat::r161().unwrap();
    let modes = ModeSet::compute(&bat, 8).unwrap();
    (bat, modes)
}

struct Geometry {
    undercut: f64,
    attack: f64,
    tilt: f64,
    direction: f64,
    side: BatterSide,
}

fn scene(bat: &Bat, modes: &ModeSet, me: &ModalEnergies, ev: &ExitVelocity, g: &Geometry) -> MarkerArray {
    swing_scene(&SceneInput {
        answer: ev,
        energies: me,
        bat,
        modes,
        ball_radius: BALL_RADIUS,
        undercut: g.undercut,
        attack_angle: g.attack,
        bat_tilt: g.tilt,
        swing_direction: g.direction,
        batter_side: g.side,
    })
}

fn find<'a>(scene: &'a MarkerArray, ns: &str, id: i32) -> &'a Marker {
    scene.markers.iter().find(|m| m.ns == ns && m.id == id).unwrap_or_else(|| panic!("no marker {ns} {id}"))
}

fn v(p: &Point) -> Vector3<f64> {
    Vector3::new(p.x, p.y, p.z)
}

#[test]
fn a_level_square_swing_is_drawn_byte_for_byte_as_before_with_the_spin_arrow_added() {
    let (bat, modes) = r161();
    let me = energies();
    for (n, &(undercut, attack, exit, launch, spin)) in PLANAR.iter().enumerate() {
        let ev = answer(exit, launch, spin);
        let g = Geometry { undercut, attack, tilt: 0.0, direction: 0.0, side: BatterSide::Right };
        let mut drawn = scene(&bat, &modes, &me, &ev, &g);
        let spin_markers: Vec<Marker> = drawn.markers.iter().filter(|m| m.ns == SPIN_NS).cloned().collect();
        drawn.markers.retain(|m| m.ns != SPIN_NS);
        // The label says the same in four short lines, taller than the golden's one long line of 3 cm; the
        // golden's label is put in its place, so everything else is compared byte for byte.
        let label_at = drawn.markers.iter().position(|m| m.ns == "label").expect("label");
        let label = drawn.markers[label_at].clone();
        let golden = std::fs::read(golden_path(n)).unwrap();
        let as_golden: MarkerArray = sweetspot::msgs::decode_cdr(&golden).unwrap();
        let one_line = &as_golden.markers[label_at].text;
        let lines = one_line.replacen(" · ", "\u{0}", 1).replace(" · ", "\n").replace('\u{0}', " · ");
        assert_eq!(label.text, lines, "the golden's label {one_line:?} in lines");
        assert_eq!(label.text.lines().count(), 4, "{}", label.text);
        assert_eq!((label.scale.z, as_golden.markers[label_at].scale.z), (0.04, 0.03));
        drawn.markers[label_at] = as_golden.markers[label_at].clone();
        assert!(sweetspot::msgs::encode_cdr(&drawn).unwrap() == golden, "planar scene {n} differs from its golden");
        // The spin arrow of a planar swing lies along the bat's axis (z), toward the barrel for backspin,
        // 1e-4 m per rpm long, centred on the ball.
        let arrow = &spin_markers[0];
        let ball = v(&find(&drawn, "ball", 0).pose.position);
        let (a, b) = (v(&arrow.points[0]), v(&arrow.points[1]));
        let rpm = spin * 60.0 / std::f64::consts::TAU;
        assert!(((b - a) - Vector3::new(0.0, 0.0, 1e-4 * rpm)).norm() < 1e-12, "{a} {b}");
        assert!(((a + b) / 2.0 - ball).norm() < 1e-12);
    }
}

/// Backspin 2,000 rpm at 180° is 12:00, a hook (90°) 9:00, a slice (270°) 3:00, topspin (0°) 6:00.
#[test]
fn the_spin_label_reads_the_axis_on_the_clock_face() {
    assert_eq!(spin_axis_clock(180.0), "12:00");
    assert_eq!(spin_axis_clock(90.0), "9:00");
    assert_eq!(spin_axis_clock(270.0), "3:00");
    assert_eq!(spin_axis_clock(0.0), "6:00");
    assert_eq!(spin_axis_clock(195.0), "12:30");
    assert_eq!(spin_axis_clock(359.9), "6:00");
    let (bat, modes) = r161();
    let ev = answer(40.0, 0.3, 2000.0 * std::f64::consts::TAU / 60.0);
    let g = Geometry { undercut: 0.01, attack: 0.1, tilt: 0.0, direction: 0.0, side: BatterSide::Right };
    let label = find(&scene(&bat, &modes, &energies(), &ev, &g), SPIN_NS, 1).text.clone();
    assert_eq!(label, "2000 rpm · axis 180° (12:00)");
}

/// The bat tilted ψ (barrel down) and turned δ toward right field: the level bat along first base, (0, −1, 0)
/// in the field frame (forward, left, up), turned by ψ about the forward axis — (0, −cos ψ, −sin ψ) — then by
/// −δ about the vertical: (−cos ψ sin δ, −cos ψ cos δ, −sin ψ); in frame `bat` (forward, up, first base):
/// (−cos ψ sin δ, −sin ψ, cos ψ cos δ).
#[test]
fn a_tilted_turned_bat_lies_along_the_hand_computed_rotation() {
    let (bat, modes) = r161();
    let me = ModalEnergies { frequency: vec![170.0], energy: vec![0.0], ..ModalEnergies::default() };
    let ev = answer(40.0, 0.2, 200.0);
    for (tilt_deg, direction_deg) in [(30.0f64, 0.0f64), (25.0, 20.0), (-10.0, -35.0), (0.0, 15.0)] {
        let (psi, delta) = (tilt_deg.to_radians(), direction_deg.to_radians());
        let g = Geometry { undercut: 0.0, attack: 0.0, tilt: psi, direction: delta, side: BatterSide::Right };
        let drawn = scene(&bat, &modes, &me, &ev, &g);
        let want = Vector3::new(-psi.cos() * delta.sin(), -psi.sin(), psi.cos() * delta.cos());
        // The outline's two sides are symmetric about the axis: their midpoints lie on it, at the knob and
        // at each station's z along it.
        for id in [0, 1] {
            let outline = &find(&drawn, "bat_outline", id).points;
            let n = (outline.len() - 1) / 2;
            for (i, s) in bat.stations.iter().enumerate() {
                let mid = (v(&outline[i]) + v(&outline[2 * n - 1 - i])) / 2.0;
                assert!((mid - want * s.z).norm() < 1e-12, "ψ {tilt_deg}° δ {direction_deg}° station {i}: {mid}");
            }
        }
        // Undeflected (no energy), the centre line is the axis itself.
        let line = &find(&drawn, "deflection x20", 0).points;
        let end = v(line.last().unwrap());
        assert!((end - want * bat.length()).norm() < 1e-12, "{end} vs {}", want * bat.length());
        // The ball touches the barrel: R + R_k from the axis at impact_z, level with the path (no undercut,
        // no attack): the path is horizontal, perpendicular to the axis.
        let c = v(&find(&drawn, "ball", 0).pose.position);
        let along = c.dot(&want);
        assert!((along - 0.68).abs() < 1e-12, "{along}");
        let reach = BALL_RADIUS + bat.radii_at(0.68).0;
        let across = c - want * along;
        assert!((across.norm() - reach).abs() < 1e-12);
        // Head-on with a level path, the ball sits straight along the path: (cos δ, 0, sin δ) in frame `bat`.
        assert!((across / reach - Vector3::new(delta.cos(), 0.0, delta.sin())).norm() < 1e-12, "{across}");
    }
    // With an attack angle the tilt still sets the axis's fall: its up component is −sin ψ.
    let g = Geometry { undercut: 0.01, attack: 0.2, tilt: 0.4, direction: 0.3, side: BatterSide::Right };
    let drawn = scene(&bat, &modes, &me, &ev, &g);
    let line = &find(&drawn, "deflection x20", 0).points;
    let axis = v(line.last().unwrap()) / bat.length();
    assert!((axis.norm() - 1.0).abs() < 1e-12 && (axis.y + 0.4f64.sin()).abs() < 1e-12, "{axis}");
}

/// The answer the node would send for `impact`, with the 3-D model's result.
fn modelled(modes: &ModeSet, impact: &SpatialImpact) -> (ExitVelocity, SpatialResult) {
    let ball = Ball::preset("mlb").unwrap();
    let r = collide_spatial(
        modes,
        &ball,
        impact,
        &TangentialContact::default(),
        &CollisionOptions { modes: 8, ..CollisionOptions::default() },
    )
    .unwrap();
    let mut ev = answer(r.exit_speed, r.launch_angle, r.backspin);
    (ev.spray_angle, ev.sidespin, ev.gyro_spin) = (r.spray_angle, r.sidespin, r.gyro_spin);
    (ev.total_spin, ev.spin_axis) = (r.total_spin, r.spin_axis);
    (ev, r)
}

fn spatial(bat: &Bat, tilt: f64, direction: f64, side: BatterSide) -> SpatialImpact {
    let impact = Impact { ball_speed: 40.0, bat_cm_speed: 20.0, bat_angular_speed: 50.0, impact_z: 0.68 };
    let oblique = ObliqueImpact {
        undercut: 0.012,
        attack_angle: 0.15,
        pitch_angle: 0.1,
        pitch_spin: 200.0,
        ..ObliqueImpact::head_on(impact, bat.radii_at(0.68).0)
    };
    SpatialImpact { oblique, bat_tilt: tilt, swing_direction: direction, batter_side: side }
}

#[test]
fn the_spin_arrow_lies_along_the_models_spin_vector_and_the_exit_arrow_along_its_velocity() {
    let (bat, modes) = r161();
    for (tilt, direction, side) in
        [(0.5, 0.3, BatterSide::Right), (0.3, -0.4, BatterSide::Right), (0.5, 0.3, BatterSide::Left)]
    {
        let impact = spatial(&bat, tilt, direction, side);
        let (ev, r) = modelled(&modes, &impact);
        let g = Geometry { undercut: 0.012, attack: 0.15, tilt, direction, side };
        let drawn = scene(&bat, &modes, &energies(), &ev, &g);
        let to_scene = |w: [f64; 3]| Vector3::new(w[0], w[2], -w[1]);
        let arrow = find(&drawn, SPIN_NS, 0);
        let along = v(&arrow.points[1]) - v(&arrow.points[0]);
        let omega = to_scene(r.spin_vector);
        assert!(along.cross(&omega).norm() < 1e-9 * along.norm() * omega.norm(), "{along} ∦ {omega}");
        assert!(along.dot(&omega) > 0.0);
        let rpm = r.total_spin * 60.0 / std::f64::consts::TAU;
        assert!((along.norm() - 1e-4 * rpm).abs() < 1e-12, "{} m for {rpm} rpm", along.norm());
        let exit = find(&drawn, "exit_velocity", 0);
        let out = v(&exit.points[1]) - v(&exit.points[0]);
        let velocity = to_scene(r.velocity);
        assert!((out - velocity * 0.01).norm() < 1e-9, "{out} vs {}", velocity * 0.01);
        assert!(r.sidespin.abs() > 10.0, "a turned, tilted swing sidespins: {}", r.sidespin);
    }
}

/// A left-handed batter's swing at δ is the mirror image (z → −z in frame `bat`) of the right-handed swing at
/// −δ: every point mirrored, the spin arrow (an axial vector) mirrored with its head and tail swapped.
#[test]
fn a_left_handed_scene_is_the_mirror_image_of_the_right_handed_one() {
    let (bat, modes) = r161();
    let me = energies();
    for (tilt, direction) in [(0.0, 0.0), (0.4, 0.25), (0.2, -0.3)] {
        let (left_ev, _) = modelled(&modes, &spatial(&bat, tilt, direction, BatterSide::Left));
        let (right_ev, _) = modelled(&modes, &spatial(&bat, tilt, -direction, BatterSide::Right));
        let lefty = scene(
            &bat,
            &modes,
            &me,
            &left_ev,
            &Geometry { undercut: 0.012, attack: 0.15, tilt, direction, side: BatterSide::Left },
        );
        let righty = scene(
            &bat,
            &modes,
            &me,
            &right_ev,
            &Geometry { undercut: 0.012, attack: 0.15, tilt, direction: -direction, side: BatterSide::Right },
        );
        let mirror = |p: &Point| Vector3::new(p.x, p.y, -p.z);
        for (ns, id) in [("bat_outline", 0), ("bat_outline", 1), ("deflection x20", 0), ("exit_velocity", 0)] {
            let (l, r) = (&find(&lefty, ns, id).points, &find(&righty, ns, id).points);
            assert_eq!(l.len(), r.len());
            for (a, b) in l.iter().zip(r) {
                assert!((v(a) - mirror(b)).norm() < 1e-9, "{ns} {id} at ψ {tilt} δ {direction}: {a:?} vs {b:?}");
            }
        }
        let (lb, rb) = (&find(&lefty, "ball", 0).pose.position, &find(&righty, "ball", 0).pose.position);
        assert!((v(lb) - mirror(rb)).norm() < 1e-12);
        if tilt == 0.0 && direction == 0.0 {
            // The level, square left-handed bat points to third base: its barrel end at z = −length (the
            // deflection bends it across its axis only).
            let end = v(find(&lefty, "deflection x20", 0).points.last().unwrap());
            assert!((end.z + bat.length()).abs() < 1e-12, "{end}");
        }
        let (l, r) = (&find(&lefty, SPIN_NS, 0).points, &find(&righty, SPIN_NS, 0).points);
        assert!((v(&l[0]) - mirror(&r[1])).norm() < 1e-9 && (v(&l[1]) - mirror(&r[0])).norm() < 1e-9, "{l:?} {r:?}");
    }
}
