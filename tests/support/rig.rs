//! Rig sessions recorded straight into a bag (no DDS): what the calibration and bag tests read back.

use std::path::{Path, PathBuf};

use sweetspot::bag::{RecordedQos, Recorder, RecorderConfig, TopicId, TopicInfo};
use sweetspot::model::time::RosTime;
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::encode_cdr;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, BatParams, Swing};
use sweetspot::rig::{RigSwing, SessionGenerator};

/// The QoS the node's parameter topics are recorded with.
pub const LATCHED: RecordedQos = RecordedQos { reliable: true, transient_local: true, depth: 1 };
/// The QoS of the swing stream.
pub const STREAM: RecordedQos = RecordedQos { reliable: true, transient_local: false, depth: 1000 };
/// Receive time of a session's first message, ns.
pub const T0: u64 = 1_700_000_000_000_000_000;

/// A rig session in a recorder that is still open.
pub struct RigRecording {
    pub bat_topic: TopicId,
    pub ball_topic: TopicId,
    pub swing_topic: TopicId,
    /// Receive time of the last swing, ns.
    pub last: u64,
    /// The rig's swings in order: the truth the bag's measurements were drawn around.
    pub truth: Vec<RigSwing>,
}

/// Records `rig`'s session the way the rig publishes it: its bats' params, its ball's (changed by
/// `edit_ball` first), then `swings` swings 100 ms apart. The recorder stays open for more.
pub fn record_rig(
    recorder: &Recorder,
    rig: &mut SessionGenerator,
    swings: usize,
    edit_ball: impl FnOnce(&mut BallParams),
) -> RigRecording {
    let bat_topic = recorder.register_topic(TopicInfo::of::<BatParams>("/rig/bat/params", LATCHED)).unwrap();
    let ball_topic = recorder.register_topic(TopicInfo::of::<BallParams>("/rig/ball/params", LATCHED)).unwrap();
    let swing_topic = recorder.register_topic(TopicInfo::of::<Swing>("/rig/swing", STREAM)).unwrap();
    let mut t = T0;
    for params in rig.bat_params(Time::from_unix_ns(t)) {
        assert!(recorder.record(bat_topic, encode_cdr(&params).unwrap(), t, t));
        t += 1000;
    }
    let mut ball = rig.ball_params(Time::from_unix_ns(t));
    edit_ball(&mut ball);
    assert!(recorder.record(ball_topic, encode_cdr(&ball).unwrap(), t, t));
    let mut truth = Vec::with_capacity(swings);
    for _ in 0..swings {
        t += 100_000_000;
        let swing = rig.next_swing().expect("swing");
        let msg = rig.swing_message(&swing, Time::from_unix_ns(t));
        assert!(recorder.record(swing_topic, encode_cdr(&msg).unwrap(), t, t));
        truth.push(swing);
    }
    RigRecording { bat_topic, ball_topic, swing_topic, last: t, truth }
}

/// Closes the bag, which must have kept every message.
pub fn finish(recorder: Recorder) {
    assert_eq!(recorder.finish().expect("finish bag").dropped, 0);
}

/// Records `swings` of `rig` into DIR/session; returns the bag.
pub fn record_rig_session(dir: &Path, swings: usize, mut rig: SessionGenerator) -> PathBuf {
    let bag = dir.join("session");
    let recorder = Recorder::start(RecorderConfig::new(&bag)).expect("start recorder");
    record_rig(&recorder, &mut rig, swings, |_| {});
    finish(recorder);
    bag
}
