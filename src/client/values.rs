//! Messages as a user writes them: YAML (flow or block, as `ros2 topic pub` takes them) or JSON on the command
//! line, and files of JSON lines, YAML documents or CSV rows, each read as the JSON the message decoder takes.

use std::io::{BufRead, Read as _};
use std::path::Path;

use anyhow::{anyhow, bail, Context as _};
use serde_json::{Map, Value};

/// The input messages as JSON values, with a description of where each came from (for errors): `message`
/// (one value or a list), then `file`'s; a message with every default when neither is given.
pub fn read_inputs(message: Option<&str>, file: Option<&Path>) -> anyhow::Result<Vec<(String, Value)>> {
    let mut out = Vec::new();
    if let Some(text) = message {
        match parse_values(text)? {
            Value::Array(items) => {
                for (i, item) in items.into_iter().enumerate() {
                    out.push((format!("message[{i}]"), item));
                }
            }
            other => out.push(("message".into(), other)),
        }
    }
    if let Some(path) = file {
        let is_csv = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        let is_yaml = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"));
        if is_csv {
            out.extend(read_csv(path)?);
        } else if is_yaml {
            out.extend(read_yaml_file(path)?);
        } else {
            out.extend(read_json_lines(path)?);
        }
    }
    if message.is_none() && file.is_none() {
        // Like `ros2 topic pub` with no values: a message with every default.
        out.push(("defaults".into(), Value::Object(Map::new())));
    }
    Ok(out)
}

/// A message given on the command line (`pub`, `call`) or a case file: JSON, else YAML (flow `{a: 1, b: x}` or block `a: 1`), as
/// `ros2 topic pub` takes it. JSON goes first so that its numbers (e.g. a u64 above i64) keep their exact value.
pub fn parse_values(text: &str) -> anyhow::Result<Value> {
    parse_document(text, "the message")
}

/// `text` as JSON, else YAML; `what` names it in errors ("the message", "the case").
pub fn parse_document(text: &str, what: &str) -> anyhow::Result<Value> {
    if let Ok(v) = serde_json::from_str::<Value>(text) {
        return Ok(v);
    }
    let docs = crate::yaml::load(text).map_err(|e| match e {
        e if e.is_syntax() => anyhow!("{what} is not valid JSON or YAML: {e}"),
        e => anyhow!("{what}: {e}"),
    })?;
    match docs.len() {
        0 => bail!("{what} is empty"),
        1 => yaml_to_json(&docs[0]).map_err(|e| anyhow!("{what}: {e}")),
        _ => Ok(Value::Array(docs.iter().map(yaml_to_json).collect::<Result<_, _>>()?)),
    }
}

/// A YAML file: one list of messages, or one message per `---` document.
fn read_yaml_file(path: &Path) -> anyhow::Result<Vec<(String, Value)>> {
    let text = crate::files::read_text(path, "--file")?;
    let docs = crate::yaml::load(&text).map_err(|e| match e {
        e if e.is_syntax() => anyhow!("{}: invalid YAML: {e}", path.display()),
        e => anyhow!("{}: {e}", path.display()),
    })?;
    let mut out = Vec::new();
    for (d, doc) in docs.iter().enumerate() {
        match yaml_to_json(doc).map_err(|e| anyhow!("{}: document {}: {e}", path.display(), d + 1))? {
            Value::Array(items) => {
                out.extend(items.into_iter().enumerate().map(|(i, v)| (format!("{}[{i}]", path.display()), v)))
            }
            other => out.push((format!("{}: document {}", path.display(), d + 1), other)),
        }
    }
    Ok(out)
}

/// YAML as the JSON the message decoder reads: `.nan`/`.inf` become the strings it accepts for floats, and
/// scalar keys become strings.
fn yaml_to_json(y: &yaml_rust2::Yaml) -> anyhow::Result<Value> {
    use yaml_rust2::Yaml;
    Ok(match y {
        Yaml::Null => Value::Null,
        Yaml::Boolean(b) => Value::Bool(*b),
        Yaml::Integer(i) => Value::from(*i),
        Yaml::Real(text) => match y.as_f64() {
            Some(x) if x.is_finite() => serde_json::Number::from_f64(x).map(Value::Number).unwrap_or(Value::Null),
            Some(x) if x.is_nan() => Value::String("nan".into()),
            Some(x) if x > 0.0 => Value::String("inf".into()),
            Some(_) => Value::String("-inf".into()),
            None => Value::String(text.clone()),
        },
        Yaml::String(s) => Value::String(s.clone()),
        Yaml::Array(items) => Value::Array(items.iter().map(yaml_to_json).collect::<Result<_, _>>()?),
        Yaml::Hash(map) => {
            let mut obj = Map::new();
            for (k, v) in map {
                let key = match k {
                    Yaml::String(s) | Yaml::Real(s) => s.clone(),
                    Yaml::Integer(i) => i.to_string(),
                    Yaml::Boolean(b) => b.to_string(),
                    other => bail!("a field name must be a word, found {other:?}"),
                };
                obj.insert(key, yaml_to_json(v)?);
            }
            Value::Object(obj)
        }
        Yaml::Alias(_) | Yaml::BadValue => bail!("unsupported YAML value {y:?}"),
    })
}

fn read_json_lines(path: &Path) -> anyhow::Result<Vec<(String, Value)>> {
    use crate::files::MAX_INPUT_BYTES;
    let reader: Box<dyn BufRead> = if path == Path::new("-") {
        Box::new(std::io::BufReader::new(std::io::stdin().take(MAX_INPUT_BYTES + 1)))
    } else {
        Box::new(std::io::Cursor::new(crate::files::read_limited(path, "--file", MAX_INPUT_BYTES)?))
    };
    let mut out = Vec::new();
    let mut lines = Vec::new();
    let mut bytes = 0u64;
    for line in reader.lines() {
        let line = line.with_context(|| format!("cannot read {}", path.display()))?;
        bytes += line.len() as u64 + 1;
        if bytes > MAX_INPUT_BYTES + 1 {
            bail!("{}: over the limit of {MAX_INPUT_BYTES} bytes for an input: refused", path.display());
        }
        lines.push(line);
    }
    // A file holding one JSON array is accepted too.
    let whole = lines.join("\n");
    if whole.trim_start().starts_with('[') {
        let v: Value = serde_json::from_str(&whole).with_context(|| format!("{}: invalid JSON", path.display()))?;
        if let Value::Array(items) = v {
            for (i, item) in items.into_iter().enumerate() {
                out.push((format!("{}[{i}]", path.display()), item));
            }
        }
        return Ok(out);
    }
    for (i, line) in lines.iter().enumerate() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') || t.starts_with("//") {
            continue;
        }
        let v: Value =
            serde_json::from_str(t).with_context(|| format!("{}:{}: invalid JSON", path.display(), i + 1))?;
        out.push((format!("{}:{}", path.display(), i + 1), v));
    }
    Ok(out)
}

fn read_csv(path: &Path) -> anyhow::Result<Vec<(String, Value)>> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(std::io::Cursor::new(crate::files::read_limited(path, "--file", crate::files::MAX_INPUT_BYTES)?));
    let headers = reader.headers().with_context(|| format!("{}: no header row", path.display()))?.clone();
    let mut out = Vec::new();
    for (i, record) in reader.records().enumerate() {
        let record = record.with_context(|| format!("{}: bad CSV record {}", path.display(), i + 1))?;
        let mut obj = Map::new();
        for (name, cell) in headers.iter().zip(record.iter()) {
            if cell.is_empty() {
                continue; // an empty cell keeps the field's default
            }
            insert_dotted(&mut obj, name, Value::String(cell.to_string()));
        }
        out.push((format!("{}:{}", path.display(), i + 2), Value::Object(obj)));
    }
    Ok(out)
}

/// `header.stamp.sec` = v → {"header": {"stamp": {"sec": v}}}.
fn insert_dotted(obj: &mut Map<String, Value>, dotted: &str, value: Value) {
    match dotted.split_once('.') {
        None => {
            obj.insert(dotted.to_string(), value);
        }
        Some((head, rest)) => {
            let child = obj.entry(head.to_string()).or_insert_with(|| Value::Object(Map::new()));
            if let Value::Object(m) = child {
                insert_dotted(m, rest, value);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::msgs::json::FromJson;
    use crate::msgs::sweetspot_msgs::msg::Swing;

    #[test]
    fn csv_cells_become_nested_fields() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.csv");
        std::fs::write(&path, "swing_id,header.frame_id,ball_speed,measured_exit_speed\n1,rig,40.5,\n2,rig,nan,44\n")
            .unwrap();
        let rows = read_csv(&path).unwrap();
        let cells: Vec<&Value> = rows.iter().map(|(_, v)| v).collect();
        assert_eq!(
            cells[0],
            &serde_json::json!({"swing_id": "1", "header": {"frame_id": "rig"}, "ball_speed": "40.5"})
        );
        assert_eq!(cells[1]["ball_speed"], "nan");
        assert_eq!(cells[1]["measured_exit_speed"], "44");
    }

    #[test]
    fn yaml_flow_and_block_values_read_like_json() {
        let want =
            serde_json::json!({"swing_id": 1, "bat_id": "r161", "ball_speed": 40.5, "header": {"frame_id": "cage"}});
        let flow = parse_values("{swing_id: 1, bat_id: r161, ball_speed: 40.5, header: {frame_id: cage}}").unwrap();
        let block = parse_values("swing_id: 1\nbat_id: r161\nball_speed: 40.5\nheader:\n  frame_id: cage\n").unwrap();
        let json =
            parse_values(r#"{"swing_id": 1, "bat_id": "r161", "ball_speed": 40.5, "header": {"frame_id": "cage"}}"#)
                .unwrap();
        assert_eq!((&flow, &block, &json), (&want, &want, &want));
        let s = Swing::from_json(&parse_values("{measured_exit_speed: .nan, ball_speed: .inf}").unwrap(), "").unwrap();
        assert!(s.measured_exit_speed.is_nan() && s.ball_speed == f64::INFINITY);
        assert_eq!(parse_values("[{a: 1}, {a: 2}]").unwrap(), serde_json::json!([{"a": 1}, {"a": 2}]));
        assert_eq!(parse_values(r#"{"swing_id": 18446744073709551615}"#).unwrap()["swing_id"], u64::MAX);
        let e = parse_values("{not json").unwrap_err().to_string();
        assert!(e.contains("not valid JSON or YAML"), "{e}");
    }
}
