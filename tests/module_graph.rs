//! No two modules of one folder import each other, directly or round a loop: within a folder, imports run
//! one way (docs/development.md, "Layout"). A structural check of the source: each file's `super::NAME` and
//! `crate::NAME` paths outside comments and its test module, where NAME is a sibling file or folder.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Every folder of Rust source: src/ and each crate's src/, with their sub-folders.
fn source_folders() -> Vec<PathBuf> {
    let mut roots = vec![Path::new(ROOT).join("src")];
    for entry in std::fs::read_dir(Path::new(ROOT).join("crates")).expect("crates/") {
        let src = entry.expect("entry").path().join("src");
        if src.is_dir() {
            roots.push(src);
        }
    }
    let mut folders = Vec::new();
    while let Some(folder) = roots.pop() {
        for entry in std::fs::read_dir(&folder).expect("folder") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                roots.push(path);
            }
        }
        folders.push(folder);
    }
    folders
}

/// The modules a folder holds (`x.rs` or `x/`), by name; the folder's own `mod.rs`/`lib.rs`/`main.rs` are not
/// among them.
fn modules(folder: &Path) -> BTreeMap<String, PathBuf> {
    let mut out = BTreeMap::new();
    for entry in std::fs::read_dir(folder).expect("folder") {
        let path = entry.expect("entry").path();
        let file = if path.is_dir() { path.join("mod.rs") } else { path.clone() };
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default().to_string();
        let is_rust = path.is_dir() || path.extension().is_some_and(|e| e == "rs");
        if is_rust && file.is_file() && !["mod", "lib", "main"].contains(&stem.as_str()) {
            out.insert(stem, file);
        }
    }
    out
}

/// The code of a file up to its test module, without comment lines.
fn code(file: &Path) -> String {
    let text = std::fs::read_to_string(file).expect("source");
    let body = text.split("#[cfg(test)]").next().unwrap_or_default();
    body.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n")
}

/// The first names of the paths that start with `prefix` (`super::` or `crate::`), groups included:
/// `super::{a, b::c}` names a and b. `super::super::x` leaves the folder and names nothing here.
fn named_after(code: &str, prefix: &str) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    let ident = |s: &str| s.trim_start().chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect::<String>();
    for (at, _) in code.match_indices(prefix) {
        let before = code[..at].chars().next_back();
        if before.is_some_and(|c| c == ':' || c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &code[at + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let mut depth = 0;
            let end = group
                .char_indices()
                .find(|&(_, c)| {
                    depth += match c {
                        '{' => 1,
                        '}' => -1,
                        _ => 0,
                    };
                    depth < 0
                })
                .map_or(group.len(), |(i, _)| i);
            let mut item_start = true;
            let mut depth = 0;
            for (i, c) in group[..end].char_indices() {
                if item_start && depth == 0 {
                    names.insert(ident(&group[i..]));
                    item_start = false;
                }
                match c {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    ',' if depth == 0 => item_start = true,
                    _ => {}
                }
            }
        } else {
            names.insert(ident(rest));
        }
    }
    names.remove("super");
    names.remove("self");
    names
}

/// The imports between the modules of `folder`: module → the siblings it names.
fn sibling_imports(folder: &Path, is_crate_root: bool) -> BTreeMap<String, BTreeSet<String>> {
    let siblings = modules(folder);
    let mut graph = BTreeMap::new();
    for (name, file) in &siblings {
        let code = code(file);
        // In a folder module `super::` is the folder; at a crate root it is the crate, as `crate::` is.
        let mut named = named_after(&code, "super::");
        if is_crate_root {
            named.extend(named_after(&code, "crate::"));
        }
        named.retain(|n| n != name && siblings.contains_key(n));
        graph.insert(name.clone(), named);
    }
    graph
}

/// A loop of the graph, as the names round it, if there is one.
fn find_loop(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|n| n == node) {
            let mut cycle = path[at..].to_vec();
            cycle.push(node.to_string());
            return Some(cycle);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(cycle) = visit(next, graph, path, done) {
                return Some(cycle);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph.keys().find_map(|start| visit(start, graph, &mut Vec::new(), &mut done))
}

#[test]
fn the_loop_finder_sees_a_loop_through_a_group_and_not_a_chain() {
    let code = "use super::{a, b::{C, D}};\nuse super::super::x;\nfn f() { crate::c::g(); }";
    assert_eq!(named_after(code, "super::"), ["a", "b"].map(String::from).into());
    let graph = |edges: &[(&str, &str)]| {
        let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (from, to) in edges {
            g.entry(from.to_string()).or_default().insert(to.to_string());
        }
        g
    };
    assert_eq!(find_loop(&graph(&[("a", "b"), ("b", "c")])), None);
    assert_eq!(find_loop(&graph(&[("a", "b"), ("b", "c"), ("c", "a")])).map(|c| c.len()), Some(4));
}

#[test]
fn no_two_modules_of_a_folder_import_each_other_round_a_loop() {
    let mut loops = Vec::new();
    for folder in source_folders() {
        let is_crate_root = folder.join("lib.rs").is_file() || folder.join("main.rs").is_file();
        if let Some(cycle) = find_loop(&sibling_imports(&folder, is_crate_root)) {
            let folder = folder.strip_prefix(ROOT).unwrap_or(&folder).display().to_string();
            loops.push(format!("{folder}: {}", cycle.join(" → ")));
        }
    }
    assert!(
        loops.is_empty(),
        "imports inside a folder run round a loop (move the shared item to the module it belongs to, so imports \
         run one way):\n{}",
        loops.join("\n")
    );
}
