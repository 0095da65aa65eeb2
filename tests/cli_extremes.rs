//! Every user-given duration and rate goes through one checked conversion (`model::time`): at 0, NaN, ±∞,
//! 1e300 and 1e-300 each flag either parses (and then means a span an `Instant` can hold: huge values and,
//! for a limit, inf saturate at 100 years, "for ever") or is refused by clap with a range error naming the
//! flag — never a panic; and what parses is not refused again when the command checks its arguments.
//! Parsing and argument checks only: no DDS participant is started here.

use clap::Parser;
use sweetspot::cli::Cli;

/// What a flag accepts.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// Seconds ≥ 0 (+∞ = for ever).
    SecondsZero,
    /// Seconds > 0 (+∞ = for ever).
    SecondsPositive,
    /// A span ≥ 0 that is not a limit: finite (+∞ refused).
    SpanZero,
    /// A swing rate, Hz: a rate of at most 10000.
    SwingRate,
    /// A rate, Hz: finite, at least one per 100 years.
    Rate,
    /// A time scale: finite, > 0.
    Scale,
}

const VALUES: [&str; 6] = ["0", "NaN", "inf", "-inf", "1e300", "1e-300"];

/// Whether `kind` accepts `value` (by the documented rule, written out here independently of the parser).
fn accepted(kind: Kind, value: &str) -> bool {
    match (kind, value) {
        (Kind::SecondsZero, v) => matches!(v, "0" | "inf" | "1e300" | "1e-300"),
        (Kind::SecondsPositive, v) => matches!(v, "inf" | "1e300" | "1e-300"),
        (Kind::SpanZero, v) => matches!(v, "0" | "1e300" | "1e-300"),
        (Kind::SwingRate, _) => false,
        (Kind::Rate, v) => v == "1e300",
        (Kind::Scale, v) => matches!(v, "1e300" | "1e-300"),
    }
}

/// (command line before the flag, flag, kind) for every duration and rate flag the CLI has.
fn flags() -> Vec<(Vec<&'static str>, &'static str, Kind)> {
    let golden = "bags/golden/sweetspot_golden";
    vec![
        (vec!["bag", "record", "-a"], "-d", Kind::SecondsZero),
        (vec!["bag", "record", "-a"], "--max-bag-duration", Kind::SecondsZero),
        (vec!["bag", "play", golden], "--start-offset", Kind::SpanZero),
        (vec!["bag", "play", golden], "--delay", Kind::SpanZero),
        (vec!["bag", "play", golden], "--timeout", Kind::SecondsPositive),
        (vec!["bag", "play", golden], "-r", Kind::Scale),
        (vec!["bag", "play", golden], "--clock", Kind::Rate),
        (vec!["pub", "swing", "{}"], "--timeout", Kind::SecondsZero),
        (vec!["pub", "swing", "{}"], "--keep-alive", Kind::SecondsZero),
        (vec!["pub", "swing", "{}"], "--rate", Kind::Rate),
        (vec!["echo", "swing"], "--timeout", Kind::SecondsZero),
        (vec!["rig"], "--wait", Kind::SecondsZero),
        (vec!["rig"], "--rate", Kind::SwingRate),
        (vec!["demo"], "--rate", Kind::SwingRate),
        (vec!["demo"], "--timeout", Kind::SecondsPositive),
    ]
}

#[test]
fn every_duration_and_rate_flag_is_checked_at_the_extremes() {
    let mut failures = Vec::new();
    for (prefix, flag, kind) in flags() {
        for value in VALUES {
            let mut argv = vec!["sweetspot"];
            argv.extend(&prefix);
            let joined = format!("{flag}={value}");
            argv.push(&joined);
            let parsed = std::panic::catch_unwind(|| Cli::try_parse_from(&argv));
            let Ok(parsed) = parsed else {
                failures.push(format!("{argv:?}: panicked"));
                continue;
            };
            match (parsed, accepted(kind, value)) {
                (Ok(_), true) => {}
                (Err(e), false) => {
                    let text = e.to_string();
                    // clap names the flag by its long form (or short form when it has only that).
                    let long = match flag {
                        "-d" => "--max-bag-duration",
                        "-r" => "--rate",
                        f => f,
                    };
                    if !text.contains(long) || !(text.contains("out of range") || text.contains("not a")) {
                        failures.push(format!("{argv:?}: unclear error: {text}"));
                    }
                }
                (Ok(_), true_or_false) => failures.push(format!("{argv:?}: accepted (expected {true_or_false})")),
                (Err(e), _) => failures.push(format!("{argv:?}: refused: {e}")),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// What parses is not refused again when the command runs: `inf` for a limit means no limit. Each run stops
/// at an invalid `ROS_DOMAIN_ID` (read before any DDS participant is made), so reaching that error shows the
/// durations passed every check before it.
#[test]
fn inf_for_a_limit_passes_the_commands_own_checks() {
    let golden = "bags/golden/sweetspot_golden";
    let runs: [&[&str]; 6] = [
        &["bag", "play", golden, "--timeout", "inf"],
        &["pub", "swing", "{}", "--timeout", "inf"],
        &["pub", "swing", "{}", "--keep-alive", "inf"],
        &["echo", "swing", "--timeout", "inf"],
        &["rig", "--wait", "inf"],
        &["rig", "--rate", "10000"],
    ];
    for args in runs {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_sweetspot"))
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .env("ROS_DOMAIN_ID", "not-a-domain")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(stderr.contains("ROS_DOMAIN_ID=\"not-a-domain\" is invalid"), "{args:?} stopped before DDS: {stderr}");
    }
}

/// A span that is not a limit refuses `inf` with the range it expects, naming the flag.
#[test]
fn inf_for_a_span_is_a_range_error_naming_the_flag() {
    for flag in ["--start-offset", "--delay"] {
        let err = Cli::try_parse_from(["sweetspot", "bag", "play", "bags/golden/sweetspot_golden", flag, "inf"])
            .unwrap_err()
            .to_string();
        assert!(err.contains(flag) && err.contains("expected finite seconds ≥ 0"), "{err}");
    }
    let err = Cli::try_parse_from(["sweetspot", "rig", "--rate", "10001"]).unwrap_err().to_string();
    assert!(err.contains("--rate") && err.contains("at most 10000 swings per second"), "{err}");
}

/// A wait that must end — the discovery of a graph listing (`--spin-time`), the answer to a service call
/// (`call`/`param --timeout`) — refuses +∞ and anything beyond its documented bound (an hour; a day) with the
/// range, naming the flag; the bound itself passes.
#[test]
fn waits_that_must_end_refuse_inf_and_pin_their_bound() {
    let spin: [&[&str]; 3] = [&["topic", "list"], &["service", "list"], &["nodes"]];
    let call: [&[&str]; 3] =
        [&["call", "simulate_swing", "{}"], &["param", "get", "/sweetspot", "x"], &["param", "dump", "/x"]];
    let cases = spin
        .iter()
        .map(|c| (*c, "--spin-time", "3600", "3600.001"))
        .chain(call.iter().map(|c| (*c, "--timeout", "86400", "86400.001")));
    for (prefix, flag, bound, beyond) in cases {
        let line = |value: &str| {
            let mut argv = vec!["sweetspot"];
            argv.extend(prefix);
            argv.extend([flag, value]);
            Cli::try_parse_from(argv)
        };
        assert!(line(bound).is_ok(), "{prefix:?} {flag} {bound} is refused");
        assert!(line("0").is_ok(), "{prefix:?} {flag} 0 is refused");
        for value in [beyond, "inf", "1e300"] {
            let err = line(value).expect_err(&format!("{prefix:?} {flag} {value} is accepted")).to_string();
            assert!(err.contains(flag) && err.contains(&format!("expected seconds from 0 to {bound}")), "{err}");
        }
    }
}

/// An error quotes at most a few hundred bytes of a name, type or request a user gave, then its length — a
/// 100-KB argument is named, not repeated. Each command stops before DDS (an invalid `ROS_DOMAIN_ID` would stop
/// any that got that far).
#[test]
fn errors_quote_a_long_argument_in_a_few_hundred_bytes() {
    let long = "x".repeat(100_000);
    let bad_name = format!("/{}-", "a".repeat(100_000));
    let request = format!("[{long}");
    let runs: [&[&str]; 7] = [
        &["call", "simulate_swing", &request],
        &["call", &long, "{}"],
        &["call", &bad_name, "{}"],
        &["param", "get", &bad_name, "x"],
        &["interface", "show", &long],
        &["pub", "swing", "{}", "--type", &long],
        &["echo", &bad_name],
    ];
    for args in runs {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_sweetspot"))
            .args(args)
            .env("ROS_DOMAIN_ID", "not-a-domain")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let shown: Vec<&str> = args.iter().map(|a| &a[..a.len().min(20)]).collect();
        assert!(!out.status.success(), "{shown:?}");
        assert!(!stderr.contains("ROS_DOMAIN_ID"), "{shown:?} reached DDS: {}", &stderr[..stderr.len().min(300)]);
        assert!(stderr.len() < 2_000, "{shown:?}: {} bytes of error: {}…", stderr.len(), &stderr[..300]);
        assert!(stderr.contains(" bytes"), "{shown:?} does not say how long the argument was: {stderr}");
    }
}
