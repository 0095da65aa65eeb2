//! The recorder against `dd`, alone (no DDS, so no network namespace needed):
//! `cargo run --release --example recorder_vs_dd -- [MESSAGES] [RUNS] [WORK_DIR] [STORAGES]`
//! (defaults 5,000,000 messages, 3 runs, `bench-work`, `zstd,none,fastwrite`; a storage is a rosbag2 preset
//! or a chunk compression, e.g. `zstd:3,lz4,zstd_fast`). Each run records Swing messages, ExitVelocity
//! messages and the node's per-swing mix with each storage, with a `dd bs=1M conv=fdatasync` of the same
//! bytes right before and right after; the table gives the median over the runs of every figure
//! (`sweetspot bench` runs one of these).

use sweetspot::bench::{disk_bench_with, storage_spec, DiskResult};

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let messages: u64 = args.next().map(|a| a.parse()).transpose()?.unwrap_or(5_000_000);
    let runs: usize = args.next().map(|a| a.parse()).transpose()?.unwrap_or(3).max(1);
    let dir = std::path::PathBuf::from(args.next().unwrap_or_else(|| "bench-work".into()));
    let storages: Vec<_> = args
        .next()
        .unwrap_or_else(|| "zstd,none,fastwrite".into())
        .split(',')
        .map(storage_spec)
        .collect::<Result<_, _>>()?;
    let loadavg = || std::fs::read_to_string("/proc/loadavg").unwrap_or_default().trim().to_string();
    println!("{} UTC, load average before: {}", chrono::Utc::now().format("%Y-%m-%d %H:%M"), loadavg());
    let mut all: Vec<Vec<DiskResult>> = Vec::new();
    for run in 0..runs {
        eprintln!("run {}/{runs}", run + 1);
        all.push(disk_bench_with(&dir, messages, &storages)?);
    }
    println!("load average after: {}", loadavg());
    println!("| message | storage | messages/s | MB/s of messages | MB/s on disk | dd MB/s | ratio (per run) |");
    println!("|---|---|---|---|---|---|---|");
    for (i, first) in all[0].iter().enumerate() {
        let col = |f: &dyn Fn(&DiskResult) -> f64| median(all.iter().map(|r| f(&r[i])).collect());
        let per_run: Vec<String> = all.iter().map(|r| format!("{:.1}", r[i].ratio * 100.0)).collect();
        println!(
            "| {} ({} B) | {} | {:.0} | {:.1} | {:.1} | {:.0} | **{:.1} %** ({}) |",
            first.message_type.rsplit('/').next().unwrap_or_default(),
            first.message_bytes,
            first.storage,
            col(&|r| r.recorder_msgs_s),
            col(&|r| r.recorder_mb_s),
            col(&|r| r.recorder_disk_mb_s),
            col(&|r| r.dd_mb_s),
            col(&|r| r.ratio * 100.0),
            per_run.join(", ")
        );
    }
    Ok(())
}
