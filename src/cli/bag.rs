//! `sweetspot bag …`: the flags of record, info, recover, export, replay and play. Playing and recording over
//! DDS are [`crate::play::console`]'s and [`crate::record::console`]'s; the rest reads bags without DDS,
//! [`crate::bag_tools`].

use std::path::PathBuf;

use crate::bag_tools::{self, ReplayRequest};
use crate::play::console::PlayRequest;
use crate::record::console::RecordRequest;

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
        /// What if: use this preset ball for every swing (baseball, bbcor, mlb, mlb2024).
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
    Record(RecordArgs),
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
    Play(PlayArgs),
}

/// `bag record`'s flags.
#[derive(Debug, clap::Args)]
pub struct RecordArgs {
    /// Topics to record (relative names are resolved in the namespace).
    #[arg(value_name = "TOPIC")]
    pub topics: Vec<String>,
    /// Record every topic.
    #[arg(short = 'a', long)]
    pub all: bool,
    /// Record the topics whose fully-qualified name matches this regular expression.
    #[arg(short = 'e', long, value_name = "REGEX")]
    pub regex: Option<String>,
    /// Also record hidden topics (a name part starting with `_`) with -a or -e.
    #[arg(long)]
    pub include_hidden_topics: bool,
    /// The bag directory to create (default: rosbag2_YYYY_MM_DD-HH_MM_SS, local time).
    #[arg(short = 'o', long, value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Storage plugin: only mcap.
    #[arg(short = 's', long, value_name = "ID", default_value = "mcap")]
    pub storage: String,
    /// rosbag2's MCAP preset: none, fastwrite, zstd_fast or zstd_small.
    #[arg(long, value_name = "PROFILE", default_value = "none")]
    pub storage_preset_profile: String,
    /// Start a new file once the current one reaches this many bytes (0: never).
    #[arg(short = 'b', long, value_name = "BYTES", default_value_t = 0)]
    pub max_bag_size: u64,
    /// Start a new file after this many seconds of recording (0: never).
    #[arg(short = 'd', long, value_name = "SECONDS", default_value_t = 0.0,
          value_parser = super::common::seconds_at_least_zero)]
    pub max_bag_duration: f64,
    /// A rosbag2 YAML file of per-topic subscription QoS (history, depth, reliability, durability).
    #[arg(long, value_name = "FILE")]
    pub qos_profile_overrides_path: Option<PathBuf>,
    /// How often to look for new topics, milliseconds.
    #[arg(short = 'p', long, value_name = "MS", default_value_t = 100)]
    pub polling_interval: u64,
    /// Namespace for relative topic names (same as `--ros-args -r __ns:=NS`).
    #[arg(long, visible_alias = "namespace", value_name = "NS")]
    pub ns: Option<String>,
    /// ROS arguments (`-r __ns:=/rig3`), as for any ROS 2 node; must come last.
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS")]
    pub ros_args: Option<Vec<String>>,
}

/// `bag play`'s flags.
#[derive(Debug, clap::Args)]
pub struct PlayArgs {
    /// Bag directory or .mcap file.
    pub path: PathBuf,
    /// Time scale: 2 plays twice as fast, 0.5 at half speed.
    #[arg(short = 'r', long, default_value_t = 1.0, value_parser = super::common::time_scale)]
    pub rate: f64,
    /// Start over when done, until interrupted.
    #[arg(short = 'l', long = "loop")]
    pub repeat: bool,
    /// Only these topics, as recorded (default: every input topic in the bag).
    #[arg(long, value_delimiter = ',', num_args = 1..)]
    pub topics: Vec<String>,
    /// Publish what was recorded on FROM on TO instead (repeatable), e.g. `--remap /lab/swing:=/swing`.
    #[arg(short = 'm', long = "remap", value_name = "FROM:=TO")]
    pub remap: Vec<String>,
    /// Start this many seconds (recorded time) after the bag's first message (finite).
    #[arg(long, value_name = "SECONDS", default_value_t = 0.0, value_parser = super::common::finite_seconds_at_least_zero)]
    pub start_offset: f64,
    /// Wait this many seconds before playing (before each pass with --loop; finite).
    #[arg(long, value_name = "SECONDS", default_value_t = 0.0, value_parser = super::common::finite_seconds_at_least_zero)]
    pub delay: f64,
    /// Publish rosgraph_msgs/Clock with the bag's time on /clock at HZ (40 without a value, as rosbag2).
    #[arg(long, value_name = "HZ", num_args = 0..=1, default_missing_value = "40", value_parser = super::common::rate_hz)]
    pub clock: Option<f64>,
    /// Wait until every topic has this many subscriptions before starting (default: wait until the
    /// subscriptions discovery shows have matched, at most --timeout, and warn of topics with none).
    #[arg(long, default_value_t = 0)]
    pub wait_subscribers: usize,
    /// Start publishing at once, without waiting for discovered subscribers to match, and exit 0 even when
    /// nobody listened (as `ros2 bag play`; without it a play no subscriber heard exits 1, as `pub` does).
    #[arg(long, conflicts_with = "wait_subscribers")]
    pub no_wait: bool,
    /// Seconds to wait for subscribers, and for acknowledgments at the end (inf: no limit).
    #[arg(long, default_value_t = 10.0, value_parser = super::common::seconds_above_zero)]
    pub timeout: f64,
    /// Do not print each message.
    #[arg(short, long)]
    pub quiet: bool,
    /// Go on past damaged chunks with everything intact around them (the damage is still listed).
    #[arg(long)]
    pub skip_damaged: bool,
    /// Also serve the bag (every topic, or --topics) on a Foxglove WebSocket server at [ADDR:]PORT
    /// (127.0.0.1 unless ADDR is given), with Foxglove's play, pause, seek and speed controls.
    #[arg(long, value_name = "[ADDR:]PORT")]
    pub foxglove: Option<String>,
    /// With --foxglove: serve only, no DDS output (playback then starts paused, for the client to start).
    #[arg(long, requires = "foxglove")]
    pub no_dds: bool,
    /// ROS arguments: `-r FROM:=TO` remaps topics as --remap does; must come last.
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS")]
    pub ros_args: Option<Vec<String>>,
}

/// Runs one `bag` subcommand.
pub fn run(cmd: BagCommand) -> anyhow::Result<()> {
    match cmd {
        BagCommand::Info { path, json, skip_damaged } => bag_tools::info(&path, json, skip_damaged),
        BagCommand::Recover { path, output } => bag_tools::recover(&path, output.as_deref()),
        BagCommand::Export { path, csv: _, output, skip_damaged } => {
            bag_tools::export(&path, output.as_deref(), skip_damaged)
        }
        BagCommand::Record(a) => crate::record::console::record_command(RecordRequest {
            topics: a.topics,
            all: a.all,
            regex: a.regex,
            include_hidden_topics: a.include_hidden_topics,
            output: a.output,
            storage: a.storage,
            storage_preset_profile: a.storage_preset_profile,
            max_bag_size: a.max_bag_size,
            max_bag_duration: a.max_bag_duration,
            qos_profile_overrides_path: a.qos_profile_overrides_path,
            polling_interval: a.polling_interval,
            ns: a.ns,
            ros_args: a.ros_args,
        }),
        BagCommand::Play(a) => {
            if a.foxglove.is_some() {
                // The server's own warnings (refused or dropped clients) go to stderr, as the node's do.
                super::node::init_logging(None);
            }
            crate::play::console::play_command(PlayRequest {
                path: a.path,
                rate: a.rate,
                repeat: a.repeat,
                topics: a.topics,
                remap: a.remap,
                start_offset: a.start_offset,
                delay: a.delay,
                clock: a.clock,
                wait_subscribers: a.wait_subscribers,
                no_wait: a.no_wait,
                timeout: a.timeout,
                quiet: a.quiet,
                skip_damaged: a.skip_damaged,
                foxglove: a.foxglove,
                no_dds: a.no_dds,
                ros_args: a.ros_args,
            })
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
        } => bag_tools::replay(ReplayRequest {
            path,
            tolerance,
            what_if: crate::bag::replay::WhatIf { bat, ball, modes },
            time_step,
            default_modes,
            default_bat,
            all,
            json,
            skip_damaged,
        }),
    }
}
