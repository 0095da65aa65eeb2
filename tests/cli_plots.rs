//! Plots and figures are written, non-empty and of the requested format (PNG magic / SVG root).

mod support;

use std::path::Path;

use support::cli::{json, ok, s};

const PNG_MAGIC: &[u8] = b"\x89PNG\r\n\x1a\n";

fn assert_png(path: &Path) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(bytes.len() > 10_000, "{} is only {} bytes", path.display(), bytes.len());
    assert!(bytes.starts_with(PNG_MAGIC), "{} is not a PNG", path.display());
}

fn assert_svg(path: &Path) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(text.trim_start().starts_with("<svg"), "{} has no <svg> root", path.display());
    assert!(text.trim_end().ends_with("</svg>"), "{} is truncated", path.display());
    assert!(text.contains("<polyline") || text.contains("<path"), "{} draws no lines", path.display());
}

#[test]
fn sweep_plots_svg_and_png_with_labels() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("nested/sweep.svg");
    let doc = json(&["sweep", "--points", "12", "--modes", "6", "--plot", s(&svg)]);
    assert_eq!(doc["plot"].as_str(), Some(s(&svg)));
    assert_svg(&svg);
    let text = std::fs::read_to_string(&svg).unwrap();
    for label in [
        "exit speed vs impact point",
        "impact point z (m from the knob)",
        "ball exit speed (m/s)",
        "flexible bat",
        "rigid bat",
        "node of mode 1",
        "node of mode 2",
        "sweet spot",
    ] {
        assert!(text.contains(label), "'{label}' missing from the SVG");
    }
    let png = dir.path().join("sweep.PNG");
    let out = ok(&["sweep", "--bat", "aluminum", "--points", "12", "--modes", "6", "--plot", s(&png)]);
    assert!(out.contains("plot written to"), "{out}");
    assert_png(&png);
}

#[test]
fn figures_are_written_with_an_index() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(&["figures", s(dir.path()), "--points", "16", "--modes", "6"]);
    let files =
        ["fig2-rigid-exit-speed.svg", "fig5-normal-vs-corked.svg", "fig6-wood-vs-aluminum.svg", "mode-shapes.svg"];
    let index = std::fs::read_to_string(dir.path().join("README.md")).unwrap();
    for file in files {
        assert_svg(&dir.path().join(file));
        assert!(out.contains(file), "{file} not listed on stdout");
        assert!(index.contains(&format!("]({file})")), "{file} not linked from README.md");
    }
    let fig6 = std::fs::read_to_string(dir.path().join("fig6-wood-vs-aluminum.svg")).unwrap();
    assert!(fig6.contains("v_ball = 8 m/s, v_bat = 4 m/s"), "Figure 6 must state the seed's speeds");
    let shapes = std::fs::read_to_string(dir.path().join("mode-shapes.svg")).unwrap();
    for preset in ["r161", "r161-corked", "aluminum", "torpedo"] {
        assert!(shapes.contains(preset), "mode shapes of {preset} missing");
    }
}

#[test]
fn figures_at_equal_effort_and_against_wall_thickness_are_written_beside_the_seed_ones() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(&["figures", s(dir.path()), "--points", "12", "--modes", "4"]);
    let index = std::fs::read_to_string(dir.path().join("README.md")).unwrap();
    let expected: [(&str, &[&str]); 4] = [
        (
            "fig5-normal-vs-corked-equal-effort.svg",
            &["normal bat (reference swing)", "corked bat (×", "R161 corked (×", "equal effort"],
        ),
        (
            "fig6-wood-vs-aluminum-equal-effort.svg",
            &["wood (e_eff 0.4", "aluminum (e_eff 0.58", "aluminum + trampoline"],
        ),
        (
            "fig-compare-equal-effort.svg",
            &["r161 (swing weight", "r161-corked (swing weight", "aluminum (swing", "torpedo (swing"],
        ),
        (
            "fig-wall-thickness.svg",
            &["barrel wall thickness (mm)", "exit speed", "BBCOR", "hoop frequency", "NCAA limit 0.50"],
        ),
    ];
    for (file, labels) in expected {
        let path = dir.path().join(file);
        assert_svg(&path);
        assert!(out.contains(file), "{file} not listed on stdout");
        assert!(index.contains(&format!("]({file})")), "{file} not linked from README.md");
        let text = std::fs::read_to_string(&path).unwrap();
        for label in labels {
            assert!(text.contains(label), "'{label}' missing from {file}");
        }
    }
    // Figure 6's physical panel is wood against aluminum with the trampoline.
    let fig6 = std::fs::read_to_string(dir.path().join("fig6-wood-vs-aluminum.svg")).unwrap();
    assert!(fig6.contains("aluminum + trampoline flexible"), "Figure 6 lacks the trampoline series");
}

#[test]
fn compare_writes_its_equal_effort_figure() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("compare.svg");
    let out = ok(&["compare", "--bats", "r161,r161-corked", "--modes", "4", "--figure", s(&svg)]);
    assert!(out.contains("figure written to"), "{out}");
    assert_svg(&svg);
    let text = std::fs::read_to_string(&svg).unwrap();
    for label in ["r161 (swing weight", "r161-corked (swing weight", "usual impact point", "equal batter effort"] {
        assert!(text.contains(label), "'{label}' missing from the compare figure");
    }
    let png = dir.path().join("compare.png");
    ok(&["compare", "--bats", "r161,torpedo", "--modes", "4", "--figure", s(&png)]);
    assert_png(&png);
}

#[test]
fn figures_as_png() {
    let dir = tempfile::tempdir().unwrap();
    ok(&["figures", s(dir.path()), "--format", "png", "--points", "12", "--modes", "4"]);
    for file in
        ["fig2-rigid-exit-speed.png", "fig5-normal-vs-corked.png", "fig6-wood-vs-aluminum.png", "mode-shapes.png"]
    {
        assert_png(&dir.path().join(file));
    }
}

#[test]
fn library_charts_for_the_demo_draw_several_bats() {
    use sweetspot::physics::{Ball, Bat, CollisionOptions, Impact, ModeSet};
    use sweetspot::report::figures::{exit_speed_chart, exit_speed_overlay_chart, mode_shapes_chart};
    use sweetspot::report::plot::{draw_line_chart, draw_panels};
    use sweetspot::report::sweep::{run_sweep, SweepRange};

    let options = CollisionOptions { modes: 6, ..CollisionOptions::default() };
    let swing = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 45.0, impact_z: f64::NAN };
    let range = SweepRange { points: Some(10), ..SweepRange::default() };
    let docs: Vec<_> = ["r161", "aluminum"]
        .into_iter()
        .map(|name| run_sweep(&Bat::preset(name).unwrap(), &Ball::default(), &swing, range, &options).unwrap())
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let overlay = dir.path().join("overlay.svg");
    draw_line_chart(&overlay, &exit_speed_overlay_chart("Exit speed per bat", &docs)).unwrap();
    assert_svg(&overlay);
    let text = std::fs::read_to_string(&overlay).unwrap();
    assert!(text.contains("r161 sweet spot") && text.contains("aluminum sweet spot"));
    let single = dir.path().join("single.png");
    draw_line_chart(&single, &exit_speed_chart(&docs[1])).unwrap();
    assert_png(&single);
    let modes = ModeSet::compute(&Bat::preset("torpedo").unwrap(), 3).unwrap();
    let shapes = dir.path().join("shapes.svg");
    draw_panels(&shapes, &[mode_shapes_chart("torpedo", &modes, 3)], 1, Some("modes")).unwrap();
    assert_svg(&shapes);
    assert!(draw_panels(&dir.path().join("empty.svg"), &[], 1, None).is_err());
}

/// A plot box as (x0, y0, x1, y1), pixels.
type PlotBox = (f64, f64, f64, f64);

/// The plot box of a plotters SVG (the extent of its major grid lines, stroke #DADADA) and every series
/// polyline (stroke from the palette), in pixels.
fn plot_box_and_lines(svg: &str) -> (PlotBox, Vec<Vec<(f64, f64)>>) {
    use quick_xml::events::Event;
    let mut reader = quick_xml::Reader::from_str(svg);
    let (mut x0, mut y0, mut x1, mut y1) = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut lines = Vec::new();
    loop {
        match reader.read_event().expect("well-formed SVG") {
            Event::Start(e) | Event::Empty(e) => {
                let attr =
                    |key: &str| e.attributes().flatten().find(|a| a.key.as_ref() == key).map(|a| a.value.to_string());
                let num = |key: &str| attr(key).and_then(|v| v.parse::<f64>().ok());
                let stroke = attr("stroke").unwrap_or_default().to_ascii_uppercase();
                match e.name().as_ref() {
                    "line" if stroke == "#DADADA" => {
                        for (x, y) in [(num("x1"), num("y1")), (num("x2"), num("y2"))] {
                            let (x, y) = (x.unwrap(), y.unwrap());
                            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
                        }
                    }
                    "polyline" if !["#DADADA", "#F4F4F4", "#000000", ""].contains(&stroke.as_str()) => {
                        let points = attr("points").unwrap_or_default();
                        lines.push(
                            points
                                .split_whitespace()
                                .filter_map(|p| p.split_once(','))
                                .map(|(x, y)| (x.parse().unwrap(), y.parse().unwrap()))
                                .collect(),
                        );
                    }
                    _ => {}
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    ((x0, y0, x1, y1), lines)
}

/// A curve leaving the plot ends where it crosses the edge: no point outside the box and no stretch drawn
/// along its edge (plotters alone pins the points beyond to the edge, a false vertical or horizontal line).
#[test]
fn curves_leaving_the_plot_are_clipped_at_its_edge() {
    use sweetspot::report::plot::{draw_line_chart, LineChart, Series};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("clipped.svg");
    // y = x², past the top at x = 2, and a line below the bottom from the start.
    let parabola: Vec<(f64, f64)> = (0..=40).map(|k| k as f64 * 0.1).map(|x| (x, x * x)).collect();
    let low: Vec<(f64, f64)> = (0..=40).map(|k| k as f64 * 0.1).map(|x| (x, x - 2.0)).collect();
    let chart = LineChart {
        series: vec![Series::solid("parabola", 0, parabola), Series::dashed("line", 1, low)],
        x_range: Some((0.0, 3.0)),
        y_range: Some((0.0, 4.0)),
        ..Default::default()
    };
    draw_line_chart(&path, &chart).unwrap();
    let svg = std::fs::read_to_string(&path).unwrap();
    let ((x0, y0, x1, y1), lines) = plot_box_and_lines(&svg);
    assert!(x1 > x0 && y1 > y0, "no plot box found");
    assert!(!lines.is_empty(), "no series drawn");
    let on_edge = |p: &(f64, f64)| {
        (p.0 - x0).abs() < 1.0 || (p.0 - x1).abs() < 1.0 || (p.1 - y0).abs() < 1.0 || (p.1 - y1).abs() < 1.0
    };
    for line in &lines {
        for p in line {
            assert!(p.0 >= x0 - 1.0 && p.0 <= x1 + 1.0 && p.1 >= y0 - 1.0 && p.1 <= y1 + 1.0, "{p:?} outside the plot");
        }
        for w in line.windows(2) {
            assert!(
                !(on_edge(&w[0]) && on_edge(&w[1]) && w[0] != w[1] && (w[0].0 == w[1].0 || w[0].1 == w[1].1)),
                "a stretch along the edge: {w:?}"
            );
        }
    }
}
