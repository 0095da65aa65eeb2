//! The Timoshenko beam model against closed forms, an independent continuum solution and Nathan's matrix.

use sweetspot::physics::{Bat, BeamMatrices, LinkRule, Material, ModeSet, PhysicsError, Station};

fn uniform_bat(length: f64, radius: f64, material: Material, slices: usize) -> Bat {
    let stations = vec![
        Station { z: 0.0, outer_radius: radius, inner_radius: 0.0 },
        Station { z: length, outer_radius: radius, inner_radius: 0.0 },
    ];
    Bat::new("uniform", stations, material, None, length / slices as f64).expect("valid uniform bat")
}

/// Free–free Euler–Bernoulli roots β_n L.
const BETA_L: [f64; 4] = [4.730_040_7, 7.853_204_6, 10.995_607_8, 14.137_165_5];

fn euler_bernoulli_hz(length: f64, radius: f64, m: &Material, n: usize) -> f64 {
    let area = std::f64::consts::PI * radius * radius;
    let inertia = area * radius * radius / 4.0;
    let bl = BETA_L[n];
    bl * bl / (length * length) * (m.youngs_modulus * inertia / (m.density * area)).sqrt() / std::f64::consts::TAU
}

#[test]
fn slender_stiff_beam_matches_euler_bernoulli_and_converges_with_slice_count() {
    // Steel-like rod, r/L = 0.002 (rotary inertia negligible), shear 10× stiffer than bending material.
    let m = Material { density: 7800.0, youngs_modulus: 2.0e11, shear_modulus: 2.0e12 };
    let (length, radius) = (1.0, 0.002);
    let mut previous_worst = f64::INFINITY;
    for &slices in &[40usize, 80, 160] {
        let modes = ModeSet::compute(&uniform_bat(length, radius, m, slices), 4).expect("modes");
        let f = modes.frequencies_hz();
        let mut worst: f64 = 0.0;
        for n in 0..4 {
            let exact = euler_bernoulli_hz(length, radius, &m, n);
            let rel = (f[n] - exact).abs() / exact;
            // Second-order stencil: error ≈ C (β_n Δz)², C < 1/10 generously; floor for the continuum's own
            // rotary-inertia/shear corrections (≈ 1e-5 here).
            let beta_dz = BETA_L[n] / slices as f64;
            let tolerance = 0.1 * beta_dz * beta_dz + 2e-5;
            assert!(
                rel < tolerance,
                "N={slices} mode {}: {} Hz vs EB {} Hz (rel {rel:e} ≥ {tolerance:e})",
                n + 1,
                f[n],
                exact
            );
            worst = worst.max(rel);
        }
        assert!(worst < previous_worst / 3.0, "N={slices}: error {worst:e} did not shrink from {previous_worst:e}");
        previous_worst = worst;
    }
}

/// Free–free uniform Timoshenko beam (κ = 1) solved independently: shoot the continuum ODEs
/// Y I φ'' + S A (y' − φ) + ρ I ω² φ = 0, S A (y'' − φ') + ρ A ω² y = 0 from the free end z = 0
/// (φ' = 0, y' = φ) with RK4, and find ω where the far end is free too (2×2 determinant = 0).
fn timoshenko_determinant(omega: f64, length: f64, radius: f64, m: &Material) -> f64 {
    let area = std::f64::consts::PI * radius * radius;
    let inertia = area * radius * radius / 4.0;
    let (yi, sa) = (m.youngs_modulus * inertia, m.shear_modulus * area);
    let (ra, ri) = (m.density * area * omega * omega, m.density * inertia * omega * omega);
    // state: [y, y', φ, φ']
    let deriv = |s: [f64; 4]| -> [f64; 4] {
        let (y, dy, phi, dphi) = (s[0], s[1], s[2], s[3]);
        let ddphi = -(sa * (dy - phi) + ri * phi) / yi;
        let ddy = dphi - ra * y / sa;
        [dy, ddy, dphi, ddphi]
    };
    let steps = 4000;
    let h = length / steps as f64;
    let shoot = |s0: [f64; 4]| {
        let mut s = s0;
        for _ in 0..steps {
            let add =
                |a: [f64; 4], b: [f64; 4], c: f64| [a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2], a[3] + c * b[3]];
            let k1 = deriv(s);
            let k2 = deriv(add(s, k1, h / 2.0));
            let k3 = deriv(add(s, k2, h / 2.0));
            let k4 = deriv(add(s, k3, h));
            for i in 0..4 {
                s[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        // Far-end conditions: moment ∝ φ', shear ∝ y' − φ (scaled to comparable size).
        [s[3] * length, s[1] - s[2]]
    };
    // Two independent starts satisfying the near-end conditions: (y=1, φ=0) and (y=0, φ=1, y'=1).
    let a = shoot([1.0, 0.0, 0.0, 0.0]);
    let b = shoot([0.0, 1.0, 1.0, 0.0]);
    a[0] * b[1] - a[1] * b[0]
}

fn timoshenko_hz(guess_hz: f64, length: f64, radius: f64, m: &Material) -> f64 {
    let tau = std::f64::consts::TAU;
    let f = |hz: f64| timoshenko_determinant(tau * hz, length, radius, m);
    // Bracket the root around the guess, then bisect.
    let (mut lo, mut hi) = (guess_hz * 0.97, guess_hz * 1.03);
    let (flo, fhi) = (f(lo), f(hi));
    assert!(flo * fhi < 0.0, "no sign change of the Timoshenko determinant near {guess_hz} Hz");
    let mut flo = flo;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let fm = f(mid);
        if (fm > 0.0) == (flo > 0.0) {
            lo = mid;
            flo = fm;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
#[allow(clippy::needless_range_loop)]
fn stubby_beam_shows_timoshenko_lowering_matching_the_continuum_solution() {
    // r/L = 0.08 and a wood-like Y/S ≈ 17: shear and rotary inertia lower the frequencies markedly.
    let m = Material { density: 649.0, youngs_modulus: 1.814e10, shear_modulus: 1.05e9 };
    let (length, radius) = (0.5, 0.04);
    let modes = ModeSet::compute(&uniform_bat(length, radius, m, 200), 3).expect("modes");
    let f = modes.frequencies_hz();
    for n in 0..3 {
        let eb = euler_bernoulli_hz(length, radius, &m, n);
        let exact = timoshenko_hz(f[n], length, radius, &m);
        let rel = (f[n] - exact).abs() / exact;
        eprintln!(
            "mode {}: discrete {:.3} Hz, continuum Timoshenko {exact:.3} Hz, Euler–Bernoulli {eb:.3} Hz",
            n + 1,
            f[n]
        );
        assert!(rel < 2e-4, "mode {}: discrete {} Hz vs continuum Timoshenko {} Hz (rel {rel:e})", n + 1, f[n], exact);
        assert!(exact < 0.9 * eb, "mode {}: Timoshenko {exact} Hz is not clearly below EB {eb} Hz", n + 1);
        assert!(f[n] < 0.9 * eb, "mode {}: discrete {} Hz is not clearly below EB {eb} Hz", n + 1, f[n]);
    }
}

#[test]
fn stiffness_matrix_reproduces_nathans_h_matrix_entry_by_entry() {
    let text = include_str!("data/H_matrix_Alan.csv");
    let bat = Bat::preset("r161").expect("r161");
    let beam = BeamMatrices::assemble(&bat, LinkRule::KnobSide).expect("assemble");
    let h = beam.nathan_h();
    assert_eq!(h.nrows(), 168, "R161 has 84 slices → 168 coordinates");
    let mut stored = vec![false; 168 * 168];
    let mut count = 0;
    let scale = h.iter().fold(0.0_f64, |a, &v| a.max(v.abs()));
    for line in text.lines().skip(1) {
        let cols: Vec<&str> = line.split(',').collect();
        assert_eq!(cols.len(), 3, "bad line {line}");
        let i: usize = cols[0].trim().parse().expect("row");
        let j: usize = cols[1].trim().parse().expect("col");
        let value: f64 = cols[2].trim().parse().expect("value");
        let ours = h[(i - 1, j - 1)];
        // 5 significant digits → relative rounding ≤ 5e-5; floor for entries that are differences of large terms.
        let tolerance = 1e-4 * value.abs() + 1e-9 * scale;
        assert!((ours - value).abs() <= tolerance, "H({i},{j}): ours {ours:e}, Nathan {value:e}");
        stored[(i - 1) * 168 + (j - 1)] = true;
        count += 1;
    }
    assert!(count > 900, "only {count} entries read");
    // Every entry Nathan does not list must vanish in ours too.
    for i in 0..168 {
        for j in 0..168 {
            if !stored[i * 168 + j] {
                assert!(
                    h[(i, j)].abs() <= 1e-9 * scale,
                    "H({},{}) = {:e} is not in Nathan's matrix",
                    i + 1,
                    j + 1,
                    h[(i, j)]
                );
            }
        }
    }
}

#[test]
fn stiffness_is_symmetric_with_exactly_the_rigid_null_space() {
    let bat = Bat::preset("r161-corked").expect("preset");
    for rule in [LinkRule::KnobSide, LinkRule::Mean] {
        let beam = BeamMatrices::assemble(&bat, rule).expect("assemble");
        let k = &beam.stiffness;
        let scale = k.iter().fold(0.0_f64, |a, &v| a.max(v.abs()));
        assert!((k - k.transpose()).amax() <= 1e-12 * scale, "K not symmetric");
        let n = k.nrows() / 2;
        let slices = bat.slices();
        let translation = nalgebra::DVector::from_fn(2 * n, |r, _| if r < n { 1.0 } else { 0.0 });
        let rotation = nalgebra::DVector::from_fn(2 * n, |r, _| if r < n { slices[r].z } else { 1.0 });
        assert!((k * &translation).amax() <= 1e-10 * scale, "translation is not a null vector");
        assert!((k * &rotation).amax() <= 1e-10 * scale, "rotation is not a null vector");
    }
}

#[test]
fn modes_are_mass_orthonormal_and_orthogonal_to_the_exact_rigid_modes() {
    let bat = Bat::preset("r161").expect("preset");
    let modes = ModeSet::compute(&bat, 10).expect("modes");
    let slices = modes.slices();
    let all = modes.all_modes();
    for a in 0..all.len() {
        for b in 0..all.len() {
            let dot: f64 = slices
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    s.mass * all[a].displacement[i] * all[b].displacement[i]
                        + s.rotary_inertia * all[a].rotation[i] * all[b].rotation[i]
                })
                .sum();
            let expected = if a == b { 1.0 } else { 0.0 };
            assert!((dot - expected).abs() < 1e-9, "⟨{a},{b}⟩_M = {dot}");
        }
    }
    let mp = modes.mass_properties();
    assert!((mp.mass - bat.mass_properties().mass).abs() < 1e-12);
    let f = modes.frequencies_hz();
    assert!(f.windows(2).all(|w| w[0] < w[1]), "frequencies not ascending: {f:?}");
    // Mode 1 of a free–free bat has two nodes, mode 2 three.
    assert_eq!(modes.nodes(1).len(), 2);
    assert_eq!(modes.nodes(2).len(), 3);
    assert!(modes.nodes(0).is_empty() && modes.nodes(99).is_empty());
}

#[test]
fn link_rules_agree_for_a_uniform_bat_and_differ_for_a_tapered_one() {
    let m = Material::R161_WOOD;
    let uniform = uniform_bat(0.8, 0.03, m, 80);
    let a = ModeSet::compute_with(&uniform, 3, LinkRule::KnobSide).expect("modes").frequencies_hz();
    let b = ModeSet::compute_with(&uniform, 3, LinkRule::Mean).expect("modes").frequencies_hz();
    for (fa, fb) in a.iter().zip(&b) {
        assert!((fa - fb).abs() < 1e-9 * fa);
    }
    let r161 = Bat::preset("r161").expect("preset");
    let a = ModeSet::compute_with(&r161, 1, LinkRule::KnobSide).expect("modes").frequencies_hz();
    let b = ModeSet::compute_with(&r161, 1, LinkRule::Mean).expect("modes").frequencies_hz();
    assert!((a[0] - b[0]).abs() > 1e-4 * a[0], "rules should differ on a tapered bat");
    assert!((a[0] - b[0]).abs() < 0.05 * a[0], "rules differ by more than 5 %: {} vs {}", a[0], b[0]);
}

#[test]
fn compute_refuses_invalid_bats() {
    let mut bat = Bat::preset("r161").expect("preset");
    bat.shell.youngs_modulus = f64::NAN;
    assert!(
        matches!(ModeSet::compute(&bat, 4), Err(PhysicsError::OutOfRange { ref field, .. }) if field == "shell.youngs_modulus")
    );
}

#[test]
fn inverse_iteration_and_dense_solvers_agree() {
    use sweetspot::physics::modes::EigenSolver;
    for name in Bat::preset_names() {
        let bat = Bat::preset(name).expect("preset");
        let fast =
            ModeSet::compute_with_solver(&bat, 24, LinkRule::KnobSide, EigenSolver::InverseIteration).expect("fast");
        let dense = ModeSet::compute_with_solver(&bat, 24, LinkRule::KnobSide, EigenSolver::Dense).expect("dense");
        for (a, b) in fast.vibrational_modes().iter().zip(dense.vibrational_modes()) {
            let rel = (a.angular_frequency - b.angular_frequency).abs() / b.angular_frequency;
            assert!(rel < 1e-9, "{name}: ω {} vs {}", a.angular_frequency, b.angular_frequency);
            let diff = a.displacement.iter().zip(&b.displacement).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            let peak = b.displacement.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            assert!(diff < 1e-7 * peak, "{name}: mode shapes differ by {diff:e} (peak {peak:e})");
        }
    }
}

#[test]
#[allow(clippy::needless_range_loop)]
fn fine_slicing_stays_banded_and_converges() {
    // 1000 slices (2000 coordinates): the default path never forms a dense 2N×2N matrix.
    let m = Material { density: 7800.0, youngs_modulus: 2.0e11, shear_modulus: 2.0e12 };
    let modes = ModeSet::compute(&uniform_bat(1.0, 0.002, m, 1000), 2).expect("modes");
    let f = modes.frequencies_hz();
    for n in 0..2 {
        let exact = euler_bernoulli_hz(1.0, 0.002, &m, n);
        // Floor: the continuum's own rotary-inertia and shear corrections at r/L = 0.002 (≈ 5e-5 for mode 2).
        assert!((f[n] - exact).abs() < 1e-4 * exact, "mode {}: {} vs {exact}", n + 1, f[n]);
    }
}
