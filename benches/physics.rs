//! Criterion benches of the physics core: R161 modes, one collision, a parallel sweep.
//! Run: `cargo bench --bench physics -- --warm-up-time 1 --measurement-time 3`.
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use sweetspot::physics::metrics::{linspace, sweep};
use sweetspot::physics::{collide, Ball, Bat, CollisionOptions, Impact, ModeSet};

fn swing(impact_z: f64) -> Impact {
    Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 50.0, impact_z }
}

fn benches(c: &mut Criterion) {
    if std::env::var_os("SWEETSPOT_CPU_REPORT").is_some() { cpu_report(); return; }
    let bat = Bat::preset("r161").expect("r161 preset");
    c.bench_function("modes_r161_n84_18_modes", |b| {
        b.iter(|| ModeSet::compute(black_box(&bat), 18).expect("modes"))
    });
    let modes = ModeSet::compute(&bat, 18).expect("modes");
    let ball = Ball::default();
    let options = CollisionOptions::default();
    let impact = swing(0.69);
    c.bench_function("collision_r161_18_modes_5us", |b| {
        b.iter(|| collide(black_box(&modes), &ball, black_box(&impact), &options).expect("collide"))
    });
    let zs = linspace(0.40, 0.82, 50);
    c.bench_function(&format!("sweep_r161_50_points_{}_threads", rayon::current_num_threads()), |b| {
        b.iter(|| sweep(black_box(&modes), &ball, &swing(0.0), &zs, &options).expect("sweep"))
    });
}

fn cpu_ns() -> u64 {
    std::fs::read_to_string("/proc/thread-self/schedstat").ok().and_then(|s| s.split_whitespace().next()?.parse().ok()).unwrap_or(0)
}
fn cpu_report() {
    let bat = Bat::preset("r161").expect("r161 preset");
    let beam = sweetspot::physics::BeamMatrices::assemble(&bat, Default::default()).unwrap();
    let a = beam.stiffness.clone();
    let t = cpu_ns();
    for _ in 0..50 { black_box(a.clone().symmetric_eigenvalues()); }
    eprintln!("CPU eigenvalues only: {:.3} ms", (cpu_ns() - t) as f64 / 50.0 / 1e6);
    let t = cpu_ns();
    for _ in 0..50 { black_box(nalgebra::SymmetricEigen::new(a.clone())); }
    eprintln!("CPU full eigen: {:.3} ms", (cpu_ns() - t) as f64 / 50.0 / 1e6);
    let t = cpu_ns();
    let mut acc = 0.0;
    for i in 0..1_000_000 { acc += black_box(1e-3 + i as f64 * 1e-9).powf(black_box(1.84)); }
    eprintln!("CPU powf: {:.2} ns {acc}", (cpu_ns() - t) as f64 / 1e6);
    let t = cpu_ns();
    let mut x = 0.5f64;
    for _ in 0..1_000_000 { x = 0.5 + 0.25 * black_box(x).powf(1.84); }
    eprintln!("CPU powf latency: {:.2} ns {x}", (cpu_ns() - t) as f64 / 1e6);
    let t = cpu_ns();
    let mut x = 0.5f64;
    for _ in 0..1_000_000 { x = 0.5 + 0.25 * (1.84 * black_box(x).ln()).exp(); }
    eprintln!("CPU exp-ln latency: {:.2} ns {x}", (cpu_ns() - t) as f64 / 1e6);
    let modes = ModeSet::compute(&bat, 18).expect("modes");
    for n in [0usize, 2, 18] {
        let options = CollisionOptions { modes: n, ..CollisionOptions::default() };
        let r = collide(&modes, &Ball::default(), &swing(0.69), &options).expect("c");
        let t = cpu_ns();
        for _ in 0..20000 { black_box(collide(&modes, &Ball::default(), black_box(&swing(0.69)), &options).expect("c")); }
        eprintln!("CPU collision {n} modes: {:.3} us, contact {} s", (cpu_ns() - t) as f64 / 20000.0 / 1e3, r.contact_time);
    }
    let t = cpu_ns();
    for _ in 0..50 { black_box(ModeSet::compute(&bat, 18).expect("modes")); }
    eprintln!("CPU modes: {:.3} ms", (cpu_ns() - t) as f64 / 50.0 / 1e6);
    let modes = ModeSet::compute(&bat, 18).expect("modes");
    let ball = Ball::default();
    let options = CollisionOptions::default();
    let impact = swing(0.69);
    let t = cpu_ns();
    for _ in 0..20000 { black_box(collide(&modes, &ball, black_box(&impact), &options).expect("c")); }
    eprintln!("CPU collision: {:.3} us", (cpu_ns() - t) as f64 / 20000.0 / 1e3);
}

criterion_group!(physics, benches);
criterion_main!(physics);
