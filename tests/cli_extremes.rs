//! Every user-given duration and rate goes through one checked conversion (`model::time`): at 0, NaN, ±∞,
//! 1e300 and 1e-300 each flag either parses (and then means a span an `Instant` can hold: huge values and
//! inf saturate at 100 years, "for ever") or is refused by clap with a range error naming the flag — never a
//! panic. Parsing only: no DDS participant is started here (the runs are in `cli_extremes_dds`).

use clap::Parser;
use sweetspot::cli::Cli;

/// What a flag accepts.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// Seconds ≥ 0 (+∞ = for ever).
    SecondsZero,
    /// Seconds > 0 (+∞ = for ever).
    SecondsPositive,
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
        (vec!["bag", "play", golden], "--start-offset", Kind::SecondsZero),
        (vec!["bag", "play", golden], "--delay", Kind::SecondsZero),
        (vec!["bag", "play", golden], "--timeout", Kind::SecondsPositive),
        (vec!["bag", "play", golden], "-r", Kind::Scale),
        (vec!["bag", "play", golden], "--clock", Kind::Rate),
        (vec!["pub", "swing", "{}"], "--timeout", Kind::SecondsZero),
        (vec!["pub", "swing", "{}"], "--keep-alive", Kind::SecondsZero),
        (vec!["pub", "swing", "{}"], "--rate", Kind::Rate),
        (vec!["echo", "swing"], "--timeout", Kind::SecondsZero),
        (vec!["rig"], "--wait", Kind::SecondsZero),
        (vec!["rig"], "--rate", Kind::Rate),
        (vec!["demo"], "--rate", Kind::Rate),
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
