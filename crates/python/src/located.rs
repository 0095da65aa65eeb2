//! `locate`'s report as the columns of the package's DataFrame (`LOCATE_COLUMNS` in python/sweetspot), built
//! in one pass over the swings instead of the report's JSON being written here, parsed and walked row by row
//! in Python. Each cell is what the command line's document says: a number its JSON writes as null (NaN, ±∞)
//! is NaN, and the solution shown is the favoured one, else the first (the handle side).

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::engine::locate::{Located, Outcome, Side, Solution};

/// The float columns taken from the solution shown, in `LOCATE_COLUMNS`' names.
const SOLUTION_FLOATS: [&str; 9] = [
    "impact_z",
    "impact_z_sigma",
    "undercut",
    "undercut_sigma",
    "sweet_spot_z",
    "chi2",
    "model_exit_speed",
    "model_launch_angle",
    "model_spin",
];
/// The float columns taken from the swing itself.
const SWING_FLOATS: [&str; 5] =
    ["measured_exit_speed", "measured_launch_angle", "measured_spin", "max_exit_speed", "excess"];
/// Nullable booleans, carried as 1 (true), 0 (false), -1 (missing) for pandas' `boolean` dtype.
const FLAGS: [&str; 3] = ["undercut_fitted", "favoured", "squared_up"];
/// Text columns (None: missing).
const TEXTS: [&str; 4] = ["bat_id", "verdict", "side", "reason"];

/// The columns of `swings`, ready to cross to Python (built without the GIL).
pub struct LocatedColumns {
    swing_id: Vec<u64>,
    solutions: Vec<i64>,
    solution_floats: [Vec<f64>; SOLUTION_FLOATS.len()],
    swing_floats: [Vec<f64>; SWING_FLOATS.len()],
    flags: [Vec<i8>; FLAGS.len()],
    texts: [Vec<Option<String>>; TEXTS.len()],
}

/// A number as it reads back from the document's JSON, where NaN and ±∞ are null.
fn as_in_json(value: f64) -> f64 {
    if value.is_finite() {
        value
    } else {
        f64::NAN
    }
}

fn flag(value: Option<bool>) -> i8 {
    value.map_or(-1, i8::from)
}

/// The verdict as the document's `verdict` tag names it.
fn verdict(outcome: &Outcome) -> &'static str {
    match outcome {
        Outcome::Located { .. } => "located",
        Outcome::TooFast { .. } => "too_fast",
        Outcome::NotReproducible { .. } => "not_reproducible",
        Outcome::NotMeasured => "not_measured",
        Outcome::Failed { .. } => "failed",
    }
}

fn side_name(side: Side) -> &'static str {
    match side {
        Side::Handle => "handle",
        Side::End => "end",
    }
}

/// The solutions, the one shown and whether the measurements favour one (None: not located).
fn solutions_of(outcome: &Outcome) -> (&[Solution], Option<&Solution>, Option<bool>) {
    match outcome {
        Outcome::Located { solutions, favoured, .. } => {
            (solutions, solutions.get(favoured.unwrap_or(0)), Some(favoured.is_some()))
        }
        Outcome::NotReproducible { solutions, .. } => (solutions, solutions.first(), None),
        _ => (&[], None, None),
    }
}

impl LocatedColumns {
    pub fn of(swings: &[Located]) -> LocatedColumns {
        let n = swings.len();
        let mut columns = LocatedColumns {
            swing_id: Vec::with_capacity(n),
            solutions: Vec::with_capacity(n),
            solution_floats: std::array::from_fn(|_| Vec::with_capacity(n)),
            swing_floats: std::array::from_fn(|_| Vec::with_capacity(n)),
            flags: std::array::from_fn(|_| Vec::with_capacity(n)),
            texts: std::array::from_fn(|_| Vec::with_capacity(n)),
        };
        for swing in swings {
            columns.push(swing);
        }
        columns
    }

    fn push(&mut self, swing: &Located) {
        let (solutions, shown, favoured) = solutions_of(&swing.outcome);
        let mut solution_floats = shown.map_or([f64::NAN; SOLUTION_FLOATS.len()], |s| {
            [
                s.impact_z,
                s.impact_z_sigma,
                s.undercut,
                s.undercut_sigma,
                s.sweet_spot_z,
                s.chi2,
                s.model[0],
                s.model[1],
                s.model[2],
            ]
        });
        let (mut max_exit_speed, mut excess, mut reason, mut squared_up) = (f64::NAN, f64::NAN, None, None);
        match &swing.outcome {
            Outcome::Located { squared_up: s, .. } => squared_up = Some(*s),
            Outcome::TooFast { max_exit_speed: m, excess: e, sweet_spot_z } => {
                (max_exit_speed, excess) = (*m, *e);
                solution_floats[4] = *sweet_spot_z;
            }
            Outcome::NotReproducible { reason: r, .. } | Outcome::Failed { reason: r } => reason = Some(r.clone()),
            Outcome::NotMeasured => {}
        }
        self.swing_id.push(swing.swing_id);
        self.solutions.push(solutions.len() as i64);
        for (column, value) in self.solution_floats.iter_mut().zip(solution_floats) {
            column.push(as_in_json(value));
        }
        let [exit_speed, launch_angle, spin] = swing.measured;
        for (column, value) in
            self.swing_floats.iter_mut().zip([exit_speed, launch_angle, spin, max_exit_speed, excess])
        {
            column.push(as_in_json(value));
        }
        for (column, value) in self.flags.iter_mut().zip([shown.map(|s| s.undercut_fitted), favoured, squared_up]) {
            column.push(flag(value));
        }
        let side = shown.map(|s| side_name(s.side).to_string());
        for (column, value) in
            self.texts.iter_mut().zip([Some(swing.bat_id.clone()), Some(verdict(&swing.outcome).into()), side, reason])
        {
            column.push(value);
        }
    }

    /// The columns by name: numpy arrays (float64; `solutions` int64; `swing_id` uint64; the flags int8) and
    /// lists of str/None.
    pub fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let dict = PyDict::new(py);
        dict.set_item("swing_id", self.swing_id.into_pyarray(py))?;
        dict.set_item("solutions", self.solutions.into_pyarray(py))?;
        for (name, column) in SOLUTION_FLOATS.iter().zip(self.solution_floats) {
            dict.set_item(name, column.into_pyarray(py))?;
        }
        for (name, column) in SWING_FLOATS.iter().zip(self.swing_floats) {
            dict.set_item(name, column.into_pyarray(py))?;
        }
        for (name, column) in FLAGS.iter().zip(self.flags) {
            dict.set_item(name, column.into_pyarray(py))?;
        }
        for (name, column) in TEXTS.iter().zip(self.texts) {
            dict.set_item(name, column)?;
        }
        Ok(dict)
    }
}
