//! Every YAML text sweetspot reads (case files, messages, `--params-file`, `-p` values, QoS override files, a
//! bag's `metadata.yaml` and the rosbag2 metadata inside MCAP files) is loaded here, under a budget a hostile
//! file cannot get around:
//!
//! - nesting at most [`MAX_DEPTH`] levels, block and flow alike and counted after alias expansion, so that no
//!   recursive walk of a document (its `Drop`, the conversions to JSON or parameters) can run out of stack;
//! - aliases expanded into at most [`node_limit`] nodes and [`text_limit`] bytes of scalar text, so that a
//!   "billion laughs" (anchors of aliases of aliases, a few hundred bytes that expand into billions of nodes)
//!   is refused at once instead of filling the memory.
//!
//! The document is built from yaml-rust2's event parser, driven one event at a time: its own loader
//! (`YamlLoader`) recurses once per nesting level before any limit could apply, and clones an anchored node for
//! each alias. Here an alias shares its anchor's node until the document is complete; it is copied out (the
//! last use moved) only once the budget has allowed it. What loads is the same `Yaml` that `YamlLoader` gives.

use std::collections::HashMap;
use std::rc::Rc;

use yaml_rust2::parser::{Event, Parser, Tag};
use yaml_rust2::scanner::{Marker, TScalarStyle};
use yaml_rust2::yaml::Hash;
use yaml_rust2::{ScanError, Yaml};

/// Deepest nesting of sequences and mappings a document may have (a scalar at the top is level 0, `[1]` level
/// 1). 128 is serde_json's own recursion limit, so a JSON text and its YAML twin are held to the same bound,
/// and far beyond any file sweetspot reads (a rosbag2 `metadata.yaml` nests 5 levels).
pub const MAX_DEPTH: usize = 128;

/// The fewest nodes the aliases of any text may expand a document into: 100,000, some 20 MB once loaded and
/// converted (a case file of 99 aliases of a 500-key mapping peaks at 32 MB of RSS, 12 MB of it the program),
/// and hundreds of times what the aliases of a hand-written case, message or parameter file expand to.
pub const MIN_NODE_LIMIT: usize = 100_000;

/// The fewest bytes of scalar text the aliases of any text may expand a document into: as much as the largest
/// text input sweetspot reads ([`crate::files::MAX_INPUT_BYTES`]).
pub const MIN_TEXT_LIMIT: usize = crate::files::MAX_INPUT_BYTES as usize;

/// How many nodes a document loaded from `text` may have, aliases expanded: 100,000, or twice its length when
/// that is more. A text without aliases never reaches it (the densest YAML, `[:,:,…]`, spells 3 nodes in 2 bytes).
pub fn node_limit(text: &str) -> usize {
    MIN_NODE_LIMIT.max(2 * text.len())
}

/// How many bytes of scalar text a document loaded from `text` may hold, aliases expanded: 16 MiB, or twice its
/// length when that is more (no escape spells more than 3 bytes in 2 characters).
pub fn text_limit(text: &str) -> usize {
    MIN_TEXT_LIMIT.max(2 * text.len())
}

/// Why a YAML text was not loaded.
#[derive(Debug, thiserror::Error)]
pub enum YamlError {
    /// Not YAML (yaml-rust2's message, with its position).
    #[error("{0}")]
    Syntax(ScanError),
    /// Sequences and mappings nested deeper than [`MAX_DEPTH`].
    #[error("YAML nested deeper than {MAX_DEPTH} levels (line {line}): refused")]
    TooDeep {
        /// Where the level past the limit begins (1-based).
        line: usize,
    },
    /// Aliases expanding the document past its node limit.
    #[error("YAML aliases expand past {limit} nodes (line {line}): refused")]
    TooManyNodes {
        /// The limit ([`node_limit`]).
        limit: usize,
        /// The alias that would pass it (1-based).
        line: usize,
    },
    /// Aliases expanding the document past its text limit.
    #[error("YAML aliases expand past {limit} bytes of text (line {line}): refused")]
    TooMuchText {
        /// The limit ([`text_limit`]).
        limit: usize,
        /// The alias that would pass it (1-based).
        line: usize,
    },
}

impl YamlError {
    /// Whether the text is not YAML at all (rather than YAML past a limit).
    pub fn is_syntax(&self) -> bool {
        matches!(self, YamlError::Syntax(_))
    }
}

/// The documents of `text`, as `YamlLoader::load_from_str` reads them, within the limits above.
pub fn load(text: &str) -> Result<Vec<Yaml>, YamlError> {
    let mut parser = Parser::new_from_str(text);
    let mut builder = Builder::new(text);
    loop {
        let (event, mark) = parser.next_token().map_err(YamlError::Syntax)?;
        if event == Event::StreamEnd {
            return Ok(builder.docs);
        }
        builder.on_event(event, mark)?;
    }
}

/// A node under construction: aliases share their anchor's node ([`Node::Shared`]) until the document is
/// complete and its size known. A collection without shared nodes inside stays plain `Yaml` (`Node::Plain`),
/// built as `YamlLoader` builds it; one turns into a `Sequence` or `Mapping` of nodes when a shared node joins it.
enum Node {
    Plain(Yaml),
    Sequence(Vec<Node>),
    /// Entries with where each value ended (a duplicated key is reported there, as yaml-rust2 does).
    Mapping(Vec<(Node, Node, Marker)>),
    Shared(Rc<Node>),
}

/// What an anchor names, and its size with every alias inside it expanded.
struct Anchored {
    node: Rc<Node>,
    size: Size,
}

/// The size of a node, aliases expanded: nodes, bytes of scalar text and height (0 for a scalar).
#[derive(Clone, Copy, Default)]
struct Size {
    nodes: usize,
    text: usize,
    height: usize,
}

/// A sequence or mapping whose end event has not come yet.
struct Open {
    node: Node,
    /// The value's key, once read, in a mapping.
    key: Option<Node>,
    anchor: usize,
    /// The document's expanded size before this collection began.
    before: Size,
    /// The tallest child so far.
    child_height: usize,
}

struct Builder {
    docs: Vec<Yaml>,
    open: Vec<Open>,
    root: Option<Node>,
    anchors: HashMap<usize, Anchored>,
    /// Anchor ids below this belong to earlier documents (yaml-rust2's parser forgets their names).
    first_anchor_of_document: usize,
    last_anchor: usize,
    /// The expanded size so far (`height` unused).
    total: Size,
    node_limit: usize,
    text_limit: usize,
}

impl Builder {
    fn new(text: &str) -> Builder {
        Builder {
            docs: Vec::new(),
            open: Vec::new(),
            root: None,
            anchors: HashMap::new(),
            first_anchor_of_document: 1,
            last_anchor: 0,
            total: Size::default(),
            node_limit: node_limit(text),
            text_limit: text_limit(text),
        }
    }

    fn on_event(&mut self, event: Event, mark: Marker) -> Result<(), YamlError> {
        match event {
            Event::Nothing | Event::StreamStart | Event::StreamEnd => Ok(()),
            Event::DocumentStart => {
                self.first_anchor_of_document = self.last_anchor + 1;
                Ok(())
            }
            Event::DocumentEnd => {
                self.anchors.clear();
                let doc = match self.root.take() {
                    Some(node) => into_yaml(node)?,
                    None => Yaml::BadValue,
                };
                self.docs.push(doc);
                Ok(())
            }
            Event::SequenceStart(anchor, _) => self.open_collection(Yaml::Array(Vec::new()), anchor, mark),
            Event::MappingStart(anchor, _) => self.open_collection(Yaml::Hash(Hash::new()), anchor, mark),
            Event::SequenceEnd | Event::MappingEnd => self.close_collection(mark),
            Event::Scalar(value, style, anchor, tag) => {
                let size = Size { nodes: 1, text: value.len(), height: 0 };
                self.spend(size, mark)?;
                self.note_anchor(anchor);
                self.insert(Node::Plain(scalar(value, style, tag)), anchor, size, mark)
            }
            Event::Alias(id) => self.alias(id, mark),
        }
    }

    fn open_collection(&mut self, empty: Yaml, anchor: usize, mark: Marker) -> Result<(), YamlError> {
        if self.open.len() >= MAX_DEPTH {
            return Err(YamlError::TooDeep { line: mark.line() });
        }
        let before = self.total;
        self.spend(Size { nodes: 1, text: 0, height: 0 }, mark)?;
        self.note_anchor(anchor);
        self.open.push(Open { node: Node::Plain(empty), key: None, anchor, before, child_height: 0 });
        Ok(())
    }

    fn close_collection(&mut self, mark: Marker) -> Result<(), YamlError> {
        let Some(done) = self.open.pop() else { return Ok(()) };
        let size = Size {
            nodes: self.total.nodes - done.before.nodes,
            text: self.total.text - done.before.text,
            height: done.child_height + 1,
        };
        self.insert(done.node, done.anchor, size, mark)
    }

    fn alias(&mut self, id: usize, mark: Marker) -> Result<(), YamlError> {
        if id < self.first_anchor_of_document {
            let error = ScanError::new(mark, "while parsing node, found unknown anchor");
            return Err(YamlError::Syntax(error));
        }
        // An alias inside its own anchor's node names nothing yet: yaml-rust2 reads it as a bad value.
        let Some(anchored) = self.anchors.get(&id) else {
            let size = Size { nodes: 1, text: 0, height: 0 };
            self.spend(size, mark)?;
            return self.insert(Node::Plain(Yaml::BadValue), 0, size, mark);
        };
        let (node, size) = (Node::Shared(Rc::clone(&anchored.node)), anchored.size);
        if self.open.len() + size.height > MAX_DEPTH {
            return Err(YamlError::TooDeep { line: mark.line() });
        }
        self.spend(size, mark)?;
        self.insert(node, 0, size, mark)
    }

    fn note_anchor(&mut self, anchor: usize) {
        self.last_anchor = self.last_anchor.max(anchor);
    }

    /// Adds a node's expanded size to the document's, refusing it past the limits.
    fn spend(&mut self, size: Size, mark: Marker) -> Result<(), YamlError> {
        let nodes = self.total.nodes.saturating_add(size.nodes);
        if nodes > self.node_limit {
            return Err(YamlError::TooManyNodes { limit: self.node_limit, line: mark.line() });
        }
        let text = self.total.text.saturating_add(size.text);
        if text > self.text_limit {
            return Err(YamlError::TooMuchText { limit: self.text_limit, line: mark.line() });
        }
        self.total.nodes = nodes;
        self.total.text = text;
        Ok(())
    }

    /// Puts a complete node into its parent (or makes it the document), remembering it under its anchor.
    fn insert(&mut self, node: Node, anchor: usize, size: Size, mark: Marker) -> Result<(), YamlError> {
        let node = if anchor > 0 {
            let shared = Rc::new(node);
            self.anchors.insert(anchor, Anchored { node: Rc::clone(&shared), size });
            Node::Shared(shared)
        } else {
            node
        };
        let Some(parent) = self.open.last_mut() else {
            self.root = Some(node);
            return Ok(());
        };
        parent.child_height = parent.child_height.max(size.height);
        parent.add(node, mark)
    }
}

impl Open {
    fn is_mapping(&self) -> bool {
        matches!(self.node, Node::Plain(Yaml::Hash(_)) | Node::Mapping(_))
    }

    /// Adds a child: an item, a key, or the value of the key before it.
    fn add(&mut self, node: Node, mark: Marker) -> Result<(), YamlError> {
        if self.is_mapping() && self.key.is_none() {
            self.key = Some(node);
            return Ok(());
        }
        match (&mut self.node, self.key.take(), node) {
            (Node::Plain(Yaml::Array(items)), _, Node::Plain(item)) => items.push(item),
            (Node::Plain(Yaml::Hash(hash)), Some(Node::Plain(key)), Node::Plain(value)) => {
                insert_entry(hash, key, value, mark)?
            }
            (collection, key, node) => match (into_nodes(collection, mark), key) {
                (Node::Sequence(items), _) => items.push(node),
                (Node::Mapping(entries), Some(key)) => entries.push((key, node, mark)),
                _ => unreachable!("only collections are open, and a mapping's value comes after its key"),
            },
        }
        Ok(())
    }
}

/// A plain collection as a `Sequence` or `Mapping` of nodes, for a shared node to join (its entries, already
/// checked against each other, take `mark`).
fn into_nodes(collection: &mut Node, mark: Marker) -> &mut Node {
    let node = std::mem::replace(collection, Node::Plain(Yaml::Null));
    *collection = match node {
        Node::Plain(Yaml::Array(items)) => Node::Sequence(items.into_iter().map(Node::Plain).collect()),
        Node::Plain(Yaml::Hash(hash)) => {
            Node::Mapping(hash.into_iter().map(|(key, value)| (Node::Plain(key), Node::Plain(value), mark)).collect())
        }
        other => other,
    };
    collection
}

/// A scalar as `YamlLoader` types it: quoted ones are strings; plain ones by their `!!` tag, else their text.
fn scalar(value: String, style: TScalarStyle, tag: Option<Tag>) -> Yaml {
    if style != TScalarStyle::Plain {
        return Yaml::String(value);
    }
    let Some(Tag { handle, suffix }) = tag else { return Yaml::from_str(&value) };
    if handle != "tag:yaml.org,2002:" {
        return Yaml::String(value);
    }
    match suffix.as_str() {
        "bool" => match value.as_str() {
            "true" | "True" | "TRUE" => Yaml::Boolean(true),
            "false" | "False" | "FALSE" => Yaml::Boolean(false),
            _ => Yaml::BadValue,
        },
        "int" => value.parse::<i64>().map_or(Yaml::BadValue, Yaml::Integer),
        "float" if is_core_schema_float(&value) => Yaml::Real(value),
        "float" => Yaml::BadValue,
        "null" => match value.as_str() {
            "~" | "null" => Yaml::Null,
            _ => Yaml::BadValue,
        },
        _ => Yaml::String(value),
    }
}

/// Whether YAML's core schema reads `value` as a float (yaml-rust2's rule: `.inf`, `.nan` and their
/// spellings, or a number Rust parses that has a digit, so that `inf` stays a word).
fn is_core_schema_float(value: &str) -> bool {
    matches!(
        value,
        ".inf" | ".Inf" | ".INF" | "+.inf" | "+.Inf" | "+.INF" | "-.inf" | "-.Inf" | "-.INF" | ".nan" | ".NaN" | ".NAN"
    ) || (value.bytes().any(|b| b.is_ascii_digit()) && value.parse::<f64>().is_ok())
}

/// The finished node as `Yaml`: a shared node is moved out by its last user and copied for the others (the
/// budget has allowed every copy). Recursion is bounded by [`MAX_DEPTH`].
fn into_yaml(node: Node) -> Result<Yaml, YamlError> {
    match node {
        Node::Plain(yaml) => Ok(yaml),
        Node::Sequence(items) => Ok(Yaml::Array(items.into_iter().map(into_yaml).collect::<Result<_, _>>()?)),
        Node::Mapping(entries) => {
            let mut hash = Hash::new();
            for (key, value, mark) in entries {
                insert_entry(&mut hash, into_yaml(key)?, into_yaml(value)?, mark)?;
            }
            Ok(Yaml::Hash(hash))
        }
        Node::Shared(shared) => match Rc::try_unwrap(shared) {
            Ok(node) => into_yaml(node),
            Err(shared) => to_yaml(&shared),
        },
    }
}

/// A copy of a shared node as `Yaml`.
fn to_yaml(node: &Node) -> Result<Yaml, YamlError> {
    match node {
        Node::Plain(yaml) => Ok(yaml.clone()),
        Node::Sequence(items) => Ok(Yaml::Array(items.iter().map(to_yaml).collect::<Result<_, _>>()?)),
        Node::Mapping(entries) => {
            let mut hash = Hash::new();
            for (key, value, mark) in entries {
                insert_entry(&mut hash, to_yaml(key)?, to_yaml(value)?, *mark)?;
            }
            Ok(Yaml::Hash(hash))
        }
        Node::Shared(shared) => to_yaml(shared),
    }
}

/// A mapping entry; a key given twice is an error, as in yaml-rust2.
fn insert_entry(hash: &mut Hash, key: Yaml, value: Yaml, mark: Marker) -> Result<(), YamlError> {
    if hash.insert(key, value).is_some() {
        // The key given again is now the last entry.
        let key = hash.back().map(|(key, _)| format!("{key:?}")).unwrap_or_default();
        let error = ScanError::new_string(mark, format!("{key}: duplicated key in mapping"));
        return Err(YamlError::Syntax(error));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use yaml_rust2::YamlLoader;

    /// A "billion laughs": `levels` anchors, each a list of `width` aliases of the one before.
    fn bomb(levels: usize, width: usize) -> String {
        let mut text = "a0: &a0 lol\n".to_string();
        for level in 1..=levels {
            let aliases = vec![format!("*a{}", level - 1); width].join(", ");
            text += &format!("a{level}: &a{level} [{aliases}]\n");
        }
        text
    }

    fn nested_sequences(levels: usize) -> String {
        "- ".repeat(levels) + "1"
    }

    #[test]
    fn a_billion_laughs_is_refused_before_it_grows() {
        // 9 levels of 9 aliases: 9^9 ≈ 387 million strings once expanded.
        let text = bomb(9, 9);
        assert!(text.len() < 600, "{} bytes", text.len());
        let e = load(&text).unwrap_err();
        assert!(matches!(e, YamlError::TooManyNodes { limit: MIN_NODE_LIMIT, .. }), "{e}");
        assert_eq!(e.to_string(), "YAML aliases expand past 100000 nodes (line 7): refused");
    }

    #[test]
    fn the_node_budget_allows_its_limit_and_refuses_one_node_more() {
        // A list of 1,000 nodes, aliased 98 times, beside 999 scalars: 1 + 99 × 1,000 + 999 = 100,000 nodes.
        let list = format!("- &x [{}0]\n", "0,".repeat(998));
        let text = |scalars: usize| format!("{list}{}{}", "- *x\n".repeat(98), "- 0\n".repeat(scalars));
        assert_eq!(node_limit(&text(1000)), MIN_NODE_LIMIT);
        assert_eq!(load(&text(999)).unwrap()[0].as_vec().unwrap().len(), 99 + 999);
        assert!(matches!(load(&text(1000)), Err(YamlError::TooManyNodes { limit: MIN_NODE_LIMIT, .. })));
        assert_eq!(node_limit(&"x".repeat(60_000)), 120_000, "twice the text past 50,000 bytes");
        // The densest YAML without aliases, 3 nodes ({~: ~}) in 2 bytes, stays under it.
        let dense = format!("[{}]", ":,".repeat(60_000));
        let items = load(&dense).unwrap().remove(0);
        assert_eq!(items[59_999], Yaml::Hash(Hash::from_iter([(Yaml::Null, Yaml::Null)])));
        assert!(1 + 3 * 60_000 < node_limit(&dense));
    }

    #[test]
    fn the_text_budget_allows_its_limit_and_refuses_one_copy_more() {
        let long = "x".repeat(1 << 20);
        let text = |aliases: usize| format!("- &s {long}\n{}", "- *s\n".repeat(aliases));
        // 16 copies of 1 MiB are exactly 16 MiB.
        assert_eq!(load(&text(15)).unwrap()[0].as_vec().unwrap().len(), 16);
        let e = load(&text(16)).unwrap_err();
        assert!(matches!(e, YamlError::TooMuchText { limit: MIN_TEXT_LIMIT, line: 17 }), "{e}");
        assert_eq!(e.to_string(), "YAML aliases expand past 16777216 bytes of text (line 17): refused");
    }

    #[test]
    fn block_nesting_128_deep_loads_and_129_is_refused() {
        let doc = load(&nested_sequences(MAX_DEPTH)).unwrap().remove(0);
        let (mut depth, mut node) = (0, &doc);
        while let Yaml::Array(items) = node {
            depth += 1;
            node = &items[0];
        }
        assert_eq!((depth, node), (MAX_DEPTH, &Yaml::Integer(1)));
        let e = load(&nested_sequences(MAX_DEPTH + 1)).unwrap_err();
        assert_eq!(e.to_string(), "YAML nested deeper than 128 levels (line 1): refused");
    }

    #[test]
    fn block_mappings_and_flow_nesting_are_held_to_the_same_depth() {
        let mappings = |levels: usize| (0..levels).map(|i| format!("{}k:\n", " ".repeat(i))).collect::<String>();
        assert!(load(&mappings(MAX_DEPTH)).is_ok());
        let e = load(&mappings(MAX_DEPTH + 1)).unwrap_err();
        assert!(matches!(e, YamlError::TooDeep { line: 129 }), "{e}");
        let flow = |levels: usize| "[".repeat(levels) + &"]".repeat(levels);
        assert!(load(&flow(MAX_DEPTH)).is_ok());
        assert!(matches!(load(&flow(MAX_DEPTH + 1)), Err(YamlError::TooDeep { .. })));
    }

    #[test]
    fn a_deep_nest_far_past_the_limit_is_refused_without_overflowing_the_stack() {
        assert!(matches!(load(&nested_sequences(200_000)), Err(YamlError::TooDeep { line: 1 })));
        // yaml-rust2's scanner, reading ahead for keys, stops an unclosed flow nest at 255 levels itself.
        for text in ["[".repeat(200_000), "{a: ".repeat(200_000)] {
            match load(&text) {
                Err(YamlError::TooDeep { .. }) => {}
                Err(YamlError::Syntax(e)) => assert_eq!(e.info(), "recursion limit exceeded"),
                other => panic!("{}: {other:?}", &text[..8]),
            }
        }
    }

    #[test]
    fn aliases_count_their_depth_where_they_land() {
        // An anchor 100 deep, aliased 28 levels down, is 128 deep: loads; 29 down is too deep.
        let anchored = "[".repeat(100) + &"]".repeat(100);
        let at = |levels: usize| format!("- &a {anchored}\n- {}*a{}\n", "[".repeat(levels), "]".repeat(levels));
        assert!(load(&at(27)).is_ok(), "the outer sequence is level 1");
        let e = load(&at(28)).unwrap_err();
        assert!(matches!(e, YamlError::TooDeep { line: 2 }), "{e}");
    }

    #[test]
    fn documents_with_anchors_load_as_yaml_rust2_loads_them() {
        let texts = [
            "defaults: &defaults {reliability: reliable, depth: 10}\n/a: *defaults\n/b: *defaults\n",
            "- &x [1, 2.5, .nan, ~, true, '3', \"q\"]\n- *x\n- {*x : k, y: *x}\n",
            "a: &a 1\nb: &a 2\nc: *a\n",
            "&r [*r_missing_until_defined, &q 1, *q]",
            "x: !!float 1\ny: !!int 7\nz: !!bool TRUE\nw: !!str 12\nv: !!null ~\nu: !!float 0x10\n",
            "--- &a [1]\n--- 2\n---\n...\n",
            "&a [*a, 1]",
            "rosbag2_bagfile_information:\n  version: 8\n  files:\n    - path: x.mcap\n      message_count: 3\n",
            "",
        ];
        for text in texts {
            let ours = load(text);
            let theirs = YamlLoader::load_from_str(text);
            match (ours, theirs) {
                (Ok(ours), Ok(theirs)) => assert_eq!(ours, theirs, "{text:?}"),
                (Err(YamlError::Syntax(ours)), Err(theirs)) => assert_eq!(ours.info(), theirs.info(), "{text:?}"),
                (ours, theirs) => panic!("{text:?}: {ours:?} against {theirs:?}"),
            }
        }
    }

    #[test]
    fn syntax_errors_are_yaml_rust2s() {
        let texts = [
            "a: [1",
            "a: b: c",
            "--- *nowhere",
            "--- &a 1\n--- *a\n",
            "{a: 1, a: 2}",
            "{a: 1, b: &x 2, a: *x}",
            "{a: &x 1, a: 2}",
        ];
        for text in texts {
            let ours = load(text).unwrap_err();
            let theirs = YamlLoader::load_from_str(text).unwrap_err();
            assert!(ours.is_syntax(), "{text:?}: {ours}");
            assert_eq!(ours.to_string(), theirs.to_string(), "{text:?}");
        }
    }
}
