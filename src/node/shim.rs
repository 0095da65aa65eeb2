//! TEMPORARY stand-ins for the msgs helper's `crate::ros` (participant factory and QoS), until it lands.
use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use ros2_client::QosProfile;

pub fn context() -> anyhow::Result<ros2_client::Context> {
    let domain: u16 = std::env::var("ROS_DOMAIN_ID").ok().and_then(|d| d.parse().ok()).unwrap_or(0);
    anyhow::ensure!(std::env::var("SWEETSPOT_TEST_NETNS").is_ok(), "shim: DDS only inside the test namespace");
    Ok(ros2_client::Context::with_options(ros2_client::ContextOptions::new().domain_id(domain))?)
}

pub mod qos {
    use super::*;
    fn reliable(depth: usize) -> QosProfile {
        QosProfile::publisher_default()
            .reliability(Reliability::Reliable { when_full: WhenFull::Wait(std::time::Duration::from_secs(1)) })
            .history(History::KeepLast { depth })
    }
    pub fn params() -> QosProfile {
        reliable(1).durability(Durability::TransientLocal)
    }
    pub fn swing() -> QosProfile {
        reliable(1000)
    }
    pub fn results() -> QosProfile {
        reliable(1000)
    }
    pub fn latched_results() -> QosProfile {
        reliable(100).durability(Durability::TransientLocal)
    }
    pub fn diagnostics() -> QosProfile {
        reliable(10)
    }
}
