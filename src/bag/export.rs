//! `bag export --csv`: one row per recorded swing, its inputs joined with the outputs computed for it.
//!
//! Rows are keyed by (namespace, swing_id): a swing on `/rig3/swing` matches the ExitVelocity and
//! ModalEnergies whose topics live in `/rig3`, so several rigs recorded into one bag stay apart. Topics are
//! recognised by type, not name.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies, Swing};
use crate::msgs::{decode_cdr, RosMessage};

use super::reader::read_bag;
use super::BagError;

/// A recorded swing with whatever was recorded for it.
#[derive(Debug, Clone, Default)]
pub struct SwingRow {
    /// Namespace of the swing topic (`/rig3` for `/rig3/swing`, `/` at the root).
    pub namespace: String,
    /// Log time of the swing, ns.
    pub log_time_ns: u64,
    /// The recorded swing.
    pub swing: Swing,
    /// The recorded answer, if any.
    pub exit_velocity: Option<ExitVelocity>,
    /// The recorded modal energies, if any.
    pub modal_energies: Option<ModalEnergies>,
}

/// What a pass over a bag found besides the rows.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExportCounts {
    /// Swings read.
    pub swings: u64,
    /// ExitVelocity messages matched to a swing.
    pub matched_exit_velocities: u64,
    /// ModalEnergies matched to a swing.
    pub matched_modal_energies: u64,
    /// Outputs whose swing is not in the bag.
    pub orphan_outputs: u64,
    /// Messages that failed to decode (skipped, never fatal).
    pub undecodable: u64,
}

/// The namespace of a topic: everything before its last segment.
pub fn namespace_of(topic: &str) -> String {
    match topic.rfind('/') {
        Some(0) | None => "/".to_string(),
        Some(i) => topic[..i].to_string(),
    }
}

/// Reads every swing of a bag and joins its recorded outputs, in swing log-time order.
pub fn swing_rows(path: &Path) -> Result<(Vec<SwingRow>, ExportCounts), BagError> {
    let mut rows: Vec<SwingRow> = Vec::new();
    let mut index: HashMap<(String, u64), usize> = HashMap::new();
    let mut exits: Vec<(String, ExitVelocity)> = Vec::new();
    let mut energies: Vec<(String, ModalEnergies)> = Vec::new();
    let mut counts = ExportCounts::default();
    read_bag(path, |m| {
        let ns = namespace_of(&m.channel.topic.name);
        match m.channel.topic.type_name.as_str() {
            Swing::TYPE_NAME => match decode_cdr::<Swing>(m.data) {
                Ok(swing) => {
                    index.insert((ns.clone(), swing.swing_id), rows.len());
                    rows.push(SwingRow { namespace: ns, log_time_ns: m.log_time_ns, swing, ..SwingRow::default() });
                }
                Err(_) => counts.undecodable += 1,
            },
            ExitVelocity::TYPE_NAME => match decode_cdr::<ExitVelocity>(m.data) {
                Ok(ev) => exits.push((ns, ev)),
                Err(_) => counts.undecodable += 1,
            },
            ModalEnergies::TYPE_NAME => match decode_cdr::<ModalEnergies>(m.data) {
                Ok(me) => energies.push((ns, me)),
                Err(_) => counts.undecodable += 1,
            },
            _ => {}
        }
    })?;
    counts.swings = rows.len() as u64;
    for (ns, ev) in exits {
        match index.get(&(ns, ev.swing_id)) {
            Some(&i) => {
                rows[i].exit_velocity = Some(ev);
                counts.matched_exit_velocities += 1;
            }
            None => counts.orphan_outputs += 1,
        }
    }
    for (ns, me) in energies {
        match index.get(&(ns, me.swing_id)) {
            Some(&i) => {
                rows[i].modal_energies = Some(me);
                counts.matched_modal_energies += 1;
            }
            None => counts.orphan_outputs += 1,
        }
    }
    rows.sort_by_key(|r| r.log_time_ns);
    Ok((rows, counts))
}

fn stamp(h: &crate::msgs::std_msgs::msg::Header) -> String {
    format!("{}.{:09}", h.stamp.sec, h.stamp.nanosec)
}

fn opt(v: Option<f64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

/// Writes the CSV: swing inputs, then ExitVelocity, then ModalEnergies totals and per-mode columns
/// (`mode<k>_frequency`, `mode<k>_energy`, `mode<k>_fraction` up to the most modes of any row). Units are SI
/// as in the messages. Missing outputs leave their cells empty.
pub fn write_csv(rows: &[SwingRow], out: impl Write) -> Result<(), BagError> {
    let modes = rows.iter().filter_map(|r| r.modal_energies.as_ref()).map(|m| m.energy.len()).max().unwrap_or(0);
    let mut w = csv::Writer::from_writer(out);
    let mut header: Vec<String> = [
        "namespace", "swing_id", "log_time_ns", "swing_stamp", "bat_id", "ball_id", "ball_speed", "bat_cm_speed",
        "bat_angular_speed", "impact_z", "measured_exit_speed", "status", "message", "exit_speed",
        "rigid_exit_speed", "effective_cor", "collision_efficiency", "contact_time", "peak_force", "impulse",
        "max_compression", "residual", "vibration_energy", "hysteresis_loss", "energy_residual",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for k in 1..=modes {
        header.push(format!("mode{k}_frequency"));
        header.push(format!("mode{k}_energy"));
        header.push(format!("mode{k}_fraction"));
    }
    let csv_err = |e: csv::Error| BagError::Format(format!("writing CSV: {e}"));
    w.write_record(&header).map_err(csv_err)?;
    for r in rows {
        let s = &r.swing;
        let ev = r.exit_velocity.as_ref();
        let me = r.modal_energies.as_ref();
        let mut rec = vec![
            r.namespace.clone(),
            s.swing_id.to_string(),
            r.log_time_ns.to_string(),
            stamp(&s.header),
            s.bat_id.clone(),
            s.ball_id.clone(),
            s.ball_speed.to_string(),
            s.bat_cm_speed.to_string(),
            s.bat_angular_speed.to_string(),
            s.impact_z.to_string(),
            s.measured_exit_speed.to_string(),
            ev.map(|e| e.status.to_string()).unwrap_or_default(),
            ev.map(|e| e.message.clone()).unwrap_or_default(),
            opt(ev.map(|e| e.exit_speed)),
            opt(ev.map(|e| e.rigid_exit_speed)),
            opt(ev.map(|e| e.effective_cor)),
            opt(ev.map(|e| e.collision_efficiency)),
            opt(ev.map(|e| e.contact_time)),
            opt(ev.map(|e| e.peak_force)),
            opt(ev.map(|e| e.impulse)),
            opt(ev.map(|e| e.max_compression)),
            opt(ev.map(|e| e.residual)),
            opt(me.map(|m| m.vibration_energy)),
            opt(me.map(|m| m.hysteresis_loss)),
            opt(me.map(|m| m.energy_residual)),
        ];
        for k in 0..modes {
            rec.push(opt(me.and_then(|m| m.frequency.get(k).copied())));
            rec.push(opt(me.and_then(|m| m.energy.get(k).copied())));
            rec.push(opt(me.and_then(|m| m.fraction.get(k).copied())));
        }
        w.write_record(&rec).map_err(csv_err)?;
    }
    w.flush().map_err(|source| BagError::Io { path: "<csv output>".into(), source })?;
    Ok(())
}
