//! `--ros-args` as rcl parses them: `-r/--remap from:=to` (including `__ns:=`, `__node:=`/`__name:=` and
//! node-scoped `node:from:=to`), `-p/--param name:=value`, `--params-file FILE`, `--log-level`,
//! `--enable-/--disable-rosout-logs` (and the stdout/external-lib variants and `-e/--enclave`, accepted and
//! ignored). Arguments after `--` or outside a `--ros-args` section are returned untouched.

use std::path::PathBuf;

use super::names::{check_node_name, normalize_namespace, resolve_topic, NameError};
use super::RosError;

/// The ROS arguments of one process.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RosArgs {
    /// `-r __ns:=/rig3` (normalised, e.g. `/rig3`).
    pub namespace: Option<String>,
    /// `-r __node:=name`.
    pub node_name: Option<String>,
    /// Topic remaps in order: (node the rule is limited to, from, to).
    pub remaps: Vec<(Option<String>, String, String)>,
    /// `-p name:=value` in order (value as written, YAML-like).
    pub params: Vec<(String, String)>,
    /// `--params-file FILE` in order.
    pub params_files: Vec<PathBuf>,
    /// `--log-level LEVEL` (the last one given).
    pub log_level: Option<String>,
    /// `--enable-rosout-logs` / `--disable-rosout-logs`.
    pub rosout_logs: Option<bool>,
}

fn split_rule(rule: &str) -> Result<(&str, &str), RosError> {
    rule.split_once(":=")
        .ok_or_else(|| RosError::Args(format!("expected `from:=to`, found `{rule}`")))
}

impl RosArgs {
    /// Splits `args` into the ROS arguments and the others.
    pub fn parse<S: AsRef<str>>(args: &[S]) -> Result<(RosArgs, Vec<String>), RosError> {
        let mut out = RosArgs::default();
        let mut rest = Vec::new();
        let mut in_ros = false;
        let mut i = 0;
        let next = |i: &mut usize, flag: &str| -> Result<String, RosError> {
            *i += 1;
            args.get(*i)
                .map(|s| s.as_ref().to_string())
                .ok_or_else(|| RosError::Args(format!("{flag} needs a value")))
        };
        while i < args.len() {
            let a = args[i].as_ref();
            if a == "--ros-args" {
                in_ros = true;
            } else if !in_ros {
                rest.push(a.to_string());
            } else if a == "--" {
                in_ros = false;
            } else {
                match a {
                    "-r" | "--remap" => {
                        let rule = next(&mut i, a)?;
                        out.add_remap(&rule)?;
                    }
                    "-p" | "--param" => {
                        let rule = next(&mut i, a)?;
                        let (name, value) = split_rule(&rule)?;
                        if name.is_empty() {
                            return Err(RosError::Args(format!(
                                "parameter without a name in `{rule}`"
                            )));
                        }
                        out.params.push((name.to_string(), value.to_string()));
                    }
                    "--params-file" => out.params_files.push(PathBuf::from(next(&mut i, a)?)),
                    "--log-level" => out.log_level = Some(next(&mut i, a)?),
                    "--enable-rosout-logs" => out.rosout_logs = Some(true),
                    "--disable-rosout-logs" => out.rosout_logs = Some(false),
                    "-e" | "--enclave" => {
                        next(&mut i, a)?;
                    }
                    "--enable-stdout-logs"
                    | "--disable-stdout-logs"
                    | "--enable-external-lib-logs"
                    | "--disable-external-lib-logs" => {}
                    other => return Err(RosError::Args(format!("unknown ROS argument `{other}`"))),
                }
            }
            i += 1;
        }
        Ok((out, rest))
    }

    fn add_remap(&mut self, rule: &str) -> Result<(), RosError> {
        let (lhs, to) = split_rule(rule)?;
        // `node:from:=to` limits the rule to one node.
        let (scope, from) = match lhs.split_once(':') {
            Some((node, from)) => (Some(node.to_string()), from),
            None => (None, lhs),
        };
        match from {
            "__ns" => self.namespace = Some(normalize_namespace(to)?),
            "__node" | "__name" => {
                check_node_name(to)?;
                self.node_name = Some(to.to_string())
            }
            _ => {
                if from.is_empty() || to.is_empty() {
                    return Err(RosError::Args(format!("empty side in remap `{rule}`")));
                }
                self.remaps.push((scope, from.to_string(), to.to_string()))
            }
        }
        Ok(())
    }

    /// The namespace to use: `__ns` if given, else `default`.
    pub fn namespace_or(&self, default: &str) -> Result<String, NameError> {
        match &self.namespace {
            Some(ns) => Ok(ns.clone()),
            None => normalize_namespace(default),
        }
    }

    /// Resolves `topic` for node `node_name` in `namespace`, then applies the first remap rule whose `from`
    /// resolves to the same name (rcl's rule), giving the fully-qualified topic name.
    pub fn resolve_topic(
        &self,
        topic: &str,
        namespace: &str,
        node_name: &str,
    ) -> Result<String, NameError> {
        let resolved = resolve_topic(topic, namespace, node_name)?;
        for (scope, from, to) in &self.remaps {
            if scope.as_deref().is_some_and(|n| n != node_name) {
                continue;
            }
            if resolve_topic(from, namespace, node_name)? == resolved {
                return resolve_topic(to, namespace, node_name);
            }
        }
        Ok(resolved)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_ros_args() {
        let args = [
            "--count",
            "3",
            "--ros-args",
            "-r",
            "__ns:=/rig3",
            "-r",
            "__node:=spot",
            "-r",
            "swing:=/lab/swing",
            "-p",
            "modes:=12",
            "--params-file",
            "p.yaml",
            "--log-level",
            "debug",
            "--",
            "tail",
        ];
        let (ros, rest) = RosArgs::parse(&args).unwrap();
        assert_eq!(rest, ["--count", "3", "tail"]);
        assert_eq!(ros.namespace.as_deref(), Some("/rig3"));
        assert_eq!(ros.node_name.as_deref(), Some("spot"));
        assert_eq!(ros.params, [("modes".to_string(), "12".to_string())]);
        assert_eq!(ros.params_files, [PathBuf::from("p.yaml")]);
        assert_eq!(
            ros.resolve_topic("swing", "/rig3", "spot").unwrap(),
            "/lab/swing"
        );
        assert_eq!(
            ros.resolve_topic("bat/params", "/rig3", "spot").unwrap(),
            "/rig3/bat/params"
        );
        assert!(RosArgs::parse(&["--ros-args", "-r"]).is_err());
        assert!(RosArgs::parse(&["--ros-args", "--bogus"]).is_err());
        assert!(RosArgs::parse(&["--ros-args", "-r", "__ns:=/bad name"]).is_err());
    }
}
