//! Generates the Rust message types from the `.msg` and `.srv` files under `msgs/` — the one source of truth.
//!
//! **What `roslibrust_codegen` does and what is sweetspot's own.** The crate (a build-dependency, with the two
//! fixes carried in `patches/roslibrust_codegen`, see patches/README.md) finds the packages, parses every
//! `.msg`/`.srv` (types, arrays and bounds, defaults, constants, the `.srv` halves), resolves the dependencies
//! and computes the RIHS01 type hashes (REP-2011) of every message, service, `Name_Request`, `Name_Response` and
//! `Name_Event`; tests/type_hashes.rs and tests/srv_hashes.rs check them against hashes rosidl published. Its
//! parser throws comments and line numbers away, so build.rs keeps one small line scanner of its own (`scan`):
//! the comment blocks (the generated docs, and the `absent:` rule below) and the line of every member (so a
//! malformed `.msg` fails the build with `file:line: reason`); each scanned member is paired with the crate's
//! reading of the same line, and any disagreement is an error. The crate takes a package's name and ROS
//! version from its `package.xml` (the vendored packages under `msgs/ros_interfaces/` carry a minimal one), and
//! its crawl stops at `COLCON_IGNORE`, so each package directory is handed to it as a search path of its own.
//!
//! What build.rs generates is sweetspot's: every `msgs/<pkg>/msg/*.msg` and `msgs/ros_interfaces/<pkg>/msg/*.msg`
//! becomes a struct in `sweetspot::msgs::<pkg>::msg`, with its full `ros2msg` schema text (the message's own text
//! followed by every dependency, depth-first, each once, exactly as rosbag2's `LocalMessageDefinitionSource`
//! concatenates them), its type hash, `Default`, the JSON conversions and the checks of the `.msg` grammar.
//! Every `msgs/<pkg>/srv/*.srv` becomes `<Name>_Request` and `<Name>_Response` in `sweetspot::msgs::<pkg>::srv`
//! as ROS 2 names them (`pkg/srv/Name_Request`, DDS `pkg::srv::dds_::Name_Request_`), with the `<Name>_Event`
//! rosidl adds (what rosbag2 records a call as; `service_msgs/ServiceEventInfo` must be under `msgs/`) and a
//! `<Name>` marker carrying the service's hash.
//! Output is deterministic (sorted inputs, no hash maps, no timestamps).
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

use roslibrust_codegen::{ArrayType, ConstantInfo, FieldInfo};

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    // The interface packages stay at the repository's top level, where colcon finds them.
    let msgs_dir = root.join("../../msgs");
    println!("cargo:rerun-if-changed=../../msgs");
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
// Model: a message as the generator needs it (from roslibrust_codegen's reading plus the comments `scan` keeps)

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
    /// `msg`, or `srv` for the request and response halves of a `.srv` and its event.
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
// Reading: roslibrust_codegen parses and hashes; `scan` keeps the comments and line numbers it drops

/// The package directories under `root`, sorted: `root/<pkg>` and, one level down, the vendored
/// `root/ros_interfaces/<pkg>` (a folder with `msg/` or `srv/` is a package). Each is handed to
/// roslibrust_codegen as a search path of its own: its crawl stops at a `COLCON_IGNORE`, which the folder of
/// vendored packages has (they are not to be built by colcon).
fn package_dirs(root: &Path) -> Result<Vec<PathBuf>, Vec<String>> {
    let read = |dir: &Path| -> Result<Vec<PathBuf>, Vec<String>> {
        let mut v: Vec<PathBuf> = fs::read_dir(dir)
            .map_err(|e| vec![format!("{}: {e}", dir.display())])?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_dir())
            .collect();
        v.sort();
        Ok(v)
    };
    let is_pkg = |dir: &Path| dir.join("msg").is_dir() || dir.join("srv").is_dir();
    let mut pkg_dirs = Vec::new();
    for entry in read(root)? {
        if is_pkg(&entry) {
            pkg_dirs.push(entry);
        } else {
            pkg_dirs.extend(read(&entry)?.into_iter().filter(|sub| is_pkg(sub)));
        }
    }
    let missing: Vec<String> = pkg_dirs
        .iter()
        .filter(|dir| !dir.join("package.xml").is_file())
        .map(|dir| format!("{}: no package.xml (roslibrust_codegen reads a package's name from it)", dir.display()))
        .collect();
    if missing.is_empty() {
        Ok(pkg_dirs)
    } else {
        Err(missing)
    }
}

/// A member line (field or constant) as `scan` sees it: what roslibrust_codegen does not keep.
struct Member {
    line: usize,
    type_tok: String,
    name: String,
    constant: bool,
    doc: Vec<String>,
}

/// The comments and member lines of one `.msg`, or of one half of a `.srv`.
struct Scanned {
    /// The first comment block, when a blank line separates it from the rest: it documents the message.
    doc: Vec<String>,
    members: Vec<Member>,
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

/// The comment blocks and member lines of `lines` (numbered from `first_line`): a member's doc is the comment
/// block right above it plus its trailing comment. Only a line without `<type> <name>` or with a malformed
/// array bracket is refused here (roslibrust_codegen would refuse it without saying where).
fn scan(lines: &[&str], first_line: usize, file: &str) -> Result<Scanned, Vec<String>> {
    let mut errors = Vec::new();
    let mut members = Vec::new();
    let mut pending_doc: Vec<String> = Vec::new();
    let mut file_doc: Vec<String> = Vec::new();
    let mut file_doc_closed = false;
    for (idx, raw) in lines.iter().enumerate() {
        let line = first_line + idx;
        let trimmed = raw.trim();
        if trimmed.is_empty() {
            if members.is_empty() && !file_doc_closed && !pending_doc.is_empty() {
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
        if let Some(t) = trailing.filter(|t| !t.is_empty()) {
            doc.push(t.to_string());
        }
        let Some((type_tok, rest)) = code.split_once(char::is_whitespace) else {
            errors.push(format!("{file}:{line}: expected `<type> <name>`, found `{code}`"));
            continue;
        };
        if type_tok.contains('[') && !type_tok.ends_with(']') {
            errors.push(format!("{file}:{line}: bad array type `{type_tok}`"));
            continue;
        }
        // Constant: NAME=VALUE (the name may be followed by spaces before '=').
        let rest = rest.trim_start();
        let name_end = rest.find(|c: char| c.is_whitespace() || c == '=').unwrap_or(rest.len());
        let constant = rest[name_end..].trim_start().starts_with('=');
        members.push(Member {
            line,
            type_tok: type_tok.to_string(),
            name: rest[..name_end].to_string(),
            constant,
            doc,
        });
    }
    if errors.is_empty() {
        Ok(Scanned { doc: file_doc, members })
    } else {
        Err(errors)
    }
}

/// A `.srv`'s two halves as rosidl_adapter splits it: at the one line that is exactly `---`.
fn split_srv<'a>(text: &'a str, file: &str) -> Result<[(usize, Vec<&'a str>); 2], Vec<String>> {
    let lines: Vec<&str> = text.lines().collect();
    let separators: Vec<usize> = lines.iter().enumerate().filter(|(_, l)| **l == "---").map(|(i, _)| i).collect();
    let [sep] = separators.as_slice() else {
        return Err(vec![format!(
            "{file}: a .srv needs exactly one `---` line between request and response, found {}",
            separators.len()
        )]);
    };
    Ok([(1, lines[..*sep].to_vec()), (sep + 2, lines[sep + 1..].to_vec())])
}

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

/// A field type as roslibrust_codegen parsed it, in the generator's terms; refuses what the generator does not
/// support (`tok` is the type as written, for the message).
fn field_type(t: &roslibrust_codegen::FieldType, tok: &str) -> Result<FieldType, String> {
    let array = match t.array_info {
        ArrayType::NotArray => Array::None,
        ArrayType::Unbounded => Array::Unbounded,
        ArrayType::Bounded(n) => Array::Bounded(n),
        ArrayType::FixedLength(0) => return Err(format!("fixed array of size 0 in `{tok}`")),
        ArrayType::FixedLength(n) if n > 32 => {
            return Err(format!("fixed arrays longer than 32 are not supported by sweetspot's generator (`{tok}`)"))
        }
        ArrayType::FixedLength(n) => Array::Fixed(n),
    };
    let base = match (t.package_name.as_deref(), t.field_type.as_str()) {
        (None, "string") => Base::String { bound: t.string_capacity },
        (None, "wstring") => return Err("wstring is not supported by sweetspot's generator (use string)".into()),
        (None, p) => match PRIMITIVES.iter().find(|q| **q == p) {
            Some(q) => Base::Prim(q),
            None => return Err(format!("bad type `{p}` (not a ROS 2 primitive)")),
        },
        (Some(pkg), name) if is_valid_pkg_name(pkg) && is_valid_type_name(name) => {
            Base::Nested { pkg: pkg.to_string(), name: name.to_string() }
        }
        (Some(_), _) => {
            let base = tok.split('[').next().unwrap_or(tok);
            return Err(format!("bad type `{base}` (expected a primitive, `Type` or `pkg/Type`)"));
        }
    };
    Ok(FieldType { base, array })
}

/// The `absent: VALUE` line of a field's comment block, if any.
fn absent_value(doc: &[String]) -> Option<String> {
    doc.iter().find_map(|l| l.strip_prefix("absent:").map(|v| v.trim().to_string()))
}

/// One message (or `.srv` half) from roslibrust_codegen's fields and constants and `scan`'s comments and lines,
/// checked as the generator needs it. A scanned member and the crate's reading of the same line must agree.
fn build_spec(
    (pkg, name, kind): (&str, String, &'static str),
    file: &str,
    text: &str,
    fields: &[FieldInfo],
    constants: &[ConstantInfo],
    scanned: Scanned,
) -> Result<MsgSpec, Vec<String>> {
    let mut errors = Vec::new();
    let mut out_fields: Vec<Field> = Vec::new();
    let mut out_constants: Vec<Constant> = Vec::new();
    let mut names = BTreeSet::new();
    let (mut fields_left, mut constants_left) = (fields.iter(), constants.iter());
    for m in scanned.members {
        let err = |msg: String| format!("{file}:{}: {msg}", m.line);
        let member = m.name.as_str();
        if m.constant {
            let Some(c) = constants_left.next().filter(|c| c.constant_name == member) else {
                errors.push(err(format!("roslibrust_codegen does not read `{member}` as a constant")));
                break;
            };
            match constant_of(&m, c).and_then(|constant| unique_name(&mut names, member).map(|()| constant)) {
                Ok((ty, value)) => out_constants.push(Constant { name: member.to_string(), ty, value, doc: m.doc }),
                Err(message) => errors.push(err(message)),
            }
            continue;
        }
        let Some(f) = fields_left.next().filter(|f| f.field_name == member) else {
            errors.push(err(format!("roslibrust_codegen does not read `{member}` as a field")));
            break;
        };
        let after_appended = out_fields.last().is_some_and(|f: &Field| f.absent.is_some());
        match checked_field(&m, f, &mut names, after_appended) {
            Ok((ty, default, absent)) => {
                out_fields.push(Field { name: member.to_string(), ty, default, absent, doc: m.doc, line: m.line })
            }
            Err(message) => errors.push(err(message)),
        }
    }
    if errors.is_empty() && (fields_left.next().is_some() || constants_left.next().is_some()) {
        errors.push(format!("{file}: roslibrust_codegen reads members that sweetspot's scan does not see"));
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    Ok(MsgSpec {
        pkg: pkg.to_string(),
        kind,
        name,
        path: PathBuf::from(file),
        text: text.to_string(),
        doc: scanned.doc,
        fields: out_fields,
        constants: out_constants,
    })
}

/// Records `member` in `names`; an error when a member of that name came before.
fn unique_name(names: &mut BTreeSet<String>, member: &str) -> Result<(), String> {
    if names.insert(member.to_string()) {
        Ok(())
    } else {
        Err(format!("duplicate name `{member}`"))
    }
}

/// A scanned field checked against the crate's reading `f`, its name against `names` and, when it follows an
/// appended field (`after_appended`), that it is appended too: its type, default and absent value.
fn checked_field(
    m: &Member,
    f: &FieldInfo,
    names: &mut BTreeSet<String>,
    after_appended: bool,
) -> Result<(FieldType, Option<String>, Option<String>), String> {
    let member = m.name.as_str();
    let (ty, default) = field_of(m, f)?;
    unique_name(names, member)?;
    let absent = absent_of(m, &ty, default.as_deref())?;
    if absent.is_none() && after_appended {
        return Err(format!(
            "field `{member}` follows appended fields: it needs an `absent:` value too (appended fields come last)"
        ));
    }
    Ok((ty, default, absent))
}

/// A scanned constant checked against the crate's reading `c`: its type and value.
fn constant_of(m: &Member, c: &ConstantInfo) -> Result<(FieldType, String), String> {
    let member = m.name.as_str();
    if !is_valid_constant_name(member) {
        return Err(format!("constant name `{member}` must be UPPER_CASE"));
    }
    // roslibrust_codegen keeps a constant's base type only (no array, no string bound).
    let base = match c.constant_type.as_str() {
        "string" => Base::String { bound: None },
        t => match PRIMITIVES.iter().find(|p| **p == t) {
            Some(p) => Base::Prim(p),
            None => Base::Nested { pkg: String::new(), name: t.to_string() },
        },
    };
    if m.type_tok != c.constant_type || matches!(base, Base::Nested { .. }) {
        return Err(format!("constant `{member}` must have a primitive or unbounded string type"));
    }
    let ty = FieldType { base, array: Array::None };
    // roslibrust_codegen keeps a string constant's whole line (ROS 1's rule); a `#` after the closing
    // quote starts a comment, as `scan` read it.
    let value = match ty.base {
        Base::String { .. } => split_comment(&c.constant_value.inner).0.trim(),
        _ => c.constant_value.inner.trim(),
    };
    if value.is_empty() {
        return Err(format!("constant `{member}` has no value"));
    }
    if let Err(m) = rust_literal(&ty, value) {
        return Err(format!("constant `{member}`: {m}"));
    }
    Ok((ty, value.to_string()))
}

/// A scanned field checked against the crate's reading `f`: its type and default.
fn field_of(m: &Member, f: &FieldInfo) -> Result<(FieldType, Option<String>), String> {
    let member = m.name.as_str();
    let ty = field_type(&f.field_type, &m.type_tok)?;
    if !is_valid_field_name(member) {
        return Err(format!("field name `{member}` must be lower_snake_case (letters, digits, single underscores)"));
    }
    if matches!(member, "self" | "super" | "crate" | "Self") {
        return Err(format!("field name `{member}` cannot be used in Rust"));
    }
    let default = f.default.as_ref().map(|d| d.inner.clone());
    if let Some(d) = &default {
        if matches!(ty.base, Base::Nested { .. }) {
            return Err(format!("field `{member}`: nested types cannot have default values"));
        }
        if let Err(m) = rust_literal(&ty, d) {
            return Err(format!("default of `{member}`: {m}"));
        }
    }
    Ok((ty, default))
}

/// The Rust literal of a field's `absent:` value, if its comment block has one; only a numeric scalar without
/// a default may have one.
fn absent_of(m: &Member, ty: &FieldType, default: Option<&str>) -> Result<Option<String>, String> {
    let member = m.name.as_str();
    let Some(v) = absent_value(&m.doc) else { return Ok(None) };
    let numeric = matches!(ty.base, Base::Prim(p) if p != "bool") && ty.array == Array::None;
    if !numeric {
        return Err(format!("field `{member}`: only numeric scalar fields can be appended with an `absent:` value"));
    }
    if default.is_some() {
        return Err(format!("field `{member}` has both a default and an `absent:` value"));
    }
    if v.eq_ignore_ascii_case("nan") && matches!(ty.base, Base::Prim("float32" | "float64")) {
        return Ok(Some(format!("{}::NAN", rust_type(ty))));
    }
    rust_literal(ty, &v).map(Some).map_err(|m| format!("`absent:` value of `{member}`: {m}"))
}

/// Everything read from a tree of packages: the message specs (`.srv` halves and events included, keyed
/// `pkg/Name`), the services by package as `(name, .srv text)`, and the RIHS01 hash of every spec and service.
struct Interfaces {
    specs: BTreeMap<String, MsgSpec>,
    services: BTreeMap<String, Vec<(String, String)>>,
    hashes: BTreeMap<String, String>,
}

/// Reads every package under `root` (see `package_dirs`); file names in errors are shown relative to `shown`.
fn read_interfaces(root: &Path, shown: &Path) -> Result<Interfaces, Vec<String>> {
    let root = root.canonicalize().map_err(|e| vec![format!("{}: {e}", root.display())])?;
    let shown = shown.canonicalize().unwrap_or_else(|_| shown.to_path_buf());
    let show = |p: &Path| p.strip_prefix(&shown).unwrap_or(p).display().to_string();
    let pkg_dirs = package_dirs(&root)?;
    // Scan first: a line roslibrust_codegen cannot parse is reported here with its file and line.
    let mut scanned = scan_packages(&pkg_dirs, &show)?;

    let (messages, services, actions) = roslibrust_codegen::find_and_parse_ros_messages(&pkg_dirs)
        .map_err(|e| vec![format!("roslibrust_codegen: {e}")])?;
    if let Some(action) = actions.first() {
        return Err(vec![format!("{}: sweetspot generates no .action types", show(&action.path))]);
    }
    let mut specs = SpecSet::default();
    let mut by_pkg: BTreeMap<String, Vec<(String, String)>> = BTreeMap::new();
    let unscanned = |path: &Path| format!("{}: not in a package's msg/ or srv/ folder", show(path));
    for m in &messages {
        let Some([s]) = take_scanned(&mut scanned, &m.path) else {
            specs.errors.push(unscanned(&m.path));
            continue;
        };
        let spec =
            build_spec((&m.package, m.name.clone(), "msg"), &show(&m.path), &m.source, &m.fields, &m.constants, s);
        specs.add(spec);
    }
    for s in &services {
        let Some([req, resp]) = take_scanned(&mut scanned, &s.path) else {
            specs.errors.push(unscanned(&s.path));
            continue;
        };
        let file = show(&s.path);
        for (half, scan, suffix) in [(&s.request_type, req, "Request"), (&s.response_type, resp, "Response")] {
            let id = (s.package.as_str(), format!("{}_{suffix}", s.name), "srv");
            specs.add(build_spec(id, &file, &half.source, &half.fields, &half.constants, scan));
        }
        by_pkg.entry(s.package.clone()).or_default().push((s.name.clone(), s.source.clone()));
        specs.add(Ok(event_spec(&s.package, &s.name, &file)));
    }
    for names in by_pkg.values_mut() {
        names.sort();
    }
    let SpecSet { specs, mut errors } = specs;
    // The crate keeps one of two packages of the same name (the other's files are left unread here).
    errors.extend(
        scanned
            .keys()
            .map(|path| format!("{}: not read by roslibrust_codegen (package name taken twice?)", show(path))),
    );
    errors.extend(unknown_nested_types(&specs));
    if !errors.is_empty() {
        return Err(errors);
    }

    let (resolved, resolved_services) = roslibrust_codegen::resolve_dependency_graph(messages, services)
        .map_err(|e| vec![format!("roslibrust_codegen: {e}")])?;
    Ok(Interfaces { specs, services: by_pkg, hashes: interface_hashes(&resolved, &resolved_services) })
}

/// The comments and member lines of every `.msg` and `.srv` (its two halves) in the packages, by path.
fn scan_packages(
    pkg_dirs: &[PathBuf],
    show: &dyn Fn(&Path) -> String,
) -> Result<BTreeMap<PathBuf, Vec<Scanned>>, Vec<String>> {
    let mut errors = Vec::new();
    let mut scanned: BTreeMap<PathBuf, Vec<Scanned>> = BTreeMap::new();
    for dir in pkg_dirs {
        for kind in ["msg", "srv"] {
            let Ok(entries) = fs::read_dir(dir.join(kind)) else { continue };
            let mut files: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
            files.sort();
            for path in files.into_iter().filter(|f| f.extension().and_then(|e| e.to_str()) == Some(kind)) {
                match scan_file(&path, kind, &show(&path)) {
                    Ok(h) => {
                        scanned.insert(path, h);
                    }
                    Err(mut e) => errors.append(&mut e),
                }
            }
        }
    }
    if errors.is_empty() {
        Ok(scanned)
    } else {
        Err(errors)
    }
}

/// One `.msg` (`kind` `msg`) or `.srv` scanned: one `Scanned`, or one per half.
fn scan_file(path: &Path, kind: &str, file: &str) -> Result<Vec<Scanned>, Vec<String>> {
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
    if !is_valid_type_name(name) {
        return Err(vec![format!("{file}: message name `{name}` must be CamelCase")]);
    }
    let text = fs::read_to_string(path).map_err(|e| vec![format!("{file}: {e}")])?;
    if kind == "srv" {
        split_srv(&text, file).and_then(|halves| {
            let [req, resp] = halves.map(|(first, lines)| scan(&lines, first, file));
            Ok(vec![req?, resp?])
        })
    } else {
        let lines: Vec<&str> = text.lines().collect();
        scan(&lines, 1, file).map(|s| vec![s])
    }
}

/// The scan of the file at `path` when it has `N` parts (1 for a `.msg`, 2 for a `.srv`), removed from `scanned`.
fn take_scanned<const N: usize>(scanned: &mut BTreeMap<PathBuf, Vec<Scanned>>, path: &Path) -> Option<[Scanned; N]> {
    scanned.remove(path).and_then(|s| <[Scanned; N]>::try_from(s).ok())
}

/// The specs built so far, keyed `pkg/Name`, and the errors met building them.
#[derive(Default)]
struct SpecSet {
    specs: BTreeMap<String, MsgSpec>,
    errors: Vec<String>,
}

impl SpecSet {
    fn add(&mut self, spec: Result<MsgSpec, Vec<String>>) {
        match spec {
            Ok(spec) => {
                if let Some(prev) = self.specs.insert(spec.key(), spec) {
                    self.errors.push(format!("{}: `{}` defined twice", prev.path.display(), prev.key()));
                }
            }
            Err(mut e) => self.errors.append(&mut e),
        }
    }
}

/// Every nested type must be here (roslibrust_codegen would only give up after many rounds).
fn unknown_nested_types(specs: &BTreeMap<String, MsgSpec>) -> Vec<String> {
    let mut errors = Vec::new();
    for spec in specs.values() {
        for f in &spec.fields {
            if let Base::Nested { pkg, name } = &f.ty.base {
                if !specs.contains_key(&format!("{pkg}/{name}")) {
                    let line = if f.line > 0 { format!(":{}", f.line) } else { String::new() };
                    errors.push(format!(
                        "{}{line}: unknown type `{pkg}/{name}` (add its .msg under msgs/)",
                        spec.path.display()
                    ));
                }
            }
        }
    }
    errors
}

/// The RIHS01 hash of every message, and of every service with its request, response and event.
fn interface_hashes(
    messages: &[roslibrust_codegen::MessageFile],
    services: &[roslibrust_codegen::ServiceFile],
) -> BTreeMap<String, String> {
    let mut hashes = BTreeMap::new();
    for m in messages {
        hashes.insert(m.get_full_name(), m.ros2_hash.to_hash_string());
    }
    for s in services {
        let key = s.get_full_name();
        hashes.insert(format!("{key}_Request"), s.request().ros2_hash.to_hash_string());
        hashes.insert(format!("{key}_Response"), s.response().ros2_hash.to_hash_string());
        hashes.insert(format!("{key}_Event"), s.get_event_ros2_hash().to_hash_string());
        hashes.insert(key, s.get_ros2_hash().to_hash_string());
    }
    hashes
}

/// The RIHS01 hashes of a set of `.msg` texts given as `(package, type name, text)`, keyed `pkg/msg/Type`; every
/// referenced type must be in the set. For checking the hashes against published ones of messages that are not
/// under `msgs/`.
#[allow(dead_code)]
pub fn type_hashes_of(messages: &[(&str, &str, &str)]) -> Result<BTreeMap<String, String>, Vec<String>> {
    interface_hashes_of(messages, &[])
}

/// [`type_hashes_of`] with `.srv` texts too: each service adds `pkg/srv/Name`, `pkg/srv/Name_Request`,
/// `pkg/srv/Name_Response` and `pkg/srv/Name_Event` (which needs `service_msgs/ServiceEventInfo` among the
/// messages, as rosidl's does). The texts are written as packages into a temporary folder for
/// roslibrust_codegen, which reads files only.
#[allow(dead_code)]
pub fn interface_hashes_of(
    messages: &[(&str, &str, &str)],
    services: &[(&str, &str, &str)],
) -> Result<BTreeMap<String, String>, Vec<String>> {
    static COUNT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = COUNT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("sweetspot-interfaces-{}-{n}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    let write = |pkg: &str, kind: &str, name: &str, text: &str| -> std::io::Result<()> {
        let pkg_dir = dir.join(pkg);
        fs::create_dir_all(pkg_dir.join(kind))?;
        fs::write(pkg_dir.join(kind).join(format!("{name}.{kind}")), text)?;
        let xml = format!(
            "<package format=\"3\"><name>{pkg}</name><buildtool_depend>ament_cmake</buildtool_depend></package>\n"
        );
        fs::write(pkg_dir.join("package.xml"), xml)
    };
    let written: std::io::Result<()> = messages
        .iter()
        .map(|(pkg, name, text)| write(pkg, "msg", name, text))
        .chain(services.iter().map(|(pkg, name, text)| write(pkg, "srv", name, text)))
        .collect();
    let read = written.map_err(|e| vec![format!("{}: {e}", dir.display())]).and_then(|()| read_interfaces(&dir, &dir));
    let _ = fs::remove_dir_all(&dir);
    let read = read?;
    let mut out: BTreeMap<String, String> =
        read.specs.values().map(|spec| (spec.full_name(), read.hashes[&spec.key()].clone())).collect();
    for (pkg, names) in &read.services {
        for (name, _) in names {
            out.insert(format!("{pkg}/srv/{name}"), read.hashes[&format!("{pkg}/{name}")].clone());
        }
    }
    Ok(out)
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
        Base::Nested { pkg, name } if name.contains('_') => format!("crate::{pkg}::srv::{name}"),
        Base::Nested { pkg, name } => format!("crate::{pkg}::msg::{name}"),
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
// Services

/// The `pkg/srv/Name_Event` type rosidl adds to a service (and rosbag2 records service calls as):
/// `service_msgs/ServiceEventInfo info` and the request and the response as bounded sequences of at most one.
/// roslibrust_codegen hashes it; sweetspot generates its Rust type and schema text.
fn event_spec(pkg: &str, name: &str, file: &str) -> MsgSpec {
    let field = |field: &str, type_pkg: &str, type_name: String, array: Array| Field {
        name: field.to_string(),
        ty: FieldType { base: Base::Nested { pkg: type_pkg.to_string(), name: type_name }, array },
        default: None,
        absent: None,
        doc: Vec::new(),
        line: 0,
    };
    MsgSpec {
        pkg: pkg.to_string(),
        kind: "srv",
        name: format!("{name}_Event"),
        path: PathBuf::from(file),
        // rosidl's event has no text of its own; this one lets bag readers decode the recorded events.
        text: format!(
            "service_msgs/ServiceEventInfo info\n{pkg}/{name}_Request[<=1] request\n{pkg}/{name}_Response[<=1] response\n"
        ),
        doc: Vec::new(),
        fields: vec![
            field("info", "service_msgs", "ServiceEventInfo".into(), Array::None),
            field("request", pkg, format!("{name}_Request"), Array::Bounded(1)),
            field("response", pkg, format!("{name}_Response"), Array::Bounded(1)),
        ],
        constants: Vec::new(),
    }
}

pub fn generate(msgs_dir: &Path) -> Result<String, Vec<String>> {
    let Interfaces { specs, services, hashes } = read_interfaces(msgs_dir, msgs_dir.parent().unwrap_or(msgs_dir))?;

    let mut out = String::new();
    out.push_str("// @generated by build.rs from msgs/**/*.msg — do not edit.\n\n");
    let mut by_pkg: BTreeMap<&str, Vec<&MsgSpec>> = BTreeMap::new();
    for s in specs.values() {
        by_pkg.entry(&s.pkg).or_default().push(s);
    }
    let mut registry = Vec::new();
    for (pkg, msgs) in &by_pkg {
        let _ = writeln!(out, "#[doc = {:?}]", format!(" Messages of the ROS 2 package `{pkg}`."));
        let _ = writeln!(out, "pub mod {pkg} {{");
        registry.extend(gen_msg_module(&mut out, pkg, msgs, &specs, &hashes));
        if let Some(names) = services.get(*pkg) {
            gen_srv_module(&mut out, pkg, names, &specs, &hashes);
        }
        let _ = writeln!(out, "}}\n");
    }
    out.push_str("/// Every message type generated from `msgs/`, sorted by type name.\n");
    out.push_str("pub static ALL_TYPES: &[crate::TypeInfo] = &[\n");
    for r in &registry {
        let _ = writeln!(out, "    <{r} as crate::RosMessage>::INFO,");
    }
    out.push_str("];\n");
    Ok(out)
}

/// A package's `msg` module; returns the paths of the types it defines.
fn gen_msg_module(
    out: &mut String,
    pkg: &str,
    msgs: &[&MsgSpec],
    specs: &BTreeMap<String, MsgSpec>,
    hashes: &BTreeMap<String, String>,
) -> Vec<String> {
    let mut registry = Vec::new();
    let _ = writeln!(out, "    #[doc = {:?}]", format!(" `{pkg}/msg/*`."));
    let _ = writeln!(out, "    pub mod msg {{");
    for spec in msgs.iter().filter(|s| s.kind == "msg") {
        gen_struct(out, spec, specs, hashes);
        registry.push(format!("crate::{pkg}::msg::{}", spec.name));
    }
    let _ = writeln!(out, "    }}");
    registry
}

/// A package's `srv` module: each service's request, response and event types and its marker.
fn gen_srv_module(
    out: &mut String,
    pkg: &str,
    names: &[(String, String)],
    specs: &BTreeMap<String, MsgSpec>,
    hashes: &BTreeMap<String, String>,
) {
    let _ = writeln!(out, "    #[doc = {:?}]", format!(" `{pkg}/srv/*`: each service's request and response."));
    let _ = writeln!(out, "    pub mod srv {{");
    for (name, text) in names {
        for suffix in ["Request", "Response", "Event"] {
            gen_struct(out, &specs[&format!("{pkg}/{name}_{suffix}")], specs, hashes);
        }
        gen_service(out, pkg, name, text, hashes);
    }
    let _ = writeln!(out, "    }}");
}

fn gen_struct(out: &mut String, spec: &MsgSpec, specs: &BTreeMap<String, MsgSpec>, hashes: &BTreeMap<String, String>) {
    gen_struct_decl(out, spec);
    if spec.fields.iter().any(|f| f.default.is_some() || f.absent.is_some()) {
        gen_default(out, spec);
    }
    if spec.fields.iter().any(|f| f.absent.is_some()) {
        gen_tolerant_deserialize(out, spec);
    }
    if !spec.constants.is_empty() {
        gen_constants(out, spec);
    }
    gen_ros_message(out, spec, specs, hashes);
    gen_from_json(out, spec);
    gen_to_json(out, spec);
    gen_field_table(out, spec);
}

/// The struct with its docs and derives (`Default` and `Deserialize` are written by hand when fields have
/// defaults or absent values).
fn gen_struct_decl(out: &mut String, spec: &MsgSpec) {
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
}

/// `Default` from the declared defaults and absent values.
fn gen_default(out: &mut String, spec: &MsgSpec) {
    let (i2, i3) = ("        ", "            ");
    let name = &spec.name;
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

/// The `.msg`'s constants as associated constants.
fn gen_constants(out: &mut String, spec: &MsgSpec) {
    let (i2, i3) = ("        ", "            ");
    let name = &spec.name;
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

/// `RosMessage`: names, schema text and type hash.
fn gen_ros_message(
    out: &mut String,
    spec: &MsgSpec,
    specs: &BTreeMap<String, MsgSpec>,
    hashes: &BTreeMap<String, String>,
) {
    let (i2, i3) = ("        ", "            ");
    let (name, pkg, full_name) = (&spec.name, &spec.pkg, spec.full_name());
    let key = spec.key();
    let schema = full_text(&key, specs);
    let _ = writeln!(out, "{i2}impl crate::RosMessage for {name} {{");
    let kind = spec.kind;
    let _ = writeln!(out, "{i3}const TYPE_NAME: &'static str = {full_name:?};");
    let _ = writeln!(out, "{i3}const DDS_TYPE_NAME: &'static str = {:?};", format!("{pkg}::{kind}::dds_::{name}_"));
    let _ = writeln!(out, "{i3}const SCHEMA_TEXT: &'static str = {schema:?};");
    let _ = writeln!(out, "{i3}const MSG_TEXT: &'static str = {:?};", spec.text);
    let _ = writeln!(out, "{i3}const TYPE_HASH: &'static str = {:?};", hashes[&key]);
    let _ = writeln!(out, "{i2}}}\n");
    let _ = writeln!(out, "{i2}#[cfg(feature = \"ros2\")]\n{i2}impl ::ros2_client::Message for {name} {{}}\n");
}

/// JSON input is tolerant: missing fields keep their defaults, null = NaN, numbers as strings.
fn gen_from_json(out: &mut String, spec: &MsgSpec) {
    let (i2, i3) = ("        ", "            ");
    let (name, full_name) = (&spec.name, spec.full_name());
    let _ = writeln!(out, "{i2}impl crate::json::FromJson for {name} {{");
    let _ = writeln!(
        out,
        "{i3}fn from_json(value: &::serde_json::Value, path: &str) -> ::core::result::Result<Self, crate::MsgError> {{"
    );
    let _ = writeln!(out, "{i3}    let object = crate::json::expect_object(value, path)?;");
    let known: Vec<String> = spec.fields.iter().map(|f| format!("{:?}", f.name)).collect();
    let _ =
        writeln!(out, "{i3}    crate::json::reject_unknown(object, &[{}], path, {:?})?;", known.join(", "), full_name);
    let _ = writeln!(
        out,
        "{i3}    #[allow(unused_mut)]\n{i3}    let mut msg = <Self as ::core::default::Default>::default();"
    );
    for f in &spec.fields {
        let _ = writeln!(
            out,
            "{i3}    if let Some(v) = object.get({:?}) {{ msg.{} = crate::json::FromJson::from_json(v, &crate::json::join(path, {:?}))?; }}",
            f.name,
            ident(&f.name),
            f.name
        );
        if let Array::Bounded(n) = f.ty.array {
            let _ = writeln!(
                out,
                "{i3}    crate::json::check_len(msg.{}.len(), {n}, &crate::json::join(path, {:?}))?;",
                ident(&f.name),
                f.name
            );
        }
        if let (Base::String { bound: Some(n) }, Array::None) = (&f.ty.base, &f.ty.array) {
            let _ = writeln!(
                out,
                "{i3}    crate::json::check_len(msg.{}.len(), {n}, &crate::json::join(path, {:?}))?;",
                ident(&f.name),
                f.name
            );
        }
    }
    let _ = writeln!(out, "{i3}    Ok(msg)\n{i3}}}\n{i2}}}\n");
}

fn gen_to_json(out: &mut String, spec: &MsgSpec) {
    let (i2, i3) = ("        ", "            ");
    let name = &spec.name;
    let _ = writeln!(out, "{i2}impl crate::json::ToJson for {name} {{");
    let _ = writeln!(out, "{i3}fn to_json(&self) -> ::serde_json::Value {{");
    let _ = writeln!(out, "{i3}    #[allow(unused_mut)]\n{i3}    let mut object = ::serde_json::Map::new();");
    for f in &spec.fields {
        let _ = writeln!(
            out,
            "{i3}    object.insert({:?}.to_string(), crate::json::ToJson::to_json(&self.{}));",
            f.name,
            ident(&f.name)
        );
    }
    let _ = writeln!(out, "{i3}    ::serde_json::Value::Object(object)\n{i3}}}\n{i2}}}\n");
}

/// The message's [`FieldTable`]: each scalar field and each `float64` sequence, in `.msg` order.
fn gen_field_table(out: &mut String, spec: &MsgSpec) {
    let (i2, i3) = ("        ", "            ");
    let entries: Vec<String> = spec
        .fields
        .iter()
        .filter_map(|f| {
            let field = format!("self.{}", ident(&f.name));
            let value = match (&f.ty.base, &f.ty.array) {
                (Base::Prim("float64"), Array::None) => format!("Float({field})"),
                (Base::Prim("float32"), Array::None) => format!("Float(f64::from({field}))"),
                (Base::Prim("bool"), Array::None) => format!("Bool({field})"),
                // Already the table's width: a conversion would be clippy's useless_conversion.
                (Base::Prim("int64"), Array::None) => format!("Int({field})"),
                (Base::Prim("uint64"), Array::None) => format!("Uint({field})"),
                (Base::Prim(p), Array::None) if p.starts_with("int") => format!("Int(i64::from({field}))"),
                (Base::Prim(_), Array::None) => format!("Uint(u64::from({field}))"),
                (Base::String { .. }, Array::None) => format!("Text(&{field})"),
                (Base::Prim("float64"), Array::Unbounded | Array::Bounded(_)) => format!("Floats(&{field})"),
                _ => return None,
            };
            Some(format!("({:?}, crate::FieldValue::{value})", f.name))
        })
        .collect();
    // `i64::from` of an `i64` field keeps the generator's one rule per type.
    let _ = writeln!(out, "{i2}#[allow(clippy::useless_conversion)]");
    let _ = writeln!(out, "{i2}impl crate::FieldTable for {} {{", spec.name);
    let _ = writeln!(out, "{i3}fn field_table(&self) -> ::std::vec::Vec<(&'static str, crate::FieldValue<'_>)> {{");
    let _ = writeln!(out, "{i3}    ::std::vec::Vec::from([{}])", entries.join(", "));
    let _ = writeln!(out, "{i3}}}\n{i2}}}\n");
}

/// A service's marker type: its names, `.srv` text and RIHS01 hash (the hash ROS 2 advertises on both of its
/// DDS topics), with its request and response types.
fn gen_service(out: &mut String, pkg: &str, name: &str, text: &str, hashes: &BTreeMap<String, String>) {
    let (i2, i3) = ("        ", "            ");
    doc_attrs(out, i2, &[format!("The service `{pkg}/srv/{name}`, generated from `{pkg}/srv/{name}.srv`.")]);
    let _ = writeln!(out, "{i2}#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]");
    let _ = writeln!(out, "{i2}pub struct {name};\n");
    let _ = writeln!(out, "{i2}impl crate::RosService for {name} {{");
    let _ = writeln!(out, "{i3}type Request = {name}_Request;");
    let _ = writeln!(out, "{i3}type Response = {name}_Response;");
    let _ = writeln!(out, "{i3}type Event = {name}_Event;");
    let _ = writeln!(out, "{i3}const TYPE_NAME: &'static str = {:?};", format!("{pkg}/srv/{name}"));
    let _ = writeln!(out, "{i3}const SRV_TEXT: &'static str = {text:?};");
    let _ = writeln!(out, "{i3}const TYPE_HASH: &'static str = {:?};", hashes[&format!("{pkg}/{name}")]);
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
