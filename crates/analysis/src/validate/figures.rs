//! The suite's figures, where a curve is compared: COR against speed, spin against launch angle, BPF against
//! hoop frequency, exit speed against impact point, total spin against launch angle in 3-D over the MLB radar,
//! the spin axis on a tracker's clock face over the summer-collegiate TrackMan balls. Drawn with the project's
//! charts ([`crate::report::plot`]).

use std::path::{Path, PathBuf};

use crate::report::plot::{
    draw_clock_chart, draw_line_chart, draw_panels, ClockChart, ClockSeries, ErrorBars, LineChart, LineKind, Series,
    VerticalMarker,
};
use sweetspot_physics::metrics::linspace;
use sweetspot_physics::Ball;

use super::cases::{wall_cor, Lab, MPH};
use super::{hit_spin, trackman, Inputs, Report, ValidateError};

fn points(label: &str, color: usize, pts: Vec<(f64, f64)>) -> Series {
    Series { label: label.into(), points: pts, color, kind: LineKind::Points }
}

fn marker(x: f64, label: &str, color: usize) -> VerticalMarker {
    VerticalMarker { x, label: label.into(), color, dashed: true }
}

/// The figures' file names, without the extension, in the order [`write`] draws them.
pub const NAMES: [&str; 6] = [
    "validate-cor-vs-speed",
    "validate-spin-vs-launch",
    "validate-bpf-vs-hoop",
    "validate-exit-vs-impact",
    "validate-radar-spin-vs-launch",
    "validate-spin-axis-clock",
];

/// The files [`write`] writes into `dir` (`ext`: `svg` or `png`).
pub fn paths(dir: &Path, ext: &str) -> Vec<PathBuf> {
    NAMES.iter().map(|name| dir.join(format!("{name}.{ext}"))).collect()
}

/// Draws `dir/name.ext` with `render`, naming the file in its error.
fn draw_with(
    dir: &Path,
    name: &str,
    ext: &str,
    render: impl FnOnce(&Path) -> anyhow::Result<()>,
) -> Result<PathBuf, ValidateError> {
    let path = dir.join(format!("{name}.{ext}"));
    render(&path).map_err(|e| ValidateError::Figure { path: path.clone(), message: format!("{e:#}") })?;
    Ok(path)
}

fn draw(dir: &Path, name: &str, ext: &str, chart: &LineChart) -> Result<PathBuf, ValidateError> {
    draw_with(dir, name, ext, |path| draw_line_chart(path, chart))
}

fn param_or(inputs: &Inputs, case: &str, key: &str, default: f64) -> f64 {
    inputs
        .measurements
        .row
        .iter()
        .filter(|r| r.case == case)
        .find_map(|r| match r.params.get(key) {
            Some(toml::Value::Float(v)) => Some(*v),
            Some(toml::Value::Integer(v)) => Some(*v as f64),
            _ => None,
        })
        .unwrap_or(default)
}

/// Draws the figures into `dir` (`ext`: `svg` or `png`) and returns their paths.
pub fn write(
    dir: &Path,
    ext: &str,
    inputs: &Inputs,
    report: &Report,
    lab: &Lab,
) -> Result<Vec<PathBuf>, ValidateError> {
    let mut out = vec![draw(dir, NAMES[0], ext, &cor_vs_speed(inputs, lab)?)?];
    out.push(draw(dir, NAMES[1], ext, &spin_vs_launch(inputs, report, lab)?)?);
    let bpf_panels = bpf_vs_hoop(inputs, lab)?;
    out.push(draw_with(dir, NAMES[2], ext, |path| {
        draw_panels(path, &bpf_panels, 1, Some("Alloy barrel, wall varied: lab test and swing"))
    })?);
    out.push(draw(dir, NAMES[3], ext, &exit_vs_impact(inputs, lab)?)?);
    if let Some(radar) = radar_spin_vs_launch(inputs, report) {
        out.push(draw(dir, NAMES[4], ext, &radar)?);
    }
    if let Some(chart) = spin_axis_clock(inputs, lab)? {
        out.push(draw_with(dir, NAMES[5], ext, |path| draw_clock_chart(path, &chart))?);
    }
    Ok(out)
}

/// COR against speed: the model's balls on a rigid wall, the MLB specification, the ball_cor.toml rows.
fn cor_vs_speed(inputs: &Inputs, lab: &Lab) -> Result<LineChart, ValidateError> {
    let phys = |source| ValidateError::Physics { case: "figure cor".to_string(), source };
    let speeds = linspace(5.0, 70.0, 27);
    let mut cor = LineChart {
        title: "Ball COR against a rigid wall vs impact speed".into(),
        x_label: "impact speed (m/s)".into(),
        y_label: "COR".into(),
        ..Default::default()
    };
    for (i, name) in [lab.game_ball.as_str(), "bbcor"].iter().enumerate() {
        let ball = Ball::preset(name).map_err(phys)?;
        let curve = speeds
            .iter()
            .map(|&v| wall_cor(&ball, v, lab.options.time_step).map(|e| (v, e)))
            .collect::<Result<Vec<_>, _>>()
            .map_err(phys)?;
        cor.series.push(Series::solid(format!("model, `{name}` ball"), i, curve));
    }
    let mlb = 85.0 * sweetspot_physics::units::FT_PER_S;
    cor.series.push(points("MLB specification 0.514–0.578 at 85 ft/s", 6, vec![(mlb, 0.514), (mlb, 0.578)]));
    let measured: Vec<(f64, f64)> =
        inputs.ball_cor.iter().filter_map(|c| super::speed_in_m_s(c).ok().map(|v| (v, c.value))).collect();
    if !measured.is_empty() {
        cor.series.push(points("measured (validation/ball_cor.toml)", 1, measured));
    }
    Ok(cor)
}

/// Spin against launch angle: game swing and tee tests of the model, TrackMan balls and bin medians, the tee
/// test's largest measured spin.
fn spin_vs_launch(inputs: &Inputs, report: &Report, lab: &Lab) -> Result<LineChart, ValidateError> {
    let mut spin = LineChart {
        title: "Batted-ball spin vs launch angle".into(),
        x_label: "launch angle (deg)".into(),
        y_label: "spin (rpm)".into(),
        x_range: Some((-10.0, 50.0)),
        ..Default::default()
    };
    if let Some(pitch) = trackman::pitch_medians(&inputs.trackman) {
        let attack = param_or(inputs, "game_spin_rpm", "attack_deg", 8.0);
        let curve = lab.game_curve(&pitch, attack)?;
        spin.series.push(Series::solid("model, average MLB game swing (R161)", 0, curve));
    }
    for (i, mph) in [63.0, 88.0].iter().enumerate() {
        let curve = lab.tee_curve("r161", mph * MPH)?;
        spin.series.push(Series::dashed(format!("model, tee, {mph:.0} mph bat"), 2 + i, curve));
    }
    spin.series.push(Series::dashed("tee test: largest measured (KNS 2017)", 6, vec![(0.0, 3500.0), (30.0, 3500.0)]));
    spin.series.push(points("TrackMan balls in play", 5, trackman::tracked_balls_in_play(&inputs.trackman)));
    let medians: Vec<(f64, f64)> =
        report.trackman_bins.iter().filter_map(|b| b.median_rpm.map(|m| (b.launch_deg, m))).collect();
    spin.series.push(points("TrackMan bin medians", 1, medians));
    let iqr: Vec<(f64, f64, f64)> =
        report.trackman_bins.iter().filter_map(|b| Some((b.launch_deg, b.q1_rpm?, b.q3_rpm?))).collect();
    spin.error_bars.push(ErrorBars {
        label: "TrackMan bin interquartile range".into(),
        color: 1,
        bars: iqr,
        horizontal: false,
    });
    Ok(spin)
}

/// `(hoop frequency, value)` of the points with a hoop frequency, in order of frequency.
fn by_hoop_frequency<P>(curve: &[P], hoop_hz: impl Fn(&P) -> f64, value: impl Fn(&P) -> f64) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> =
        curve.iter().filter(|p| hoop_hz(p).is_finite()).map(|p| (hoop_hz(p), value(p))).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    sorted
}

/// BPF against hoop frequency (the lab test), above the exit speed of a swing at equal effort against it.
fn bpf_vs_hoop(inputs: &Inputs, lab: &Lab) -> Result<[LineChart; 2], ValidateError> {
    let ball = inputs
        .measurements
        .row
        .iter()
        .find(|r| r.case == "bpf_hoop_trend")
        .and_then(|r| r.params.get("ball").and_then(|v| v.as_str().map(str::to_string)))
        .unwrap_or_else(|| "bbcor".into());
    let speed = param_or(inputs, "bpf_hoop_trend", "ball_speed_mph", 60.0) * MPH;
    let curve = lab.bpf_curve(&ball, speed)?;
    let sorted = by_hoop_frequency(&curve, |p| p.hoop_hz, |p| p.bpf);
    let band =
        vec![marker(1000.0, "measured hoop range 1–2.5 kHz", 2), marker(2500.0, "measured hoop range 1–2.5 kHz", 2)];
    let bpf = LineChart {
        title: "BPF (bat at rest, 60 mph) vs hoop frequency".into(),
        x_label: "hoop frequency 6 in from the end (Hz)".into(),
        y_label: "BPF = BBCOR / ball COR".into(),
        series: vec![
            Series::solid("model", 0, sorted.clone()),
            Series::dashed(
                "youth limit 1.15",
                6,
                vec![(sorted.first().map_or(1000.0, |p| p.0), 1.15), (sorted.last().map_or(2500.0, |p| p.0), 1.15)],
            ),
        ],
        markers: band.clone(),
        ..Default::default()
    };
    let swing = by_hoop_frequency(&curve, |p| p.hoop_hz, |p| p.swing_exit_speed / MPH);
    let matched = by_hoop_frequency(lab.matched_swing_curve()?, |p| p.hoop_hz, |p| p.exit_speed / MPH);
    let field = LineChart {
        title: "Exit speed in a swing at equal effort vs hoop frequency".into(),
        x_label: "hoop frequency 6 in from the end (Hz)".into(),
        y_label: "exit speed 6 in from the end (mph)".into(),
        series: vec![
            Series::dashed("model, wall alone (the bat's mass changes)", 1, swing),
            Series::solid("model, at aluminum's mass and swing weight", 0, matched),
        ],
        markers: band,
        ..Default::default()
    };
    Ok([bpf, field])
}

/// Exit speed against the impact point, at equal effort.
fn exit_vs_impact(inputs: &Inputs, lab: &Lab) -> Result<LineChart, ValidateError> {
    let pitch = param_or(inputs, "cage_exit_difference_mph", "pitch_speed", 40.0);
    let cage = lab.cage("r161", "aluminum", pitch)?;
    let (_, _, wood, metal) = &*cage;
    Ok(LineChart {
        title: "Exit speed vs impact point, one batter at equal effort".into(),
        x_label: "distance from the barrel end (in)".into(),
        y_label: "exit speed (mph)".into(),
        series: vec![Series::solid("r161", 0, wood.clone()), Series::solid("aluminum", 1, metal.clone())],
        markers: vec![
            marker(5.0, "first-mode node, measured 5–7 in", 2),
            marker(7.0, "first-mode node, measured 5–7 in", 2),
        ],
        ..Default::default()
    })
}

/// Total spin against launch angle, the 3-D model over the MLB radar (the `radar-spin/…` rows). `None` without
/// the radar table.
fn radar_spin_vs_launch(inputs: &Inputs, report: &Report) -> Option<LineChart> {
    if inputs.radar.is_empty() {
        return None;
    }
    let model: Vec<(f64, f64)> = inputs
        .radar
        .iter()
        .filter_map(|b| {
            let id = format!("radar-spin/{}deg", b.launch_deg);
            report.rows.iter().find(|r| r.id == id).and_then(|r| r.model).map(|m| (b.launch_deg, m))
        })
        .collect();
    Some(LineChart {
        title: "Total spin vs launch angle: 3-D model and MLB radar (80–88 mph)".into(),
        x_label: "launch angle (deg)".into(),
        y_label: "total spin (rpm)".into(),
        x_range: Some((0.0, 50.0)),
        series: vec![
            Series::solid("model, median over the bin's sprays (R161, tilted bat)", 0, model),
            points(
                "TrackMan radar, MLB 2018: median",
                1,
                inputs.radar.iter().map(|b| (b.launch_deg, b.spin_median_rpm)).collect(),
            ),
        ],
        error_bars: vec![ErrorBars {
            label: "radar interquartile range".into(),
            color: 1,
            bars: inputs.radar.iter().map(|b| (b.launch_deg, b.spin_q1_rpm, b.spin_q3_rpm)).collect(),
            horizontal: false,
        }],
        ..Default::default()
    })
}

/// TrackMan's spin axis (deg, [0, 360)) of a ball with `backspin` and `sidespin`: atan2(sidespin, −backspin).
fn axis_deg(backspin: f64, sidespin: f64) -> f64 {
    sidespin.atan2(-backspin).to_degrees().rem_euclid(360.0)
}

/// The spin axis on the clock face: the model's over the spray scan of the `trackman-…spin` rows' most
/// populous launch bin, for a right- and a left-handed batter (total spin as the distance from the centre),
/// over every collegiate TrackMan ball's HitSpinAxis and HitSpinRate. `None` without the TrackMan balls, the
/// radar table's swing paths or a pitch.
fn spin_axis_clock(inputs: &Inputs, lab: &Lab) -> Result<Option<ClockChart>, ValidateError> {
    let bins = hit_spin::bins(&inputs.hit_spin);
    let (Some(pitch), Some(bin)) =
        (trackman::pitch_medians(&inputs.trackman), bins.iter().max_by_key(|b| b.balls.len()))
    else {
        return Ok(None);
    };
    let mut series = Vec::new();
    let mut scan_note = None;
    if let Some(scan) = super::hit_spin_scan(lab, bin, &inputs.radar, &pitch)? {
        // Fair territory only: where the TrackMan balls went.
        let points: Vec<_> = scan.into_iter().filter(|p| p.spray_deg.abs() <= 45.0).collect();
        let right: Vec<(f64, f64)> =
            points.iter().map(|p| (axis_deg(p.backspin_rpm, p.sidespin_rpm), p.total_spin_rpm)).collect();
        // The left-handed batter's mirror image: the same backspin, the opposite sidespin.
        let left: Vec<(f64, f64)> =
            points.iter().map(|p| (axis_deg(p.backspin_rpm, -p.sidespin_rpm), p.total_spin_rpm)).collect();
        let (low, high) = (points.first().map_or(0.0, |p| p.spray_deg), points.last().map_or(0.0, |p| p.spray_deg));
        scan_note = Some(format!(
            "Model: R161 in 3-D at {:.0}° launch, {:.0} mph, spray {low:.0}° to {high:.0}°",
            bin.launch_median_deg,
            bin.exit_median_mph.unwrap_or(f64::NAN)
        ));
        series.push(ClockSeries { label: "model, right-handed batter".into(), color: 0, points: right, joined: true });
        series.push(ClockSeries { label: "model, left-handed batter".into(), color: 2, points: left, joined: true });
    }
    for (left_handed, label, color) in
        [(false, "TrackMan, right-handed batters", 1), (true, "TrackMan, left-handed batters", 3)]
    {
        let points: Vec<(f64, f64)> =
            inputs.hit_spin.iter().filter(|b| b.left_handed == left_handed).map(|b| (b.axis_deg, b.spin_rpm)).collect();
        series.push(ClockSeries { label: format!("{label} (n = {})", points.len()), color, points, joined: false });
    }
    let largest = series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).fold(0.0f64, f64::max);
    let max_radius = (largest / 1000.0).ceil().max(1.0) * 1000.0;
    Ok(Some(ClockChart {
        title: "Spin axis on the clock face: 3-D model and summer-collegiate TrackMan".into(),
        radius_label: "total spin (rpm)".into(),
        max_radius,
        rings: (1..).map(|k| 1000.0 * k as f64).take_while(|r| *r < max_radius).collect(),
        series,
        notes: scan_note
            .into_iter()
            .chain([
                "(the launch bin with the most TrackMan balls).".to_string(),
                "TrackMan: summer collegiate, files marked unverified,".into(),
                "every tracked ball in play, all launch angles.".into(),
                "12:00 pure backspin (HitSpinAxis 180°), 6:00 topspin (0°),".into(),
                "9:00 hook toward left field (90°), 3:00 slice (270°).".into(),
            ])
            .collect(),
    }))
}
