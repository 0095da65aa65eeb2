//! A DataFrame's columns as the CSV export they stand for, written here rather than by pandas' `to_csv`
//! (which formats a season's 4 million numbers at ~4 µs each): the importer then reads the text as it reads
//! a file, so the same parsing and refusals apply. Numbers are written in the shortest form that parses back
//! to the same f64 (as `to_csv` writes them); a missing value is an empty cell; a line break inside a text
//! cell becomes a space, so line n + 2 of the text is the frame's row n.

use numpy::PyReadonlyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// One column's cells.
pub enum Cells {
    Floats(Vec<f64>),
    Integers(Vec<i64>),
    Texts(Vec<Option<String>>),
}

impl Cells {
    fn len(&self) -> usize {
        match self {
            Cells::Floats(v) => v.len(),
            Cells::Integers(v) => v.len(),
            Cells::Texts(v) => v.len(),
        }
    }

    fn write(&self, row: usize, out: &mut String) {
        use std::fmt::Write;
        match self {
            Cells::Floats(v) if v[row].is_nan() => {}
            // `{:?}` keeps `.0` on whole numbers, as pandas writes them.
            Cells::Floats(v) => {
                let _ = write!(out, "{:?}", v[row]);
            }
            Cells::Integers(v) => {
                let _ = write!(out, "{}", v[row]);
            }
            Cells::Texts(v) => {
                if let Some(text) = &v[row] {
                    write_text(text, out);
                }
            }
        }
    }
}

/// A text cell on one line, quoted when it holds a comma or a quote (as pandas quotes, minimally).
fn write_text(text: &str, out: &mut String) {
    let mut one_line = String::with_capacity(text.len());
    let mut in_break = false;
    for c in text.chars() {
        if c == '\r' || c == '\n' {
            if !in_break {
                one_line.push(' ');
            }
            in_break = true;
        } else {
            one_line.push(c);
            in_break = false;
        }
    }
    if one_line.contains([',', '"']) {
        out.push('"');
        out.push_str(&one_line.replace('"', "\"\""));
        out.push('"');
    } else {
        out.push_str(&one_line);
    }
}

/// A column from Python: a float64 or int64 numpy array, or a list of str/None.
pub fn cells_of(column: &Bound<'_, PyAny>) -> PyResult<Cells> {
    if let Ok(values) = column.extract::<PyReadonlyArray1<'_, f64>>() {
        return Ok(Cells::Floats(values.as_array().to_vec()));
    }
    if let Ok(values) = column.extract::<PyReadonlyArray1<'_, i64>>() {
        return Ok(Cells::Integers(values.as_array().to_vec()));
    }
    column
        .extract::<Vec<Option<String>>>()
        .map(Cells::Texts)
        .map_err(|_| PyValueError::new_err("a column must be a float64 or int64 array or a list of str/None"))
}

/// The CSV text of `columns` (name, cells), header first.
pub fn csv_text(columns: &[(String, Cells)]) -> PyResult<Vec<u8>> {
    let rows = columns.first().map_or(0, |(_, c)| c.len());
    if let Some((name, _)) = columns.iter().find(|(_, c)| c.len() != rows) {
        return Err(PyValueError::new_err(format!("column {name:?}: not {rows} rows long")));
    }
    let mut out = String::with_capacity(rows * columns.len() * 8);
    for (k, (name, _)) in columns.iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        write_text(name, &mut out);
    }
    out.push('\n');
    for row in 0..rows {
        for (k, (_, cells)) in columns.iter().enumerate() {
            if k > 0 {
                out.push(',');
            }
            cells.write(row, &mut out);
        }
        out.push('\n');
    }
    Ok(out.into_bytes())
}
