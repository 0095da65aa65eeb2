//! Criterion benches of the physics core: R161 modes (both eigen-solver strategies), one collision, an
//! oblique collision paired with its normal part (the tangential step's cost), the same swing in three
//! dimensions, a parallel sweep. Run: `cargo bench --bench physics -- --warm-up-time 1 --measurement-time 3`.
//!
//! On a shared machine wall-clock medians include time the thread spent descheduled; with
//! `SWEETSPOT_BENCH_CPU=1` the bench instead prints the mean per-thread CPU time of each operation
//! (from /proc/thread-self/schedstat) and exits.
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use sweetspot::physics::metrics::{linspace, sweep};
use sweetspot::physics::rigid;
use sweetspot::physics::{
    collide, collide_oblique, collide_spatial, collide_with_hoop, Ball, Bat, CollisionOptions, EigenSolver, Impact,
    LinkRule, ModeSet, ObliqueImpact, SpatialImpact, TangentialContact,
};

fn swing(impact_z: f64) -> Impact {
    Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 50.0, impact_z }
}

fn modes_with(bat: &Bat, solver: EigenSolver) -> ModeSet {
    ModeSet::compute_with_solver(bat, 18, LinkRule::KnobSide, solver).expect("modes")
}

fn cpu_ns() -> u64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

fn cpu_time_per_call(label: &str, calls: u32, mut f: impl FnMut()) {
    f();
    let start = cpu_ns();
    for _ in 0..calls {
        f();
    }
    eprintln!("cpu {label}: {:.3} µs", (cpu_ns() - start) as f64 / calls as f64 / 1e3);
}

fn benches(c: &mut Criterion) {
    let bat = Bat::preset("r161").expect("r161 preset");
    let modes = ModeSet::compute(&bat, 18).expect("modes");
    let ball = Ball::default();
    let options = CollisionOptions::default();
    let impact = swing(0.69);
    let zs = linspace(0.40, 0.82, 50);
    let alloy = ModeSet::compute(&Bat::preset("aluminum").expect("aluminum preset"), 18).expect("modes");
    let alloy_impact = swing(0.68);
    // `SWEETSPOT_BENCH_CPU=aluminum` runs only the hollow-barrel pair, a fixed number of times: under
    // `valgrind --tool=callgrind` the instruction counts of the two, which the machine's load does not move.
    if std::env::var("SWEETSPOT_BENCH_CPU").as_deref() == Ok("aluminum") {
        cpu_time_per_call("collision_aluminum_hoop_18_modes_5us", 2_000, || {
            black_box(collide(&alloy, &ball, black_box(&alloy_impact), &options).expect("collide"));
        });
        cpu_time_per_call("collision_aluminum_no_hoop_18_modes_5us", 2_000, || {
            black_box(collide_with_hoop(&alloy, &ball, black_box(&alloy_impact), &options, None).expect("collide"));
        });
        return;
    }
    if std::env::var_os("SWEETSPOT_BENCH_CPU").is_some() {
        cpu_time_per_call("modes_r161_inverse_iteration", 100, || {
            black_box(modes_with(&bat, EigenSolver::InverseIteration));
        });
        cpu_time_per_call("modes_r161_dense", 50, || {
            black_box(modes_with(&bat, EigenSolver::Dense));
        });
        cpu_time_per_call("collision_r161_18_modes_5us", 20_000, || {
            black_box(collide(&modes, &ball, black_box(&impact), &options).expect("collide"));
        });
        return;
    }
    c.bench_function("modes_r161_n84_inverse_iteration", |b| {
        b.iter(|| modes_with(black_box(&bat), EigenSolver::InverseIteration))
    });
    c.bench_function("modes_r161_n84_dense_symmetric_eigen", |b| {
        b.iter(|| modes_with(black_box(&bat), EigenSolver::Dense))
    });
    c.bench_function("collision_r161_18_modes_5us", |b| {
        b.iter(|| collide(black_box(&modes), &ball, black_box(&impact), &options).expect("collide"))
    });
    // The game ball, whose e0 follows the approach speed, against a constant-COR ball with the very e0 it
    // resolves to here (same trajectory, same steps): the pair's difference is the speed law's cost.
    let game = Ball::mlb();
    let twin = game.at_approach_speed(impact.ball_speed + rigid::bat_speed_at(&modes.mass_properties(), &impact));
    c.bench_function("collision_r161_speed_law_ball_18_modes_5us", |b| {
        b.iter(|| collide(black_box(&modes), &game, black_box(&impact), &options).expect("collide"))
    });
    c.bench_function("collision_r161_speed_law_constant_twin_18_modes_5us", |b| {
        b.iter(|| collide(black_box(&modes), &twin, black_box(&impact), &options).expect("collide"))
    });
    // An oblique swing (1 cm undercut, bat path +10°, pitch descending 6° with 2000 rpm backspin) against the
    // head-on collision it drives along the line of centres: the pair's difference is the tangential step's cost.
    let oblique = ObliqueImpact {
        impact,
        barrel_radius: bat.radii_at(impact.impact_z).0,
        undercut: 0.01,
        attack_angle: 10f64.to_radians(),
        pitch_angle: 6f64.to_radians(),
        pitch_spin: sweetspot::physics::units::rpm_to_rad_per_s(2000.0),
    };
    let contact = TangentialContact::default();
    let beta = oblique.attack_angle + (oblique.undercut / (ball.radius + oblique.barrel_radius)).asin();
    let cos_phi = (beta - oblique.attack_angle).cos();
    let normal_part = Impact {
        ball_speed: impact.ball_speed * (beta - oblique.pitch_angle).cos(),
        bat_cm_speed: impact.bat_cm_speed * cos_phi,
        bat_angular_speed: impact.bat_angular_speed * cos_phi,
        impact_z: impact.impact_z,
    };
    c.bench_function("collision_r161_oblique_18_modes_5us", |b| {
        b.iter(|| collide_oblique(black_box(&modes), &ball, black_box(&oblique), &contact, &options).expect("oblique"))
    });
    c.bench_function("collision_r161_oblique_normal_part_18_modes_5us", |b| {
        b.iter(|| collide(black_box(&modes), &ball, black_box(&normal_part), &options).expect("collide"))
    });
    // The same swing in three dimensions (the bat tilted 32°, swung 5° toward the pull side): the pair with the
    // planar oblique collision is what the third dimension costs.
    let spatial = SpatialImpact {
        bat_tilt: 32f64.to_radians(),
        swing_direction: -5f64.to_radians(),
        ..SpatialImpact::planar(oblique)
    };
    c.bench_function("collision_r161_spatial_18_modes_5us", |b| {
        b.iter(|| collide_spatial(black_box(&modes), &ball, black_box(&spatial), &contact, &options).expect("spatial"))
    });
    // A hollow barrel: the same collision with the wall's hoop mode as one more integrated mode (compare with
    // collision_r161_18_modes_5us for the hoop's cost; the solid bat's path is unchanged).
    c.bench_function("collision_aluminum_hoop_18_modes_5us", |b| {
        b.iter(|| collide(black_box(&alloy), &ball, black_box(&alloy_impact), &options).expect("collide"))
    });
    c.bench_function("collision_aluminum_no_hoop_18_modes_5us", |b| {
        b.iter(|| {
            collide_with_hoop(black_box(&alloy), &ball, black_box(&alloy_impact), &options, None).expect("collide")
        })
    });
    c.bench_function(&format!("sweep_r161_50_points_{}_threads", rayon::current_num_threads()), |b| {
        b.iter(|| sweep(black_box(&modes), &ball, &swing(0.0), &zs, &options).expect("sweep"))
    });
}

criterion_group!(physics, benches);
criterion_main!(physics);
