//! Sweeps, sweet spots, BBCOR and BESR built on the collision.

use sweetspot::physics::metrics::{self, linspace, PIVOT_Z};
use sweetspot::physics::{collide, rigid, Ball, Bat, CollisionOptions, Impact, ModeSet};

fn modes(name: &str) -> ModeSet {
    ModeSet::compute(&Bat::preset(name).expect("preset"), 18).expect("modes")
}

fn swing() -> Impact {
    Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 50.0, impact_z: 0.0 }
}

#[test]
fn parallel_sweep_equals_one_collision_per_point_in_order() {
    let m = modes("r161");
    let zs = linspace(0.3, 0.83, 12);
    let options = CollisionOptions::default();
    let points = metrics::sweep(&m, &Ball::default(), &swing(), &zs, &options).expect("sweep");
    assert_eq!(points.len(), zs.len());
    for (p, &z) in points.iter().zip(&zs) {
        assert_eq!(p.impact_z, z);
        let single = collide(&m, &Ball::default(), &Impact { impact_z: z, ..swing() }, &options).expect("collide");
        assert_eq!(p.result, single);
    }
    // One bad point fails the whole sweep with the typed error.
    assert!(metrics::sweep(&m, &Ball::default(), &swing(), &[0.5, 2.0], &options).is_err());
}

#[test]
fn sweet_spot_set_is_consistent_with_its_definitions() {
    for name in ["r161", "aluminum"] {
        let m = modes(name);
        let ball = Ball::default();
        let options = CollisionOptions::default();
        let set = metrics::sweet_spots(&m, &ball, &swing(), &options).expect("sweet spots");
        let length = m.length();
        // No sampled point beats the reported maximum.
        let zs = linspace(0.5 * length, length - ball.radius, 60);
        for p in metrics::sweep(&m, &ball, &swing(), &zs, &options).expect("sweep") {
            assert!(p.result.exit_speed <= set.max_exit_speed + 1e-9, "{name}: z={} beats the maximum", p.impact_z);
        }
        let at_max =
            collide(&m, &ball, &Impact { impact_z: set.max_exit_speed_z, ..swing() }, &options).expect("collide");
        assert!((at_max.exit_speed - set.max_exit_speed).abs() < 1e-12);
        let mp = m.mass_properties();
        assert!((set.rigid_optimum_z - rigid::optimum_impact_z(&mp, ball.mass, &swing())).abs() < 1e-12);
        assert!((set.center_of_percussion_z - mp.center_of_percussion(PIVOT_Z)).abs() < 1e-12);
        assert_eq!(set.node1_z, m.nodes(1).into_iter().fold(f64::MIN, f64::max));
        assert_eq!(set.node2_z, m.nodes(2).into_iter().fold(f64::MIN, f64::max));
        // The barrel nodes lie in the barrel, mode 2's beyond mode 1's; the flexible maximum sits near them.
        assert!(set.node1_z > 0.6 * length && set.node1_z < set.node2_z && set.node2_z < length, "{name}: {set:?}");
        assert!((set.max_exit_speed_z - set.node1_z).abs() < 0.1, "{name}: {set:?}");
    }
}

#[test]
fn bbcor_is_e0_for_a_rigid_bat_and_lower_for_a_flexible_one() {
    let ball = Ball::bbcor_protocol();
    for name in Bat::preset_names() {
        let m = modes(name);
        let rigid_report =
            metrics::bbcor_report(&m, &ball, &CollisionOptions { modes: 0, ..CollisionOptions::default() })
                .expect("bbcor");
        let flexible = metrics::bbcor(&m, &CollisionOptions::default()).expect("bbcor");
        if m.hoop_at(rigid_report.impact_z).is_some() {
            // A hollow barrel's wall gives back what it stored: the trampoline lifts even a rigid beam above e0.
            assert!(rigid_report.bbcor > ball.cor + 1e-3, "{name}: rigid-beam BBCOR {}", rigid_report.bbcor);
            assert!(flexible > 0.3 && flexible < 1.0, "{name}: BBCOR {flexible}");
        } else {
            assert!(
                (rigid_report.bbcor - ball.cor).abs() < 1e-6,
                "{name}: rigid BBCOR {} vs e0 {}",
                rigid_report.bbcor,
                ball.cor
            );
            assert!(flexible > 0.3 && flexible <= ball.cor + 1e-9, "{name}: BBCOR {flexible}");
        }
        // For a bat at rest the protocol's BBCOR = e_A(1 + r) + r with r = m_ball / m_eff.
        let report = metrics::bbcor_report(&m, &ball, &CollisionOptions::default()).expect("bbcor");
        let r = ball.mass / m.mass_properties().effective_mass_at(report.impact_z);
        let from_ea = report.collision_efficiency * (1.0 + r) + r;
        assert!((from_ea - report.bbcor).abs() < 1e-12, "{name}: {from_ea} vs {}", report.bbcor);
        let length = m.length();
        assert!(report.impact_z >= length - 9.0 * 0.0254 - 1e-9 && report.impact_z <= length - 3.0 * 0.0254 + 1e-9);
    }
}

#[test]
fn besr_is_collision_efficiency_plus_one_half_at_the_protocol_point() {
    let m = modes("r161");
    let ball = Ball::bbcor_protocol();
    let rigid_besr =
        metrics::besr(&m, &ball, &CollisionOptions { modes: 0, ..CollisionOptions::default() }).expect("besr");
    let mp = m.mass_properties();
    assert!((rigid_besr.impact_z - (m.length() - 0.1524)).abs() < 1e-12);
    let r = rigid::recoil_factor(&mp, ball.mass, rigid_besr.impact_z);
    let e_a = (ball.cor - r) / (1.0 + r);
    assert!((rigid_besr.besr - (e_a + 0.5)).abs() < 1e-6, "{} vs {}", rigid_besr.besr, e_a + 0.5);
    let flexible = metrics::besr(&m, &ball, &CollisionOptions::default()).expect("besr");
    assert!(flexible.besr < rigid_besr.besr && flexible.besr > 0.5);
}

#[test]
fn besr_scan_of_a_rigid_bat_is_the_brody_maximum_over_three_to_nine_inches() {
    // Textbook rigid bat (Brody): a free bat of mass M and moment I_cm about its centre of mass recoils with
    // r = m/M + m (z − z_cm)²/I_cm, and v_out = [(e − r) v + (1 + e) V_z]/(1 + r) for a ball at v into the bat
    // point moving at V_z. In the BESR test the bat turns about the 6-in pivot with V = 66 mph at the point 6 in
    // from the barrel end, so V_z = V (z − pivot)/(L − 6 in − pivot).
    let m = modes("r161");
    let ball = Ball::bbcor_protocol();
    let mp = m.mass_properties();
    let (mph, inch, length) = (0.44704, 0.0254, m.length());
    let (v, big_v) = (70.0 * mph, 66.0 * mph);
    let v_out = |z: f64| {
        let r = ball.mass / mp.mass + ball.mass * (z - mp.center_of_mass).powi(2) / mp.moment_of_inertia;
        let v_z = big_v * (z - PIVOT_Z) / (length - 6.0 * inch - PIVOT_Z);
        ((ball.cor - r) * v + (1.0 + ball.cor) * v_z) / (1.0 + r)
    };
    let (z_best, best) = linspace(length - 9.0 * inch, length - 3.0 * inch, 60_001)
        .into_iter()
        .map(|z| (z, v_out(z)))
        .fold((0.0, f64::NEG_INFINITY), |acc, p| if p.1 > acc.1 { p } else { acc });
    let rigid = metrics::besr_scan(&m, &ball, &CollisionOptions { modes: 0, ..CollisionOptions::default() })
        .expect("besr scan");
    assert!((rigid.exit_speed - best).abs() < 2e-3, "{} vs {best} m/s", rigid.exit_speed);
    assert!((rigid.impact_z - z_best).abs() < 2e-3, "{} vs {z_best} m", rigid.impact_z);
    assert!((rigid.besr - (best - 0.5 * (big_v - v)) / (big_v + v)).abs() < 1e-4);
    // The bat's vibrations take energy: the flexible bat's best is lower, and at least the 6-in point's.
    let flexible = metrics::besr_scan(&m, &ball, &CollisionOptions::default()).expect("besr scan");
    let at_six = metrics::besr(&m, &ball, &CollisionOptions::default()).expect("besr");
    assert!(flexible.exit_speed < rigid.exit_speed);
    assert!(flexible.exit_speed >= at_six.exit_speed - 1e-9, "{} < {}", flexible.exit_speed, at_six.exit_speed);
}
