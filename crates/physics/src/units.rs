//! The customary units bat testing and ball tracking quote (mph, inches, feet, rpm) in SI; degrees are
//! `f64::to_radians`.
//!
//! Each constant is the SI value of one customary unit, so `88.0 * MPH` is in m/s and `v / MPH` in mph. The
//! length units are exact by definition (international yard and pound, 1959; NIST SP 811, appendix B).

use std::f64::consts::TAU;

/// One inch in metres (exact).
pub const INCH: f64 = 0.0254;
/// One foot (12 in) in metres (exact).
pub const FOOT: f64 = 0.3048;
/// One foot per second in metres per second (exact).
pub const FT_PER_S: f64 = FOOT;
/// One mile per hour (1609.344 m in 3600 s) in metres per second (exact).
pub const MPH: f64 = 0.44704;

/// Converts rad/s to revolutions per minute.
pub fn rad_per_s_to_rpm(omega: f64) -> f64 {
    omega * 60.0 / TAU
}

/// Converts revolutions per minute to rad/s.
pub fn rpm_to_rad_per_s(rpm: f64) -> f64 {
    rpm * TAU / 60.0
}

#[cfg(test)]
mod tests {
    use super::*;

    // NIST SP 811 B.8: 1 in = 2.54 cm, 1 ft = 12 in, 1 mi = 5280 ft, all exact. Whole numbers of
    // ten-thousandths of a metre are exact in f64, and IEEE division rounds correctly, so each quotient is the
    // double nearest the exact value — the same double the decimal literal parses to.
    const TEN_THOUSANDTHS_PER_INCH: f64 = 254.0;

    #[test]
    fn inch_and_foot_are_the_exact_international_definitions() {
        assert_eq!(INCH, TEN_THOUSANDTHS_PER_INCH / 10_000.0);
        assert_eq!(FOOT, 12.0 * TEN_THOUSANDTHS_PER_INCH / 10_000.0);
        assert_eq!(FT_PER_S, FOOT);
    }

    #[test]
    fn mph_is_one_mile_per_hour_exactly() {
        let mile = 5280.0 * 12.0 * TEN_THOUSANDTHS_PER_INCH; // 16 093 440 ten-thousandths of a metre
        assert_eq!(MPH, mile / (10_000.0 * 3600.0));
    }

    #[test]
    fn sixty_rpm_is_one_turn_a_second() {
        assert!((rpm_to_rad_per_s(60.0) - TAU).abs() < 1e-15);
        assert!((rad_per_s_to_rpm(TAU) - 60.0).abs() < 1e-12);
        assert!((rpm_to_rad_per_s(rad_per_s_to_rpm(123.4)) - 123.4).abs() < 1e-12);
    }
}
