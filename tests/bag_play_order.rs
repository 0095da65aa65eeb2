//! `bag play` over real DDS (inside the private network namespace of scripts/test) from a bag written out of
//! log-time order: swings go out in the order they were recorded, whatever their order in the file; a
//! `--start-offset` that lands exactly on a swing plays that swing; and a play that nobody hears fails, as
//! `pub` does, unless `--no-wait` says to publish regardless.

mod support;

use std::path::{Path, PathBuf};
use std::process::Child;
use std::time::Duration;

use support::node::{keep_all, Peer};
use support::{spawn_piped, sweetspot};
use sweetspot::bag::{RecordedQos, Recorder, RecorderConfig, TopicInfo};
use sweetspot::msgs::encode_cdr;
use sweetspot::msgs::sweetspot_msgs::msg::Swing;

const ORDER_DOMAIN: u16 = 213;
const OFFSET_DOMAIN: u16 = 214;
const NOBODY_DOMAIN: u16 = 215;

const STREAM: RecordedQos = RecordedQos { reliable: true, transient_local: false, depth: 1000 };
const T0: u64 = 1_700_000_000_000_000_000;
/// A quarter of a second between recorded swings: offsets in whole quarters are exact in binary floating
/// point, so `--start-offset 0.75` means exactly 750,000,000 ns.
const SLOT_NS: u64 = 250_000_000;
/// The file order of the swings, by recorded slot: swing `slot + 1` was recorded at `T0 + slot × SLOT_NS`.
const FILE_ORDER: [u64; 6] = [2, 0, 4, 1, 5, 3];

/// A bag of six swings on /order/swing whose messages are written in [`FILE_ORDER`], not in log-time order
/// (MCAP allows it: its readers sort by log time when asked).
fn shuffled_bag(dir: &Path) -> PathBuf {
    let recorder = Recorder::start_with(RecorderConfig::new(dir), Default::default()).expect("start recorder");
    let topic = recorder.register_topic(TopicInfo::of::<Swing>("/order/swing", STREAM)).unwrap();
    for slot in FILE_ORDER {
        let t = T0 + slot * SLOT_NS;
        let swing =
            Swing { swing_id: slot + 1, bat_id: "r161".into(), ball_speed: 40.0, impact_z: 0.7, ..Default::default() };
        assert!(recorder.record(topic, encode_cdr(&swing).unwrap(), t, t));
    }
    assert_eq!(recorder.finish().expect("finish bag").dropped, 0);
    dir.to_path_buf()
}

/// The swing ids in file order, as an MCAP reader that does not sort sees them.
fn file_order_ids(bag: &Path) -> Vec<u64> {
    let mut ids = Vec::new();
    sweetspot::bag::reader::read_bag(bag, |m| ids.push(sweetspot::msgs::decode_cdr::<Swing>(m.data).unwrap().swing_id))
        .unwrap();
    ids
}

fn start_play(domain: u16, bag: &Path, args: &[&str]) -> Child {
    let mut c = sweetspot(domain, &["bag", "play", "-q", "--wait-subscribers", "1", "--timeout", "30", "-r", "4"]);
    c.arg(bag).args(args);
    spawn_piped(c)
}

fn finish(child: Child) -> String {
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "bag play failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn swings_written_out_of_order_are_played_in_log_time_order() {
    support::require_isolated_network();
    let tmp = tempfile::tempdir().unwrap();
    let bag = shuffled_bag(&tmp.path().join("shuffled"));
    assert_eq!(file_order_ids(&bag), FILE_ORDER.map(|slot| slot + 1), "the file is out of log-time order");
    let mut peer = Peer::new(ORDER_DOMAIN, "order_listener");
    let swings = peer.subscription::<Swing>("/order/swing", keep_all(sweetspot::ros::swing_qos()));
    let child = start_play(ORDER_DOMAIN, &bag, &[]);
    let got = peer.collect(&swings, 6, Duration::from_secs(20));
    assert!(finish(child).contains("published 6 messages"));
    assert_eq!(got.iter().map(|s| s.swing_id).collect::<Vec<_>>(), vec![1, 2, 3, 4, 5, 6]);
}

#[test]
fn a_start_offset_landing_on_a_swing_plays_that_swing() {
    support::require_isolated_network();
    let tmp = tempfile::tempdir().unwrap();
    let bag = shuffled_bag(&tmp.path().join("shuffled"));
    let mut peer = Peer::new(OFFSET_DOMAIN, "offset_listener");
    let swings = peer.subscription::<Swing>("/order/swing", keep_all(sweetspot::ros::swing_qos()));
    // 0.75 s after the first swing is exactly when the fourth was recorded: it and the two after it play.
    let child = start_play(OFFSET_DOMAIN, &bag, &["--start-offset", "0.75"]);
    let got = peer.collect(&swings, 3, Duration::from_secs(20));
    let stderr = finish(child);
    assert!(stderr.contains("published 3 messages"), "{stderr}");
    assert_eq!(got.iter().map(|s| s.swing_id).collect::<Vec<_>>(), vec![4, 5, 6]);
}

#[test]
fn a_play_nobody_hears_fails_unless_no_wait_says_to_publish_regardless() {
    support::require_isolated_network();
    let tmp = tempfile::tempdir().unwrap();
    let bag = shuffled_bag(&tmp.path().join("shuffled"));
    let play = |extra: &[&str]| {
        let mut c = sweetspot(NOBODY_DOMAIN, &["bag", "play", "-q", "-r", "8"]);
        c.arg(&bag).args(extra);
        c.output().unwrap()
    };
    let heard_by_nobody = play(&[]);
    let stderr = String::from_utf8_lossy(&heard_by_nobody.stderr);
    assert_eq!(heard_by_nobody.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no subscriber on any played topic: all 6 messages went to nobody"), "{stderr}");
    assert!(stderr.contains("--no-wait"), "names the way to publish regardless: {stderr}");

    let regardless = play(&["--no-wait"]);
    let stderr = String::from_utf8_lossy(&regardless.stderr);
    assert!(regardless.status.success(), "{stderr}");
    assert!(stderr.contains("published 6 messages"), "{stderr}");
}

/// The same six swings written by the `mcap` crate (an MCAP writer independent of sweetspot's recorder) into one
/// file, in [`FILE_ORDER`]. No DDS: what `bag play` schedules and what `bag play --foxglove` serves.
fn shuffled_mcap_file(dir: &Path) -> PathBuf {
    use sweetspot::msgs::RosMessage;
    let path = dir.join("shuffled.mcap");
    let file = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    let mut w = mcap::Writer::new(file).unwrap();
    let schema = w.add_schema(Swing::TYPE_NAME, "ros2msg", Swing::SCHEMA_TEXT.as_bytes()).unwrap();
    let channel = w.add_channel(schema, "/order/swing", "cdr", &Default::default()).unwrap();
    for (sequence, slot) in (0u32..).zip(FILE_ORDER) {
        let t = T0 + slot * SLOT_NS;
        let swing =
            Swing { swing_id: slot + 1, bat_id: "r161".into(), ball_speed: 40.0, impact_z: 0.7, ..Default::default() };
        let header = mcap::records::MessageHeader { channel_id: channel, sequence, log_time: t, publish_time: t };
        w.write_to_known_channel(&header, &encode_cdr(&swing).unwrap()).unwrap();
    }
    w.finish().unwrap();
    path
}

fn ids(cdrs: impl Iterator<Item = Vec<u8>>) -> Vec<u64> {
    cdrs.map(|cdr| sweetspot::msgs::decode_cdr::<Swing>(&cdr).unwrap().swing_id).collect()
}

#[test]
fn the_schedule_and_the_served_bag_of_a_file_out_of_log_time_order_follow_log_time_and_include_the_offset() {
    let tmp = tempfile::tempdir().unwrap();
    let file = shuffled_mcap_file(tmp.path());
    assert_eq!(file_order_ids(&file), FILE_ORDER.map(|slot| slot + 1), "the file is out of log-time order");

    let all = sweetspot::play::schedule_from(&file, &[], 1.0, Duration::ZERO).unwrap();
    assert_eq!(ids(all.items.iter().map(|i| i.cdr.clone())), [1, 2, 3, 4, 5, 6]);
    // 0.75 s after the first swing is exactly when the fourth was recorded: the pass starts with it, at 0.
    let from_fourth = sweetspot::play::schedule_from(&file, &[], 1.0, Duration::from_millis(750)).unwrap();
    assert_eq!(ids(from_fourth.items.iter().map(|i| i.cdr.clone())), [4, 5, 6]);
    assert_eq!(from_fourth.origin_ns, T0 + 3 * SLOT_NS);
    assert_eq!(from_fourth.items[0].at, Duration::ZERO);
    let past_fourth = sweetspot::play::schedule_from(&file, &[], 1.0, Duration::from_nanos(750_000_001)).unwrap();
    assert_eq!(ids(past_fourth.items.iter().map(|i| i.cdr.clone())), [5, 6]);

    let served = sweetspot::play::foxglove::ServedBag::read(&file, &[], str::to_string).unwrap();
    assert_eq!(ids(served.messages.iter().map(|m| m.2.clone())), [1, 2, 3, 4, 5, 6]);
    assert_eq!(served.range(), (T0, T0 + 5 * SLOT_NS));
    assert_eq!(served.first_at(T0 + 3 * SLOT_NS), 3, "a seek to a swing's log time starts at that swing");
    assert_eq!(served.first_at(T0 + 3 * SLOT_NS + 1), 4);
}
