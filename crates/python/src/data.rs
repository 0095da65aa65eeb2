//! Tracker exports, bags and `locate`: the importer's parsing and refusals row by row, an export
//! located in memory as `sweetspot import` then `sweetspot locate --json` would locate it, a bag located,
//! and a bag's messages.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::{json, Value};

use crate::cli_shared::{batter_from_spec, load_batter_file, BatterSpec};
use crate::engine::bag::export::{namespace_of, swing_rows};
use crate::engine::bag::reader::read_bag;
use crate::engine::calibrate::CalibrateError;
use crate::engine::import::table::Table;
use crate::engine::import::{
    hittrax, import_table, statcast, trackman, Format, ImportError, ImportOptions, Skip, SwingBuilder, TrackedRow,
};
use crate::engine::locate::{locate_bag as locate, locate_imported, LocateError, LocateOptions, LocateReport};
use crate::engine::model::convert::{params_from_ball, params_from_bat, params_of_preset};
use crate::engine::msgs::json::ToJson;
use crate::engine::msgs::std_msgs::msg::Header;
use crate::engine::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};
use crate::engine::msgs::{decode_cdr, RosMessage};
use crate::engine::physics::oblique::rpm_to_rad_per_s;
use crate::engine::physics::{self, Ball};
use crate::errors::{bag_error, require_exists, value_error};
use crate::frame::{cells_of, csv_text, Cells};
use crate::located::LocatedColumns;
use crate::physics::Bat;

/// The import's options as `sweetspot import --bat BAT --ball BALL [--batter FILE] --undercut D [--tee]`
/// resolves them (`bat_spec`: the preset name, or the file the bat was read from).
fn import_options(
    bat: &physics::Bat,
    bat_spec: &str,
    ball: &str,
    batter: Option<&Path>,
    undercut: f64,
    tee: bool,
    format: Option<Format>,
) -> PyResult<ImportOptions> {
    let bat_params = if physics::Bat::preset_names().contains(&bat_spec) {
        params_of_preset(bat_spec, bat_spec, Header::default())
    } else {
        params_from_bat(&bat.name, bat, 0, Header::default())
    };
    let ball_model = Ball::preset(ball).map_err(|e| PyValueError::new_err(format!("--ball {ball}: {e}")))?;
    let ball_params = params_from_ball(ball, &ball_model, None, Header::default());
    let (batter, _) = match batter {
        Some(path) => {
            require_exists(path, "batter file")?;
            load_batter_file(path).map_err(value_error)?
        }
        None => batter_from_spec(&BatterSpec::default(), None).map_err(value_error)?,
    };
    Ok(ImportOptions { format, bat: bat.clone(), bat_params, ball_params, batter, undercut, map: None, tee })
}

/// A frame's columns (name, cells), copied out of Python to be written as the CSV export they stand for
/// ([`crate::frame`]) with the GIL released.
fn frame_cells(columns: &[(String, Bound<'_, PyAny>)]) -> PyResult<Vec<(String, Cells)>> {
    columns.iter().map(|(name, column)| Ok((name.clone(), cells_of(column)?))).collect()
}

fn format_of(kind: Option<&str>) -> PyResult<Option<Format>> {
    kind.map(str::parse::<Format>).transpose().map_err(|e| PyValueError::new_err(e.to_string()))
}

fn import_error(error: ImportError) -> PyErr {
    match error {
        ImportError::Io { path, error } if error.kind() == std::io::ErrorKind::NotFound => {
            pyo3::exceptions::PyFileNotFoundError::new_err((2, error.to_string(), path.display().to_string()))
        }
        ImportError::Bag(e) => bag_error(e),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// One file's reader, in its format.
enum Reader {
    TrackMan(trackman::Columns),
    Statcast(statcast::Columns),
    HitTrax(hittrax::Columns),
}

/// The format of `table` (forced, or detected from its header as `import` does), with the importer's
/// messages.
fn reader_of(table: &Table, forced: Option<Format>, name: &str) -> PyResult<(Format, Reader)> {
    let format = match forced {
        Some(format) => {
            let missing = format.missing(table.headers());
            if !missing.is_empty() {
                return Err(PyValueError::new_err(format!(
                    "{name}: not a {} export: its header lacks {}",
                    format.name(),
                    missing.join(", ")
                )));
            }
            format
        }
        None => Format::detect(table.headers()).ok_or_else(|| {
            PyValueError::new_err(format!(
                "{name}: the header row matches no known export: {} (kind= to force one, which names what is missing)",
                Format::ALL
                    .iter()
                    .map(|f| format!("{} needs {}", f.name(), f.required().join(", ")))
                    .collect::<Vec<_>>()
                    .join("; ")
            ))
        })?,
    };
    let reader = match format {
        Format::TrackMan => Reader::TrackMan(trackman::Columns::of(table)),
        Format::Statcast => Reader::Statcast(statcast::Columns::of(table)),
        Format::HitTrax => Reader::HitTrax(hittrax::Columns::of(table)),
        Format::Mapped => return Err(PyValueError::new_err("a mapped export needs a column map")),
    };
    Ok((format, reader))
}

/// The rows of one export, column by column.
#[derive(Default)]
struct TrackerColumns {
    line: Vec<u64>,
    time_ns: Vec<Option<u64>>,
    contact: Vec<Option<bool>>,
    call: Vec<String>,
    numbers: Vec<[f64; 10]>,
    batter: Vec<String>,
    pitcher: Vec<String>,
    pitch_id: Vec<String>,
    swing_id: Vec<Option<u64>>,
    bat_cm_speed: Vec<f64>,
    bat_angular_speed: Vec<f64>,
    assumed: Vec<String>,
    skipped: Vec<Option<String>>,
    refused: Vec<Option<String>>,
}

/// The numbers of a [`TrackedRow`], SI units, in this order.
const NUMBERS: [&str; 10] = [
    "pitch_speed",
    "pitch_angle",
    "pitch_spin",
    "bat_speed",
    "attack_angle",
    "exit_speed",
    "launch_angle",
    "spin",
    "swing_length",
    "impact_z",
];

impl TrackerColumns {
    fn push(&mut self, line: u64, tracked: Option<&TrackedRow>, outcome: Result<(&Swing, Vec<&str>), &Skip>) {
        let nan = f64::NAN;
        self.line.push(line);
        self.time_ns.push(tracked.and_then(|t| t.stamp_ns));
        self.contact.push(tracked.map(|t| t.contact));
        self.call.push(tracked.map(|t| t.call.clone()).unwrap_or_default());
        let swing = outcome.as_ref().ok().map(|(s, _)| *s);
        self.numbers.push(match tracked {
            Some(t) => [
                t.pitch_speed,
                t.pitch_angle,
                t.pitch_spin,
                t.bat_speed,
                t.attack_angle,
                t.exit_speed,
                t.launch_angle,
                t.spin,
                t.swing_length,
                swing.map_or(nan, |s| s.impact_z),
            ],
            None => [nan; 10],
        });
        self.batter.push(tracked.map(|t| t.batter.clone()).unwrap_or_default());
        self.pitcher.push(tracked.map(|t| t.pitcher.clone()).unwrap_or_default());
        self.pitch_id.push(tracked.map(|t| t.pitch_id.clone()).unwrap_or_default());
        self.swing_id.push(swing.map(|s| s.swing_id));
        self.bat_cm_speed.push(swing.map_or(nan, |s| s.bat_cm_speed));
        self.bat_angular_speed.push(swing.map_or(nan, |s| s.bat_angular_speed));
        self.assumed.push(outcome.as_ref().map(|(_, a)| a.join(";")).unwrap_or_default());
        match outcome {
            Ok(_) => {
                self.skipped.push(None);
                self.refused.push(None);
            }
            Err(skip) => {
                self.skipped.push(Some(skip.reason()));
                self.refused.push(skip.is_refusal().then(|| format!("line {line}: {skip}")));
            }
        }
    }

    fn into_dict(self, py: Python<'_>, format: Format) -> PyResult<Bound<'_, PyDict>> {
        let out = PyDict::new(py);
        out.set_item("format", format.name())?;
        out.set_item("line", self.line)?;
        out.set_item("time_ns", self.time_ns)?;
        out.set_item("contact", self.contact)?;
        out.set_item("call", self.call)?;
        for (k, name) in NUMBERS.iter().enumerate() {
            let column: Vec<f64> = self.numbers.iter().map(|row| row[k]).collect();
            out.set_item(*name, column)?;
        }
        out.set_item("batter", self.batter)?;
        out.set_item("pitcher", self.pitcher)?;
        out.set_item("pitch_id", self.pitch_id)?;
        out.set_item("swing_id", self.swing_id)?;
        out.set_item("bat_cm_speed", self.bat_cm_speed)?;
        out.set_item("bat_angular_speed", self.bat_angular_speed)?;
        out.set_item("assumed", self.assumed)?;
        out.set_item("skipped", self.skipped)?;
        out.set_item("refused", self.refused)?;
        Ok(out)
    }
}

/// Every row of an export (the file at `path`, or a frame's `columns` named `name`) as the importer reads it: the
/// tracker's values in SI units, the swing it became (swing_id numbered as `import` numbers them) or why it
/// was skipped, and the refusal's message for a row refused as bad input.
#[pyfunction]
#[pyo3(signature = (*, path=None, columns=None, name="DataFrame", kind=None, bat, bat_spec, ball="mlb2024",
    batter=None, undercut=0.0, tee=false))]
#[allow(clippy::too_many_arguments)]
pub fn read_tracker_columns<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    columns: Option<Vec<(String, Bound<'py, PyAny>)>>,
    name: &str,
    kind: Option<&str>,
    bat: &Bat,
    bat_spec: &str,
    ball: &str,
    batter: Option<PathBuf>,
    undercut: f64,
    tee: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let forced = format_of(kind)?;
    let options = import_options(&bat.bat, bat_spec, ball, batter.as_deref(), undercut, tee, forced)?;
    let builder = SwingBuilder::new(&options).map_err(import_error)?;
    let cells = columns.as_deref().map(frame_cells).transpose()?;
    let (format, columns) = py.allow_threads(move || -> PyResult<(Format, TrackerColumns)> {
        let (mut table, name) = match (path, cells) {
            (Some(path), None) => {
                require_exists(&path, "export")?;
                (Table::open(&path).map_err(import_error)?, path.display().to_string())
            }
            (None, Some(cells)) => {
                let text = csv_text(&cells)?;
                let table = Table::from_reader(Path::new(name), Box::new(Cursor::new(text))).map_err(import_error)?;
                (table, name.to_string())
            }
            _ => return Err(PyValueError::new_err("give a path or columns")),
        };
        let (format, reader) = reader_of(&table, forced, &name)?;
        let mut columns = TrackerColumns::default();
        let mut swings = 0u64;
        while table.next_row().map_err(import_error)? {
            let row = table.row();
            let tracked = if let Some(why) = row.unreadable() {
                Err(Skip::Unreadable { why: why.to_string() })
            } else if let Some(why) = row.malformed() {
                Err(Skip::Malformed { why: why.to_string() })
            } else {
                match &reader {
                    Reader::TrackMan(cols) => trackman::read(&row, cols),
                    Reader::Statcast(cols) => statcast::read(&row, cols),
                    Reader::HitTrax(cols) => hittrax::read(&row, cols),
                }
            };
            let stamp = crate::engine::msgs::builtin_interfaces::msg::Time::default();
            let built = tracked.as_ref().map_err(Clone::clone).and_then(|t| builder.swing(t, swings + 1, stamp));
            match &built {
                Ok((swing, assumed)) => {
                    swings += 1;
                    columns.push(row.line(), tracked.as_ref().ok(), Ok((swing, assumed.names())));
                }
                Err(skip) => columns.push(row.line(), tracked.as_ref().ok(), Err(skip)),
            }
        }
        Ok((format, columns))
    })?;
    columns.into_dict(py, format)
}

/// The trackers' accuracies as `sweetspot locate` takes them (m/s, degrees, rpm), checked.
fn locate_options(
    exit_speed_sigma: f64,
    launch_angle_sigma: f64,
    spin_sigma: f64,
    fit_bat_speed: bool,
) -> PyResult<LocateOptions> {
    for (name, v) in
        [("exit_speed_sigma", exit_speed_sigma), ("launch_angle_sigma", launch_angle_sigma), ("spin_sigma", spin_sigma)]
    {
        if !(v > 0.0 && v.is_finite()) {
            return Err(PyValueError::new_err(format!("{name} = {v}: expected > 0")));
        }
    }
    Ok(LocateOptions {
        exit_speed_sigma,
        launch_angle_sigma: launch_angle_sigma.to_radians(),
        spin_sigma: rpm_to_rad_per_s(spin_sigma),
        fit_bat_speed,
    })
}

fn report_json(report: &LocateReport) -> PyResult<String> {
    serde_json::to_string(report).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// `sweetspot locate BAG --json` with these accuracies (m/s, degrees, rpm): the document as JSON text, and
/// its swings as the DataFrame's columns ([`LocatedColumns`]).
#[pyfunction]
#[pyo3(signature = (bag, *, exit_speed_sigma=0.45, launch_angle_sigma=1.0, spin_sigma=100.0,
    fit_bat_speed=false))]
pub fn locate_bag<'py>(
    py: Python<'py>,
    bag: PathBuf,
    exit_speed_sigma: f64,
    launch_angle_sigma: f64,
    spin_sigma: f64,
    fit_bat_speed: bool,
) -> PyResult<(String, Bound<'py, PyDict>)> {
    let options = locate_options(exit_speed_sigma, launch_angle_sigma, spin_sigma, fit_bat_speed)?;
    require_exists(&bag, "bag")?;
    let (text, columns) = py
        .allow_threads(|| {
            let report = locate(&bag, &options)?;
            Ok((report_json(&report), LocatedColumns::of(&report.swings)))
        })
        .map_err(|e: LocateError| {
            let message = format!("{}: {e}", bag.display());
            match e {
                LocateError::Read(CalibrateError::Bag(_)) => bag_error(message),
                _ => PyValueError::new_err(message),
            }
        })?;
    Ok((text?, columns.into_dict(py)?))
}

/// `sweetspot import [KIND] CSV -o BAG …` then `sweetspot locate BAG --json` of the export a frame's
/// `columns` stand for (named `name` in messages), in memory: the swings are built by the importer's row
/// parsing and refusals and located without a bag. Returns the document's counts as JSON text (its `swings`
/// empty), the swings as the DataFrame's columns ([`LocatedColumns`]) and each swing's line in the export.
#[pyfunction]
#[pyo3(signature = (columns, *, name="DataFrame", kind=None, bat, bat_spec, ball="mlb2024", batter=None,
    undercut=0.0, tee=false, exit_speed_sigma=0.45, launch_angle_sigma=1.0, spin_sigma=100.0,
    fit_bat_speed=false))]
#[allow(clippy::too_many_arguments)]
pub fn locate_export<'py>(
    py: Python<'py>,
    columns: Vec<(String, Bound<'_, PyAny>)>,
    name: &str,
    kind: Option<&str>,
    bat: &Bat,
    bat_spec: &str,
    ball: &str,
    batter: Option<PathBuf>,
    undercut: f64,
    tee: bool,
    exit_speed_sigma: f64,
    launch_angle_sigma: f64,
    spin_sigma: f64,
    fit_bat_speed: bool,
) -> PyResult<(String, Bound<'py, PyDict>, Bound<'py, PyArray1<u64>>)> {
    let options = locate_options(exit_speed_sigma, launch_angle_sigma, spin_sigma, fit_bat_speed)?;
    let import = import_options(&bat.bat, bat_spec, ball, batter.as_deref(), undercut, tee, format_of(kind)?)?;
    let cells = frame_cells(&columns)?;
    let (counts, columns, lines) = py.allow_threads(|| -> PyResult<_> {
        let text = csv_text(&cells)?;
        let table = Table::from_reader(Path::new(name), Box::new(Cursor::new(text))).map_err(import_error)?;
        let imported = import_table(table, Path::new(name), &import).map_err(import_error)?;
        let mut report = locate_imported(&imported, &import, &options, &|_, _| {});
        let columns = LocatedColumns::of(&report.swings);
        report.swings = Vec::new();
        let lines: Vec<u64> = imported.swings.iter().map(|s| s.line).collect();
        Ok((report_json(&report)?, columns, lines))
    })?;
    Ok((counts, columns.into_dict(py)?, lines.into_pyarray(py)))
}

/// A message of one of sweetspot's types as JSON, None for another type or one that does not decode.
fn message_json(type_name: &str, data: &[u8]) -> Option<Value> {
    fn decoded<T: serde::de::DeserializeOwned + ToJson>(data: &[u8]) -> Option<Value> {
        decode_cdr::<T>(data).ok().map(|m| m.to_json())
    }
    match type_name {
        t if t == Swing::TYPE_NAME => decoded::<Swing>(data),
        t if t == ExitVelocity::TYPE_NAME => decoded::<ExitVelocity>(data),
        t if t == ModalEnergies::TYPE_NAME => decoded::<ModalEnergies>(data),
        t if t == SweetSpot::TYPE_NAME => decoded::<SweetSpot>(data),
        t if t == BatParams::TYPE_NAME => decoded::<BatParams>(data),
        t if t == BallParams::TYPE_NAME => decoded::<BallParams>(data),
        _ => None,
    }
}

/// A bag's messages of sweetspot's types per topic, and its swings joined to their answers (as `bag export
/// --csv` joins them), as JSON text: `{"topics": [{"topic", "type", "namespace", "log_time_ns": [...],
/// "messages": [...]}], "swings": [{"namespace", "log_time_ns", "swing", "exit_velocity",
/// "modal_energies"}], "skipped": {type: count}}`.
#[pyfunction]
pub fn read_bag_document(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    require_exists(&path, "bag")?;
    let document = py.allow_threads(|| -> Result<Value, crate::engine::bag::BagError> {
        let mut topics: Vec<(String, String, Vec<u64>, Vec<Value>)> = Vec::new();
        let mut skipped: std::collections::BTreeMap<String, u64> = Default::default();
        read_bag(&path, |m| {
            let topic = &m.channel.topic;
            match message_json(&topic.type_name, m.data) {
                Some(value) => {
                    let at = match topics.iter().position(|(name, ..)| *name == topic.name) {
                        Some(at) => at,
                        None => {
                            topics.push((topic.name.clone(), topic.type_name.clone(), Vec::new(), Vec::new()));
                            topics.len() - 1
                        }
                    };
                    topics[at].2.push(m.log_time_ns);
                    topics[at].3.push(value);
                }
                None => *skipped.entry(topic.type_name.clone()).or_default() += 1,
            }
        })?;
        let (rows, _) = swing_rows(&path)?;
        let swings: Vec<Value> = rows
            .iter()
            .map(|r| {
                json!({
                    "namespace": r.namespace,
                    "log_time_ns": r.log_time_ns,
                    "swing": r.swing.to_json(),
                    "exit_velocity": r.exit_velocity.as_ref().map(ToJson::to_json),
                    "modal_energies": r.modal_energies.as_ref().map(ToJson::to_json),
                })
            })
            .collect();
        let topics: Vec<Value> = topics
            .into_iter()
            .map(|(name, type_name, times, messages)| {
                json!({
                    "namespace": namespace_of(&name, &type_name),
                    "topic": name,
                    "type": type_name,
                    "log_time_ns": times,
                    "messages": messages,
                })
            })
            .collect();
        Ok(json!({ "topics": topics, "swings": swings, "skipped": skipped }))
    });
    let document = document.map_err(bag_error)?;
    serde_json::to_string(&document).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The validation suite's data directory: `data`, else `./validation`, else the source tree's.
fn validation_dir(data: Option<PathBuf>) -> PathBuf {
    data.unwrap_or_else(|| {
        let here = PathBuf::from("validation");
        if here.join("measurements.toml").is_file() {
            here
        } else {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation")
        }
    })
}

/// `sweetspot validate [--data DIR] [--tangential-stiffness-ratio ETA2] --json`: the report as JSON text
/// (whatever the verdicts: a FAIL row is a finding about the model, not an error).
#[pyfunction]
#[pyo3(signature = (data=None, *, tangential_stiffness_ratio=None, modes=18, dt=5e-6))]
pub fn validate_document(
    py: Python<'_>,
    data: Option<PathBuf>,
    tangential_stiffness_ratio: Option<f64>,
    modes: usize,
    dt: f64,
) -> PyResult<String> {
    use crate::cli_shared::check_options;
    use crate::engine::physics::{CollisionOptions, TangentialContact};
    use crate::engine::validate::{evaluate, read_inputs};
    let dir = validation_dir(data);
    require_exists(&dir, "validation data directory")?;
    let report = py.allow_threads(|| -> anyhow::Result<_> {
        use anyhow::Context;
        let options = check_options(CollisionOptions { modes, time_step: dt })?;
        let inputs = read_inputs(&dir).with_context(|| format!("validation data in '{}'", dir.display()))?;
        let contact = TangentialContact { stiffness_ratio: tangential_stiffness_ratio, ..TangentialContact::default() };
        contact.validate().context("tangential_stiffness_ratio")?;
        let (report, _) = evaluate(&inputs, options, contact).context("running the validation cases")?;
        Ok(report)
    });
    serde_json::to_string(&report.map_err(value_error)?).map_err(|e| PyValueError::new_err(e.to_string()))
}
