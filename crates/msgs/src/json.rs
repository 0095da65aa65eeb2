//! Tolerant JSON conversions of the generated messages, for people and scripts (`sweetspot pub` / `echo`).
//!
//! Reading ([`FromJson`]): fields left out keep their default; unknown fields are errors naming the field
//! (typos must not pass silently); integers are range-checked; a float may be a number, `null` or `"nan"` (NaN),
//! `"inf"` / `"-inf"`; numbers and bools may also be given as strings (so CSV cells work); an array may also be
//! a string holding a JSON array or `;`-separated values.
//!
//! Writing ([`ToJson`]): plain JSON; a NaN float becomes `null` and ±∞ become `"inf"` / `"-inf"` (JSON has no
//! such numbers), which [`FromJson`] reads back to the same values.

use serde_json::{Map, Value};

use super::MsgError;

/// Builds a value from JSON, naming the offending field (`path`) on error.
pub trait FromJson: Sized {
    /// Converts `value`, found at `path` (e.g. `swing.header.stamp.sec`).
    fn from_json(value: &Value, path: &str) -> Result<Self, MsgError>;
}

/// Converts a value to JSON.
pub trait ToJson {
    /// The JSON form.
    fn to_json(&self) -> Value;
}

/// Parses a whole message from a JSON value.
pub fn from_json<T: FromJson>(value: &Value) -> Result<T, MsgError> {
    T::from_json(value, "")
}

fn err(path: &str, reason: impl Into<String>) -> MsgError {
    MsgError::Json { path: if path.is_empty() { "message".into() } else { path.to_string() }, reason: reason.into() }
}

/// `path` + `.field`.
pub fn join(path: &str, field: &str) -> String {
    if path.is_empty() {
        field.to_string()
    } else {
        format!("{path}.{field}")
    }
}

/// The object at `path`, or an error.
pub fn expect_object<'a>(value: &'a Value, path: &str) -> Result<&'a Map<String, Value>, MsgError> {
    match value {
        Value::Object(m) => Ok(m),
        other => Err(err(path, format!("expected an object, found {}", kind(other)))),
    }
}

/// Errors on the first key of `object` that is not a field of `type_name`.
pub fn reject_unknown(
    object: &Map<String, Value>,
    known: &[&str],
    path: &str,
    type_name: &str,
) -> Result<(), MsgError> {
    for key in object.keys() {
        if !known.contains(&key.as_str()) {
            return Err(err(&join(path, key), format!("{type_name} has no such field (fields: {})", known.join(", "))));
        }
    }
    Ok(())
}

/// Errors when a bounded string or sequence is longer than its bound.
pub fn check_len(len: usize, bound: usize, path: &str) -> Result<(), MsgError> {
    if len > bound {
        return Err(err(path, format!("length {len} exceeds the bound {bound}")));
    }
    Ok(())
}

fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a bool",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

fn parse_float(value: &Value, path: &str) -> Result<f64, MsgError> {
    match value {
        Value::Number(n) => n.as_f64().ok_or_else(|| err(path, "not representable as a float")),
        Value::Null => Ok(f64::NAN),
        Value::String(s) => {
            let t = s.trim();
            match t.to_ascii_lowercase().as_str() {
                "" | "nan" | ".nan" | "null" => Ok(f64::NAN),
                "inf" | "+inf" | "infinity" | ".inf" => Ok(f64::INFINITY),
                "-inf" | "-infinity" | "-.inf" => Ok(f64::NEG_INFINITY),
                _ => t.parse::<f64>().map_err(|_| err(path, format!("expected a number, found \"{s}\""))),
            }
        }
        other => Err(err(path, format!("expected a number, found {}", kind(other)))),
    }
}

impl FromJson for f64 {
    fn from_json(value: &Value, path: &str) -> Result<Self, MsgError> {
        parse_float(value, path)
    }
}

impl FromJson for f32 {
    fn from_json(value: &Value, path: &str) -> Result<Self, MsgError> {
        let v = parse_float(value, path)?;
        if v.is_finite() && v.abs() > f32::MAX as f64 {
            return Err(err(path, format!("{v} is out of the float32 range")));
        }
        Ok(v as f32)
    }
}

fn float_json(v: f64) -> Value {
    if v.is_nan() {
        Value::Null
    } else if v.is_infinite() {
        Value::String(if v > 0.0 { "inf" } else { "-inf" }.into())
    } else {
        serde_json::Number::from_f64(v).map(Value::Number).unwrap_or(Value::Null)
    }
}

impl ToJson for f64 {
    fn to_json(&self) -> Value {
        float_json(*self)
    }
}

impl ToJson for f32 {
    fn to_json(&self) -> Value {
        // Through the shortest decimal of the f32, so 0.1f32 prints as 0.1, not 0.10000000149011612.
        match format!("{self}").parse::<f64>() {
            Ok(v) => float_json(v),
            Err(_) => float_json(*self as f64),
        }
    }
}

macro_rules! int_json {
    ($($t:ty),*) => {$(
        impl FromJson for $t {
            fn from_json(value: &Value, path: &str) -> Result<Self, MsgError> {
                let range = || format!("expected an integer in [{}, {}]", <$t>::MIN, <$t>::MAX);
                match value {
                    Value::Number(n) => {
                        if let Some(i) = n.as_i64() {
                            <$t>::try_from(i).map_err(|_| err(path, format!("{i}: {}", range())))
                        } else if let Some(u) = n.as_u64() {
                            <$t>::try_from(u).map_err(|_| err(path, format!("{u}: {}", range())))
                        } else {
                            Err(err(path, format!("{n}: {}", range())))
                        }
                    }
                    Value::String(s) => s.trim().parse::<$t>().map_err(|_| err(path, format!("\"{s}\": {}", range()))),
                    Value::Bool(b) => Ok(<$t>::from(*b)),
                    other => Err(err(path, format!("{}: {}", kind(other), range()))),
                }
            }
        }
        impl ToJson for $t {
            fn to_json(&self) -> Value {
                Value::from(*self)
            }
        }
    )*};
}
int_json!(i8, u8, i16, u16, i32, u32, i64, u64);

impl FromJson for bool {
    fn from_json(value: &Value, path: &str) -> Result<Self, MsgError> {
        match value {
            Value::Bool(b) => Ok(*b),
            Value::Number(n) if n.as_u64() == Some(0) => Ok(false),
            Value::Number(n) if n.as_u64() == Some(1) => Ok(true),
            Value::String(s) => match s.trim().to_ascii_lowercase().as_str() {
                "true" | "1" => Ok(true),
                "false" | "0" => Ok(false),
                _ => Err(err(path, format!("expected true or false, found \"{s}\""))),
            },
            other => Err(err(path, format!("expected true or false, found {}", kind(other)))),
        }
    }
}

impl ToJson for bool {
    fn to_json(&self) -> Value {
        Value::Bool(*self)
    }
}

impl FromJson for String {
    fn from_json(value: &Value, path: &str) -> Result<Self, MsgError> {
        match value {
            Value::String(s) => {
                if s.contains('\0') {
                    return Err(err(path, "strings cannot contain NUL characters"));
                }
                Ok(s.clone())
            }
            other => Err(err(path, format!("expected a string, found {}", kind(other)))),
        }
    }
}

impl ToJson for String {
    fn to_json(&self) -> Value {
        Value::String(self.clone())
    }
}

/// The elements of a JSON array, or of a string holding a JSON array or `;`-separated values (CSV cells).
fn array_elements(value: &Value, path: &str) -> Result<Vec<Value>, MsgError> {
    match value {
        Value::Array(a) => Ok(a.clone()),
        Value::String(s) => {
            let t = s.trim();
            if t.starts_with('[') {
                match serde_json::from_str::<Value>(t) {
                    Ok(Value::Array(a)) => Ok(a),
                    _ => Err(err(path, format!("expected a JSON array, found \"{s}\""))),
                }
            } else if t.is_empty() {
                Ok(Vec::new())
            } else {
                Ok(t.split(';').map(|e| Value::String(e.trim().to_string())).collect())
            }
        }
        other => Err(err(path, format!("expected an array, found {}", kind(other)))),
    }
}

impl<T: FromJson> FromJson for Vec<T> {
    fn from_json(value: &Value, path: &str) -> Result<Self, MsgError> {
        array_elements(value, path)?.iter().enumerate().map(|(i, v)| T::from_json(v, &format!("{path}[{i}]"))).collect()
    }
}

impl<T: ToJson> ToJson for Vec<T> {
    fn to_json(&self) -> Value {
        Value::Array(self.iter().map(ToJson::to_json).collect())
    }
}

impl<T: FromJson, const N: usize> FromJson for [T; N] {
    fn from_json(value: &Value, path: &str) -> Result<Self, MsgError> {
        let v: Vec<T> = Vec::from_json(value, path)?;
        let len = v.len();
        v.try_into().map_err(|_| err(path, format!("expected exactly {N} elements, found {len}")))
    }
}

impl<T: ToJson, const N: usize> ToJson for [T; N] {
    fn to_json(&self) -> Value {
        Value::Array(self.iter().map(ToJson::to_json).collect())
    }
}

/// Renders JSON in the indented `key: value` form `ros2 topic echo` prints (NaN shows as `.nan`).
pub fn to_readable(value: &Value) -> String {
    to_readable_named(value, &[])
}

/// [`to_readable`], with the integer value of each field named in `names` followed by its constant's name
/// (`status: 0 (OK)`; a value no constant has prints bare).
pub fn to_readable_named(value: &Value, names: &[(&str, &[(u64, &str)])]) -> String {
    let mut out = String::new();
    write_readable(value, 0, names, &mut out);
    out
}

/// `scalar` as [`scalar_readable`] prints it, with the name of the constant of field `key` it equals.
fn named_scalar(key: &str, scalar: &Value, names: &[(&str, &[(u64, &str)])]) -> String {
    let plain = scalar_readable(scalar);
    let name = names
        .iter()
        .find(|(field, _)| *field == key)
        .and_then(|(_, consts)| consts.iter().find(|(v, _)| Some(*v) == scalar.as_u64()))
        .map(|(_, name)| *name);
    match name {
        Some(name) => format!("{plain} ({name})"),
        None => plain,
    }
}

fn scalar_readable(v: &Value) -> String {
    match v {
        Value::Null => ".nan".into(),
        Value::String(s) if s == "inf" => ".inf".into(),
        Value::String(s) if s == "-inf" => "-.inf".into(),
        Value::String(s) => format!("'{}'", s.replace('\'', "''")),
        Value::Number(n) => {
            // Keep floats recognisable as floats (1.0 rather than 1).
            if n.is_f64() {
                let f = n.as_f64().unwrap_or(f64::NAN);
                if f.fract() == 0.0 && f.abs() < 1e15 {
                    format!("{f:.1}")
                } else {
                    format!("{f}")
                }
            } else {
                n.to_string()
            }
        }
        Value::Bool(b) => b.to_string(),
        _ => String::new(),
    }
}

fn write_readable(value: &Value, indent: usize, names: &[(&str, &[(u64, &str)])], out: &mut String) {
    let pad = " ".repeat(indent);
    match value {
        Value::Object(map) => {
            for (k, v) in map {
                match v {
                    Value::Object(m) if !m.is_empty() => {
                        out.push_str(&format!("{pad}{k}:\n"));
                        write_readable(v, indent + 2, names, out);
                    }
                    Value::Array(a) if !a.is_empty() => {
                        if a.iter().all(|e| !e.is_object() && !e.is_array()) {
                            out.push_str(&format!("{pad}{k}:\n"));
                            for e in a {
                                out.push_str(&format!("{pad}- {}\n", scalar_readable(e)));
                            }
                        } else {
                            out.push_str(&format!("{pad}{k}:\n"));
                            for e in a {
                                let mut inner = String::new();
                                write_readable(e, indent + 2, names, &mut inner);
                                // First line of each element gets the list marker.
                                let inner = inner.replacen(&format!("{pad}  "), &format!("{pad}- "), 1);
                                out.push_str(&inner);
                            }
                        }
                    }
                    Value::Array(_) => out.push_str(&format!("{pad}{k}: []\n")),
                    Value::Object(_) => out.push_str(&format!("{pad}{k}: {{}}\n")),
                    scalar => out.push_str(&format!("{pad}{k}: {}\n", named_scalar(k, scalar, names))),
                }
            }
        }
        scalar => out.push_str(&format!("{pad}{}\n", scalar_readable(scalar))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweetspot_msgs::msg::Swing;

    #[test]
    fn tolerant_reading() {
        let v: Value = serde_json::json!({"swing_id": "7", "ball_speed": 40, "measured_exit_speed": null,
                                          "header": {"frame_id": "rig"}});
        let s: Swing = from_json(&v).unwrap();
        assert_eq!(s.swing_id, 7);
        assert_eq!(s.ball_speed, 40.0);
        assert!(s.measured_exit_speed.is_nan());
        assert_eq!(s.header.frame_id, "rig");
    }

    #[test]
    fn errors_name_the_field() {
        let e = from_json::<Swing>(&serde_json::json!({"header": {"stamp": {"sec": 1e12}}})).unwrap_err();
        assert!(e.to_string().starts_with("header.stamp.sec:"), "{e}");
        let e = from_json::<Swing>(&serde_json::json!({"bat_idd": "x"})).unwrap_err();
        assert!(e.to_string().contains("bat_idd") && e.to_string().contains("no such field"), "{e}");
        let e = from_json::<Swing>(&serde_json::json!({"swing_id": -1})).unwrap_err();
        assert!(e.to_string().starts_with("swing_id:"), "{e}");
    }

    #[test]
    fn nan_round_trips_through_json() {
        let s = Swing { measured_exit_speed: f64::NAN, impact_z: f64::INFINITY, ..Default::default() };
        let back: Swing = from_json(&s.to_json()).unwrap();
        assert!(back.measured_exit_speed.is_nan());
        assert_eq!(back.impact_z, f64::INFINITY);
    }

    #[test]
    fn readable_form_is_ros2_echo_like() {
        use crate::diagnostic_msgs::msg::{DiagnosticArray, DiagnosticStatus, KeyValue};
        let d = DiagnosticArray {
            status: vec![DiagnosticStatus {
                level: 1,
                name: "it's".into(),
                values: vec![KeyValue { key: "k".into(), value: "v".into() }],
                ..Default::default()
            }],
            ..Default::default()
        };
        let text = to_readable(&d.to_json());
        assert_eq!(
            text,
            "header:\n  stamp:\n    sec: 0\n    nanosec: 0\n  frame_id: ''\nstatus:\n- level: 1\n  name: 'it''s'\n  \
             message: ''\n  hardware_id: ''\n  values:\n  - key: 'k'\n    value: 'v'\n"
        );
        let s = Swing { measured_exit_speed: f64::NAN, ball_speed: 40.0, ..Default::default() };
        let text = to_readable(&s.to_json());
        assert!(text.contains("ball_speed: 40.0\n") && text.contains("measured_exit_speed: .nan\n"), "{text}");
    }
}
