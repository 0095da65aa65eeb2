//! Shared helpers of the node tests: the `sweetspot node` process, a unique DDS domain per test, and an
//! in-test ros2-client participant. Every DDS use goes through the msgs helper's network guard first.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A running `sweetspot node`; killed if the test ends without stopping it.
pub struct NodeProcess {
    child: Option<Child>,
    stderr: Arc<Mutex<Vec<String>>>,
}

impl NodeProcess {
    /// Starts the node binary on `domain` in `cwd` with `args` after `node`.
    pub fn spawn(domain: u16, cwd: &Path, args: &[&str]) -> NodeProcess {
        let mut child = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
            .arg("node")
            .args(args)
            .current_dir(cwd)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .env("RUST_LOG", "info,rustdds=error,ros2_client=error,ros2_client::parameter_services=warn")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("starting the sweetspot binary");
        let stderr = Arc::new(Mutex::new(Vec::new()));
        let pipe = child.stderr.take().expect("piped stderr");
        let lines = Arc::clone(&stderr);
        std::thread::spawn(move || {
            for line in BufReader::new(pipe).lines().map_while(Result::ok) {
                lines.lock().unwrap().push(line);
            }
        });
        NodeProcess { child: Some(child), stderr }
    }

    /// Waits until a stderr line contains `needle` (panics with the log after `limit`).
    pub fn wait_for_log(&self, needle: &str, limit: Duration) {
        let start = Instant::now();
        loop {
            if self.stderr.lock().unwrap().iter().any(|l| l.contains(needle)) {
                return;
            }
            if start.elapsed() > limit {
                panic!("node never logged '{needle}'; stderr:\n{}", self.log());
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// The node's process id.
    pub fn pid(&self) -> u32 {
        self.child.as_ref().map_or(0, |c| c.id())
    }

    /// Everything the node wrote to stderr so far.
    pub fn log(&self) -> String {
        self.stderr.lock().unwrap().join("\n")
    }

    /// Sends `signal` (e.g. libc SIGTERM = 15) and waits for the exit; returns status, time to exit, log.
    pub fn stop_with(mut self, signal: i32) -> (ExitStatus, Duration, String) {
        let mut child = self.child.take().expect("running");
        let pid = child.id().to_string();
        let sent = Instant::now();
        let status = Command::new("kill").arg(format!("-{signal}")).arg(&pid).status().expect("kill");
        assert!(status.success(), "kill -{signal} {pid} failed");
        // Generous limit only to turn a hang into a failure instead of a stuck suite.
        loop {
            if let Some(status) = child.try_wait().expect("try_wait") {
                let elapsed = sent.elapsed();
                std::thread::sleep(Duration::from_millis(50)); // let the stderr reader drain
                return (status, elapsed, self.log());
            }
            if sent.elapsed() > Duration::from_secs(30) {
                let _ = child.kill();
                panic!("node did not exit within 30 s of signal {signal}; stderr:\n{}", self.log());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for NodeProcess {
    fn drop(&mut self) {
        if let Some(mut child) = self.child.take() {
            if std::thread::panicking() {
                // Ask for the node's own summary before showing its log with the failure.
                let _ = Command::new("kill").arg("-15").arg(child.id().to_string()).status();
                let start = Instant::now();
                while child.try_wait().ok().flatten().is_none() && start.elapsed() < Duration::from_secs(5) {
                    std::thread::sleep(Duration::from_millis(20));
                }
                std::thread::sleep(Duration::from_millis(50));
                eprintln!("---- sweetspot node stderr ----\n{}\n-------------------------------", self.log());
            }
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// A DDS domain id unique to one test (parallel tests never share one). Node tests use 100..=199.
pub fn domain(offset: u16) -> u16 {
    100 + offset
}

#[allow(unused_imports)] // used by some test files only
pub use super::python;

// ---------------------------------------------------------------------------------------------------------
// An in-test ROS 2 participant (ros2-client), for publishing inputs and listening to the node.
// ---------------------------------------------------------------------------------------------------------

use std::pin::pin;

use futures::StreamExt;
use ros2_client::qos::{History, Reliability, WhenFull};
use ros2_client::{Node, NodeName, NodeOptions, Publisher, QosProfile, Subscription};
use sweetspot::msgs::RosMessage;

pub use super::require_isolated_network;

/// A ros2-client node of the test on `domain`, with its own async runtime.
pub struct Peer {
    pub rt: tokio::runtime::Runtime,
    pub node: Node,
    pub context: ros2_client::Context,
}

impl Peer {
    /// A node named `name` on `domain`.
    pub fn new(domain: u16, name: &str) -> Peer {
        require_isolated_network();
        let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().unwrap();
        let context = dds::context(domain);
        let mut node = context
            .new_node(NodeName::new("/", name).unwrap(), NodeOptions::new().enable_rosout(false))
            .expect("test node");
        let spinner = node.spinner().expect("spinner");
        rt.spawn(spinner.spin());
        Peer { rt, node, context }
    }

    /// A publisher of `M` on the absolute topic `name` with `qos`.
    pub fn publisher<M: RosMessage>(&mut self, name: &str, qos: QosProfile) -> Publisher<M> {
        let topic = dds::topic::<M>(&self.node, name, &qos);
        self.node.create_publisher::<M>(&topic, None).expect("publisher")
    }

    /// A subscription to `M` on the absolute topic `name` with `qos`.
    pub fn subscription<M: RosMessage>(&mut self, name: &str, qos: QosProfile) -> Subscription<M> {
        let topic = dds::topic::<M>(&self.node, name, &qos);
        self.node.create_subscription::<M>(&topic, None).expect("subscription")
    }

    /// Waits until `publisher` is matched with a subscription (the node's), or panics after 60 s.
    pub fn wait_for_reader<M: RosMessage>(&self, publisher: &Publisher<M>) {
        self.rt
            .block_on(async {
                tokio::time::timeout(Duration::from_secs(60), publisher.wait_for_subscription(&self.node)).await
            })
            .expect("no subscription matched the test publisher within 60 s");
    }

    /// Takes messages until `done(&received)` says enough, or panics after `limit` without a new one.
    pub fn collect_until<M: RosMessage>(
        &self,
        subscription: &Subscription<M>,
        limit: Duration,
        mut done: impl FnMut(&[M]) -> bool,
    ) -> Vec<M> {
        self.rt.block_on(async {
            let mut out = Vec::new();
            let mut stream = pin!(subscription.async_stream());
            // Periodic topics (diagnostics) never go quiet: bound the whole wait too.
            let deadline = Instant::now() + limit * 3;
            while !done(&out) {
                assert!(
                    Instant::now() < deadline,
                    "condition not met within {:?} ({} messages of {})",
                    limit * 3,
                    out.len(),
                    M::TYPE_NAME
                );
                match tokio::time::timeout(limit, stream.next()).await {
                    Ok(Some(Ok((msg, _)))) => out.push(msg),
                    Ok(Some(Err(e))) => panic!("receive error: {e:?}"),
                    Ok(None) => panic!("subscription stream ended"),
                    Err(_) => panic!("nothing new for {limit:?} after {} messages of {}", out.len(), M::TYPE_NAME),
                }
            }
            out
        })
    }

    /// Exactly `n` messages (panics if one takes longer than `limit`).
    pub fn collect<M: RosMessage>(&self, subscription: &Subscription<M>, n: usize, limit: Duration) -> Vec<M> {
        self.collect_until(subscription, limit, |got| got.len() >= n)
    }
}

/// The node's three inputs published by a test peer, and the node's answers.
pub struct NodeInputs {
    pub bat: Publisher<sweetspot::msgs::sweetspot_msgs::msg::BatParams>,
    pub ball: Publisher<sweetspot::msgs::sweetspot_msgs::msg::BallParams>,
    pub swing: Publisher<sweetspot::msgs::sweetspot_msgs::msg::Swing>,
    pub answers: Subscription<sweetspot::msgs::sweetspot_msgs::msg::ExitVelocity>,
}

impl NodeInputs {
    /// Publishers of /bat/params, /ball/params and /swing (blocking when the window is full) and a reader of
    /// /exit_velocity that keeps every answer, on `peer`.
    pub fn on(peer: &mut Peer) -> NodeInputs {
        NodeInputs {
            bat: peer.publisher("/bat/params", dds::params()),
            ball: peer.publisher("/ball/params", dds::params()),
            swing: peer.publisher("/swing", blocking(dds::swing())),
            answers: peer.subscription("/exit_velocity", keep_all(dds::results())),
        }
    }

    /// Waits until the node reads all three inputs, then lets its readers settle (300 ms): what a test
    /// publishes next is taken.
    pub fn wait_for_node(&self, peer: &Peer) {
        peer.wait_for_reader(&self.bat);
        peer.wait_for_reader(&self.ball);
        peer.wait_for_reader(&self.swing);
        std::thread::sleep(Duration::from_millis(300));
    }
}

/// A reader QoS that never loses what the node sent reliably, however slowly the test takes it. (Not
/// KeepAll: RustDDS caps a KeepAll reader without resource limits at 64 samples.)
pub fn keep_all(qos: QosProfile) -> QosProfile {
    qos.history(History::KeepLast { depth: 20_000 })
}

/// A writer QoS that blocks instead of failing when the reliable send window is full.
pub fn blocking(qos: QosProfile) -> QosProfile {
    qos.reliability(Reliability::Reliable { when_full: WhenFull::Block })
}

/// DDS plumbing of the tests: the msgs helper's network-safe factory, topics and QoS.
pub mod dds {
    use ros2_client::{Context, Node, QosProfile};
    use sweetspot::msgs::RosMessage;
    use sweetspot::ros::{DdsConfig, DiscoveryRange};

    #[allow(unused_imports)] // kept for test files that call it directly
    pub use sweetspot::ros::network_guard;

    /// A loopback-only context on `domain`.
    pub fn context(domain: u16) -> Context {
        sweetspot::ros::context(&DdsConfig { domain_id: domain, range: DiscoveryRange::Localhost }).expect("context")
    }

    /// The topic `name` (absolute) for `M`.
    pub fn topic<M: RosMessage>(node: &Node, name: &str, qos: &QosProfile) -> rustdds::Topic {
        sweetspot::ros::create_topic::<M>(node, name, qos).expect("topic")
    }

    pub fn params() -> QosProfile {
        sweetspot::ros::params_qos()
    }
    pub fn swing() -> QosProfile {
        sweetspot::ros::swing_qos()
    }
    pub fn results() -> QosProfile {
        sweetspot::ros::results_qos()
    }
    pub fn latched_results() -> QosProfile {
        sweetspot::ros::sweet_spot_qos()
    }
}
