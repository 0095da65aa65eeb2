//! The rig's DDS shell: writers for `bat/params`, `ball/params` (reliable, transient-local) and `swing`
//! (reliable), and a listener for the node's answers — the same QoS and names as the node (`crate::ros`).
//!
//! Synchronous on purpose: a rig publishes from one loop at a fixed rate, and the demo polls the answers.

use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Result};
use rustdds::no_key::{DataWriterCdr, SimpleDataReaderCdr};

use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};
use crate::msgs::RosMessage;
use crate::ros::edge::{matched_subscriptions, reader, write_reliably, writer};
use crate::ros::{self, interrupt_flag, topics, DdsConfig};

/// Node name the rig's topics are resolved with (only `~/` names would use it).
pub const RIG_NODE_NAME: &str = "sweetspot_rig";

/// Fully-qualified names of the node's topics in a namespace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopicNames {
    /// `<ns>/bat/params`.
    pub bat_params: String,
    /// `<ns>/ball/params`.
    pub ball_params: String,
    /// `<ns>/swing`.
    pub swing: String,
    /// `<ns>/exit_velocity`.
    pub exit_velocity: String,
    /// `<ns>/modal_energies`.
    pub modal_energies: String,
    /// `<ns>/sweet_spot`.
    pub sweet_spot: String,
}

impl TopicNames {
    /// The names in `namespace` (e.g. `/rig3`; `/` for none).
    pub fn in_namespace(namespace: &str) -> Result<TopicNames> {
        let r = |t: &str| {
            ros::resolve_topic(t, namespace, RIG_NODE_NAME).map_err(|e| anyhow!("namespace '{namespace}': {e}"))
        };
        Ok(TopicNames {
            bat_params: r(topics::BAT_PARAMS)?,
            ball_params: r(topics::BALL_PARAMS)?,
            swing: r(topics::SWING)?,
            exit_velocity: r(topics::EXIT_VELOCITY)?,
            modal_energies: r(topics::MODAL_ENERGIES)?,
            sweet_spot: r(topics::SWEET_SPOT)?,
        })
    }
}

/// The rig's publishers.
pub struct RigPublisher {
    /// Topic names used.
    pub names: TopicNames,
    bats: DataWriterCdr<BatParams>,
    balls: DataWriterCdr<BallParams>,
    swings: DataWriterCdr<Swing>,
    swing_matches: usize,
    /// Subscriptions matched on the bat and the ball params so far.
    param_matches: [usize; 2],
    /// Give up a write after this long with a full send window.
    pub write_timeout: Duration,
}

impl RigPublisher {
    /// Creates the three writers in `ctx` under `namespace`.
    pub fn new(ctx: &ros2_client::Context, namespace: &str) -> Result<RigPublisher> {
        let names = TopicNames::in_namespace(namespace)?;
        Ok(RigPublisher {
            bats: writer(ctx, &names.bat_params, &ros::params_qos())?,
            balls: writer(ctx, &names.ball_params, &ros::params_qos())?,
            swings: writer(ctx, &names.swing, &ros::swing_qos())?,
            names,
            swing_matches: 0,
            param_matches: [0, 0],
            write_timeout: Duration::from_secs(10),
        })
    }

    /// Subscriptions (nodes, recorders, echoes) matched on `swing` so far.
    pub fn swing_subscribers(&mut self) -> usize {
        self.swing_matches = matched_subscriptions(&self.swings, self.swing_matches);
        self.swing_matches
    }

    /// Waits until at least `count` subscriptions matched on `swing` and as many on the bat and the ball
    /// params (a node subscribes to all three, and discovery matches each on its own: a swing may otherwise reach
    /// a node whose params reader is not yet matched, and be answered "unknown ball_id"), checking `abort`
    /// (e.g. "the node process died") every 20 ms.
    pub fn wait_for_subscribers(
        &mut self,
        count: usize,
        timeout: Duration,
        mut abort: impl FnMut() -> Option<String>,
    ) -> Result<()> {
        let start = Instant::now();
        loop {
            self.param_matches = [
                matched_subscriptions(&self.bats, self.param_matches[0]),
                matched_subscriptions(&self.balls, self.param_matches[1]),
            ];
            if self.swing_subscribers() >= count && self.param_matches.iter().all(|&m| m >= count) {
                break;
            }
            if let Some(reason) = abort() {
                bail!("{reason}");
            }
            if start.elapsed() >= timeout {
                bail!(
                    "no node subscribed to {} within {:.0} s (is `sweetspot node` running in the same namespace, domain \
                     (ROS_DOMAIN_ID) and discovery range (ROS_AUTOMATIC_DISCOVERY_RANGE)?)",
                    self.names.swing,
                    timeout.as_secs_f64()
                );
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        Ok(())
    }

    /// Publishes a bat's params (latched).
    pub fn publish_bat(&self, msg: BatParams) -> Result<()> {
        Ok(write_reliably(&self.bats, msg, self.write_timeout, &interrupt_flag())?)
    }

    /// Publishes a ball's params (latched).
    pub fn publish_ball(&self, msg: BallParams) -> Result<()> {
        Ok(write_reliably(&self.balls, msg, self.write_timeout, &interrupt_flag())?)
    }

    /// Publishes one swing.
    pub fn publish_swing(&self, msg: Swing) -> Result<()> {
        Ok(write_reliably(&self.swings, msg, self.write_timeout, &interrupt_flag())?)
    }

    /// Waits until every matched subscription acknowledged the bat and ball params written; false on timeout.
    /// Sent before the first swing, so a node has its params before any swing that names them.
    pub fn wait_params_acknowledged(&self, timeout: Duration) -> bool {
        [self.bats.wait_for_acknowledgments(timeout), self.balls.wait_for_acknowledgments(timeout)]
            .into_iter()
            .all(|r| matches!(r, Ok(true)))
    }

    /// Waits until every matched subscription acknowledged everything written; false on timeout.
    pub fn wait_acknowledged(&self, timeout: Duration) -> bool {
        [
            self.bats.wait_for_acknowledgments(timeout),
            self.balls.wait_for_acknowledgments(timeout),
            self.swings.wait_for_acknowledgments(timeout),
        ]
        .into_iter()
        .all(|r| matches!(r, Ok(true)))
    }
}

/// Something the node answered.
#[derive(Debug, Clone, PartialEq)]
pub enum Answer {
    /// An ExitVelocity.
    Exit(ExitVelocity),
    /// A ModalEnergies.
    Modal(ModalEnergies),
    /// A SweetSpot.
    SweetSpot(SweetSpot),
}

/// Listens to the node's answers in a namespace.
pub struct AnswerListener {
    exits: SimpleDataReaderCdr<ExitVelocity>,
    modals: SimpleDataReaderCdr<ModalEnergies>,
    spots: SimpleDataReaderCdr<SweetSpot>,
}

impl AnswerListener {
    /// Subscribes to `exit_velocity`, `modal_energies` and `sweet_spot` (latched) of `names`.
    pub fn new(ctx: &ros2_client::Context, names: &TopicNames) -> Result<AnswerListener> {
        // Deep enough that a burst of answers waits in our queue instead of being replaced.
        let deep = ros::results_qos().history(ros2_client::qos::History::KeepLast { depth: 10_000 });
        Ok(AnswerListener {
            exits: reader(ctx, &names.exit_velocity, &deep)?,
            modals: reader(ctx, &names.modal_energies, &deep)?,
            spots: reader(ctx, &names.sweet_spot, &ros::sweet_spot_qos())?,
        })
    }

    /// Everything received since the last call (undecodable samples are counted, not fatal).
    pub fn poll(&self) -> (Vec<Answer>, u64) {
        let mut out = Vec::new();
        let bad = take_all(&self.exits, Answer::Exit, &mut out)
            + take_all(&self.modals, Answer::Modal, &mut out)
            + take_all(&self.spots, Answer::SweetSpot, &mut out);
        (out, bad)
    }
}

/// Takes what `reader` holds into `out`, stopping at the first undecodable sample (returns 1 then, else 0).
fn take_all<T: RosMessage>(reader: &SimpleDataReaderCdr<T>, answer: fn(T) -> Answer, out: &mut Vec<Answer>) -> u64 {
    loop {
        match reader.try_take_one() {
            Ok(Some(sample)) => out.push(answer(sample.into_value())),
            Ok(None) => return 0,
            Err(_) => return 1,
        }
    }
}

/// A ros2-client context for `config` (the network-safe factory of `crate::ros`).
pub fn context(config: &DdsConfig) -> Result<ros2_client::Context> {
    ros::context(config).map_err(|e| anyhow!("{e}"))
}
