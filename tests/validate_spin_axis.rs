//! The spin-axis parts of `sweetspot validate`: the summer-collegiate TrackMan table
//! (validation/trackman_hit_spin.csv) is what scripts/trackman_hit_spin.py derives from the shared exports
//! (re-derived when they are present), its bins' backspin and sidespin quartiles are re-derived here with a
//! plain string split and a textbook quantile, and the clock-face figure puts HitSpinAxis 180° at 12 o'clock,
//! 90° at 9 o'clock, 270° at 3 o'clock and 0° at 6 o'clock (TrackMan's Tilt-to-SpinAxis mapping).

mod support;

use std::path::PathBuf;
use std::process::Command;

use sweetspot::report::plot::{draw_clock_chart, ClockChart, ClockSeries, PALETTE};
use sweetspot::validate::hit_spin;

/// Quantile p of `v` by linear interpolation between order statistics at p·(n − 1) (Hyndman–Fan type 7).
fn textbook_quantile(mut v: Vec<f64>, p: f64) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let h = p * (v.len() - 1) as f64;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    v[lo] + (h - h.floor()) * (v[hi] - v[lo])
}

#[test]
fn the_bins_quartiles_are_those_of_the_committed_rows() {
    let text = std::fs::read_to_string(support::repo().join("validation/trackman_hit_spin.csv")).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // (launch, backspin, sidespin, left-handed) per ball: backspin −T cos a, sidespin T sin a.
    let balls: Vec<(f64, f64, f64, bool)> = lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            let f = |name: &str| c[col(name)].parse::<f64>().unwrap();
            let (t, a) = (f("HitSpinRate"), f("HitSpinAxis").to_radians());
            (f("Angle"), -t * a.cos(), t * a.sin(), c[col("BatterSide")] == "Left")
        })
        .collect();
    assert_eq!(balls.len(), 32, "tracked balls in play with a spin axis in the two games");
    let parsed = hit_spin::read(&support::repo().join("validation/trackman_hit_spin.csv")).unwrap();
    let bins = hit_spin::bins(&parsed);
    assert_eq!(bins.len(), 3);
    let mut binned = 0;
    for (bin, (low, high)) in bins.iter().zip([(-90.0, 10.0), (10.0, 20.0), (20.0, 90.0)]) {
        assert_eq!(bin.launch_range_deg, (low, high));
        let inside: Vec<_> = balls.iter().filter(|b| b.0 >= low && b.0 < high).collect();
        assert_eq!(bin.balls.len(), inside.len());
        assert!(inside.len() >= 10, "{low}–{high}°: {} balls", inside.len());
        binned += inside.len();
        assert_eq!(bin.balls.iter().filter(|b| b.left_handed).count(), inside.iter().filter(|b| b.3).count());
        for (got, pick) in [(bin.backspin, 1usize), (bin.sidespin, 2)] {
            let values: Vec<f64> = inside.iter().map(|b| if pick == 1 { b.1 } else { b.2 }).collect();
            for (q, p) in [(got.q1, 0.25), (got.median, 0.5), (got.q3, 0.75)] {
                let want = textbook_quantile(values.clone(), p);
                assert!((q - want).abs() < 1e-9, "{low}–{high}° column {pick} p{p}: {q} vs {want}");
            }
        }
    }
    assert_eq!(binned, 32, "every ball falls in a bin");
}

/// validation/trackman_hit_spin.csv is what scripts/trackman_hit_spin.py derives from the two exports
/// (skipped, saying so, when ../shared/reference/trackman is absent).
#[test]
fn committed_hit_spin_table_equals_a_fresh_derivation() {
    let reference = std::env::var_os("SWEETSPOT_REFERENCE_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| support::repo().join("../shared/reference"));
    if !reference.join("trackman/20250612-McBean-1_unverified.csv").is_file() {
        eprintln!("skipped: {} has no TrackMan exports, the table cannot be re-derived here", reference.display());
        return;
    }
    let python = std::env::var_os("SWEETSPOT_PYTHON").map(PathBuf::from).unwrap_or_else(|| "python3".into());
    let out = Command::new(&python)
        .arg(support::repo().join("scripts/trackman_hit_spin.py"))
        .arg("--check")
        .env("SWEETSPOT_REFERENCE_DIR", &reference)
        .output()
        .unwrap_or_else(|e| panic!("running {}: {e}", python.display()));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("equals a fresh derivation from 2 exports"), "{stdout}");
}

/// Circles of an SVG: (cx, cy, r, fill, stroke).
fn circles(svg: &str) -> Vec<(f64, f64, f64, String, String)> {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(svg);
    let mut out = Vec::new();
    loop {
        match reader.read_event().expect("well-formed SVG") {
            Event::Start(e) | Event::Empty(e) if e.name().as_ref() == "circle" => {
                let attr = |key: &str| {
                    e.attributes()
                        .flatten()
                        .find(|a| a.key.as_ref() == key)
                        .map(|a| a.value.to_string().to_ascii_uppercase())
                        .unwrap_or_default()
                };
                let num = |key: &str| attr(key).parse::<f64>().unwrap();
                out.push((num("cx"), num("cy"), num("r"), attr("fill"), attr("stroke")));
            }
            Event::Eof => return out,
            _ => {}
        }
    }
}

#[test]
fn the_clock_face_puts_backspin_at_twelve_and_a_hook_at_nine() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("clock.svg");
    // One series of four balls on the rim (3,000 rpm) and one ball at half the rim's spin.
    let chart = ClockChart {
        title: "test".into(),
        radius_label: "total spin (rpm)".into(),
        max_radius: 3000.0,
        rings: vec![1000.0, 2000.0],
        series: vec![
            ClockSeries {
                label: "rim".into(),
                color: 1,
                points: vec![(180.0, 3000.0), (90.0, 3000.0), (270.0, 3000.0), (0.0, 3000.0)],
                joined: false,
            },
            ClockSeries { label: "half".into(), color: 3, points: vec![(120.0, 1500.0)], joined: false },
        ],
        notes: vec![],
    };
    draw_clock_chart(&path, &chart).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    let all = circles(&svg);
    // The rim: the largest unfilled circle; its centre is the clock's.
    let rim = all.iter().filter(|c| c.3 == "NONE").max_by(|a, b| a.2.total_cmp(&b.2)).expect("rim");
    let (cx, cy, r) = (rim.0, rim.1, rim.2);
    let rings: Vec<f64> = all.iter().filter(|c| c.3 == "NONE" && c.0 == cx && c.1 == cy).map(|c| c.2).collect();
    assert_eq!(rings.len(), 3, "rings at 1000, 2000 and the rim: {rings:?}");
    let hex = |i: usize| {
        let c = PALETTE[i];
        format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
    };
    // The plotted balls (radius 4; the legend's glyphs are radius 5, outside the clock face).
    let dots = |i: usize| -> Vec<(f64, f64)> {
        all.iter().filter(|c| c.3 == hex(i) && c.2 == 4.0).map(|c| (c.0, c.1)).collect()
    };
    let near = |a: (f64, f64), b: (f64, f64)| (a.0 - b.0).abs() <= 1.0 && (a.1 - b.1).abs() <= 1.0;
    // SVG y grows downward: 12 o'clock is above the centre, 9 o'clock to its left.
    let want = [(cx, cy - r), (cx - r, cy), (cx + r, cy), (cx, cy + r)];
    let rim_dots = dots(1);
    assert_eq!(rim_dots.len(), 4, "{rim_dots:?}");
    for (got, (want, hour)) in rim_dots.iter().zip(want.iter().zip(["12:00", "9:00", "3:00", "6:00"])) {
        assert!(near(*got, *want), "{hour}: drawn at {got:?}, want {want:?} (centre {cx}, {cy}, rim {r})");
    }
    // 120°: 10 o'clock, half-way out: 60° left of 12, (cx − r/2 sin 60°, cy − r/2 cos 60°).
    let half = dots(3);
    let want = (cx - 0.5 * r * 60f64.to_radians().sin(), cy - 0.5 * r * 60f64.to_radians().cos());
    assert!(half.len() == 1 && near(half[0], want), "{half:?} vs {want:?}");
    assert!(draw_clock_chart(&path, &ClockChart { max_radius: 0.0, ..chart }).is_err());
}
