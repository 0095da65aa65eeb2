//! `sweetspot bag …`: inspect, recover, export, replay and play recorded bags.

use std::io::IsTerminal;
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
    },
    /// Rebuild files cut off by a crash (no summary/footer), keeping every complete chunk, and rewrite
    /// metadata.yaml. Originals are kept as `<file>.broken`.
    Recover {
        /// Bag directory or .mcap file.
        path: PathBuf,
    },
    /// One row per recorded swing: its inputs joined with the ExitVelocity and ModalEnergies computed for
    /// it (matched by namespace and swing_id).
    Export {
        /// Bag directory or .mcap file.
        path: PathBuf,
        /// Write CSV (the only format so far; required so that future formats stay explicit).
        #[arg(long, required = true)]
        csv: bool,
        /// Output file (default: stdout).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
}

/// Runs one `bag` subcommand.
pub fn run(cmd: BagCommand) -> anyhow::Result<()> {
    match cmd {
        BagCommand::Info { path, json } => info(path, json),
        BagCommand::Recover { path } => recover(path),
        BagCommand::Export { path, csv: _, output } => export(path, output),
    }
}

/// BagError's message already includes its I/O cause; flatten it so anyhow's chain does not print it twice.
fn flat(err: bag::BagError) -> anyhow::Error {
    anyhow::anyhow!("{err}")
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

fn info(path: PathBuf, json: bool) -> anyhow::Result<()> {
    let files = bag::reader::bag_files(&path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    let bar = progress(files.len() as u64, "scanning");
    let mut scans = Vec::new();
    for file in &files {
        scans.push(bag::reader::scan_file(file, |_| {}).map_err(flat).with_context(|| format!("reading {}", file.display()))?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let info = bag::info::info_of(&scans);
    if json {
        println!("{}", serde_json::to_string_pretty(&info)?);
    } else {
        print!("{info}");
    }
    Ok(())
}

fn recover(path: PathBuf) -> anyhow::Result<()> {
    let files = bag::reader::bag_files(&path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    let bar = progress(files.len() as u64, "recovering");
    let report = bag::recover::recover(&path, |_| bar.inc(1)).map_err(flat).with_context(|| format!("recovering {}", path.display()))?;
    bar.finish_and_clear();
    for file in &report {
        let name = file.path.display();
        if file.rebuilt {
            println!(
                "{name}: rebuilt — kept {} messages in {} complete chunks; dropped {} bytes of cut-off tail and {} corrupt chunks; original kept as {}",
                file.messages,
                file.chunks,
                file.dropped_tail_bytes,
                file.dropped_corrupt_chunks,
                file.original_kept_as.as_ref().map(|p| p.display().to_string()).unwrap_or_default()
            );
        } else {
            println!("{name}: complete, left as is ({} messages)", file.messages);
        }
    }
    if path.is_dir() {
        println!("{}: metadata.yaml rewritten", path.display());
    }
    Ok(())
}

fn export(path: PathBuf, output: Option<PathBuf>) -> anyhow::Result<()> {
    let (rows, counts) =
        bag::export::swing_rows(&path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    match &output {
        Some(file) => {
            let out = std::fs::File::create(file).with_context(|| format!("creating {}", file.display()))?;
            bag::export::write_csv(&rows, std::io::BufWriter::new(out)).map_err(flat)?;
        }
        None => bag::export::write_csv(&rows, std::io::stdout().lock()).map_err(flat)?,
    }
    eprintln!(
        "exported {} swings ({} with ExitVelocity, {} with ModalEnergies; {} outputs without their swing, {} undecodable messages skipped)",
        counts.swings, counts.matched_exit_velocities, counts.matched_modal_energies, counts.orphan_outputs, counts.undecodable
    );
    Ok(())
}
