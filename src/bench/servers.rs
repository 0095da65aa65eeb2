//! The servers the bench measures, each a child process of the bench on its own DDS domain: the raw
//! ros2-client echo (`sweetspot bench --echo-server`) and the node, recording.

use std::path::Path;
use std::pin::pin;
use std::time::{Duration, Instant};

use futures::StreamExt;
use ros2_client::qos::{History, Reliability, WhenFull};
use ros2_client::{NodeName, NodeOptions};

use super::client::{dds, dds_config};
use super::require_private_network;
use crate::child::{ChildCommand, ChildProcess};
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};

/// How long a server is given to exit after SIGTERM (a node finishes its bag first).
const STOP_GRACE: Duration = Duration::from_secs(20);

/// Runs the raw ros2-client echo on `domain` until killed: every `Swing` on `/swing` is answered on
/// `/exit_velocity` with an `ExitVelocity` carrying its ids, with the node's QoS on both sides — at once, or
/// after spinning for `work`.
pub fn run_echo_server(domain: u16, work: Duration) -> anyhow::Result<()> {
    require_private_network()?;
    let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
    let context = crate::ros::context(&dds_config(domain))?;
    let mut node = context
        .new_node(NodeName::new("/", "sweetspot_raw_echo").map_err(dds)?, NodeOptions::new().enable_rosout(false))
        .map_err(dds)?;
    let swing_topic = crate::ros::create_topic::<Swing>(&node, "/swing", &crate::ros::swing_qos())?;
    let ev_topic = crate::ros::create_topic::<ExitVelocity>(&node, "/exit_velocity", &crate::ros::results_qos())?;
    let reader_qos = crate::ros::swing_qos().history(History::KeepLast { depth: 16_384 });
    let sub = node.create_subscription::<Swing>(&swing_topic, Some(reader_qos)).map_err(dds)?;
    let writer_qos = crate::ros::results_qos()
        .history(History::KeepLast { depth: 1000 })
        .reliability(Reliability::Reliable { when_full: WhenFull::Wait(Duration::from_millis(500)) });
    let publisher = node.create_publisher::<ExitVelocity>(&ev_topic, Some(writer_qos)).map_err(dds)?;
    let spinner = node.spinner().map_err(dds)?;
    rt.spawn(spinner.spin());
    eprintln!("raw echo up on domain {domain}");
    rt.block_on(async move {
        let mut stream = pin!(sub.async_stream());
        while let Some(received) = stream.next().await {
            if let Ok((swing, _)) = received {
                // Spin rather than sleep: the node's physics keeps the core busy for as long.
                let start = Instant::now();
                while start.elapsed() < work {
                    std::hint::spin_loop();
                }
                let ev = ExitVelocity {
                    header: swing.header.clone(),
                    swing_id: swing.swing_id,
                    bat_id: swing.bat_id,
                    ball_id: swing.ball_id,
                    impact_z: swing.impact_z,
                    measured_exit_speed: swing.measured_exit_speed,
                    ..ExitVelocity::default()
                };
                let _ = publisher.publish(ev);
            }
        }
    });
    Ok(())
}

/// `exe` with the bench's environment: DDS `domain` on loopback, quiet DDS logs, `cwd` as working directory.
fn bench_child(command: ChildCommand, domain: u16, cwd: &Path) -> ChildCommand {
    command
        .current_dir(cwd)
        .env(crate::ros::ENV_DOMAIN_ID, domain.to_string())
        .env(crate::ros::ENV_DISCOVERY_RANGE, "LOCALHOST")
        .env("RUST_LOG", "warn,rustdds=error,ros2_client=error")
}

/// Starts `exe bench --echo-server` on `domain`.
pub(super) fn start_echo(exe: &Path, domain: u16, cwd: &Path) -> anyhow::Result<ChildProcess> {
    let command = ChildCommand::new(exe, "the raw echo")
        .arg("bench")
        .arg("--echo-server")
        .arg("--domain")
        .arg(domain.to_string());
    bench_child(command, domain, cwd).spawn()
}

/// Starts `exe` as `sweetspot node` on `domain`, recording to a fresh `bag_dir`, diagnostics every 0.5 s, and
/// serving Foxglove on 127.0.0.1:`foxglove_port` if given.
pub(super) fn start_recording_node(
    exe: &Path,
    bag_dir: &Path,
    domain: u16,
    cwd: &Path,
    foxglove_port: Option<u16>,
) -> anyhow::Result<ChildProcess> {
    let _ = std::fs::remove_dir_all(bag_dir);
    let mut command = ChildCommand::node(exe).param("record_path", bag_dir.display()).param("diagnostics_period", 0.5);
    if let Some(port) = foxglove_port {
        command = command.param("foxglove_port", format!("127.0.0.1:{port}"));
    }
    bench_child(command, domain, cwd).spawn()
}

/// Stops a server and returns what it wrote to stderr (its shutdown summary is at the end).
pub(super) fn stop(mut server: ChildProcess) -> String {
    let _ = server.stop(STOP_GRACE);
    server.output()
}
