//! The modal collision: rigid limit, conservation laws, energy budget, convergence, frame invariance, errors.

use sweetspot::physics::{
    collide, rigid, Ball, Bat, CollisionOptions, CollisionResult, Impact, LinkRule, Material, ModeSet, PhysicsError,
    Station,
};

fn r161_modes() -> ModeSet {
    ModeSet::compute(&Bat::preset("r161").expect("preset"), 24).expect("modes")
}

fn swing(impact_z: f64) -> Impact {
    Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 50.0, impact_z }
}

fn run(modes: &ModeSet, impact: &Impact, n: usize, dt: f64) -> CollisionResult {
    collide(modes, &Ball::default(), impact, &CollisionOptions { modes: n, time_step: dt }).expect("collision")
}

#[test]
fn without_vibrational_modes_the_exit_speed_is_the_closed_form_rigid_one() {
    let modes = r161_modes();
    for &z in &[0.30, 0.50, 0.65, 0.75, 0.83] {
        for ball in [Ball::default(), Ball { cor: 0.8, exponent: 1.0, stiffness: 1.0e6, ..Ball::default() }] {
            let r =
                collide(&modes, &ball, &swing(z), &CollisionOptions { modes: 0, time_step: 5e-6 }).expect("collision");
            let rel = (r.exit_speed - r.rigid_exit_speed).abs() / r.rigid_exit_speed.abs().max(1.0);
            assert!(rel < 1e-6, "z={z}: {} vs closed form {}", r.exit_speed, r.rigid_exit_speed);
            assert!((r.effective_cor - ball.cor).abs() < 1e-6, "z={z}: e_eff {} ≠ e0 {}", r.effective_cor, ball.cor);
            assert!(r.energy.vibration == 0.0 && r.mode_energies.is_empty());
        }
    }
}

#[test]
fn a_very_stiff_bat_approaches_the_rigid_limit() {
    // Y and S × 100 raise the frequencies ×10; vibrational losses must nearly vanish.
    let mut bat = Bat::preset("r161").expect("preset");
    let soft = ModeSet::compute(&bat, 6).expect("modes");
    bat.shell.youngs_modulus *= 100.0;
    bat.shell.shear_modulus *= 100.0;
    let stiff = ModeSet::compute(&bat, 6).expect("modes");
    let z = 0.62; // far from the nodes: the flexible R161 loses clearly here
    let r_soft = run(&soft, &swing(z), 6, 1e-6);
    let r_stiff = run(&stiff, &swing(z), 6, 1e-6);
    let gap_soft = (r_soft.rigid_exit_speed - r_soft.exit_speed).abs();
    let gap_stiff = (r_stiff.rigid_exit_speed - r_stiff.exit_speed).abs();
    assert!(gap_soft > 0.3, "flexible bat should lose noticeably at z={z}: gap {gap_soft}");
    assert!(gap_stiff < 0.05 * gap_soft, "stiff gap {gap_stiff} vs flexible {gap_soft}");
}

#[test]
fn momentum_and_angular_momentum_are_conserved_through_contact() {
    let modes = r161_modes();
    let mp = modes.mass_properties();
    let ball = Ball::default();
    for &z in &[0.45, 0.62, 0.70, 0.80] {
        let impact = swing(z);
        let r = run(&modes, &impact, 18, 5e-6);
        // Axis points from the bat toward the incoming ball.
        let p_before = -ball.mass * impact.ball_speed + mp.mass * impact.bat_cm_speed;
        let p_after = ball.mass * r.exit_speed + mp.mass * r.bat_cm_speed_after;
        let b = z - mp.center_of_mass;
        let l_before = -ball.mass * impact.ball_speed * b + mp.moment_of_inertia * impact.bat_angular_speed;
        let l_after = ball.mass * r.exit_speed * b + mp.moment_of_inertia * r.bat_angular_speed_after;
        assert!(
            (p_after - p_before).abs() < 1e-10 * ball.mass * impact.ball_speed,
            "z={z}: momentum {p_before} → {p_after}"
        );
        assert!(
            (l_after - l_before).abs() < 1e-10 * ball.mass * impact.ball_speed,
            "z={z}: angular momentum {l_before} → {l_after}"
        );
        assert!((r.impulse - ball.mass * (r.exit_speed + impact.ball_speed)).abs() < 1e-12);
    }
}

#[test]
fn energy_budget_closes_to_a_millionth() {
    let modes = r161_modes();
    for &z in &[0.40, 0.60, 0.68, 0.78, 0.835] {
        let r = run(&modes, &swing(z), 18, 5e-6);
        let e = r.energy;
        assert!(e.residual.abs() < 1e-6 * e.initial, "z={z}: residual {:e} of {:e}", e.residual, e.initial);
        assert!(e.ball > 0.0 && e.bat_rigid > 0.0 && e.vibration >= 0.0 && e.hysteresis_loss > 0.0);
        let sum: f64 = r.mode_energies.iter().map(|m| m.energy).sum();
        assert!((sum - e.vibration).abs() <= 1e-12 * e.initial);
        assert!(r.mode_energies.iter().all(|m| m.energy >= 0.0 && m.frequency > 0.0));
    }
}

#[test]
fn hysteresis_loss_is_the_e0_fraction_for_a_rigid_wall_like_bat() {
    // A collision with the rigid bat at its CM and no rotation is a two-body collision with reduced mass μ:
    // the ball's loss must be (1 − e0²) of the centre-of-mass-frame energy ½ μ v_rel².
    let modes = r161_modes();
    let mp = modes.mass_properties();
    let ball = Ball::default();
    let impact = Impact { ball_speed: 30.0, bat_cm_speed: 10.0, bat_angular_speed: 0.0, impact_z: mp.center_of_mass };
    let r = collide(&modes, &ball, &impact, &CollisionOptions { modes: 0, time_step: 2e-6 }).expect("collision");
    let mu = ball.mass * mp.mass / (ball.mass + mp.mass);
    let expected = (1.0 - ball.cor * ball.cor) * 0.5 * mu * 40.0 * 40.0;
    assert!(
        (r.energy.hysteresis_loss - expected).abs() < 1e-6 * expected,
        "{} vs {expected}",
        r.energy.hysteresis_loss
    );
}

#[test]
fn results_converge_as_the_time_step_shrinks() {
    let modes = r161_modes();
    let z = 0.66;
    let speeds: Vec<f64> =
        [1e-5, 5e-6, 2.5e-6, 1.25e-6].iter().map(|&dt| run(&modes, &swing(z), 12, dt).exit_speed).collect();
    let d1 = (speeds[0] - speeds[1]).abs();
    let d2 = (speeds[1] - speeds[2]).abs();
    let d3 = (speeds[2] - speeds[3]).abs();
    assert!(d2 < d1 / 4.0 || d2 < 1e-9, "dt convergence too slow: {speeds:?}");
    assert!(d3 < d2 / 4.0 || d3 < 1e-9, "dt convergence too slow: {speeds:?}");
    assert!(d3 < 1e-5, "5 µs vs 2.5 µs still differ by {d3}");
}

fn tapered_bat(slices: usize) -> Bat {
    // A smooth analytic wood bat, so finer slicing samples the same geometry.
    let length = 0.84;
    let stations: Vec<Station> = (0..=84)
        .map(|i| {
            let z = length * i as f64 / 84.0;
            let t = ((z - 0.25) / 0.35).clamp(0.0, 1.0);
            let smooth = t * t * (3.0 - 2.0 * t);
            Station { z, outer_radius: 0.0135 + (0.0325 - 0.0135) * smooth, inner_radius: 0.0 }
        })
        .collect();
    Bat::new("tapered", stations, Material::R161_WOOD, None, length / slices as f64).expect("bat")
}

#[test]
fn results_converge_as_the_slice_count_grows() {
    // The symmetric (mean) link rule is second order: successive differences shrink about fourfold.
    let z = 0.64;
    let speeds: Vec<f64> = [42usize, 84, 168]
        .iter()
        .map(|&n| {
            let modes = ModeSet::compute_with(&tapered_bat(n), 10, LinkRule::Mean).expect("modes");
            run(&modes, &swing(z), 10, 2.5e-6).exit_speed
        })
        .collect();
    let d1 = (speeds[0] - speeds[1]).abs();
    let d2 = (speeds[1] - speeds[2]).abs();
    assert!(d2 < d1 / 3.0, "slice convergence (mean rule): {speeds:?}");
    assert!(d2 < 0.005, "84 vs 168 slices differ by {d2} m/s");
    // Nathan's knob-side rule is first order: the first frequency's successive changes halve.
    let f1: Vec<f64> = [42usize, 84, 168, 336]
        .iter()
        .map(|&n| ModeSet::compute_with(&tapered_bat(n), 1, LinkRule::KnobSide).expect("modes").frequencies_hz()[0])
        .collect();
    for w in f1.windows(3) {
        let ratio = (w[1] - w[0]) / (w[2] - w[1]);
        assert!((1.6..2.4).contains(&ratio), "knob-side rule not first order: {f1:?}");
    }
}

#[test]
fn same_relative_speeds_give_the_same_relative_results() {
    let modes = r161_modes();
    let base = swing(0.7);
    let r0 = run(&modes, &base, 18, 5e-6);
    for shift in [-20.0, 7.5, 30.0] {
        // Add `shift` (m/s, along the axis toward the ball) to everything: ball and bat.
        let moved = Impact { ball_speed: base.ball_speed - shift, bat_cm_speed: base.bat_cm_speed + shift, ..base };
        let r = run(&modes, &moved, 18, 5e-6);
        assert!(
            (r.exit_speed - shift - r0.exit_speed).abs() < 1e-9,
            "shift {shift}: {} vs {}",
            r.exit_speed - shift,
            r0.exit_speed
        );
        assert!((r.collision_efficiency - r0.collision_efficiency).abs() < 1e-9);
        assert!((r.effective_cor - r0.effective_cor).abs() < 1e-9);
        assert!((r.contact_time - r0.contact_time).abs() < 1e-12);
        assert!((r.energy.vibration - r0.energy.vibration).abs() < 1e-9 * r0.energy.vibration);
        assert!((r.energy.hysteresis_loss - r0.energy.hysteresis_loss).abs() < 1e-9 * r0.energy.hysteresis_loss);
    }
}

#[test]
fn impacts_at_the_nodes_excite_little_vibration() {
    let modes = r161_modes();
    let node = modes.nodes(1).into_iter().fold(f64::NAN, f64::max);
    let at_node = run(&modes, &swing(node), 18, 5e-6);
    let off_node = run(&modes, &swing(node - 0.12), 18, 5e-6);
    assert!(
        at_node.mode_energies[0].energy < 1e-3 * off_node.mode_energies[0].energy,
        "mode 1 energy at its node {} vs 12 cm away {}",
        at_node.mode_energies[0].energy,
        off_node.mode_energies[0].energy
    );
    assert!(at_node.exit_speed > off_node.exit_speed);
    assert!(at_node.effective_cor > off_node.effective_cor);
    // Flexible exit speed never beats the rigid one for the same e0 (vibrations only take energy).
    for r in [&at_node, &off_node] {
        assert!(r.exit_speed <= r.rigid_exit_speed + 1e-9);
        assert!(r.peak_force > 0.0 && r.contact_time > 2e-4 && r.contact_time < 3e-3 && r.max_compression > 0.0);
    }
}

#[test]
fn bad_inputs_give_typed_errors_naming_the_field() {
    let modes = r161_modes();
    let ok = CollisionOptions::default();
    let ball = Ball::default();
    let off = collide(&modes, &ball, &swing(0.9), &ok);
    assert!(matches!(off, Err(PhysicsError::ImpactOffBat { .. })), "{off:?}");
    let nan = collide(&modes, &ball, &Impact { ball_speed: f64::NAN, ..swing(0.7) }, &ok);
    assert!(matches!(nan, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "ball_speed"), "{nan:?}");
    let inf = collide(&modes, &ball, &Impact { bat_angular_speed: f64::INFINITY, ..swing(0.7) }, &ok);
    assert!(matches!(inf, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "bat_angular_speed"), "{inf:?}");
    let too_many = collide(&modes, &ball, &swing(0.7), &CollisionOptions { modes: 25, ..ok });
    assert!(matches!(too_many, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "modes"), "{too_many:?}");
    for dt in [0.0, -1e-6, 1e-3, f64::NAN] {
        let bad = collide(&modes, &ball, &swing(0.7), &CollisionOptions { time_step: dt, ..ok });
        assert!(
            matches!(bad, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "time_step"),
            "dt={dt}: {bad:?}"
        );
    }
    // 9e-5 s is in range but unstable for mode 24 of the R161: refused, not integrated into garbage.
    let unstable = collide(&modes, &ball, &swing(0.7), &CollisionOptions { modes: 24, time_step: 9e-5 });
    assert!(
        matches!(unstable, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "time_step"),
        "{unstable:?}"
    );
    let receding = collide(
        &modes,
        &ball,
        &Impact { ball_speed: -30.0, bat_cm_speed: 0.0, bat_angular_speed: 0.0, impact_z: 0.7 },
        &ok,
    );
    assert!(matches!(receding, Err(PhysicsError::OutOfRange { .. })), "{receding:?}");
    let bad_ball = collide(&modes, &Ball { cor: 1.5, ..ball }, &swing(0.7), &ok);
    assert!(matches!(bad_ball, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "ball.cor"), "{bad_ball:?}");
    let zero_cor = Ball { cor: 0.0, ..ball }.validate();
    assert!(matches!(zero_cor, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "ball.cor"));
    let soft_ball = collide(&modes, &Ball { stiffness: 10.0, exponent: 1.0, ..ball }, &swing(0.7), &ok);
    assert!(matches!(soft_ball, Err(PhysicsError::Numerical(_))), "a ball that never separates: {soft_ball:?}");
}

#[test]
fn rigid_closed_form_helpers_are_consistent() {
    let modes = r161_modes();
    let mp = modes.mass_properties();
    let impact = swing(0.7);
    let vf = rigid::exit_speed(&mp, 0.145, 0.5, &impact);
    assert!((rigid::effective_cor(&mp, 0.145, &impact, vf) - 0.5).abs() < 1e-12);
}
