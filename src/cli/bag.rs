//! `sweetspot bag …`: record, inspect, recover, export, replay and play bags.

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
    /// it (matched by namespace, swing_id and header stamp, wherever they lie in the bag).
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
        /// What if: use this preset bat for every swing (r161, r161-corked, aluminum, torpedo).
        #[arg(long, value_name = "PRESET")]
        bat: Option<String>,
        /// What if: use this preset ball for every swing (baseball, bbcor, mlb).
        #[arg(long, value_name = "PRESET")]
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
    /// Record ROS topics from DDS into a rosbag2 MCAP bag, like `ros2 bag record`, with the node's own writer.
    #[command(after_help = "\
Examples:
  sweetspot bag record -a                                  every topic, into rosbag2_YYYY_MM_DD-HH_MM_SS
  sweetspot bag record -a -o lab_session                   into ./lab_session
  sweetspot bag record /lab/swing /lab/exit_velocity       only these topics
  sweetspot bag record swing exit_velocity --ns /lab       relative names resolved in /lab
  sweetspot bag record -e '^/rig[0-9]+/' -b 100000000      topics matching a regex, a new file every 100 MB
  sweetspot bag record -a -s mcap --storage-preset-profile zstd_fast -d 600
  sweetspot bag record -a --qos-profile-overrides-path qos.yaml

Stops on Ctrl-C or SIGTERM and finishes the bag. Topics are picked up as their publishers are discovered;
every message is recorded as it travelled. Types generated from msgs/ get their ros2msg schema; other types
are recorded without one (said once per topic). Services and hidden topics (a name part starting with _) are
not recorded with -a/-e. Only the mcap storage exists: -s sqlite3 is refused.")]
    Record {
        /// Topics to record (relative names are resolved in the namespace).
        #[arg(value_name = "TOPIC")]
        topics: Vec<String>,
        /// Record every topic.
        #[arg(short = 'a', long)]
        all: bool,
        /// Record the topics whose fully-qualified name matches this regular expression.
        #[arg(short = 'e', long, value_name = "REGEX")]
        regex: Option<String>,
        /// Also record hidden topics (a name part starting with `_`) with -a or -e.
        #[arg(long)]
        include_hidden_topics: bool,
        /// The bag directory to create (default: rosbag2_YYYY_MM_DD-HH_MM_SS, local time).
        #[arg(short = 'o', long, value_name = "DIR")]
        output: Option<PathBuf>,
        /// Storage plugin: only mcap.
        #[arg(short = 's', long, value_name = "ID", default_value = "mcap")]
        storage: String,
        /// rosbag2's MCAP preset: none, fastwrite, zstd_fast or zstd_small.
        #[arg(long, value_name = "PROFILE", default_value = "none")]
        storage_preset_profile: String,
        /// Start a new file once the current one reaches this many bytes (0: never).
        #[arg(short = 'b', long, value_name = "BYTES", default_value_t = 0)]
        max_bag_size: u64,
        /// Start a new file after this many seconds of recording (0: never).
        #[arg(short = 'd', long, value_name = "SECONDS", default_value_t = 0.0,
              value_parser = super::common::seconds_at_least_zero)]
        max_bag_duration: f64,
        /// A rosbag2 YAML file of per-topic subscription QoS (history, depth, reliability, durability).
        #[arg(long, value_name = "FILE")]
        qos_profile_overrides_path: Option<PathBuf>,
        /// How often to look for new topics, milliseconds.
        #[arg(short = 'p', long, value_name = "MS", default_value_t = 100)]
        polling_interval: u64,
        /// Namespace for relative topic names (same as `--ros-args -r __ns:=NS`).
        #[arg(long, visible_alias = "namespace", value_name = "NS")]
        ns: Option<String>,
        /// ROS arguments (`-r __ns:=/rig3`), as for any ROS 2 node; must come last.
        #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS")]
        ros_args: Option<Vec<String>>,
    },
    /// Republish the recorded inputs (BatParams, BallParams, Swing) over DDS with their original timing;
    /// params recorded before the first swing go out first, latched (transient-local).
    #[command(after_help = "\
Examples:
  sweetspot bag play BAG                                  play once, at the recorded pace
  sweetspot bag play BAG -r 2 -l                          twice as fast, over and over until Ctrl-C
  sweetspot bag play BAG --topics /lab/swing              only the swings
  sweetspot bag play BAG --remap /lab/swing:=/test/swing  publish /lab/swing's messages on /test/swing
  sweetspot bag play BAG --ros-args -r /lab/swing:=/test/swing   the same, as ROS arguments
  sweetspot bag play BAG --start-offset 30                start 30 s (recorded time) into the bag
  sweetspot bag play BAG --clock                          also publish the bag's time on /clock at 40 Hz
  sweetspot bag play BAG --clock 100 --delay 2            /clock at 100 Hz, after waiting 2 s
  sweetspot bag play BAG --foxglove 8765 --no-dds         serve every topic to Foxglove (ws://localhost:8765) only

Before the first message it waits (at most --timeout) until the subscriptions discovery shows on each played
topic have matched, so a node already running misses nothing, and warns of topics nobody subscribes to
(--wait-subscribers N: wait for N per topic instead; --no-wait: start at once, as ros2 bag play does).
On a terminal, the space bar pauses and resumes playback (and /clock stands still meanwhile).
--start-offset skips the swings recorded before that point; params recorded before it still go out first,
so every swing meets the bat and ball in force when it was recorded.")]
    Play {
        /// Bag directory or .mcap file.
        path: PathBuf,
        /// Time scale: 2 plays twice as fast, 0.5 at half speed.
        #[arg(short = 'r', long, default_value_t = 1.0, value_parser = super::common::time_scale)]
        rate: f64,
        /// Start over when done, until interrupted.
        #[arg(short = 'l', long = "loop")]
        repeat: bool,
        /// Only these topics, as recorded (default: every input topic in the bag).
        #[arg(long, value_delimiter = ',', num_args = 1..)]
        topics: Vec<String>,
        /// Publish what was recorded on FROM on TO instead (repeatable), e.g. `--remap /lab/swing:=/swing`.
        #[arg(short = 'm', long = "remap", value_name = "FROM:=TO")]
        remap: Vec<String>,
        /// Start this many seconds (recorded time) after the bag's first message (finite).
        #[arg(long, value_name = "SECONDS", default_value_t = 0.0, value_parser = super::common::finite_seconds_at_least_zero)]
        start_offset: f64,
        /// Wait this many seconds before playing (before each pass with --loop; finite).
        #[arg(long, value_name = "SECONDS", default_value_t = 0.0, value_parser = super::common::finite_seconds_at_least_zero)]
        delay: f64,
        /// Publish rosgraph_msgs/Clock with the bag's time on /clock at HZ (40 without a value, as rosbag2).
        #[arg(long, value_name = "HZ", num_args = 0..=1, default_missing_value = "40", value_parser = super::common::rate_hz)]
        clock: Option<f64>,
        /// Wait until every topic has this many subscriptions before starting (default: wait until the
        /// subscriptions discovery shows have matched, at most --timeout, and warn of topics with none).
        #[arg(long, default_value_t = 0)]
        wait_subscribers: usize,
        /// Start publishing at once, without waiting for discovered subscribers to match, and exit 0 even when
        /// nobody listened (as `ros2 bag play`; without it a play no subscriber heard exits 1, as `pub` does).
        #[arg(long, conflicts_with = "wait_subscribers")]
        no_wait: bool,
        /// Seconds to wait for subscribers, and for acknowledgments at the end (inf: no limit).
        #[arg(long, default_value_t = 10.0, value_parser = super::common::seconds_above_zero)]
        timeout: f64,
        /// Do not print each message.
        #[arg(short, long)]
        quiet: bool,
        /// Go on past damaged chunks with everything intact around them (the damage is still listed).
        #[arg(long)]
        skip_damaged: bool,
        /// Also serve the bag (every topic, or --topics) on a Foxglove WebSocket server at [ADDR:]PORT
        /// (127.0.0.1 unless ADDR is given), with Foxglove's play, pause, seek and speed controls.
        #[arg(long, value_name = "[ADDR:]PORT")]
        foxglove: Option<String>,
        /// With --foxglove: serve only, no DDS output (playback then starts paused, for the client to start).
        #[arg(long, requires = "foxglove")]
        no_dds: bool,
        /// ROS arguments: `-r FROM:=TO` remaps topics as --remap does; must come last.
        #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS")]
        ros_args: Option<Vec<String>>,
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
        BagCommand::Record {
            topics,
            all,
            regex,
            include_hidden_topics,
            output,
            storage,
            storage_preset_profile,
            max_bag_size,
            max_bag_duration,
            qos_profile_overrides_path,
            polling_interval,
            ns,
            ros_args,
        } => {
            if storage != "mcap" {
                anyhow::bail!("-s/--storage {storage:?} is not available: sweetspot records MCAP only (-s mcap)");
            }
            if !all && regex.is_none() && topics.is_empty() {
                anyhow::bail!("nothing to record: pass -a/--all, topic names, or -e/--regex");
            }
            if polling_interval == 0 {
                anyhow::bail!("-p/--polling-interval must be at least 1 ms");
            }
            let regex = match regex {
                Some(r) => Some(regex::Regex::new(&r).map_err(|e| anyhow::anyhow!("-e/--regex {r:?}: {e}"))?),
                None => None,
            };
            let storage = bag::StorageOptions::preset(&storage_preset_profile)
                .map_err(|e| anyhow::anyhow!("--storage-preset-profile: {e}"))?;
            let qos_overrides = match &qos_profile_overrides_path {
                Some(path) => crate::record::QosOverrides::load(path)?,
                None => crate::record::QosOverrides::default(),
            };
            let options = crate::record::RecordOptions {
                output: output.unwrap_or_else(|| {
                    PathBuf::from(chrono::Local::now().format("rosbag2_%Y_%m_%d-%H_%M_%S").to_string())
                }),
                selection: crate::record::Selection {
                    all,
                    topics: record_topics(&topics, &ns, ros_args.as_deref().unwrap_or_default())?,
                    regex,
                    include_hidden: include_hidden_topics,
                },
                storage,
                max_bag_size: (max_bag_size > 0).then_some(max_bag_size),
                max_bag_duration: (max_bag_duration > 0.0)
                    .then(|| crate::model::time::saturating_secs(max_bag_duration)),
                qos_overrides,
                polling_interval: std::time::Duration::from_millis(polling_interval),
            };
            // Before anything starts (the overrides file, read above, is an input).
            crate::files::refuse_clobber("-o/--output", &options.output, &[], &[]).map_err(anyhow::Error::msg)?;
            record(options)
        }
        BagCommand::Play {
            path,
            rate,
            repeat,
            topics,
            remap,
            start_offset,
            delay,
            clock,
            wait_subscribers,
            no_wait,
            timeout,
            quiet,
            skip_damaged,
            foxglove,
            no_dds,
            ros_args,
        } => {
            check_damage(&path, skip_damaged)?;
            // Checked by their value parsers (model::time): --timeout inf waits for ever, the spans are finite.
            let seconds = crate::model::time::saturating_secs;
            let options = crate::play::PlayOptions {
                rate,
                repeat,
                topics,
                wait_subscribers,
                wait_discovered: !no_wait,
                timeout: seconds(timeout),
                remaps: play_remaps(&remap, ros_args.as_deref().unwrap_or_default())?,
                start_offset: seconds(start_offset),
                delay: seconds(delay),
                clock_hz: clock,
                paused: None,
                interval: None,
            };
            match foxglove {
                None => play(path, options, quiet),
                Some(bind) => {
                    let bind = crate::foxglove::Bind::parse(&bind).map_err(|e| anyhow::anyhow!("--foxglove: {e}"))?;
                    play_foxglove(path, options, bind, !no_dds, quiet)
                }
            }
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
pub(crate) fn check_damage(path: &std::path::Path, skip_damaged: bool) -> anyhow::Result<Option<String>> {
    let listing =
        bag::reader::bag_listing(path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    let bar = progress(listing.files.len() as u64, "checking");
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
    let scans = reader.finish().map_err(flat)?;
    damage_verdict(&scans, skip_damaged)
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
    let listing =
        bag::reader::bag_listing(&path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    let bar = progress(listing.files.len() as u64, "scanning");
    // Every file is checked (regular file, MCAP magic) before any is read.
    let mut reader =
        bag::reader::BagReader::open(&path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    note_listing(&reader);
    let mut seen = 0;
    while reader.next_message().map_err(flat)?.is_some() {
        if reader.scans().len() != seen {
            seen = reader.scans().len();
            bar.set_position(seen as u64);
        }
    }
    let scans = reader.finish().map_err(flat)?;
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
    if let Some(out) = &output {
        crate::files::refuse_clobber("-o/--output", out, &[], std::slice::from_ref(&path))
            .map_err(anyhow::Error::msg)?;
    }
    // Recovery reads a directory whatever its metadata.yaml says (rebuilding that is part of its job).
    let files = match bag::reader::bag_listing(&path) {
        Ok(listing) => listing.files.len(),
        Err(_) if path.is_dir() => bag::reader::mcap_files_in_dir(&path).map_or(0, |f| f.len()),
        Err(_) => 1,
    };
    let bar = progress(files as u64, "recovering");
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
    for missing in &recovery.missing_files {
        crate::outln!("{}: listed in metadata.yaml but missing: left out of the copy", missing.display())?;
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
    if let Some(file) = &output {
        crate::files::refuse_clobber("-o/--output", file, &[], std::slice::from_ref(&path))
            .map_err(anyhow::Error::msg)?;
    }
    let (rows, counts) =
        bag::export::swing_rows(&path).map_err(flat).with_context(|| format!("reading bag {}", path.display()))?;
    if !counts.has_swing_topic() {
        let found = if counts.topics.is_empty() {
            "it has no topics".to_string()
        } else {
            let listed: Vec<String> = counts
                .topics
                .iter()
                .map(|(name, type_name)| {
                    let shown = if type_name.is_empty() { "no schema" } else { type_name.as_str() };
                    format!("{name} ({shown})")
                })
                .collect();
            format!("its topics: {}", listed.join(", "))
        };
        anyhow::bail!(
            "{}: no swing topics (type {}) to export, nothing written; {found}",
            path.display(),
            <crate::msgs::sweetspot_msgs::msg::Swing as crate::msgs::RosMessage>::TYPE_NAME
        );
    }
    match &output {
        Some(file) => {
            let out = std::fs::File::create(file).with_context(|| format!("creating {}", file.display()))?;
            bag::export::write_csv(&rows, std::io::BufWriter::new(out)).map_err(flat)?;
        }
        None => bag::export::write_csv(&rows, super::common::Stdout::default()).map_err(flat)?,
    }
    eprintln!(
        "exported {} ({} with ExitVelocity, {} with ModalEnergies; {} outputs without their swing, {} undecodable messages skipped)",
        super::common::plural(counts.swings, "swing"), counts.matched_exit_velocities, counts.matched_modal_energies, counts.orphan_outputs, counts.undecodable
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
        // An imported or tracked session: its measurements against the model, beside replay's own check.
        let measured = report.measured_against_model();
        let measured_header = match measured {
            Some(_) => format!(" {:>12} {:>12}", "measured v_f", "meas − model"),
            None => String::new(),
        };
        crate::outln!(
            "{:<10} {:>9} {:<12} {:<10} {:>14} {:>14} {:>12} {:>10}{measured_header}  verdict",
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
                Verdict::MissingInput => {
                    format!("not checked: the bag lacks the {}", row.missing_input.as_deref().unwrap_or("params"))
                }
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
            let measured_cells = match measured {
                Some(_) => format!(
                    " {:>12.3} {:>12.3}",
                    row.measured_exit_speed,
                    row.measured_exit_speed - row.replayed_exit_speed
                ),
                None => String::new(),
            };
            crate::outln!(
                "{:<10} {:>9} {:<12} {:<10} {:>14.6} {:>14.6} {:>12.3e} {:>10.2e}{measured_cells}  {verdict}",
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
            "{} swings: {matched} match, {differ} differ ({tol}), {unrecorded} without recorded output. Settings: default_bat {}, default_ball {}, default_modes {}, time_step {} s, max_bats {}, max_balls {}, max_bat_slices {}. Bag written by: {}",
            report.rows.len(),
            s.default_bat,
            s.default_ball,
            s.default_modes,
            s.time_step,
            s.max_bats,
            s.max_balls,
            s.max_bat_slices,
            report.recorded_by
        )?;
        if let Some((n, mean, rms)) = measured {
            crate::outln!(
                "measured against model: {n} measured swings, measured − model exit speed mean {mean:+.2} m/s, RMS \
                 {rms:.2} m/s (for an imported session the model's inputs include assumed ones: `sweetspot calibrate` \
                 fits the ball to them, `sweetspot locate` the impact points)"
            )?;
        }
    }
    if report.what_if {
        crate::outln!("what-if replay (--bat/--ball/--modes): differences are the answer, not a failure")?;
        return Ok(());
    }
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

/// The topics named on the command line, fully qualified: `__ns` over `--ns` over `/`, as `pub`/`echo` do.
fn record_topics(topics: &[String], ns: &Option<String>, ros_args: &[String]) -> anyhow::Result<Vec<String>> {
    let parsed = crate::ros::args::RosArgs::parse(ros_args)?;
    let namespace = match ns {
        Some(n) => crate::ros::names::normalize_namespace(n)?,
        None => "/".to_string(),
    };
    let identity = parsed.identity("sweetspot_record", &namespace);
    let resolver = parsed.resolver(&identity);
    topics
        .iter()
        .map(|t| Ok(resolver.resolve(&crate::ros::resolve_topic(t, &identity.namespace, &identity.name)?)))
        .collect()
}

fn record(options: crate::record::RecordOptions) -> anyhow::Result<()> {
    let stop = crate::ros::interrupt_flag();
    for (topic, key) in options.qos_overrides.ignored() {
        eprintln!("--qos-profile-overrides-path: {topic}: {key} is accepted but not applied");
    }
    let stats = crate::record::record(&options, &stop, |event| match event {
        // Said once the bag directory exists, so a refused -o never reads as a recording.
        crate::record::RecordEvent::Started { dir } => eprintln!("recording to {} (Ctrl-C to stop)", dir.display()),
        crate::record::RecordEvent::Subscribed { topic, type_name, schema: true } => {
            eprintln!("subscribed to {topic} ({type_name})")
        }
        crate::record::RecordEvent::Subscribed { topic, type_name, schema: false } => eprintln!(
            "subscribed to {topic} ({type_name}): type not generated from msgs/, recorded as raw CDR without a \
             schema (readers can list it but not decode it)"
        ),
        crate::record::RecordEvent::Skipped { topic, reason } => eprintln!("skipped {topic}: {reason}"),
    })
    .with_context(|| format!("recording {}", options.output.display()))?;
    let total: u64 = stats.per_topic.values().sum();
    for (topic, count) in &stats.per_topic {
        eprintln!("  {topic}: {count} messages");
    }
    for topic in &options.selection.topics {
        if !stats.per_topic.contains_key(topic) {
            eprintln!("  {topic}: no publisher seen, nothing recorded");
        }
    }
    eprintln!(
        "recorded {total} messages on {} topics to {}{}",
        stats.per_topic.len(),
        options.output.display(),
        if stats.dropped > 0 {
            format!(" ({} dropped: the disk did not keep up)", stats.dropped)
        } else {
            String::new()
        }
    );
    if stats.late > 0 {
        eprintln!(
            "{} messages were taken from DDS more than {} ms after they arrived (the recorder stalled): written \
             with the log time of the message before them, so the bag stays in log-time order",
            stats.late,
            crate::record::REORDER_WINDOW.as_millis()
        );
    }
    Ok(())
}

/// `--remap FROM:=TO` and `--ros-args -r FROM:=TO` as (from, to) pairs of fully qualified names (relative
/// names are taken from the root, as the bag's own names are absolute); --remap rules come first.
fn play_remaps(remap: &[String], ros_args: &[String]) -> anyhow::Result<Vec<(String, String)>> {
    let mut tokens: Vec<String> = Vec::new();
    for rule in remap {
        tokens.push("-r".to_string());
        tokens.push(rule.clone());
    }
    tokens.extend(ros_args.iter().cloned());
    let parsed = crate::ros::args::RosArgs::parse(&tokens).map_err(|e| anyhow::anyhow!("--remap/--ros-args: {e}"))?;
    let identity = parsed.identity("sweetspot_play", "/");
    Ok(parsed
        .remaps
        .iter()
        .filter(|r| r.node.as_deref().is_none_or(|n| n == identity.name))
        .map(|r| (crate::ros::args::resolve_name(&r.from, &identity), crate::ros::args::resolve_name(&r.to, &identity)))
        .collect())
}

/// `bag play --foxglove`: serves the bag on a Foxglove server until Ctrl-C, while (unless `dds` is false)
/// playing its inputs over DDS as `bag play` does; each keeps its own clock, so pausing or seeking in
/// Foxglove moves what Foxglove shows, not what goes out over DDS.
fn play_foxglove(
    path: PathBuf,
    options: crate::play::PlayOptions,
    bind: crate::foxglove::Bind,
    dds: bool,
    quiet: bool,
) -> anyhow::Result<()> {
    use crate::play::foxglove::{serve, ServeOptions, ServedBag};
    let stop = crate::ros::interrupt_flag();
    let served = ServedBag::read(&path, &options.topics, |topic| options.remapped(topic).to_string())
        .map_err(flat)
        .with_context(|| format!("reading bag {}", path.display()))?;
    // The server's own warnings (refused or dropped clients) go to stderr, as the node's do.
    super::node::init_logging(None);
    let serve_options = ServeOptions {
        bind: bind.clone(),
        playing: dds,
        rate: options.rate,
        start_offset: options.start_offset,
        delay: options.delay,
        repeat: options.repeat,
        limits: crate::foxglove::Limits::default(),
    };
    std::thread::scope(|scope| {
        let server = scope.spawn(|| {
            serve(&served, &serve_options, &stop, |port| {
                eprintln!(
                    "Foxglove WebSocket server on {}: {} messages on {} topics, {} (Ctrl-C to stop)",
                    bind.url(port),
                    served.messages.len(),
                    served.topics.len(),
                    if dds {
                        "playing"
                    } else {
                        "paused until a client plays (or plays by itself 2 s after the first subscription)"
                    }
                )
            })
        });
        if dds {
            let played = play(path.clone(), options, quiet);
            if played.is_err() {
                stop.store(true, std::sync::atomic::Ordering::Relaxed);
            }
            played?;
        }
        let sent = server.join().map_err(|_| anyhow::anyhow!("the Foxglove server thread panicked"))?;
        let sent = sent.map_err(flat).with_context(|| format!("serving {}", path.display()))?;
        eprintln!("served {sent} messages to Foxglove");
        Ok(())
    })
}

/// Plays `path` over DDS with a progress bar (`quiet`) or a line per message; `bag play` and `import --pub`.
pub(crate) fn play(path: PathBuf, mut options: crate::play::PlayOptions, quiet: bool) -> anyhow::Result<()> {
    let stop = crate::ros::interrupt_flag();
    let total = options.schedule(&path).map_err(flat)?.items.len() as u64;
    let keys = crate::play::keys::SpaceBarPause::on_terminal();
    options.paused = keys.as_ref().map(|k| k.paused.clone());
    let bar = if quiet { progress(total, "playing") } else { indicatif::ProgressBar::hidden() };
    let mut listing = super::common::Stdout::default();
    let stats = crate::play::play(&path, &options, &stop, |event| match event {
        crate::play::PlayEvent::Published(item) => {
            bar.inc(1);
            if !quiet {
                // The listing is a courtesy: a stdout that fails must not stop what is being published.
                let _ =
                    writeln!(listing, "{:>10.3} s  {}  ({} bytes)", item.at.as_secs_f64(), item.topic, item.cdr.len());
            }
        }
        crate::play::PlayEvent::Waiting(text) => bar.suspend(|| eprintln!("{text}")),
        crate::play::PlayEvent::Warning(text) => bar.suspend(|| eprintln!("warning: {text}")),
    })
    .map_err(flat)
    .with_context(|| format!("playing {}", path.display()));
    drop(keys);
    let stats = stats?;
    bar.finish_and_clear();
    eprintln!("published {} messages in {} pass(es)", stats.published, stats.passes);
    // As `pub` fails when no subscription appears: a play nobody heard did nothing. --no-wait opts out, as
    // `pub -w 0` does (fire and forget, as `ros2 bag play`).
    if options.wait_discovered && !stats.heard && stats.published > 0 {
        anyhow::bail!(
            "no subscriber on any played topic: all {} messages went to nobody (start the node first; --no-wait \
             plays without looking, with status 0)",
            stats.published
        );
    }
    Ok(())
}
