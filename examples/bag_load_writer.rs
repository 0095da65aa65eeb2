//! Records under load until killed: the subject of the kill -9 test (tests/bag_kill.rs).
//!
//! Usage: `bag_load_writer DIR FLUSH_MS`. Prints `started` once recording, then records std_msgs/String
//! messages `"<index> <log_time_ns>"` round-robin on three topics as fast as a light throttle allows,
//! forever. Exits with status 3 if a message is ever dropped (the test counts on a gap-free sequence).

use std::io::Write;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use sweetspot::bag::{RecordedQos, Recorder, RecorderConfig, TopicInfo};

fn cdr_string(text: &str) -> Vec<u8> {
    let mut out = vec![0x00, 0x01, 0x00, 0x00];
    out.extend_from_slice(&((text.len() + 1) as u32).to_le_bytes());
    out.extend_from_slice(text.as_bytes());
    out.push(0);
    while out.len() % 4 != 0 {
        out.push(0);
    }
    out
}

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let dir = args.next().ok_or_else(|| anyhow::anyhow!("usage: bag_load_writer DIR FLUSH_MS"))?;
    let flush_ms: u64 = args.next().ok_or_else(|| anyhow::anyhow!("usage: bag_load_writer DIR FLUSH_MS"))?.parse()?;
    let mut config = RecorderConfig::new(dir);
    config.flush_interval = Duration::from_millis(flush_ms);
    let recorder = Recorder::start(config)?;
    let qos = RecordedQos { reliable: true, transient_local: false, depth: 10 };
    let topics = ["/load/a", "/load/b", "/load/c"]
        .iter()
        .map(|name| {
            recorder.register_topic(TopicInfo {
                name: name.to_string(),
                type_name: "std_msgs/msg/String".to_string(),
                schema_text: "string data\n".to_string(),
                type_hash: String::new(),
                qos,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    println!("started");
    std::io::stdout().flush()?;
    for index in 0u64.. {
        let now = SystemTime::now().duration_since(UNIX_EPOCH)?.as_nanos() as u64;
        let payload = cdr_string(&format!("{index} {now} {}", "x".repeat(100)));
        if !recorder.record(topics[(index % 3) as usize], payload, now, now) {
            eprintln!("dropped message {index}: {:?}", recorder.stats());
            std::process::exit(3);
        }
        if index % 50 == 49 {
            std::thread::sleep(Duration::from_millis(1));
        }
    }
    Ok(())
}
