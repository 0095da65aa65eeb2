//! ROS 2 conventions of `sweetspot node` over real DDS (inside the private network namespace of scripts/test):
//! `-r __ns:=`/`__node:=`/topic remaps move the topics; `--params-file` and `-p` set parameters that
//! `ros2 param` sees (through the rcl_interfaces services) and that change the answers; `ros2 param set` is
//! validated; SIGTERM ends the node with a finished bag holding every input and output.

mod support;

use std::time::Duration;

use ros2_client::qos::History;
use ros2_client::rcl_interfaces::{
    GetParametersRequest, GetParametersResponse, ListParametersRequest, ListParametersResponse, SetParametersRequest,
    SetParametersResponse,
};
use ros2_client::service::Client;
use ros2_client::{Message, Name, Parameter, ParameterValue, QosProfile, ServiceMapping, ServiceTypeName};
use support::node::{blocking, dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};
use sweetspot::physics::{collide, Ball, Bat, CollisionOptions, Impact, ModeSet};

const WAIT: Duration = Duration::from_secs(60);

fn swing(id: u64, bat_id: &str, impact_z: f64) -> Swing {
    Swing {
        header: Header { stamp: Time { sec: 2000 + id as i32, nanosec: 9 }, frame_id: "rig".into() },
        swing_id: id,
        bat_id: bat_id.into(),
        ball_id: String::new(),
        ball_speed: 39.0,
        bat_cm_speed: 19.0,
        bat_angular_speed: 47.0,
        impact_z,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    }
}

#[test]
fn namespace_node_name_and_topic_remaps_move_the_topics() {
    let domain = domain(5);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "remap_peer");
    let swing_pub = peer.publisher::<Swing>("/rig3/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/shared/answers", keep_all(dds::results()));
    let energies = peer.subscription::<ModalEnergies>("/rig3/modal_energies", keep_all(dds::results()));
    let spots = peer.subscription::<SweetSpot>("/rig3/sweet_spot", keep_all(dds::latched_results()));
    let node = NodeProcess::spawn(
        domain,
        dir.path(),
        &[
            "--no-record",
            "--ros-args",
            "-r",
            "__ns:=/rig3",
            "-r",
            "__node:=lab",
            "-r",
            "exit_velocity:=/shared/answers",
        ],
    );
    node.wait_for_log("/rig3/lab up", WAIT);
    peer.wait_for_reader(&swing_pub);
    let s = swing(1, "", 0.66);
    swing_pub.publish(s.clone()).unwrap();
    let ev = &peer.collect(&answers, 1, WAIT)[0];
    assert_eq!((ev.swing_id, ev.status, ev.bat_id.as_str()), (1, ExitVelocity::STATUS_OK, "r161"));
    assert_eq!(peer.collect(&energies, 1, WAIT)[0].swing_id, 1);
    let spot = &peer.collect(&spots, 1, WAIT)[0];
    assert_eq!(spot.bat_id, "r161", "the default bat's SweetSpot is latched on the namespaced topic");

    let topics: Vec<String> = peer.context.discovered_topics().into_iter().map(|t| t.name).collect();
    for expected in [
        "rt/rig3/swing",
        "rt/rig3/bat/params",
        "rt/rig3/ball/params",
        "rt/shared/answers",
        "rt/rig3/modal_energies",
        "rt/rig3/sweet_spot",
        "rt/diagnostics",
    ] {
        assert!(topics.iter().any(|t| t == expected), "{expected} not discovered in {topics:?}");
    }
    for moved in ["rt/swing", "rt/exit_velocity", "rt/rig3/exit_velocity", "rt/bat/params", "rt/sweet_spot"] {
        assert!(!topics.iter().any(|t| t == moved), "{moved} should have been remapped away: {topics:?}");
    }
    drop(node);
    assert!(!dir.path().join("bags").exists(), "--no-record writes no bag");
}

struct ParamClients {
    get: Client<GetParametersRequest, GetParametersResponse>,
    set: Client<SetParametersRequest, SetParametersResponse>,
    list: Client<ListParametersRequest, ListParametersResponse>,
}

fn param_clients(peer: &mut Peer, node_fqn: &str) -> ParamClients {
    let qos = QosProfile::publisher_default().history(History::KeepLast { depth: 1 });
    let name = |service: &str| Name::new(node_fqn, service).unwrap();
    ParamClients {
        get: peer
            .node
            .create_client(
                ServiceMapping::Enhanced,
                &name("get_parameters"),
                &ServiceTypeName::new("rcl_interfaces", "GetParameters"),
                qos.clone(),
                qos.clone(),
            )
            .unwrap(),
        set: peer
            .node
            .create_client(
                ServiceMapping::Enhanced,
                &name("set_parameters"),
                &ServiceTypeName::new("rcl_interfaces", "SetParameters"),
                qos.clone(),
                qos.clone(),
            )
            .unwrap(),
        list: peer
            .node
            .create_client(
                ServiceMapping::Enhanced,
                &name("list_parameters"),
                &ServiceTypeName::new("rcl_interfaces", "ListParameters"),
                qos.clone(),
                qos,
            )
            .unwrap(),
    }
}

fn call<Req: Message + 'static, Resp: Message + 'static>(
    peer: &Peer,
    client: &Client<Req, Resp>,
    request: Req,
) -> Resp {
    peer.rt.block_on(async {
        tokio::time::timeout(WAIT, client.wait_for_service(&peer.node)).await.expect("service never appeared");
        let id = client.async_send_request(request).await.expect("request sent");
        tokio::time::timeout(WAIT, client.async_receive_response(id)).await.expect("no response").expect("response")
    })
}

fn get(peer: &Peer, clients: &ParamClients, names: &[&str]) -> Vec<ParameterValue> {
    let request = GetParametersRequest { names: names.iter().map(|n| n.to_string()).collect() };
    call(peer, &clients.get, request).values.into_iter().map(ParameterValue::from).collect()
}

fn set(peer: &Peer, clients: &ParamClients, name: &str, value: ParameterValue) -> (bool, String) {
    let request = SetParametersRequest { parameter: vec![Parameter { name: name.into(), value }.into()] };
    let result = call(peer, &clients.set, request).results.remove(0);
    (result.successful, result.reason)
}

fn library_energies(modes: usize, time_step: f64, s: &Swing) -> Vec<f64> {
    let set = ModeSet::compute(&Bat::preset("r161").unwrap(), modes).unwrap();
    let impact = Impact {
        ball_speed: s.ball_speed,
        bat_cm_speed: s.bat_cm_speed,
        bat_angular_speed: s.bat_angular_speed,
        impact_z: s.impact_z,
    };
    // The swings name no ball: the node's default_ball, the game ball.
    let r = collide(&set, &Ball::game(), &impact, &CollisionOptions { modes, time_step }).unwrap();
    r.mode_energies.iter().map(|m| m.energy).collect()
}

#[test]
fn params_file_and_dash_p_set_parameters_that_ros2_param_sees_validates_and_applies() {
    let domain = domain(6);
    let dir = tempfile::tempdir().unwrap();
    let params = dir.path().join("params.yaml");
    std::fs::write(
        &params,
        "/**:\n  ros__parameters:\n    default_modes: 7\n    reference_ball_speed: 35\n\
         sweetspot:\n  ros__parameters:\n    time_step: 4.0e-6\n    queue_capacity: 2048\n",
    )
    .unwrap();
    let mut peer = Peer::new(domain, "param_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let bat_pub = peer.publisher::<BatParams>("/bat/params", dds::params());
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let energies = peer.subscription::<ModalEnergies>("/modal_energies", keep_all(dds::results()));
    let spots = peer.subscription::<SweetSpot>("/sweet_spot", keep_all(dds::latched_results()));
    let clients = param_clients(&mut peer, "/sweetspot");
    let node = NodeProcess::spawn(
        domain,
        dir.path(),
        &["--no-record", "--ros-args", "--params-file", params.to_str().unwrap(), "-p", "default_modes:=9"],
    );

    let values =
        get(&peer, &clients, &["default_modes", "reference_ball_speed", "time_step", "queue_capacity", "record"]);
    assert_eq!(
        values,
        vec![
            ParameterValue::Integer(9),   // -p beats the file
            ParameterValue::Double(35.0), // from /**, an integer accepted for a double
            ParameterValue::Double(4e-6), // from the node's own section
            ParameterValue::Integer(2048),
            ParameterValue::Boolean(false), // --no-record
        ]
    );
    let listed = call(&peer, &clients.list, ListParametersRequest { prefixes: vec![], depth: 0 }).result.names;
    for name in sweetspot::node::settings::parameter_names() {
        assert!(listed.iter().any(|n| n == name), "{name} not listed: {listed:?}");
    }

    // The values are in force: 9 modes at 4 µs, and the SweetSpot's reference swing at 35 m/s.
    let spot = &peer.collect(&spots, 1, WAIT)[0];
    assert_eq!((spot.bat_id.as_str(), spot.ball_speed, spot.frequency.len()), ("r161", 35.0, 9));
    peer.wait_for_reader(&swing_pub);
    let s1 = swing(1, "r161", 0.6);
    swing_pub.publish(s1.clone()).unwrap();
    let me = &peer.collect(&energies, 1, WAIT)[0];
    assert_eq!(me.energy, library_energies(9, 4e-6, &s1));

    // `ros2 param set`: bad values and read-only parameters are refused with a reason, nothing changes.
    let (ok, reason) = set(&peer, &clients, "default_modes", ParameterValue::Integer(0));
    assert!(!ok && reason.contains("default_modes") && reason.contains("200"), "{reason}");
    let (ok, reason) = set(&peer, &clients, "default_bat", ParameterValue::String("alumnium".into()));
    assert!(!ok && reason.contains("default_bat") && reason.contains("aluminum"), "{reason}");
    let (ok, reason) = set(&peer, &clients, "queue_capacity", ParameterValue::Integer(5));
    assert!(!ok && reason.contains("read-only"), "{reason}");
    let (ok, reason) = set(&peer, &clients, "time_step", ParameterValue::String("fast".into()));
    assert!(!ok, "a string for a double must be refused: {reason}");
    assert_eq!(
        get(&peer, &clients, &["default_modes", "queue_capacity"]),
        vec![ParameterValue::Integer(9), ParameterValue::Integer(2048)]
    );

    // A valid set takes effect: cached modes are recomputed with 5 modes, and the SweetSpot is republished.
    let (ok, reason) = set(&peer, &clients, "default_modes", ParameterValue::Integer(5));
    assert!(ok, "{reason}");
    let republished = peer.collect_until(&spots, WAIT, |got| got.iter().any(|s| s.frequency.len() == 5));
    assert!(republished.iter().any(|s| s.bat_id == "r161" && s.frequency.len() == 5));
    let s2 = swing(2, "r161", 0.6);
    swing_pub.publish(s2.clone()).unwrap();
    let me = &peer.collect(&energies, 1, WAIT)[0];
    assert_eq!(me.swing_id, 2);
    assert_eq!(me.energy, library_energies(5, 4e-6, &s2));

    // The registry limits are live parameters too: a bad value is refused with its range, a good one applies
    // to the next BatParams.
    let (ok, reason) = set(&peer, &clients, "max_bats", ParameterValue::Integer(1));
    assert!(!ok && reason.contains("2 ≤ max_bats"), "{reason}");
    let (ok, reason) = set(&peer, &clients, "max_bat_slices", ParameterValue::Integer(150));
    assert!(ok, "{reason}");
    assert_eq!(
        get(&peer, &clients, &["max_bat_slices", "max_bats"]),
        vec![ParameterValue::Integer(150), ParameterValue::Integer(64)]
    );
    let r161 = Bat::preset("r161").unwrap();
    let at_5mm = BatParams {
        slice_length: 0.005,
        ..sweetspot::model::convert::params_from_bat("fine", &r161, 0, Header::default())
    };
    peer.wait_for_reader(&bat_pub);
    bat_pub.publish(at_5mm).unwrap();
    let refused = peer.collect_until(&answers, WAIT, |got| got.iter().any(|ev| ev.bat_id == "fine"));
    let refused = refused.iter().find(|ev| ev.bat_id == "fine").unwrap();
    assert_eq!(refused.status, ExitVelocity::STATUS_REJECTED);
    assert!(
        refused.message.contains("into 168 slices") && refused.message.contains("max_bat_slices = 150"),
        "{}",
        refused.message
    );

    // Accepted BatParams make their bat the one of swings with an empty bat_id: default_bat no longer
    // applies, and a set of it is refused with the bat in force instead of a success that changes nothing.
    let (ok, reason) = set(&peer, &clients, "default_bat", ParameterValue::String("aluminum".into()));
    assert!(ok, "before any accepted BatParams default_bat applies: {reason}");
    bat_pub.publish(sweetspot::model::convert::params_from_bat("rig_bat", &r161, 0, Header::default())).unwrap();
    peer.collect_until(&spots, WAIT, |got| got.iter().any(|s| s.bat_id == "rig_bat"));
    let (ok, reason) = set(&peer, &clients, "default_bat", ParameterValue::String("r161".into()));
    assert!(!ok && reason.contains("'rig_bat'") && reason.contains("BatParams"), "{reason}");
    assert_eq!(get(&peer, &clients, &["default_bat"]), vec![ParameterValue::String("aluminum".into())]);
    drop(node);
}

fn count(info: &sweetspot::bag::info::BagInfo, topic: &str) -> u64 {
    info.topics.iter().find(|t| t.name == topic).map_or(0, |t| t.count)
}

#[test]
fn sigterm_ends_the_node_with_a_finished_bag_of_every_input_and_output() {
    const N: u64 = 20;
    let domain = domain(7);
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("run1");
    let mut peer = Peer::new(domain, "bag_peer");
    let bat_pub = peer.publisher::<BatParams>("/bat/params", dds::params());
    let ball_pub = peer.publisher::<BallParams>("/ball/params", dds::params());
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let energies = peer.subscription::<ModalEnergies>("/modal_energies", keep_all(dds::results()));
    let spots = peer.subscription::<SweetSpot>("/sweet_spot", keep_all(dds::latched_results()));
    // A non-default mode count: the replay below only matches if the bag tells it the node's settings.
    // lz4 chunks instead of the default zstd: the bag must still read back complete, byte for byte.
    let node = NodeProcess::spawn(
        domain,
        dir.path(),
        &[
            "--ros-args",
            "-p",
            &format!("record_path:={}", bag.display()),
            "-p",
            "default_modes:=12",
            "-p",
            "record_compression:=lz4",
        ],
    );
    ball_pub
        .publish(BallParams {
            ball_id: "b".into(),
            mass: 0.145,
            radius: 0.0366,
            cor: 0.55,
            stiffness: 6.5e7,
            exponent: 1.84,
            ..BallParams::default()
        })
        .unwrap();
    node.wait_for_log("ball 'b' set", WAIT);
    bat_pub.publish(BatParams { bat_id: "t".into(), preset: "torpedo".into(), ..BatParams::default() }).unwrap();
    peer.collect_until(&spots, WAIT, |got| got.iter().any(|s| s.bat_id == "t"));
    peer.wait_for_reader(&swing_pub);
    let swings: Vec<Swing> = (0..N).map(|i| swing(i, "t", 0.5 + 0.01 * i as f64)).collect();
    for s in &swings {
        swing_pub.publish(s.clone()).unwrap();
    }
    let got = peer.collect(&answers, N as usize, WAIT);
    let got_energies = peer.collect(&energies, N as usize, WAIT);

    let (status, elapsed, log) = node.stop_with(15);
    println!("SIGTERM → exit in {elapsed:?}");
    assert!(status.success(), "exit status {status:?}\n{log}");
    assert!(log.contains("SIGTERM: shutting down") && log.contains("closed"), "{log}");

    let info = sweetspot::bag::info::bag_info(&bag).expect("the bag opens");
    assert!(info.complete(), "every file has its summary and footer");
    assert_eq!(info.compression, vec!["lz4".to_string()], "record_compression chose the chunk compression");
    assert!(bag.join("metadata.yaml").exists());
    assert_eq!(count(&info, "/swing"), N);
    assert_eq!(count(&info, "/exit_velocity"), N);
    assert_eq!(count(&info, "/modal_energies"), N);
    assert_eq!(count(&info, "/bat/params"), 1);
    assert_eq!(count(&info, "/ball/params"), 1);
    assert!(count(&info, "/sweet_spot") >= 2, "the default bat's and t's");

    // What was recorded is byte for byte what was sent and received; publish_time = the header stamp.
    let mut recorded_answers = Vec::new();
    let mut recorded_swings = Vec::new();
    let mut recorded_energies = Vec::new();
    sweetspot::bag::reader::read_bag(&bag, |m| {
        let stamp_ns = |h: &Header| h.stamp.sec as u64 * 1_000_000_000 + h.stamp.nanosec as u64;
        match m.channel.topic.name.as_str() {
            "/exit_velocity" => {
                let ev: ExitVelocity = sweetspot::msgs::decode_cdr(m.data).unwrap();
                assert_eq!(m.publish_time_ns, stamp_ns(&ev.header));
                recorded_answers.push(m.data.to_vec());
            }
            "/swing" => {
                let s: Swing = sweetspot::msgs::decode_cdr(m.data).unwrap();
                assert_eq!(m.publish_time_ns, stamp_ns(&s.header));
                recorded_swings.push(m.data.to_vec());
            }
            "/modal_energies" => recorded_energies.push(m.data.to_vec()),
            _ => {}
        }
    })
    .expect("read the bag");
    assert_eq!(recorded_swings, swings.iter().map(|s| sweetspot::msgs::encode_cdr(s).unwrap()).collect::<Vec<_>>());
    assert_eq!(recorded_answers, got.iter().map(|ev| sweetspot::msgs::encode_cdr(ev).unwrap()).collect::<Vec<_>>());
    assert_eq!(
        recorded_energies,
        got_energies.iter().map(|me| sweetspot::msgs::encode_cdr(me).unwrap()).collect::<Vec<_>>()
    );

    // The node → replay contract: the bag carries the node's settings (rosbag2 custom_data), so a plain
    // `sweetspot bag replay` recomputes every swing bit-exactly with 12 modes and no override flags.
    let replay = std::process::Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["bag", "replay"])
        .arg(&bag)
        .output()
        .expect("run sweetspot bag replay");
    let stdout = String::from_utf8_lossy(&replay.stdout);
    let stderr = String::from_utf8_lossy(&replay.stderr);
    assert!(replay.status.success(), "bag replay failed: {:?}\n{stdout}\n{stderr}", replay.status);
    assert!(stdout.contains("default_modes 12"), "replay used the recorded settings:\n{stdout}");
    assert!(stdout.contains(&format!("{N} swings: {N} match")), "{stdout}");
}

/// A node told to record that cannot record does not pretend to: it stops at start-up with one line naming
/// record_path and the reason.
#[test]
fn an_unwritable_record_path_stops_the_node_at_start_up_naming_it() {
    support::require_isolated_network();
    let dir = tempfile::tempdir().unwrap();
    // Not even root can create a directory under /proc.
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["node", "--ros-args", "-p", "record_path:=/proc/sweetspot/bag"])
        .current_dir(dir.path())
        .env("ROS_DOMAIN_ID", domain(9).to_string())
        .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + WAIT;
    while child.try_wait().unwrap().is_none() {
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            panic!("the node started although it cannot record to /proc/sweetspot/bag");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(errors[0].contains("record_path") && errors[0].contains("/proc/sweetspot/bag"), "{stderr}");
    assert!(!stderr.contains("recording /proc"), "it must not claim to record: {stderr}");
}

#[test]
fn fastwrite_preset_records_an_unchunked_bag_that_reads_back_complete() {
    const N: u64 = 20;
    let domain = domain(43);
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("fastwrite_run");
    let mut peer = Peer::new(domain, "fastwrite_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node = NodeProcess::spawn(
        domain,
        dir.path(),
        &["--ros-args", "-p", &format!("record_path:={}", bag.display()), "-p", "record_storage_preset:=fastwrite"],
    );
    peer.wait_for_reader(&swing_pub);
    let swings: Vec<Swing> = (0..N).map(|i| swing(i, "", 0.5 + 0.01 * i as f64)).collect();
    for s in &swings {
        swing_pub.publish(s.clone()).unwrap();
    }
    let got = peer.collect(&answers, N as usize, WAIT);
    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "exit status {status:?}\n{log}");

    let info = sweetspot::bag::info::bag_info(&bag).expect("the bag opens");
    assert!(info.complete(), "every file has its summary and footer");
    assert_eq!(info.layout, vec![sweetspot::bag::McapLayout::Unchunked], "record_storage_preset chose the layout");
    assert!(info.compression.is_empty() && info.files.iter().all(|f| f.chunks == 0));
    assert_eq!((count(&info, "/swing"), count(&info, "/exit_velocity"), count(&info, "/modal_energies")), (N, N, N));

    let mut recorded_swings = Vec::new();
    let mut recorded_answers = Vec::new();
    sweetspot::bag::reader::read_bag(&bag, |m| match m.channel.topic.name.as_str() {
        "/swing" => recorded_swings.push(m.data.to_vec()),
        "/exit_velocity" => recorded_answers.push(m.data.to_vec()),
        _ => {}
    })
    .expect("read the bag");
    assert_eq!(recorded_swings, swings.iter().map(|s| sweetspot::msgs::encode_cdr(s).unwrap()).collect::<Vec<_>>());
    assert_eq!(recorded_answers, got.iter().map(|ev| sweetspot::msgs::encode_cdr(ev).unwrap()).collect::<Vec<_>>());

    // The mcap crate agrees: every message in the file, none in a chunk, statistics right.
    let files = sweetspot::bag::reader::bag_files(&bag).unwrap();
    let bytes = std::fs::read(&files[0]).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().expect("a summary");
    assert!(summary.chunk_indexes.is_empty());
    let streamed = mcap::MessageStream::new(&bytes).unwrap().collect::<Result<Vec<_>, _>>().unwrap().len() as u64;
    assert_eq!(streamed, summary.stats.as_ref().unwrap().message_count);
    assert_eq!(streamed, info.messages);
}

#[test]
fn fastwrite_with_a_compression_refuses_to_start_naming_both_parameters() {
    support::require_isolated_network();
    let dir = tempfile::tempdir().unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["node", "--ros-args", "-p", "record_storage_preset:=fastwrite", "-p", "record_compression:=zstd"])
        .current_dir(dir.path())
        .env("ROS_DOMAIN_ID", domain(44).to_string())
        .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + WAIT;
    while child.try_wait().unwrap().is_none() {
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            panic!("the node started with fastwrite + zstd instead of refusing");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    for part in ["record_storage_preset", "record_compression", "REJECTED", "needs chunks"] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    assert!(!dir.path().join("bags").exists(), "no bag is started");
}
