//! The one table mechanism every format reads through: a CSV file opened only if it is a regular file,
//! streamed record by record (one record in memory, each line at most [`MAX_LINE_BYTES`]), its header
//! row (a UTF-8 byte-order mark stripped, names trimmed) mapped to column indexes, and cells read as
//! numbers with the trackers' spellings of "not measured" — blank, `NA`, `NULL`, `null`, `NaN`, `-` — as NaN.
//!
//! The `csv` crate does the quoting (a quoted field may hold commas, quotes doubled, line breaks) and CRLF or
//! LF line ends; what is added here is the file check, the line cap, the header map, the cell rules and the
//! malformed records the crate reads without complaint ([`Row::malformed`]): a record with fewer cells than
//! the header (cut short) or more (an unquoted comma inside a cell shifts every cell after it, and a shifted
//! row whose last cell was blank ends in an empty extra cell, so extra cells are refused whether blank or
//! not), a quote never closed (one stray `"` would make every line after it one cell), and text after a
//! closing quote (two stray quotes joining the lines between them).
//!
//! A header may name a column twice (Baseball Savant's search CSV carries `pitcher` twice, both the
//! pitcher's id). A name read by a format and repeated in the header is read from every place it holds: a
//! record whose cells there agree is read, one whose cells differ is refused ([`Row::malformed`]) naming the
//! column and both cells, since which one is meant is unknown.

use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap, VecDeque};
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::{Path, PathBuf};
use std::rc::Rc;

use super::ImportError;

/// Longest line (bytes between two line feeds) accepted: far beyond any tracker's row (TrackMan's 167
/// columns are ~1.5 KB), small enough that a file without line breaks cannot fill memory.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Cell texts that mean "not measured" (compared after trimming, case-sensitive as the trackers write them).
pub const MISSING: &[&str] = &["", "NA", "N/A", "NULL", "null", "NaN", "nan", "-"];

/// Opens `path` for reading if it is (or a symlink resolves to) a regular file: a directory, FIFO, device or
/// socket is refused before it is opened, so a FIFO never blocks the import.
pub fn open_regular(path: &Path) -> Result<File, ImportError> {
    let io = |error| ImportError::Io { path: path.to_path_buf(), error };
    let meta = std::fs::metadata(path).map_err(io)?;
    if let Some(what) = sweetspot_model::files::not_regular(meta.file_type()) {
        return Err(ImportError::NotRegularFile { path: path.to_path_buf(), what: what.to_string() });
    }
    let file = File::open(path).map_err(io)?;
    sweetspot_model::files::note_input(path, &file.metadata().map_err(io)?);
    Ok(file)
}

/// Where the line breaks are among the bytes read so far, so that a record's line is told exactly.
///
/// The csv crate's own record position counts a record from the end of the previous one: with CRLF lines
/// that is the `\n` left over from the `\r\n` (its line number one short), and before a blank line the blank
/// line too. The byte offset it gives is exact, so the line is counted here from the `\r`/`\n` bytes seen:
/// those at the record's start are skipped, and the record's line is 1 + the `\n` bytes before its first
/// byte of content. Only the breaks of the bytes read ahead (a buffer or two) are held.
#[derive(Debug, Default)]
struct Breaks {
    /// Bytes read so far.
    offset: u64,
    /// Offsets of the `\r` and `\n` bytes at or after the current record's start, and whether each is `\n`.
    pending: VecDeque<(u64, bool)>,
    /// `\n` bytes before the current record's content.
    passed: u64,
}

impl Breaks {
    /// The line (1 = the first) of the first byte of content at or after byte `start`.
    fn line_at(&mut self, start: u64) -> u64 {
        while let Some(&(at, newline)) = self.pending.front() {
            if at >= start {
                break;
            }
            self.passed += u64::from(newline);
            self.pending.pop_front();
        }
        let mut content = start;
        while let Some(&(at, newline)) = self.pending.front() {
            if at != content {
                break;
            }
            self.passed += u64::from(newline);
            self.pending.pop_front();
            content += 1;
        }
        self.passed + 1
    }
}

/// Where the reader is in the quoting, as the csv crate reads it (RFC 4180: a quote opens a cell only at its
/// start; inside, `""` is a quote and a lone `"` closes the cell).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
enum Quoting {
    /// At the start of a cell.
    #[default]
    CellStart,
    /// In a cell that did not start with a quote.
    Unquoted,
    /// In a quoted cell, opened at this byte.
    Quoted(u64),
    /// Just after a quote inside a quoted cell opened at this byte (a close, or the first of `""`).
    QuoteInQuoted(u64),
}

/// Broken quoting found while reading (byte offsets from the start of the input).
#[derive(Debug, Default)]
struct QuoteFaults {
    state: Quoting,
    /// Offsets of text after a closing quote (the closing quote was a stray one, or the opening).
    after_close: VecDeque<u64>,
    /// The input ended inside a quoted cell opened at this byte.
    unclosed: Option<u64>,
}

impl QuoteFaults {
    fn step(&mut self, at: u64, b: u8) {
        let end_of_cell = matches!(b, b',' | b'\n' | b'\r');
        self.state = match self.state {
            Quoting::CellStart if b == b'"' => Quoting::Quoted(at),
            Quoting::CellStart | Quoting::Unquoted if end_of_cell => Quoting::CellStart,
            Quoting::CellStart | Quoting::Unquoted => Quoting::Unquoted,
            Quoting::Quoted(open) if b == b'"' => Quoting::QuoteInQuoted(open),
            Quoting::Quoted(open) => Quoting::Quoted(open),
            Quoting::QuoteInQuoted(open) if b == b'"' => Quoting::Quoted(open),
            Quoting::QuoteInQuoted(_) if end_of_cell => Quoting::CellStart,
            Quoting::QuoteInQuoted(_) => {
                self.after_close.push_back(at);
                Quoting::Unquoted
            }
        };
    }
}

/// A reader that fails once a line grows past `max` bytes, so a record can never be larger than that, and
/// notes where the line breaks are ([`Breaks`]) and where the quoting breaks ([`QuoteFaults`]).
struct LineCap<R> {
    inner: R,
    since_newline: usize,
    max: usize,
    breaks: Rc<RefCell<Breaks>>,
    quotes: Rc<RefCell<QuoteFaults>>,
}

impl<R: Read> Read for LineCap<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        let mut breaks = self.breaks.borrow_mut();
        let mut quotes = self.quotes.borrow_mut();
        let base = breaks.offset;
        if let (0, false, Quoting::Quoted(open)) = (n, buf.is_empty(), quotes.state) {
            quotes.unclosed = Some(open);
        }
        for (i, &b) in buf[..n].iter().enumerate() {
            quotes.step(base + i as u64, b);
            if b == b'\n' || b == b'\r' {
                breaks.pending.push_back((base + i as u64, b == b'\n'));
            }
            if b == b'\n' {
                self.since_newline = 0;
            } else {
                self.since_newline += 1;
                if self.since_newline > self.max {
                    return Err(std::io::Error::new(
                        std::io::ErrorKind::InvalidData,
                        format!("a line longer than {} bytes: not a tracker export", self.max),
                    ));
                }
            }
        }
        breaks.offset += n as u64;
        Ok(n)
    }
}

/// A CSV table being streamed: its header and the current record.
pub struct Table {
    path: PathBuf,
    reader: csv::Reader<LineCap<BufReader<Box<dyn Read>>>>,
    headers: Vec<String>,
    index: HashMap<String, usize>,
    /// Every place of each name the header holds more than once.
    repeated: HashMap<String, Vec<usize>>,
    /// Repeated names a format has looked up ([`Table::column`]): each record's cells there must agree.
    repeated_read: RefCell<BTreeMap<String, Vec<usize>>>,
    record: csv::StringRecord,
    line: u64,
    breaks: Rc<RefCell<Breaks>>,
    quotes: Rc<RefCell<QuoteFaults>>,
    /// Why the current record could not be read (it is then empty).
    unreadable: Option<String>,
    /// Why the current record is malformed, if it is.
    malformed: Option<String>,
}

impl Table {
    /// Opens a regular file and reads its header row.
    pub fn open(path: &Path) -> Result<Table, ImportError> {
        let file = open_regular(path)?;
        Table::from_reader(path, Box::new(file))
    }

    /// Reads the header row of `input`; `path` names it in errors.
    pub fn from_reader(path: &Path, input: Box<dyn Read>) -> Result<Table, ImportError> {
        let breaks = Rc::new(RefCell::new(Breaks::default()));
        let quotes = Rc::new(RefCell::new(QuoteFaults::default()));
        let capped = LineCap {
            inner: BufReader::new(input),
            since_newline: 0,
            max: MAX_LINE_BYTES,
            breaks: breaks.clone(),
            quotes: quotes.clone(),
        };
        let mut reader = csv::ReaderBuilder::new().has_headers(true).flexible(true).from_reader(capped);
        let headers: Vec<String> = reader
            .headers()
            .map_err(|e| csv_error(path, &breaks, e))?
            .iter()
            .enumerate()
            .map(|(i, h)| if i == 0 { h.trim_start_matches('\u{feff}') } else { h }.trim().to_string())
            .collect();
        let mut index = HashMap::new();
        let mut places: HashMap<String, Vec<usize>> = HashMap::new();
        for (i, h) in headers.iter().enumerate() {
            // A repeated name is read at its first place, once every place agrees (see the module docs).
            index.entry(h.clone()).or_insert(i);
            places.entry(h.clone()).or_default().push(i);
        }
        places.retain(|_, at| at.len() > 1);
        Ok(Table {
            path: path.to_path_buf(),
            reader,
            headers,
            index,
            repeated: places,
            repeated_read: RefCell::new(BTreeMap::new()),
            record: csv::StringRecord::new(),
            line: 1,
            breaks,
            quotes,
            unreadable: None,
            malformed: None,
        })
    }

    /// The header names, in file order.
    pub fn headers(&self) -> &[String] {
        &self.headers
    }

    /// The index of column `name`, if the header has it (its first place when the header repeats it: each
    /// record is then checked to hold the same text at every place).
    pub fn column(&self, name: &str) -> Option<usize> {
        if let Some(places) = self.repeated.get(name) {
            self.repeated_read.borrow_mut().insert(name.to_string(), places.clone());
        }
        self.index.get(name).copied()
    }

    /// Advances to the next record; false at the end of the file. A record that is not UTF-8 text is a row
    /// of its own, empty and [`Row::unreadable`], so the rows around it are still read; other errors (I/O, a
    /// line past [`MAX_LINE_BYTES`]) end the file.
    pub fn next_row(&mut self) -> Result<bool, ImportError> {
        self.unreadable = None;
        self.malformed = None;
        match self.reader.read_record(&mut self.record) {
            Ok(more) => {
                if let Some(position) = self.record.position() {
                    self.line = self.breaks.borrow_mut().line_at(position.byte());
                }
                if more {
                    self.malformed = self.malformation();
                }
                Ok(more)
            }
            Err(e) => match csv_error(&self.path, &self.breaks, e) {
                ImportError::Csv { line: Some(line), message, .. } if message.contains(NOT_UTF8) => {
                    self.record.clear();
                    self.line = line;
                    self.unreadable = Some(message);
                    Ok(true)
                }
                other => Err(other),
            },
        }
    }

    /// The current record.
    pub fn row(&self) -> Row<'_> {
        Row {
            record: &self.record,
            line: self.line,
            unreadable: self.unreadable.as_deref(),
            malformed: self.malformed.as_deref(),
        }
    }

    /// What is wrong with the record just read (between its start and the reader's position), if anything.
    fn malformation(&mut self) -> Option<String> {
        let start = self.record.position().map_or(0, csv::Position::byte);
        let end = self.reader.position().byte();
        // Line breaks inside the cells (those ending the file are no line of content).
        let lines = self
            .record
            .iter()
            .map(|cell| cell.trim_end_matches(['\r', '\n']).matches('\n').count() as u64)
            .sum::<u64>();
        let span = if lines > 0 {
            format!(" (lines {}–{} read as one record)", self.line, self.line + lines)
        } else {
            String::new()
        };
        let mut quotes = self.quotes.borrow_mut();
        while quotes.after_close.front().is_some_and(|&at| at < start) {
            quotes.after_close.pop_front();
        }
        if let Some(&at) = quotes.after_close.front().filter(|&&at| at < end) {
            return Some(format!("quoting is broken: text after a closing quote at byte {at}, a stray `\"`{span}"));
        }
        // The crate ends a record in an unclosed quote only at the end of the input, which it has then read.
        if let Some(open) = quotes.unclosed.filter(|&open| open >= start && open < end) {
            return Some(format!(
                "quote at byte {open} is never closed: a stray `\"` makes the rest of the file one cell{span}"
            ));
        }
        drop(quotes);
        let (cells, header) = (self.record.len(), self.headers.len());
        if cells < header {
            return Some(format!("has {cells} cells where the header has {header}: cut short{span}"));
        }
        if cells > header {
            return Some(format!(
                "has {cells} cells where the header has {header}: an extra cell (an unquoted comma shifts the cells \
                 after it){span}"
            ));
        }
        self.disagreement()
    }

    /// Why the record cannot be read at a repeated column a format reads: its cells there differ.
    fn disagreement(&self) -> Option<String> {
        let cell = |i: usize| self.record.get(i).map_or("", str::trim);
        self.repeated_read.borrow().iter().find_map(|(name, places)| {
            let first = places[0];
            let other = places.iter().copied().find(|&i| cell(i) != cell(first))?;
            Some(format!(
                "column \"{}\" appears {} times in the header (columns {} and {}) and this record's cells there \
                 differ ({:?} against {:?}): which one is meant is unknown",
                sweetspot_model::files::echo(name),
                places.len(),
                first + 1,
                other + 1,
                sweetspot_model::files::echo(cell(first)),
                sweetspot_model::files::echo(cell(other))
            ))
        })
    }
}

/// How a record that is not UTF-8 text is described.
const NOT_UTF8: &str = "is not UTF-8 text (tracker exports are)";

/// A record the csv crate could not read, on the line an editor shows (the crate's own is one short on CRLF
/// files, see [`Breaks`]).
fn csv_error(path: &Path, breaks: &RefCell<Breaks>, e: csv::Error) -> ImportError {
    let line = e.position().map(|p| breaks.borrow_mut().line_at(p.byte()));
    let message = match e.kind() {
        csv::ErrorKind::Utf8 { err, .. } => {
            format!("field {} {NOT_UTF8}", err.field() + 1)
        }
        _ => e.to_string(),
    };
    ImportError::Csv { path: path.to_path_buf(), line, message }
}

/// Why a cell could not be read as a number.
#[derive(Debug, Clone, PartialEq)]
pub struct CellError {
    /// The cell's text (cut to 40 bytes).
    pub text: String,
}

/// One record of a [`Table`].
#[derive(Debug, Clone, Copy)]
pub struct Row<'a> {
    record: &'a csv::StringRecord,
    line: u64,
    unreadable: Option<&'a str>,
    malformed: Option<&'a str>,
}

impl<'a> Row<'a> {
    /// Why the record is malformed, if it is: fewer or more cells than the header, a quote never closed, text
    /// after a closing quote, or different cells under one name the header repeats. Its cells are not to be
    /// trusted (a row is refused for it, never read half).
    pub fn malformed(&self) -> Option<&'a str> {
        self.malformed
    }

    /// Why the record could not be read, if it could not (its cells are then all absent).
    pub fn unreadable(&self) -> Option<&'a str> {
        self.unreadable
    }

    /// The line of the file the record starts on (the header is line 1).
    pub fn line(&self) -> u64 {
        self.line
    }

    /// The trimmed text of column `col` ("" when the column is absent or the row short).
    pub fn text(&self, col: Option<usize>) -> &'a str {
        col.and_then(|c| self.record.get(c)).map_or("", str::trim)
    }

    /// Column `col` as a number: NaN when absent or written as "not measured" ([`MISSING`]); an error for any
    /// other text that is not a number (including `inf`).
    pub fn number(&self, col: Option<usize>) -> Result<f64, CellError> {
        let text = self.text(col);
        if MISSING.contains(&text) {
            return Ok(f64::NAN);
        }
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(CellError { text: text.chars().take(40).collect() }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &'static str) -> Table {
        Table::from_reader(Path::new("t.csv"), Box::new(text.as_bytes())).expect("header")
    }

    #[test]
    fn bom_crlf_quotes_and_missing_cells() {
        let mut t = table("\u{feff}a,\"b\",c\r\n1.5,\"x, y\",NA\r\n-,,2e3\r\n");
        assert_eq!(t.headers(), ["a", "b", "c"]);
        assert!(t.next_row().unwrap());
        let (a, b, c) = (t.column("a"), t.column("b"), t.column("c"));
        assert_eq!(t.row().number(a).unwrap(), 1.5);
        assert_eq!(t.row().text(b), "x, y");
        assert!(t.row().number(c).unwrap().is_nan());
        assert_eq!(t.row().line(), 2);
        assert!(t.next_row().unwrap());
        assert!(t.row().number(a).unwrap().is_nan());
        assert!(t.row().number(b).unwrap().is_nan());
        assert_eq!(t.row().number(c).unwrap(), 2000.0);
        assert!(t.row().number(None).unwrap().is_nan());
        assert!(!t.next_row().unwrap());
    }

    /// The line of each record as an editor shows it, whatever the line ends: LF, CRLF, a BOM, a blank line
    /// (skipped) and a quoted cell over two lines.
    #[test]
    fn each_record_is_on_the_line_an_editor_shows() {
        let lines = |text: &'static str| {
            let mut t = table(text);
            let mut out = Vec::new();
            while t.next_row().unwrap() {
                out.push(t.row().line());
            }
            out
        };
        assert_eq!(lines("h1,h2\n1,2\n3,4\n\n5,6\n"), [2, 3, 5]);
        assert_eq!(lines("\u{feff}h1,h2\r\n1,2\r\n3,4\r\n\r\n5,6"), [2, 3, 5]);
        assert_eq!(lines("h1,h2\n\"a\nb\",2\n3,4\n"), [2, 4]);
        assert_eq!(lines("h1,h2\r\n\"a\r\nb\",2\r\n3,4\r\n"), [2, 4]);
    }

    /// A record that is not UTF-8 is a row of its own, unreadable, on the line an editor shows (CRLF or LF),
    /// and the rows after it are still read.
    #[test]
    fn an_unreadable_record_is_named_by_its_editor_line_and_reading_goes_on() {
        for text in [&b"h1,h2\r\n1,2\r\n3,\xff\r\n5,6\r\n"[..], &b"h1,h2\n1,2\n3,\xff\n5,6\n"[..]] {
            let mut t = Table::from_reader(Path::new("t.csv"), Box::new(std::io::Cursor::new(text.to_vec()))).unwrap();
            assert!(t.next_row().unwrap());
            assert_eq!(t.row().unreadable(), None);
            assert!(t.next_row().unwrap());
            let (line, why) = (t.row().line(), t.row().unreadable().expect("unreadable"));
            assert_eq!(line, 3, "{why}");
            assert!(why.starts_with("field 2 "), "{why}");
            assert_eq!(t.row().text(Some(0)), "", "no cell of a broken record is read");
            assert!(t.next_row().unwrap());
            assert_eq!((t.row().line(), t.row().text(Some(1)), t.row().unreadable()), (4, "6", None));
            assert!(!t.next_row().unwrap());
        }
    }

    /// Quoted cells over several lines are sound; a quote never closed, text after a closing quote and a row
    /// with fewer cells than the header are malformed, named with the lines they span.
    #[test]
    fn stray_quotes_and_short_rows_are_malformed() {
        let malformed = |text: &'static str| {
            let mut t = table(text);
            let mut out = Vec::new();
            while t.next_row().unwrap() {
                out.push((t.row().line(), t.row().malformed().map(str::to_string)));
            }
            out
        };
        let sound = malformed("a,b\n\"x\ny\",1\n\"q \"\"z\"\"\",2\n");
        assert_eq!(sound, [(2, None), (4, None)]);
        let rows = malformed("a,b,c\n1,\"oops,3\n4,5,6\n7,8,9\n");
        assert_eq!(rows.len(), 1, "{rows:?}");
        let why = rows[0].1.as_deref().expect("malformed");
        assert!(why.contains("never closed") && why.contains("lines 2–4 read as one record"), "{why}");
        let rows = malformed("a,b,c\r\n1,\"oops,3\r\n4,5,6\r\n7,8\"x,9\r\n10,11,12\r\n");
        assert_eq!(rows.len(), 2, "{rows:?}");
        let why = rows[0].1.as_deref().expect("malformed");
        assert!(why.contains("after a closing quote") && why.contains("lines 2–4"), "{why}");
        assert_eq!(rows[1], (5, None));
        let rows = malformed("a,b,c\n1,2\n4,5,6\n");
        assert_eq!(rows[0], (2, Some("has 2 cells where the header has 3: cut short".to_string())));
        assert_eq!(rows[1], (3, None));
    }

    #[test]
    fn garbage_and_infinities_are_errors_not_nan() {
        let mut t = table("a,b\nfast,inf\n");
        assert!(t.next_row().unwrap());
        assert_eq!(t.row().number(t.column("a")).unwrap_err().text, "fast");
        assert!(t.row().number(t.column("b")).is_err());
    }

    #[test]
    fn an_endless_line_is_refused_not_buffered() {
        let long = format!("a,b\n{}\n", "9".repeat(MAX_LINE_BYTES + 10));
        let mut t = Table::from_reader(Path::new("t.csv"), Box::new(std::io::Cursor::new(long))).unwrap();
        let err = t.next_row().unwrap_err().to_string();
        assert!(err.contains("longer than"), "{err}");
    }
}
