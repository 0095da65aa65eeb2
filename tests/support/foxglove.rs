//! Raw WebSocket frames for Foxglove clients that misbehave, and the server process's resident memory.

/// Opcodes of RFC 6455 5.2.
pub const TEXT: u8 = 0x1;
pub const BINARY: u8 = 0x2;
pub const CONTINUATION: u8 = 0x0;

/// A client frame's header (RFC 6455 5.2): `opcode`, FIN when `last`, a 64-bit length and an all-zero mask
/// key, so the payload goes out as it is.
pub fn frame_header(opcode: u8, last: bool, len: usize) -> Vec<u8> {
    let mut h = vec![if last { 0x80 } else { 0 } | opcode, 0x80 | 127];
    h.extend_from_slice(&(len as u64).to_be_bytes());
    h.extend_from_slice(&[0; 4]);
    h
}

/// The resident memory of process `pid` (VmRSS of /proc/PID/status), MiB.
pub fn rss_mib(pid: u32) -> f64 {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).expect("/proc/PID/status");
    let kb: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .expect("VmRSS");
    kb / 1024.0
}

/// Whether the server closes `stream` (EOF or reset) within `limit`, reading whatever it sends meanwhile.
pub fn closed_within(stream: &mut std::net::TcpStream, limit: std::time::Duration) -> bool {
    use std::io::Read;
    let end = std::time::Instant::now() + limit;
    let mut buf = [0u8; 4096];
    loop {
        let left = end.saturating_duration_since(std::time::Instant::now());
        if left.is_zero() {
            return false;
        }
        stream.set_read_timeout(Some(left)).expect("a read timeout");
        match stream.read(&mut buf) {
            Ok(0) => return true,
            Ok(_) => continue,
            Err(e) if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {
                return false
            }
            Err(_) => return true,
        }
    }
}
