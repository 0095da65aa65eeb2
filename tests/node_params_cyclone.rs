//! `ros2 param` with someone else's client: a Cyclone DDS participant (tests/python/cyclone_params.py, request
//! and response types built from the rcl_interfaces .msg/.srv files in msgs/ros_interfaces alone, no ros2-client)
//! calls the `sweetspot node` binary's parameter services — list_parameters, get_parameter_types,
//! get_parameters, describe_parameters and set_parameters — over real DDS, inside the private network namespace
//! of scripts/test. The ranges described are what set_parameters enforces: each end is accepted, the next
//! representable value past it is refused with its reason.

mod support;

use std::collections::BTreeMap;
use std::process::Command;
use std::time::Duration;

use ros2_client::ParameterValue;
use serde_json::{json, Value};
use support::node::{domain, NodeProcess};
use sweetspot::node::settings::{Parameter, PARAMETERS};

const WAIT: Duration = Duration::from_secs(60);

/// What the Cyclone client printed: the constants of the .msg/.srv files it read, and one response per call.
struct Replies {
    constants: Value,
    responses: Vec<Value>,
}

impl Replies {
    /// `rcl_interfaces/ParameterType`'s constant `name` (e.g. `PARAMETER_INTEGER`), from the .msg text.
    fn parameter_type(&self, name: &str) -> u64 {
        self.constants["rcl_interfaces/ParameterType"][name]
            .as_u64()
            .unwrap_or_else(|| panic!("ParameterType.msg has no {name}: {}", self.constants))
    }
}

/// Makes `calls` (a JSON list of {"service", "request"}) to the node `/sweetspot` on `domain`, one at a time.
fn call(domain: u16, calls: Value) -> Replies {
    call_mapped(domain, calls, "enhanced")
}

/// [`call`] in the request/reply `mapping` (`enhanced` or `cyclone`, rmw_cyclonedds_cpp's header).
fn call_mapped(domain: u16, calls: Value, mapping: &str) -> Replies {
    call_with(domain, &calls, &calls.to_string(), mapping)
}

/// [`call`] with requests too large for a command line: the calls go to the client in a file.
fn call_large(domain: u16, calls: Value) -> Replies {
    let file = tempfile::NamedTempFile::new().unwrap();
    std::fs::write(file.path(), calls.to_string()).unwrap();
    call_with(domain, &calls, &format!("@{}", file.path().display()), "enhanced")
}

fn call_with(domain: u16, calls: &Value, calls_arg: &str, mapping: &str) -> Replies {
    let mut c = Command::new(support::python());
    c.arg(support::repo().join("tests/python/cyclone_params.py")).arg("--loopback").args([
        "call",
        "--node",
        "/sweetspot",
        "--calls",
        calls_arg,
        "--timeout",
        "60",
        "--mapping",
        mapping,
    ]);
    support::dds_env(&mut c, domain);
    let out = c.output().expect("run cyclone_params.py");
    let lines = support::json_lines(&out, "cyclone_params.py");
    let constants = lines[0]["constants"].clone();
    let responses: Vec<Value> = lines[1..].iter().map(|l| l["response"].clone()).collect();
    assert_eq!(responses.len(), calls.as_array().map_or(0, Vec::len), "one response per call");
    Replies { constants, responses }
}

fn start_node(domain: u16, dir: &std::path::Path) -> NodeProcess {
    let node = NodeProcess::spawn(domain, dir, &["--no-record"]);
    node.wait_for_log("/sweetspot up", WAIT);
    node
}

fn names() -> Vec<&'static str> {
    PARAMETERS.iter().map(|p| p.name).collect()
}

/// The ParameterType constant name of a value of `p`'s type.
fn type_constant(p: &Parameter) -> &'static str {
    match p.default_value() {
        ParameterValue::Boolean(_) => "PARAMETER_BOOL",
        ParameterValue::Integer(_) => "PARAMETER_INTEGER",
        ParameterValue::Double(_) => "PARAMETER_DOUBLE",
        ParameterValue::String(_) => "PARAMETER_STRING",
        other => panic!("{}: unexpected type {other:?}", p.name),
    }
}

/// A ParameterValue message (rcl_interfaces/msg/ParameterValue fields) holding `v`.
fn value_msg(replies: &Replies, v: &ParameterValue) -> Value {
    let (constant, field, value) = match v {
        ParameterValue::Boolean(b) => ("PARAMETER_BOOL", "bool_value", json!(b)),
        ParameterValue::Integer(i) => ("PARAMETER_INTEGER", "integer_value", json!(i)),
        ParameterValue::Double(x) => ("PARAMETER_DOUBLE", "double_value", json!(x)),
        ParameterValue::String(s) => ("PARAMETER_STRING", "string_value", json!(s)),
        other => panic!("no test uses {other:?}"),
    };
    json!({ "type": replies.parameter_type(constant), field: value })
}

/// The value a ParameterValue message holds, by its type field.
fn value_of(replies: &Replies, msg: &Value) -> ParameterValue {
    let t = msg["type"].as_u64().expect("type");
    if t == replies.parameter_type("PARAMETER_BOOL") {
        ParameterValue::Boolean(msg["bool_value"].as_bool().expect("bool_value"))
    } else if t == replies.parameter_type("PARAMETER_INTEGER") {
        ParameterValue::Integer(msg["integer_value"].as_i64().expect("integer_value"))
    } else if t == replies.parameter_type("PARAMETER_DOUBLE") {
        ParameterValue::Double(msg["double_value"].as_f64().expect("double_value"))
    } else if t == replies.parameter_type("PARAMETER_STRING") {
        ParameterValue::String(msg["string_value"].as_str().expect("string_value").to_string())
    } else {
        ParameterValue::NotSet
    }
}

fn set_request(replies: &Replies, params: &[(&str, ParameterValue)]) -> Value {
    let parameters: Vec<Value> =
        params.iter().map(|(name, v)| json!({ "name": name, "value": value_msg(replies, v) })).collect();
    json!({ "service": "set_parameters", "request": { "parameters": parameters } })
}

type Ranges<T> = BTreeMap<&'static str, (T, T)>;

/// The ranges the README documents (step 0 = any value in the range), written out here rather than read
/// from the node's table: integer ranges as (from, to), floating-point ranges as (from, to).
fn documented_ranges() -> (Ranges<i64>, Ranges<f64>) {
    let integers = BTreeMap::from([
        ("default_modes", (1, 200)),
        ("max_bats", (2, 100_000)),
        ("max_balls", (2, 100_000)),
        ("max_bat_slices", (100, 4000)),
        ("queue_capacity", (1, 1_000_000)),
        ("workers", (0, 256)),
        ("foxglove_max_clients", (1, 10_000)),
    ]);
    let doubles = BTreeMap::from([
        ("time_step", (1e-8, 1e-4)),
        ("reference_ball_speed", (0.0, 100.0)),
        ("reference_bat_cm_speed", (0.0, 100.0)),
        ("reference_bat_angular_speed", (-500.0, 500.0)),
        ("diagnostics_period", (0.1, 60.0)),
        ("swing_scene_live_hz", (0.0, 1000.0)),
    ]);
    (integers, doubles)
}

#[test]
fn list_types_values_and_descriptors_are_the_declared_ones() {
    support::require_isolated_network();
    let domain = domain(57);
    let dir = tempfile::tempdir().unwrap();
    let node = start_node(domain, dir.path());
    let mut asked: Vec<&str> = names();
    asked.push("no_such_parameter");
    let replies = call(
        domain,
        json!([
            { "service": "list_parameters", "request": { "prefixes": [], "depth": 0 } },
            { "service": "get_parameter_types", "request": { "names": asked } },
            { "service": "get_parameters", "request": { "names": names() } },
            { "service": "describe_parameters", "request": { "names": asked } },
        ]),
    );
    let [list, types, values, described] = &replies.responses[..] else { unreachable!() };

    // list_parameters: every declared parameter and ros2-client's use_sim_time, nothing else.
    let mut listed: Vec<&str> =
        list["result"]["names"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
    listed.sort();
    let mut expected = names();
    expected.push("use_sim_time");
    expected.sort();
    assert_eq!(listed, expected);

    // get_parameter_types and get_parameters: the start-up values (--no-record sets record:=false).
    let types: Vec<u64> = types["types"].as_array().unwrap().iter().map(|t| t.as_u64().unwrap()).collect();
    let values = values["values"].as_array().unwrap();
    assert_eq!(values.len(), PARAMETERS.len());
    for (i, p) in PARAMETERS.iter().enumerate() {
        assert_eq!(types[i], replies.parameter_type(type_constant(p)), "type of {}", p.name);
        let expected = match p.name {
            "record" => ParameterValue::Boolean(false),
            _ => p.default_value(),
        };
        assert_eq!(value_of(&replies, &values[i]), expected, "value of {}", p.name);
    }
    assert_eq!(types[PARAMETERS.len()], replies.parameter_type("PARAMETER_NOT_SET"), "an unknown name");

    // describe_parameters: the type get_parameter_types gives, the declared description (with the unit),
    // read-only flag, constraints, and the documented range in the field of its kind.
    let descriptors = described["descriptors"].as_array().unwrap();
    assert_eq!(descriptors.len(), asked.len());
    let (integer_ranges, float_ranges) = documented_ranges();
    for (i, p) in PARAMETERS.iter().enumerate() {
        let d = &descriptors[i];
        let what = format!("descriptor of {}: {d}", p.name);
        assert_eq!(d["name"], p.name, "{what}");
        assert_eq!(d["type"].as_u64(), Some(types[i]), "{what}");
        let description = d["description"].as_str().unwrap();
        assert!(description.starts_with(p.description), "{what}");
        assert!(!description.contains("missing"), "{what}");
        if !p.unit.is_empty() {
            assert!(description.ends_with(&format!("[{}]", p.unit)), "{what}");
        }
        assert_eq!(d["read_only"], p.read_only, "{what}");
        assert_eq!(d["additional_constraints"], p.constraints, "{what}");
        assert_eq!(d["dynamic_typing"], false, "{what}");
        let ints = d["integer_range"].as_array().unwrap();
        let floats = d["floating_point_range"].as_array().unwrap();
        match (integer_ranges.get(p.name), float_ranges.get(p.name)) {
            (Some(&(from, to)), None) => {
                assert_eq!(ints, &vec![json!({ "from_value": from, "to_value": to, "step": 0 })], "{what}");
                assert!(floats.is_empty(), "{what}");
            }
            (None, Some(&(from, to))) => {
                assert_eq!(floats, &vec![json!({ "from_value": from, "to_value": to, "step": 0.0 })], "{what}");
                assert!(ints.is_empty(), "{what}");
            }
            _ => assert!(ints.is_empty() && floats.is_empty(), "{what}: no range documented"),
        }
    }
    // A few flags written out: the live-tunable ones are not read-only, the start-up ones are.
    for (name, read_only) in
        [("default_modes", false), ("time_step", false), ("queue_capacity", true), ("record", true)]
    {
        let i = PARAMETERS.iter().position(|p| p.name == name).unwrap();
        assert_eq!(descriptors[i]["read_only"], read_only, "{name}");
    }
    let split = PARAMETERS.iter().position(|p| p.name == "record_max_file_size").unwrap();
    assert!(descriptors[split]["additional_constraints"].as_str().unwrap().contains("4096"));
    let unknown = &descriptors[PARAMETERS.len()];
    assert_eq!(unknown["type"].as_u64(), Some(replies.parameter_type("PARAMETER_NOT_SET")), "{unknown}");
    drop(node);
}

#[test]
fn set_parameters_accepts_the_described_range_and_refuses_past_it_with_the_reason() {
    support::require_isolated_network();
    let domain = domain(58);
    let dir = tempfile::tempdir().unwrap();
    let node = start_node(domain, dir.path());
    let described = call(domain, json!([{ "service": "describe_parameters", "request": { "names": names() } }]));
    let descriptors = described.responses[0]["descriptors"].as_array().unwrap().clone();

    // For every live-tunable parameter with a range: below it, its lower end, its upper end, above it — in one
    // request, applied in order. Each end must be accepted (unless a constraint beyond the range excludes it),
    // each value past an end refused, naming the parameter and the range.
    struct Probe {
        name: &'static str,
        values: Vec<ParameterValue>,
        accepted: Vec<bool>,
        constraints: String,
    }
    let mut probes = Vec::new();
    for (p, d) in PARAMETERS.iter().zip(&descriptors) {
        if d["read_only"] == true {
            continue;
        }
        let constraints = d["additional_constraints"].as_str().unwrap().to_string();
        let (values, lower_end_ok) = if let Some(r) = d["integer_range"].as_array().unwrap().first() {
            let (from, to) = (r["from_value"].as_i64().unwrap(), r["to_value"].as_i64().unwrap());
            let values = [from - 1, from, to, to + 1].map(ParameterValue::Integer).to_vec();
            (values, constraints.is_empty())
        } else if let Some(r) = d["floating_point_range"].as_array().unwrap().first() {
            let (from, to) = (r["from_value"].as_f64().unwrap(), r["to_value"].as_f64().unwrap());
            let values = [from.next_down(), from, to, to.next_up()].map(ParameterValue::Double).to_vec();
            (values, constraints.is_empty())
        } else {
            continue;
        };
        probes.push(Probe { name: p.name, values, accepted: vec![false, lower_end_ok, true, false], constraints });
    }
    let probed: Vec<&str> = probes.iter().map(|p| p.name).collect();
    for expected in ["default_modes", "time_step", "reference_ball_speed", "max_bats", "max_bat_slices"] {
        assert!(probed.contains(&expected), "{expected} has no described range: {probed:?}");
    }

    let mut calls: Vec<Value> = probes
        .iter()
        .map(|probe| {
            let params: Vec<(&str, ParameterValue)> = probe.values.iter().map(|v| (probe.name, v.clone())).collect();
            set_request(&described, &params)
        })
        .collect();
    // A valid value, then read back; a read-only parameter (in range and out of it), a wrong type, a bad preset.
    let restored: Vec<(&str, ParameterValue)> = PARAMETERS
        .iter()
        .filter(|p| !p.read_only && probed.contains(&p.name))
        .map(|p| (p.name, p.default_value()))
        .collect();
    calls.push(set_request(&described, &restored));
    calls.push(set_request(&described, &[("default_modes", ParameterValue::Integer(12))]));
    calls.push(set_request(
        &described,
        &[
            ("queue_capacity", ParameterValue::Integer(5)),
            ("diagnostics_period", ParameterValue::Double(2.0)),
            ("default_modes", ParameterValue::Double(3.0)),
            ("default_bat", ParameterValue::String("no_such_bat".into())),
        ],
    ));
    calls.push(json!({ "service": "get_parameters", "request": {
        "names": ["default_modes", "queue_capacity", "diagnostics_period", "default_bat", "time_step"] } }));
    let replies = call(domain, Value::Array(calls));

    for (probe, response) in probes.iter().zip(&replies.responses) {
        let results = response["results"].as_array().unwrap();
        assert_eq!(results.len(), 4, "{}: {response}", probe.name);
        for ((value, accepted), result) in probe.values.iter().zip(&probe.accepted).zip(results) {
            let what = format!("{} = {value:?}: {result}", probe.name);
            assert_eq!(result["successful"], *accepted, "{what}");
            let reason = result["reason"].as_str().unwrap();
            if *accepted {
                assert_eq!(reason, "", "{what}");
            } else if !probe.constraints.is_empty() && value == &probe.values[1] {
                assert!(reason.contains(&probe.constraints), "{what}: the constraint beyond the range is named");
            } else {
                assert!(
                    reason.contains(probe.name) && reason.contains("out of range") && reason.contains('≤'),
                    "{what}"
                );
            }
        }
    }
    let rest = &replies.responses[probes.len()..];
    let restored_results = rest[0]["results"].as_array().unwrap();
    assert!(restored_results.iter().all(|r| r["successful"] == true), "defaults restored: {}", rest[0]);
    assert_eq!(rest[1]["results"], json!([{ "successful": true, "reason": "" }]), "a valid value");

    let refused = rest[2]["results"].as_array().unwrap();
    let reason = |i: usize| -> &str {
        assert_eq!(refused[i]["successful"], false, "{}", rest[2]);
        refused[i]["reason"].as_str().unwrap()
    };
    assert!(reason(0).contains("queue_capacity is read-only"), "{}", reason(0));
    assert!(reason(1).contains("diagnostics_period is read-only"), "{}", reason(1));
    assert!(reason(2).contains("default_modes") && reason(2).to_lowercase().contains("type"), "{}", reason(2));
    assert!(reason(3).contains("default_bat") && reason(3).contains("r161"), "{}", reason(3));

    let now: Vec<ParameterValue> =
        rest[3]["values"].as_array().unwrap().iter().map(|v| value_of(&replies, v)).collect();
    assert_eq!(
        now,
        [
            ParameterValue::Integer(12),
            ParameterValue::Integer(16_384),
            ParameterValue::Double(1.0),
            ParameterValue::String("r161".into()),
            ParameterValue::Double(5e-6),
        ],
        "the valid value is set, every refused one left as it was"
    );
    drop(node);
}

/// A node started with `service_mapping:=cyclone` serves its parameters to clients on rmw_cyclonedds_cpp too: the
/// Cyclone peer sends that RMW's `{guid, seq}` header in front of each request and accepts only replies that
/// echo it; the node lists its parameters and reads `service_mapping` back as `cyclone`.
#[test]
fn parameter_services_follow_the_cyclone_mapping() {
    support::require_isolated_network();
    let domain = domain(59);
    let dir = tempfile::tempdir().unwrap();
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record", "--ros-args", "-p", "service_mapping:=cyclone"]);
    node.wait_for_log("/sweetspot up", WAIT);
    let replies = call_mapped(
        domain,
        json!([
            { "service": "list_parameters", "request": { "prefixes": [], "depth": 0 } },
            { "service": "get_parameters", "request": { "names": ["service_mapping", "queue_capacity"] } },
        ]),
        "cyclone",
    );
    let [list, values] = &replies.responses[..] else { unreachable!() };
    let listed: Vec<&str> = list["result"]["names"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
    assert!(listed.contains(&"service_mapping") && listed.contains(&"default_bat"), "{list}");
    let got = values["values"].as_array().unwrap();
    assert_eq!(got[0]["string_value"], json!("cyclone"), "{values}");
    assert_eq!(got[1]["integer_value"], json!(16384), "{values}");
    drop(node);
}

/// Hostile requests to every parameter service — a 1 MiB name or value, 100,000 names, prefixes or parameters —
/// are each answered, with a small reply: a get, types, describe or list request over the documented bounds
/// (docs/node.md: at most 1024 names of at most 256 bytes) with an empty list, as rclcpp answers a request naming
/// an undeclared parameter, and a set with the reason. One warning per refused request names the reason. A
/// describe at the bounds (1024 unknown 256-byte names) is answered in full: a reply of some 350 KB, sent in
/// fragments; one name more (1025) is refused. Afterwards a second client's ordinary calls are answered as before.
#[test]
fn huge_parameter_requests_are_answered_small_and_the_node_keeps_answering() {
    support::require_isolated_network();
    let domain = domain(60);
    let dir = tempfile::tempdir().unwrap();
    let node = start_node(domain, dir.path());
    let constants = call(domain, json!([{ "service": "list_parameters", "request": {} }]));
    let string = constants.parameter_type("PARAMETER_STRING");
    let mib = "x".repeat(1 << 20);
    let many: Vec<String> = (0..100_000).map(|i| format!("n{i}")).collect();
    let longest: Vec<String> = (0..1024).map(|i| format!("{i:0>256}")).collect();
    let one_too_many: Vec<String> = (0..1025).map(|i| format!("{i:0>256}")).collect();
    let set = |name: &str, value: &str| json!({ "name": name, "value": { "type": string, "string_value": value } });
    let many_sets: Vec<Value> = many.iter().map(|n| set(n, "a")).collect();
    let hostile = json!([
        { "service": "get_parameters", "request": { "names": many } },
        { "service": "get_parameters", "request": { "names": [mib] } },
        { "service": "get_parameter_types", "request": { "names": many } },
        { "service": "get_parameter_types", "request": { "names": ["default_bat", mib] } },
        { "service": "describe_parameters", "request": { "names": many } },
        { "service": "describe_parameters", "request": { "names": [mib] } },
        { "service": "describe_parameters", "request": { "names": longest } },
        { "service": "list_parameters", "request": { "prefixes": many } },
        { "service": "list_parameters", "request": { "prefixes": [mib] } },
        { "service": "set_parameters", "request": { "parameters": [set(&mib, "a")] } },
        { "service": "set_parameters", "request": { "parameters": [set("default_bat", &mib)] } },
        { "service": "set_parameters", "request": { "parameters": many_sets } },
        { "service": "describe_parameters", "request": { "names": one_too_many } },
    ]);
    let started = std::time::Instant::now();
    let replies = call_large(domain, hostile);
    let took = started.elapsed();
    let r = &replies.responses;

    let empty = |i: usize, field: &str| {
        let shown: String = r[i].to_string().chars().take(200).collect();
        assert_eq!(r[i][field], json!([]), "call {i}: {shown}");
    };
    empty(0, "values");
    empty(1, "values");
    empty(2, "types");
    empty(3, "types");
    empty(4, "descriptors");
    empty(5, "descriptors");
    let described = r[6]["descriptors"].as_array().unwrap();
    assert_eq!(described.len(), 1024, "a describe at the bounds is answered in full");
    for (d, name) in described.iter().zip(&longest) {
        assert_eq!(d["name"], json!(name));
        assert_eq!(d["type"].as_u64(), Some(replies.parameter_type("PARAMETER_NOT_SET")));
    }
    assert_eq!(r[7]["result"], json!({ "names": [], "prefixes": [] }));
    assert_eq!(r[8]["result"], json!({ "names": [], "prefixes": [] }));
    assert_eq!(
        r[9]["results"],
        json!([{ "successful": false, "reason": "a parameter name of 1048576 bytes is over the limit of 256 bytes" }])
    );
    assert_eq!(
        r[10]["results"],
        json!([{
            "successful": false,
            "reason": "the value for 'default_bat' is 1048576 bytes, over the limit of 65536 bytes"
        }])
    );
    assert_eq!(
        r[11]["results"],
        json!([{ "successful": false, "reason": "100000 parameters in one request, over the limit of 1024" }]),
        "too many parameters: one result with the reason"
    );
    empty(12, "descriptors");
    eprintln!("13 hostile calls answered in {took:?}");

    // A second client, after all that: ordinary calls answered as before, and the refused sets changed nothing.
    let after = call(
        domain,
        json!([
            { "service": "get_parameters", "request": { "names": ["default_bat", "default_modes"] } },
            { "service": "set_parameters", "request": { "parameters": [
                { "name": "default_modes", "value": { "type": replies.parameter_type("PARAMETER_INTEGER"),
                                                      "integer_value": 12 } }] } },
            { "service": "list_parameters", "request": { "prefixes": [], "depth": 0 } },
        ]),
    );
    let got = after.responses[0]["values"].as_array().unwrap();
    assert_eq!(value_of(&after, &got[0]), ParameterValue::String("r161".into()));
    assert_eq!(
        value_of(&after, &got[1]),
        PARAMETERS.iter().find(|p| p.name == "default_modes").unwrap().default_value()
    );
    assert_eq!(after.responses[1]["results"], json!([{ "successful": true, "reason": "" }]));
    assert!(after.responses[2]["result"]["names"].as_array().unwrap().len() > 20);

    // One warning per refused request, with the reason (the valid describe at the bounds is not one).
    let log = node.log();
    let refusals: Vec<&str> = log.lines().filter(|l| l.contains("request refused")).collect();
    assert_eq!(refusals.len(), 12, "{log}");
    for (service, reason) in [
        ("get_parameters", "100000 names in one request, over the limit of 1024"),
        ("get_parameters", "names[0] is 1048576 bytes long, over the limit of 256 bytes"),
        ("get_parameter_types", "names[1] is 1048576 bytes long"),
        ("describe_parameters", "100000 names in one request"),
        ("describe_parameters", "1025 names in one request, over the limit of 1024"),
        ("list_parameters", "100000 prefixes in one request"),
        ("set_parameters", "a parameter name of 1048576 bytes"),
        ("set_parameters", "100000 parameters in one request"),
    ] {
        let line = format!("/sweetspot: {service} request refused: {reason}");
        assert!(refusals.iter().any(|l| l.contains("WARN") && l.contains(&line)), "no '{line}' in:\n{log}");
    }
    assert!(refusals.iter().all(|l| l.len() < 400), "no line quotes a huge name: {refusals:?}");
    drop(node);
}
