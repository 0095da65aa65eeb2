//! ROS time ↔ nanoseconds since the Unix epoch (the clock of MCAP log times), as methods on the message's
//! [`Time`].

use crate::msgs::builtin_interfaces::msg::Time;

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

    #[test]
    fn stamps_round_trip() {
        let t = Time::from_unix_ns(1_700_000_000_123_456_789);
        assert_eq!((t.sec, t.nanosec), (1_700_000_000, 123_456_789));
        assert_eq!(t.unix_ns(), 1_700_000_000_123_456_789);
        assert_eq!(Time { sec: -1, nanosec: 0 }.unix_ns(), 0);
        assert_eq!(Time::from_unix_ns(u64::MAX).sec, i32::MAX);
    }
}
