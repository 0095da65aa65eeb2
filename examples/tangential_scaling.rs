//! How `calibrate --fit-tangential`'s cost grows with the session: fits e_T (and every swing's undercut, held
//! to its reported value by the 2-mm prior, as `calibrate` does) to synthetic rig sessions of each size given
//! and prints the wall and CPU time, the iterations and collisions per swing. No DDS, no files.
//! `cargo run --release --example tangential_scaling -- [SWINGS…]` (default 5000 50000).
//!
//! The sessions are the demo rig's (two wood bats, true e_T 0.30, tracker noise 1° and 100 rpm), built in
//! memory and turned into the fit's problem by the same `problem_from_inputs` `calibrate` uses on a bag.

use std::time::Instant;

use sweetspot::calibrate::tangential::{fit_tangential_with_progress, problem_from_inputs, TangentialOptions};
use sweetspot::calibrate::RecordedInputs;
use sweetspot::model::time::RosTime;
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::physics::oblique::TangentialContact;
use sweetspot::physics::CollisionOptions;
use sweetspot::rig::{LaunchConditions, RigConfig, SessionGenerator};

/// CPU time of the whole process so far, s (user + system, every thread).
fn cpu_seconds() -> f64 {
    let mut usage = std::mem::MaybeUninit::<libc::rusage>::zeroed();
    // SAFETY: getrusage fills the struct it is given.
    let usage = unsafe {
        libc::getrusage(libc::RUSAGE_SELF, usage.as_mut_ptr());
        usage.assume_init()
    };
    let t = |tv: libc::timeval| tv.tv_sec as f64 + tv.tv_usec as f64 * 1e-6;
    t(usage.ru_utime) + t(usage.ru_stime)
}

fn main() -> anyhow::Result<()> {
    let sizes: Vec<usize> = match std::env::args().skip(1).map(|a| a.parse()).collect::<Result<Vec<_>, _>>()? {
        v if v.is_empty() => vec![5_000, 50_000],
        v => v,
    };
    for swings in sizes {
        let launch = LaunchConditions {
            contact: TangentialContact { tangential_cor: 0.30, ..TangentialContact::default() },
            ..LaunchConditions::default()
        };
        let config = RigConfig {
            bats: vec!["r161".into(), "r161-corked".into()],
            seed: 2000,
            options: CollisionOptions { modes: 18, ..CollisionOptions::default() },
            launch: Some(launch),
            ..RigConfig::default()
        };
        let mut rig = SessionGenerator::new(config)?.with_block(5);
        let mut t = 1_700_000_000_000_000_000u64;
        let mut inputs = RecordedInputs {
            bats: rig.bat_params(Time::from_unix_ns(t)).into_iter().map(|b| (t, b)).collect(),
            balls: vec![(t, rig.ball_params(Time::from_unix_ns(t)))],
            ..RecordedInputs::default()
        };
        for _ in 0..swings {
            t += 1_000_000;
            let swing = rig.next_swing()?;
            inputs.swings.push((t, rig.swing_message(&swing, Time::from_unix_ns(t))));
        }
        let problem = problem_from_inputs(&inputs, None)?;
        let options =
            TangentialOptions { contact: problem.contact, max_iterations: 30, ..TangentialOptions::default() };
        let (wall, cpu) = (Instant::now(), cpu_seconds());
        let mut evaluations = 0;
        let fit = fit_tangential_with_progress(&problem, &problem.ball, &options, |p| evaluations = p.evaluations)?;
        let (wall, cpu) = (wall.elapsed().as_secs_f64(), cpu_seconds() - cpu);
        let e = fit.parameter("tangential_cor").expect("e_T");
        println!(
            "{swings} swings: {wall:.1} s wall, {cpu:.1} s CPU, {} iterations ({}), {evaluations} evaluations; \
             e_T = {:.4} ± {:.4}, {} undercuts fitted; peak RSS {} MB",
            fit.iterations,
            if fit.converged { "converged" } else { "NOT converged" },
            e.value,
            e.std_error,
            fit.parameters.len() - 1,
            peak_rss_mb()
        );
    }
    Ok(())
}

/// Peak resident set of this process, MB (from /proc/self/status; 0 when unreadable).
fn peak_rss_mb() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("VmHWM:")).map(str::to_string))
        .and_then(|l| l.split_whitespace().nth(1).and_then(|kb| kb.parse::<u64>().ok()))
        .map_or(0, |kb| kb / 1024)
}
