//! Generates the Rust message types from the `.msg` files under `msgs/` — the one source of truth.
//!
//! Every `msgs/<pkg>/msg/*.msg` and `msgs/ros_interfaces/<pkg>/msg/*.msg` becomes a struct in
//! `sweetspot::msgs::<pkg>::msg`, with its full `ros2msg` schema text (the message's own text followed by every
//! dependency, depth-first, each once, exactly as rosbag2's `LocalMessageDefinitionSource` concatenates them)
//! and its RIHS01 type hash (REP-2011; see `type_hash`). The hand-written hash follows
//! rosidl_generator_type_description line by line: the crates that compute RIHS01 need their own type-description
//! structs filled from a parsed `.msg` anyway, and checking it against rosidl's published hashes
//! (tests/type_hashes.rs) is what makes it trustworthy either way.
//! Every `msgs/<pkg>/srv/*.srv` is split at its `---` line into `<Name>_Request` and `<Name>_Response`, generated
//! in `sweetspot::msgs::<pkg>::srv` as ROS 2 names them (`pkg/srv/Name_Request`, DDS
//! `pkg::srv::dds_::Name_Request_`), with the `<Name>_Event` rosidl adds (what rosbag2 records a call as) and a
//! `<Name>` marker carrying the service's RIHS01 hash (the service described with its request, response and
//! event types; `service_msgs/ServiceEventInfo` must be under `msgs/`).
//! Output is deterministic (sorted inputs, no hash maps, no timestamps). A malformed `.msg` fails the build with
//! `file:line: reason`.
//!
//! **Appended fields.** A field whose comment block has a line `absent: VALUE` (`0`, `NaN`, any literal of its
//! type) was appended to the message after data had been recorded without it. Such fields must be the
//! message's last ones and numeric scalars (no bool, string, array or nested type, so that the only way to
//! fail reading one is that the data has ended). The generated `Deserialize` then accepts data that ends at
//! any field boundary inside that tail and gives every missing field its absent value; `Default` gives the
//! absent value too (a field nobody set reads as "head-on" or "not measured", as the `.msg` says). rosidl
//! ignores comments, so the `.msg` stays a plain ROS interface.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let msgs_dir = root.join("msgs");
    println!("cargo:rerun-if-changed=msgs");
    println!("cargo:rerun-if-changed=build.rs");

    match generate(&msgs_dir) {
        Ok(code) => {
            let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("msgs.rs");
            // Only rewrite when changed so dependents are not rebuilt needlessly.
            let unchanged = fs::read_to_string(&out).map(|old| old == code).unwrap_or(false);
            if !unchanged {
                if let Err(err) = fs::write(&out, code) {
                    panic!("cannot write {}: {err}", out.display());
                }
            }
        }
        Err(errors) => {
            for e in &errors {
                println!("cargo:warning={e}");
                eprintln!("error: {e}");
            }
            panic!("{} error(s) in .msg files:\n{}", errors.len(), errors.join("\n"));
        }
    }
}

// ---------------------------------------------------------------------------------------------------------------
// Model

#[derive(Debug, Clone, PartialEq)]
enum Base {
    Prim(&'static str), // ROS primitive name: bool, byte, char, int8 … float64
    String { bound: Option<usize> },
    Nested { pkg: String, name: String },
}

#[derive(Debug, Clone, PartialEq)]
enum Array {
    None,
    Unbounded,
    Bounded(usize),
    Fixed(usize),
}

#[derive(Debug, Clone)]
struct FieldType {
    base: Base,
    array: Array,
}

#[derive(Debug, Clone)]
struct Field {
    name: String,
    ty: FieldType,
    default: Option<String>,
    /// Value of an appended field when the data ends before it (`absent:` line of its comment block).
    absent: Option<String>,
    doc: Vec<String>,
    line: usize,
}

#[derive(Debug, Clone)]
struct Constant {
    name: String,
    ty: FieldType,
    value: String,
    doc: Vec<String>,
}

#[derive(Debug, Clone)]
struct MsgSpec {
    pkg: String,
    /// `msg`, or `srv` for the request and response halves of a `.srv` (and the types only hashed).
    kind: &'static str,
    name: String,
    path: PathBuf,
    text: String,
    doc: Vec<String>,
    fields: Vec<Field>,
    constants: Vec<Constant>,
}

impl MsgSpec {
    fn key(&self) -> String {
        format!("{}/{}", self.pkg, self.name)
    }

    /// The ROS 2 type name, `pkg/msg/Type` or `pkg/srv/Type_Request`.
    fn full_name(&self) -> String {
        format!("{}/{}/{}", self.pkg, self.kind, self.name)
    }
}

const PRIMITIVES: &[&str] = &[
    "bool", "byte", "char", "int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64", "float32",
    "float64",
];

fn rust_prim(p: &str) -> &'static str {
    match p {
        "bool" => "bool",
        "byte" | "char" | "uint8" => "u8",
        "int8" => "i8",
        "int16" => "i16",
        "uint16" => "u16",
        "int32" => "i32",
        "uint32" => "u32",
        "int64" => "i64",
        "uint64" => "u64",
        "float32" => "f32",
        "float64" => "f64",
        _ => unreachable!("not a primitive: {p}"),
    }
}

// ---------------------------------------------------------------------------------------------------------------
// Discovery

fn discover(msgs_dir: &Path) -> Result<Vec<(String, PathBuf)>, Vec<String>> {
    let mut found = Vec::new();
    let mut pkg_dirs = Vec::new();
    let read = |dir: &Path| -> Result<Vec<PathBuf>, String> {
        let mut v: Vec<PathBuf> = fs::read_dir(dir)
            .map_err(|e| format!("{}: {e}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        v.sort();
        Ok(v)
    };
    for entry in read(msgs_dir).map_err(|e| vec![e])? {
        if !entry.is_dir() {
            continue;
        }
        if entry.join("msg").is_dir() || entry.join("srv").is_dir() {
            pkg_dirs.push(entry.clone());
        } else {
            // A folder of vendored packages (msgs/ros_interfaces/<pkg>/msg).
            for sub in read(&entry).map_err(|e| vec![e])? {
                if sub.join("msg").is_dir() || sub.join("srv").is_dir() {
                    pkg_dirs.push(sub);
                }
            }
        }
    }
    for pkg_dir in pkg_dirs {
        let pkg = pkg_dir.file_name().and_then(|s| s.to_str()).unwrap_or_default().to_string();
        for kind in ["msg", "srv"] {
            if !pkg_dir.join(kind).is_dir() {
                continue;
            }
            for f in read(&pkg_dir.join(kind)).map_err(|e| vec![e])? {
                if f.extension().and_then(|e| e.to_str()) == Some(kind) {
                    found.push((pkg.clone(), f));
                }
            }
        }
    }
    Ok(found)
}

// ---------------------------------------------------------------------------------------------------------------
// Parsing

fn is_valid_field_name(s: &str) -> bool {
    let b = s.as_bytes();
    !b.is_empty()
        && b[0].is_ascii_lowercase()
        && b.iter().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == b'_')
        && !s.contains("__")
        && !s.ends_with('_')
}

fn is_valid_constant_name(s: &str) -> bool {
    let b = s.as_bytes();
    !b.is_empty()
        && b[0].is_ascii_uppercase()
        && b.iter().all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || *c == b'_')
        && !s.contains("__")
        && !s.ends_with('_')
}

fn is_valid_type_name(s: &str) -> bool {
    let b = s.as_bytes();
    !b.is_empty() && b[0].is_ascii_uppercase() && b.iter().all(|c| c.is_ascii_alphanumeric())
}

fn is_valid_pkg_name(s: &str) -> bool {
    let b = s.as_bytes();
    !b.is_empty()
        && b[0].is_ascii_lowercase()
        && b.iter().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == b'_')
}

fn parse_type(tok: &str, pkg: &str) -> Result<FieldType, String> {
    let (base_str, array) = match tok.find('[') {
        Some(i) => {
            if !tok.ends_with(']') {
                return Err(format!("bad array type `{tok}`"));
            }
            let inner = &tok[i + 1..tok.len() - 1];
            let array = if inner.is_empty() {
                Array::Unbounded
            } else if let Some(n) = inner.strip_prefix("<=") {
                Array::Bounded(n.parse().map_err(|_| format!("bad array bound in `{tok}`"))?)
            } else {
                Array::Fixed(inner.parse().map_err(|_| format!("bad array size in `{tok}`"))?)
            };
            (&tok[..i], array)
        }
        None => (tok, Array::None),
    };
    let base = if let Some(p) = PRIMITIVES.iter().find(|p| **p == base_str) {
        Base::Prim(p)
    } else if base_str == "string" {
        Base::String { bound: None }
    } else if let Some(n) = base_str.strip_prefix("string<=") {
        Base::String { bound: Some(n.parse().map_err(|_| format!("bad string bound in `{tok}`"))?) }
    } else if base_str == "wstring" || base_str.starts_with("wstring<=") {
        return Err("wstring is not supported by sweetspot's generator (use string)".into());
    } else {
        let parts: Vec<&str> = base_str.split('/').collect();
        let (p, n) = match parts.as_slice() {
            [n] => (pkg, *n),
            [p, n] => (*p, *n),
            [p, "msg", n] => (*p, *n),
            _ => return Err(format!("bad type `{base_str}`")),
        };
        if !is_valid_pkg_name(p) || !is_valid_type_name(n) {
            return Err(format!("bad type `{base_str}` (expected a primitive, `Type` or `pkg/Type`)"));
        }
        Base::Nested { pkg: p.to_string(), name: n.to_string() }
    };
    if let Array::Fixed(n) = array {
        if n == 0 {
            return Err(format!("fixed array of size 0 in `{tok}`"));
        }
        if n > 32 {
            return Err(format!("fixed arrays longer than 32 are not supported by sweetspot's generator (`{tok}`)"));
        }
    }
    Ok(FieldType { base, array })
}

/// Splits off a trailing `# comment` that is not inside a quoted string.
fn split_comment(s: &str) -> (&str, Option<&str>) {
    let mut quote: Option<char> = None;
    let mut escaped = false;
    for (i, c) in s.char_indices() {
        if escaped {
            escaped = false;
            continue;
        }
        match (quote, c) {
            (Some(_), '\\') => escaped = true,
            (Some(q), c) if c == q => quote = None,
            (None, '"') | (None, '\'') => quote = Some(c),
            (None, '#') => return (&s[..i], Some(s[i + 1..].trim())),
            _ => {}
        }
    }
    (s, None)
}

/// The `absent: VALUE` line of a field's comment block, if any.
fn absent_value(doc: &[String]) -> Option<String> {
    doc.iter().find_map(|l| l.strip_prefix("absent:").map(|v| v.trim().to_string()))
}

fn parse_msg(pkg: &str, name: &str, path: &Path, text: &str) -> Result<MsgSpec, Vec<String>> {
    let mut errors = Vec::new();
    let mut fields: Vec<Field> = Vec::new();
    let mut constants: Vec<Constant> = Vec::new();
    let mut pending_doc: Vec<String> = Vec::new();
    let mut file_doc: Vec<String> = Vec::new();
    let mut seen_member = false;
    let mut file_doc_closed = false;
    let mut names = BTreeSet::new();
    let file = path.display().to_string();

    for (idx, raw) in text.lines().enumerate() {
        let line_no = idx + 1;
        let trimmed = raw.trim();
        if trimmed.is_empty() {
            if !seen_member && !file_doc_closed && !pending_doc.is_empty() {
                // The first comment block of a file, separated by a blank line, documents the message.
                file_doc.append(&mut pending_doc);
                file_doc_closed = true;
            } else if !pending_doc.is_empty() {
                pending_doc.push(String::new());
            }
            continue;
        }
        if let Some(c) = trimmed.strip_prefix('#') {
            pending_doc.push(c.trim_start_matches('#').trim().to_string());
            continue;
        }
        let (code, trailing) = split_comment(trimmed);
        let code = code.trim();
        let mut doc: Vec<String> = std::mem::take(&mut pending_doc);
        while doc.last().is_some_and(|l| l.is_empty()) {
            doc.pop();
        }
        if let Some(t) = trailing {
            if !t.is_empty() {
                doc.push(t.to_string());
            }
        }
        seen_member = true;
        let err = |m: String| format!("{file}:{line_no}: {m}");

        let (type_tok, rest) = match code.split_once(char::is_whitespace) {
            Some((t, r)) => (t, r.trim_start()),
            None => {
                errors.push(err(format!("expected `<type> <name>`, found `{code}`")));
                continue;
            }
        };
        let ty = match parse_type(type_tok, pkg) {
            Ok(t) => t,
            Err(m) => {
                errors.push(err(m));
                continue;
            }
        };
        // Constant: NAME=VALUE (the name may be followed by spaces before '=').
        let name_end = rest.find(|c: char| c.is_whitespace() || c == '=').unwrap_or(rest.len());
        let member = &rest[..name_end];
        let after = rest[name_end..].trim_start();
        if let Some(value) = after.strip_prefix('=') {
            // For strings the value is the rest of the raw line (a '#' inside quotes belongs to it).
            let value = value.trim();
            if !is_valid_constant_name(member) {
                errors.push(err(format!("constant name `{member}` must be UPPER_CASE")));
                continue;
            }
            if ty.array != Array::None || matches!(ty.base, Base::Nested { .. }) {
                errors.push(err(format!("constant `{member}` must have a primitive or string type")));
                continue;
            }
            if value.is_empty() {
                errors.push(err(format!("constant `{member}` has no value")));
                continue;
            }
            if let Err(m) = rust_literal(&ty, value) {
                errors.push(err(format!("constant `{member}`: {m}")));
                continue;
            }
            if !names.insert(member.to_string()) {
                errors.push(err(format!("duplicate name `{member}`")));
                continue;
            }
            constants.push(Constant { name: member.to_string(), ty, value: value.to_string(), doc });
            continue;
        }
        if !is_valid_field_name(member) {
            errors.push(err(format!(
                "field name `{member}` must be lower_snake_case (letters, digits, single underscores)"
            )));
            continue;
        }
        if matches!(member, "self" | "super" | "crate" | "Self") {
            errors.push(err(format!("field name `{member}` cannot be used in Rust")));
            continue;
        }
        let default = if after.is_empty() { None } else { Some(after.to_string()) };
        if let Some(d) = &default {
            if matches!(ty.base, Base::Nested { .. }) {
                errors.push(err(format!("field `{member}`: nested types cannot have default values")));
                continue;
            }
            if let Err(m) = rust_literal(&ty, d) {
                errors.push(err(format!("default of `{member}`: {m}")));
                continue;
            }
        }
        if !names.insert(member.to_string()) {
            errors.push(err(format!("duplicate name `{member}`")));
            continue;
        }
        let absent = match absent_value(&doc) {
            None => None,
            Some(v) => {
                let numeric = matches!(ty.base, Base::Prim(p) if p != "bool") && ty.array == Array::None;
                if !numeric {
                    errors.push(err(format!(
                        "field `{member}`: only numeric scalar fields can be appended with an `absent:` value"
                    )));
                    continue;
                }
                if default.is_some() {
                    errors.push(err(format!("field `{member}` has both a default and an `absent:` value")));
                    continue;
                }
                let literal = if v.eq_ignore_ascii_case("nan") && matches!(ty.base, Base::Prim("float32" | "float64")) {
                    format!("{}::NAN", rust_type(&ty))
                } else {
                    match rust_literal(&ty, &v) {
                        Ok(l) => l,
                        Err(m) => {
                            errors.push(err(format!("`absent:` value of `{member}`: {m}")));
                            continue;
                        }
                    }
                };
                Some(literal)
            }
        };
        if absent.is_none() && fields.last().is_some_and(|f: &Field| f.absent.is_some()) {
            errors.push(err(format!(
                "field `{member}` follows appended fields: it needs an `absent:` value too (appended fields come last)"
            )));
            continue;
        }
        fields.push(Field { name: member.to_string(), ty, default, absent, doc, line: line_no });
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(MsgSpec {
        pkg: pkg.to_string(),
        kind: "msg",
        name: name.to_string(),
        path: path.to_path_buf(),
        text: text.to_string(),
        doc: file_doc,
        fields,
        constants,
    })
}

// ---------------------------------------------------------------------------------------------------------------
// Literals

fn parse_string_literal(s: &str) -> Result<String, String> {
    let s = s.trim();
    let (q, body) = match s.chars().next() {
        Some(q @ ('"' | '\'')) => {
            if s.len() < 2 || !s.ends_with(q) {
                return Err(format!("unterminated string literal {s}"));
            }
            (Some(q), &s[1..s.len() - 1])
        }
        _ => (None, s),
    };
    if q.is_none() {
        return Ok(body.to_string());
    }
    let mut out = String::new();
    let mut chars = body.chars();
    while let Some(c) = chars.next() {
        if c == '\\' {
            match chars.next() {
                Some('n') => out.push('\n'),
                Some('t') => out.push('\t'),
                Some('\\') => out.push('\\'),
                Some('\'') => out.push('\''),
                Some('"') => out.push('"'),
                Some(o) => {
                    out.push('\\');
                    out.push(o)
                }
                None => out.push('\\'),
            }
        } else {
            out.push(c);
        }
    }
    Ok(out)
}

fn scalar_literal(base: &Base, s: &str) -> Result<String, String> {
    let s = s.trim();
    match base {
        Base::Prim("bool") => match s.to_ascii_lowercase().as_str() {
            "true" | "1" => Ok("true".into()),
            "false" | "0" => Ok("false".into()),
            _ => Err(format!("`{s}` is not a bool")),
        },
        Base::Prim(p @ ("float32" | "float64")) => {
            let v: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
            if !v.is_finite() {
                return Err(format!("`{s}` is not finite"));
            }
            Ok(format!("{v:?}_{}", rust_prim(p)))
        }
        Base::Prim(p) => {
            let r = rust_prim(p);
            let ok = match r {
                "u8" => s.parse::<u8>().is_ok(),
                "i8" => s.parse::<i8>().is_ok(),
                "i16" => s.parse::<i16>().is_ok(),
                "u16" => s.parse::<u16>().is_ok(),
                "i32" => s.parse::<i32>().is_ok(),
                "u32" => s.parse::<u32>().is_ok(),
                "i64" => s.parse::<i64>().is_ok(),
                "u64" => s.parse::<u64>().is_ok(),
                _ => false,
            };
            if !ok {
                return Err(format!("`{s}` is not a valid {p}"));
            }
            Ok(format!("{s}_{r}"))
        }
        Base::String { bound } => {
            let v = parse_string_literal(s)?;
            if let Some(b) = bound {
                if v.len() > *b {
                    return Err(format!("string longer than its bound {b}"));
                }
            }
            Ok(format!("{v:?}"))
        }
        Base::Nested { .. } => Err("nested types have no literals".into()),
    }
}

/// Splits `[a, b, "c,d"]` into elements, respecting quotes.
fn split_array_literal(s: &str) -> Result<Vec<String>, String> {
    let s = s.trim();
    let inner = s
        .strip_prefix('[')
        .and_then(|s| s.strip_suffix(']'))
        .ok_or_else(|| format!("array default must be written [a, b, ...], found `{s}`"))?;
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quote: Option<char> = None;
    for c in inner.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => {
                quote = None;
                cur.push(c)
            }
            (None, '"') | (None, '\'') => {
                quote = Some(c);
                cur.push(c)
            }
            (None, ',') => out.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    if !cur.trim().is_empty() || !out.is_empty() {
        out.push(cur);
    }
    Ok(out.into_iter().map(|e| e.trim().to_string()).collect())
}

/// The Rust expression of a constant or default value.
fn rust_literal(ty: &FieldType, s: &str) -> Result<String, String> {
    match ty.array {
        Array::None => scalar_literal(&ty.base, s),
        _ => {
            let elems = split_array_literal(s)?;
            let lits = elems.iter().map(|e| scalar_literal(&ty.base, e)).collect::<Result<Vec<_>, _>>()?;
            let lits: Vec<String> = if matches!(ty.base, Base::String { .. }) {
                lits.into_iter().map(|l| format!("{l}.to_string()")).collect()
            } else {
                lits
            };
            match ty.array {
                Array::Fixed(n) if elems.len() != n => Err(format!("expected {n} elements, found {}", elems.len())),
                Array::Fixed(_) => Ok(format!("[{}]", lits.join(", "))),
                Array::Bounded(n) if elems.len() > n => Err(format!("more than {n} elements")),
                _ => Ok(format!("vec![{}]", lits.join(", "))),
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------------------------
// Code generation

const RUST_KEYWORDS: &[&str] = &[
    "as", "break", "const", "continue", "else", "enum", "extern", "false", "fn", "for", "if", "impl", "in", "let",
    "loop", "match", "mod", "move", "mut", "pub", "ref", "return", "static", "struct", "trait", "true", "type",
    "unsafe", "use", "where", "while", "async", "await", "dyn", "abstract", "become", "box", "do", "final", "macro",
    "override", "priv", "typeof", "unsized", "virtual", "yield", "try", "gen",
];

fn ident(name: &str) -> String {
    if RUST_KEYWORDS.contains(&name) {
        format!("r#{name}")
    } else {
        name.to_string()
    }
}

fn rust_base(base: &Base) -> String {
    match base {
        Base::Prim(p) => rust_prim(p).to_string(),
        Base::String { .. } => "::std::string::String".to_string(),
        // A `.msg` type name has no `_` (is_valid_type_name): one with `_` is a service's `Name_Request` etc.
        Base::Nested { pkg, name } if name.contains('_') => format!("crate::msgs::{pkg}::srv::{name}"),
        Base::Nested { pkg, name } => format!("crate::msgs::{pkg}::msg::{name}"),
    }
}

fn rust_type(ty: &FieldType) -> String {
    let b = rust_base(&ty.base);
    match ty.array {
        Array::None => b,
        Array::Unbounded | Array::Bounded(_) => format!("::std::vec::Vec<{b}>"),
        Array::Fixed(n) => format!("[{b}; {n}]"),
    }
}

fn ros_type_string(ty: &FieldType) -> String {
    let b = match &ty.base {
        Base::Prim(p) => p.to_string(),
        Base::String { bound: None } => "string".into(),
        Base::String { bound: Some(n) } => format!("string<={n}"),
        Base::Nested { pkg, name } => format!("{pkg}/{name}"),
    };
    match ty.array {
        Array::None => b,
        Array::Unbounded => format!("{b}[]"),
        Array::Bounded(n) => format!("{b}[<={n}]"),
        Array::Fixed(n) => format!("{b}[{n}]"),
    }
}

fn doc_attrs(out: &mut String, indent: &str, doc: &[String]) {
    for l in doc {
        let _ = writeln!(out, "{indent}#[doc = {:?}]", format!(" {l}"));
    }
}

/// rosbag2's dependency set of a message: every non-primitive field type as `pkg/Type`, sorted (a `std::set`).
fn deps_of(spec: &MsgSpec) -> BTreeSet<String> {
    spec.fields
        .iter()
        .filter_map(|f| match &f.ty.base {
            Base::Nested { pkg, name } => Some(format!("{pkg}/{name}")),
            _ => None,
        })
        .collect()
}

/// The full `ros2msg` text, as rosbag2's `LocalMessageDefinitionSource::get_full_text` builds it.
fn full_text(root: &str, specs: &BTreeMap<String, MsgSpec>) -> String {
    fn rec(key: &str, specs: &BTreeMap<String, MsgSpec>, seen: &mut BTreeSet<String>, depth: u32) -> String {
        let spec = &specs[key];
        let mut result = spec.text.clone();
        if depth == 0 {
            return result;
        }
        for dep in deps_of(spec) {
            if seen.insert(dep.clone()) {
                result.push('\n');
                result.push_str(&"=".repeat(80));
                result.push('\n');
                result.push_str("MSG: ");
                result.push_str(&dep);
                result.push('\n');
                result.push_str(&rec(&dep, specs, seen, depth - 1));
            }
        }
        result
    }
    let mut seen = BTreeSet::new();
    rec(root, specs, &mut seen, 50)
}

// ---------------------------------------------------------------------------------------------------------------
// Type hashes (REP-2011, RIHS01)

/// rosidl's `type_description_interfaces/msg/FieldType` id of a field type: the value type's id plus 48 for a
/// fixed array, 96 for a bounded sequence, 144 for an unbounded one (rosidl_generator_type_description's
/// `FIELD_TYPE_NAME_TO_ID`). A `.msg` `char` is an IDL `uint8` and `byte` an `octet`, as rosidl_adapter maps them.
fn field_type_id(ty: &FieldType) -> u32 {
    let value = match &ty.base {
        Base::Nested { .. } => 1,
        Base::Prim(p) => match *p {
            "int8" => 2,
            "uint8" | "char" => 3,
            "int16" => 4,
            "uint16" => 5,
            "int32" => 6,
            "uint32" => 7,
            "int64" => 8,
            "uint64" => 9,
            "float32" => 10,
            "float64" => 11,
            "bool" => 15,
            "byte" => 16,
            _ => unreachable!("not a primitive: {p}"),
        },
        Base::String { bound: None } => 17,
        Base::String { bound: Some(_) } => 21,
    };
    value
        + match ty.array {
            Array::None => 0,
            Array::Fixed(_) => 48,
            Array::Bounded(_) => 96,
            Array::Unbounded => 144,
        }
}

/// A JSON string as Python's `json.dumps(ensure_ascii=True)` writes it.
fn json_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_ascii() && !c.is_ascii_control() => out.push(c),
            c => {
                let mut units = [0u16; 2];
                for unit in c.encode_utf16(&mut units) {
                    let _ = write!(out, "\\u{unit:04x}");
                }
            }
        }
    }
    out.push('"');
    out
}

/// One `IndividualTypeDescription` without default values, in rosidl's key order and with Python's
/// `separators=(', ', ': ')`. An empty message has the one `uint8` member rosidl_adapter gives it in the IDL.
fn individual_type_description_json(spec: &MsgSpec, specs: &BTreeMap<String, MsgSpec>) -> String {
    let placeholder = Field {
        name: "structure_needs_at_least_one_member".into(),
        ty: FieldType { base: Base::Prim("uint8"), array: Array::None },
        default: None,
        absent: None,
        doc: Vec::new(),
        line: 0,
    };
    let fields: Vec<&Field> = if spec.fields.is_empty() { vec![&placeholder] } else { spec.fields.iter().collect() };
    let fields: Vec<String> = fields
        .iter()
        .map(|f| {
            let capacity = match f.ty.array {
                Array::Fixed(n) | Array::Bounded(n) => n,
                Array::None | Array::Unbounded => 0,
            };
            let string_capacity = match f.ty.base {
                Base::String { bound: Some(n) } => n,
                _ => 0,
            };
            let nested = match &f.ty.base {
                Base::Nested { pkg, name } => specs
                    .get(&format!("{pkg}/{name}"))
                    .map(MsgSpec::full_name)
                    .unwrap_or_else(|| format!("{pkg}/msg/{name}")),
                _ => String::new(),
            };
            format!(
                "{{\"name\": {}, \"type\": {{\"type_id\": {}, \"capacity\": {capacity}, \"string_capacity\": \
                 {string_capacity}, \"nested_type_name\": {}}}}}",
                json_string(&f.name),
                field_type_id(&f.ty),
                json_string(&nested)
            )
        })
        .collect();
    format!("{{\"type_name\": {}, \"fields\": [{}]}}", json_string(&spec.full_name()), fields.join(", "))
}

/// The RIHS01 hash of a message (REP-2011): SHA-256 of the JSON of its `TypeDescription` — its own description
/// then every type it references directly or indirectly, sorted by name — as
/// `rosidl_generator_type_description.calculate_type_hash` writes it (default values and constants left out,
/// comments never part of it), as `RIHS01_` and 64 lower-case hex digits.
fn type_hash(key: &str, specs: &BTreeMap<String, MsgSpec>) -> String {
    use sha2::Digest as _;
    let mut referenced = BTreeSet::new();
    let mut queue: Vec<String> = deps_of(&specs[key]).into_iter().collect();
    while let Some(dep) = queue.pop() {
        if referenced.insert(dep.clone()) {
            queue.extend(deps_of(&specs[&dep]));
        }
    }
    // Sorted by full type name (`pkg/msg/Type`, `pkg/srv/Type_Request`), as rosidl sorts them.
    let mut referenced: Vec<(String, &MsgSpec)> =
        referenced.iter().map(|k| (specs[k].full_name(), &specs[k])).collect();
    referenced.sort_by(|a, b| a.0.cmp(&b.0));
    let referenced: Vec<String> =
        referenced.iter().map(|(_, spec)| individual_type_description_json(spec, specs)).collect();
    let json = format!(
        "{{\"type_description\": {}, \"referenced_type_descriptions\": [{}]}}",
        individual_type_description_json(&specs[key], specs),
        referenced.join(", ")
    );
    let digest = sha2::Sha256::digest(json.as_bytes());
    let mut out = String::from("RIHS01_");
    for byte in digest.iter() {
        let _ = write!(out, "{byte:02x}");
    }
    out
}

/// The RIHS01 hashes of a set of `.msg` texts given as `(package, type name, text)`, keyed `pkg/msg/Type`; every
/// referenced type must be in the set. For checking the algorithm against published hashes of messages that
/// are not under `msgs/`.
#[allow(dead_code)]
pub fn type_hashes_of(messages: &[(&str, &str, &str)]) -> Result<BTreeMap<String, String>, Vec<String>> {
    interface_hashes_of(messages, &[])
}

/// [`type_hashes_of`] with `.srv` texts too: each service adds `pkg/srv/Name`, `pkg/srv/Name_Request`,
/// `pkg/srv/Name_Response` and `pkg/srv/Name_Event` (which needs `service_msgs/ServiceEventInfo` among the
/// messages, as rosidl's does).
#[allow(dead_code)]
pub fn interface_hashes_of(
    messages: &[(&str, &str, &str)],
    services: &[(&str, &str, &str)],
) -> Result<BTreeMap<String, String>, Vec<String>> {
    let mut specs = BTreeMap::new();
    for (pkg, name, text) in messages {
        let spec = parse_msg(pkg, name, Path::new(&format!("{pkg}/msg/{name}.msg")), text)?;
        specs.insert(spec.key(), spec);
    }
    for (pkg, name, text) in services {
        for spec in parse_srv(pkg, name, Path::new(&format!("{pkg}/srv/{name}.srv")), text)? {
            specs.insert(spec.key(), spec);
        }
    }
    for (pkg, name, _) in services {
        for spec in service_hash_only_specs(pkg, name) {
            specs.insert(spec.key(), spec);
        }
    }
    for spec in specs.values() {
        for dep in deps_of(spec) {
            if !specs.contains_key(&dep) {
                return Err(vec![format!("{}: unknown type `{dep}`", spec.key())]);
            }
        }
    }
    Ok(specs.keys().map(|k| (specs[k].full_name(), type_hash(k, &specs))).collect())
}

// ---------------------------------------------------------------------------------------------------------------
// Services

/// A `.srv` split as rosidl_adapter splits it (at the one line that is exactly `---`) into its request and
/// response messages, `pkg/srv/Name_Request` and `pkg/srv/Name_Response`; each half is parsed as a `.msg`.
fn parse_srv(pkg: &str, name: &str, path: &Path, text: &str) -> Result<[MsgSpec; 2], Vec<String>> {
    let lines: Vec<&str> = text.lines().collect();
    let separators: Vec<usize> = lines.iter().enumerate().filter(|(_, l)| **l == "---").map(|(i, _)| i).collect();
    let [sep] = separators.as_slice() else {
        return Err(vec![format!(
            "{}: a .srv needs exactly one `---` line between request and response, found {}",
            path.display(),
            separators.len()
        )]);
    };
    let half = |from: usize, to: usize, suffix: &str| -> Result<MsgSpec, Vec<String>> {
        let own: String = lines[from..to].iter().map(|l| format!("{l}\n")).collect();
        // Blank lines in front keep the error messages' line numbers those of the .srv file.
        let padded = format!("{}{own}", "\n".repeat(from));
        let mut spec = parse_msg(pkg, &format!("{name}_{suffix}"), path, &padded)?;
        spec.kind = "srv";
        spec.text = own;
        Ok(spec)
    };
    Ok([half(0, *sep, "Request")?, half(sep + 1, lines.len(), "Response")?])
}

/// The two types rosidl adds to a service (sweetspot generates Rust for the event only, which rosbag2 records
/// service calls as): `pkg/srv/Name_Event` (`service_msgs/ServiceEventInfo info`, the request and the response as
/// bounded sequences of at most one) and the service `pkg/srv/Name` itself (`request_message`,
/// `response_message`, `event_message`), as rosidl_generator_type_description describes them.
fn service_hash_only_specs(pkg: &str, name: &str) -> [MsgSpec; 2] {
    let field = |field: &str, type_pkg: &str, type_name: String, array: Array| Field {
        name: field.to_string(),
        ty: FieldType { base: Base::Nested { pkg: type_pkg.to_string(), name: type_name }, array },
        default: None,
        absent: None,
        doc: Vec::new(),
        line: 0,
    };
    let spec = |type_name: String, fields: Vec<Field>| MsgSpec {
        pkg: pkg.to_string(),
        kind: "srv",
        name: type_name,
        path: PathBuf::from(format!("{pkg}/srv/{name}.srv")),
        text: String::new(),
        doc: Vec::new(),
        fields,
        constants: Vec::new(),
    };
    let mut event = spec(
        format!("{name}_Event"),
        vec![
            field("info", "service_msgs", "ServiceEventInfo".into(), Array::None),
            field("request", pkg, format!("{name}_Request"), Array::Bounded(1)),
            field("response", pkg, format!("{name}_Response"), Array::Bounded(1)),
        ],
    );
    // rosidl's event has no text of its own; this one lets bag readers decode the recorded events.
    event.text = format!(
        "service_msgs/ServiceEventInfo info\n{pkg}/{name}_Request[<=1] request\n{pkg}/{name}_Response[<=1] response\n"
    );
    let service = spec(
        name.to_string(),
        vec![
            field("request_message", pkg, format!("{name}_Request"), Array::None),
            field("response_message", pkg, format!("{name}_Response"), Array::None),
            field("event_message", pkg, format!("{name}_Event"), Array::None),
        ],
    );
    [event, service]
}

pub fn generate(msgs_dir: &Path) -> Result<String, Vec<String>> {
    let files = discover(msgs_dir)?;
    let mut errors = Vec::new();
    let mut specs: BTreeMap<String, MsgSpec> = BTreeMap::new();
    // Services by package: (name, .srv text).
    let mut services: BTreeMap<String, Vec<(String, String)>> = BTreeMap::new();
    for (pkg, path) in files {
        let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default().to_string();
        if !is_valid_pkg_name(&pkg) {
            errors.push(format!("{}: package name `{pkg}` is not a valid ROS package name", path.display()));
            continue;
        }
        if !is_valid_type_name(&name) {
            errors.push(format!("{}: message name `{name}` must be CamelCase", path.display()));
            continue;
        }
        let text = match fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) => {
                errors.push(format!("{}: {e}", path.display()));
                continue;
            }
        };
        let parsed = if path.extension().and_then(|e| e.to_str()) == Some("srv") {
            services.entry(pkg.clone()).or_default().push((name.clone(), text.clone()));
            parse_srv(&pkg, &name, &path, &text).map(Vec::from)
        } else {
            parse_msg(&pkg, &name, &path, &text).map(|spec| vec![spec])
        };
        match parsed {
            Ok(parsed) => {
                for spec in parsed {
                    if let Some(prev) = specs.insert(spec.key(), spec) {
                        errors.push(format!("{}: `{}` defined twice", prev.path.display(), prev.key()));
                    }
                }
            }
            Err(mut e) => errors.append(&mut e),
        }
    }
    if !services.is_empty() && !specs.contains_key("service_msgs/ServiceEventInfo") {
        errors.push("a .srv's type hash needs service_msgs/msg/ServiceEventInfo.msg under msgs/".into());
    }
    // Every nested type must exist; the type graph must be acyclic.
    for spec in specs.values() {
        for f in &spec.fields {
            if let Base::Nested { pkg, name } = &f.ty.base {
                if !specs.contains_key(&format!("{pkg}/{name}")) {
                    let hint = if name == "Header" { "; ROS 2 needs `std_msgs/Header`" } else { "" };
                    errors.push(format!(
                        "{}:{}: unknown type `{pkg}/{name}` (add its .msg under msgs/{hint})",
                        spec.path.display(),
                        f.line
                    ));
                }
            }
        }
    }
    if errors.is_empty() {
        for key in specs.keys() {
            let mut stack = vec![(key.clone(), 0u32)];
            while let Some((k, d)) = stack.pop() {
                if d > 40 {
                    errors.push(format!("{}: recursive message definition", specs[key].path.display()));
                    break;
                }
                for dep in deps_of(&specs[&k]) {
                    stack.push((dep, d + 1));
                }
            }
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }

    let mut out = String::new();
    out.push_str("// @generated by build.rs from msgs/**/*.msg — do not edit.\n\n");
    let mut by_pkg: BTreeMap<&str, Vec<&MsgSpec>> = BTreeMap::new();
    for s in specs.values() {
        by_pkg.entry(&s.pkg).or_default().push(s);
    }
    // The hashes see the types rosidl adds to every service (its Event and the service itself) too.
    let mut hashed = specs.clone();
    for (pkg, names) in &services {
        for (name, _) in names {
            for spec in service_hash_only_specs(pkg, name) {
                hashed.insert(spec.key(), spec);
            }
        }
    }
    let mut registry = Vec::new();
    for (pkg, msgs) in &by_pkg {
        let _ = writeln!(out, "#[doc = {:?}]", format!(" Messages of the ROS 2 package `{pkg}`."));
        let _ = writeln!(out, "pub mod {pkg} {{");
        let _ = writeln!(out, "    #[doc = {:?}]", format!(" `{pkg}/msg/*`."));
        let _ = writeln!(out, "    pub mod msg {{");
        for spec in msgs.iter().filter(|s| s.kind == "msg") {
            gen_struct(&mut out, spec, &hashed);
            registry.push(format!("crate::msgs::{pkg}::msg::{}", spec.name));
        }
        out.push_str("    }\n");
        if let Some(names) = services.get(*pkg) {
            let _ = writeln!(out, "    #[doc = {:?}]", format!(" `{pkg}/srv/*`: each service's request and response."));
            let _ = writeln!(out, "    pub mod srv {{");
            for (name, text) in names {
                for suffix in ["Request", "Response", "Event"] {
                    gen_struct(&mut out, &hashed[&format!("{pkg}/{name}_{suffix}")], &hashed);
                }
                gen_service(&mut out, pkg, name, text, &hashed);
            }
            out.push_str("    }\n");
        }
        out.push_str("}\n\n");
    }
    out.push_str("/// Every message type generated from `msgs/`, sorted by type name.\n");
    out.push_str("pub static ALL_TYPES: &[crate::msgs::TypeInfo] = &[\n");
    for r in &registry {
        let _ = writeln!(out, "    <{r} as crate::msgs::RosMessage>::INFO,");
    }
    out.push_str("];\n");
    Ok(out)
}

fn gen_struct(out: &mut String, spec: &MsgSpec, specs: &BTreeMap<String, MsgSpec>) {
    let i2 = "        ";
    let i3 = "            ";
    let name = &spec.name;
    let pkg = &spec.pkg;
    let full_name = spec.full_name();
    let source = match spec.kind {
        "srv" => format!("{pkg}/srv/{}.srv", name.rsplit_once('_').map_or(name.as_str(), |(service, _)| service)),
        _ => format!("{pkg}/msg/{name}.msg"),
    };
    let mut doc = vec![format!("`{full_name}`, generated from `{source}`.")];
    if !spec.doc.is_empty() {
        doc.push(String::new());
        doc.extend(spec.doc.iter().cloned());
    }
    doc_attrs(out, i2, &doc);
    let has_defaults = spec.fields.iter().any(|f| f.default.is_some() || f.absent.is_some());
    let has_tail = spec.fields.iter().any(|f| f.absent.is_some());
    let derive_default = if has_defaults { "" } else { " Default," };
    let derive_deserialize = if has_tail { "" } else { " ::serde::Deserialize" };
    let _ = writeln!(
        out,
        "{i2}#[derive(Debug, Clone, PartialEq,{derive_default} ::serde::Serialize,{derive_deserialize})]"
    );
    if name.contains('_') {
        // ROS 2's names of a service's request and response types (`Name_Request`).
        let _ = writeln!(out, "{i2}#[allow(non_camel_case_types)]");
    }
    let _ = writeln!(out, "{i2}pub struct {name} {{");
    if spec.fields.is_empty() {
        // rosidl adds this member to empty messages so that they have a wire representation.
        let _ = writeln!(out, "{i3}#[doc = \" Placeholder member rosidl adds to empty messages.\"]");
        let _ = writeln!(out, "{i3}pub structure_needs_at_least_one_member: u8,");
    }
    for f in &spec.fields {
        let mut d = f.doc.clone();
        d.push(format!("ROS type: `{}`.", ros_type_string(&f.ty)));
        doc_attrs(out, i3, &d);
        let _ = writeln!(out, "{i3}pub {}: {},", ident(&f.name), rust_type(&f.ty));
    }
    let _ = writeln!(out, "{i2}}}\n");

    if has_defaults {
        // A declared default may equal the type's own (rcl_interfaces' `bool read_only false`).
        let _ = writeln!(out, "{i2}#[allow(clippy::derivable_impls)]");
        let _ = writeln!(out, "{i2}impl ::core::default::Default for {name} {{");
        let _ = writeln!(out, "{i3}fn default() -> Self {{");
        let _ = writeln!(out, "{i3}    Self {{");
        for f in &spec.fields {
            let v = match (&f.default, &f.absent) {
                (_, Some(absent)) => absent.clone(),
                (Some(d), None) => {
                    let lit = rust_literal(&f.ty, d).unwrap_or_default();
                    if matches!(f.ty.base, Base::String { .. }) && f.ty.array == Array::None {
                        format!("{lit}.to_string()")
                    } else {
                        lit
                    }
                }
                (None, None) => "::core::default::Default::default()".into(),
            };
            let _ = writeln!(out, "{i3}        {}: {v},", ident(&f.name));
        }
        let _ = writeln!(out, "{i3}    }}\n{i3}}}\n{i2}}}\n");
    }

    if has_tail {
        gen_tolerant_deserialize(out, spec);
    }

    if !spec.constants.is_empty() {
        let _ = writeln!(out, "{i2}impl {name} {{");
        for c in &spec.constants {
            let mut d = c.doc.clone();
            d.push(format!("ROS constant `{} {}={}`.", ros_type_string(&c.ty), c.name, c.value));
            doc_attrs(out, i3, &d);
            let ty = match c.ty.base {
                Base::String { .. } => "&'static str".to_string(),
                _ => rust_type(&c.ty),
            };
            let lit = rust_literal(&c.ty, &c.value).unwrap_or_default();
            let _ = writeln!(out, "{i3}pub const {}: {ty} = {lit};", c.name);
        }
        let _ = writeln!(out, "{i2}}}\n");
    }

    let key = spec.key();
    let schema = full_text(&key, specs);
    let _ = writeln!(out, "{i2}impl crate::msgs::RosMessage for {name} {{");
    let kind = spec.kind;
    let _ = writeln!(out, "{i3}const TYPE_NAME: &'static str = {full_name:?};");
    let _ = writeln!(out, "{i3}const DDS_TYPE_NAME: &'static str = {:?};", format!("{pkg}::{kind}::dds_::{name}_"));
    let _ = writeln!(out, "{i3}const SCHEMA_TEXT: &'static str = {schema:?};");
    let _ = writeln!(out, "{i3}const MSG_TEXT: &'static str = {:?};", spec.text);
    let _ = writeln!(out, "{i3}const TYPE_HASH: &'static str = {:?};", type_hash(&key, specs));
    let _ = writeln!(out, "{i2}}}\n");
    let _ = writeln!(out, "{i2}impl ::ros2_client::Message for {name} {{}}\n");

    // JSON conversion (tolerant input: missing fields keep their defaults, null = NaN, numbers as strings).
    let _ = writeln!(out, "{i2}impl crate::msgs::json::FromJson for {name} {{");
    let _ = writeln!(
        out,
        "{i3}fn from_json(value: &::serde_json::Value, path: &str) -> ::core::result::Result<Self, crate::msgs::MsgError> {{"
    );
    let _ = writeln!(out, "{i3}    let object = crate::msgs::json::expect_object(value, path)?;");
    let known: Vec<String> = spec.fields.iter().map(|f| format!("{:?}", f.name)).collect();
    let _ = writeln!(
        out,
        "{i3}    crate::msgs::json::reject_unknown(object, &[{}], path, {:?})?;",
        known.join(", "),
        full_name
    );
    let _ = writeln!(
        out,
        "{i3}    #[allow(unused_mut)]\n{i3}    let mut msg = <Self as ::core::default::Default>::default();"
    );
    for f in &spec.fields {
        let _ = writeln!(
            out,
            "{i3}    if let Some(v) = object.get({:?}) {{ msg.{} = crate::msgs::json::FromJson::from_json(v, &crate::msgs::json::join(path, {:?}))?; }}",
            f.name,
            ident(&f.name),
            f.name
        );
        if let Array::Bounded(n) = f.ty.array {
            let _ = writeln!(
                out,
                "{i3}    crate::msgs::json::check_len(msg.{}.len(), {n}, &crate::msgs::json::join(path, {:?}))?;",
                ident(&f.name),
                f.name
            );
        }
        if let (Base::String { bound: Some(n) }, Array::None) = (&f.ty.base, &f.ty.array) {
            let _ = writeln!(
                out,
                "{i3}    crate::msgs::json::check_len(msg.{}.len(), {n}, &crate::msgs::json::join(path, {:?}))?;",
                ident(&f.name),
                f.name
            );
        }
    }
    let _ = writeln!(out, "{i3}    Ok(msg)\n{i3}}}\n{i2}}}\n");

    let _ = writeln!(out, "{i2}impl crate::msgs::json::ToJson for {name} {{");
    let _ = writeln!(out, "{i3}fn to_json(&self) -> ::serde_json::Value {{");
    let _ = writeln!(out, "{i3}    #[allow(unused_mut)]\n{i3}    let mut object = ::serde_json::Map::new();");
    for f in &spec.fields {
        let _ = writeln!(
            out,
            "{i3}    object.insert({:?}.to_string(), crate::msgs::json::ToJson::to_json(&self.{}));",
            f.name,
            ident(&f.name)
        );
    }
    let _ = writeln!(out, "{i3}    ::serde_json::Value::Object(object)\n{i3}}}\n{i2}}}\n");
}

/// A service's marker type: its names, `.srv` text and RIHS01 hash (the hash ROS 2 advertises on both of its
/// DDS topics), with its request and response types.
fn gen_service(out: &mut String, pkg: &str, name: &str, text: &str, hashed: &BTreeMap<String, MsgSpec>) {
    let (i2, i3) = ("        ", "            ");
    doc_attrs(out, i2, &[format!("The service `{pkg}/srv/{name}`, generated from `{pkg}/srv/{name}.srv`.")]);
    let _ = writeln!(out, "{i2}#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]");
    let _ = writeln!(out, "{i2}pub struct {name};\n");
    let _ = writeln!(out, "{i2}impl crate::msgs::RosService for {name} {{");
    let _ = writeln!(out, "{i3}type Request = {name}_Request;");
    let _ = writeln!(out, "{i3}type Response = {name}_Response;");
    let _ = writeln!(out, "{i3}type Event = {name}_Event;");
    let _ = writeln!(out, "{i3}const TYPE_NAME: &'static str = {:?};", format!("{pkg}/srv/{name}"));
    let _ = writeln!(out, "{i3}const SRV_TEXT: &'static str = {text:?};");
    let _ = writeln!(out, "{i3}const TYPE_HASH: &'static str = {:?};", type_hash(&format!("{pkg}/{name}"), hashed));
    let _ = writeln!(out, "{i2}}}\n");
}

/// `Deserialize` of a message with appended fields: a sequence (CDR) may end before any appended field, the
/// rest keeping their absent values (see the module docs); a map (self-describing formats) may leave any
/// field out.
fn gen_tolerant_deserialize(out: &mut String, spec: &MsgSpec) {
    let i2 = "        ";
    let i3 = "            ";
    let name = &spec.name;
    let names: Vec<String> = spec.fields.iter().map(|f| format!("{:?}", f.name)).collect();
    let _ = writeln!(out, "{i2}impl<'de> ::serde::Deserialize<'de> for {name} {{");
    let _ = writeln!(out, "{i3}#[allow(clippy::field_reassign_with_default)]");
    let _ = writeln!(
        out,
        "{i3}fn deserialize<D: ::serde::Deserializer<'de>>(deserializer: D) -> ::core::result::Result<Self, D::Error> {{"
    );
    let _ = writeln!(out, "{i3}    const FIELDS: &[&str] = &[{}];", names.join(", "));
    let _ = writeln!(out, "{i3}    struct Visitor;");
    let _ = writeln!(out, "{i3}    impl<'de> ::serde::de::Visitor<'de> for Visitor {{");
    let _ = writeln!(out, "{i3}        type Value = {name};");
    let _ = writeln!(
        out,
        "{i3}        fn expecting(&self, f: &mut ::core::fmt::Formatter) -> ::core::fmt::Result {{ f.write_str({:?}) }}",
        spec.full_name()
    );
    let _ = writeln!(
        out,
        "{i3}        fn visit_seq<A: ::serde::de::SeqAccess<'de>>(self, mut seq: A) -> ::core::result::Result<{name}, A::Error> {{"
    );
    let _ = writeln!(out, "{i3}            let mut msg = <{name} as ::core::default::Default>::default();");
    for (k, f) in spec.fields.iter().enumerate() {
        let field = ident(&f.name);
        if f.absent.is_none() {
            let _ = writeln!(
                out,
                "{i3}            msg.{field} = seq.next_element()?.ok_or_else(|| ::serde::de::Error::invalid_length({k}, &self))?;"
            );
        } else {
            // Reading a numeric scalar fails only when the data has ended: the data predates this field.
            let _ = writeln!(
                out,
                "{i3}            match seq.next_element() {{ Ok(Some(v)) => msg.{field} = v, Ok(None) | Err(_) => return Ok(msg) }}"
            );
        }
    }
    let _ = writeln!(out, "{i3}            Ok(msg)\n{i3}        }}");
    let _ = writeln!(
        out,
        "{i3}        fn visit_map<A: ::serde::de::MapAccess<'de>>(self, mut map: A) -> ::core::result::Result<{name}, A::Error> {{"
    );
    let _ = writeln!(out, "{i3}            let mut msg = <{name} as ::core::default::Default>::default();");
    let _ = writeln!(out, "{i3}            while let Some(key) = map.next_key::<::std::string::String>()? {{");
    let _ = writeln!(out, "{i3}                match key.as_str() {{");
    for f in &spec.fields {
        let _ = writeln!(out, "{i3}                    {:?} => msg.{} = map.next_value()?,", f.name, ident(&f.name));
    }
    let _ = writeln!(out, "{i3}                    _ => {{ let _: ::serde::de::IgnoredAny = map.next_value()?; }}");
    let _ = writeln!(out, "{i3}                }}\n{i3}            }}\n{i3}            Ok(msg)\n{i3}        }}");
    let _ = writeln!(out, "{i3}    }}");
    let _ = writeln!(out, "{i3}    deserializer.deserialize_struct({name:?}, FIELDS, Visitor)");
    let _ = writeln!(out, "{i3}}}\n{i2}}}\n");
}
