//! The workspace's layering, read off Cargo's own resolution (`cargo tree`), not off our manifests' text: the
//! crates under `crates/` build without DDS, an async runtime or a server (what the Python package links), each
//! depends only on the layers below it, and the root crate is where ROS 2 comes in.
use std::process::Command;

/// The crates a package is built with (normal dependencies, resolved for that package alone), one name each.
fn resolved_dependencies(package: &str) -> Vec<String> {
    let out = Command::new(env!("CARGO"))
        .args(["tree", "--offline", "--locked", "-e", "normal", "--prefix", "none", "--format", "{p}", "-p", package])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo runs");
    assert!(out.status.success(), "cargo tree -p {package}: {}", String::from_utf8_lossy(&out.stderr));
    let mut names: Vec<String> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|line| line.split_whitespace().next().map(str::to_owned))
        .collect();
    names.sort();
    names.dedup();
    names
}

const SHELL_ONLY: [&str; 5] = ["rustdds", "ros2-client", "tokio", "foxglove", "tokio-tungstenite"];
const LAYERS: [&str; 5] =
    ["sweetspot-physics", "sweetspot-msgs", "sweetspot-model", "sweetspot-bag", "sweetspot-analysis"];

#[test]
fn the_library_crates_build_without_dds_tokio_or_the_foxglove_server() {
    for layer in LAYERS {
        let deps = resolved_dependencies(layer);
        let shell: Vec<_> = deps.iter().filter(|d| SHELL_ONLY.contains(&d.as_str())).collect();
        assert!(shell.is_empty(), "{layer} pulls in {shell:?}");
    }
}

#[test]
fn the_python_extension_module_builds_without_dds_tokio_or_the_foxglove_server() {
    let deps = resolved_dependencies("sweetspot-python");
    assert!(deps.iter().any(|d| d == "pyo3"), "sweetspot-python without pyo3: {deps:?}");
    let shell: Vec<_> = deps.iter().filter(|d| SHELL_ONLY.contains(&d.as_str()) || *d == "sweetspot").collect();
    assert!(shell.is_empty(), "the wheel pulls in {shell:?}");
}

#[test]
fn the_root_crate_is_where_ros2_comes_in() {
    let deps = resolved_dependencies("sweetspot");
    for shell in ["rustdds", "ros2-client", "tokio", "foxglove"] {
        assert!(deps.iter().any(|d| d == shell), "sweetspot without {shell}: {deps:?}");
    }
}

#[test]
fn each_layer_depends_only_on_the_layers_below_it() {
    for (i, layer) in LAYERS.iter().enumerate() {
        let deps = resolved_dependencies(layer);
        let above: Vec<_> = LAYERS[i + 1..].iter().filter(|l| deps.iter().any(|d| d == *l)).collect();
        assert!(above.is_empty(), "{layer} depends on {above:?}, above it");
        assert!(!deps.iter().any(|d| d == "sweetspot"), "{layer} depends on the root crate");
    }
    // The physics is the bottom: nothing of sweetspot's below it.
    let physics = resolved_dependencies("sweetspot-physics");
    assert_eq!(physics.iter().filter(|d| d.starts_with("sweetspot")).collect::<Vec<_>>(), ["sweetspot-physics"]);
}
