//! Aligned text tables and compact numbers, for every command's human-readable output.

/// A plain text table: a header row and right-aligned cells.
#[derive(Debug, Clone, Default)]
pub struct Table {
    headers: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column headers.
    pub fn new<S: Into<String>>(headers: impl IntoIterator<Item = S>) -> Table {
        Table { headers: headers.into_iter().map(Into::into).collect(), rows: Vec::new() }
    }

    /// Appends a row (missing cells are blank, extra cells are kept).
    pub fn row<S: Into<String>>(&mut self, cells: impl IntoIterator<Item = S>) -> &mut Table {
        self.rows.push(cells.into_iter().map(Into::into).collect());
        self
    }

    /// The table as text, columns separated by two spaces; columns of numbers right-aligned, others left.
    pub fn render(&self) -> String {
        let columns = self.rows.iter().map(Vec::len).chain([self.headers.len()]).max().unwrap_or(0);
        let mut widths = vec![0usize; columns];
        for row in std::iter::once(&self.headers).chain(&self.rows) {
            for (i, cell) in row.iter().enumerate() {
                widths[i] = widths[i].max(cell.chars().count());
            }
        }
        // Columns of numbers are right-aligned; a column holding any word (names, lists) is left-aligned.
        let left: Vec<bool> = (0..columns)
            .map(|i| self.rows.iter().any(|r| r.get(i).is_some_and(|c| !c.is_empty() && c.parse::<f64>().is_err())))
            .collect();
        let mut out = String::new();
        let line = |row: &[String], out: &mut String| {
            let mut text = String::new();
            for (i, width) in widths.iter().enumerate() {
                let cell = row.get(i).map(String::as_str).unwrap_or("");
                let pad = width - cell.chars().count();
                if i > 0 {
                    text.push_str("  ");
                }
                if left[i] {
                    text.push_str(cell);
                    text.push_str(&" ".repeat(pad));
                } else {
                    text.push_str(&" ".repeat(pad));
                    text.push_str(cell);
                }
            }
            out.push_str(text.trim_end());
            out.push('\n');
        };
        if !self.headers.is_empty() {
            line(&self.headers, &mut out);
            let rule: Vec<String> = widths.iter().map(|w| "-".repeat(*w)).collect();
            line(&rule, &mut out);
        }
        for row in &self.rows {
            line(row, &mut out);
        }
        out
    }
}

/// A number with `digits` significant digits, in plain or scientific notation as fits.
pub fn num(value: f64, digits: usize) -> String {
    if !value.is_finite() {
        return value.to_string();
    }
    if value == 0.0 {
        return "0".to_string();
    }
    let magnitude = value.abs().log10().floor() as i32;
    if !(-3..6).contains(&magnitude) {
        return format!("{:.*e}", digits.saturating_sub(1), value);
    }
    let decimals = (digits as i32 - 1 - magnitude).max(0) as usize;
    format!("{value:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_compact() {
        assert_eq!(num(0.0, 4), "0");
        assert_eq!(num(1.23456, 4), "1.235");
        assert_eq!(num(123.456, 4), "123.5");
        assert_eq!(num(5e-6, 3), "5.00e-6");
        assert_eq!(num(1.814e10, 4), "1.814e10");
    }

    #[test]
    fn tables_align() {
        let mut t = Table::new(["n", "f (Hz)"]);
        t.row(["1", "177.5"]).row(["10", "2000.0"]);
        assert_eq!(t.render(), " n  f (Hz)\n--  ------\n 1   177.5\n10  2000.0\n");
    }
}
