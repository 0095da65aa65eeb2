//! The bag commands that need no DDS — `bag info`, `recover`, `export` and `replay` — and the damage check
//! every command reading a bag makes first: a bag read with a progress bar on stderr (on a terminal only), its
//! report ([`crate::bag::reports`]) on stdout.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::Context;

use crate::bag;
use crate::report::stdout::{emit, Stdout};

/// BagError's message already includes its I/O cause; flatten it so anyhow's chain does not print it twice.
pub fn flat(err: bag::BagError) -> anyhow::Error {
    anyhow::anyhow!("{err}")
}

/// A spinner/bar on stderr, only when stderr is a terminal (scripts and tests get clean output).
pub fn progress(len: u64, what: &str) -> indicatif::ProgressBar {
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

/// Reads every message of `path` once, streaming, with a progress bar (`what`) over its files; the scans.
fn scan(path: &Path, what: &str) -> anyhow::Result<Vec<bag::reader::FileScan>> {
    let listing =
        bag::reader::bag_listing(path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    let bar = progress(listing.files.len() as u64, what);
    // Every file is checked (regular file, MCAP magic) before any is read.
    let mut reader =
        bag::reader::BagReader::open(path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    note_listing(&reader);
    let mut seen = 0;
    while reader.next_message().map_err(flat)?.is_some() {
        if reader.scans().len() != seen {
            seen = reader.scans().len();
            bar.set_position(seen as u64);
        }
    }
    bar.finish_and_clear();
    reader.finish().map_err(flat)
}

/// Reads a bag once, streaming, to find damage before a tool uses it. Damage is an error naming every damaged
/// place unless `skip_damaged`; then it is listed on stderr and its one-line summary returned, for the tool
/// to repeat when it is done.
pub fn check_damage(path: &Path, skip_damaged: bool) -> anyhow::Result<Option<String>> {
    damage_verdict(&scan(path, "checking")?, skip_damaged)
}

/// Names the `.mcap` files of a bag directory that its metadata.yaml does not list (they are not read), and
/// those it lists more than once (read once).
fn note_listing(reader: &bag::reader::BagReader) {
    for file in reader.stray() {
        eprintln!("{}: not listed in metadata.yaml: left out (not part of the bag)", file.display());
    }
    for duplicate in reader.duplicates() {
        eprintln!("warning: {duplicate}");
    }
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

/// `bag info`: topics, types, counts, duration and size, as `ros2 bag info` lays them out or as JSON; a
/// damaged bag fails after its listing unless `skip_damaged`.
pub fn info(path: &Path, json: bool, skip_damaged: bool) -> anyhow::Result<()> {
    let scans = scan(path, "scanning")?;
    let info = bag::info::info_of(&scans);
    if json {
        crate::outln!("{}", serde_json::to_string_pretty(&info)?)?;
    } else {
        emit(&info.to_string())?;
    }
    damage_verdict(&scans, skip_damaged)?;
    Ok(())
}

/// `bag recover`: a repaired copy of `path` beside it or at `output` (which must not exist), and what was kept
/// and dropped.
pub fn recover(path: &Path, output: Option<&Path>) -> anyhow::Result<()> {
    if let Some(out) = output {
        crate::files::refuse_clobber("-o/--output", out, &[], &[path.to_path_buf()]).map_err(anyhow::Error::msg)?;
    }
    // Recovery reads a directory whatever its metadata.yaml says (rebuilding that is part of its job).
    let files = match bag::reader::bag_listing(path) {
        Ok(listing) => listing.files.len(),
        Err(_) if path.is_dir() => bag::reader::mcap_files_in_dir(path).map_or(0, |f| f.len()),
        Err(_) => 1,
    };
    let bar = progress(files as u64, "recovering");
    let recovery = bag::recover::recover(path, output, |_| bar.inc(1))
        .map_err(flat)
        .with_context(|| format!("recovering {}", path.display()))?;
    bar.finish_and_clear();
    emit(&bag::reports::recovery_report(&recovery, path))
}

/// `bag export`: one CSV row per recorded swing, to `output` or stdout.
pub fn export(path: &Path, output: Option<&Path>, skip_damaged: bool) -> anyhow::Result<()> {
    let skipped = check_damage(path, skip_damaged)?;
    if let Some(file) = output {
        crate::files::refuse_clobber("-o/--output", file, &[], &[path.to_path_buf()]).map_err(anyhow::Error::msg)?;
    }
    let (rows, counts) =
        bag::export::swing_rows(path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    if !counts.has_swing_topic() {
        anyhow::bail!("{}", bag::reports::no_swing_topics(path, &counts));
    }
    match output {
        Some(file) => {
            let out = std::fs::File::create(file).with_context(|| format!("creating {}", file.display()))?;
            bag::export::write_csv(&rows, std::io::BufWriter::new(out)).map_err(flat)?;
        }
        None => bag::export::write_csv(&rows, Stdout::default()).map_err(flat)?,
    }
    eprintln!("{}", bag::reports::export_summary(&counts));
    if let Some(skipped) = skipped {
        eprintln!("skipped (--skip-damaged): {skipped}");
    }
    Ok(())
}

/// What `bag replay` checks and how it reports.
#[derive(Debug, Clone)]
pub struct ReplayRequest {
    /// The bag.
    pub path: PathBuf,
    /// Relative tolerance (0: bit-exact).
    pub tolerance: f64,
    /// Presets used for every swing instead of the recorded ones.
    pub what_if: bag::replay::WhatIf,
    /// The node settings over the bag's: time_step, default_modes, default_bat.
    pub time_step: Option<f64>,
    /// See `time_step`.
    pub default_modes: Option<usize>,
    /// See `time_step`.
    pub default_bat: Option<String>,
    /// Print every swing.
    pub all: bool,
    /// Print JSON.
    pub json: bool,
    /// Go on past damaged chunks.
    pub skip_damaged: bool,
}

/// `bag replay`: the physics re-run on every recorded swing and compared with the recording; an error when a
/// swing differs beyond the tolerance or could not be checked (never for a what-if).
pub fn replay(request: ReplayRequest) -> anyhow::Result<()> {
    let w = &request.what_if;
    // A what-if names presets: check them here so a typo is blamed on the flag, not on the bag.
    for (flag, name, known) in [
        ("--bat", &w.bat, crate::physics::Bat::preset_names()),
        ("--ball", &w.ball, crate::physics::Ball::preset_names()),
        ("--default-bat", &request.default_bat, crate::physics::Bat::preset_names()),
    ] {
        if let Some(name) = name.as_deref().filter(|n| !known.contains(n)) {
            anyhow::bail!("{flag} '{name}' is not a preset (presets: {})", known.join(", "));
        }
    }
    let skipped = check_damage(&request.path, request.skip_damaged)?;
    let report = replay_report(&request)?;
    if request.json {
        crate::outln!("{}", serde_json::to_string_pretty(&report)?)?;
    } else {
        emit(&bag::reports::replay_table(&report, request.all))?;
    }
    replay_verdict(&report)?;
    if let Some(skipped) = skipped {
        eprintln!("skipped (--skip-damaged): {skipped}");
    }
    Ok(())
}

/// The replay of `request.path` under the recorded settings with the request's overrides.
fn replay_report(request: &ReplayRequest) -> anyhow::Result<bag::replay::ReplayReport> {
    let path = &request.path;
    let mut settings = bag::replay::recorded_settings(path)
        .map_err(flat)
        .with_context(|| format!("reading bag {}", path.display()))?;
    if let Some(v) = request.time_step {
        settings.time_step = v;
    }
    if let Some(v) = request.default_modes {
        settings.default_modes = v;
    }
    if let Some(v) = request.default_bat.clone() {
        settings.default_bat = v;
    }
    let bar = progress(0, "replaying");
    let report = bag::replay::replay(path, &settings, &request.what_if, request.tolerance, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
    .map_err(flat)
    .with_context(|| format!("replaying {}", path.display()))?;
    bar.finish_and_clear();
    Ok(report)
}

/// Ok for a replay that matched (or a what-if, whose differences are the answer); an error naming the swings
/// that differ or could not be checked.
fn replay_verdict(report: &bag::replay::ReplayReport) -> anyhow::Result<()> {
    if report.what_if {
        crate::outln!("what-if replay (--bat/--ball/--modes): differences are the answer, not a failure")?;
        return Ok(());
    }
    let (_, differ, _) = report.tally();
    let (missing, what) = report.missing_inputs();
    if missing > 0 {
        eprintln!(
            "{missing} swings were answered OK by the node with params the bag does not hold ({}): recorded without \
             them (e.g. `bag record` not given /ball/params or /bat/params, or started after they were sent), so \
             they cannot be checked",
            what.join(", ")
        );
    }
    if differ > 0 {
        anyhow::bail!("{differ} of {} swings differ from the recording beyond the tolerance", report.rows.len());
    }
    if missing > 0 {
        anyhow::bail!("{missing} of {} swings could not be checked: the bag lacks their params", report.rows.len());
    }
    Ok(())
}
