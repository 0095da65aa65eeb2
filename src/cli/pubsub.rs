//! `sweetspot pub` and `sweetspot echo`: their flags; the publishing and echoing are
//! [`crate::client::pubsub`]'s.

use std::path::PathBuf;

use crate::client::kind::QosOverrides;
use crate::client::pubsub::{EchoOptions, PubOptions};

/// Arguments of `sweetspot pub`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Examples:
  sweetspot pub swing '{swing_id: 1, bat_id: r161, ball_speed: 40, bat_cm_speed: 20, impact_z: 0.7}'
  sweetspot pub /swing sweetspot_msgs/msg/Swing '{bat_id: r161, ball_speed: 40, bat_cm_speed: 25, impact_z: 0.62}' -1
  sweetspot pub bat '{\"bat_id\": \"mine\", \"preset\": \"aluminum\"}' --keep-alive 5
  sweetspot pub swing '{ball_speed: 40, bat_cm_speed: 25, impact_z: 0.7}' -r 10 -t 30
  sweetspot pub swing --file swings.csv --rate 100 -w 1
  sweetspot pub /lab/swing --type Swing --file swings.jsonl --ros-args -r __ns:=/rig3

VALUES are YAML (flow `{a: 1}` or block `a: 1`, as `ros2 topic pub` takes them) or JSON; a list publishes
each item. Fields left out keep their defaults; header.stamp defaults to the publish time, a Swing's
swing_id to 1, 2, 3… and its measured_exit_speed to NaN (not measured). Floats accept null/nan/.nan.

Like `ros2 topic pub --once/--times`, pub waits for a matching subscription (-w, default 1) before the first
message and exits non-zero with a warning if none appears within --timeout; on a latched topic (bat, ball)
it does not wait (late joiners get the message), nor when one message repeats forever at --rate.")]
pub struct PubArgs {
    /// What to publish: a message kind (bat, ball, swing, or a type such as BatParams or
    /// sweetspot_msgs/msg/Swing) on its default topic, or a topic name (relative names are resolved in the
    /// namespace).
    pub target: String,
    /// `TYPE VALUES` or `VALUES` (the `ros2 topic pub TOPIC TYPE VALUES` form): a type when it is not a
    /// message, e.g. `sweetspot_msgs/msg/Swing`.
    #[arg(value_name = "TYPE|VALUES")]
    pub type_or_message: Option<String>,
    /// The message as YAML or JSON: an object, or a list of objects.
    #[arg(value_name = "VALUES")]
    pub message: Option<String>,
    /// Message type when TARGET is a topic whose type cannot be told from its name.
    #[arg(long = "type", value_name = "TYPE")]
    pub msg_type: Option<String>,
    /// Read messages from a file: JSON lines (one object per line; `-` = stdin), YAML (`.yaml`/`.yml`: a list
    /// or `---`-separated documents) or CSV (`.csv`, one column per field, nested fields as `header.frame_id`,
    /// arrays as `[1,2]` or `1;2`).
    #[arg(long, value_name = "PATH")]
    pub file: Option<PathBuf>,
    /// Publish at this rate (messages per second); without it messages go out as fast as they are acknowledged.
    #[arg(short = 'r', long, value_name = "HZ", value_parser = super::common::rate_hz)]
    pub rate: Option<f64>,
    /// Publish this many messages in total, cycling through the input (default: each input message once, or
    /// forever when a single message is repeated with --rate).
    #[arg(short = 't', long = "times", visible_alias = "count", value_name = "N")]
    pub count: Option<u64>,
    /// Publish one message and exit (same as `--times 1`).
    #[arg(short = '1', long, conflicts_with = "count")]
    pub once: bool,
    /// Before the first message, wait until this many subscriptions on the topic have matched this publisher
    /// (default 1; 0 on latched topics and when repeating forever at --rate).
    #[arg(short = 'w', long = "wait-matching-subscriptions", visible_alias = "wait-subscribers", value_name = "N")]
    pub wait_subscribers: Option<usize>,
    /// Seconds to wait for matching subscriptions, and for subscribers to acknowledge everything at the end
    /// (inf: no limit).
    #[arg(long, visible_alias = "max-wait-time-secs", value_name = "SECS", default_value_t = 10.0,
          value_parser = super::common::seconds_at_least_zero)]
    pub timeout: f64,
    /// Stay up this many seconds after every subscription acknowledged the last message: readers need a moment
    /// to take what they acknowledged (a RustDDS reader drops the untaken samples of a writer whose participant
    /// has left), and late joiners get latched params only while we are up (inf: until Ctrl-C).
    #[arg(long, value_name = "SECS", default_value_t = 0.5, value_parser = super::common::seconds_at_least_zero)]
    pub keep_alive: f64,
    /// QoS over the topic's own.
    #[command(flatten)]
    pub qos: QosArgs,
    /// Namespace for relative topic names (same as `--ros-args -r __ns:=NS`).
    #[arg(long, visible_alias = "namespace", value_name = "NS")]
    pub ns: Option<String>,
    /// Do not print what is published.
    #[arg(long, short)]
    pub quiet: bool,
    /// ROS arguments (`-r __ns:=/rig3`, `-r from:=to`), as for any ROS 2 node; must come last.
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS")]
    pub ros_args: Option<Vec<String>>,
}

/// Arguments of `sweetspot echo`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Examples:
  sweetspot echo exit_velocity
  sweetspot echo /exit_velocity --ns /lab --once
  sweetspot echo /rig3/modal_energies --json --count 10 --timeout 30
  sweetspot echo /lab/thing sweetspot_msgs/msg/Swing --qos-reliability best_effort
  sweetspot echo /diagnostics
  sweetspot echo /clock --once                # the bag time `bag play --clock` publishes

When nothing publishes on the topic after a few seconds, echo says so on stderr and names the topics (and so
the namespaces) where that message type is published, then keeps listening.")]
pub struct EchoArgs {
    /// Topic to print (relative names are resolved in the namespace), or a message kind (bat, ball, swing,
    /// exit_velocity, modal_energies, sweet_spot, diagnostics, rosout, clock) for its default topic.
    pub topic: String,
    /// Message type (the `ros2 topic echo TOPIC TYPE` form), same as --type.
    #[arg(value_name = "TYPE")]
    pub positional_type: Option<String>,
    /// Message type when the topic's type cannot be told from its name.
    #[arg(long = "type", value_name = "TYPE")]
    pub msg_type: Option<String>,
    /// One JSON object per line (NaN as null) instead of the readable form.
    #[arg(long)]
    pub json: bool,
    /// Exit after this many messages (exit status 1 if --timeout ends the wait first).
    #[arg(long, value_name = "N")]
    pub count: Option<u64>,
    /// Print the first message received and exit (same as `--count 1`).
    #[arg(long, conflicts_with = "count")]
    pub once: bool,
    /// Exit after this many seconds (inf: no limit, as without it).
    #[arg(long, value_name = "SECS", value_parser = super::common::seconds_at_least_zero)]
    pub timeout: Option<f64>,
    /// Subscribe volatile even on latched topics (params, sweet_spot): only messages published from now on.
    #[arg(long)]
    pub no_latched: bool,
    /// QoS over the topic's own.
    #[command(flatten)]
    pub qos: QosArgs,
    /// Namespace for relative topic names (same as `--ros-args -r __ns:=NS`).
    #[arg(long, visible_alias = "namespace", value_name = "NS")]
    pub ns: Option<String>,
    /// ROS arguments (`-r __ns:=/rig3`, `-r from:=to`), as for any ROS 2 node; must come last.
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS")]
    pub ros_args: Option<Vec<String>>,
}

/// `--qos-*` overrides of a topic's QoS, as `ros2 topic pub/echo` take them.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct QosArgs {
    /// Reliability: reliable, best_effort, or system_default (the topic's own).
    #[arg(long, value_name = "POLICY", value_parser = ["reliable", "best_effort", "system_default"])]
    pub qos_reliability: Option<String>,
    /// Durability: volatile, transient_local, or system_default (the topic's own).
    #[arg(long, value_name = "POLICY", value_parser = ["volatile", "transient_local", "system_default"])]
    pub qos_durability: Option<String>,
    /// History depth (keep last N).
    #[arg(long, value_name = "N")]
    pub qos_depth: Option<usize>,
}

impl QosArgs {
    fn overrides(&self) -> QosOverrides {
        QosOverrides {
            reliability: self.qos_reliability.clone(),
            durability: self.qos_durability.clone(),
            depth: self.qos_depth,
        }
    }
}

impl From<PubArgs> for PubOptions {
    fn from(a: PubArgs) -> PubOptions {
        let qos = a.qos.overrides();
        PubOptions {
            target: a.target,
            type_or_message: a.type_or_message,
            message: a.message,
            msg_type: a.msg_type,
            file: a.file,
            rate: a.rate,
            count: a.count,
            once: a.once,
            wait_subscribers: a.wait_subscribers,
            timeout: a.timeout,
            keep_alive: a.keep_alive,
            qos,
            ns: a.ns,
            quiet: a.quiet,
            ros_args: a.ros_args,
        }
    }
}

/// Publishes messages.
pub fn run_pub(args: PubArgs) -> anyhow::Result<()> {
    crate::client::pubsub::publish(args.into())
}

/// Prints what arrives on a topic.
pub fn run_echo(a: EchoArgs) -> anyhow::Result<()> {
    let qos = a.qos.overrides();
    crate::client::pubsub::echo(EchoOptions {
        topic: a.topic,
        positional_type: a.positional_type,
        msg_type: a.msg_type,
        json: a.json,
        count: a.count,
        once: a.once,
        timeout: a.timeout,
        no_latched: a.no_latched,
        qos,
        ns: a.ns,
        ros_args: a.ros_args,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::client::kind::Kind;
    use crate::client::pubsub::{default_wait, split_positionals};

    fn parse_pub(line: &[&str]) -> PubOptions {
        use clap::Parser;
        let argv = std::iter::once("sweetspot").chain(std::iter::once("pub")).chain(line.iter().copied());
        match crate::cli::Cli::try_parse_from(argv).unwrap().command {
            crate::cli::Command::Pub(args) => args.into(),
            other => panic!("parsed as {other:?}"),
        }
    }

    #[test]
    fn the_ros2_topic_pub_forms_parse() {
        let a = parse_pub(&[
            "/swing",
            "sweetspot_msgs/msg/Swing",
            "{bat_id: r161}",
            "-1",
            "-w",
            "2",
            "--namespace",
            "/lab",
        ]);
        assert_eq!(
            split_positionals(&a).unwrap(),
            (Some("sweetspot_msgs/msg/Swing".into()), Some("{bat_id: r161}".into()))
        );
        assert!(a.once);
        assert_eq!((a.wait_subscribers, a.ns.as_deref()), (Some(2), Some("/lab")));
        let a = parse_pub(&["swing", "bat_id: r161", "-r", "5", "-t", "3"]);
        assert_eq!(split_positionals(&a).unwrap(), (None, Some("bat_id: r161".into())));
        assert_eq!((a.rate, a.count), (Some(5.0), Some(3)));
        let a = parse_pub(&["/lab/thing", "Swing", "--count", "2", "--wait-subscribers", "0", "--ns", "/x"]);
        assert_eq!(split_positionals(&a).unwrap(), (Some("Swing".into()), None));
        assert_eq!((a.count, a.wait_subscribers), (Some(2), Some(0)));
        let a = parse_pub(&["/lab/thing", "Swing", "{}", "--type", "ExitVelocity"]);
        assert!(split_positionals(&a).is_err(), "TYPE and --type disagree");
        let a = parse_pub(&[
            "swing",
            "--qos-reliability",
            "best_effort",
            "--qos-durability",
            "transient_local",
            "--qos-depth",
            "7",
        ]);
        let q = a.qos.apply(Kind::Swing.qos()).unwrap();
        assert_eq!(q.reliability, ros2_client::qos::Reliability::BestEffort);
        assert_eq!(q.durability, ros2_client::qos::Durability::TransientLocal);
        assert_eq!(q.history, ros2_client::qos::History::KeepLast { depth: 7 });
        assert_eq!(default_wait(false, false), 1, "ros2 topic pub --once waits for one subscription");
        assert_eq!(default_wait(true, false), 0);
        assert_eq!(default_wait(false, true), 0);
    }
}
