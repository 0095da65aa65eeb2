//! `sweetspot param list|get|set|describe|dump NODE …`: a running node's parameters, as `ros2 param` shows and
//! changes them, through the node's rcl_interfaces services (`NODE/list_parameters`, `get_parameters`,
//! `set_parameters`, `describe_parameters`) — for sweetspot's node or any ROS 2 node (rclcpp, rclpy).
//!
//! Output as `ros2 param` prints it: `list` one name a line (indented by two), `get` `Integer value is: 18`,
//! `set` `Set parameter successful` (or `Setting parameter failed: REASON` on stderr, exit 1), `describe` the
//! name, type, description and constraints, `dump` the node's parameters as a `--params-file` YAML. Values on
//! the command line are YAML, as for `ros2 param set` and `--ros-args -p` (`12` an integer, `12.0` a double,
//! `true` a bool, anything else a string). Exit status 1 when the node does not answer within `--timeout`.

use std::time::Duration;

use anyhow::{anyhow, bail, Context as _};
use ros2_client::parameters::{raw, ParameterValue};
use ros2_client::rcl_interfaces::{
    DescribeParametersRequest, DescribeParametersResponse, GetParametersRequest, GetParametersResponse,
    ListParametersRequest, ListParametersResponse, SetParametersRequest, SetParametersResponse,
};
use ros2_client::{Message, ServiceMapping};

use super::graph::warn_of_namesakes;
use super::{bounded_error, quoted};
use crate::ros::{self, DdsConfig};

/// The node asked and how (`sweetspot param`'s common flags).
#[derive(Debug, Clone)]
pub struct ParamTarget {
    /// The node's name (a leading `/` is added when missing).
    pub node: String,
    /// Seconds to wait for an answer, waiting for the service included.
    pub timeout: f64,
    /// `enhanced` or `cyclone`.
    pub mapping: String,
}

/// What is asked of the node's parameters.
#[derive(Debug, Clone)]
pub enum ParamRequest {
    /// Every name.
    List,
    /// One value, with its type unless `hide_type`.
    Get { name: String, hide_type: bool },
    /// A new value, as YAML.
    Set { name: String, value: String },
    /// Type, description and constraints of `names`.
    Describe { names: Vec<String> },
    /// Every parameter as a `--params-file` YAML.
    Dump,
}

/// Asks `target` for `request` and prints the answer as `ros2 param` does.
pub fn param(target: ParamTarget, request: ParamRequest) -> anyhow::Result<()> {
    let node = &target;
    let fq_node = fully_qualified(&node.node)?;
    let mapping = crate::node::settings::service_mapping(&node.mapping)
        .ok_or_else(|| anyhow!("--mapping {}: expected enhanced or cyclone", node.mapping))?;
    let timeout = crate::model::time::saturating_secs(node.timeout);
    let config = DdsConfig::from_env()?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    let session = Session { config: &config, node: &fq_node, mapping, timeout };
    runtime.block_on(async {
        match request {
            ParamRequest::List => {
                let reply: ListParametersResponse =
                    session.call("list_parameters", ListParametersRequest { prefixes: vec![], depth: 0 }).await?;
                let mut names = reply.result.names;
                names.sort();
                for name in names {
                    crate::outln!("  {name}")?;
                }
                Ok(())
            }
            ParamRequest::Get { name, hide_type } => {
                let value = session.get(std::slice::from_ref(&name)).await?.pop().unwrap_or(ParameterValue::NotSet);
                if matches!(value, ParameterValue::NotSet) {
                    bail!("Parameter not set: {}", quoted(&name));
                }
                match hide_type {
                    true => crate::outln!("{}", plain(&value)),
                    false => crate::outln!("{} value is: {}", type_label(&value), plain(&value)),
                }
            }
            ParamRequest::Set { name, value } => {
                let parsed = crate::ros::args::parse_parameter_value(&name, &value).map_err(|e| anyhow!("{e}"))?;
                let request = SetParametersRequest {
                    parameter: vec![raw::Parameter { name: name.clone(), value: parsed.into() }],
                };
                let reply: SetParametersResponse = session.call("set_parameters", request).await?;
                let result =
                    reply.results.into_iter().next().ok_or_else(|| anyhow!("{} sent no result", quoted(&fq_node)))?;
                let reason = if result.reason.is_empty() { String::new() } else { format!(": {}", result.reason) };
                match result.successful {
                    true => {
                        crate::outln!("Set parameter successful{reason}")?;
                        Ok(())
                    }
                    false => bail!("Setting parameter failed{reason}"),
                }
            }
            ParamRequest::Describe { names } => {
                let asked = names.len();
                let reply: DescribeParametersResponse =
                    session.call("describe_parameters", DescribeParametersRequest { names }).await?;
                answered_all(&fq_node, "described", reply.values.len(), asked)?;
                for d in reply.values {
                    crate::report::stdout::emit(&describe(&d))?;
                }
                Ok(())
            }
            ParamRequest::Dump => {
                let reply: ListParametersResponse =
                    session.call("list_parameters", ListParametersRequest { prefixes: vec![], depth: 0 }).await?;
                let mut names = reply.result.names;
                names.sort();
                let values = session.get(&names).await?;
                answered_all(&fq_node, "gave the values of", values.len(), names.len())?;
                crate::report::stdout::emit(&dump(&fq_node, &names, &values))?;
                Ok(())
            }
        }
    })
}

/// Refuses a reply that answers `got` of the `asked` names: a node answers a request it refuses (too many
/// names, a name too long, an undeclared one for some nodes) with an empty list, and says why only in its log.
fn answered_all(node: &str, did: &str, got: usize, asked: usize) -> anyhow::Result<()> {
    if got == asked {
        return Ok(());
    }
    bail!(
        "{node} {did} {got} of the {asked} parameter(s) asked: it refused the request (its log says why;          sweetspot's node takes at most {} names of at most {} bytes in one request)",
        ros2_client::parameters::limits::MAX_NAMES_PER_REQUEST,
        ros2_client::parameters::limits::MAX_NAME_BYTES
    )
}

/// `name` as a fully-qualified node name (a leading `/` added).
fn fully_qualified(name: &str) -> anyhow::Result<String> {
    let fq = if name.starts_with('/') { name.to_string() } else { format!("/{name}") };
    ros::names::to_client_name(&format!("{fq}/list_parameters"))
        .map_err(|e| anyhow!("node name {:?}: {}", quoted(name), bounded_error(e)))
        .map(|_| fq)
}

struct Session<'a> {
    config: &'a DdsConfig,
    node: &'a str,
    mapping: ServiceMapping,
    timeout: Duration,
}

impl Session<'_> {
    async fn get(&self, names: &[String]) -> anyhow::Result<Vec<ParameterValue>> {
        let reply: GetParametersResponse =
            self.call("get_parameters", GetParametersRequest { names: names.to_vec() }).await?;
        Ok(reply.values.into_iter().map(ParameterValue::from).collect())
    }

    /// One call of the node's `NODE/<service>` (rcl_interfaces/srv/<Type>).
    async fn call<Req, Resp>(&self, service: &str, request: Req) -> anyhow::Result<Resp>
    where
        Req: Message + Clone + 'static,
        Resp: Message + 'static,
    {
        let fq_name = format!("{}/{service}", self.node);
        let type_name: String = service.split('_').map(capitalized).collect();
        let context = ros::context(self.config)?;
        let discovering_since = std::time::Instant::now();
        let node_name = ros2_client::NodeName::new("/", &format!("sweetspot_param_{}", std::process::id()))
            .map_err(|e| anyhow!("node name: {e:?}"))?;
        let mut node = context
            .new_node(node_name, ros2_client::NodeOptions::new().enable_rosout(false))
            .map_err(|e| anyhow!("creating the DDS node: {e:?}"))?;
        let name = ros::names::to_client_name(&fq_name)?;
        let service_type = ros2_client::ServiceTypeName::new("rcl_interfaces", &type_name);
        let client = node
            .create_client::<Req, Resp>(self.mapping, &name, &service_type, ros::swing_qos(), ros::results_qos())
            .map_err(|e| anyhow!("service client of {fq_name}: {e:?}"))?;
        let spinning = tokio::spawn(node.spinner().map_err(|e| anyhow!("{e:?}"))?.spin());
        let outcome = tokio::time::timeout(self.timeout, async {
            client.wait_for_service(&node).await;
            let id = client.async_send_request(request).await.map_err(|e| anyhow!("sending the request: {e:?}"))?;
            client.async_receive_response(id).await.map_err(|e| anyhow!("reading the response: {e:?}"))
        })
        .await;
        spinning.abort();
        if outcome.is_ok() {
            warn_of_namesakes(&context, &fq_name, discovering_since).await;
        }
        match outcome {
            Ok(result) => result,
            Err(_) => bail!(
                "no answer from {} within {:.1} s (ROS_DOMAIN_ID {}, discovery {}): is the node running? \
                 (`sweetspot node`; give its fully-qualified name; raise --timeout)",
                quoted(&fq_name),
                self.timeout.as_secs_f64(),
                self.config.domain_id,
                self.config.range
            ),
        }
    }
}

fn capitalized(word: &str) -> String {
    let mut chars = word.chars();
    chars.next().map(|c| c.to_ascii_uppercase().to_string() + chars.as_str()).unwrap_or_default()
}

/// The type word `ros2 param get` prints (`Integer value is: …`).
fn type_label(value: &ParameterValue) -> &'static str {
    match value {
        ParameterValue::NotSet => "Not set",
        ParameterValue::Boolean(_) => "Boolean",
        ParameterValue::Integer(_) => "Integer",
        ParameterValue::Double(_) => "Double",
        ParameterValue::String(_) => "String",
        ParameterValue::ByteArray(_) => "Byte values are",
        ParameterValue::BooleanArray(_) => "Boolean values are",
        ParameterValue::IntegerArray(_) => "Integer values are",
        ParameterValue::DoubleArray(_) => "Double values are",
        ParameterValue::StringArray(_) => "String values are",
    }
}

/// A value as `ros2 param get` prints it (Python's `str`: `True`, `5e-06`, `[1, 2]`).
fn plain(value: &ParameterValue) -> String {
    fn double(x: f64) -> String {
        python_float(x)
    }
    match value {
        ParameterValue::NotSet => String::new(),
        ParameterValue::Boolean(b) => if *b { "True" } else { "False" }.to_string(),
        ParameterValue::Integer(n) => n.to_string(),
        ParameterValue::Double(x) => double(*x),
        ParameterValue::String(s) => s.clone(),
        ParameterValue::ByteArray(v) => format!("{v:?}"),
        ParameterValue::BooleanArray(v) => {
            format!("[{}]", v.iter().map(|b| if *b { "True" } else { "False" }).collect::<Vec<_>>().join(", "))
        }
        ParameterValue::IntegerArray(v) => format!("{v:?}"),
        ParameterValue::DoubleArray(v) => format!("[{}]", v.iter().map(|x| double(*x)).collect::<Vec<_>>().join(", ")),
        ParameterValue::StringArray(v) => format!("{v:?}"),
    }
}

/// Python's `repr` of a float: the shortest round-trip digits, exponent form below 1e-4 and from 1e16.
fn python_float(x: f64) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "nan".into()
        } else if x > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    let a = x.abs();
    if a != 0.0 && !(1e-4..1e16).contains(&a) {
        let s = format!("{x:e}"); // e.g. 5e-6, 1.5e20
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let exponent: i32 = exponent.parse().unwrap_or(0);
        let sign = if exponent < 0 { '-' } else { '+' };
        return format!("{mantissa}e{sign}{:02}", exponent.abs());
    }
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') {
        s
    } else {
        format!("{s}.0")
    }
}

const TYPE_NAMES: [&str; 10] = [
    "not set",
    "boolean",
    "integer",
    "double",
    "string",
    "byte array",
    "boolean array",
    "integer array",
    "double array",
    "string array",
];

/// One descriptor as `ros2 param describe` prints it.
fn describe(d: &raw::ParameterDescriptor) -> String {
    let mut out = format!("Parameter name: {}\n", d.name);
    out += &format!("  Type: {}\n", TYPE_NAMES.get(d.r#type as usize).copied().unwrap_or("unknown"));
    if !d.description.is_empty() {
        out += &format!("  Description: {}\n", d.description);
    }
    if d.read_only
        || !d.additional_constraints.is_empty()
        || !d.integer_range.is_empty()
        || !d.floating_point_range.is_empty()
    {
        out += "  Constraints:\n";
        if d.read_only {
            out += "    Read only: true\n";
        }
        if !d.additional_constraints.is_empty() {
            out += &format!("    Additional constraints: {}\n", d.additional_constraints);
        }
        for r in &d.integer_range {
            out += &format!("    Min value: {}\n    Max value: {}\n", r.from_value, r.to_value);
            if r.step != 0 {
                out += &format!("    Step: {}\n", r.step);
            }
        }
        for r in &d.floating_point_range {
            out += &format!(
                "    Min value: {}\n    Max value: {}\n",
                python_float(r.from_value),
                python_float(r.to_value)
            );
            if r.step != 0.0 {
                out += &format!("    Step: {}\n", python_float(r.step));
            }
        }
    }
    out
}

/// The parameters as a ROS 2 params file (what `--params-file` and `ros2 param load` read back).
fn dump(node: &str, names: &[String], values: &[ParameterValue]) -> String {
    let mut out = format!("{node}:\n  ros__parameters:\n");
    for (name, value) in names.iter().zip(values) {
        let yaml = match value {
            ParameterValue::NotSet => continue,
            ParameterValue::Boolean(b) => b.to_string(),
            ParameterValue::Integer(n) => n.to_string(),
            ParameterValue::Double(x) => python_float(*x),
            ParameterValue::String(s) => yaml_string(s),
            ParameterValue::ByteArray(v) => format!("{v:?}"),
            ParameterValue::BooleanArray(v) => format!("{v:?}"),
            ParameterValue::IntegerArray(v) => format!("{v:?}"),
            ParameterValue::DoubleArray(v) => {
                format!("[{}]", v.iter().map(|x| python_float(*x)).collect::<Vec<_>>().join(", "))
            }
            ParameterValue::StringArray(v) => {
                format!("[{}]", v.iter().map(|s| yaml_string(s)).collect::<Vec<_>>().join(", "))
            }
        };
        out += &format!("    {name}: {yaml}\n");
    }
    out
}

/// A string as YAML that reads back as that string (quoted when it is empty or would read as anything else).
fn yaml_string(s: &str) -> String {
    let plain_ok = !s.is_empty()
        && crate::ros::args::parse_parameter_value("x", s).is_ok_and(|v| v == ParameterValue::String(s.to_string()))
        && !s.starts_with([' ', '\'', '"', '[', '{', '&', '*', '!', '|', '>', '%', '@', '`', '#', '-', '?', ':'])
        && !s.contains(": ")
        && !s.contains(" #")
        && !s.ends_with(' ');
    match plain_ok {
        true => s.to_string(),
        false => format!("'{}'", s.replace('\'', "''")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The float text of Python's `repr`, as `ros2 param get` shows doubles.
    #[test]
    fn doubles_print_as_python_does() {
        for (x, python) in [(5e-6, "5e-06"), (1e-8, "1e-08"), (0.0001, "0.0001"), (40.0, "40.0"), (1.5e20, "1.5e+20")] {
            assert_eq!(python_float(x), python, "{x}");
        }
    }

    /// What dump writes reads back as the same values through the `--params-file` parser.
    #[test]
    fn a_dump_reads_back_as_the_same_values() {
        let names: Vec<String> = ["a", "b", "c", "d", "e", "f"].iter().map(|s| s.to_string()).collect();
        let values = vec![
            ParameterValue::String("r161".into()),
            ParameterValue::String("".into()),
            ParameterValue::String("12".into()),
            ParameterValue::Double(5e-6),
            ParameterValue::Integer(18),
            ParameterValue::Boolean(true),
        ];
        let text = dump("/sweetspot", &names, &values);
        let node = crate::ros::args::NodeIdentity { name: "sweetspot".into(), namespace: "/".into() };
        let back = crate::ros::args::params_file_values(&text, std::path::Path::new("dump.yaml"), &node).unwrap();
        let expected: Vec<(String, ParameterValue)> = names.into_iter().zip(values).collect();
        assert_eq!(back, expected, "{text}");
    }
}
