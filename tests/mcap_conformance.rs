//! Every valid MCAP file reads: the official MCAP conformance corpus, checked file by file.
//!
//! foxglove/mcap's tests/conformance holds 416 variants of six inputs (NoData, OneSchemalessMessage,
//! OneMessage, OneAttachment, OneMetadata, TenMessages) × the writer's feature switches (chunks, message
//! indexes, chunk indexes, statistics, repeated schemas and channels, attachment and metadata indexes,
//! summary offsets, padded records). Its `.mcap` files are Git LFS objects, so the corpus is generated here
//! (tests/mcap_conformance/generate.mjs, with the official TypeScript writer `@mcap/core` from npm, pinned in
//! that directory's package-lock.json and installed by scripts/test), and every file must be byte for byte the
//! one the MCAP repository commits (tests/mcap_conformance/sha256.txt: the LFS object ids at a pinned commit).
//!
//! The truth about each file comes from `@mcap/core`'s own streamed reader (CRCs checked): messages, counts
//! per topic, message encodings, log-time range, attachments and metadata records. `sweetspot bag info --json`
//! must exit 0, call no file damaged and report exactly that; `sweetspot bag export` must refuse each file
//! because it holds no swing topic (saying which topics it holds), never because it is damaged.

mod support;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::Command;

use serde_json::Value;

fn corpus_dir() -> PathBuf {
    support::repo().join("tests/mcap_conformance")
}

/// The pinned SHA-256 of every variant, by name.
fn pinned_hashes() -> BTreeMap<String, String> {
    let text = std::fs::read_to_string(corpus_dir().join("sha256.txt")).expect("tests/mcap_conformance/sha256.txt");
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let (hash, name) = l.split_once("  ").expect("`HASH  NAME` lines");
            (name.to_string(), hash.to_string())
        })
        .collect()
}

/// Generates the corpus into `dir` and returns the reader's manifest (one object per variant).
fn generate(dir: &std::path::Path) -> Vec<Value> {
    let modules = corpus_dir().join("node_modules/@mcap/core");
    assert!(
        modules.is_dir(),
        "{} missing: run `bash scripts/test` (it runs npm ci in tests/mcap_conformance)",
        modules.display()
    );
    let out = Command::new("node")
        .arg(corpus_dir().join("generate.mjs"))
        .arg(dir)
        .output()
        .expect("starting node (Node.js); scripts/test installs it");
    assert!(out.status.success(), "generate.mjs failed:\n{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice::<Vec<Value>>(&out.stdout).expect("generate.mjs prints a JSON array")
}

/// What `bag info --json` says that differs from the official reader, if anything.
fn info_disagreement(variant: &Value) -> Option<String> {
    let path = variant["path"].as_str().expect("path");
    let run = support::cli::sweetspot(&["bag", "info", path, "--json"]);
    if !run.status_ok || run.stderr.contains("panicked") {
        return Some(format!("exit {:?}: {}", run.code, run.stderr.trim()));
    }
    let info: Value = match serde_json::from_str(&run.stdout) {
        Ok(v) => v,
        Err(e) => return Some(format!("stdout is not JSON ({e})")),
    };
    let mut problems = Vec::new();
    if info["damaged"] != Value::Bool(false) {
        problems.push(format!("called damaged: {}", info["files"][0]["damage"]));
    }
    for (key, theirs) in [("messages", "messages"), ("attachments", "attachments"), ("metadata", "metadata")] {
        if info[key] != variant[theirs] {
            problems.push(format!("{key} {} where the reader finds {}", info[key], variant[theirs]));
        }
    }
    let topics = info["topics"].as_array().cloned().unwrap_or_default();
    let counts: BTreeMap<String, u64> = topics
        .iter()
        .map(|t| (t["name"].as_str().unwrap_or_default().to_string(), t["count"].as_u64().unwrap_or(u64::MAX)))
        .collect();
    let expected: BTreeMap<String, u64> = variant["topics"]
        .as_object()
        .map(|m| m.iter().map(|(k, v)| (k.clone(), v.as_u64().unwrap_or(0))).collect())
        .unwrap_or_default();
    if counts != expected {
        problems.push(format!("topic counts {counts:?} where the reader finds {expected:?}"));
    }
    let encodings: BTreeMap<String, String> = topics
        .iter()
        .map(|t| {
            let name = t["name"].as_str().unwrap_or_default().to_string();
            (name, t["serialization_format"].as_str().unwrap_or_default().to_string())
        })
        .collect();
    let expected: BTreeMap<String, String> = variant["encodings"]
        .as_object()
        .map(|m| m.iter().map(|(k, v)| (k.clone(), v.as_str().unwrap_or_default().to_string())).collect())
        .unwrap_or_default();
    if encodings != expected {
        problems.push(format!("serialization formats {encodings:?} where the channels say {expected:?}"));
    }
    if variant["messages"].as_u64() != Some(0) {
        for (key, theirs) in [("start_ns", "start_ns"), ("end_ns", "end_ns")] {
            if info[key] != variant[theirs] {
                problems.push(format!("{key} {} where the reader finds {}", info[key], variant[theirs]));
            }
        }
    }
    (!problems.is_empty()).then(|| problems.join("; "))
}

/// What is wrong with `bag export`'s answer, if anything: it must refuse for want of a swing topic.
fn export_disagreement(variant: &Value) -> Option<String> {
    let path = variant["path"].as_str().expect("path");
    let run = support::cli::sweetspot(&["bag", "export", path]);
    let names: Vec<&String> = variant["topics"].as_object().map(|m| m.keys().collect()).unwrap_or_default();
    let says_why = run.stderr.contains("no swing topics") && names.iter().all(|n| run.stderr.contains(n.as_str()));
    if run.status_ok || run.code.is_none() || run.stderr.contains("panicked") || !says_why || !run.stdout.is_empty() {
        return Some(format!("export: exit {:?}, stdout {:?}, stderr {}", run.code, run.stdout, run.stderr.trim()));
    }
    None
}

#[test]
fn every_variant_of_the_mcap_conformance_corpus_reads_as_the_official_reader_reads_it() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = generate(dir.path());
    let pinned = pinned_hashes();
    assert_eq!(pinned.len(), 416, "sha256.txt lists the 416 variants");
    let generated: BTreeMap<String, String> = manifest
        .iter()
        .map(|v| (v["name"].as_str().unwrap().to_string(), v["sha256"].as_str().unwrap().to_string()))
        .collect();
    assert_eq!(
        generated.keys().collect::<Vec<_>>(),
        pinned.keys().collect::<Vec<_>>(),
        "the generated variants are the MCAP repository's"
    );
    let differing: Vec<&String> = pinned.keys().filter(|name| generated[*name] != pinned[*name]).collect();
    assert!(differing.is_empty(), "not byte for byte the committed corpus: {differing:?}");

    let mut failures = Vec::new();
    for variant in &manifest {
        let name = variant["name"].as_str().unwrap();
        if let Some(problem) = info_disagreement(variant) {
            failures.push(format!("{name}: bag info: {problem}"));
        }
        if let Some(problem) = export_disagreement(variant) {
            failures.push(format!("{name}: {problem}"));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} checks failed:\n{}",
        failures.len(),
        2 * manifest.len(),
        failures.join("\n")
    );
}
