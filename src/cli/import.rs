//! `sweetspot import [FORMAT] FILE… -o DIR`: tracker exports into a rosbag2 bag (see [`crate::import`]);
//! `--pub` then plays that bag to a running node with `bag play`'s publisher ([`crate::play`]), at the rows'
//! pace or `--rate`, the bag in a temporary directory unless `-o` keeps it.

use std::path::PathBuf;

use anyhow::{anyhow, bail, Context, Result};
use clap::Args;

use super::common::{plural, print_json, resolve_bat};
use super::compare::{batter_from_spec, load_batter_file, BatterSpec};
use crate::import::mapped::ColumnMap;
use crate::import::{import_files, Format, ImportOptions, ImportReport};
use crate::model::convert::{params_from_ball, params_from_bat, params_of_preset};
use crate::msgs::std_msgs::msg::Header;
use crate::physics::{Ball, Bat};

/// Arguments of `sweetspot import`.
#[derive(Debug, Args)]
#[command(after_help = "Examples:
  sweetspot import trackman game.csv -o bags/game            # TrackMan Baseball CSV export
  sweetspot import savant_2025.csv -o bags/savant            # the format is detected from the header
  sweetspot import a.csv b.csv --batter me.toml --bat torpedo -o bags/lab
  sweetspot locate bags/game                                 # where on the bat each ball was hit
  sweetspot import trackman game.csv --pub                   # to a running node, at the recorded pace
  sweetspot import trackman game.csv --pub --rate 2 -o bags/game   # 2 swings/s, and keep the bag
  sweetspot import trackman game.csv --pub --ns /rig3        # to the node of namespace /rig3
  sweetspot import hittrax tee_work.csv --tee -o bags/tee    # a HitTrax session off a tee (Pitch 0)

Rows the bat did not hit, or without a pitch speed, are skipped and counted by reason; rows with a value
out of range (a negative or absurd speed, or a column in other units) are refused with file and line.
What no tracker measures (impact point, undercut; bat speed for TrackMan and HitTrax) is filled in from the batter
and marked assumed in the bag (import_rows.csv beside the MCAP file, custom_data sweetspot/import/*).
The 3-D columns are read too: TrackMan Direction, HitSpinAxis, BatterSide; Savant stand, attack_direction,
swing_path_tilt, hc_x/hc_y (spray angle, spin axis, batter side, swing direction, bat tilt: docs/rig-data.md).
--pub plays the imported bag as `bag play` does (on /bat/params, /ball/params, /swing, under --ns; it waits
for the node's subscriptions discovery shows, at most --timeout); without -o no bag is kept.")]
pub struct ImportArgs {
    /// [FORMAT] FILE…: the exports (CSV); a first word `trackman`, `statcast` or `hittrax` that is not a file
    /// forces the format, as --format does.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<String>,
    /// The bag directory to create [default: bags/import_<UTC time>; with --pub, none is kept].
    #[arg(short = 'o', long, value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Force the format (trackman, statcast, hittrax) instead of detecting it from each header.
    #[arg(long, value_name = "FORMAT")]
    pub format: Option<String>,
    /// The bat the swings were made with: a preset (r161, r161-corked, aluminum, torpedo) or a bat file (.toml).
    #[arg(long, value_name = "PRESET|FILE", default_value = "r161")]
    pub bat: String,
    /// The ball: a preset (baseball, bbcor, mlb, mlb2024: the game ball fitted to the 2024 MLB season).
    #[arg(long, value_name = "PRESET", default_value = crate::physics::ball::GAME_BALL)]
    pub ball: String,
    /// Batter file (as `compare --batter` reads): its swing stands in for a bat speed the tracker did not
    /// measure, and its pivot splits a measured one [default: the Statcast-average batter].
    #[arg(long, value_name = "FILE")]
    pub batter: Option<PathBuf>,
    /// Undercut given to every swing, m (no tracker measures it); `nan` leaves it unmeasured for
    /// `calibrate --fit-tangential` (the node and `bag replay` then refuse the swings).
    #[arg(long, value_name = "M", default_value_t = 0.0, allow_negative_numbers = true)]
    pub undercut: f64,
    /// The session was hit off a tee: a pitch speed of 0 is a ball at rest (no spin), not a speed nobody
    /// entered (HitTrax writes 0 for both; without --tee those rows are skipped as not measured).
    #[arg(long)]
    pub tee: bool,
    /// A mapping file (TOML) for a CSV of any other tracker (Rapsodo, …): `name = "…"`, a `[columns]` table
    /// naming the export's column for each of pitch_speed and exit_speed (required), launch_angle, spin,
    /// bat_speed, attack_angle, pitch_angle, time, batter, and an optional `[units]` table (speeds mph, km/h,
    /// m/s, ft/s; angles deg, rad; spin rpm, rad/s). docs/file-formats.md shows a whole file.
    #[arg(long, value_name = "FILE", conflicts_with = "format")]
    pub map: Option<PathBuf>,
    /// Write one batter file per batter with measured bat speeds (Statcast bat tracking) into DIR, as
    /// `compare --batter` and `import --batter` read: their mean bat speed (6 in from the head) and swing
    /// length with this import's bat as the reference bat, the rest from --batter.
    #[arg(long, value_name = "DIR")]
    pub batter_out: Option<PathBuf>,
    /// Print one JSON document instead of the summary (its `bag` null with --pub and no -o).
    #[arg(long)]
    pub json: bool,
    /// Send the swings (after the bat and ball, latched) to a running node over DDS, at the pace of the
    /// rows' times (header.stamp), as `bag play` plays a bag.
    #[arg(long = "pub")]
    pub publish: bool,
    /// With --pub: this many swings per second instead of the recorded pace (a rig's rate, at most 10000).
    #[arg(long, value_name = "HZ", requires = "publish", value_parser = super::common::swing_rate_hz)]
    pub rate: Option<f64>,
    /// With --pub: namespace of the node the swings go to (e.g. /rig3), as `rig --namespace`.
    #[arg(long, visible_alias = "ns", default_value = "/", value_name = "NS", requires = "publish")]
    pub namespace: String,
    /// With --pub: start at once, without waiting for the node's subscriptions to match.
    #[arg(long, requires = "publish")]
    pub no_wait: bool,
    /// With --pub: seconds to wait for subscribers, and for acknowledgments at the end (inf: no limit).
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0, requires = "publish",
          value_parser = super::common::seconds_above_zero)]
    pub timeout: f64,
}

/// Runs `sweetspot import`.
pub fn run(args: ImportArgs) -> Result<()> {
    let (format, files) = format_and_files(&args)?;
    let mut options = import_options(&args, format)?;
    // The imported bag's topics are the root namespace's; --namespace moves them to the node's (checked
    // before anything is written).
    let names = crate::rig::dds::TopicNames::in_namespace(&args.namespace)?;
    // --pub without -o plays a bag nobody keeps: it lives in a temporary directory, removed when done.
    let scratch = match (&args.output, args.publish) {
        (None, true) => Some(tempfile::tempdir().context("--pub: creating a temporary directory for the bag")?),
        _ => None,
    };
    let output = match (&args.output, &scratch) {
        (Some(dir), _) => dir.clone(),
        (None, Some(tmp)) => tmp.path().join("import"),
        (None, None) => {
            crate::bag::default_bag_dir(std::path::Path::new("bags"), "import", std::time::SystemTime::now())
        }
    };
    refuse_output(&args, &files, &output)?;
    options.map = args.map.as_deref().map(ColumnMap::load).transpose().map_err(|e| anyhow!("--map: {e}"))?;
    if options.map.is_some() && format.is_some() {
        bail!("--map reads every file through the map: give no format with it");
    }
    let paths: Vec<PathBuf> = files.iter().map(PathBuf::from).collect();
    let report = import_files(&paths, &output, &options).map_err(|e| anyhow!("{e}"))?;
    if let Some(dir) = &args.batter_out {
        write_batters(&report, dir, &args.bat, &options)?;
    }
    if args.json {
        let mut document = serde_json::to_value(&report).context("cannot serialise the output as JSON")?;
        if scratch.is_some() {
            // The bag played from a temporary directory that is gone by the time anyone reads this.
            document["bag"] = serde_json::Value::Null;
        }
        print_json(&document)?;
    } else {
        print_report(&report, scratch.is_none())?;
    }
    if args.publish {
        publish(&args, &report, names, output)?;
    }
    Ok(())
}

/// The format (the first word, if it names one and no file, or `--format`) and the export files.
fn format_and_files(args: &ImportArgs) -> Result<(Option<Format>, Vec<String>)> {
    let mut files = args.files.clone();
    let mut format =
        args.format.as_deref().map(str::parse::<Format>).transpose().map_err(|e| anyhow!("--format: {e}"))?;
    if let Some(first) = files.first() {
        if let Ok(word) = first.parse::<Format>() {
            if !std::path::Path::new(first).exists() {
                if format.is_some_and(|f| f != word) {
                    bail!("format '{first}' and --format {} disagree", args.format.as_deref().unwrap_or(""));
                }
                format = Some(word);
                files.remove(0);
            }
        }
    }
    if files.is_empty() {
        bail!("no export file given");
    }
    Ok((format, files))
}

/// The import's bat, ball and batter from the flags (the column map is read later, after the output check).
fn import_options(args: &ImportArgs, format: Option<Format>) -> Result<ImportOptions> {
    let bat = resolve_bat(&args.bat, None)?;
    let bat_params = if Bat::preset_names().contains(&args.bat.as_str()) {
        params_of_preset(&args.bat, &args.bat, Header::default())
    } else {
        params_from_bat(&bat.name, &bat, 0, Header::default())
    };
    let ball = Ball::preset(&args.ball).with_context(|| format!("--ball {}", crate::files::echo(&args.ball)))?;
    let ball_params = params_from_ball(&args.ball, &ball, None, Header::default());
    let (batter, _) = match &args.batter {
        Some(path) => load_batter_file(path)?,
        None => batter_from_spec(&BatterSpec::default(), None)?,
    };
    Ok(ImportOptions {
        format,
        bat,
        bat_params,
        ball_params,
        batter,
        undercut: args.undercut,
        map: None,
        tee: args.tee,
    })
}

/// Refuses an output directory that exists or is one of the inputs.
fn refuse_output(args: &ImportArgs, files: &[String], output: &std::path::Path) -> Result<()> {
    // Every input named here (the exports, the batter file, the column map, a bat file and its profile —
    // those read above are noted by crate::files) before the bag directory, which must be new.
    let mut inputs: Vec<PathBuf> = files.iter().map(PathBuf::from).collect();
    inputs.extend(args.batter.iter().cloned());
    inputs.extend(args.map.iter().cloned());
    crate::files::refuse_clobber("-o/--output", output, &inputs, &[]).map_err(anyhow::Error::msg)?;
    if output.exists() {
        bail!("{}: already exists (the bag directory must be new)", output.display());
    }
    Ok(())
}

/// `--pub`: plays the imported bag to a running node, on its namespace's topics.
fn publish(
    args: &ImportArgs,
    report: &ImportReport,
    names: crate::rig::dds::TopicNames,
    output: PathBuf,
) -> Result<()> {
    if report.swings == 0 {
        bail!("--pub: no row became a swing, nothing to send");
    }
    let seconds = crate::model::time::saturating_secs;
    let remaps = [
        (crate::import::topics::BAT_PARAMS, names.bat_params),
        (crate::import::topics::BALL_PARAMS, names.ball_params),
        (crate::import::topics::SWING, names.swing),
    ];
    let options = crate::play::PlayOptions {
        remaps: remaps.into_iter().map(|(from, to)| (from.to_string(), to)).collect(),
        wait_discovered: !args.no_wait,
        timeout: seconds(args.timeout),
        interval: args.rate.map(crate::model::time::period_of),
        ..crate::play::PlayOptions::new(1.0)
    };
    crate::play::console::play(output, options, true)?;
    Ok(())
}

/// One batter file per batter of the report.
fn write_batters(report: &ImportReport, dir: &std::path::Path, bat: &str, options: &ImportOptions) -> Result<()> {
    let inputs: Vec<PathBuf> = report.files.iter().map(|f| f.path.clone()).collect();
    crate::files::refuse_clobber("--batter-out", dir, &inputs, &[]).map_err(anyhow::Error::msg)?;
    std::fs::create_dir_all(dir).with_context(|| format!("--batter-out {}", dir.display()))?;
    // The bat is named as given; a bat file is named by its absolute path so the batter file works anywhere.
    let reference_bat = if Bat::preset_names().contains(&bat) {
        bat.to_string()
    } else {
        std::fs::canonicalize(bat).map_or(bat.to_string(), |p| p.display().to_string())
    };
    let reference = &options.batter.reference;
    let pivot_z = if reference.bat_angular_speed != 0.0 {
        reference.bat.center_of_mass - reference.bat_cm_speed / reference.bat_angular_speed
    } else {
        0.0
    };
    if report.batters.is_empty() {
        bail!("--batter-out: no row has a measured bat speed (Statcast bat_speed), so there is no batter to write");
    }
    // Every batter gets a file of its own: two ids that spell the same file name are refused before any is
    // written (one would silently overwrite the other).
    let mut files: std::collections::BTreeMap<PathBuf, &String> = std::collections::BTreeMap::new();
    for name in report.batters.keys() {
        let path = dir.join(batter_file_name(name));
        if let Some(other) = files.insert(path.clone(), name) {
            bail!(
                "--batter-out: batters {other:?} and {name:?} would both be written to {}: refused, nothing written",
                path.display()
            );
        }
    }
    for (name, stats) in &report.batters {
        let spec = BatterSpec {
            reference_bat: Some(reference_bat.clone()),
            bat_speed: Some(stats.bat_speed),
            impact_from_barrel_end: Some(crate::import::BAT_SPEED_POINT_FROM_HEAD),
            pivot_z: Some(pivot_z),
            exponent: Some(options.batter.exponent),
            swing_length: stats.swing_length.is_finite().then_some(stats.swing_length),
            shape: Some(options.batter.shape),
        };
        let path = dir.join(batter_file_name(name));
        // The exports, and (noted by crate::files as they were read) the batter file, the map, the bat file.
        crate::files::refuse_clobber("--batter-out", &path, &inputs, &[]).map_err(anyhow::Error::msg)?;
        // The id is a CSV cell: quoted and escaped (a line break in it must not become a line of the file).
        let text = format!(
            "# batter {}: mean of {} and {} (sweetspot import)\n{}",
            escaped(name),
            plural(stats.swings, "measured bat speed"),
            plural(stats.swing_lengths, "swing length"),
            toml::to_string(&spec).context("batter file")?
        );
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
        crate::outln!(
            "batter {}: {}, {:.2} m/s → {}",
            escaped(name),
            plural(stats.swings, "swing"),
            stats.bat_speed,
            path.display()
        )?;
    }
    Ok(())
}

/// The file a batter's spec is written to: `batter_<id>.toml`, the id's characters other than ASCII letters,
/// digits, `-` and `_` as `_`.
fn batter_file_name(name: &str) -> String {
    let safe: String =
        name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect();
    format!("batter_{safe}.toml")
}

/// A batter id as one quoted line: control characters and quotes escaped.
fn escaped(name: &str) -> String {
    format!("{name:?}")
}

/// The summary on stdout; `kept` says whether the bag stays (not with --pub alone).
fn print_report(report: &ImportReport, kept: bool) -> Result<()> {
    crate::cli::common::emit(&report_text(report, kept))
}

/// The summary's text; `kept` says whether the bag stays (not with --pub alone).
fn report_text(report: &ImportReport, kept: bool) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    for file in &report.files {
        let _ = writeln!(
            out,
            "{}: {} export, {}, {}",
            file.path.display(),
            file.format.name(),
            plural(file.rows, "row"),
            plural(file.swings, "swing")
        );
    }
    if kept {
        let _ = writeln!(out, "{} written to {}", plural(report.swings, "swing"), report.bag.display());
    } else {
        let _ = writeln!(
            out,
            "{} imported into a temporary bag, not kept (-o DIR keeps it)",
            plural(report.swings, "swing")
        );
    }
    for (reason, count) in &report.skipped {
        let _ = writeln!(out, "  skipped {count:>6}: {reason}");
    }
    let refused: u64 = report.skipped.iter().filter(|(reason, _)| reason.ends_with("(refused)")).map(|(_, n)| n).sum();
    for line in &report.refused {
        let _ = writeln!(out, "  refused: {line}");
    }
    if refused > report.refused.len() as u64 {
        let _ = writeln!(
            out,
            "  refused: … {} more not listed (the first {} are)",
            refused - report.refused.len() as u64,
            report.refused.len()
        );
    }
    let assumed: Vec<String> = report.assumed.iter().map(|(k, n)| format!("{k} ({n})")).collect();
    if !assumed.is_empty() {
        let locate = if kept {
            format!("`sweetspot locate {}` finds it", report.bag.display())
        } else {
            "import with -o DIR to keep the bag, then `sweetspot locate DIR` finds it".to_string()
        };
        let _ = writeln!(
            out,
            "assumed, not measured: {} — impact_z = {:.4} m from the knob; {locate}",
            assumed.join(", "),
            report.impact_z
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::import::FileReport;

    fn report(swings: u64) -> ImportReport {
        ImportReport {
            bag: PathBuf::from("bags/game"),
            files: vec![FileReport { path: PathBuf::from("game.csv"), format: Format::TrackMan, rows: 1, swings }],
            swings,
            skipped: Default::default(),
            refused: Vec::new(),
            assumed: [("impact_z".to_string(), swings)].into_iter().collect(),
            impact_z: 0.68,
            batters: Default::default(),
        }
    }

    #[test]
    fn one_swing_is_one_swing_and_a_bag_not_kept_is_not_offered_to_locate() {
        let kept = report_text(&report(1), true);
        assert!(kept.contains("game.csv: trackman export, 1 row, 1 swing\n"), "{kept}");
        assert!(kept.contains("1 swing written to bags/game\n"), "{kept}");
        assert!(kept.contains("`sweetspot locate bags/game` finds it"), "{kept}");
        let gone = report_text(&report(2), false);
        assert!(gone.contains("2 swings imported into a temporary bag, not kept (-o DIR keeps it)"), "{gone}");
        assert!(!gone.contains("sweetspot locate bags") && !gone.contains("locate BAG"), "{gone}");
        assert!(gone.contains("import with -o DIR to keep the bag"), "{gone}");
    }
}
