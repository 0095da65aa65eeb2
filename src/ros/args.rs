//! ROS 2 command-line conventions without a ROS installation: `--ros-args` with `-r`, `-p`, `--params-file`,
//! and the name resolution they imply (namespace, node name, topic remaps, `~` private names). The one parser
//! of the crate: `sweetspot node`, `pub` and `echo` all use it (also reachable as `node::ros_args`).
//!
//! Everything here is pure: parsing produces a [`RosArgs`], which [`RosArgs::identity`] and
//! [`NameResolver`] turn into fully qualified names, and [`RosArgs::parameter_overrides`] into the parameter
//! values for one node (params files first, in order, then `-p`, the way rcl ranks them).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use ros2_client::ParameterValue;
use yaml_rust2::Yaml;

/// A malformed `--ros-args` section or parameters file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RosArgsError {
    /// A flag that needs a value was last.
    #[error("--ros-args: {flag} needs a value")]
    MissingValue { flag: String },
    /// A `-r`/`-p` argument without `:=`.
    #[error("--ros-args: '{arg}' after {flag} must look like NAME:=VALUE")]
    NoAssignment { flag: String, arg: String },
    /// An argument `--ros-args` does not know.
    #[error("--ros-args: unknown argument '{0}' (known: -r/--remap, -p/--param, --params-file, --log-level, -e/--enclave, --enable-rosout-logs, --disable-rosout-logs, --enable-stdout-logs, --disable-stdout-logs, --)")]
    Unknown(String),
    /// A name that ROS 2 naming rules refuse.
    #[error("invalid ROS name '{name}': {why}")]
    BadName { name: String, why: String },
    /// A parameter value that is not valid YAML or not a ROS parameter type.
    #[error("parameter '{name}': {why}")]
    BadValue { name: String, why: String },
    /// A parameters file that cannot be read or is not in the `node: ros__parameters:` layout.
    #[error("parameters file {path}: {why}")]
    BadParamsFile { path: PathBuf, why: String },
}

/// One `-r FROM:=TO` rule, optionally restricted to one node (`node:FROM:=TO`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Remap {
    /// Only applies to the node with this base name, if set.
    pub node: Option<String>,
    /// The name to replace (relative names are resolved against the node's namespace).
    pub from: String,
    /// Its replacement (relative names are resolved against the node's namespace).
    pub to: String,
}

/// Which part of the node's identity an `__node`/`__ns` rule renames.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IdentityPart {
    /// `__node` (or `__name`): the node's base name.
    Name,
    /// `__ns`: the node's namespace.
    Namespace,
}

/// One `-r [node:]__node:=…` or `-r [node:]__ns:=…` rule.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IdentityRemap {
    /// Only applies to the node whose name *before renaming* is this, if set (as rcl matches it).
    pub node: Option<String>,
    /// What the rule renames.
    pub part: IdentityPart,
    /// The new name, or the new namespace (absolute, normalised).
    pub value: String,
}

/// Everything found in the `--ros-args` sections of a command line.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RosArgs {
    /// `-r [node:]__node:=NAME` (also `__name`) and `-r [node:]__ns:=/NAMESPACE`, in command-line order;
    /// [`RosArgs::identity`] applies the first rule of each kind that concerns the node.
    pub identity_remaps: Vec<IdentityRemap>,
    /// Topic and service remaps, in command-line order.
    pub remaps: Vec<Remap>,
    /// `-p NAME:=VALUE`, in command-line order (values parsed as YAML).
    pub params: Vec<(String, ParameterValue)>,
    /// `--params-file FILE`, in command-line order.
    pub params_files: Vec<PathBuf>,
    /// `--log-level LEVEL` (a `tracing` filter, e.g. `debug`).
    pub log_level: Option<String>,
    /// `--enable-rosout-logs` / `--disable-rosout-logs`.
    pub rosout_logs: Option<bool>,
    /// `--enable-stdout-logs` / `--disable-stdout-logs`.
    pub stdout_logs: Option<bool>,
}

/// The node's final name and namespace after `__node`/`__ns` remaps.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeIdentity {
    /// Namespace, absolute, `/` for the root.
    pub namespace: String,
    /// Base name.
    pub name: String,
}

impl NodeIdentity {
    /// `/ns/name` (or `/name` in the root namespace).
    pub fn fully_qualified_name(&self) -> String {
        join_ros_names(&self.namespace, &self.name)
    }
}

impl RosArgs {
    /// Parses the arguments of a command line that follow the program's own flags. Tokens outside a
    /// `--ros-args … [--]` section are refused (the caller keeps its own flags before `--ros-args`).
    /// Tokens are accepted with or without a leading `--ros-args` (clap hands over what follows it).
    pub fn parse<S: AsRef<str>>(tokens: &[S]) -> Result<RosArgs, RosArgsError> {
        let mut out = RosArgs::default();
        let mut i = 0;
        let next_value = |i: &mut usize, flag: &str| -> Result<String, RosArgsError> {
            *i += 1;
            tokens
                .get(*i)
                .map(|s| s.as_ref().to_string())
                .ok_or_else(|| RosArgsError::MissingValue { flag: flag.to_string() })
        };
        while i < tokens.len() {
            let token = tokens[i].as_ref();
            match token {
                "--ros-args" | "--" => {}
                "-r" | "--remap" => {
                    let arg = next_value(&mut i, token)?;
                    out.add_remap(token, &arg)?;
                }
                "-p" | "--param" => {
                    let arg = next_value(&mut i, token)?;
                    let (name, value) = split_assignment(token, &arg)?;
                    let value = parse_parameter_value(name, value)?;
                    out.params.push((name.to_string(), value));
                }
                "--params-file" => {
                    let path = next_value(&mut i, token)?;
                    out.params_files.push(PathBuf::from(path));
                }
                "--log-level" => {
                    let level = next_value(&mut i, token)?;
                    out.log_level = Some(level);
                }
                "-e" | "--enclave" => {
                    // Security enclaves need DDS security, which this node does not enable; accept and ignore.
                    next_value(&mut i, token)?;
                }
                "--enable-rosout-logs" => out.rosout_logs = Some(true),
                "--disable-rosout-logs" => out.rosout_logs = Some(false),
                "--enable-stdout-logs" => out.stdout_logs = Some(true),
                "--disable-stdout-logs" => out.stdout_logs = Some(false),
                "--disable-external-lib-logs" => {}
                other => return Err(RosArgsError::Unknown(other.to_string())),
            }
            i += 1;
        }
        Ok(out)
    }

    fn add_remap(&mut self, flag: &str, arg: &str) -> Result<(), RosArgsError> {
        let (from, to) = split_assignment(flag, arg)?;
        // `node:from:=to` restricts the rule to one node; `__ns`/`__node` never contain ':'.
        let (node, from) = match from.split_once(':') {
            Some((node, from)) => (Some(node.to_string()), from),
            None => (None, from),
        };
        match from {
            "__ns" => {
                let value = normalize_namespace(to)?;
                self.identity_remaps.push(IdentityRemap { node, part: IdentityPart::Namespace, value });
            }
            "__node" | "__name" => {
                validate_token(to)?;
                self.identity_remaps.push(IdentityRemap { node, part: IdentityPart::Name, value: to.to_string() });
            }
            _ => {
                validate_topic_name(from)?;
                validate_topic_name(to)?;
                self.remaps.push(Remap { node, from: from.to_string(), to: to.to_string() });
            }
        }
        Ok(())
    }

    /// The name and namespace of the node called `default_name` in code: for each of the two, the first
    /// `__node`/`__ns` rule that is unprefixed or prefixed with `default_name` (rcl matches a node-specific
    /// rule against the name before renaming, and takes the first matching rule), else the defaults.
    pub fn identity(&self, default_name: &str, default_namespace: &str) -> NodeIdentity {
        let first = |part: IdentityPart| {
            self.identity_remaps
                .iter()
                .find(|r| r.part == part && r.node.as_deref().is_none_or(|n| n == default_name))
                .map(|r| r.value.clone())
        };
        NodeIdentity {
            namespace: first(IdentityPart::Namespace).unwrap_or_else(|| default_namespace.to_string()),
            name: first(IdentityPart::Name).unwrap_or_else(|| default_name.to_string()),
        }
    }

    /// A resolver of topic names for `node`, with the remap rules that apply to it.
    pub fn resolver(&self, node: &NodeIdentity) -> NameResolver {
        let rules = self
            .remaps
            .iter()
            .filter(|r| r.node.as_deref().is_none_or(|n| n == node.name))
            .map(|r| (resolve_name(&r.from, node), resolve_name(&r.to, node)))
            .collect();
        NameResolver { node: node.clone(), rules }
    }

    /// The parameter values that apply to `node`: every `--params-file` in order (wildcard sections before
    /// the node's own section within each file), then every `-p`. Later values win.
    pub fn parameter_overrides(&self, node: &NodeIdentity) -> Result<BTreeMap<String, ParameterValue>, RosArgsError> {
        let mut values = BTreeMap::new();
        for path in &self.params_files {
            let text = crate::files::read_text(path, "parameter file")
                .map_err(|e| RosArgsError::BadParamsFile { path: path.clone(), why: e.to_string() })?;
            for (name, value) in params_file_values(&text, path, node)? {
                values.insert(name, value);
            }
        }
        for (name, value) in &self.params {
            values.insert(name.clone(), value.clone());
        }
        Ok(values)
    }
}

/// Resolves the node's topic names: expansion against the namespace, then the first matching remap rule.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NameResolver {
    node: NodeIdentity,
    rules: Vec<(String, String)>,
}

impl NameResolver {
    /// The fully qualified name a topic `name` (relative, absolute or `~/private`) ends up on.
    pub fn resolve(&self, name: &str) -> String {
        let expanded = resolve_name(name, &self.node);
        self.rules.iter().find(|(from, _)| *from == expanded).map(|(_, to)| to.clone()).unwrap_or(expanded)
    }
}

/// Expands a relative or private (`~`) name against the node's namespace and name.
pub fn resolve_name(name: &str, node: &NodeIdentity) -> String {
    if name.starts_with('/') {
        name.to_string()
    } else if name == "~" {
        node.fully_qualified_name()
    } else if let Some(rest) = name.strip_prefix("~/") {
        join_ros_names(&node.fully_qualified_name(), rest)
    } else {
        join_ros_names(&node.namespace, name)
    }
}

fn join_ros_names(namespace: &str, name: &str) -> String {
    if namespace.ends_with('/') {
        format!("{namespace}{name}")
    } else {
        format!("{namespace}/{name}")
    }
}

fn split_assignment<'a>(flag: &str, arg: &'a str) -> Result<(&'a str, &'a str), RosArgsError> {
    arg.split_once(":=")
        .filter(|(name, _)| !name.is_empty())
        .ok_or_else(|| RosArgsError::NoAssignment { flag: flag.to_string(), arg: arg.to_string() })
}

fn validate_token(token: &str) -> Result<(), RosArgsError> {
    let bad = |why: &str| Err(RosArgsError::BadName { name: token.to_string(), why: why.to_string() });
    match token.chars().next() {
        None => return bad("must not be empty"),
        Some(c) if !(c.is_ascii_alphabetic() || c == '_') => return bad("must start with a letter or '_'"),
        _ => {}
    }
    if !token.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return bad("may contain only letters, digits and '_'");
    }
    if token.contains("__") {
        return bad("must not contain '__'");
    }
    Ok(())
}

fn validate_topic_name(name: &str) -> Result<(), RosArgsError> {
    let body = name.strip_prefix("~/").or_else(|| name.strip_prefix('/')).unwrap_or(name);
    if name == "~" {
        return Ok(());
    }
    if body.is_empty() || body.ends_with('/') {
        return Err(RosArgsError::BadName { name: name.to_string(), why: "must not be empty or end with '/'".into() });
    }
    body.split('/').try_for_each(|token| {
        validate_token(token).map_err(|_| RosArgsError::BadName {
            name: name.to_string(),
            why: format!(
                "token '{token}' must start with a letter or '_' and contain only letters, digits, single '_'"
            ),
        })
    })
}

fn normalize_namespace(ns: &str) -> Result<String, RosArgsError> {
    let trimmed = ns.trim_end_matches('/');
    if trimmed.is_empty() {
        return Ok("/".to_string());
    }
    let absolute = if trimmed.starts_with('/') { trimmed.to_string() } else { format!("/{trimmed}") };
    absolute[1..].split('/').try_for_each(|token| {
        validate_token(token).map_err(|e| RosArgsError::BadName { name: ns.to_string(), why: e.to_string() })
    })?;
    Ok(absolute)
}

/// Parses a `-p` value the way rcl does: as a YAML scalar or flow sequence.
pub fn parse_parameter_value(name: &str, text: &str) -> Result<ParameterValue, RosArgsError> {
    let docs =
        crate::yaml::load(text).map_err(|e| RosArgsError::BadValue { name: name.to_string(), why: yaml_why(&e) })?;
    match docs.into_iter().next() {
        // An empty value is the empty string, as in rcl.
        None => Ok(ParameterValue::String(String::new())),
        Some(doc) => yaml_to_parameter(name, &doc),
    }
}

/// Why a YAML text was not read, as the end of an error naming it.
fn yaml_why(e: &crate::yaml::YamlError) -> String {
    if e.is_syntax() {
        format!("not valid YAML: {e}")
    } else {
        e.to_string()
    }
}

fn yaml_to_parameter(name: &str, yaml: &Yaml) -> Result<ParameterValue, RosArgsError> {
    let bad = |why: String| RosArgsError::BadValue { name: name.to_string(), why };
    Ok(match yaml {
        Yaml::Boolean(b) => ParameterValue::Boolean(*b),
        Yaml::Integer(i) => ParameterValue::Integer(*i),
        Yaml::Real(text) => {
            ParameterValue::Double(parse_yaml_real(text).ok_or_else(|| bad(format!("'{text}' is not a number")))?)
        }
        Yaml::String(s) => ParameterValue::String(s.clone()),
        Yaml::Array(items) => {
            if items.is_empty() {
                return Err(bad("an empty list has no type; give at least one element".into()));
            }
            if items.iter().all(|y| matches!(y, Yaml::Boolean(_))) {
                ParameterValue::BooleanArray(items.iter().filter_map(Yaml::as_bool).collect())
            } else if items.iter().all(|y| matches!(y, Yaml::Integer(_))) {
                ParameterValue::IntegerArray(items.iter().filter_map(Yaml::as_i64).collect())
            } else if items.iter().all(|y| matches!(y, Yaml::Integer(_) | Yaml::Real(_))) {
                let mut out = Vec::with_capacity(items.len());
                for item in items {
                    out.push(match item {
                        Yaml::Integer(i) => *i as f64,
                        Yaml::Real(t) => parse_yaml_real(t).ok_or_else(|| bad(format!("'{t}' is not a number")))?,
                        _ => unreachable!("filtered above"),
                    });
                }
                ParameterValue::DoubleArray(out)
            } else if items.iter().all(|y| matches!(y, Yaml::String(_))) {
                ParameterValue::StringArray(items.iter().filter_map(|y| y.as_str().map(str::to_string)).collect())
            } else {
                return Err(bad("list elements must all be booleans, all numbers or all strings".into()));
            }
        }
        Yaml::Null => return Err(bad("null is not a parameter value".into())),
        Yaml::Hash(_) => return Err(bad("a mapping is not a parameter value (nest names with '.')".into())),
        Yaml::Alias(_) | Yaml::BadValue => return Err(bad("unsupported YAML".into())),
    })
}

fn parse_yaml_real(text: &str) -> Option<f64> {
    match text {
        ".inf" | ".Inf" | ".INF" | "+.inf" | "+.Inf" | "+.INF" => Some(f64::INFINITY),
        "-.inf" | "-.Inf" | "-.INF" => Some(f64::NEG_INFINITY),
        ".nan" | ".NaN" | ".NAN" => Some(f64::NAN),
        _ => text.parse().ok(),
    }
}

/// The parameters a ROS 2 parameters file gives `node`, in the order they apply: sections whose key is a
/// wildcard (`/**`, `/*/name`, …) first, then the section naming the node exactly.
pub fn params_file_values(
    text: &str,
    path: &Path,
    node: &NodeIdentity,
) -> Result<Vec<(String, ParameterValue)>, RosArgsError> {
    let bad = |why: String| RosArgsError::BadParamsFile { path: path.to_path_buf(), why };
    let docs = crate::yaml::load(text).map_err(|e| bad(yaml_why(&e)))?;
    let Some(Yaml::Hash(top)) = docs.into_iter().next() else {
        return Err(bad("expected a mapping `node_name: {ros__parameters: {...}}` at the top".into()));
    };
    let fqn = node.fully_qualified_name();
    let mut wildcard = Vec::new();
    let mut exact = Vec::new();
    for (key, section) in &top {
        let Some(key) = key.as_str() else {
            return Err(bad(format!("top-level key {key:?} is not a node name")));
        };
        let pattern = if key.starts_with('/') { key.to_string() } else { format!("/{key}") };
        if !node_pattern_matches(&pattern, &fqn) {
            continue;
        }
        let params = match section {
            Yaml::Hash(h) => h.get(&Yaml::String("ros__parameters".into())),
            _ => None,
        };
        let Some(params) = params else {
            return Err(bad(format!("section '{key}' has no `ros__parameters:` mapping")));
        };
        let target = if pattern.contains('*') { &mut wildcard } else { &mut exact };
        flatten_params("", params, target).map_err(|e| bad(e.to_string()))?;
    }
    wildcard.extend(exact);
    Ok(wildcard)
}

fn flatten_params(prefix: &str, yaml: &Yaml, out: &mut Vec<(String, ParameterValue)>) -> Result<(), RosArgsError> {
    match yaml {
        Yaml::Hash(map) => {
            for (key, value) in map {
                let key = match key {
                    Yaml::String(s) => s.clone(),
                    Yaml::Integer(i) => i.to_string(),
                    other => {
                        return Err(RosArgsError::BadValue {
                            name: prefix.to_string(),
                            why: format!("key {other:?} is not a name"),
                        })
                    }
                };
                let name = if prefix.is_empty() { key } else { format!("{prefix}.{key}") };
                flatten_params(&name, value, out)?;
            }
            Ok(())
        }
        leaf => {
            out.push((prefix.to_string(), yaml_to_parameter(prefix, leaf)?));
            Ok(())
        }
    }
}

/// rcl's node-name matching in parameter files: `*` is one name token, `**` any number of tokens.
fn node_pattern_matches(pattern: &str, fqn: &str) -> bool {
    let pattern: Vec<&str> = pattern.trim_start_matches('/').split('/').collect();
    let name: Vec<&str> = fqn.trim_start_matches('/').split('/').collect();
    fn matches(p: &[&str], n: &[&str]) -> bool {
        match (p.first(), n.first()) {
            (None, None) => true,
            (Some(&"**"), _) => (0..=n.len()).any(|k| matches(&p[1..], &n[k..])),
            (Some(&"*"), Some(_)) => matches(&p[1..], &n[1..]),
            (Some(a), Some(b)) if a == b => matches(&p[1..], &n[1..]),
            _ => false,
        }
    }
    matches(&pattern, &name)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_string).collect()
    }

    /// The cases of the former `ros::args` parser of `pub`/`echo`, now served by this one.
    #[test]
    fn parses_the_pub_echo_ros_args() {
        let a = RosArgs::parse(&args(
            "--ros-args -r __ns:=/rig3 -r __node:=spot -r swing:=/lab/swing -p modes:=12 --params-file p.yaml \
             --log-level debug --",
        ))
        .unwrap();
        assert_eq!(a.identity("sweetspot_echo", "/"), NodeIdentity { namespace: "/rig3".into(), name: "spot".into() });
        assert_eq!(a.params, [("modes".to_string(), ParameterValue::Integer(12))]);
        assert_eq!(a.params_files, [PathBuf::from("p.yaml")]);
        assert_eq!(a.log_level.as_deref(), Some("debug"));
        let r = a.resolver(&a.identity("sweetspot_echo", "/"));
        assert_eq!(r.resolve("swing"), "/lab/swing");
        assert_eq!(r.resolve("bat/params"), "/rig3/bat/params");
        assert!(RosArgs::parse(&args("--ros-args -r")).is_err());
        assert!(RosArgs::parse(&args("--ros-args --bogus")).is_err());
        assert!(RosArgs::parse(&["--ros-args", "-r", "__ns:=/bad name"]).is_err());
    }

    #[test]
    fn namespace_and_node_name_remaps() {
        let a = RosArgs::parse(&args("--ros-args -r __ns:=/rig3 -r __node:=bat_lab")).unwrap();
        let id = a.identity("sweetspot", "/");
        assert_eq!(id, NodeIdentity { namespace: "/rig3".into(), name: "bat_lab".into() });
        assert_eq!(id.fully_qualified_name(), "/rig3/bat_lab");
        let r = a.resolver(&id);
        assert_eq!(r.resolve("swing"), "/rig3/swing");
        assert_eq!(r.resolve("bat/params"), "/rig3/bat/params");
        assert_eq!(r.resolve("/diagnostics"), "/diagnostics");
        assert_eq!(r.resolve("~/status"), "/rig3/bat_lab/status");
    }

    /// rcl: `node:__ns:=` and `node:__node:=` concern only the node whose name in code is `node`, and the
    /// first matching rule of each kind wins (rcl_remap.c `_rcl_remap_first_match`).
    #[test]
    fn node_prefixed_identity_rules_apply_only_to_that_node() {
        let a = RosArgs::parse(&args("--ros-args -r other_node:__ns:=/x -r other_node:__node:=y")).unwrap();
        assert_eq!(a.identity("sweetspot", "/"), NodeIdentity { namespace: "/".into(), name: "sweetspot".into() });
        assert_eq!(a.identity("other_node", "/"), NodeIdentity { namespace: "/x".into(), name: "y".into() });

        let a = RosArgs::parse(&args("-r sweetspot:__ns:=/mine -r __ns:=/everyone -r sweetspot:__node:=spot")).unwrap();
        assert_eq!(a.identity("sweetspot", "/"), NodeIdentity { namespace: "/mine".into(), name: "spot".into() });
        assert_eq!(
            a.identity("sweetspot_echo", "/"),
            NodeIdentity { namespace: "/everyone".into(), name: "sweetspot_echo".into() }
        );

        let a = RosArgs::parse(&args("-r __ns:=/first -r __ns:=/second")).unwrap();
        assert_eq!(a.identity("sweetspot", "/").namespace, "/first");
    }

    #[test]
    fn root_namespace_resolution_has_single_slashes() {
        let id = RosArgs::default().identity("sweetspot", "/");
        let r = RosArgs::default().resolver(&id);
        assert_eq!(r.resolve("swing"), "/swing");
        assert_eq!(id.fully_qualified_name(), "/sweetspot");
    }

    #[test]
    fn namespace_without_leading_slash_is_made_absolute() {
        let a = RosArgs::parse(&args("-r __ns:=lab/rig3/")).unwrap();
        assert_eq!(a.identity("sweetspot", "/").namespace, "/lab/rig3");
    }

    #[test]
    fn topic_remaps_match_resolved_names() {
        let a = RosArgs::parse(&args("--ros-args -r __ns:=/rig3 -r swing:=/shared/swings -r /rig3/exit_velocity:=ev -r other_node:bat/params:=nope")).unwrap();
        let id = a.identity("sweetspot", "/");
        let r = a.resolver(&id);
        assert_eq!(r.resolve("swing"), "/shared/swings");
        assert_eq!(r.resolve("exit_velocity"), "/rig3/ev");
        assert_eq!(r.resolve("bat/params"), "/rig3/bat/params", "rule for another node must not apply");
        let a = RosArgs::parse(&args("-r sweetspot:bat/params:=yes")).unwrap();
        assert_eq!(a.resolver(&a.identity("sweetspot", "/")).resolve("bat/params"), "/yes");
    }

    #[test]
    fn parameter_values_are_yaml_typed() {
        let a = RosArgs::parse(&args(
            "-p record:=false -p default_modes:=12 -p time_step:=2.5e-6 -p record_path:=/tmp/x -p speeds:=[1,2.5] -p ids:=[a,b] -p flags:=[true,false] -p n:=[1,2] -p empty:=",
        ))
        .unwrap();
        let got: BTreeMap<_, _> = a.params.into_iter().collect();
        assert_eq!(got["record"], ParameterValue::Boolean(false));
        assert_eq!(got["default_modes"], ParameterValue::Integer(12));
        assert_eq!(got["time_step"], ParameterValue::Double(2.5e-6));
        assert_eq!(got["record_path"], ParameterValue::String("/tmp/x".into()));
        assert_eq!(got["speeds"], ParameterValue::DoubleArray(vec![1.0, 2.5]));
        assert_eq!(got["ids"], ParameterValue::StringArray(vec!["a".into(), "b".into()]));
        assert_eq!(got["flags"], ParameterValue::BooleanArray(vec![true, false]));
        assert_eq!(got["n"], ParameterValue::IntegerArray(vec![1, 2]));
        assert_eq!(got["empty"], ParameterValue::String(String::new()));
    }

    #[test]
    fn malformed_arguments_are_refused_with_a_reason() {
        assert!(matches!(RosArgs::parse(&args("-r")), Err(RosArgsError::MissingValue { .. })));
        assert!(matches!(RosArgs::parse(&args("-p novalue")), Err(RosArgsError::NoAssignment { .. })));
        assert!(matches!(RosArgs::parse(&args("--frobnicate")), Err(RosArgsError::Unknown(_))));
        assert!(matches!(RosArgs::parse(&args("-r __node:=9lives")), Err(RosArgsError::BadName { .. })));
        assert!(matches!(RosArgs::parse(&args("-r a//b:=c")), Err(RosArgsError::BadName { .. })));
        assert!(matches!(RosArgs::parse(&args("-p x:=[1,a]")), Err(RosArgsError::BadValue { .. })));
        let e = RosArgs::parse(&args("-p x:=[1,a]")).unwrap_err().to_string();
        assert!(e.contains("'x'"), "{e}");
    }

    #[test]
    fn params_file_wildcards_then_exact_section_then_dash_p() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("params.yaml");
        std::fs::write(
            &path,
            "/rig3/sweetspot:\n  ros__parameters:\n    default_modes: 10\n    reference:\n      ball_speed: 35.0\n\
             /**:\n  ros__parameters:\n    default_modes: 8\n    record: false\n    time_step: 1.0e-6\n\
             other_node:\n  ros__parameters:\n    default_modes: 3\n\
             /*/sweetspot:\n  ros__parameters:\n    queue_capacity: 64\n",
        )
        .unwrap();
        let cmd = vec![
            "--ros-args".to_string(),
            "-r".into(),
            "__ns:=/rig3".into(),
            "--params-file".into(),
            path.display().to_string(),
            "-p".into(),
            "time_step:=3e-6".into(),
        ];
        let a = RosArgs::parse(&cmd).unwrap();
        let values = a.parameter_overrides(&a.identity("sweetspot", "/")).unwrap();
        assert_eq!(values["default_modes"], ParameterValue::Integer(10), "exact section beats /**");
        assert_eq!(values["record"], ParameterValue::Boolean(false));
        assert_eq!(values["reference.ball_speed"], ParameterValue::Double(35.0));
        assert_eq!(values["queue_capacity"], ParameterValue::Integer(64));
        assert_eq!(values["time_step"], ParameterValue::Double(3e-6), "-p beats the file");
        assert!(!values.contains_key("other"));
        // In the root namespace only `/**` applies.
        let values = RosArgs { params_files: vec![path.clone()], ..Default::default() }
            .parameter_overrides(&NodeIdentity { namespace: "/".into(), name: "sweetspot".into() })
            .unwrap();
        assert_eq!(values["default_modes"], ParameterValue::Integer(8));
        assert!(!values.contains_key("queue_capacity"));
    }

    #[test]
    fn params_file_errors_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.yaml");
        std::fs::write(&path, "sweetspot:\n  default_modes: 3\n").unwrap();
        let a = RosArgs { params_files: vec![path.clone()], ..Default::default() };
        let e = a.parameter_overrides(&a.identity("sweetspot", "/")).unwrap_err();
        assert!(e.to_string().contains("ros__parameters"), "{e}");
        assert!(e.to_string().contains("bad.yaml"), "{e}");
        let missing = RosArgs { params_files: vec![dir.path().join("nope.yaml")], ..Default::default() };
        assert!(missing.parameter_overrides(&missing.identity("sweetspot", "/")).is_err());
    }

    #[test]
    fn node_patterns() {
        assert!(node_pattern_matches("/**", "/sweetspot"));
        assert!(node_pattern_matches("/**", "/a/b/sweetspot"));
        assert!(node_pattern_matches("/**/sweetspot", "/a/b/sweetspot"));
        assert!(node_pattern_matches("/**/sweetspot", "/sweetspot"));
        assert!(!node_pattern_matches("/*/sweetspot", "/sweetspot"));
        assert!(node_pattern_matches("/*/sweetspot", "/rig/sweetspot"));
        assert!(!node_pattern_matches("/sweetspot", "/rig/sweetspot"));
    }
}
