//! ROS time ↔ nanoseconds since the Unix epoch (the clock of MCAP log times), as methods on the message's
//! [`Time`]; and the one checked way a user-given number of seconds or rate becomes a [`Duration`].
//!
//! **Durations and rates from users.** Every duration flag or parameter (timeouts, delays, offsets, split
//! times) is checked by [`check_seconds`] (NaN and negatives refused, +∞ allowed) and converted by
//! [`saturating_secs`], which never panics: anything beyond [`FOREVER`] (1e300, +∞) is FOREVER, which
//! `Instant` arithmetic can hold. A span that is not a limit (a bag offset, a delay) is checked by
//! [`check_finite_seconds`] instead: +∞ there is a range error, not "for ever". Every rate (Hz) is checked by [`check_rate`] (finite, at least one per
//! FOREVER; a swing rate also at most [`MAX_SWING_RATE_HZ`], [`check_swing_rate`]) and turned into a period by
//! [`period_of`]; a time scale applied to a duration goes through
//! [`scaled`].

use std::time::Duration;

use sweetspot_msgs::builtin_interfaces::msg::Time;

/// The longest span a user-given duration stands for: 100 years, "for ever" in practice (an `Instant` plus
/// it does not overflow).
pub const FOREVER: Duration = Duration::from_secs(100 * 365 * 86_400);

/// The slowest rate accepted, Hz: one per [`FOREVER`].
pub const MIN_RATE_HZ: f64 = 1.0 / (100.0 * 365.0 * 86_400.0);

/// `seconds` as a Duration, never panicking: NaN and ≤ 0 give zero, anything at or beyond [`FOREVER`]
/// (+∞ included) gives FOREVER, and a positive value stays positive (1e-300 s gives 1 ns).
pub fn saturating_secs(seconds: f64) -> Duration {
    if seconds.is_nan() || seconds <= 0.0 {
        Duration::ZERO
    } else if seconds >= FOREVER.as_secs_f64() {
        FOREVER
    } else {
        Duration::from_secs_f64(seconds).max(Duration::from_nanos(1))
    }
}

/// The period of a rate `hz` (1/hz s), saturating as [`saturating_secs`] does (a rate ≤ 0 or NaN: FOREVER).
pub fn period_of(hz: f64) -> Duration {
    if hz > 0.0 {
        saturating_secs(1.0 / hz)
    } else {
        FOREVER
    }
}

/// `duration × factor`, saturating at [`FOREVER`] (a NaN or negative factor gives zero).
pub fn scaled(duration: Duration, factor: f64) -> Duration {
    saturating_secs(duration.as_secs_f64() * factor)
}

/// Whether a duration may be zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Least {
    /// 0 allowed (often "off" or "no wait").
    Zero,
    /// Must be above 0.
    AboveZero,
}

/// Checks a user-given number of seconds: NaN, negatives (and 0 under [`Least::AboveZero`]) are refused
/// with the range expected; +∞ and huge values are accepted and mean [`FOREVER`] ([`saturating_secs`]).
pub fn check_seconds(seconds: f64, least: Least) -> Result<f64, String> {
    let ok = match least {
        Least::Zero => seconds >= 0.0,
        Least::AboveZero => seconds > 0.0,
    };
    if ok {
        return Ok(seconds);
    }
    let bound = if least == Least::Zero { "≥ 0" } else { "> 0" };
    let value = super::limits::number(seconds);
    Err(format!("{value} s is out of range: expected seconds {bound} (inf or anything over 100 years: for ever)"))
}

/// Checks a user-given span that is not a limit (an offset into a bag, a delay before starting): as
/// [`check_seconds`], but +∞ is refused with the range expected, since "for ever" there would only mean the
/// command never does anything. Finite huge values still saturate at [`FOREVER`].
pub fn check_finite_seconds(seconds: f64, least: Least) -> Result<f64, String> {
    let seconds = check_seconds(seconds, least).map_err(|_| finite_range(seconds, least))?;
    if seconds.is_finite() {
        Ok(seconds)
    } else {
        Err(finite_range(seconds, least))
    }
}

fn finite_range(seconds: f64, least: Least) -> String {
    let bound = if least == Least::Zero { "≥ 0" } else { "> 0" };
    let value = super::limits::number(seconds);
    format!("{value} s is out of range: expected finite seconds {bound} (a span, not a limit: inf is not one)")
}

/// The fastest a rig (or the demo's rig) publishes swings, Hz: a swing every 100 µs, about what one node
/// answers (faster only fills its queue with DROPPED answers).
pub const MAX_SWING_RATE_HZ: f64 = 10_000.0;

/// Checks a user-given swing rate: a rate ([`check_rate`]) of at most [`MAX_SWING_RATE_HZ`].
pub fn check_swing_rate(hz: f64) -> Result<f64, String> {
    let hz = check_rate(hz)?;
    if hz <= MAX_SWING_RATE_HZ {
        Ok(hz)
    } else {
        let value = super::limits::number(hz);
        Err(format!("{value} Hz is out of range: expected at most {MAX_SWING_RATE_HZ} swings per second"))
    }
}

/// Checks a user-given rate: finite and at least [`MIN_RATE_HZ`] (one per 100 years).
pub fn check_rate(hz: f64) -> Result<f64, String> {
    if hz.is_finite() && hz >= MIN_RATE_HZ {
        return Ok(hz);
    }
    let value = super::limits::number(hz);
    Err(format!("{value} Hz is out of range: expected a finite rate ≥ {MIN_RATE_HZ:.2e} Hz (one per 100 years)"))
}

/// Conversions of a ROS `builtin_interfaces/Time` stamp.
pub trait RosTime: Sized {
    /// The stamp of `ns` nanoseconds since the Unix epoch (seconds saturate at `i32::MAX`).
    fn from_unix_ns(ns: u64) -> Self;
    /// Nanoseconds since the Unix epoch (0 for stamps before the epoch).
    fn unix_ns(&self) -> u64;
    /// The stamp of now.
    fn now() -> Self {
        Self::from_unix_ns(now_ns())
    }
}

impl RosTime for Time {
    fn from_unix_ns(ns: u64) -> Time {
        Time { sec: (ns / 1_000_000_000).min(i32::MAX as u64) as i32, nanosec: (ns % 1_000_000_000) as u32 }
    }

    fn unix_ns(&self) -> u64 {
        if self.sec < 0 {
            0
        } else {
            self.sec as u64 * 1_000_000_000 + self.nanosec as u64
        }
    }
}

/// Now, in nanoseconds since the Unix epoch (0 if the clock is before it).
pub fn now_ns() -> u64 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map(|d| d.as_nanos() as u64).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The user-facing extremes: nothing panics, "for ever" saturates, NaN and negatives are refused.
    #[test]
    fn durations_and_rates_at_the_extremes() {
        for v in [0.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e300, -1e300, 1e-300, -0.0] {
            let d = saturating_secs(v);
            assert!(d <= FOREVER, "{v}");
            let _ = std::time::Instant::now() + d;
            let _ = std::time::Instant::now() + period_of(v);
            let _ = std::time::Instant::now() + scaled(Duration::from_secs(u64::MAX), v);
            let _ = std::time::Instant::now() + scaled(Duration::from_nanos(1), v);
        }
        assert_eq!(saturating_secs(1e300), FOREVER);
        assert_eq!(saturating_secs(f64::INFINITY), FOREVER);
        assert_eq!(saturating_secs(1.5), Duration::from_millis(1500));
        assert_eq!(saturating_secs(1e-300), Duration::from_nanos(1));
        assert_eq!(saturating_secs(0.0), Duration::ZERO);
        assert_eq!(period_of(1e-300), FOREVER);
        assert_eq!(period_of(4.0), Duration::from_millis(250));
        assert_eq!(scaled(Duration::from_secs(10), 1e300), FOREVER);
        assert!(check_seconds(0.0, Least::Zero).is_ok());
        assert!(check_seconds(0.0, Least::AboveZero).is_err());
        assert!(check_seconds(1e-300, Least::AboveZero).is_ok());
        assert!(check_seconds(f64::INFINITY, Least::AboveZero).is_ok());
        assert!(check_seconds(f64::NAN, Least::Zero).unwrap_err().contains("out of range"));
        assert!(check_seconds(f64::NEG_INFINITY, Least::Zero).is_err());
        assert!(check_seconds(-1.0, Least::Zero).is_err());
        assert!(check_rate(1e-300).unwrap_err().contains("one per 100 years"));
        assert!(check_rate(f64::INFINITY).is_err() && check_rate(f64::NAN).is_err() && check_rate(0.0).is_err());
        assert!(check_rate(1e300).is_ok() && check_rate(MIN_RATE_HZ).is_ok());
        assert!(std::time::Instant::now().checked_add(period_of(MIN_RATE_HZ)).is_some());
    }

    #[test]
    fn stamps_round_trip() {
        let t = Time::from_unix_ns(1_700_000_000_123_456_789);
        assert_eq!((t.sec, t.nanosec), (1_700_000_000, 123_456_789));
        assert_eq!(t.unix_ns(), 1_700_000_000_123_456_789);
        assert_eq!(Time { sec: -1, nanosec: 0 }.unix_ns(), 0);
        assert_eq!(Time::from_unix_ns(u64::MAX).sec, i32::MAX);
    }
}
