//! Message types generated at build time from `msgs/` (the one source of truth).
//!
//! `build.rs` turns every `msgs/<pkg>/msg/*.msg` (and the vendored official ROS definitions under
//! `msgs/ros_interfaces/`) into a struct in `sweetspot::msgs::<pkg>::msg`, e.g.
//! [`sweetspot_msgs::msg::Swing`], [`std_msgs::msg::Header`], [`builtin_interfaces::msg::Time`],
//! [`diagnostic_msgs::msg::DiagnosticArray`], [`rcl_interfaces::msg::Log`]. Fields are public and in `.msg`
//! order (serde serialises them in that order, which is the CDR layout); constants are associated consts.
//!
//! Every type implements [`RosMessage`] (type names, the `ros2msg` schema text and the RIHS01 type hash rosbag2
//! stores), [`Transport`] (with the `ros2` feature: `ros2_client::Message`, so it can be published with
//! ros2-client), and the tolerant JSON conversions
//! of [`json`] used by `sweetspot pub` / `echo`. [`encode_cdr`] / [`decode_cdr`] produce and read the bytes
//! ROS 2 puts on the wire and rosbag2 stores in bags: a 4-byte encapsulation header and a CDR body.

pub mod json;

include!(concat!(env!("OUT_DIR"), "/msgs.rs"));

/// Errors of message encoding, decoding and conversion.
#[derive(Debug, thiserror::Error)]
pub enum MsgError {
    /// Input shorter than the 4-byte encapsulation header.
    #[error("CDR data too short: {len} bytes, the encapsulation header alone needs 4")]
    MissingHeader { len: usize },
    /// An encapsulation kind other than plain CDR (big or little endian).
    #[error("unsupported CDR encapsulation {0:#06x} (only CDR_BE 0x0000 and CDR_LE 0x0001 are supported)")]
    UnsupportedEncapsulation(u16),
    /// The CDR body does not decode as the expected type (truncated, bad string, bad bool, …).
    #[error("malformed CDR for {type_name}: {source}")]
    Malformed {
        type_name: &'static str,
        #[source]
        source: cdr_encoding::Error,
    },
    /// The body decoded but more bytes than the at most 3 alignment padding bytes follow it.
    #[error("malformed CDR for {type_name}: {extra} unexpected bytes after the message")]
    TrailingBytes { type_name: &'static str, extra: usize },
    /// The value could not be serialised (should not happen for generated types).
    #[error("cannot encode {type_name} as CDR: {source}")]
    Encode {
        type_name: &'static str,
        #[source]
        source: cdr_encoding::Error,
    },
    /// A JSON value does not fit a message field.
    #[error("{path}: {reason}")]
    Json { path: String, reason: String },
    /// A type name that is not one of the generated messages.
    #[error("unknown message type `{0}`")]
    UnknownType(String),
}

/// Names and schema of a generated message type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TypeInfo {
    /// ROS 2 type name, e.g. `sweetspot_msgs/msg/Swing`.
    pub type_name: &'static str,
    /// DDS type name, e.g. `sweetspot_msgs::msg::dds_::Swing_`.
    pub dds_type_name: &'static str,
    /// Full `ros2msg` schema text (own text, then each dependency after a `=`×80 / `MSG: pkg/Type` line).
    pub schema_text: &'static str,
    /// The message's own `.msg` text.
    pub msg_text: &'static str,
    /// RIHS01 type description hash (REP-2011), e.g. `RIHS01_5a8a…`, as rosidl computes it.
    pub type_hash: &'static str,
}

impl TypeInfo {
    /// The ROS package, e.g. `sweetspot_msgs`.
    pub fn package(&self) -> &'static str {
        self.type_name.split('/').next().unwrap_or(self.type_name)
    }

    /// The bare type name, e.g. `Swing`.
    pub fn name(&self) -> &'static str {
        self.type_name.rsplit('/').next().unwrap_or(self.type_name)
    }
}

/// What a message needs to travel: with the `ros2` feature, ros2-client's `Message` (serde both ways); without
/// it (the Python package, the analyses), serde alone, so that nothing here pulls DDS in.
#[cfg(feature = "ros2")]
pub trait Transport: ros2_client::Message {}
#[cfg(feature = "ros2")]
impl<T: ros2_client::Message> Transport for T {}
/// What a message needs to travel: serde both ways (ros2-client's `Message` with the `ros2` feature).
#[cfg(not(feature = "ros2"))]
pub trait Transport: serde::Serialize + serde::de::DeserializeOwned {}
#[cfg(not(feature = "ros2"))]
impl<T: serde::Serialize + serde::de::DeserializeOwned> Transport for T {}

/// A message generated from a `.msg` file: its ROS and DDS names and the schema text rosbag2 stores.
pub trait RosMessage:
    Transport + Clone + std::fmt::Debug + PartialEq + Default + json::FromJson + json::ToJson + Send + Sync + 'static
{
    /// ROS 2 type name, e.g. `"sweetspot_msgs/msg/Swing"`.
    const TYPE_NAME: &'static str;
    /// DDS type name, e.g. `"sweetspot_msgs::msg::dds_::Swing_"`.
    const DDS_TYPE_NAME: &'static str;
    /// The full `ros2msg` text: the message's own `.msg` text, then for every dependency (depth-first, each
    /// once, dependencies of one message in sorted order) `"\n"`, a line of 80 `=`, `"MSG: pkg/Type"` and its
    /// text — exactly as rosbag2 writes MCAP schemas.
    const SCHEMA_TEXT: &'static str;
    /// The message's own `.msg` text.
    const MSG_TEXT: &'static str;
    /// RIHS01 type description hash (REP-2011) of the type and every type it references, computed by build.rs
    /// from the `.msg` files the way rosidl_generator_type_description does (field names, types, bounds and
    /// order; comments, constants and default values do not count): what ROS 2 Jazzy advertises in discovery
    /// and rosbag2 stores as `type_description_hash` / `topic_type_hash`.
    const TYPE_HASH: &'static str;
    /// All of the above in one value.
    const INFO: TypeInfo = TypeInfo {
        type_name: Self::TYPE_NAME,
        dds_type_name: Self::DDS_TYPE_NAME,
        schema_text: Self::SCHEMA_TEXT,
        msg_text: Self::MSG_TEXT,
        type_hash: Self::TYPE_HASH,
    };
}

/// A service generated from a `.srv` file (`sweetspot::msgs::<pkg>::srv::<Name>`): its request and response
/// types (`<Name>_Request`, `<Name>_Response`, ROS 2's `pkg/srv/Name_Request` and DDS
/// `pkg::srv::dds_::Name_Request_`), its text and the RIHS01 hash of the service, which ROS 2 advertises in the
/// USER_DATA of both of the service's DDS topics.
pub trait RosService: 'static {
    /// The request half of the `.srv`.
    type Request: RosMessage;
    /// The response half of the `.srv`.
    type Response: RosMessage;
    /// `pkg/srv/Name_Event` (`service_msgs/ServiceEventInfo info`, the request and the response as sequences
    /// of at most one), the message of ROS 2's service introspection and of rosbag2's recorded services.
    type Event: RosMessage;
    /// ROS 2 type name, e.g. `"sweetspot_msgs/srv/SimulateSwing"`.
    const TYPE_NAME: &'static str;
    /// The `.srv` text.
    const SRV_TEXT: &'static str;
    /// RIHS01 hash of the service's type description (the service with its request, response and event types,
    /// as rosidl_generator_type_description describes a service).
    const TYPE_HASH: &'static str;
}

/// One entry of a message's [`FieldTable`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldValue<'a> {
    /// A `float32` or `float64` field.
    Float(f64),
    /// A signed integer field.
    Int(i64),
    /// An unsigned integer, `byte` or `char` field.
    Uint(u64),
    /// A `bool` field.
    Bool(bool),
    /// A `string` field.
    Text(&'a str),
    /// A `float64` sequence.
    Floats(&'a [f64]),
}

impl FieldValue<'_> {
    /// The value as a number (`None` for text and sequences); integers above 2⁵³ round.
    pub fn number(&self) -> Option<f64> {
        match *self {
            FieldValue::Float(x) => Some(x),
            FieldValue::Int(x) => Some(x as f64),
            FieldValue::Uint(x) => Some(x as f64),
            FieldValue::Bool(x) => Some(f64::from(u8::from(x))),
            FieldValue::Text(_) | FieldValue::Floats(_) => None,
        }
    }
}

/// A scalar as a CSV cell: numbers in Rust's shortest round-trip form, text as is (a sequence has no cell).
impl std::fmt::Display for FieldValue<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FieldValue::Float(x) => write!(f, "{x}"),
            FieldValue::Int(x) => write!(f, "{x}"),
            FieldValue::Uint(x) => write!(f, "{x}"),
            FieldValue::Bool(x) => write!(f, "{x}"),
            FieldValue::Text(x) => f.write_str(x),
            FieldValue::Floats(_) => Ok(()),
        }
    }
}

/// A generated message's fields as a table, in `.msg` order: every scalar field and every `float64` sequence
/// (nested messages and other arrays are left out). Bag export's columns and replay's comparison are made from
/// it, so a field added to a `.msg` file reaches them without a line of code.
pub trait FieldTable {
    /// Each field's name and value.
    fn field_table(&self) -> Vec<(&'static str, FieldValue<'_>)>;
}

/// Looks a generated type up by ROS name, `pkg/msg/Type` or `pkg/Type`.
pub fn type_info(type_name: &str) -> Option<&'static TypeInfo> {
    let normalized = normalize_type_name(type_name)?;
    ALL_TYPES.iter().find(|t| t.type_name == normalized)
}

/// The full `ros2msg` schema text of a generated type (`pkg/msg/Type` or `pkg/Type`), as rosbag2 stores it.
pub fn schema_for(type_name: &str) -> Option<&'static str> {
    type_info(type_name).map(|t| t.schema_text)
}

/// The RIHS01 type hash of a generated type (`pkg/msg/Type` or `pkg/Type`).
pub fn type_hash_for(type_name: &str) -> Option<&'static str> {
    type_info(type_name).map(|t| t.type_hash)
}

/// `pkg/Type` or `pkg/msg/Type` → `pkg/msg/Type`.
fn normalize_type_name(type_name: &str) -> Option<String> {
    let parts: Vec<&str> = type_name.split('/').collect();
    match parts.as_slice() {
        [pkg, name] => Some(format!("{pkg}/msg/{name}")),
        [pkg, "msg", name] => Some(format!("{pkg}/msg/{name}")),
        _ => None,
    }
}

/// The encapsulation header of little-endian plain CDR (`CDR_LE`), as ROS 2 writes it.
pub const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// Serialises a message the way ROS 2 and rosbag2 do: `00 01 00 00` (CDR_LE, no options) followed by the
/// little-endian CDR body, aligned relative to the start of the body.
pub fn encode_cdr<T: serde::Serialize>(message: &T) -> Result<Vec<u8>, MsgError> {
    let mut out = Vec::with_capacity(64);
    out.extend_from_slice(&CDR_LE_HEADER);
    cdr_encoding::to_writer::<T, byteorder::LittleEndian, _>(&mut out, message)
        .map_err(|source| MsgError::Encode { type_name: std::any::type_name::<T>(), source })?;
    Ok(out)
}

/// Decodes bytes written by [`encode_cdr`], by any ROS 2 middleware or from a bag: accepts both the
/// little-endian (`00 01`) and big-endian (`00 00`) plain CDR headers and up to 3 trailing padding bytes.
/// Malformed or truncated input gives a typed error, never a panic.
pub fn decode_cdr<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> Result<T, MsgError> {
    if bytes.len() < 4 {
        return Err(MsgError::MissingHeader { len: bytes.len() });
    }
    let kind = u16::from_be_bytes([bytes[0], bytes[1]]);
    let body = &bytes[4..];
    let type_name = std::any::type_name::<T>();
    let (value, consumed) = match kind {
        0x0001 => cdr_encoding::from_bytes::<T, byteorder::LittleEndian>(body),
        0x0000 => cdr_encoding::from_bytes::<T, byteorder::BigEndian>(body),
        other => return Err(MsgError::UnsupportedEncapsulation(other)),
    }
    .map_err(|source| MsgError::Malformed { type_name, source })?;
    let extra = body.len().saturating_sub(consumed);
    if extra > 3 {
        return Err(MsgError::TrailingBytes { type_name, extra });
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn swing_names_and_schema() {
        use sweetspot_msgs::msg::Swing;
        assert_eq!(Swing::TYPE_NAME, "sweetspot_msgs/msg/Swing");
        assert_eq!(Swing::DDS_TYPE_NAME, "sweetspot_msgs::msg::dds_::Swing_");
        assert!(Swing::SCHEMA_TEXT.starts_with(Swing::MSG_TEXT));
        assert!(Swing::SCHEMA_TEXT.contains("\nMSG: std_msgs/Header\n"));
        assert!(Swing::SCHEMA_TEXT.contains("\nMSG: builtin_interfaces/Time\n"));
        assert_eq!(schema_for("sweetspot_msgs/Swing"), Some(Swing::SCHEMA_TEXT));
        assert_eq!(schema_for("sweetspot_msgs/msg/Swing"), Some(Swing::SCHEMA_TEXT));
        assert_eq!(schema_for("sweetspot_msgs/msg/Nope"), None);
    }

    #[test]
    fn field_tables_follow_the_msg_files() {
        use sweetspot_msgs::msg::{ModalEnergies, Swing};
        let swing = Swing { bat_id: "r161".into(), ball_speed: 40.0, batter_side: 1, ..Swing::default() };
        let names: Vec<&str> = swing.field_table().iter().map(|(n, _)| *n).collect();
        // Swing.msg's fields but the nested header, in file order.
        assert_eq!(
            names,
            [
                "swing_id",
                "bat_id",
                "ball_id",
                "ball_speed",
                "bat_cm_speed",
                "bat_angular_speed",
                "impact_z",
                "measured_exit_speed",
                "undercut",
                "attack_angle",
                "pitch_angle",
                "pitch_spin",
                "measured_launch_angle",
                "measured_spin",
                "bat_tilt",
                "swing_direction",
                "batter_side",
                "measured_spray_angle",
                "measured_spin_axis"
            ]
        );
        let table = swing.field_table();
        assert_eq!(table[1].1, FieldValue::Text("r161"));
        assert_eq!(table[3].1, FieldValue::Float(40.0));
        assert_eq!(table[16].1, FieldValue::Uint(1));
        assert_eq!(table[16].1.to_string(), "1");
        let me = ModalEnergies { energy: vec![1.5, 2.5], ..ModalEnergies::default() };
        let table = me.field_table();
        assert!(table.contains(&("energy", FieldValue::Floats(&[1.5, 2.5]))));
        assert_eq!(table.iter().find(|(n, _)| *n == "energy").map(|(_, v)| v.number()), Some(None));
    }

    #[test]
    fn constants_are_associated() {
        use sweetspot_msgs::msg::ExitVelocity;
        assert_eq!(ExitVelocity::STATUS_OK, 0u8);
        assert_eq!(ExitVelocity::STATUS_REJECTED, 1u8);
        assert_eq!(ExitVelocity::STATUS_DROPPED, 2u8);
        assert_eq!(diagnostic_msgs::msg::DiagnosticStatus::STALE, 3u8);
        assert_eq!(rcl_interfaces::msg::Log::FATAL, 50u8);
    }
}
