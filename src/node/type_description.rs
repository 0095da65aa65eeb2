//! `~/get_type_description` (REP-2011, `type_description_interfaces/srv/GetTypeDescription`), as ROS 2 Jazzy
//! nodes serve it: a tool that has none of sweetspot's packages installed asks the node for a type it uses
//! (by name, and by RIHS01 hash if it has one) and gets the type's fields, every type it references, and the
//! `.msg`/`.srv` text it was generated from.
//!
//! The descriptions are built from the generated types' own `.msg` text ([`crate::msgs::ALL_TYPES`]), the way
//! rosidl_generator_type_description builds them: one entry per field (type id, array capacity, string bound,
//! nested type name), the referenced types sorted by name, a service as its `request_message`,
//! `response_message` and `event_message`. Its RIHS01 hash is the one build.rs computed (checked in the tests
//! below), so a client can verify what it got.

use crate::model::limits::echo;
use crate::msgs::type_description_interfaces::msg::{
    Field, FieldType, IndividualTypeDescription, KeyValue, TypeDescription, TypeSource,
};
use crate::msgs::type_description_interfaces::srv::{GetTypeDescription_Request, GetTypeDescription_Response};
use crate::msgs::TypeInfo;
use std::collections::BTreeMap;

/// The service's name relative to the node.
pub const SERVICE_NAME: &str = "~/get_type_description";

/// Creates the node's `~/get_type_description` server (reliable, volatile, keep-last 10: ROS 2's service
/// QoS) and answers it on a task of its own until that task is aborted (which drops the server).
pub fn start(
    node: &mut ros2_client::Node,
    names: &super::ros_args::NameResolver,
    mapping: ros2_client::ServiceMapping,
) -> anyhow::Result<tokio::task::JoinHandle<()>> {
    use ros2_client::qos::{History, Reliability};
    let fq_name = names.resolve(SERVICE_NAME);
    let name = crate::ros::names::to_client_name(&fq_name).map_err(|e| anyhow::anyhow!("service {fq_name}: {e}"))?;
    let service_type = ros2_client::ServiceTypeName::new("type_description_interfaces", "GetTypeDescription");
    let qos = ros2_client::QosProfile::publisher_default()
        .reliability(Reliability::Reliable { when_full: ros2_client::qos::WhenFull::DEFAULT })
        .history(History::KeepLast { depth: 10 });
    let server: ros2_client::Server<GetTypeDescription_Request, GetTypeDescription_Response> = node
        .create_server(mapping, &name, &service_type, qos.clone(), qos)
        .map_err(|e| anyhow::anyhow!("service {fq_name}: {e:?}"))?;
    Ok(tokio::spawn(async move {
        loop {
            match server.async_receive_request().await {
                Ok((id, request)) => {
                    if let Err(e) = server.async_send_response(id, answer(&request)).await {
                        tracing::warn!("{fq_name}: cannot send a reply: {e:?}");
                    }
                }
                Err(e) => tracing::warn!("{fq_name}: cannot read a request: {e:?}"),
            }
        }
    }))
}

/// What can go wrong describing a type (the response's `failure_reason`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DescribeError {
    /// The node does not use (or know) a type of that name.
    #[error("Type not currently in use by this node: {0}")]
    UnknownType(String),
    /// A name was given with a hash that is not that type's.
    #[error("Type hash mismatch for {name}: the node's is {ours}, the request has {theirs}")]
    HashMismatch { name: String, ours: String, theirs: String },
    /// A field's `.msg` line could not be read (a generator bug, never user input).
    #[error("cannot describe {type_name}: field line '{line}'")]
    BadField { type_name: String, line: String },
}

/// The answer to one request: the description (with sources if asked) or the reason there is none.
pub fn answer(request: &GetTypeDescription_Request) -> GetTypeDescription_Response {
    match lookup(&request.type_name, &request.type_hash).and_then(|name| describe(&name).map(|d| (name, d))) {
        Ok((name, description)) => GetTypeDescription_Response {
            successful: true,
            failure_reason: String::new(),
            type_sources: if request.include_type_sources { sources(&name, &description) } else { Vec::new() },
            type_description: description,
            extra_information: vec![KeyValue { key: "type_hash".into(), value: hash_of(&name).to_string() }],
        },
        Err(e) => GetTypeDescription_Response {
            successful: false,
            failure_reason: e.to_string(),
            ..GetTypeDescription_Response::default()
        },
    }
}

/// The full ROS 2 name (`pkg/msg/Type`, `pkg/srv/Name`) the request asks for: by name (with the hash, if
/// any, checked), or by hash alone.
fn lookup(name: &str, hash: &str) -> Result<String, DescribeError> {
    if name.is_empty() {
        let by_hash = all_names().into_iter().find(|n| !hash.is_empty() && hash_of(n) == hash);
        return by_hash.ok_or_else(|| DescribeError::UnknownType(format!("(hash {})", echo(hash))));
    }
    if !all_names().iter().any(|n| n == name) {
        return Err(DescribeError::UnknownType(echo(name).into_owned()));
    }
    let ours = hash_of(name);
    if !hash.is_empty() && hash != ours {
        return Err(DescribeError::HashMismatch { name: name.into(), ours: ours.into(), theirs: echo(hash).into() });
    }
    Ok(name.to_string())
}

/// Every type the node can describe: the generated messages (and service halves and events) and the
/// services.
fn all_names() -> Vec<String> {
    let mut names: Vec<String> = crate::msgs::ALL_TYPES.iter().map(|t| t.type_name.to_string()).collect();
    names.extend(services().into_iter().map(|(name, _, _)| name.to_string()));
    names
}

/// The generated services: name, `.srv` text, RIHS01 hash.
fn services() -> Vec<(&'static str, &'static str, &'static str)> {
    use crate::msgs::RosService;
    fn of<S: RosService>() -> (&'static str, &'static str, &'static str) {
        (S::TYPE_NAME, S::SRV_TEXT, S::TYPE_HASH)
    }
    vec![
        of::<crate::msgs::sweetspot_msgs::srv::SimulateSwing>(),
        of::<crate::msgs::type_description_interfaces::srv::GetTypeDescription>(),
    ]
}

/// The RIHS01 hash build.rs computed for `name` (empty if unknown).
fn hash_of(name: &str) -> &'static str {
    if let Some(info) = info(name) {
        return info.type_hash;
    }
    services().into_iter().find(|(n, _, _)| *n == name).map_or("", |(_, _, hash)| hash)
}

/// The request and response halves of the services, which [`crate::msgs::ALL_TYPES`] does not list.
static SERVICE_HALVES: [TypeInfo; 4] = {
    use crate::msgs::sweetspot_msgs::srv::{SimulateSwing_Request, SimulateSwing_Response};
    use crate::msgs::RosMessage;
    [
        SimulateSwing_Request::INFO,
        SimulateSwing_Response::INFO,
        GetTypeDescription_Request::INFO,
        GetTypeDescription_Response::INFO,
    ]
};

fn info(name: &str) -> Option<&'static TypeInfo> {
    crate::msgs::ALL_TYPES.iter().chain(SERVICE_HALVES.iter()).find(|t| t.type_name == name)
}

/// The REP-2011 description of `name` (`pkg/msg/Type`, `pkg/srv/Name_Request`, `pkg/srv/Name`): its own fields
/// and every type it references, sorted by name, each once.
pub fn describe(name: &str) -> Result<TypeDescription, DescribeError> {
    let own = individual(name)?;
    let mut referenced = BTreeMap::new();
    let mut pending: Vec<String> = nested_names(&own);
    while let Some(next) = pending.pop() {
        if referenced.contains_key(&next) {
            continue;
        }
        let description = individual(&next)?;
        pending.extend(nested_names(&description));
        referenced.insert(next, description);
    }
    Ok(TypeDescription { type_description: own, referenced_type_descriptions: referenced.into_values().collect() })
}

fn nested_names(d: &IndividualTypeDescription) -> Vec<String> {
    d.fields.iter().map(|f| f.r#type.nested_type_name.clone()).filter(|n| !n.is_empty()).collect()
}

/// One type's own fields.
fn individual(name: &str) -> Result<IndividualTypeDescription, DescribeError> {
    if let Some((service, _, _)) = services().into_iter().find(|(n, _, _)| *n == name) {
        let nested = |field: &str, suffix: &str| Field {
            name: field.to_string(),
            r#type: FieldType {
                type_id: NESTED,
                nested_type_name: format!("{service}_{suffix}"),
                ..Default::default()
            },
            default_value: String::new(),
        };
        return Ok(IndividualTypeDescription {
            type_name: name.to_string(),
            fields: vec![
                nested("request_message", "Request"),
                nested("response_message", "Response"),
                nested("event_message", "Event"),
            ],
        });
    }
    if let Some(service) = name.strip_suffix("_Event").filter(|s| services().iter().any(|(n, _, _)| n == s)) {
        // rosidl's event type of a service: its info, and the request and the response as sequences of <= 1.
        let field = |field: &str, type_id: u8, capacity: u64, nested: String| Field {
            name: field.to_string(),
            r#type: FieldType { type_id, capacity, string_capacity: 0, nested_type_name: nested },
            default_value: String::new(),
        };
        return Ok(IndividualTypeDescription {
            type_name: name.to_string(),
            fields: vec![
                field("info", NESTED, 0, "service_msgs/msg/ServiceEventInfo".into()),
                field("request", NESTED + BOUNDED_SEQUENCE, 1, format!("{service}_Request")),
                field("response", NESTED + BOUNDED_SEQUENCE, 1, format!("{service}_Response")),
            ],
        });
    }
    let info = info(name).ok_or_else(|| DescribeError::UnknownType(name.to_string()))?;
    let mut fields = Vec::new();
    for line in info.msg_text.lines() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let bad = || DescribeError::BadField { type_name: name.to_string(), line: line.to_string() };
        let mut parts = line.split_whitespace();
        let (Some(ty), Some(field)) = (parts.next(), parts.next()) else { return Err(bad()) };
        if field.contains('=') || parts.next().is_some_and(|p| p.starts_with('=')) {
            continue; // a constant, not a field
        }
        let r#type = field_type(ty, info.package()).ok_or_else(bad)?;
        fields.push(Field { name: field.to_string(), r#type, default_value: String::new() });
    }
    if fields.is_empty() {
        // rosidl gives an empty message one uint8 member.
        fields.push(Field {
            name: "structure_needs_at_least_one_member".into(),
            r#type: FieldType { type_id: 3, ..Default::default() },
            default_value: String::new(),
        });
    }
    Ok(IndividualTypeDescription { type_name: name.to_string(), fields })
}

const NESTED: u8 = 1;
/// Added to an element type's id for a fixed array, a bounded and an unbounded sequence (FieldType.msg).
const ARRAY: u8 = 48;
const BOUNDED_SEQUENCE: u8 = 96;
const UNBOUNDED_SEQUENCE: u8 = 144;

/// A `.msg` field type (`float64`, `string<=10`, `uint8[3]`, `pkg/Type[<=1]`, `Type[]`) in package `pkg`.
fn field_type(ty: &str, pkg: &str) -> Option<FieldType> {
    let (base, array) = match ty.find('[') {
        Some(i) => (&ty[..i], Some(ty[i + 1..].strip_suffix(']')?)),
        None => (ty, None),
    };
    let (base, string_capacity) = match base.split_once("<=") {
        Some((b, n)) => (b, n.parse::<u64>().ok()?),
        None => (base, 0),
    };
    let (mut type_id, nested_type_name) = match base {
        "int8" => (2, String::new()),
        "uint8" | "char" => (3, String::new()),
        "int16" => (4, String::new()),
        "uint16" => (5, String::new()),
        "int32" => (6, String::new()),
        "uint32" => (7, String::new()),
        "int64" => (8, String::new()),
        "uint64" => (9, String::new()),
        "float32" => (10, String::new()),
        "float64" => (11, String::new()),
        "bool" => (15, String::new()),
        "byte" => (16, String::new()),
        "string" if string_capacity > 0 => (21, String::new()),
        "wstring" if string_capacity > 0 => (22, String::new()),
        "string" => (17, String::new()),
        "wstring" => (18, String::new()),
        nested => (NESTED, resolve(nested, pkg)?),
    };
    let capacity = match array {
        None => 0,
        Some("") => {
            type_id += UNBOUNDED_SEQUENCE;
            0
        }
        Some(bound) => match bound.strip_prefix("<=") {
            Some(n) => {
                type_id += BOUNDED_SEQUENCE;
                n.parse().ok()?
            }
            None => {
                type_id += ARRAY;
                bound.parse().ok()?
            }
        },
    };
    Some(FieldType { type_id, capacity, string_capacity, nested_type_name })
}

/// `pkg/Type` or `Type` (in `pkg`) as the full name of a generated type (`pkg/msg/Type`, `pkg/srv/Name_Event`).
fn resolve(nested: &str, pkg: &str) -> Option<String> {
    let (p, n) = nested.split_once('/').unwrap_or((pkg, nested));
    let n = n.rsplit('/').next().unwrap_or(n);
    ["msg", "srv"].iter().map(|kind| format!("{p}/{kind}/{n}")).find(|full| info(full).is_some())
}

/// The `.msg` (or `.srv`) text of the type and of every type it references, as `type_sources`.
fn sources(name: &str, description: &TypeDescription) -> Vec<TypeSource> {
    let source = |n: &str| -> Option<TypeSource> {
        if let Some((_, text, _)) = services().into_iter().find(|(s, _, _)| *s == n) {
            return Some(TypeSource { type_name: n.into(), encoding: "srv".into(), raw_file_contents: text.into() });
        }
        let info = info(n)?;
        Some(TypeSource { type_name: n.into(), encoding: "msg".into(), raw_file_contents: info.msg_text.into() })
    };
    std::iter::once(name)
        .chain(description.referenced_type_descriptions.iter().map(|d| d.type_name.as_str()))
        .filter_map(source)
        .collect()
}

#[cfg(test)]
/// The description as rosidl_generator_type_description serializes it to hash it (REP-2011: JSON with
/// `", "`/`": "` separators, default values left out).
fn hashable_json(description: &TypeDescription) -> String {
    fn individual(d: &IndividualTypeDescription) -> String {
        let fields: Vec<String> = d
            .fields
            .iter()
            .map(|f| {
                format!(
                    "{{\"name\": {}, \"type\": {{\"type_id\": {}, \"capacity\": {}, \"string_capacity\": {}, \
                     \"nested_type_name\": {}}}}}",
                    serde_json::Value::from(f.name.as_str()),
                    f.r#type.type_id,
                    f.r#type.capacity,
                    f.r#type.string_capacity,
                    serde_json::Value::from(f.r#type.nested_type_name.as_str()),
                )
            })
            .collect();
        format!(
            "{{\"type_name\": {}, \"fields\": [{}]}}",
            serde_json::Value::from(d.type_name.as_str()),
            fields.join(", ")
        )
    }
    let referenced: Vec<String> = description.referenced_type_descriptions.iter().map(individual).collect();
    format!(
        "{{\"type_description\": {}, \"referenced_type_descriptions\": [{}]}}",
        individual(&description.type_description),
        referenced.join(", ")
    )
}

#[cfg(test)]
/// The RIHS01 hash of a description: `RIHS01_` and the SHA-256 of [`hashable_json`] in hex.
fn rihs01(description: &TypeDescription) -> String {
    use sha2::Digest;
    let digest = sha2::Sha256::digest(hashable_json(description).as_bytes());
    let hex: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    format!("RIHS01_{hex}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every generated type and service is described so that its RIHS01 hash is the one build.rs computed with
    /// roslibrust_codegen (checked against rosidl's published hashes in tests/type_hashes.rs and
    /// tests/srv_hashes.rs): fields, bounds, nested names and the referenced set all as rosidl has them.
    #[test]
    fn every_description_hashes_to_the_generated_type_hash() {
        let names = all_names();
        assert!(names.iter().any(|n| n == "sweetspot_msgs/srv/SimulateSwing"));
        for name in names {
            let description = describe(&name).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(rihs01(&description), hash_of(&name), "{name}: {}", hashable_json(&description));
        }
    }

    #[test]
    fn unknown_names_and_wrong_hashes_are_refused_with_a_reason() {
        let ask = |name: &str, hash: &str| {
            answer(&GetTypeDescription_Request {
                type_name: name.into(),
                type_hash: hash.into(),
                include_type_sources: true,
            })
        };
        let swing = ask("sweetspot_msgs/msg/Swing", "");
        assert!(swing.successful, "{}", swing.failure_reason);
        assert_eq!(swing.type_sources[0].raw_file_contents, info("sweetspot_msgs/msg/Swing").unwrap().msg_text);
        let by_hash = ask("", hash_of("sweetspot_msgs/msg/Swing"));
        assert_eq!(by_hash.type_description.type_description.type_name, "sweetspot_msgs/msg/Swing");
        let unknown = ask("nav_msgs/msg/Odometry", "");
        assert!(!unknown.successful && unknown.failure_reason.contains("nav_msgs/msg/Odometry"));
        let wrong = ask("sweetspot_msgs/msg/Swing", hash_of("sweetspot_msgs/msg/ExitVelocity"));
        assert!(!wrong.successful && wrong.failure_reason.contains("mismatch"), "{}", wrong.failure_reason);
    }

    /// A peer's name or hash is echoed in the failure reason at most 256 bytes long (the node's bound for
    /// any peer string it echoes), however long the request's: a 1 MB name gets a short answer, not 1 MB back.
    #[test]
    fn a_huge_name_or_hash_is_echoed_cut() {
        let huge = "x".repeat(1 << 20);
        for (type_name, type_hash) in
            [(huge.as_str(), ""), ("", huge.as_str()), ("sweetspot_msgs/msg/Swing", huge.as_str())]
        {
            let reply = answer(&GetTypeDescription_Request {
                type_name: type_name.into(),
                type_hash: type_hash.into(),
                include_type_sources: false,
            });
            assert!(!reply.successful);
            assert!(reply.failure_reason.len() < 600, "{} bytes", reply.failure_reason.len());
            assert!(reply.failure_reason.contains("(1048576 bytes)"), "{}", &reply.failure_reason);
        }
    }
}
