//! `sweetspot bag …`: inspect, recover, export, replay and play recorded bags.

use std::io::IsTerminal;
use std::io::Write as _;
use std::path::PathBuf;

use anyhow::Context;

use crate::bag;

/// The `bag` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum BagCommand {
    /// Topics, types, counts, duration and size of a bag (a rosbag2 directory or one .mcap file).
    Info {
        /// Bag directory or .mcap file.
        path: PathBuf,
        /// Print JSON instead of the `ros2 bag info` layout.
        #[arg(long)]
        json: bool,
        /// Exit 0 even if the bag is damaged (the damage is still listed).
        #[arg(long)]
        skip_damaged: bool,
    },
    /// Write a repaired copy of a bag cut off by a crash (no summary/footer) or damaged, keeping every intact
    /// chunk (every complete message of an unchunked file), and say what was dropped. The original is never
    /// modified; the copy goes beside it (`NAME.recovered.mcap`, `DIR.recovered/`) or to --output.
    Recover {
        /// Bag directory or .mcap file.
        path: PathBuf,
        /// Where to write the copy (must not exist).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// One row per recorded swing: its inputs joined with the ExitVelocity and ModalEnergies computed for
    /// it (matched by namespace and swing_id).
    Export {
        /// Bag directory or .mcap file.
        path: PathBuf,
        /// Write CSV (the default, and the only format so far).
        #[arg(long)]
        csv: bool,
        /// Output file (default: stdout).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Go on past damaged chunks with everything intact around them (the damage is still listed).
        #[arg(long)]
        skip_damaged: bool,
    },
    /// Re-run the physics on every recorded swing with the bat/ball in force at that moment and compare with
    /// the recorded ExitVelocity and ModalEnergies. Exits non-zero if any swing differs beyond the tolerance
    /// (bit-exact by default). With --bat/--ball/--modes it answers "what if" and only prints the differences.
    Replay {
        /// Bag directory or .mcap file.
        path: PathBuf,
        /// Relative tolerance |replayed − recorded| / max(|replayed|, |recorded|); 0 = bit-exact.
        #[arg(long, default_value_t = 0.0)]
        tolerance: f64,
        /// What if: use this preset bat for every swing.
        #[arg(long)]
        bat: Option<String>,
        /// What if: use this preset ball for every swing.
        #[arg(long)]
        ball: Option<String>,
        /// What if: integrate this many modes for every bat.
        #[arg(long)]
        modes: Option<usize>,
        /// Node setting time_step, s (default: from the bag's custom_data, else the node default).
        #[arg(long)]
        time_step: Option<f64>,
        /// Node setting default_modes (default: from the bag, else the node default).
        #[arg(long)]
        default_modes: Option<usize>,
        /// Node setting default_bat (default: from the bag, else the node default).
        #[arg(long)]
        default_bat: Option<String>,
        /// Print every swing (default: all when ≤ 40, else only the differing ones).
        #[arg(long)]
        all: bool,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
        /// Go on past damaged chunks with everything intact around them (the damage is still listed).
        #[arg(long)]
        skip_damaged: bool,
    },
    /// Republish the recorded inputs (BatParams, BallParams, Swing) over DDS with their original timing;
    /// params recorded before the first swing go out first, latched (transient-local).
    Play {
        /// Bag directory or .mcap file.
        path: PathBuf,
        /// Time scale: 2 plays twice as fast.
        #[arg(long, default_value_t = 1.0)]
        rate: f64,
        /// Start over when done, until interrupted.
        #[arg(long = "loop")]
        repeat: bool,
        /// Only these topics (default: every input topic in the bag).
        #[arg(long, value_delimiter = ',', num_args = 1..)]
        topics: Vec<String>,
        /// Wait until every topic has this many subscriptions before starting.
        #[arg(long, default_value_t = 0)]
        wait_subscribers: usize,
        /// Seconds to wait for subscribers, and for acknowledgments at the end.
        #[arg(long, default_value_t = 10.0)]
        timeout: f64,
        /// Do not print each message.
        #[arg(short, long)]
        quiet: bool,
        /// Go on past damaged chunks with everything intact around them (the damage is still listed).
        #[arg(long)]
        skip_damaged: bool,
    },
}

/// Runs one `bag` subcommand.
pub fn run(cmd: BagCommand) -> anyhow::Result<()> {
    match cmd {
        BagCommand::Info { path, json, skip_damaged } => info(path, json, skip_damaged),
        BagCommand::Recover { path, output } => recover(path, output),
        BagCommand::Export { path, csv: _, output, skip_damaged } => {
            let skipped = check_damage(&path, skip_damaged)?;
            export(path, output, skipped)
        }
        BagCommand::Play { path, rate, repeat, topics, wait_subscribers, timeout, quiet, skip_damaged } => {
            check_damage(&path, skip_damaged)?;
            if !(timeout > 0.0 && timeout.is_finite()) {
                anyhow::bail!("--timeout {timeout} is out of range: expected a finite value > 0 s");
            }
            let options = crate::play::PlayOptions {
                rate,
                repeat,
                topics,
                wait_subscribers,
                timeout: std::time::Duration::from_secs_f64(timeout),
            };
            play(path, options, quiet)
        }
        BagCommand::Replay {
            path,
            tolerance,
            bat,
            ball,
            modes,
            time_step,
            default_modes,
            default_bat,
            all,
            json,
            skip_damaged,
        } => {
            // A what-if names presets: check them here so a typo is blamed on the flag, not on the bag.
            for (flag, name, known) in [
                ("--bat", &bat, crate::physics::Bat::preset_names()),
                ("--ball", &ball, crate::physics::Ball::preset_names()),
                ("--default-bat", &default_bat, crate::physics::Bat::preset_names()),
            ] {
                if let Some(name) = name.as_deref().filter(|n| !known.contains(n)) {
                    anyhow::bail!("{flag} '{name}' is not a preset (presets: {})", known.join(", "));
                }
            }
            let skipped = check_damage(&path, skip_damaged)?;
            let what_if = bag::replay::WhatIf { bat, ball, modes };
            replay(path, tolerance, what_if, (time_step, default_modes, default_bat), all, json)?;
            if let Some(skipped) = skipped {
                eprintln!("skipped (--skip-damaged): {skipped}");
            }
            Ok(())
        }
    }
}

/// BagError's message already includes its I/O cause; flatten it so anyhow's chain does not print it twice.
fn flat(err: bag::BagError) -> anyhow::Error {
    anyhow::anyhow!("{err}")
}

/// Reads a bag once, streaming, to find damage before a tool uses it. Damage is an error naming every damaged
/// place unless `skip_damaged`; then it is listed on stderr and its one-line summary returned, for the tool
/// to repeat when it is done.
fn check_damage(path: &std::path::Path, skip_damaged: bool) -> anyhow::Result<Option<String>> {
    let files =
        bag::reader::bag_files(path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    let bar = progress(files.len() as u64, "checking");
    let mut reader =
        bag::reader::BagReader::open(path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    let mut seen = 0;
    while reader.next_message().map_err(flat)?.is_some() {
        if reader.scans().len() != seen {
            seen = reader.scans().len();
            bar.set_position(seen as u64);
        }
    }
    bar.finish_and_clear();
    let scans = reader.finish().map_err(flat)?;
    damage_verdict(&scans, skip_damaged)
}

/// Ok(None) for an undamaged bag; for a damaged one, an error listing the damage, or with `skip_damaged` the
/// list on stderr and Ok(summary).
fn damage_verdict(scans: &[bag::reader::FileScan], skip_damaged: bool) -> anyhow::Result<Option<String>> {
    let damage = bag::reader::damage_of(scans);
    if damage.is_empty() {
        return Ok(None);
    }
    let details = damage.iter().map(|d| format!("  {d}")).collect::<Vec<_>>().join("\n");
    let summary = format!("damaged bag: {}", bag::reader::damage_summary(scans));
    if skip_damaged {
        eprintln!("{summary}; going on without it (--skip-damaged):\n{details}");
        Ok(Some(summary))
    } else {
        Err(flat(bag::BagError::Damaged { summary, details }))
    }
}

/// A spinner/bar on stderr, only when stderr is a terminal (scripts and tests get clean output).
pub(crate) fn progress(len: u64, what: &str) -> indicatif::ProgressBar {
    if !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    let style = indicatif::ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} {elapsed}")
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    bar.set_style(style.progress_chars("=> "));
    bar.set_message(what.to_string());
    bar
}

fn info(path: PathBuf, json: bool, skip_damaged: bool) -> anyhow::Result<()> {
    let files =
        bag::reader::bag_files(&path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    let bar = progress(files.len() as u64, "scanning");
    // Every file is checked (regular file, MCAP magic) before any is read.
    bag::reader::BagReader::open(&path).map_err(flat)?;
    let mut scans = Vec::new();
    for file in &files {
        scans.push(
            bag::reader::scan_file(file, |_| {})
                .map_err(flat)
                .with_context(|| format!("reading {}", file.display()))?,
        );
        bar.inc(1);
    }
    bar.finish_and_clear();
    let info = bag::info::info_of(&scans);
    if json {
        crate::outln!("{}", serde_json::to_string_pretty(&info)?)?;
    } else {
        crate::cli::common::emit(&info.to_string())?;
    }
    damage_verdict(&scans, skip_damaged)?;
    Ok(())
}

fn recover(path: PathBuf, output: Option<PathBuf>) -> anyhow::Result<()> {
    let files =
        bag::reader::bag_files(&path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    let bar = progress(files.len() as u64, "recovering");
    let recovery = bag::recover::recover(&path, output.as_deref(), |_| bar.inc(1))
        .map_err(flat)
        .with_context(|| format!("recovering {}", path.display()))?;
    bar.finish_and_clear();
    for file in &recovery.files {
        let name = file.path.display();
        for damage in &file.damage {
            crate::outln!("{name}: dropped: {damage}")?;
        }
        let lost = match (file.lost_messages, file.lost_messages_unknown) {
            (n, false) => format!("{n} messages"),
            (n, true) => format!("at least {n} messages (the rest of the count is unknown)"),
        };
        let kept_in = match file.layout {
            Some(bag::McapLayout::Unchunked) => "unchunked".to_string(),
            _ => format!("in {} intact chunks", file.chunks),
        };
        let state = if file.complete { "finished but damaged" } else { "unfinished (no summary)" };
        match (&file.output, file.rebuilt) {
            (Some(out), true) => crate::outln!(
                "{name}: {state}: rebuilt as {} — kept {} messages {kept_in}; dropped {lost}, {} bytes of cut-off tail \
                 and {} damaged chunks",
                out.display(),
                file.messages,
                file.dropped_tail_bytes,
                file.dropped_corrupt_chunks
            )?,
            (Some(out), false) => crate::outln!(
                "{name}: finished and undamaged ({} messages): copied as {}",
                file.messages,
                out.display()
            )?,
            (None, _) => {
                crate::outln!("{name}: finished and undamaged ({} messages): nothing to recover", file.messages)?
            }
        }
    }
    match &recovery.output {
        Some(out) if path.is_dir() => crate::outln!(
            "{}: repaired copy written to {} (metadata.yaml rebuilt); the original is unchanged",
            path.display(),
            out.display()
        )?,
        Some(out) => {
            crate::outln!("{}: repaired copy written to {}; the original is unchanged", path.display(), out.display())?
        }
        None => crate::outln!("{}: nothing to recover, nothing written", path.display())?,
    }
    Ok(())
}

fn export(path: PathBuf, output: Option<PathBuf>, skipped: Option<String>) -> anyhow::Result<()> {
    let (rows, counts) =
        bag::export::swing_rows(&path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    match &output {
        Some(file) => {
            let out = std::fs::File::create(file).with_context(|| format!("creating {}", file.display()))?;
            bag::export::write_csv(&rows, std::io::BufWriter::new(out)).map_err(flat)?;
        }
        None => bag::export::write_csv(&rows, super::common::Stdout::default()).map_err(flat)?,
    }
    eprintln!(
        "exported {} swings ({} with ExitVelocity, {} with ModalEnergies; {} outputs without their swing, {} undecodable messages skipped)",
        counts.swings, counts.matched_exit_velocities, counts.matched_modal_energies, counts.orphan_outputs, counts.undecodable
    );
    if let Some(skipped) = skipped {
        eprintln!("skipped (--skip-damaged): {skipped}");
    }
    Ok(())
}

type SettingOverrides = (Option<f64>, Option<usize>, Option<String>);

fn replay(
    path: PathBuf,
    tolerance: f64,
    what_if: bag::replay::WhatIf,
    (time_step, default_modes, default_bat): SettingOverrides,
    all: bool,
    json: bool,
) -> anyhow::Result<()> {
    use bag::replay::Verdict;
    let mut settings = bag::replay::recorded_settings(&path)
        .map_err(flat)
        .with_context(|| format!("reading bag {}", path.display()))?;
    if let Some(v) = time_step {
        settings.time_step = v;
    }
    if let Some(v) = default_modes {
        settings.default_modes = v;
    }
    if let Some(v) = default_bat {
        settings.default_bat = v;
    }
    let bar = progress(0, "replaying");
    let report = bag::replay::replay(&path, &settings, &what_if, tolerance, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
    .map_err(flat)
    .with_context(|| format!("replaying {}", path.display()))?;
    bar.finish_and_clear();
    let (matched, differ, unrecorded) = report.tally();
    if json {
        crate::outln!("{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        let show_all = all || report.rows.len() <= 40;
        crate::outln!(
            "{:<10} {:>9} {:<12} {:<10} {:>14} {:>14} {:>12} {:>10}  verdict",
            "namespace",
            "swing_id",
            "bat",
            "ball",
            "recorded v_f",
            "replayed v_f",
            "Δ v_f",
            "worst rel"
        )?;
        let mut shown = 0;
        for row in &report.rows {
            if !show_all && (row.verdict != Verdict::Differs || shown >= 40) {
                continue;
            }
            shown += 1;
            let verdict = match row.verdict {
                Verdict::Match => "match".to_string(),
                Verdict::NotRecorded => "no recorded output".to_string(),
                Verdict::Differs => {
                    let first = &row.differences[0];
                    format!(
                        "DIFFERS ({} fields; e.g. {}: {} → {})",
                        row.differences.len(),
                        first.field,
                        first.recorded,
                        first.replayed
                    )
                }
            };
            crate::outln!(
                "{:<10} {:>9} {:<12} {:<10} {:>14.6} {:>14.6} {:>12.3e} {:>10.2e}  {verdict}",
                row.namespace,
                row.swing_id,
                row.bat_id,
                row.ball_id,
                row.recorded_exit_speed,
                row.replayed_exit_speed,
                row.replayed_exit_speed - row.recorded_exit_speed,
                row.worst_relative
            )?;
        }
        let tol = if report.tolerance == 0.0 {
            "bit-exact".to_string()
        } else {
            format!("relative tolerance {}", report.tolerance)
        };
        let s = &report.settings;
        crate::outln!(
            "{} swings: {matched} match, {differ} differ ({tol}), {unrecorded} without recorded output. Settings: default_bat {}, default_modes {}, time_step {} s, max_bats {}, max_balls {}, max_bat_slices {}. Bag written by: {}",
            report.rows.len(),
            s.default_bat,
            s.default_modes,
            s.time_step,
            s.max_bats,
            s.max_balls,
            s.max_bat_slices,
            report.recorded_by
        )?;
    }
    if report.what_if {
        crate::outln!("what-if replay (--bat/--ball/--modes): differences are the answer, not a failure")?;
        return Ok(());
    }
    if differ > 0 {
        anyhow::bail!("{differ} of {} swings differ from the recording beyond the tolerance", report.rows.len());
    }
    Ok(())
}

fn play(path: PathBuf, options: crate::play::PlayOptions, quiet: bool) -> anyhow::Result<()> {
    let stop = crate::ros::interrupt_flag();
    let total = crate::play::schedule(&path, &options.topics, options.rate).map_err(flat)?.len() as u64;
    let bar = if quiet { progress(total, "playing") } else { indicatif::ProgressBar::hidden() };
    let mut listing = super::common::Stdout::default();
    let stats = crate::play::play(&path, &options, &stop, |item| {
        bar.inc(1);
        if !quiet {
            // The listing is a courtesy: a stdout that fails must not stop what is being published.
            let _ = writeln!(listing, "{:>10.3} s  {}  ({} bytes)", item.at.as_secs_f64(), item.topic, item.cdr.len());
        }
    })
    .map_err(flat)
    .with_context(|| format!("playing {}", path.display()))?;
    bar.finish_and_clear();
    eprintln!("published {} messages in {} pass(es)", stats.published, stats.passes);
    Ok(())
}
