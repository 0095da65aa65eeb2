//! `import` and `locate` under hostile input and hostile file systems: nothing is lost without being named,
//! nothing is written where it must not be, and nothing a CSV cell holds becomes code or configuration.
//!
//! - A stray `"` in a cell: the csv crate reads on to the next quote or the end of the file, so the lines in
//!   between become one cell. The record is refused as malformed, naming the lines it swallowed, never counted
//!   as a row with a missing value nor read as a swing made of two rows. A row cut short is refused the same.
//! - The refused rows listed are exactly the documented first [`MAX_REFUSALS_LISTED`], and the rest are said
//!   to exist.
//! - `--batter-out`: two ids spelling one file name are refused; a line break in an id stays inside its
//!   comment (the file parses to the same fields).
//! - `import_rows.csv` never holds a cell a spreadsheet runs as a formula (OWASP: a leading `'`).
//! - A full disk (RLIMIT_FSIZE) leaves no partial bag behind: the same `-o` works next time.
//! - `locate --figure` through a symlink onto the bag is refused; a side table with a 50 MB name is refused
//!   by line length, not read whole.
//! - A missing file's OS error is printed once.
//! - A map naming one column for two quantities is refused naming both; a column the header repeats is read
//!   only where its cells agree (Savant's two `pitcher` columns), else the row is refused naming it; a row with
//!   an extra cell is refused as one cut short is; a refused 1e308 is quoted as `4.4704e307`.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;

use sweetspot::import::mapped::ColumnMap;
use sweetspot::import::{import_files, ImportOptions, ImportReport, MAX_REFUSALS_LISTED, ROWS_TABLE};

use support::import::{data, options};

const BIN: &str = env!("CARGO_BIN_EXE_sweetspot");

/// The lines of the real TrackMan rows (CRLF; no quotes in it, so cells split on commas).
fn trackman_lines() -> Vec<String> {
    let text = std::fs::read_to_string(data("trackman_game.csv")).unwrap();
    text.split("\r\n").filter(|l| !l.is_empty()).map(str::to_string).collect()
}

/// Column `name`'s index in the TrackMan header.
fn column(lines: &[String], name: &str) -> usize {
    lines[0].split(',').position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"))
}

/// `line` with cell `col` replaced by `text`.
fn with_cell(line: &str, col: usize, text: &str) -> String {
    let mut cells: Vec<&str> = line.split(',').collect();
    cells[col] = text;
    cells.join(",")
}

/// Writes `lines` (CRLF) to `dir/name` and imports it into `dir/bag_<name>`.
fn import_lines(dir: &Path, name: &str, lines: &[String]) -> ImportReport {
    let csv = dir.join(name);
    std::fs::write(&csv, lines.join("\r\n") + "\r\n").unwrap();
    import_files(&[csv], &dir.join(format!("bag_{name}")), &options()).unwrap()
}

#[test]
fn a_stray_quote_or_a_row_cut_short_is_refused_naming_its_lines() {
    let tmp = tempfile::tempdir().unwrap();
    let lines = trackman_lines();
    let (notes, zone_speed) = (column(&lines, "Notes"), column(&lines, "ZoneSpeed"));
    let intact = import_lines(tmp.path(), "intact.csv", &lines);
    assert_eq!((intact.files[0].rows, intact.swings), (7, 5));
    assert!(intact.refused.is_empty(), "{:?}", intact.refused);
    // File line 5 is the first InPlay row (lines 2–4: a ball, a foul, a swinging strike).
    assert!(lines[4].contains(",InPlay,"));

    // One stray quote at the start of line 5's Notes cell: lines 5–8 become one record.
    let mut one = lines.clone();
    one[4] = with_cell(&lines[4], notes, "\"oops");
    let report = import_lines(tmp.path(), "one_quote.csv", &one);
    let refused = report.refused.join("\n");
    assert_eq!(report.skipped.get("record malformed (refused)"), Some(&1), "{:?}", report.skipped);
    assert!(refused.contains("line 5: malformed record") && refused.contains("never closed"), "{refused}");
    assert!(refused.contains("lines 5–8 read as one record"), "every swallowed line is named: {refused}");
    assert_eq!(report.skipped.get("ZoneSpeed not measured"), None, "not counted as a row without a value");
    assert_eq!(report.files[0].rows, 4, "lines 2, 3, 4 and 5–8");
    assert_eq!(report.swings, intact.swings - 4, "the rows before the quote are read as before");

    // Two stray quotes (lines 5 and 7): the lines between are one cell and the record has the header's
    // length, so only the text after the closing quote tells; it must not become a swing made of two rows.
    let mut two = lines.clone();
    two[4] = with_cell(&lines[4], notes, "\"oops");
    two[6] = with_cell(&lines[6], notes, "\"again");
    let report = import_lines(tmp.path(), "two_quotes.csv", &two);
    let refused = report.refused.join("\n");
    assert!(refused.contains("line 5: malformed record") && refused.contains("closing quote"), "{refused}");
    assert!(refused.contains("lines 5–7 read as one record"), "{refused}");
    assert_eq!(report.files[0].rows, 5, "lines 2, 3, 4, 5–7 and 8");
    assert_eq!(report.swings, intact.swings - 3, "the swings of lines 5–7 are refused, and named");

    // A row cut short before its ZoneSpeed: malformed, not "ZoneSpeed not measured".
    let mut short = lines.clone();
    short[4] = lines[4].split(',').take(zone_speed - 2).collect::<Vec<_>>().join(",");
    let report = import_lines(tmp.path(), "short.csv", &short);
    let refused = report.refused.join("\n");
    assert_eq!(report.skipped.get("record malformed (refused)"), Some(&1), "{:?}", report.skipped);
    assert_eq!(report.skipped.get("ZoneSpeed not measured"), None, "{:?}", report.skipped);
    let expected = format!("line 5: malformed record: has {} cells where the header has 167", zone_speed - 2);
    assert!(refused.contains(&expected), "{refused}");
    assert_eq!(report.swings, intact.swings - 1);
}

#[test]
fn exactly_the_documented_number_of_refusals_is_listed_and_the_rest_is_said() {
    let tmp = tempfile::tempdir().unwrap();
    let lines = trackman_lines();
    let angle = column(&lines, "Angle");
    let mut bad = vec![lines[0].clone(), lines[4].clone()];
    for _ in 0..25 {
        bad.push(with_cell(&lines[4], angle, "high"));
    }
    let report = import_lines(tmp.path(), "bad.csv", &bad);
    assert_eq!(MAX_REFUSALS_LISTED, 20, "the documented number");
    assert_eq!(report.skipped.get("Angle not a number (refused)"), Some(&25));
    assert_eq!(report.refused.len(), MAX_REFUSALS_LISTED, "{:#?}", report.refused);
    assert!(report.refused[19].contains("line 22:"), "the first twenty, in file order: {}", report.refused[19]);
    let csv = tmp.path().join("bad.csv");
    let out = Command::new(BIN).arg("import").arg(&csv).arg("-o").arg(tmp.path().join("cli")).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(stdout.matches("  refused: ").count(), 21, "{stdout}");
    assert!(stdout.contains("… 5 more not listed (the first 20 are)"), "{stdout}");
    assert!(stdout.contains(": trackman export, 26 rows, 1 swing\n"), "one swing, not '1 swings': {stdout}");
    assert!(stdout.contains("1 swing written to "), "{stdout}");
}

/// The Statcast fixture with the batter id of its rows 1 and 4 (the two with bat tracking) replaced.
fn statcast_with_batters(dir: &Path, first: &str, fourth: &str) -> PathBuf {
    let mut reader = csv::Reader::from_path(data("statcast_search.csv")).unwrap();
    let headers = reader.headers().unwrap().clone();
    let batter = headers.iter().position(|h| h == "batter").unwrap();
    let path = dir.join(format!("statcast_{}.csv", first.len() + 7 * fourth.len()));
    let mut writer = csv::Writer::from_path(&path).unwrap();
    writer.write_record(&headers).unwrap();
    for (i, record) in reader.records().enumerate() {
        let mut cells: Vec<String> = record.unwrap().iter().map(str::to_string).collect();
        match i {
            0 => cells[batter] = first.to_string(),
            3 => cells[batter] = fourth.to_string(),
            _ => {}
        }
        writer.write_record(&cells).unwrap();
    }
    writer.flush().unwrap();
    path
}

fn import_batters(csv: &Path, out: &Path, batters: &Path) -> std::process::Output {
    Command::new(BIN).arg("import").arg(csv).arg("-o").arg(out).arg("--batter-out").arg(batters).output().unwrap()
}

#[test]
fn batter_files_never_overwrite_each_other_nor_take_fields_from_an_id() {
    let tmp = tempfile::tempdir().unwrap();
    // "a b" and "a_b" are both batter_a_b.toml.
    let csv = statcast_with_batters(tmp.path(), "a b", "a_b");
    let batters = tmp.path().join("batters");
    let out = import_batters(&csv, &tmp.path().join("bag1"), &batters);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "two batters, one file name: {}", String::from_utf8_lossy(&out.stdout));
    assert!(stderr.contains("\"a b\"") && stderr.contains("\"a_b\"") && stderr.contains("batter_a_b.toml"), "{stderr}");
    assert!(!batters.join("batter_a_b.toml").exists(), "nothing written");

    // A line break in an id: the file parses to the fields the import computed, none from the id.
    let id = "7\nbat_speed = 1.0\n#";
    let csv = statcast_with_batters(tmp.path(), id, "100002");
    let out = import_batters(&csv, &tmp.path().join("bag2"), &batters);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let written = std::fs::read_to_string(batters.join("batter_7_bat_speed___1_0__.toml")).unwrap();
    let spec: toml::Value = toml::from_str(&written).unwrap_or_else(|e| panic!("{e}:\n{written}"));
    // Row 1: 74.5 mph = 33.30448 m/s, swing length 7.4 ft = 2.25552 m.
    let bat_speed = spec["bat_speed"].as_float().unwrap();
    assert!((bat_speed - 33.30448).abs() < 1e-9, "{written}");
    assert!(!written.lines().any(|l| l.starts_with("bat_speed = 1.0")), "{written}");
}

#[test]
fn the_side_table_never_holds_a_formula() {
    let tmp = tempfile::tempdir().unwrap();
    let lines = trackman_lines();
    let (batter, pitcher) = (column(&lines, "Batter"), column(&lines, "Pitcher"));
    let mut hostile = lines.clone();
    for (i, text) in [(4, "=HYPERLINK(\"http://evil.example\")"), (5, "@SUM(A1)"), (6, "+1+2"), (7, "-3+4")] {
        hostile[i] = with_cell(&lines[i], batter, text);
    }
    hostile[4] = with_cell(&hostile[4], pitcher, "=1+1");
    // Commas would split the CSV line: the first one is written quoted, as an export would.
    hostile[4] =
        hostile[4].replace("=HYPERLINK(\"http://evil.example\")", "\"=HYPERLINK(\"\"http://evil.example\"\")\"");
    let report = import_lines(tmp.path(), "hostile.csv", &hostile);
    assert_eq!(report.swings, 5);
    let mut reader = csv::Reader::from_path(tmp.path().join("bag_hostile.csv").join(ROWS_TABLE)).unwrap();
    let headers = reader.headers().unwrap().clone();
    let col = |name: &str| headers.iter().position(|h| h == name).unwrap();
    let mut batters = Vec::new();
    for record in reader.records() {
        let record = record.unwrap();
        for cell in record.iter() {
            assert!(!cell.starts_with(['=', '+', '-', '@']), "a formula in {ROWS_TABLE}: {record:?}");
        }
        batters.push(record[col("batter")].to_string());
        if record[col("line")] == *"5" {
            assert_eq!(&record[col("pitcher")], "'=1+1");
        }
    }
    // The batter column is "NAME (ID)": the escaped name leads it.
    for name in ["'=HYPERLINK(\"http://evil.example\")", "'@SUM(A1)", "'+1+2", "'-3+4"] {
        assert!(batters.iter().any(|b| b.starts_with(&format!("{name} ("))), "{name}: {batters:?}");
    }
}

#[test]
fn a_full_disk_leaves_no_partial_bag_behind() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("full");
    // Files may grow to 2 KiB (RLIMIT_FSIZE; SIGXFSZ ignored so the write fails with EFBIG as on a full disk).
    let out = Command::new("bash")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 2; exec \"$@\"")
        .arg("bash")
        .arg(BIN)
        .arg("import")
        .arg(data("trackman_game.csv"))
        .arg("-o")
        .arg(&bag)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "the bag cannot fit in 2 KiB: {}", String::from_utf8_lossy(&out.stdout));
    assert!(stderr.contains("File too large"), "{stderr}");
    assert!(!bag.exists(), "a partial bag was left at {}", bag.display());
    let out = Command::new(BIN).arg("import").arg(data("trackman_game.csv")).arg("-o").arg(&bag).output().unwrap();
    assert!(out.status.success(), "the same -o again: {}", String::from_utf8_lossy(&out.stderr));
}

/// A bag imported from the real TrackMan rows, and its MCAP file.
fn imported_bag(dir: &Path) -> (PathBuf, PathBuf) {
    let bag = dir.join("game");
    import_files(&[data("trackman_game.csv")], &bag, &options()).unwrap();
    let mcap = std::fs::read_dir(&bag)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "mcap"))
        .unwrap();
    (bag, mcap)
}

#[test]
fn locate_never_writes_its_figure_over_the_bag_nor_reads_a_name_unbounded() {
    let tmp = tempfile::tempdir().unwrap();
    let (bag, mcap) = imported_bag(tmp.path());
    let before = std::fs::read(&mcap).unwrap();
    let link = tmp.path().join("figure.svg");
    std::os::unix::fs::symlink(&mcap, &link).unwrap();
    let out = Command::new(BIN).arg("locate").arg(&bag).arg("--figure").arg(&link).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "a figure written through a symlink onto the bag");
    assert!(stderr.contains("--figure") && stderr.contains("is the input file"), "{stderr}");
    assert_eq!(std::fs::read(&mcap).unwrap(), before, "the bag is unchanged");

    // A side table edited to hold a 50 MB batter name: refused by its line length, the figure not drawn.
    let table = bag.join(ROWS_TABLE);
    let text = std::fs::read_to_string(&table).unwrap();
    let huge = "x".repeat(50 << 20);
    std::fs::write(&table, text.replacen("Batter 05", &huge, 1)).unwrap();
    let figure = tmp.path().join("located.svg");
    let out = Command::new(BIN).arg("locate").arg(&bag).arg("--figure").arg(&figure).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("a line longer than"), "{stderr}");
}

#[test]
fn a_missing_file_is_named_with_its_os_error_once() {
    let tmp = tempfile::tempdir().unwrap();
    let missing = tmp.path().join("missing.toml");
    let out = Command::new(BIN)
        .arg("import")
        .arg(data("trackman_game.csv"))
        .arg("--batter")
        .arg(&missing)
        .arg("-o")
        .arg(tmp.path().join("bag"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(stderr.matches("No such file or directory").count(), 1, "{stderr}");
    assert!(stderr.contains(&missing.display().to_string()), "{stderr}");
}

/// A map file `text` in `dir`, loaded.
fn load_map(dir: &Path, text: &str) -> Result<ColumnMap, String> {
    let path = dir.join("map.toml");
    std::fs::write(&path, text).unwrap();
    ColumnMap::load(&path).map_err(|e| e.to_string())
}

#[test]
fn a_map_naming_one_column_for_two_quantities_is_refused_naming_both() {
    let tmp = tempfile::tempdir().unwrap();
    let error = load_map(tmp.path(), "name = \"t\"\n[columns]\npitch_speed = \"E\"\nexit_speed = \"E\"\n").unwrap_err();
    assert!(error.contains("exit_speed and pitch_speed") && error.contains("\"E\""), "{error}");
    let error =
        load_map(tmp.path(), "name = \"t\"\n[columns]\npitch_speed = \"P\"\nexit_speed = \"E\"\nspin = \"P\"\n")
            .unwrap_err();
    assert!(error.contains("pitch_speed and spin") && error.contains("\"P\""), "{error}");
    // Each quantity in a column of its own: read.
    load_map(tmp.path(), "name = \"t\"\n[columns]\npitch_speed = \"P\"\nexit_speed = \"E\"\n").unwrap();
    // Through the command: refused before any bag is written.
    std::fs::write(tmp.path().join("pe.csv"), "P,E\n80,95\n").unwrap();
    std::fs::write(tmp.path().join("same.toml"), "name = \"t\"\n[columns]\npitch_speed = \"E\"\nexit_speed = \"E\"\n")
        .unwrap();
    let bag = tmp.path().join("bag");
    let out = Command::new(BIN)
        .arg("import")
        .arg("--map")
        .arg(tmp.path().join("same.toml"))
        .arg(tmp.path().join("pe.csv"))
        .arg("-o")
        .arg(&bag)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("both name the column \"E\""), "{stderr}");
    assert!(!bag.exists());
}

#[test]
fn a_column_the_header_repeats_is_read_only_where_its_cells_agree() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("dup.csv");
    // Line 2: the two E cells agree; line 3: they differ; line 4: agree again.
    std::fs::write(&csv, "P,E,E\n80,95,95\n80,95,100\n81,96, 96 \n").unwrap();
    let map = load_map(tmp.path(), "name = \"t\"\n[columns]\npitch_speed = \"P\"\nexit_speed = \"E\"\n").unwrap();
    let mapped = ImportOptions { map: Some(map), ..options() };
    let report = import_files(&[csv], &tmp.path().join("bag"), &mapped).unwrap();
    assert_eq!(report.swings, 2, "lines 2 and 4: {:?}", report.refused);
    assert_eq!(report.refused.len(), 1, "{:?}", report.refused);
    let refused = &report.refused[0];
    assert!(refused.contains("line 3:") && refused.contains("column \"E\" appears 2 times"), "{refused}");
    assert!(refused.contains("\"95\" against \"100\""), "{refused}");

    // Baseball Savant's search CSV names `pitcher` twice, both the pitcher's id: read as before. One row whose
    // second `pitcher` differs is refused, naming the column; the rest are read.
    let mut reader = csv::Reader::from_path(data("statcast_search.csv")).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    let at = header.iter().position(|h| h == "pitcher").unwrap();
    let rows: Vec<Vec<String>> = reader.records().map(|r| r.unwrap().iter().map(String::from).collect()).collect();
    let write = |name: &str, changed: Option<usize>| {
        let path = tmp.path().join(name);
        let mut w = csv::Writer::from_path(&path).unwrap();
        w.write_record(header.iter().chain(["pitcher".to_string()].iter())).unwrap();
        for (i, row) in rows.iter().enumerate() {
            let twin = if Some(i) == changed { "999999".to_string() } else { row[at].clone() };
            w.write_record(row.iter().chain([twin].iter())).unwrap();
        }
        w.flush().unwrap();
        path
    };
    let intact = import_files(&[data("statcast_search.csv")], &tmp.path().join("intact"), &options()).unwrap();
    let twice = import_files(&[write("twice.csv", None)], &tmp.path().join("twice"), &options()).unwrap();
    assert_eq!((twice.swings, twice.refused.len()), (intact.swings, 0), "{:?}", twice.refused);
    let differs = import_files(&[write("differs.csv", Some(0))], &tmp.path().join("differs"), &options()).unwrap();
    assert_eq!(differs.swings, intact.swings - 1);
    assert!(
        differs.refused[0].contains("line 2:") && differs.refused[0].contains("column \"pitcher\""),
        "{:?}",
        differs.refused
    );
}

#[test]
fn a_row_with_an_extra_cell_is_refused_as_one_cut_short_is() {
    let tmp = tempfile::tempdir().unwrap();
    let lines = trackman_lines();
    let intact = import_lines(tmp.path(), "intact.csv", &lines);
    let cells = lines[0].split(',').count();
    // Line 5 (the first InPlay row) with one cell too many, blank or not, and one too few.
    for (name, row) in [
        ("extra.csv", format!("{},x", lines[4])),
        ("blank.csv", format!("{},", lines[4])),
        ("short.csv", lines[4].rsplit_once(',').unwrap().0.to_string()),
    ] {
        let mut edited = lines.clone();
        edited[4] = row;
        let report = import_lines(tmp.path(), name, &edited);
        assert_eq!(report.skipped.get("record malformed (refused)"), Some(&1), "{name}: {:?}", report.skipped);
        assert_eq!(report.swings, intact.swings - 1, "{name}: everything else is read");
        assert!(report.refused[0].contains("line 5: malformed record: has "), "{name}: {:?}", report.refused);
        assert!(report.refused[0].contains(&format!("where the header has {cells}")), "{name}: {:?}", report.refused);
    }
}

#[test]
fn a_refused_number_is_quoted_readably_never_as_three_hundred_digits() {
    let tmp = tempfile::tempdir().unwrap();
    let lines = trackman_lines();
    let exit = column(&lines, "ExitSpeed");
    let mut huge = lines.clone();
    huge[4] = with_cell(&lines[4], exit, "1e308");
    let report = import_lines(tmp.path(), "huge.csv", &huge);
    let refused = &report.refused[0];
    // 1e308 mph × 0.44704 = 4.4704e307 m/s.
    assert!(refused.contains("exit speed gives 4.4704") && refused.contains("e307 (SI units)"), "{refused}");
    assert!(refused.len() < 200, "{} bytes: {refused}", refused.len());
}
