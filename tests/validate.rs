//! `sweetspot validate` run as a process: every row gets a verdict, the exit status is non-zero exactly when a
//! row fails, `--json` parses, the TrackMan medians are those of the copied rows (computed here independently,
//! with a plain sort and the textbook median), the tolerances are the ones the sources state (pinned here, so
//! a loosened row fails), and the rows that agree with measurement today keep agreeing.

mod support;

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;
use support::cli::{num, s, sweetspot};

/// Rows inside their tolerance today: a model change that pushes one out fails this test.
const GREEN: &[&str] = &[
    "q-statcast-max",
    "mlb-ball-cor-58mph",
    "bbcor-wood",
    "wood-first-bending-mode",
    "wood-first-node",
    "alloy-hoop-frequency",
    "spin-vs-incoming-spin",
    "game-spin-20deg",
    // Green since μ = 0.15 (Nathan et al. 2012's sliding friction; docs/physics-spin.md).
    "tee-spin-63mph",
    "bpf-falls-with-hoop-frequency",
    "field-performance-falls-with-hoop-frequency",
];

/// Rows outside their tolerance today (README, "Validation against measurement", says why). They may turn
/// green through the model, never through their tolerance (pinned in [`BOUNDS`]).
const RED: &[&str] = &[
    "q-sweet-spot",
    "bpf-youth-limit-reached",
    "tee-spin-88mph",
    "game-spin-10deg",
    "game-spin-30deg",
    "cage-metal-minus-wood",
    "sweet-spot-same-distance",
    "contact-time-game",
    "besr-wood-max-exit",
];

/// (id, low, high) as the sources state them (see validation/measurements.toml); `None`: no bound that side.
const BOUNDS: &[(&str, Option<f64>, Option<f64>)] = &[
    ("q-sweet-spot", Some(0.10), Some(0.20)),
    ("q-statcast-max", Some(0.20), Some(0.23)),
    ("mlb-ball-cor-58mph", Some(0.514), Some(0.578)),
    ("bbcor-wood", None, Some(0.50)),
    ("wood-first-bending-mode", Some(153.0), Some(187.0)),
    ("wood-first-node", Some(5.0), Some(7.0)),
    ("alloy-hoop-frequency", Some(1000.0), Some(2500.0)),
    ("tee-spin-88mph", None, Some(3500.0)),
    ("tee-spin-63mph", None, Some(3500.0)),
    ("spin-vs-incoming-spin", Some(-0.1), Some(0.1)),
    ("bpf-falls-with-hoop-frequency", None, Some(0.0)),
    ("field-performance-falls-with-hoop-frequency", None, Some(0.0)),
    ("bpf-youth-limit-reached", None, Some(1.15)),
    ("cage-metal-minus-wood", Some(5.0), Some(9.0)),
    ("sweet-spot-same-distance", Some(-1.0), Some(1.0)),
    ("contact-time-game", Some(0.6), Some(0.8)),
    ("besr-wood-max-exit", None, Some(97.0)),
];

fn opt(v: &Value) -> Option<f64> {
    v.as_f64()
}

/// The median of `values` by the textbook rule: the middle value, or the mean of the two middle ones.
fn textbook_median(mut values: Vec<f64>) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(|a, b| a.partial_cmp(b).expect("finite spins"));
    let n = values.len();
    Some(if n % 2 == 1 { values[n / 2] } else { 0.5 * (values[n / 2 - 1] + values[n / 2]) })
}

/// Spins of balls in play tracked with High or Medium launch confidence, launched within 5° of `center`,
/// read from the CSV with plain string splitting (the file has no quoted cells).
fn spins_near(csv: &str, center: f64) -> Vec<f64> {
    balls_near(csv, center).into_iter().map(|(spin, _)| spin).collect()
}

/// (spin rpm, exit speed mph if tracked) of the tracked balls in play launched within 5° of `center`.
fn balls_near(csv: &str, center: f64) -> Vec<(f64, Option<f64>)> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let (call, angle, spin, conf) = (col("PitchCall"), col("Angle"), col("HitSpinRate"), col("HitLaunchConfidence"));
    let exit = col("ExitSpeed");
    lines
        .filter_map(|line| {
            let cells: Vec<&str> = line.split(',').collect();
            assert!(!line.contains('"'), "quoted cell in {line}");
            if cells[call] != "InPlay" || !(cells[conf] == "High" || cells[conf] == "Medium") {
                return None;
            }
            let a: f64 = cells[angle].parse().ok()?;
            let sp: f64 = cells[spin].parse().ok()?;
            ((a - center).abs() <= 5.0).then_some((sp, cells[exit].parse().ok()))
        })
        .collect()
}

fn run_json(args: &[&str]) -> (bool, Value, String) {
    let run = sweetspot(args);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    let doc: Value = serde_json::from_str(&run.stdout)
        .unwrap_or_else(|e| panic!("stdout of {args:?} is not JSON ({e}):\n{}\n{}", run.stdout, run.stderr));
    (run.status_ok, doc, run.stderr)
}

#[test]
fn the_suite_judges_every_row_and_fails_exactly_when_one_is_outside_its_tolerance() {
    let figures = tempfile::tempdir().unwrap();
    let (ok, doc, stderr) = run_json(&["validate", "--json", "--figures", s(figures.path())]);
    let rows = doc["rows"].as_array().expect("rows");
    assert!(rows.len() >= GREEN.len() + RED.len(), "{} rows", rows.len());
    let mut verdicts = BTreeMap::new();
    for r in rows {
        let id = r["id"].as_str().expect("id");
        let verdict = r["verdict"].as_str().expect("verdict");
        assert!(["PASS", "FAIL", "N/A"].contains(&verdict), "{id}: {verdict}");
        // A model number and a ratio go with every judged row; a row is FAIL only with a number.
        if verdict != "N/A" {
            assert!(opt(&r["model"]).is_some(), "{id} judged without a model number");
        }
        // The verdict follows the bounds, judged here from the JSON alone: a model number outside them is FAIL.
        if let Some(m) = opt(&r["model"]) {
            let (lo, hi) = (opt(&r["low"]), opt(&r["high"]));
            let expected = match r["rule"].as_str().expect("rule") {
                "range" | "within" | "trackman_iqr" => lo.zip(hi).map(|(lo, hi)| lo <= m && m <= hi),
                "at_most" => hi.map(|hi| m <= hi),
                "at_least" => lo.map(|lo| m >= lo),
                other => panic!("{id}: unknown rule {other}"),
            };
            let expected = expected.map_or("N/A", |inside| if inside { "PASS" } else { "FAIL" });
            assert_eq!(verdict, expected, "{id}: model {m} against {lo:?}–{hi:?}");
        }
        for key in ["quantity", "source", "read_from", "tolerance", "conditions"] {
            assert!(!r[key].as_str().unwrap_or("").is_empty(), "{id}: empty {key}");
        }
        verdicts.insert(id.to_string(), verdict.to_string());
    }
    let fails = verdicts.values().filter(|v| *v == "FAIL").count();
    assert_eq!(num(&doc, "/fail") as usize, fails);
    assert_eq!(ok, fails == 0, "exit status {ok} with {fails} FAIL rows; stderr: {stderr}");
    if fails > 0 {
        assert!(stderr.contains("outside their stated tolerance"), "{stderr}");
    }
    for id in GREEN {
        assert_eq!(verdicts.get(*id).map(String::as_str), Some("PASS"), "{id} no longer agrees with measurement");
    }
    // The collegiate TrackMan spin rows (docs/validation.md): sidespin agrees, backspin is too high, and below
    // 10° no swing of the scan launches at the bin's median.
    for (id, verdict) in [
        ("trackman-backspin/launch-90to10deg", "N/A"),
        ("trackman-sidespin/launch-90to10deg", "N/A"),
        ("trackman-backspin/launch10to20deg", "FAIL"),
        ("trackman-sidespin/launch10to20deg", "PASS"),
        ("trackman-backspin/launch20to90deg", "FAIL"),
        ("trackman-sidespin/launch20to90deg", "PASS"),
    ] {
        assert_eq!(verdicts.get(id).map(String::as_str), Some(verdict), "{id}");
    }
    for id in verdicts.keys() {
        let joined = id.starts_with("ball-cor")
            || id.starts_with("statcast-q/")
            || id.starts_with("statcast-undercut/")
            || id.starts_with("radar-spin/")
            || id.starts_with("trackman-backspin/")
            || id.starts_with("trackman-sidespin/")
            || rows.iter().any(|r| r["id"] == id.as_str() && r["note"] == "from validation/ball_cor.toml");
        assert!(joined || GREEN.contains(&id.as_str()) || RED.contains(&id.as_str()), "row {id} is in neither list");
    }
    // The tolerances are the sources' (a loosened row fails here).
    for (id, low, high) in BOUNDS {
        let r = rows.iter().find(|r| r["id"] == *id).unwrap_or_else(|| panic!("no row {id}"));
        assert_eq!(opt(&r["low"]), *low, "{id}: low bound changed");
        assert_eq!(opt(&r["high"]), *high, "{id}: high bound changed");
    }
    // The Statcast q rows: one per season bin of the batter's median bat speed and of the plate pitch speed,
    // bounded by the bin's 97th and 99.8th percentiles as the table states them (read here with plain string
    // splitting), and all inside with the game ball fitted to the odd half of the season.
    let table = std::fs::read_to_string(support::repo().join("validation/statcast_q.csv")).unwrap();
    let mut lines = table.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let mut statcast_rows = 0;
    for line in lines {
        let c: Vec<&str> = line.split(',').collect();
        if c[col("half")] != "all" || !["batter_median_bat", "plate_pitch"].contains(&c[col("by")]) {
            continue;
        }
        let id = format!("statcast-q/{}-{}-{}", c[col("by")].replace('_', "-"), c[col("low")], c[col("high")]);
        let r = rows.iter().find(|r| r["id"] == id.as_str()).unwrap_or_else(|| panic!("no row {id}"));
        let p = |name: &str| c[col(name)].parse::<f64>().unwrap();
        assert_eq!(opt(&r["low"]), Some(p("q_p97")), "{id}: low bound");
        assert_eq!(opt(&r["high"]), Some(p("q_p99_8")), "{id}: high bound");
        assert_eq!(r["verdict"], "PASS", "{id}: {r}");
        statcast_rows += 1;
    }
    assert_eq!(statcast_rows, 11);
    assert_eq!(rows.iter().filter(|r| r["id"].as_str().is_some_and(|i| i.starts_with("statcast-q/"))).count(), 11);
    // The exit-speed-against-undercut rows: one per bin of launch − attack angle, bounded by the 95 % interval
    // of the ratio of 99th percentiles (the bin's interval over the peak bin's, as the table states them), and
    // inside it everywhere but on the topspin side at −25…−15°, where the model keeps ~2 % too much exit speed
    // today (docs/statcast.md).
    let table = std::fs::read_to_string(support::repo().join("validation/statcast_exit_undercut.csv")).unwrap();
    let mut lines = table.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let bins: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let p = |c: &Vec<&str>, name: &str| c[col(name)].parse::<f64>().unwrap();
    let peak = bins.iter().max_by(|a, b| p(a, "exit_p99_mph").total_cmp(&p(b, "exit_p99_mph"))).expect("bins");
    const UNDERCUT_RED: &[&str] = &["statcast-undercut/-25--20", "statcast-undercut/-20--15"];
    for c in &bins {
        let id = format!("statcast-undercut/{}-{}", c[col("low_deg")], c[col("high_deg")]);
        let r = rows.iter().find(|r| r["id"] == id.as_str()).unwrap_or_else(|| panic!("no row {id}"));
        let low = p(c, "exit_p99_ci_low_mph") / p(peak, "exit_p99_ci_high_mph");
        let high = p(c, "exit_p99_ci_high_mph") / p(peak, "exit_p99_ci_low_mph");
        assert!((opt(&r["low"]).unwrap() - low).abs() < 1e-12, "{id}: low bound {} vs {low}", r["low"]);
        assert!((opt(&r["high"]).unwrap() - high).abs() < 1e-12, "{id}: high bound {} vs {high}", r["high"]);
        // The red ones may turn green through the model, never through their band.
        if !UNDERCUT_RED.contains(&id.as_str()) {
            assert_eq!(r["verdict"], "PASS", "{id}: {r}");
        }
    }
    assert_eq!(bins.len(), 20);
    // The radar rows: one per 5° launch bin from 5° to 45°, bounded by the radar's interquartile range cut to
    // ±12 % of its median (the table's numbers, read here with plain string splitting). Green today: 5°, 40°
    // and 45°; red at 10–35°, where the model spins the ball 1.2–1.5× the radar's median (docs/physics-spin.md).
    let table = std::fs::read_to_string(support::repo().join("validation/mlb2018_radar_spin.csv")).unwrap();
    let mut lines = table.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let mut radar_rows = 0;
    for line in lines {
        let c: Vec<&str> = line.split(',').collect();
        let p = |name: &str| c[col(name)].parse::<f64>().unwrap();
        let id = format!("radar-spin/{}deg", c[col("launch_deg")]);
        let r = rows.iter().find(|r| r["id"] == id.as_str()).unwrap_or_else(|| panic!("no row {id}"));
        let median = p("spin_median_rpm");
        assert_eq!(opt(&r["reference"]), Some(median), "{id}: reference");
        assert_eq!(opt(&r["low"]), Some(p("spin_q1_rpm").max(0.88 * median)), "{id}: low bound");
        assert_eq!(opt(&r["high"]), Some(p("spin_q3_rpm").min(1.12 * median)), "{id}: high bound");
        let green = ["radar-spin/5deg", "radar-spin/40deg", "radar-spin/45deg"].contains(&id.as_str());
        assert_eq!(r["verdict"], if green { "PASS" } else { "FAIL" }, "{id}: {r}");
        radar_rows += 1;
    }
    assert_eq!(radar_rows, 9);
    // The four figures were drawn.
    for name in [
        "validate-cor-vs-speed",
        "validate-spin-vs-launch",
        "validate-bpf-vs-hoop",
        "validate-exit-vs-impact",
        "validate-radar-spin-vs-launch",
        "validate-spin-axis-clock",
    ] {
        let path = figures.path().join(format!("{name}.svg"));
        let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
        assert!(size > 1000, "{} missing or empty", path.display());
    }
}

#[test]
fn trackman_medians_are_those_of_the_copied_rows() {
    let csv = std::fs::read_to_string(support::repo().join("validation/trackman_spin.csv")).unwrap();
    let (_, doc, _) = run_json(&["validate", "--json", "--modes", "4"]);
    let bins = doc["trackman_bins"].as_array().expect("trackman_bins");
    assert_eq!(bins.len(), 3);
    for (bin, center) in bins.iter().zip([10.0, 20.0, 30.0]) {
        assert_eq!(num(bin, "/launch_deg"), center);
        let spins = spins_near(&csv, center);
        assert_eq!(num(bin, "/count") as usize, spins.len(), "bin {center}");
        let expected = textbook_median(spins).expect("a non-empty bin");
        assert!((num(bin, "/median_rpm") - expected).abs() < 1e-9, "bin {center}: {bin}");
        // The row's reference is that median.
        let id = format!("game-spin-{center:.0}deg");
        let row = doc["rows"].as_array().unwrap().iter().find(|r| r["id"] == id.as_str()).expect("row");
        assert!((num(row, "/reference") - expected).abs() < 1e-9, "{id}");
        // The model's swing leaves the ball at the bin's median exit speed (the exports carry no bat speed).
        let exits = balls_near(&csv, center).into_iter().filter_map(|(_, exit)| exit).collect();
        let exit = textbook_median(exits).expect("exit speeds in the bin");
        assert!((num(bin, "/median_exit_speed_mph") - exit).abs() < 1e-9, "bin {center}: {bin}");
        let detail = row["model_detail"].as_str().expect("model_detail");
        assert!(detail.contains(&format!("exit {exit:.1} mph")), "{id}: {detail} (bin median {exit} mph)");
    }
}

fn write_suite(dir: &Path, rows: &str) {
    std::fs::write(dir.join("measurements.toml"), rows).unwrap();
    std::fs::copy(support::repo().join("validation/trackman_spin.csv"), dir.join("trackman_spin.csv")).unwrap();
}

#[test]
fn exit_status_follows_the_verdicts_and_ball_cor_rows_join() {
    // One row that any bat passes (a first bending mode between 1 Hz and 100 kHz) and a ball COR row built
    // from the game ball's own constant e0 = 0.53 at a slow speed: exit 0.
    let green = tempfile::tempdir().unwrap();
    write_suite(
        green.path(),
        r#"[[row]]
id = "any-mode"
quantity = "first bending mode"
case = "first_mode_hz"
unit = "Hz"
conditions = "test"
rule = "range"
low = 1.0
high = 100000.0
tolerance = "test"
source = "test"
read_from = "text"
[row.params]
bat = "r161"
"#,
    );
    let (ok, doc, stderr) = run_json(&["validate", "--json", "--modes", "4", "--data", s(green.path())]);
    assert!(ok, "{stderr}");
    assert_eq!(doc["rows"].as_array().unwrap().len(), 1);
    assert_eq!(doc["rows"][0]["verdict"], "PASS");

    // Add a row no bat can meet (BBCOR at most 0.1) and a joined ball-COR row without uncertainty: exit ≠ 0,
    // the joined row is there with N/A.
    let red = tempfile::tempdir().unwrap();
    write_suite(
        red.path(),
        r#"[[row]]
id = "impossible"
quantity = "BBCOR"
case = "bbcor"
unit = "1"
conditions = "test"
rule = "at_most"
high = 0.1
tolerance = "test"
source = "test"
read_from = "text"
[row.params]
bat = "r161"
ball = "bbcor"
"#,
    );
    std::fs::write(
        red.path().join("ball_cor.toml"),
        "[[point]]\nid = \"x\"\nquantity = \"COR\"\nspeed = 85.0\nspeed_unit = \"ft/s\"\nvalue = 0.55\ntarget = \"ash\"\nsource = \"test\"\nread_from = \"text\"\n\n[[point]]\nid = \"no-value\"\nhigh = 0.5\nspeed = 60.0\n\n[[fact]]\nstatement = \"ignored\"\n",
    )
    .unwrap();
    let (ok, doc, stderr) = run_json(&["validate", "--json", "--modes", "4", "--data", s(red.path())]);
    assert!(!ok, "a FAIL row must make the exit status non-zero");
    assert!(stderr.contains("1 of 2 rows outside their stated tolerance"), "{stderr}");
    // The last line says what a red row means, so a new user does not read it as a broken install.
    assert!(
        stderr.contains("disagrees with a published measurement") && stderr.contains("The install works"),
        "{stderr}"
    );
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows[0]["verdict"], "FAIL");
    assert_eq!(rows.len(), 2, "a point without a value is not a COR row");
    assert_eq!(rows[1]["id"], "ball-cor/x");
    assert_eq!(rows[1]["verdict"], "N/A");
    // 85 ft/s = 25.908 m/s, converted by the loader.
    assert!(rows[1]["conditions"].as_str().unwrap().contains("25.91 m/s"), "{}", rows[1]);
}

#[test]
fn the_table_names_every_row_with_its_verdict() {
    let run = sweetspot(&["validate", "--modes", "4"]);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    for id in GREEN.iter().chain(RED) {
        let line = run
            .stdout
            .lines()
            .find(|l| l.split_whitespace().next() == Some(id))
            .unwrap_or_else(|| panic!("no line for {id}:\n{}", run.stdout));
        assert!(line.contains("PASS") || line.contains("FAIL") || line.contains("N/A"), "{line}");
    }
    assert!(run.stdout.contains("rows:"), "{}", run.stdout);
    // Two rows of one range (MLB's 0.514–0.578) divide by different stated values, a sample's mean and the
    // spec's centre: the measured column shows each, so their ratios differ visibly for a reason.
    let line = |id: &str| run.stdout.lines().find(|l| l.starts_with(id)).unwrap_or_default().to_string();
    assert!(line("mlb-ball-cor-58mph ").contains("0.5500 (0.5140–0.5780)"), "{}", line("mlb-ball-cor-58mph "));
    // The spec's centre is the range's midpoint, so that row shows the range alone.
    let spec = line("ball-cor/mlb-spec ");
    assert!(spec.contains("0.5140–0.5780") && !spec.contains("(0.5140"), "{spec}");
}

/// The commands (`$ ` lines) of docs/validation.md's blocks, trailing `# comment` dropped.
fn documented_lines() -> Vec<String> {
    let page = std::fs::read_to_string(support::repo().join("docs/validation.md")).unwrap();
    page.lines()
        .filter_map(|l| l.trim().strip_prefix("$ "))
        .map(|t| match t.find(" #") {
            Some(i) => t[..i].trim_end().to_string(),
            None => t.to_string(),
        })
        .collect()
}

#[test]
fn the_documented_commands_run_from_any_directory() {
    let lines = documented_lines();
    assert!(!lines.is_empty(), "docs/validation.md shows no command");
    let dir = tempfile::tempdir().unwrap();
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_sweetspot")).parent().expect("binary directory").to_path_buf();
    let mut dirs = vec![bin_dir];
    dirs.extend(std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()));
    for line in &lines {
        // From a directory without validation/: the suite finds its data in the source tree.
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg(line)
            .current_dir(dir.path())
            .env("PATH", std::env::join_paths(&dirs).unwrap())
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{line}: {stderr}");
        // Exit 0, or the suite's own verdict (red rows), never an argument or data error.
        assert!(out.status.success() || stderr.contains("outside their stated tolerance"), "{line}: {stderr}");
        if line.contains("--json") {
            let doc: Value = serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{line}: not JSON ({e})"));
            assert!(doc["rows"].as_array().is_some_and(|r| !r.is_empty()));
            assert!(dir.path().join("validation-figures/validate-spin-vs-launch.svg").is_file());
        } else {
            assert!(stdout.contains("rows:"), "{line}: {stdout}");
        }
    }
}

/// Every rule judged at, inside and beyond its bounds: on a bound is PASS, a hair outside is FAIL, on either
/// side (catches `lo <= m && m <= hi` turned into `||`, and a bound compared the wrong way).
#[test]
fn every_rule_is_judged_on_and_beyond_its_bounds() {
    use sweetspot::validate::{judge, Rule, Verdict};
    let (lo, hi) = (2.0, 3.0);
    let eps = 1e-9;
    for rule in [Rule::Range, Rule::Within, Rule::TrackmanIqr] {
        for (m, v) in [
            (lo, Verdict::Pass),
            (hi, Verdict::Pass),
            (2.5, Verdict::Pass),
            (lo - eps, Verdict::Fail),
            (hi + eps, Verdict::Fail),
            (-10.0, Verdict::Fail),
            (10.0, Verdict::Fail),
        ] {
            assert_eq!(judge(rule, Some(m), Some(lo), Some(hi)), v, "{rule:?} at {m}");
        }
        assert_eq!(judge(rule, Some(2.5), None, Some(hi)), Verdict::NotApplicable, "{rule:?} without low");
        assert_eq!(judge(rule, Some(2.5), Some(lo), None), Verdict::NotApplicable, "{rule:?} without high");
    }
    for (m, v) in [(hi, Verdict::Pass), (hi - 1.0, Verdict::Pass), (hi + eps, Verdict::Fail), (1e9, Verdict::Fail)] {
        assert_eq!(judge(Rule::AtMost, Some(m), None, Some(hi)), v, "at_most at {m}");
        // A low bound does not matter to at_most.
        assert_eq!(judge(Rule::AtMost, Some(m), Some(hi + 100.0), Some(hi)), v, "at_most at {m} with a low");
    }
    assert_eq!(judge(Rule::AtMost, Some(1.0), Some(0.0), None), Verdict::NotApplicable);
    for (m, v) in [(lo, Verdict::Pass), (lo + 1.0, Verdict::Pass), (lo - eps, Verdict::Fail), (-1e9, Verdict::Fail)] {
        assert_eq!(judge(Rule::AtLeast, Some(m), None, Some(lo)).label(), "N/A");
        assert_eq!(judge(Rule::AtLeast, Some(m), Some(lo), None), v, "at_least at {m}");
        assert_eq!(judge(Rule::AtLeast, Some(m), Some(lo), Some(lo - 100.0)), v, "at_least at {m} with a high");
    }
    // No model number, or not a finite one: N/A, whatever the bounds.
    for m in [None, Some(f64::NAN), Some(f64::INFINITY)] {
        assert_eq!(judge(Rule::Range, m, Some(lo), Some(hi)), Verdict::NotApplicable);
    }
}

/// The rows an oblique contact law can move: everything with a tangential impulse in it.
fn is_oblique(id: &str) -> bool {
    id.starts_with("tee-spin-")
        || id.starts_with("game-spin-")
        || id.starts_with("statcast-undercut/")
        || id.starts_with("radar-spin/")
        || id == "spin-vs-incoming-spin"
}

#[test]
fn the_compliant_contact_law_moves_the_oblique_rows_only_and_does_not_close_the_spin_gap() {
    let (_, default, _) = run_json(&["validate", "--json"]);
    let (ok, compliant, stderr) = run_json(&["validate", "--json", "--tangential-stiffness-ratio", "4.75"]);
    let rows = |doc: &Value| -> BTreeMap<String, Value> {
        doc["rows"]
            .as_array()
            .expect("rows")
            .iter()
            .map(|r| (r["id"].as_str().unwrap().to_string(), r.clone()))
            .collect()
    };
    let (before, after) = (rows(&default), rows(&compliant));
    assert_eq!(before.keys().collect::<Vec<_>>(), after.keys().collect::<Vec<_>>());
    let mut undercut_moved = 0;
    for (id, row) in &before {
        let moved = row["model"] != after[id]["model"];
        if id.starts_with("statcast-undercut/") {
            // The bin the ratios are taken against stays at 1.
            undercut_moved += usize::from(moved);
        } else if is_oblique(id) {
            assert!(moved, "{id} did not move with the tangential law");
        } else if id.starts_with("trackman-backspin/") || id.starts_with("trackman-sidespin/") {
            // Spin rows of the 3-D model: they move, unless no swing reaches the bin (N/A either way).
            assert!(moved || row["model"].is_null(), "{id} did not move with the tangential law");
        } else {
            assert_eq!(row, &after[id], "{id} moved with the tangential law");
        }
    }
    assert!(undercut_moved >= 19, "{undercut_moved} undercut rows moved");
    // What docs/physics-spin.md reports, judged by the suite against the measurements: the gap at 30° stays,
    // and the law's e_T, which falls with incidence, makes the outgoing spin follow the incoming one on a
    // fixed cylinder, which Nathan et al. 2012 measured it does not.
    let verdict = |id: &str| after[id]["verdict"].as_str().unwrap().to_string();
    assert_eq!(verdict("game-spin-30deg"), "FAIL");
    assert_eq!(verdict("spin-vs-incoming-spin"), "FAIL");
    assert!(!ok && stderr.contains("outside their stated tolerance"), "{stderr}");
    // The report says which law it ran.
    assert_eq!(compliant["contact"]["stiffness_ratio"].as_f64(), Some(4.75));
    assert!(default["contact"].get("stiffness_ratio").is_none(), "{}", default["contact"]);
    assert_eq!(default["contact"]["tangential_cor"].as_f64(), Some(0.405));
    let text = sweetspot(&["validate", "--tangential-stiffness-ratio", "4.75"]).stdout;
    assert!(text.contains("Tangential contact of the oblique rows: compliant, η² = k_n/k_t = 4.75"), "{text}");

    let refused = sweetspot(&["validate", "--tangential-stiffness-ratio", "0"]);
    assert!(!refused.status_ok);
    assert!(refused.stderr.contains("stiffness_ratio") && refused.stderr.contains("η²"), "{}", refused.stderr);
}
