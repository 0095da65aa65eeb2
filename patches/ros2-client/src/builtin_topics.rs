use rustdds::{policy::*, *};

/// The USER_DATA ROS 2 (Iron and later) gives every DataWriter and DataReader:
/// `typehash=RIHS01_<64 hex>;` (rmw_dds_common's
/// `encode_type_hash_for_user_data_qos`), from which peers learn the type's
/// hash.
fn type_hash_user_data(hash: &str) -> Vec<u8> {
  format!("typehash={hash};").into_bytes()
}

pub mod ros_discovery {
  use super::*;

  lazy_static! {
    pub static ref QOS_PUB: QosPolicies = QosPolicyBuilder::new()
      .durability(Durability::TransientLocal)
      .deadline(Deadline(Duration::INFINITE))
      .ownership(Ownership::Shared)
      .reliable(Duration::ZERO)
      .history(History::KeepLast { depth: 1 })
      .lifespan(Lifespan {
        duration: Duration::INFINITE
      })
      .build()
      .with_user_data(type_hash_user_data(TYPE_HASH));
    pub static ref QOS_SUB: QosPolicies = QosPolicyBuilder::new()
      .durability(Durability::Volatile)
      .ownership(Ownership::Shared)
      .reliable(Duration::ZERO)
      .history(History::KeepLast { depth: 1 })
      .lifespan(Lifespan {
        duration: Duration::INFINITE
      })
      .build()
      .with_user_data(type_hash_user_data(TYPE_HASH));
  }

  pub const TOPIC_NAME: &str = "ros_discovery_info";

  pub const TYPE_NAME: &str = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";

  /// RIHS01 hash of rmw_dds_common/msg/ParticipantEntitiesInfo (Jazzy, Kilted).
  pub const TYPE_HASH: &str =
    "RIHS01_91a0593bacdcc50ea9bdcf849a938b128412cc1ea821245c663bcd26f83c295e";
}

pub mod parameter_events {
  use super::*;

  lazy_static! {
    pub static ref QOS: QosPolicies = QosPolicyBuilder::new()
      .durability(Durability::TransientLocal)
      .reliable(Duration::ZERO)
      .history(History::KeepLast { depth: 1 })
      .build()
      .with_user_data(type_hash_user_data(TYPE_HASH));
  }

  pub const TOPIC_NAME: &str = "rt/parameter_events";

  pub const TYPE_NAME: &str = "rcl_interfaces::msg::dds_::ParameterEvent_";

  /// RIHS01 hash of rcl_interfaces/msg/ParameterEvent (Jazzy, Kilted).
  pub const TYPE_HASH: &str =
    "RIHS01_043e627780fcad87a22d225bc2a037361dba713fca6a6b9f4b869a5aa0393204";
}

pub mod rosout {
  use super::*;

  lazy_static! {
    pub static ref QOS: QosPolicies = QosPolicyBuilder::new()
      .durability(Durability::TransientLocal)
      .deadline(Deadline(Duration::INFINITE))
      .ownership(Ownership::Shared)
      .reliable(Duration::ZERO)
      .history(History::KeepLast { depth: 1 })
      .lifespan(Lifespan {
        duration: Duration::from_secs(10)
      })
      .build()
      .with_user_data(type_hash_user_data(TYPE_HASH));
  }

  pub const TOPIC_NAME: &str = "rt/rosout";

  pub const TYPE_NAME: &str = "rcl_interfaces::msg::dds_::Log_";

  /// RIHS01 hash of rcl_interfaces/msg/Log (Jazzy, Kilted).
  pub const TYPE_HASH: &str =
    "RIHS01_e28ce254ca8abc06abf92773b74602cdbf116ed34fbaf294fb9f81da9f318eac";
}
