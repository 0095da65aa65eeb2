//! Criterion benches of the physics core: R161 modes (both eigen-solver strategies), one collision, a
//! parallel sweep. Run: `cargo bench --bench physics -- --warm-up-time 1 --measurement-time 3`.
//!
//! On a shared machine wall-clock medians include time the thread spent descheduled; with
//! `SWEETSPOT_BENCH_CPU=1` the bench instead prints the mean per-thread CPU time of each operation
//! (from /proc/thread-self/schedstat) and exits.
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use sweetspot::physics::metrics::{linspace, sweep};
use sweetspot::physics::{
    collide, collide_with_hoop, Ball, Bat, CollisionOptions, EigenSolver, Impact, LinkRule, ModeSet,
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
    // A hollow barrel: the same collision with the wall's hoop mode as one more integrated mode (compare with
    // collision_r161_18_modes_5us for the hoop's cost; the solid bat's path is unchanged).
    let alloy = ModeSet::compute(&Bat::preset("aluminum").expect("aluminum preset"), 18).expect("modes");
    let alloy_impact = swing(0.68);
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
