//! `bag play` as the command line runs it: the bag checked for damage, the request's flags turned into
//! [`PlayOptions`], then playback over DDS with a line per message (or a progress bar), over Foxglove, or both.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::Context as _;

use super::PlayOptions;
use crate::bag_tools::{check_damage, flat, progress};

/// `bag play`'s flags (see `sweetspot bag play --help`).
#[derive(Debug, Clone, Default)]
pub struct PlayRequest {
    /// The bag.
    pub path: PathBuf,
    /// Time scale.
    pub rate: f64,
    /// Start over when done.
    pub repeat: bool,
    /// Only these topics.
    pub topics: Vec<String>,
    /// `--remap FROM:=TO` rules.
    pub remap: Vec<String>,
    /// Seconds (recorded time) into the bag.
    pub start_offset: f64,
    /// Seconds to wait before each pass.
    pub delay: f64,
    /// `/clock` rate, Hz.
    pub clock: Option<f64>,
    /// Subscriptions to wait for on every topic.
    pub wait_subscribers: usize,
    /// Start at once, without waiting for discovered subscribers.
    pub no_wait: bool,
    /// Seconds to wait for subscribers and acknowledgments.
    pub timeout: f64,
    /// A progress bar instead of a line per message.
    pub quiet: bool,
    /// Go on past damaged chunks.
    pub skip_damaged: bool,
    /// `[ADDR:]PORT` of a Foxglove server to serve the bag on.
    pub foxglove: Option<String>,
    /// With `foxglove`: no DDS output.
    pub no_dds: bool,
    /// `--ros-args`.
    pub ros_args: Option<Vec<String>>,
}

/// Runs `bag play`.
pub fn play_command(r: PlayRequest) -> anyhow::Result<()> {
    check_damage(&r.path, r.skip_damaged)?;
    // Checked by their value parsers (model::time): --timeout inf waits for ever, the spans are finite.
    let seconds = crate::model::time::saturating_secs;
    let options = PlayOptions {
        rate: r.rate,
        repeat: r.repeat,
        topics: r.topics,
        wait_subscribers: r.wait_subscribers,
        wait_discovered: !r.no_wait,
        timeout: seconds(r.timeout),
        remaps: play_remaps(&r.remap, r.ros_args.as_deref().unwrap_or_default())?,
        start_offset: seconds(r.start_offset),
        delay: seconds(r.delay),
        clock_hz: r.clock,
        paused: None,
        interval: None,
    };
    match r.foxglove {
        None => play(r.path, options, r.quiet),
        Some(bind) => {
            let bind = crate::foxglove::Bind::parse(&bind).map_err(|e| anyhow::anyhow!("--foxglove: {e}"))?;
            play_with_foxglove(r.path, options, bind, !r.no_dds, r.quiet)
        }
    }
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
fn play_with_foxglove(
    path: PathBuf,
    options: PlayOptions,
    bind: crate::foxglove::Bind,
    dds: bool,
    quiet: bool,
) -> anyhow::Result<()> {
    use super::foxglove::{serve, ServeOptions, ServedBag};
    let stop = crate::ros::interrupt_flag();
    let served = ServedBag::read(&path, &options.topics, |topic| options.remapped(topic).to_string())
        .map_err(flat)
        .with_context(|| format!("reading bag {}", path.display()))?;
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
pub fn play(path: PathBuf, mut options: PlayOptions, quiet: bool) -> anyhow::Result<()> {
    let stop = crate::ros::interrupt_flag();
    let total = options.schedule(&path).map_err(flat)?.items.len() as u64;
    let keys = super::keys::SpaceBarPause::on_terminal();
    options.paused = keys.as_ref().map(|k| k.paused.clone());
    let bar = if quiet { progress(total, "playing") } else { indicatif::ProgressBar::hidden() };
    let mut listing = crate::report::stdout::Stdout::default();
    let stats = super::play(&path, &options, &stop, |event| match event {
        super::PlayEvent::Published(item) => {
            bar.inc(1);
            if !quiet {
                // The listing is a courtesy: a stdout that fails must not stop what is being published.
                let _ =
                    writeln!(listing, "{:>10.3} s  {}  ({} bytes)", item.at.as_secs_f64(), item.topic, item.cdr.len());
            }
        }
        super::PlayEvent::Waiting(text) => bar.suspend(|| eprintln!("{text}")),
        super::PlayEvent::Warning(text) => bar.suspend(|| eprintln!("warning: {text}")),
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
