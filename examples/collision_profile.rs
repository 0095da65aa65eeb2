//! The criterion collision benchmark's case (R161, 18 modes, 5 µs, default ball, impact at 0.69 m) run N
//! times in a plain loop, for instruction-count profiling, which the machine's noise does not disturb:
//!
//! ```sh
//! cargo build --release --example collision_profile
//! valgrind --tool=cachegrind --cache-sim=no target/release/examples/collision_profile 2000
//! valgrind --tool=cachegrind --cache-sim=no target/release/examples/collision_profile 0   # setup only
//! ```
//!
//! (instructions per collision = the difference / 2000). Arguments: collisions (default 1000), vibrational
//! modes (default 18). Prints the wall time per collision and the result's bits, so two builds can be
//! compared for identical answers.
use sweetspot::physics::{collide, Ball, Bat, CollisionOptions, Impact, ModeSet};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let collisions: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(1000);
    let modes_count: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(18);
    let modes = ModeSet::compute(&Bat::preset("r161")?, modes_count.max(18))?;
    let ball = Ball::default();
    let options = CollisionOptions { modes: modes_count, ..CollisionOptions::default() };
    let impact = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 50.0, impact_z: 0.69 };
    let start = std::time::Instant::now();
    for _ in 0..collisions {
        std::hint::black_box(collide(std::hint::black_box(&modes), &ball, std::hint::black_box(&impact), &options)?);
    }
    let per_collision = start.elapsed().as_secs_f64() * 1e6 / collisions.max(1) as f64;
    let r = collide(&modes, &ball, &impact, &options)?;
    println!(
        "{per_collision:.3} µs/collision; exit_speed bits {:016x}, energy residual {:e} J, contact {:e} s",
        r.exit_speed.to_bits(),
        r.energy.residual,
        r.contact_time
    );
    Ok(())
}
