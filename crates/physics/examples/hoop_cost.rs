//! What the hollow barrel's hoop mode costs: the `aluminum` bat's collision at 0.68 m with its hoop mode
//! against the same collision without it, timed in alternating rounds (per-thread CPU time from
//! /proc/thread-self/schedstat, so time spent descheduled on a shared machine is not counted), each
//! round's ratio printed and the median quoted. With `--results` it prints the hollow bat's exit speed,
//! COR and hoop energies at several impact points instead, to full precision, for comparing two builds.
//!
//! Run: `cargo run --release -p sweetspot-physics --example hoop_cost [-- ROUNDS | --results]`.
use std::hint::black_box;
use sweetspot_physics::{collide, collide_with_hoop, Ball, Bat, CollisionOptions, Impact, ModeSet};

fn swing(impact_z: f64) -> Impact {
    Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 50.0, impact_z }
}

fn cpu_ns() -> u64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

fn per_call_us(calls: u32, mut f: impl FnMut()) -> f64 {
    let start = cpu_ns();
    for _ in 0..calls {
        f();
    }
    (cpu_ns() - start) as f64 / calls as f64 / 1e3
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

fn main() {
    let alloy = ModeSet::compute(&Bat::preset("aluminum").expect("aluminum preset"), 18).expect("modes");
    let ball = Ball::default();
    let options = CollisionOptions::default();
    let arg = std::env::args().nth(1);
    if arg.as_deref() == Some("--results") {
        for z in [0.50, 0.55, 0.60, 0.64, 0.68, 0.72, 0.76, 0.80] {
            let r = collide(&alloy, &ball, &swing(z), &options).expect("collide");
            let e = r.energy;
            println!(
                "z {z:.2} exit {:.17e} cor {:.17e} hoop {:.17e} stored {:.17e} returned {:.17e} residual {:.3e}",
                r.exit_speed, r.effective_cor, e.hoop, e.hoop_stored, e.hoop_returned, e.residual
            );
        }
        return;
    }
    let impact = swing(0.68);
    // `--count hoop|solid N`: only N collisions of one kind, for counting instructions (valgrind).
    if arg.as_deref() == Some("--count") {
        let kind = std::env::args().nth(2).unwrap_or_default();
        let n: usize = std::env::args().nth(3).and_then(|a| a.parse().ok()).unwrap_or(0);
        let section = if kind == "hoop" { None } else { Some(None) };
        for _ in 0..n {
            black_box(match section {
                None => collide(&alloy, &ball, black_box(&impact), &options),
                Some(none) => collide_with_hoop(&alloy, &ball, black_box(&impact), &options, none),
            })
            .expect("collide");
        }
        return;
    }
    let rounds: usize = arg.and_then(|a| a.parse().ok()).unwrap_or(15);
    let hoop = || {
        black_box(collide(&alloy, &ball, black_box(&impact), &options).expect("collide"));
    };
    let solid = || {
        black_box(collide_with_hoop(&alloy, &ball, black_box(&impact), &options, None).expect("collide"));
    };
    per_call_us(500, hoop);
    per_call_us(500, solid);
    let (mut with, mut without, mut ratios) = (vec![], vec![], vec![]);
    for _ in 0..rounds {
        let a = per_call_us(2_000, hoop);
        let b = per_call_us(2_000, solid);
        println!("hoop {a:.2} µs  no hoop {b:.2} µs  ratio {:.3}", a / b);
        with.push(a);
        without.push(b);
        ratios.push(a / b);
    }
    let spread = |x: &[f64]| x.iter().cloned().fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let (lo, hi) = spread(&ratios);
    println!(
        "median: hoop {:.2} µs, no hoop {:.2} µs, ratio {:.3} (rounds {lo:.3}–{hi:.3})",
        median(with),
        median(without),
        median(ratios)
    );
}
