//! `bag record` as the command line runs it: the request's flags checked and turned into [`RecordOptions`],
//! then the recording, with what it subscribed to and what it recorded said on stderr.

use std::path::PathBuf;

use anyhow::Context as _;

use super::{QosOverrides, RecordOptions};

/// `bag record`'s flags (see `sweetspot bag record --help`).
#[derive(Debug, Clone, Default)]
pub struct RecordRequest {
    /// Topics to record.
    pub topics: Vec<String>,
    /// Record every topic.
    pub all: bool,
    /// Record the topics matching this regular expression.
    pub regex: Option<String>,
    /// Also hidden topics with `all` or `regex`.
    pub include_hidden_topics: bool,
    /// The bag directory to create.
    pub output: Option<PathBuf>,
    /// Storage plugin (mcap only).
    pub storage: String,
    /// rosbag2's MCAP preset.
    pub storage_preset_profile: String,
    /// Bytes per file (0: never split).
    pub max_bag_size: u64,
    /// Seconds per file (0: never split).
    pub max_bag_duration: f64,
    /// A rosbag2 QoS overrides file.
    pub qos_profile_overrides_path: Option<PathBuf>,
    /// Milliseconds between looks for new topics.
    pub polling_interval: u64,
    /// Namespace for relative topic names.
    pub ns: Option<String>,
    /// `--ros-args`.
    pub ros_args: Option<Vec<String>>,
}

/// Runs `bag record` until Ctrl-C or SIGTERM.
pub fn record_command(request: RecordRequest) -> anyhow::Result<()> {
    let RecordRequest { topics, all, regex, storage, ns, ros_args, .. } = request;
    if storage != "mcap" {
        anyhow::bail!("-s/--storage {storage:?} is not available: sweetspot records MCAP only (-s mcap)");
    }
    if !all && regex.is_none() && topics.is_empty() {
        anyhow::bail!("nothing to record: pass -a/--all, topic names, or -e/--regex");
    }
    if request.polling_interval == 0 {
        anyhow::bail!("-p/--polling-interval must be at least 1 ms");
    }
    let regex = match regex {
        Some(r) => Some(regex::Regex::new(&r).map_err(|e| anyhow::anyhow!("-e/--regex {r:?}: {e}"))?),
        None => None,
    };
    let storage = crate::bag::StorageOptions::preset(&request.storage_preset_profile)
        .map_err(|e| anyhow::anyhow!("--storage-preset-profile: {e}"))?;
    let qos_overrides = match &request.qos_profile_overrides_path {
        Some(path) => QosOverrides::load(path)?,
        None => QosOverrides::default(),
    };
    let options = RecordOptions {
        output: request
            .output
            .unwrap_or_else(|| PathBuf::from(chrono::Local::now().format("rosbag2_%Y_%m_%d-%H_%M_%S").to_string())),
        selection: super::Selection {
            all,
            topics: record_topics(&topics, &ns, ros_args.as_deref().unwrap_or_default())?,
            regex,
            include_hidden: request.include_hidden_topics,
        },
        storage,
        max_bag_size: (request.max_bag_size > 0).then_some(request.max_bag_size),
        max_bag_duration: (request.max_bag_duration > 0.0)
            .then(|| crate::model::time::saturating_secs(request.max_bag_duration)),
        qos_overrides,
        polling_interval: std::time::Duration::from_millis(request.polling_interval),
    };
    // Before anything starts (the overrides file, read above, is an input).
    crate::files::refuse_clobber("-o/--output", &options.output, &[], &[]).map_err(anyhow::Error::msg)?;
    record_reporting(options)
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

fn record_reporting(options: RecordOptions) -> anyhow::Result<()> {
    let stop = crate::ros::interrupt_flag();
    for (topic, key) in options.qos_overrides.ignored() {
        eprintln!("--qos-profile-overrides-path: {topic}: {key} is accepted but not applied");
    }
    let stats = super::record(&options, &stop, |event| match event {
        // Said once the bag directory exists, so a refused -o never reads as a recording.
        super::RecordEvent::Started { dir } => eprintln!("recording to {} (Ctrl-C to stop)", dir.display()),
        super::RecordEvent::Subscribed { topic, type_name, schema: true } => {
            eprintln!("subscribed to {topic} ({type_name})")
        }
        super::RecordEvent::Subscribed { topic, type_name, schema: false } => eprintln!(
            "subscribed to {topic} ({type_name}): type not generated from msgs/, recorded as raw CDR without a \
             schema (readers can list it but not decode it)"
        ),
        super::RecordEvent::Skipped { topic, reason } => eprintln!("skipped {topic}: {reason}"),
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
            super::REORDER_WINDOW.as_millis()
        );
    }
    Ok(())
}
