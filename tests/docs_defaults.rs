//! What the docs say the defaults are is what the program does: the ball `docs/physics.md` calls the default
//! is the ball `simulate` uses without `--ball`, and the wall-thickness figure's comparison curve is the one
//! `docs/cli.md` names.

mod support;

use std::process::Command;

fn sweetspot(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot")).args(args).output().expect("sweetspot runs");
    assert!(out.status.success(), "sweetspot {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).expect("UTF-8")
}

fn ball_of(json: &str) -> serde_json::Value {
    serde_json::from_str::<serde_json::Value>(json).expect("JSON")["ball"].clone()
}

#[test]
fn the_ball_the_physics_page_calls_the_default_is_the_one_simulate_uses() {
    let page = std::fs::read_to_string(support::repo().join("docs/physics.md")).expect("docs/physics.md");
    let flat = page.split_whitespace().collect::<Vec<_>>().join(" ");
    let after = flat.split_once("`--ball NAME` (`").expect("physics.md lists the balls").1;
    let (named, rest) = after.split_once('`').expect("a ball name");
    assert!(rest.starts_with(", the default"), "physics.md names its default first: {}", &after[..80.min(after.len())]);
    let default = ball_of(&sweetspot(&["simulate", "--json"]));
    let named_ball = ball_of(&sweetspot(&["simulate", "--json", "--ball", named]));
    assert_eq!(default, named_ball, "docs/physics.md calls `{named}` the default ball");
}

#[test]
fn the_wall_thickness_figure_draws_the_frequency_the_cli_page_names() {
    let dir = tempfile::tempdir().unwrap();
    sweetspot(&["figures", "--points", "10", dir.path().to_str().unwrap()]);
    let svg = std::fs::read_to_string(dir.path().join("fig-wall-thickness.svg")).expect("the figure");
    let page = std::fs::read_to_string(support::repo().join("docs/cli.md")).expect("docs/cli.md");
    let row = page.lines().find(|l| l.starts_with("| `fig-wall-thickness.*`")).expect("the figure's row");
    assert!(svg.contains("2/contact time"), "the figure's comparison curve changed");
    assert!(row.contains("2/contact time") && !row.contains("1/(2·contact time)"), "docs/cli.md: {row}");
}
