//! ROS 2 topic names: validation, resolution of relative and private names against a namespace, and the
//! DDS topic name (`rt/` + the fully-qualified name) every ROS 2 middleware uses.

/// A malformed ROS name, with the rule it breaks.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("invalid ROS name {name:?}: {reason}")]
pub struct NameError {
    /// The offending name, cut to the bound the node echoes any peer string to (a name may come from a 1 MB
    /// argument or parameter file).
    pub name: String,
    /// The rule it breaks.
    pub reason: &'static str,
}

fn bad(name: &str, reason: &'static str) -> NameError {
    NameError { name: crate::model::limits::echo(name).into_owned(), reason }
}

fn check_tokens(full: &str, tokens: &str) -> Result<(), NameError> {
    for token in tokens.split('/') {
        if token.is_empty() {
            return Err(bad(full, "empty token (a doubled or trailing '/')"));
        }
        let first = token.as_bytes()[0];
        if first.is_ascii_digit() {
            return Err(bad(full, "a token may not start with a digit"));
        }
        if !token.bytes().all(|c| c.is_ascii_alphanumeric() || c == b'_') {
            return Err(bad(full, "only letters, digits, '_' and '/' are allowed"));
        }
        if token.contains("__") {
            return Err(bad(full, "'__' is not allowed"));
        }
    }
    Ok(())
}

/// Validates and normalises a namespace: `""`, `"/"` → `"/"`; `"rig3"`, `"/rig3/"` → `"/rig3"`.
pub fn normalize_namespace(namespace: &str) -> Result<String, NameError> {
    let trimmed = namespace.trim_start_matches('/').trim_end_matches('/');
    if trimmed.is_empty() {
        return Ok("/".into());
    }
    check_tokens(namespace, trimmed)?;
    Ok(format!("/{trimmed}"))
}

/// Validates a node name (one token).
pub fn check_node_name(name: &str) -> Result<(), NameError> {
    if name.is_empty() || name.contains('/') {
        return Err(bad(name, "a node name is one non-empty token"));
    }
    check_tokens(name, name)
}

/// The fully-qualified topic name of `topic` for a node `node_name` in `namespace`, as rcl resolves it:
/// `/abs` stays, `rel/x` becomes `<namespace>/rel/x`, `~/x` becomes `<namespace>/<node_name>/x`.
pub fn resolve_topic(topic: &str, namespace: &str, node_name: &str) -> Result<String, NameError> {
    let ns = normalize_namespace(namespace)?;
    let join = |prefix: &str, rest: &str| {
        if prefix == "/" {
            format!("/{rest}")
        } else {
            format!("{prefix}/{rest}")
        }
    };
    let full = if let Some(abs) = topic.strip_prefix('/') {
        format!("/{abs}")
    } else if topic == "~" {
        check_node_name(node_name)?;
        join(&ns, node_name)
    } else if let Some(private) = topic.strip_prefix("~/") {
        check_node_name(node_name)?;
        join(&join(&ns, node_name), private)
    } else {
        join(&ns, topic)
    };
    if full.len() < 2 {
        return Err(bad(topic, "empty name"));
    }
    check_tokens(topic, &full[1..])?;
    Ok(full)
}

/// The DDS topic name of a fully-qualified ROS topic: `/rig3/swing` → `rt/rig3/swing`.
pub fn dds_topic_name(fq_topic: &str) -> String {
    format!("rt{fq_topic}")
}

/// A fully-qualified name as ros2-client's absolute [`ros2_client::Name`].
pub fn to_client_name(fq_topic: &str) -> Result<ros2_client::Name, NameError> {
    ros2_client::Name::parse(fq_topic).map_err(|_| bad(fq_topic, "not accepted by ros2-client"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1 MB name is refused with its first bytes and its length, not echoed whole.
    #[test]
    fn a_huge_bad_name_is_echoed_cut() {
        let huge = format!("bad name {}", "x".repeat(1 << 20));
        let error = resolve_topic(&huge, "/", "n").unwrap_err().to_string();
        assert!(error.len() < 400, "{} bytes", error.len());
        assert!(error.starts_with("invalid ROS name \"bad name xxx") && error.contains("(1048585 bytes)"), "{error}");
    }

    #[test]
    fn resolves_like_rcl() {
        assert_eq!(resolve_topic("swing", "/", "n").unwrap(), "/swing");
        assert_eq!(resolve_topic("swing", "", "n").unwrap(), "/swing");
        assert_eq!(resolve_topic("bat/params", "/rig3", "n").unwrap(), "/rig3/bat/params");
        assert_eq!(resolve_topic("bat/params", "rig3/", "n").unwrap(), "/rig3/bat/params");
        assert_eq!(resolve_topic("/diagnostics", "/rig3", "n").unwrap(), "/diagnostics");
        assert_eq!(resolve_topic("~/status", "/rig3", "sweetspot").unwrap(), "/rig3/sweetspot/status");
        assert_eq!(dds_topic_name("/rig3/swing"), "rt/rig3/swing");
        for bad in ["", "a//b", "a/", "1abc", "a__b", "a-b", "/"] {
            assert!(resolve_topic(bad, "/", "n").is_err(), "{bad:?}");
        }
        assert!(normalize_namespace("/r ig").is_err());
        assert_eq!(to_client_name("/rig3/swing").unwrap().to_string(), "/rig3/swing");
    }
}
