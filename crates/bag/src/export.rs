//! `bag export --csv`: one row per recorded swing, its inputs joined with the outputs computed for it.
//!
//! Rows are keyed by (namespace, swing_id): a swing on `/rig3/swing` matches the ExitVelocity and
//! ModalEnergies whose topics live in `/rig3`, so several rigs recorded into one bag stay apart. Topics are
//! recognised by type, not name.

use std::collections::{BTreeSet, HashMap};
use std::io::Write;
use std::path::Path;

use sweetspot_msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, Swing};
use sweetspot_msgs::{decode_cdr, FieldTable, FieldValue, RosMessage};

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
    /// Every topic of the bag as (name, type), first-seen order: what there is when no swing topic is.
    pub topics: Vec<(String, String)>,
}

impl ExportCounts {
    /// Whether the bag has a topic of type `sweetspot_msgs/msg/Swing` (empty or not).
    pub fn has_swing_topic(&self) -> bool {
        self.topics.iter().any(|(_, type_name)| type_name == Swing::TYPE_NAME)
    }
}

/// The node namespace of a recorded topic: the topic minus the node's relative name for that message type
/// (`/rig3/bat/params` → `/rig3`), else minus its last segment (remapped topics).
pub fn namespace_of(topic: &str, type_name: &str) -> String {
    use sweetspot_model::topics;
    let relative = match type_name {
        BatParams::TYPE_NAME => topics::BAT_PARAMS,
        BallParams::TYPE_NAME => topics::BALL_PARAMS,
        Swing::TYPE_NAME => topics::SWING,
        ExitVelocity::TYPE_NAME => topics::EXIT_VELOCITY,
        ModalEnergies::TYPE_NAME => topics::MODAL_ENERGIES,
        _ => "",
    };
    if let Some(ns) = topic.strip_suffix(relative).and_then(|t| t.strip_suffix('/')).filter(|_| !relative.is_empty()) {
        return if ns.is_empty() { "/".to_string() } else { ns.to_string() };
    }
    match topic.rfind('/') {
        Some(0) | None => "/".to_string(),
        Some(i) => topic[..i].to_string(),
    }
}

/// Reads every swing of a bag and joins its recorded outputs, in recorded order.
///
/// An output belongs to the swing with its identity: the same namespace, `swing_id` and header stamp (the
/// node copies both from the swing into its answers), wherever it lies in the bag — a recorder that drains
/// its subscriptions one after another may well write an answer before its swing. When several swings share
/// an identity (a swing sent twice), their outputs pair with them in recorded order. Anything else is an
/// orphan, e.g. the params rejections (ExitVelocity with swing_id 0 and the params' stamp).
pub fn swing_rows(path: &Path) -> Result<(Vec<SwingRow>, ExportCounts), BagError> {
    let run = read_run(path)?;
    Ok((run.rows, run.counts))
}

/// What identifies the swing an output answers: namespace, swing_id, header stamp (sec, nanosec).
type SwingKey = (String, u64, i32, u32);

fn key_of(ns: &str, swing_id: u64, header: &sweetspot_msgs::std_msgs::msg::Header) -> SwingKey {
    (ns.to_string(), swing_id, header.stamp.sec, header.stamp.nanosec)
}

/// An input in recorded order, as a node saw it.
#[derive(Debug, Clone)]
pub enum RunEvent {
    /// BatParams received in a namespace.
    BatParams(String, BatParams),
    /// BallParams received in a namespace.
    BallParams(String, BallParams),
    /// The swing `rows[index]`.
    Swing(usize),
}

/// A recorded run: the inputs in order, and every swing with its recorded outputs.
#[derive(Debug, Clone, Default)]
pub struct Run {
    /// Inputs in recorded order.
    pub events: Vec<RunEvent>,
    /// Swings with their recorded outputs.
    pub rows: Vec<SwingRow>,
    /// Matching statistics.
    pub counts: ExportCounts,
    /// Per message type, the fields its recorded schema names (those of every channel of the type): a bag
    /// recorded before a field was appended to a `.msg` lacks it, and its messages decode it as NaN.
    pub recorded_fields: HashMap<String, BTreeSet<String>>,
}

/// Reads a bag as a run (see [`swing_rows`] for how outputs are matched).
pub fn read_run(path: &Path) -> Result<Run, BagError> {
    let mut events: Vec<RunEvent> = Vec::new();
    let mut rows: Vec<SwingRow> = Vec::new();
    let mut by_key: HashMap<SwingKey, Vec<usize>> = HashMap::new();
    let mut exit_velocities: Vec<(SwingKey, ExitVelocity)> = Vec::new();
    let mut modal_energies: Vec<(SwingKey, ModalEnergies)> = Vec::new();
    let mut counts = ExportCounts::default();
    // A node records its own bag: with one topic per message type there is one node, whatever the remaps; its
    // namespace is the swing topic's (`/lab` for `/lab/swing`).
    let scans = super::reader::read_bag(path, |_| {})?;
    let mut per_type: HashMap<String, BTreeSet<String>> = HashMap::new();
    let mut recorded_fields: HashMap<String, BTreeSet<String>> = HashMap::new();
    for channel in scans.iter().flat_map(|s| s.channels.values()) {
        let topic = &channel.topic;
        per_type.entry(topic.type_name.clone()).or_default().insert(topic.name.clone());
        if !topic.schema_text.is_empty() {
            let fields = schema_fields(&topic.schema_text);
            recorded_fields
                .entry(topic.type_name.clone())
                .and_modify(|known| known.retain(|f| fields.contains(f)))
                .or_insert(fields);
        }
    }
    counts.topics =
        super::info::topics_of(&scans).into_iter().map(|(topic, _)| (topic.name, topic.type_name)).collect();
    let single_node = per_type.values().all(|names| names.len() <= 1);
    let node_ns = per_type
        .get(Swing::TYPE_NAME)
        .and_then(|names| names.iter().next())
        .map_or_else(|| "/".to_string(), |topic| namespace_of(topic, Swing::TYPE_NAME));
    read_bag(path, |m| {
        let ns =
            if single_node { node_ns.clone() } else { namespace_of(&m.channel.topic.name, &m.channel.topic.type_name) };
        match m.channel.topic.type_name.as_str() {
            BatParams::TYPE_NAME => match decode_cdr::<BatParams>(m.data) {
                Ok(p) => events.push(RunEvent::BatParams(ns, p)),
                Err(_) => counts.undecodable += 1,
            },
            BallParams::TYPE_NAME => match decode_cdr::<BallParams>(m.data) {
                Ok(p) => events.push(RunEvent::BallParams(ns, p)),
                Err(_) => counts.undecodable += 1,
            },
            Swing::TYPE_NAME => match decode_cdr::<Swing>(m.data) {
                Ok(swing) => {
                    events.push(RunEvent::Swing(rows.len()));
                    by_key.entry(key_of(&ns, swing.swing_id, &swing.header)).or_default().push(rows.len());
                    rows.push(SwingRow { namespace: ns, log_time_ns: m.log_time_ns, swing, ..SwingRow::default() });
                }
                Err(_) => counts.undecodable += 1,
            },
            ExitVelocity::TYPE_NAME => match decode_cdr::<ExitVelocity>(m.data) {
                Ok(ev) => exit_velocities.push((key_of(&ns, ev.swing_id, &ev.header), ev)),
                Err(_) => counts.undecodable += 1,
            },
            ModalEnergies::TYPE_NAME => match decode_cdr::<ModalEnergies>(m.data) {
                Ok(me) => modal_energies.push((key_of(&ns, me.swing_id, &me.header), me)),
                Err(_) => counts.undecodable += 1,
            },
            _ => {}
        }
    })?;
    // Each output goes to the first swing of its identity that has none of its kind yet.
    let (matched, orphans) = pair(&mut rows, &by_key, exit_velocities, |row| &mut row.exit_velocity);
    counts.matched_exit_velocities += matched;
    counts.orphan_outputs += orphans;
    let (matched, orphans) = pair(&mut rows, &by_key, modal_energies, |row| &mut row.modal_energies);
    counts.matched_modal_energies += matched;
    counts.orphan_outputs += orphans;
    counts.swings = rows.len() as u64;
    Ok(Run { events, rows, counts, recorded_fields })
}

/// Gives each output to the first swing of its identity whose `slot` is still empty; returns how many found a
/// swing and how many did not (orphans).
fn pair<T>(
    rows: &mut [SwingRow],
    by_key: &HashMap<SwingKey, Vec<usize>>,
    outputs: Vec<(SwingKey, T)>,
    slot: impl Fn(&mut SwingRow) -> &mut Option<T>,
) -> (u64, u64) {
    let (mut matched, mut orphans) = (0, 0);
    for (key, output) in outputs {
        match by_key.get(&key).and_then(|list| list.iter().copied().find(|&i| slot(&mut rows[i]).is_none())) {
            Some(i) => {
                *slot(&mut rows[i]) = Some(output);
                matched += 1;
            }
            None => orphans += 1,
        }
    }
    (matched, orphans)
}

/// The field names of a `ros2msg` schema's own message (the text before its first dependency), constants
/// (`NAME=value`) left out.
pub fn schema_fields(schema_text: &str) -> BTreeSet<String> {
    schema_text
        .lines()
        .take_while(|line| !line.starts_with("====="))
        .filter_map(|line| {
            let code = line.split('#').next().unwrap_or("");
            let mut words = code.split_whitespace();
            let (_type, name) = (words.next()?, words.next()?);
            let constant = name.contains('=') || words.next().is_some_and(|rest| rest.starts_with('='));
            (!constant).then(|| name.to_string())
        })
        .collect()
}

fn stamp(h: &sweetspot_msgs::std_msgs::msg::Header) -> String {
    format!("{}.{:09}", h.stamp.sec, h.stamp.nanosec)
}

/// Where a message type's columns sit in its field table: its scalar fields that no earlier column has.
struct Section {
    keep: Vec<bool>,
    names: Vec<&'static str>,
}

impl Section {
    fn of(table: &[(&'static str, FieldValue<'_>)], taken: &mut Vec<&'static str>) -> Section {
        let keep: Vec<bool> = table
            .iter()
            .map(|(name, value)| !matches!(value, FieldValue::Floats(_)) && !taken.contains(name))
            .collect();
        let names: Vec<&'static str> = table.iter().zip(&keep).filter(|(_, &k)| k).map(|((n, _), _)| *n).collect();
        taken.extend(&names);
        Section { keep, names }
    }

    /// The cells of one message (empty cells when it was not recorded).
    fn cells<T: FieldTable>(&self, message: Option<&T>, out: &mut Vec<String>) {
        match message {
            Some(m) => out.extend(
                m.field_table().iter().zip(&self.keep).filter(|(_, &k)| k).map(|((_, value), _)| value.to_string()),
            ),
            None => out.extend(self.names.iter().map(|_| String::new())),
        }
    }
}

/// Writes the CSV: the swing's identity (`namespace`, `swing_id`, `log_time_ns`, `swing_stamp`), then every
/// scalar field of Swing, of ExitVelocity and of ModalEnergies in `.msg` order (a name already given by an
/// earlier message, such as the answer's copy of `bat_id`, is not repeated), then per-mode columns
/// (`mode<k>_frequency`, `mode<k>_energy`, `mode<k>_fraction` up to the most modes of any row). Units are SI as
/// in the messages; the columns follow the `.msg` files, so a field added there is exported without a line of
/// code. Missing outputs leave their cells empty; a field recorded before it existed reads NaN.
pub fn write_csv(rows: &[SwingRow], out: impl Write) -> Result<(), BagError> {
    let modes = rows.iter().filter_map(|r| r.modal_energies.as_ref()).map(|m| m.energy.len()).max().unwrap_or(0);
    let mut taken = vec!["namespace", "swing_id", "log_time_ns", "swing_stamp"];
    let mut header: Vec<String> = taken.iter().map(|s| s.to_string()).collect();
    let swing = Section::of(&Swing::default().field_table(), &mut taken);
    let exit_velocity = Section::of(&ExitVelocity::default().field_table(), &mut taken);
    let modal_energies = Section::of(&ModalEnergies::default().field_table(), &mut taken);
    for section in [&swing, &exit_velocity, &modal_energies] {
        header.extend(section.names.iter().map(|s| s.to_string()));
    }
    for k in 1..=modes {
        header.push(format!("mode{k}_frequency"));
        header.push(format!("mode{k}_energy"));
        header.push(format!("mode{k}_fraction"));
    }
    let mut w = csv::Writer::from_writer(out);
    write_rows(&mut w, &header, rows, modes, [&swing, &exit_velocity, &modal_energies])
        .map_err(|e| BagError::Format(format!("writing CSV: {e}")))?;
    w.flush().map_err(|source| BagError::Io { path: "<csv output>".into(), source })?;
    Ok(())
}

fn write_rows<W: Write>(
    w: &mut csv::Writer<W>,
    header: &[String],
    rows: &[SwingRow],
    modes: usize,
    [swing, exit_velocity, modal_energies]: [&Section; 3],
) -> Result<(), csv::Error> {
    w.write_record(header)?;
    let cell = |v: Option<f64>| v.map(|x| x.to_string()).unwrap_or_default();
    for r in rows {
        let s = &r.swing;
        let mut rec = vec![r.namespace.clone(), s.swing_id.to_string(), r.log_time_ns.to_string(), stamp(&s.header)];
        swing.cells(Some(s), &mut rec);
        exit_velocity.cells(r.exit_velocity.as_ref(), &mut rec);
        modal_energies.cells(r.modal_energies.as_ref(), &mut rec);
        let me = r.modal_energies.as_ref();
        for k in 0..modes {
            rec.push(cell(me.and_then(|m| m.frequency.get(k).copied())));
            rec.push(cell(me.and_then(|m| m.energy.get(k).copied())));
            rec.push(cell(me.and_then(|m| m.fraction.get(k).copied())));
        }
        w.write_record(&rec)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_schema_names_its_own_fields_not_its_constants_or_dependencies() {
        let fields = schema_fields(ExitVelocity::SCHEMA_TEXT);
        assert!(fields.contains("header") && fields.contains("hoop_energy_returned"));
        assert!(!fields.contains("STATUS_OK") && !fields.contains("stamp") && !fields.contains("frame_id"));
        // A recording made before the spin fields were appended.
        let old = "uint8 STATUS_OK=0 # accepted\nstd_msgs/Header header\nfloat64 exit_speed  # m/s\n\
                   string message \"\"\n================================================================================\n\
                   MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n";
        assert_eq!(schema_fields(old).into_iter().collect::<Vec<_>>(), ["exit_speed", "header", "message"]);
    }

    #[test]
    fn namespaces_follow_the_node_topic_names() {
        assert_eq!(namespace_of("/rig3/bat/params", BatParams::TYPE_NAME), "/rig3");
        assert_eq!(namespace_of("/rig3/swing", Swing::TYPE_NAME), "/rig3");
        assert_eq!(namespace_of("/a/b/exit_velocity", ExitVelocity::TYPE_NAME), "/a/b");
        assert_eq!(namespace_of("/bat/params", BatParams::TYPE_NAME), "/");
        assert_eq!(namespace_of("/shared/swings", Swing::TYPE_NAME), "/shared");
    }
}
