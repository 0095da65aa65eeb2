//! What a peer may make the node hold or say: the longest string any message field may carry, the most
//! stations a bat profile may list, how much of a peer's text a rejection quotes, the physical limits of a
//! ball's compression and of a measured speed, and the one way numbers are printed in rejection texts.
//! Every check here runs before anything a peer sent is stored.

use std::borrow::Cow;

use sweetspot_msgs::sweetspot_msgs::msg::Swing;
use sweetspot_physics::Ball;

/// Longest string (bat_id, ball_id, preset, header.frame_id) a BatParams, BallParams or Swing may carry, bytes.
pub const MAX_STRING_BYTES: usize = 256;
/// Most stations a BatParams profile may list: a 1-mm grid on a 4 m profile, far beyond any bat.
pub const MAX_STATIONS: usize = 4096;
/// Bytes of an over-long or unknown string a rejection text quotes.
pub const QUOTED_PREFIX_BYTES: usize = 32;
/// Most ids an "unknown bat_id / ball_id" rejection lists.
pub const MAX_IDS_LISTED: usize = 20;
/// Most bytes of ids such a list holds (each id cut to [`QUOTED_PREFIX_BYTES`]).
pub const MAX_ID_LIST_BYTES: usize = 1024;
/// Longest ExitVelocity.message the node sends, bytes.
pub const MAX_MESSAGE_BYTES: usize = 4096;
/// Largest ball compression accepted, as a fraction of the ball's radius. The compression u is that of the
/// radius: at u = R the ball is pressed flat through its own centre, so no ball can take more, whatever its
/// force law says. (The point-contact law F = k·u^α is already strained past u ≈ R/2, where a sphere pressed
/// flat has a contact circle √(2Ru − u²) = 0.87 R wide; only the impossible is refused. A baseball at game
/// speeds compresses by about R/3.)
pub const MAX_COMPRESSION_FRACTION: f64 = 1.0;
/// Largest |attack_angle| and |pitch_angle| a swing may have, rad (80°, the oblique model's limit); the node,
/// `simulate` and case files all refuse beyond it.
pub const MAX_SWING_ANGLE: f64 = 80.0 * std::f64::consts::PI / 180.0;
/// Largest |pitch_spin| a swing may have, rad/s (~9,549 rpm, well above any pitch); the node, `simulate` and
/// case files all refuse beyond it.
pub const MAX_PITCH_SPIN: f64 = 1000.0;
/// Largest |measured_exit_speed| accepted, m/s: above any ball speed the node accepts (300 m/s) by far.
pub const MAX_MEASURED_SPEED: f64 = 1000.0;

/// `v` printed readably: plain decimals for 1e-4 ≤ |v| < 1e6 (and 0), else shortest scientific (`1e300`).
pub fn number(v: f64) -> String {
    sweetspot_physics::error::readable(v).to_string()
}

/// `s` cut to at most `max_bytes` (on a character boundary), with `…` and its full length when cut.
pub fn shorten(s: &str, max_bytes: usize) -> Cow<'_, str> {
    if s.len() <= max_bytes {
        return Cow::Borrowed(s);
    }
    let mut end = max_bytes;
    while !s.is_char_boundary(end) {
        end -= 1;
    }
    Cow::Owned(format!("{}…({} bytes)", &s[..end], s.len()))
}

/// A peer's string as an answer echoes it (an id, a `header.frame_id`, a message): at most `max_bytes` bytes
/// in all, its marker `…(N bytes)` included when it had to be cut (on a character boundary).
pub fn bounded(s: &str, max_bytes: usize) -> Cow<'_, str> {
    if s.len() <= max_bytes {
        return Cow::Borrowed(s);
    }
    let marker = format!("…({} bytes)", s.len());
    let mut end = max_bytes.saturating_sub(marker.len());
    while !s.is_char_boundary(end) {
        end -= 1;
    }
    if end == 0 && marker.len() > max_bytes {
        // No room for the marker: the plain prefix.
        let mut end = max_bytes;
        while !s.is_char_boundary(end) {
            end -= 1;
        }
        return Cow::Owned(s[..end].to_string());
    }
    Cow::Owned(format!("{}{marker}", &s[..end]))
}

/// An id or `header.frame_id` as an answer echoes it: at most [`MAX_STRING_BYTES`] bytes.
pub fn echo(s: &str) -> Cow<'_, str> {
    bounded(s, MAX_STRING_BYTES)
}

/// A peer's string as a rejection text quotes it: at most [`QUOTED_PREFIX_BYTES`] of it.
pub fn quote(s: &str) -> Cow<'_, str> {
    shorten(s, QUOTED_PREFIX_BYTES)
}

/// Refuses a string field longer than [`MAX_STRING_BYTES`], naming the field and the limit.
pub fn check_string(field: &str, value: &str) -> Result<(), String> {
    if value.len() <= MAX_STRING_BYTES {
        return Ok(());
    }
    Err(format!(
        "{field} is {} bytes long, over the limit of {MAX_STRING_BYTES} bytes (it starts '{}')",
        value.len(),
        quote(value)
    ))
}

/// Refuses a measured value that is ±inf or beyond ±[`MAX_MEASURED_SPEED`]; NaN means "not measured".
pub fn check_measured_speed(field: &str, value: f64) -> Result<(), String> {
    if value.is_nan() || value.abs() <= MAX_MEASURED_SPEED {
        return Ok(());
    }
    Err(format!(
        "{field} = {} m/s is out of range: expected NaN (not measured) or −{} ≤ {field} ≤ {} m/s",
        number(value),
        number(MAX_MEASURED_SPEED),
        number(MAX_MEASURED_SPEED)
    ))
}

/// What a Swing carries besides its initial conditions (checked by the physics): its strings and its
/// measured exit speed.
pub fn check_swing(swing: &Swing) -> Result<(), String> {
    check_string("header.frame_id", &swing.header.frame_id)?;
    check_string("bat_id", &swing.bat_id)?;
    check_string("ball_id", &swing.ball_id)?;
    check_measured_speed("measured_exit_speed", swing.measured_exit_speed)
}

/// Refuses a collision whose largest compression exceeds [`MAX_COMPRESSION_FRACTION`] of the ball's radius,
/// naming the ball and its force law.
pub fn check_compression(ball_id: &str, ball: &Ball, max_compression: f64) -> Result<(), String> {
    let limit = MAX_COMPRESSION_FRACTION * ball.radius;
    if max_compression <= limit {
        return Ok(());
    }
    Err(format!(
        "ball '{}' (stiffness = {} N/m^α, exponent α = {}, radius = {} m) is compressed by {} m in this collision, \
         more than a ball can take: expected max_compression ≤ {} × radius = {} m (beyond it the contact is no \
         longer a local deformation and the force law does not hold); use a stiffer ball or a slower swing",
        quote(ball_id),
        number(ball.stiffness),
        number(ball.exponent),
        number(ball.radius),
        number(max_compression),
        number(MAX_COMPRESSION_FRACTION),
        number(limit)
    ))
}

/// Ids for a rejection text, sorted: at most [`MAX_IDS_LISTED`] of them and [`MAX_ID_LIST_BYTES`] in all,
/// each cut to [`QUOTED_PREFIX_BYTES`]; what is left out is counted.
pub fn list_ids<'a>(ids: impl Iterator<Item = &'a str>) -> String {
    let mut ids: Vec<&str> = ids.collect();
    ids.sort_unstable();
    let mut shown = String::new();
    let mut listed = 0;
    for id in &ids {
        let id = quote(id);
        if listed == MAX_IDS_LISTED || shown.len() + id.len() + 2 > MAX_ID_LIST_BYTES {
            break;
        }
        if listed > 0 {
            shown.push_str(", ");
        }
        shown.push_str(&id);
        listed += 1;
    }
    if ids.len() > listed {
        shown.push_str(&format!("{}… {} more", if listed > 0 { ", " } else { "" }, ids.len() - listed));
    }
    shown
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_print_short_whatever_their_magnitude() {
        assert_eq!(number(1e300), "1e300");
        assert_eq!(number(-1e300), "-1e300");
        assert_eq!(number(5e-324), "5e-324");
        assert_eq!(number(f64::MAX), "1.7976931348623157e308");
        assert_eq!(number(0.0005), "0.0005");
        assert_eq!(number(0.0366), "0.0366");
        assert_eq!(number(40.0), "40");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(1e6), "1e6");
        assert_eq!(number(f64::NAN), "NaN");
        assert_eq!(number(f64::NEG_INFINITY), "-inf");
        assert!(number(f64::MIN_POSITIVE).len() < 30);
    }

    #[test]
    fn long_strings_are_refused_quoting_only_a_prefix() {
        assert!(check_string("bat_id", &"x".repeat(MAX_STRING_BYTES)).is_ok());
        let e = check_string("bat_id", &"é".repeat(1 << 19)).unwrap_err();
        assert!(e.starts_with("bat_id is 1048576 bytes long, over the limit of 256 bytes"), "{e}");
        assert!(e.len() < 200, "{} bytes: {e}", e.len());
        assert_eq!(shorten("abc", 3), "abc");
        assert_eq!(shorten("aé", 2), "a…(3 bytes)");
    }

    #[test]
    fn echoed_strings_hold_at_most_their_limit_marker_included() {
        assert_eq!(echo("rig"), "rig");
        let at_limit = "x".repeat(MAX_STRING_BYTES);
        assert_eq!(echo(&at_limit), at_limit.as_str());
        for n in [MAX_STRING_BYTES + 1, 300, 70_000, 10 << 20] {
            let long = "é".repeat(n / 2 + 1);
            let e = echo(&long);
            assert!(e.len() <= MAX_STRING_BYTES, "{n}: {} bytes", e.len());
            assert!(e.starts_with("éé") && e.ends_with(" bytes)"), "{e}");
        }
        assert_eq!(bounded("abcdef", 3), "abc");
        assert_eq!(bounded("abcdef", 6), "abcdef");
        assert!(bounded(&"m".repeat(10_000), MAX_MESSAGE_BYTES).len() <= MAX_MESSAGE_BYTES);
    }

    #[test]
    fn id_lists_are_bounded_in_count_and_bytes() {
        let ids: Vec<String> = (0..5000).map(|i| format!("{i:04}{}", "b".repeat(300))).collect();
        let list = list_ids(ids.iter().map(String::as_str));
        assert!(list.len() <= MAX_ID_LIST_BYTES + 40, "{}", list.len());
        assert!(list.starts_with("0000bbb") && list.ends_with("more"), "{list}");
        let few = list_ids(["b", "a"].into_iter());
        assert_eq!(few, "a, b");
        assert_eq!(list_ids(std::iter::empty()), "");
    }

    #[test]
    fn measured_speeds_are_finite_and_bounded_or_nan() {
        assert!(check_measured_speed("m", f64::NAN).is_ok());
        assert!(check_measured_speed("m", -45.0).is_ok());
        for bad in [f64::INFINITY, f64::NEG_INFINITY, 1e300, -1000.5] {
            let e = check_measured_speed("measured_exit_speed", bad).unwrap_err();
            assert!(e.contains("measured_exit_speed") && e.len() < 150, "{e}");
        }
        assert!(check_measured_speed("m", 1e300).unwrap_err().contains("= 1e300 m/s"));
    }
}
