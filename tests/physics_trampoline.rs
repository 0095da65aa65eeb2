//! The hoop (trampoline) mode of hollow barrels: its stiffness, mass and frequency against independent
//! solutions, the collision with it against its limits, and the direction of its effect.

// Index loops mirror the banded elimination's matrix notation.
#![allow(clippy::needless_range_loop)]

use sweetspot::physics::bat::{ALUMINUM_BARREL_WALL, BBCOR_ALLOY_BARREL_WALL};
use sweetspot::physics::collision::{collide_with_hoop, collide_with_patch, hoop_under_ball};
use sweetspot::physics::hoop::{poisson_ratio, ring_frequency_hz, ContactPatch, PatchLaw};
use sweetspot::physics::{
    collide, metrics, Ball, Bat, CollisionOptions, CollisionResult, HoopMode, Impact, Material, ModeSet, PhysicsError,
};

fn modes(bat: &Bat) -> ModeSet {
    ModeSet::compute(bat, 18).expect("modes")
}

fn swing(impact_z: f64) -> Impact {
    Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 50.0, impact_z }
}

fn bbcor_shot(impact_z: f64) -> Impact {
    Impact { ball_speed: metrics::BBCOR_BALL_SPEED, bat_cm_speed: 0.0, bat_angular_speed: 0.0, impact_z }
}

fn with_dt(time_step: f64) -> CollisionOptions {
    CollisionOptions { time_step, ..CollisionOptions::default() }
}

/// Every number of a result as bits, so that equality means bit for bit.
fn bits(r: &CollisionResult) -> Vec<u64> {
    let e = &r.energy;
    let mut v = vec![
        r.exit_speed,
        r.rigid_exit_speed,
        r.effective_cor,
        r.collision_efficiency,
        r.contact_time,
        r.peak_force,
        r.impulse,
        r.max_compression,
        e.initial,
        e.ball,
        e.bat_rigid,
        e.vibration,
        e.hysteresis_loss,
        e.hoop,
        e.hoop_stored,
        e.hoop_returned,
        e.residual,
        r.bat_cm_speed_after,
        r.bat_angular_speed_after,
    ];
    v.extend(r.mode_energies.iter().flat_map(|m| [m.frequency, m.energy]));
    v.into_iter().map(f64::to_bits).collect()
}

#[test]
fn solid_and_wooden_sections_take_the_no_hoop_path_bit_for_bit() {
    let ball = Ball::default();
    for name in ["r161", "torpedo", "r161-corked"] {
        let m = modes(&Bat::preset(name).expect("preset"));
        for z in [0.3, 0.55, 0.62, 0.69, 0.75, 0.8] {
            assert_eq!(m.hoop_at(z), None, "{name} at {z}");
            let full = collide(&m, &ball, &swing(z), &CollisionOptions::default()).expect("collide");
            let off = collide_with_hoop(&m, &ball, &swing(z), &CollisionOptions::default(), None).expect("collide");
            assert_eq!(bits(&full), bits(&off), "{name} at {z}");
            assert_eq!(full.hoop, None);
            assert_eq!((full.energy.hoop, full.energy.hoop_stored, full.energy.hoop_returned), (0.0, 0.0, 0.0));
        }
    }
    // The alloy bat's knob slice is solid: no hoop there either.
    let alloy = modes(&Bat::preset("aluminum").expect("preset"));
    assert_eq!(alloy.hoop_at(0.004), None);
    let full = collide(&alloy, &ball, &swing(0.004), &CollisionOptions::default());
    let off = collide_with_hoop(&alloy, &ball, &swing(0.004), &CollisionOptions::default(), None);
    match (full, off) {
        (Ok(a), Ok(b)) => assert_eq!(bits(&a), bits(&b)),
        (a, b) => assert_eq!(a.map(|r| bits(&r)), b.map(|r| bits(&r))),
    }
}

/// The in-plane (inextensional) ring mode formula in its textbook form (Blevins, "Formulas for natural
/// frequency and mode shape", ring in-plane bending): f_n = n (n² − 1)/(2π √(n² + 1)) · √(E I/(m a⁴)), here
/// per unit length of a long tube (plate modulus E/(1 − ν²), I = h³/12, m = ρ h).
fn blevins_ring_hz(n: f64, e: f64, nu: f64, rho: f64, a: f64, h: f64) -> f64 {
    let ei = e / (1.0 - nu * nu) * h.powi(3) / 12.0;
    n * (n * n - 1.0) / (std::f64::consts::TAU * (n * n + 1.0).sqrt()) * (ei / (rho * h * a.powi(4))).sqrt()
}

#[test]
fn the_ring_frequency_of_a_thin_aluminum_tube_is_the_textbook_one() {
    let al = Material::ALUMINUM;
    let nu = poisson_ratio(&al);
    assert!((nu - (70.0 / 52.0 - 1.0)).abs() < 1e-15);
    for (a, h) in [(0.0321, 0.0024), (0.0286, 0.0015), (0.05, 0.001)] {
        let ours = ring_frequency_hz(&al, a, h);
        let textbook = blevins_ring_hz(2.0, al.youngs_modulus, nu, al.density, a, h);
        assert!(((ours - textbook) / textbook).abs() < 1e-12, "a = {a}, h = {h}: {ours} vs {textbook} Hz");
    }
    // A 2⅝-in alloy barrel with a 2.4-mm wall: ~1.5 kHz ring, ~1.8 kHz hoop mode, in the measured band.
    let hoop = HoopMode::of_section(0.0333375, 0.0333375 - 0.0024, &al, false).expect("hollow");
    let ring = ring_frequency_hz(&al, hoop.radius, hoop.wall_thickness);
    assert!((1400.0..1650.0).contains(&ring), "{ring}");
    assert!((1000.0..2500.0).contains(&hoop.frequency_hz()), "{}", hoop.frequency_hz());
}

/// Static point load on the wall's n = 2 amplitude: a beam of stiffness B on a foundation k_f, solved by
/// finite differences on a long barrel with free ends (independent of the closed form in `hoop`).
/// Returns (point stiffness, Rayleigh mass ∫μW²/W₀²).
fn finite_difference_point_load(b: f64, k_f: f64, mu: f64, half_length: f64, cells: usize) -> (f64, f64) {
    let n = 2 * cells + 1;
    let dz = 2.0 * half_length / (n - 1) as f64;
    // Energy ½ Σ B (w_{i+1} − 2 w_i + w_{i−1})²/Δz⁴ Δz + ½ Σ k_f w_i² Δz − P w_mid: its gradient is the system.
    let mut a = vec![vec![0.0; n]; n];
    for i in 1..n - 1 {
        let c = b / dz.powi(3);
        let idx = [i - 1, i, i + 1];
        let coef = [1.0, -2.0, 1.0];
        for (p, &ip) in idx.iter().enumerate() {
            for (q, &iq) in idx.iter().enumerate() {
                a[ip][iq] += c * coef[p] * coef[q];
            }
        }
    }
    for (i, row) in a.iter_mut().enumerate() {
        let w = if i == 0 || i == n - 1 { 0.5 } else { 1.0 };
        row[i] += k_f * dz * w;
    }
    let mut rhs = vec![0.0; n];
    rhs[cells] = 1.0;
    // Banded Gaussian elimination (half-bandwidth 2), no pivoting (the matrix is positive definite).
    for k in 0..n {
        for i in k + 1..(k + 3).min(n) {
            let f = a[i][k] / a[k][k];
            for j in k..(k + 3).min(n) {
                a[i][j] -= f * a[k][j];
            }
            rhs[i] -= f * rhs[k];
        }
    }
    let mut w = vec![0.0; n];
    for k in (0..n).rev() {
        let mut sum = rhs[k];
        for j in k + 1..(k + 3).min(n) {
            sum -= a[k][j] * w[j];
        }
        w[k] = sum / a[k][k];
    }
    let w0 = w[cells];
    let mass: f64 =
        w.iter().enumerate().map(|(i, x)| if i == 0 || i == n - 1 { 0.5 } else { 1.0 } * mu * x * x * dz).sum();
    (1.0 / w0, mass / (w0 * w0))
}

#[test]
fn hoop_stiffness_and_mass_match_a_finite_difference_shell_under_a_point_load() {
    let al = Material::ALUMINUM;
    let nu = poisson_ratio(&al);
    for (outer, wall) in [(0.0333375, ALUMINUM_BARREL_WALL), (0.0286, 0.0015), (0.0333375, 0.004)] {
        let hoop = HoopMode::of_section(outer, outer - wall, &al, false).expect("hollow");
        let (a, h, e) = (outer - 0.5 * wall, wall, al.youngs_modulus);
        // The n = 2 harmonic's energies per unit length (semi-membrane theory): ring bending, axial stretch.
        let pi = std::f64::consts::PI;
        let d = e * h.powi(3) / (12.0 * (1.0 - nu * nu));
        let k_f = pi * d * 9.0 / a.powi(3);
        let b = pi * e * h * a.powi(3) / 16.0;
        let mu = pi * a * al.density * h * 5.0 / 4.0;
        let (k_fd, m_fd) = finite_difference_point_load(b, k_f, mu, 20.0 * hoop.decay_length, 4000);
        assert!(((hoop.stiffness - k_fd) / k_fd).abs() < 1e-4, "k_h {} vs {k_fd} N/m", hoop.stiffness);
        assert!(((hoop.effective_mass - m_fd) / m_fd).abs() < 1e-4, "m_h {} vs {m_fd} kg", hoop.effective_mass);
    }
}

#[test]
fn the_alloy_barrel_has_a_hoop_mode_and_the_budget_closes() {
    let bat = Bat::preset("aluminum").expect("preset");
    let m = modes(&bat);
    for (impact, label) in [(swing(0.62), "swing"), (swing(0.70), "swing"), (bbcor_shot(0.66), "bbcor")] {
        let z = impact.impact_z;
        let r = collide(&m, &Ball::default(), &impact, &CollisionOptions::default()).expect("collide");
        let hoop = r.hoop.expect("hollow barrel");
        // The section's mode, loaded through the ball's patch: a share of the point load's coupling. The patch
        // follows the compression; the result carries its coupling at the peak, which the wall's give keeps
        // below the reference compression of a rigid wall (`hoop_under_ball`), so the coupling is larger.
        let section = bat.hoop_at(z).expect("hollow barrel");
        assert_eq!((hoop.stiffness, hoop.effective_mass), (section.stiffness, section.effective_mass));
        let at_peak = section.under_patch(Ball::default().radius, r.max_compression).coupling;
        assert!((hoop.coupling - at_peak).abs() < 1e-4, "{label} at {z}: ψ {} vs the patch's {at_peak}", hoop.coupling);
        let reference = hoop_under_ball(&m, &Ball::default(), &impact).expect("hollow").coupling;
        assert!(hoop.coupling > reference, "{label} at {z}: ψ {} at the peak vs {reference}", hoop.coupling);
        assert!(hoop.coupling < 0.9 * section.coupling && hoop.coupling > 0.3, "{label} at {z}: ψ = {}", hoop.coupling);
        assert_eq!(m.hoop_frequency_at(z), Some(hoop.frequency_hz()));
        let e = &r.energy;
        let relative = (e.residual / e.initial).abs();
        assert!(relative < 1e-6, "{label} at {z}: residual {relative:e}");
        assert!(e.hoop_stored > 0.5, "{label} at {z}: the wall took {} J", e.hoop_stored);
        assert!(e.hoop_returned > 0.1 * e.hoop_stored, "{label} at {z}: it gave back {} J", e.hoop_returned);
        assert!((e.hoop_stored - e.hoop_returned - e.hoop).abs() < 1e-9 * e.hoop_stored);
        // The sum of the parts, written out.
        let sum = e.ball + e.bat_rigid + e.vibration + e.hoop + e.hysteresis_loss + e.residual;
        assert!((sum - e.initial).abs() < 1e-12 * e.initial);
        assert!(r.mode_energies.len() == 18, "the hoop mode is reported apart from the beam modes");
    }
}

#[test]
fn momentum_and_angular_momentum_pass_through_the_wall_unchanged() {
    let bat = Bat::preset("aluminum").expect("preset");
    let m = modes(&bat);
    let mp = m.mass_properties();
    let ball = Ball::default();
    for z in [0.58, 0.66, 0.74] {
        let impact = swing(z);
        let r = collide(&m, &ball, &impact, &CollisionOptions::default()).expect("collide");
        assert!(r.hoop.is_some());
        let impulse = ball.mass * (r.exit_speed + impact.ball_speed);
        let bat_linear = mp.mass * (impact.bat_cm_speed - r.bat_cm_speed_after);
        assert!(((impulse - bat_linear) / impulse).abs() < 1e-12, "z = {z}: {impulse} vs {bat_linear}");
        let bat_angular = mp.moment_of_inertia * (impact.bat_angular_speed - r.bat_angular_speed_after);
        let arm = z - mp.center_of_mass;
        assert!(((impulse * arm - bat_angular) / (impulse * arm)).abs() < 1e-12, "z = {z}");
    }
}

#[test]
fn the_hoop_collision_converges_in_the_time_step() {
    let m = modes(&Bat::preset("aluminum").expect("preset"));
    let ball = Ball::default();
    let impact = swing(0.68);
    let exit = |dt: f64| collide(&m, &ball, &impact, &with_dt(dt)).expect("collide").exit_speed;
    let reference = exit(0.25e-6);
    let errors: Vec<f64> = [8e-6, 4e-6, 2e-6, 1e-6].iter().map(|&dt| (exit(dt) - reference).abs()).collect();
    for pair in errors.windows(2) {
        assert!(pair[1] < pair[0] / 4.0 || pair[1] < 1e-10, "errors {errors:?}");
    }
    assert!((exit(5e-6) - reference).abs() < 1e-5, "the default step is converged to 10 µm/s");
}

#[test]
fn a_stiffer_wall_tends_continuously_to_the_rigid_wall() {
    let bat = Bat::preset("aluminum").expect("preset");
    let m = modes(&bat);
    let ball = Ball::default();
    let impact = swing(0.68);
    let options = CollisionOptions::default();
    let rigid = collide_with_hoop(&m, &ball, &impact, &options, None).expect("collide").exit_speed;
    let hoop = bat.hoop_at(0.68).expect("hollow");
    // k_h → ∞ at a fixed frequency (k_h and m_h scaled together): the wall's compliance 1/k_h → 0.
    let mut previous = f64::INFINITY;
    for scale in [1.0, 10.0, 100.0, 1e3, 1e4, 1e5] {
        let stiff = HoopMode { stiffness: hoop.stiffness * scale, effective_mass: hoop.effective_mass * scale, ..hoop };
        let gap =
            (collide_with_hoop(&m, &ball, &impact, &options, Some(&stiff)).expect("collide").exit_speed - rigid).abs();
        assert!(gap < previous / 5.0, "scale {scale}: gap {gap} after {previous}");
        previous = gap;
    }
    assert!(previous < 1e-4, "k_h × 1e5 is within {previous} m/s of the rigid wall");
    // The wall thickened toward solid, from the wall of the largest trampoline (about 3 mm, see the README)
    // up: the hoop's effect shrinks monotonically (each bat against itself without the hoop, since a thicker
    // wall changes the beam too) and vanishes as the bore closes (the bore share χ → 0, see `hoop`).
    let outer = 2.625 / 2.0 * 0.0254;
    let mut previous = f64::INFINITY;
    let mut first = None;
    for wall in [0.003, 0.004, 0.008, 0.016, 0.030, outer - 1e-5] {
        let b = Bat::alloy_profile("wall", wall).expect("bat");
        let m = modes(&b);
        // A closing bore's hoop mode rings near 90 kHz: resolved by a finer step (the default one is refused).
        let options = if wall > 0.03 { with_dt(1e-6) } else { options };
        let with = collide(&m, &ball, &impact, &options).expect("collide").exit_speed;
        let without = collide_with_hoop(&m, &ball, &impact, &options, None).expect("collide").exit_speed;
        let gain = with - without;
        eprintln!("wall {wall} m: hoop gain {gain} m/s");
        assert!(gain >= 0.0 && gain < previous, "wall {wall} m: gain {gain} after {previous}");
        first.get_or_insert(gain);
        previous = gain;
    }
    let first = first.expect("walls");
    assert!(previous < 1e-4 * first, "a closing bore: gain {previous} m/s against {first} m/s for 3 mm");
}

/// A wall too thin for the contact: its hoop period is longer than the contact, so the wall is still
/// deflected when the ball leaves and keeps much of what it stored — the trampoline turns into a loss.
#[test]
fn a_wall_too_thin_keeps_its_energy_past_separation() {
    let ball = Ball::default();
    let impact = swing(0.68);
    let options = CollisionOptions::default();
    let kept_share = |wall: f64| {
        let m = modes(&Bat::alloy_profile("wall", wall).expect("bat"));
        let r = collide(&m, &ball, &impact, &options).expect("collide");
        let period = 1.0 / r.hoop.expect("hollow").frequency_hz();
        (r.energy.hoop / r.energy.hoop_stored, period / r.contact_time)
    };
    let (thin, thin_ratio) = kept_share(0.0015);
    let (thick, thick_ratio) = kept_share(0.004);
    assert!(thin_ratio > 0.6 && thick_ratio < 0.4, "hoop period / contact time {thin_ratio}, {thick_ratio}");
    assert!(thin > 0.5 && thick < 0.2, "share of the stored energy kept: {thin} (1.5 mm), {thick} (4 mm)");
}

#[test]
fn an_unresolved_hoop_mode_is_refused_by_name() {
    let m = modes(&Bat::preset("aluminum").expect("preset"));
    // In the thick, narrow handle the hoop mode rings near 20 kHz.
    let hoop = m.hoop_at(0.2).expect("hollow handle");
    assert!(hoop.frequency_hz() > 10_000.0, "{}", hoop.frequency_hz());
    let options = CollisionOptions { modes: 0, time_step: 5e-5 };
    let impact = Impact { impact_z: 0.2, ..swing(0.2) };
    match collide(&m, &Ball::default(), &impact, &options) {
        Err(PhysicsError::OutOfRange { field, allowed, .. }) => {
            assert_eq!(field, "time_step");
            assert!(allowed.contains("hoop mode"), "{allowed}");
        }
        other => panic!("expected a refused time step, got {other:?}"),
    }
    let bad = HoopMode { stiffness: f64::NAN, ..hoop };
    assert!(collide_with_hoop(&m, &Ball::default(), &swing(0.68), &CollisionOptions::default(), Some(&bad)).is_err());
}

/// The protocol's BBCOR grid (3 to 9 in from the barrel end) evaluated with the hoop mode on or off.
fn best_grid_bbcor(m: &ModeSet, hoop_on: bool) -> f64 {
    let ball = Ball::bbcor_protocol();
    (0..13)
        .map(|i| m.length() - (9.0 - 0.5 * i as f64) * 0.0254)
        .map(|z| {
            let hoop = if hoop_on { hoop_under_ball(m, &ball, &bbcor_shot(z)) } else { None };
            collide_with_hoop(m, &ball, &bbcor_shot(z), &CollisionOptions::default(), hoop.as_ref())
                .expect("collide")
                .effective_cor
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn the_trampoline_raises_the_alloy_bats_bbcor_and_exit_speed() {
    let m = modes(&Bat::preset("aluminum").expect("preset"));
    let with = best_grid_bbcor(&m, true);
    let without = best_grid_bbcor(&m, false);
    assert!(with > without + 0.005, "BBCOR {with} with the hoop vs {without} without");
    assert!(metrics::bbcor(&m, &CollisionOptions::default()).expect("bbcor") >= with - 1e-12);
    // The best exit speed along the barrel (the sweet spot) rises; the hoop gains most toward the handle
    // side of the barrel and can lose a little toward its end, where the wall keeps more of its energy.
    let ball = Ball::default();
    let grid: Vec<f64> = (0..12).map(|i| 0.55 + 0.02 * i as f64).collect();
    let best = |hoop_on: bool| {
        grid.iter()
            .map(|&z| {
                let options = CollisionOptions::default();
                let r = if hoop_on {
                    collide(&m, &ball, &swing(z), &options)
                } else {
                    collide_with_hoop(&m, &ball, &swing(z), &options, None)
                };
                r.expect("collide").exit_speed
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let (on, off) = (best(true), best(false));
    assert!(on > off + 1.0, "best exit speed {on} with the hoop vs {off} m/s without");
    // Less is lost in the ball at the sweet spot: it compresses less.
    let on = collide(&m, &ball, &swing(0.61), &CollisionOptions::default()).expect("collide");
    let off = collide_with_hoop(&m, &ball, &swing(0.61), &CollisionOptions::default(), None).expect("collide");
    assert!(on.energy.hysteresis_loss < off.energy.hysteresis_loss && on.max_compression < off.max_compression);
}

#[test]
fn the_bbcor_alloy_preset_sits_at_the_ncaa_limit() {
    let bat = Bat::preset("bbcor-alloy").expect("preset");
    const { assert!(BBCOR_ALLOY_BARREL_WALL > ALUMINUM_BARREL_WALL) };
    let bbcor = metrics::bbcor(&modes(&bat), &CollisionOptions::default()).expect("bbcor");
    assert!((bbcor - 0.50).abs() < 5e-4, "BBCOR {bbcor}");
}

/// The root solve behind [`BBCOR_ALLOY_BARREL_WALL`]: the barrel wall of the alloy profile at which the
/// model's BBCOR is 0.50 (secant on the wall, 18 modes, 5-µs steps). Slow; run with `--ignored`.
#[test]
#[ignore]
fn bbcor_alloy_wall_solve() {
    let bbcor_of = |wall: f64| {
        let bat = Bat::alloy_profile("solve", wall).expect("bat");
        metrics::bbcor(&modes(&bat), &CollisionOptions::default()).expect("bbcor") - 0.50
    };
    let (mut a, mut b) = (0.008, 0.011);
    let (mut fa, mut fb) = (bbcor_of(a), bbcor_of(b));
    eprintln!("wall {a} → {fa:+e}; wall {b} → {fb:+e}");
    for _ in 0..30 {
        let c = b - fb * (b - a) / (fb - fa);
        let fc = bbcor_of(c);
        eprintln!("wall {c} → {fc:+e}");
        (a, fa, b, fb) = (b, fb, c, fc);
        if fb.abs() < 1e-7 || (b - a).abs() < 1e-9 {
            break;
        }
    }
    let mp = Bat::alloy_profile("solve", b).expect("bat").mass_properties();
    eprintln!(
        "bbcor-alloy barrel wall = {b} m; mass {} kg, CM {} m, I_cm {} kg m²",
        mp.mass, mp.center_of_mass, mp.moment_of_inertia
    );
    assert!(fb.abs() < 1e-6);
}

/// The patch's coupling ψ(u) as the collision carries it: within 1e-4 of the patch formulas (the bore share
/// times S·A of [`ContactPatch`]) over its range, 1 at a point contact, and its slope the derivative of its value.
#[test]
fn the_patch_law_interpolates_the_patch_share_and_its_slope_is_its_derivative() {
    let outer = 2.625 / 2.0 * 0.0254;
    let ball = Ball::default();
    for wall in [0.0015, ALUMINUM_BARREL_WALL, 0.004] {
        let section = HoopMode::of_section(outer, outer - wall, &Material::ALUMINUM, false).expect("hollow");
        let range = 0.025;
        let law = PatchLaw::following(&section, ball.radius, range);
        for i in 0..=200 {
            let u = range * i as f64 / 200.0;
            let exact = section.coupling * ContactPatch::new(ball.radius, outer, u).share(section.decay_length);
            let (psi, slope) = law.value_and_slope(u);
            assert!((psi - exact).abs() < 1e-4, "wall {wall}, u = {u}: ψ {psi} vs {exact}");
            let e = 1e-7;
            let numeric = (law.value_and_slope(u + e).0 - law.value_and_slope(u - e).0) / (2.0 * e);
            assert!(
                (slope - numeric).abs() < 1e-5 * slope.abs().max(1.0),
                "wall {wall}, u = {u}: {slope} vs {numeric}"
            );
        }
        assert!(
            (law.value_and_slope(0.0).0 - section.coupling).abs() < 1e-4,
            "a point contact takes the point coupling"
        );
    }
    let fixed = PatchLaw::constant(0.6);
    assert_eq!(fixed.value_and_slope(0.013), (0.6, 0.0));
}

/// The collision with a patch that follows the compression, integrated independently: plain RK4 on every
/// mode, the wall and the ball at a 50-ns step, the patch share from the geometric formulas at every stage
/// (not the interpolant), its slope by central differences, the compression solved by Newton's method.
fn following_patch_reference(m: &ModeSet, ball: &Ball, imp: &Impact, section: &HoopMode) -> (f64, f64) {
    let nm = 20;
    let mp = m.mass_properties();
    let phi: Vec<f64> = (0..nm).map(|k| m.shape_at(k, imp.impact_z)).collect();
    let w2: Vec<f64> = m.all_modes()[..nm].iter().map(|x| x.angular_frequency.powi(2)).collect();
    let (wh2, r) = (section.stiffness / section.effective_mass, 1.0 / section.effective_mass.sqrt());
    let psi = |u: f64| {
        section.coupling
            * ContactPatch::new(ball.radius, section.outer_radius(), u.max(0.0)).share(section.decay_length)
    };
    let slope = |u: f64| {
        let e = 1e-8;
        let u = u.max(e);
        (psi(u + e) - psi(u - e)) / (2.0 * e)
    };
    let solve = |delta: f64, w: f64| {
        let mut u = delta;
        for _ in 0..50 {
            let step = (u - delta - psi(u) * w) / (1.0 - slope(u) * w);
            u -= step;
            if step.abs() < 1e-17 {
                break;
            }
        }
        u
    };
    let force = |u: f64, um: f64| {
        if u <= 0.0 {
            0.0
        } else if u >= um {
            ball.stiffness * u.powf(ball.exponent)
        } else {
            ball.unloading_stiffness(um) * u.powf(ball.unloading_exponent())
        }
    };
    // y = [q (nm), p (nm), q_h, p_h, s, v]
    let n = nm;
    let deriv = |y: &[f64], um: f64, out: &mut [f64]| -> f64 {
        let delta: f64 = (0..n).map(|k| phi[k] * y[k]).sum::<f64>() - y[2 * n + 2];
        let w = y[2 * n] * r;
        let u = solve(delta, w);
        let f = force(u, um);
        let g = if f > 0.0 { 1.0 / (1.0 - slope(u) * w) } else { 0.0 };
        for k in 0..n {
            out[k] = y[n + k];
            out[n + k] = -w2[k] * y[k] - f * g * phi[k];
        }
        out[2 * n] = y[2 * n + 1];
        out[2 * n + 1] = -wh2 * y[2 * n] - f * g * psi(u) * r;
        out[2 * n + 2] = y[2 * n + 3];
        out[2 * n + 3] = f * g / ball.mass;
        u
    };
    let mut y = vec![0.0; 2 * n + 4];
    y[n] = imp.bat_cm_speed * mp.mass.sqrt();
    y[n + 1] = imp.bat_angular_speed * mp.moment_of_inertia.sqrt();
    y[2 * n + 3] = -imp.ball_speed;
    let (h, mut um, mut started) = (5e-8, 0.0f64, false);
    let len = y.len();
    let (mut k1, mut k2, mut k3, mut k4, mut tmp) =
        (vec![0.0; len], vec![0.0; len], vec![0.0; len], vec![0.0; len], vec![0.0; len]);
    for _ in 0..400_000 {
        let u0 = deriv(&y, um, &mut k1);
        for i in 0..len {
            tmp[i] = y[i] + 0.5 * h * k1[i];
        }
        deriv(&tmp, um, &mut k2);
        for i in 0..len {
            tmp[i] = y[i] + 0.5 * h * k2[i];
        }
        deriv(&tmp, um, &mut k3);
        for i in 0..len {
            tmp[i] = y[i] + h * k3[i];
        }
        deriv(&tmp, um, &mut k4);
        for i in 0..len {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        let u1 = deriv(&y, um, &mut tmp);
        um = um.max(u1);
        started |= u1 > 0.0;
        if started && u1 <= 0.0 && u0 > 0.0 {
            return (y[2 * n + 3], 0.5 * (y[2 * n + 1].powi(2) + wh2 * y[2 * n].powi(2)));
        }
    }
    panic!("the reference integration did not separate");
}

#[test]
fn a_patch_that_follows_the_compression_matches_an_independent_integration() {
    let outer = 2.625 / 2.0 * 0.0254;
    let ball = Ball::default();
    let m = modes(&Bat::preset("aluminum").expect("preset"));
    let impact = swing(m.length() - 6.0 * 0.0254);
    for wall in [0.0015, ALUMINUM_BARREL_WALL] {
        let section = HoopMode::of_section(outer, outer - wall, &Material::ALUMINUM, false).expect("hollow");
        let r = collide_with_patch(&m, &ball, &impact, &CollisionOptions::default(), Some(&section)).expect("collide");
        let (exit, kept) = following_patch_reference(&m, &ball, &impact, &section);
        // The reference's separation is found to its 50-ns step only (~1e-3 m/s of exit speed).
        assert!((r.exit_speed - exit).abs() < 5e-3, "wall {wall}: exit {} vs {exit} m/s", r.exit_speed);
        assert!((r.energy.hoop - kept).abs() < 0.01 * kept.max(1.0), "wall {wall}: kept {} vs {kept} J", r.energy.hoop);
        assert!((r.energy.residual / r.energy.initial).abs() < 1e-6);
    }
}

/// Measured hollow bats get hotter as their lowest hoop frequency falls through the band measured on them,
/// about 1,000–2,500 Hz (D. A. Russell, "Hoop frequency as a predictor of performance for softball bats",
/// abstract: "higher performance bats ... tend to have lower hoop frequencies"; A. D. Sutton & J. A. Sherwood,
/// Procedia Eng. 2, 2687 (2010), abstract: lowering the hoop frequency raises performance; A. M. Nathan et
/// al., Sports Eng. 13, 153 (2011), abstract: BBCOR "strongly correlated with the frequency of the lowest hoop
/// mode"), and youth bats were certified up to a BPF of 1.15 (BPF = BBCOR / ball COR: Washington State
/// University Sports Science Laboratory, "Bat performance measures"). On the alloy profile, walls from 1.5 to
/// 3 mm span that band: the model's BBCOR must rise at every step down in frequency and reach BPF 1.15
/// (protocol ball e0 = 0.50). With the patch fixed at its largest it did neither (BBCOR 0.5298 at 1.64 kHz
/// against 0.5374 at 2.04 kHz; largest BPF in the band 1.135).
#[test]
fn bbcor_rises_as_the_hoop_frequency_falls_through_the_measured_band() {
    let mut previous: Option<(f64, f64)> = None;
    let mut largest_bpf = 0.0f64;
    for wall in [0.003, 0.0027, 0.0024, 0.0022, 0.002, 0.0018, 0.0015] {
        let m = modes(&Bat::alloy_profile("wall", wall).expect("bat"));
        let report = metrics::bbcor_report(&m, &Ball::bbcor_protocol(), &CollisionOptions::default()).expect("bbcor");
        let f = m.hoop_frequency_at(report.impact_z).expect("hollow barrel");
        assert!((1000.0..2500.0).contains(&f), "wall {wall}: {f} Hz");
        if let Some((f_before, bbcor_before)) = previous {
            assert!(f < f_before, "wall {wall}: {f} Hz after {f_before} Hz");
            assert!(
                report.bbcor > bbcor_before,
                "wall {wall}: BBCOR {} at {f} Hz after {bbcor_before} at {f_before} Hz",
                report.bbcor
            );
        }
        largest_bpf = largest_bpf.max(report.bbcor / Ball::bbcor_protocol().cor);
        eprintln!("wall {wall} m: hoop {f:.0} Hz, BBCOR {:.4}, BPF {:.3}", report.bbcor, report.bbcor / 0.5);
        previous = Some((f, report.bbcor));
    }
    assert!(largest_bpf >= 1.15, "largest BPF in the band {largest_bpf}");
}

/// Exit speed (m/s) and the closed-form rigid bat's (same mass properties, same swing) for the average MLB
/// batter swinging `bat` at equal effort, game ball at 40 m/s, impact 6 in from the end.
fn equal_effort_swing(bat: &Bat) -> (f64, f64, f64) {
    use sweetspot::physics::batter::Batter;
    let r161 = Bat::preset("r161").expect("preset").mass_properties();
    let batter = Batter::typical(r161).expect("batter");
    let m = modes(bat);
    let swing = batter.predict(&m.mass_properties()).expect("swing");
    let ball = Ball::preset("mlb").expect("ball");
    let r = collide(&m, &ball, &swing.impact(40.0), &CollisionOptions::default()).expect("collision");
    let hoop = m.hoop_frequency_at(m.length() - 6.0 * 0.0254).expect("hollow barrel");
    (r.exit_speed, r.rigid_exit_speed, hoop)
}

#[test]
fn a_thinner_wall_loses_exit_speed_only_through_the_lighter_bat() {
    // The wall alone varied (the bat's mass with it): the thinner wall's swing is slower, but a rigid bat of
    // the same mass properties (the closed form) loses more than that, so the wall itself gains.
    let (thin, thin_rigid, f_thin) = equal_effort_swing(&Bat::alloy_profile("thin", 1.4e-3).expect("bat"));
    let (thick, thick_rigid, f_thick) = equal_effort_swing(&Bat::alloy_profile("thick", 3.2e-3).expect("bat"));
    assert!(f_thin < 1100.0 && f_thick > 2400.0, "{f_thin} {f_thick}");
    assert!(thin < thick, "{thin} vs {thick}");
    assert!(thick_rigid - thin_rigid > thick - thin, "rigid loss {} vs {}", thick_rigid - thin_rigid, thick - thin);
    assert!(thin > thin_rigid && thick > thick_rigid);
    // At one mass and swing weight the rigid bats are nearly one bat (the centre of mass moves a little, so
    // the effective mass at the impact does too: within 0.2 %), and the thinner wall hits faster at every
    // step down in hoop frequency from 1.6 to 1.0 kHz; between 1.6 and 1.8 kHz (`aluminum`'s own wall) the
    // exit speed is flat within 0.3 %.
    let walls = [1.45e-3, 1.7e-3, 1.95e-3, 2.2e-3];
    let points: Vec<(f64, f64, f64)> =
        walls.iter().map(|&w| equal_effort_swing(&Bat::alloy_weight_matched("m", w).expect("bat"))).collect();
    for pair in points.windows(2) {
        let ((a, ra, fa), (b, rb, fb)) = (pair[0], pair[1]);
        assert!(fa < fb && a > b, "{fa:.0} Hz: {a} m/s; {fb:.0} Hz: {b} m/s");
        assert!((ra - rb).abs() < 2e-3 * ra, "rigid {ra} vs {rb}");
    }
    let (top, _, f_top) = equal_effort_swing(&Bat::alloy_weight_matched("m", ALUMINUM_BARREL_WALL).expect("bat"));
    let (last, _, f_last) = points[points.len() - 1];
    assert!(f_top > f_last && (top - last).abs() < 3e-3 * top, "{f_last:.0} Hz: {last}; {f_top:.0} Hz: {top}");
}
