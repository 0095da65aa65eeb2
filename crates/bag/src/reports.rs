//! The reports of `bag replay` and `bag recover` as the command line prints them, and what `bag export` says
//! of a bag: text only, from the values the bag's readers return.

use std::path::Path;

use crate::export::ExportCounts;
use crate::recover::Recovery;
use crate::replay::{ReplayReport, ReplayRow, Verdict};

/// The replay as a table (every row when `all` or at most 40 rows, else the first 40 that differ), its summary
/// line and, for a session with measured exit speeds, the measured against the model.
pub fn replay_table(report: &ReplayReport, all: bool) -> String {
    let mut text = String::new();
    let (matched, differ, unrecorded) = report.tally();
    let show_all = all || report.rows.len() <= 40;
    // An imported or tracked session: its measurements against the model, beside replay's own check.
    let measured = report.measured_against_model();
    let measured_header = match measured {
        Some(_) => format!(" {:>12} {:>12}", "measured v_f", "meas − model"),
        None => String::new(),
    };
    text += &format!(
        "{:<10} {:>9} {:<12} {:<10} {:>14} {:>14} {:>12} {:>10}{measured_header}  verdict\n",
        "namespace", "swing_id", "bat", "ball", "recorded v_f", "replayed v_f", "Δ v_f", "worst rel"
    );
    let mut shown = 0;
    for row in &report.rows {
        if !show_all && (row.verdict != Verdict::Differs || shown >= 40) {
            continue;
        }
        shown += 1;
        text += &replay_row(row, measured.is_some());
    }
    let tol = if report.tolerance == 0.0 {
        "bit-exact".to_string()
    } else {
        format!("relative tolerance {}", report.tolerance)
    };
    let s = &report.settings;
    text += &format!(
        "{} swings: {matched} match, {differ} differ ({tol}), {unrecorded} without recorded output. Settings: default_bat {}, default_ball {}, default_modes {}, time_step {} s, max_bats {}, max_balls {}, max_bat_slices {}. Bag written by: {}\n",
        report.rows.len(),
        s.default_bat,
        s.default_ball,
        s.default_modes,
        s.time_step,
        s.max_bats,
        s.max_balls,
        s.max_bat_slices,
        report.recorded_by
    );
    if let Some((n, mean, rms)) = measured {
        text += &format!(
            "measured against model: {n} measured swings, measured − model exit speed mean {mean:+.2} m/s, RMS \
             {rms:.2} m/s (for an imported session the model's inputs include assumed ones: `sweetspot calibrate` \
             fits the ball to them, `sweetspot locate` the impact points)\n"
        );
    }
    text
}

/// One row of the replay table (with the measured columns when `measured`).
fn replay_row(row: &ReplayRow, measured: bool) -> String {
    let verdict = match row.verdict {
        Verdict::Match => "match".to_string(),
        Verdict::NotRecorded => "no recorded output".to_string(),
        Verdict::MissingInput => {
            format!("not checked: the bag lacks the {}", row.missing_input.as_deref().unwrap_or("params"))
        }
        Verdict::Differs => {
            let first = &row.differences[0];
            format!(
                "DIFFERS ({} fields; e.g. {}: {} → {})",
                row.differences.len(),
                first.field,
                first.recorded,
                first.replayed
            )
        }
    };
    let measured_cells = match measured {
        true => {
            format!(" {:>12.3} {:>12.3}", row.measured_exit_speed, row.measured_exit_speed - row.replayed_exit_speed)
        }
        false => String::new(),
    };
    format!(
        "{:<10} {:>9} {:<12} {:<10} {:>14.6} {:>14.6} {:>12.3e} {:>10.2e}{measured_cells}  {verdict}\n",
        row.namespace,
        row.swing_id,
        row.bat_id,
        row.ball_id,
        row.recorded_exit_speed,
        row.replayed_exit_speed,
        row.replayed_exit_speed - row.recorded_exit_speed,
        row.worst_relative
    )
}

/// What recovery did, file by file, and where the copy of `path` went.
pub fn recovery_report(recovery: &Recovery, path: &Path) -> String {
    let mut text = String::new();
    for file in &recovery.files {
        let name = file.path.display();
        for damage in &file.damage {
            text += &format!("{name}: dropped: {damage}\n");
        }
        let lost = match (file.lost_messages, file.lost_messages_unknown) {
            (n, false) => format!("{n} messages"),
            (n, true) => format!("at least {n} messages (the rest of the count is unknown)"),
        };
        let kept_in = match file.layout {
            Some(crate::McapLayout::Unchunked) => "unchunked".to_string(),
            _ => format!("in {} intact chunks", file.chunks),
        };
        let state = if file.complete { "finished but damaged" } else { "unfinished (no summary)" };
        match (&file.output, file.rebuilt) {
            (Some(out), true) => {
                text += &format!(
                "{name}: {state}: rebuilt as {} — kept {} messages {kept_in}; dropped {lost}, {} bytes of cut-off tail \
                 and {} damaged chunks\n",
                out.display(),
                file.messages,
                file.dropped_tail_bytes,
                file.dropped_corrupt_chunks
            )
            }
            (Some(out), false) => {
                text += &format!(
                    "{name}: finished and undamaged ({} messages): copied as {}\n",
                    file.messages,
                    out.display()
                )
            }
            (None, _) => {
                text += &format!("{name}: finished and undamaged ({} messages): nothing to recover\n", file.messages)
            }
        }
    }
    for missing in &recovery.missing_files {
        text += &format!("{}: listed in metadata.yaml but missing: left out of the copy\n", missing.display());
    }
    match &recovery.output {
        Some(out) if path.is_dir() => {
            text += &format!(
                "{}: repaired copy written to {} (metadata.yaml rebuilt); the original is unchanged\n",
                path.display(),
                out.display()
            )
        }
        Some(out) => {
            text +=
                &format!("{}: repaired copy written to {}; the original is unchanged\n", path.display(), out.display())
        }
        None => text += &format!("{}: nothing to recover, nothing written\n", path.display()),
    }
    text
}

/// Why `path` gives nothing to export: it has no swing topic, and what it has instead.
pub fn no_swing_topics(path: &Path, counts: &ExportCounts) -> String {
    let found = if counts.topics.is_empty() {
        "it has no topics".to_string()
    } else {
        let listed: Vec<String> = counts
            .topics
            .iter()
            .map(|(name, type_name)| {
                let shown = if type_name.is_empty() { "no schema" } else { type_name.as_str() };
                format!("{name} ({shown})")
            })
            .collect();
        format!("its topics: {}", listed.join(", "))
    };
    format!(
        "{}: no swing topics (type {}) to export, nothing written; {found}",
        path.display(),
        <sweetspot_msgs::sweetspot_msgs::msg::Swing as sweetspot_msgs::RosMessage>::TYPE_NAME
    )
}

/// The line `bag export` ends with: what it wrote and what it skipped.
pub fn export_summary(counts: &ExportCounts) -> String {
    let swings = match counts.swings {
        1 => "1 swing".to_string(),
        n => format!("{n} swings"),
    };
    format!(
        "exported {swings} ({} with ExitVelocity, {} with ModalEnergies; {} outputs without their swing, {} \
         undecodable messages skipped)",
        counts.matched_exit_velocities, counts.matched_modal_energies, counts.orphan_outputs, counts.undecodable
    )
}
