//! The Foxglove layout shipped in `layouts/sweetspot.json` refers only to topics the node serves and fields
//! that exist in `msgs/` (read from the .msg files themselves, not the generated code), so renaming a field
//! breaks this test instead of a user's dashboard. Every panel the layout places has a configuration, and every
//! configuration is placed.

use std::collections::BTreeSet;
use std::path::Path;

use serde_json::Value;

/// The node's default topic names and their types (`package/Type`).
const TOPICS: &[(&str, &str)] = &[
    ("/bat/params", "sweetspot_msgs/BatParams"),
    ("/ball/params", "sweetspot_msgs/BallParams"),
    ("/swing", "sweetspot_msgs/Swing"),
    ("/exit_velocity", "sweetspot_msgs/ExitVelocity"),
    ("/modal_energies", "sweetspot_msgs/ModalEnergies"),
    ("/sweet_spot", "sweetspot_msgs/SweetSpot"),
    ("/swing_scene", "visualization_msgs/MarkerArray"),
    ("/diagnostics", "diagnostic_msgs/DiagnosticArray"),
    ("/rosout", "rcl_interfaces/Log"),
];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The fields (name, type) of `package/Type`, read from its .msg file under msgs/.
fn fields(type_name: &str) -> Vec<(String, String)> {
    let (package, name) = type_name.split_once('/').unwrap();
    let candidates = [
        root().join(format!("msgs/{package}/msg/{name}.msg")),
        root().join(format!("msgs/ros_interfaces/{package}/msg/{name}.msg")),
    ];
    let path = candidates.iter().find(|p| p.is_file()).unwrap_or_else(|| panic!("no .msg for {type_name}"));
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .map(|l| l.split('#').next().unwrap().trim())
        .filter(|l| !l.is_empty() && !l.contains('='))
        .map(|l| {
            let mut words = l.split_whitespace();
            let ty = words.next().unwrap().to_string();
            let field = words.next().unwrap().to_string();
            // A field's type relative to its own package, arrays stripped.
            let base = ty.split('[').next().unwrap().to_string();
            let resolved = if base.contains('/') || base.chars().next().unwrap().is_lowercase() {
                base
            } else if base == "Header" {
                "std_msgs/Header".to_string()
            } else {
                format!("{package}/{base}")
            };
            (field, resolved)
        })
        .collect()
}

/// Checks a message path like `/exit_velocity{bat_id=="r161"}.exit_speed` or `/modal_energies.energy[:]`.
fn check_path(path: &str) -> Result<(), String> {
    // Filters `{field==value}` name fields of the message they follow.
    let mut filters = Vec::new();
    let mut plain = String::new();
    let mut rest = path;
    while let Some(open) = rest.find('{') {
        plain.push_str(&rest[..open]);
        let close = rest[open..].find('}').ok_or(format!("{path}: unclosed filter"))? + open;
        let filter = &rest[open + 1..close];
        let field = filter.split(['=', '!', '<', '>']).next().unwrap().trim().to_string();
        filters.push((plain.clone(), field));
        rest = &rest[close + 1..];
    }
    plain.push_str(rest);
    let mut segments = plain.split('.');
    let topic = segments.next().unwrap();
    let (_, ty) = TOPICS.iter().find(|(t, _)| *t == topic).ok_or(format!("{path}: topic {topic} is not served"))?;
    for (prefix, field) in &filters {
        if prefix != topic {
            return Err(format!("{path}: filters are checked on the topic only"));
        }
        if !fields(ty).iter().any(|(f, _)| f == field) {
            return Err(format!("{path}: {ty} has no field {field}"));
        }
    }
    let mut ty = ty.to_string();
    for segment in segments {
        let name = segment.split('[').next().unwrap();
        let (_, next) =
            fields(&ty).into_iter().find(|(f, _)| f == name).ok_or(format!("{path}: {ty} has no field {name}"))?;
        ty = next;
    }
    Ok(())
}

fn placed(node: &Value, out: &mut BTreeSet<String>) {
    match node {
        Value::String(id) => {
            out.insert(id.clone());
        }
        Value::Object(split) => {
            placed(&split["first"], out);
            placed(&split["second"], out);
        }
        other => panic!("layout node {other}"),
    }
}

#[test]
fn the_layout_references_only_served_topics_and_existing_fields() {
    let text = std::fs::read_to_string(root().join("layouts/sweetspot.json")).unwrap();
    let layout: Value = serde_json::from_str(&text).unwrap();
    let configs = layout["configById"].as_object().expect("configById");
    let mut ids = BTreeSet::new();
    placed(&layout["layout"], &mut ids);
    assert_eq!(ids, configs.keys().cloned().collect::<BTreeSet<_>>(), "placed panels = configured panels");

    let mut checked = 0;
    for (id, config) in configs {
        // A plot's series and the path its x axis takes values from (`xAxisPath`, e.g. the modes' frequencies).
        for path in config["paths"].as_array().into_iter().flatten().chain(config.get("xAxisPath")) {
            check_path(path["value"].as_str().unwrap()).unwrap_or_else(|e| panic!("{id}: {e}"));
            checked += 1;
        }
        // A 3D panel's topics, and the frame it follows: the one the scene's markers are drawn in.
        for topic in config.get("topics").and_then(Value::as_object).into_iter().flat_map(|t| t.keys()) {
            assert!(TOPICS.iter().any(|(t, _)| t == topic), "{id}: topic {topic}");
            checked += 1;
        }
        if let Some(frame) = config.get("followTf").and_then(Value::as_str) {
            assert_eq!(frame, sweetspot::model::scene::FRAME_ID, "{id}");
        }
        if let Some(topic) = config.get("topicToRender").and_then(Value::as_str) {
            assert!(TOPICS.iter().any(|(t, _)| *t == topic), "{id}: topic {topic}");
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked} references checked");
    assert!(configs.values().any(|c| c["topics"]["/swing_scene"]["visible"] == true), "a 3D panel shows the scene");

    // The checker itself rejects what it must.
    assert!(check_path("/exit_velocity.exit_sped").is_err());
    assert!(check_path("/exit_velocity{bat==\"x\"}.exit_speed").is_err());
    assert!(check_path("/exit_speed.exit_speed").is_err());
    assert!(check_path("/exit_velocity.header.stamp.nanosec").is_ok());
    assert!(check_path("/exit_velocity.header.stamp.nsec").is_err());
    assert!(check_path("/swing_scene.markers[0].pose.position.z").is_ok(), "nested types of other packages");
    assert!(check_path("/swing_scene.markers[0].pose.position.w").is_err());
}

/// The layout as a user first sees it, before touching a setting: Lichtblick's "floating" legend is drawn inside
/// the plot area (the other positions, "top" and "left", take room beside it), so every plot puts its legend
/// beside the data; no series waits for the user to edit the layout (an id to fill in); and the 3D panel draws
/// no frame-axis labels, which at the scene's scale dwarf the bat and the swing's own label.
#[test]
fn the_layout_opens_readable_without_editing() {
    let text = std::fs::read_to_string(root().join("layouts/sweetspot.json")).unwrap();
    let layout: Value = serde_json::from_str(&text).unwrap();
    let configs = layout["configById"].as_object().expect("configById");
    for (id, config) in configs.iter().filter(|(id, _)| id.starts_with("Plot!")) {
        if config["showLegend"] == true {
            let place = config["legendDisplay"].as_str().unwrap_or("floating");
            assert!(["top", "left"].contains(&place), "{id}: legend {place} covers the data");
        }
        for series in config["paths"].as_array().expect("paths") {
            let label = series["label"].as_str().unwrap_or_default();
            assert!(series["enabled"] == true, "{id}: series {label} is off until a user edits the layout");
            assert!(!label.contains("edit"), "{id}: series {label}");
        }
    }
    let scenes: Vec<&Value> = configs.iter().filter(|(id, _)| id.starts_with("3D!")).map(|(_, c)| c).collect();
    assert!(!scenes.is_empty());
    for scene in scenes {
        assert_eq!(scene["scene"]["transforms"]["showLabel"], false, "frame labels drawn");
    }
}
