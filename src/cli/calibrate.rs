//! `sweetspot calibrate BAG`: fit the ball's COR (and, with `--fit-youngs`, each bat's Young's modulus) to
//! the measured exit speeds of a recorded session, and optionally write the fitted params for `sweetspot pub`;
//! with `--fit-batter`, fit the batter (bat speed against swing weight) and write it for `sweetspot compare`.

use std::io::Write as _;

use super::common::{emit, print_json};
use crate::outln;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use clap::Args;
use serde_json::json;

use crate::calibrate::batter::{batter_fit_from_bag, render_batter_fit, BatterFit, BatterFitOptions};
use crate::calibrate::cor_speed::fit_cor_law;
use crate::calibrate::{fit, problem_from_bag, CalibrateError, Fit, FitOptions, Problem};
use crate::model::convert::{params_from_ball, params_from_bat};
use crate::msgs::json::ToJson;
use crate::msgs::std_msgs::msg::Header;
use crate::physics::oblique::TangentialContact;
use crate::report::table::{num, Table};

/// Arguments of `sweetspot calibrate`.
#[derive(Debug, Args)]
#[command(after_help = "Examples:
  sweetspot calibrate bags/demo_2026_11_21-05_00_00
  sweetspot calibrate bags/demo_2026_11_21-05_00_00 --fit-youngs --write fitted.jsonl
  sweetspot pub ball --file fitted.jsonl        # send the fitted ball to a running node
  sweetspot calibrate bags/demo_2026_11_21-05_00_00 --fit-tangential --write fitted.jsonl   # e_T in tangential_cor
  sweetspot calibrate bags/demo_2026_11_21-05_00_00 --batter-out batter.toml
  sweetspot compare --batter batter.toml        # the bats as the fitted batter swings them")]
pub struct CalibrateArgs {
    /// The recorded session: a rosbag2 directory (or one .mcap file) with Swing messages whose
    /// measured_exit_speed is set, and the BatParams/BallParams they refer to.
    pub bag: PathBuf,
    /// Also fit each bat's shell Young's modulus (one parameter per bat).
    #[arg(long)]
    pub fit_youngs: bool,
    /// Fit the swings made with this ball_id (default: the ball most measured swings used).
    #[arg(long, value_name = "BALL_ID")]
    pub ball: Option<String>,
    /// Write the fitted BallParams as JSON lines to FILE (for `sweetspot pub ball --file FILE`), with the
    /// fitted e_T as tangential_cor under --fit-tangential (else the bag's); with --fit-youngs the fitted
    /// BatParams go to FILE with `.bats` before the extension.
    #[arg(long, value_name = "FILE")]
    pub write: Option<PathBuf>,
    /// Iteration limit of Levenberg–Marquardt, for each fit (0 runs none: the start values with their
    /// uncertainties, reported as not converged).
    #[arg(long, default_value_t = 30, value_name = "N")]
    pub max_iterations: usize,
    /// Residual rows printed (largest |residual| first); 0 = all.
    #[arg(long, default_value_t = 12, value_name = "N")]
    pub show: usize,
    /// Print one JSON document instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Fit the batter instead: bat speed at the usual impact point against the bats' swing weights,
    /// v = v_ref·(I/I_ref)^(−n) (needs a session with bats of two or more swing weights).
    #[arg(long, conflicts_with_all = ["fit_youngs", "write", "fit_tangential"])]
    pub fit_batter: bool,
    /// The bat_id whose swing is the fitted batter's reference [default: the bat of the first swing]; implies
    /// --fit-batter.
    #[arg(long, value_name = "BAT_ID", conflicts_with_all = ["fit_youngs", "write", "fit_tangential"])]
    pub reference_bat: Option<String>,
    /// Write the fitted batter to FILE in the format `sweetspot compare --batter` and `sweetspot demo --batter`
    /// read (implies --fit-batter; a reference bat that is no preset is written beside it as a bat file).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["fit_youngs", "write", "fit_tangential"])]
    pub batter_out: Option<PathBuf>,
    /// Also fit the tangential COR e_T (and unmeasured undercuts) to the measured launch angles and spins.
    #[arg(long)]
    pub fit_tangential: bool,
    /// Fit a damaged bag with everything intact around the damage (the damage is still listed); without
    /// it a damaged bag is refused and nothing is written.
    #[arg(long)]
    pub skip_damaged: bool,
    /// Write --write's files even when a fit did not converge within --max-iterations (without it, a fit
    /// that did not converge writes nothing and exits with status 1).
    #[arg(long)]
    pub force: bool,
    /// Also fit how the ball's COR falls with impact speed, e0(v) = cor·(v/v_ref)^(−p), to sessions at several
    /// pitch speeds; --write then writes the fitted law (cor_speed_exponent, cor_reference_speed).
    #[arg(long, conflicts_with = "fit_youngs")]
    pub fit_cor_exponent: bool,
}

/// A calibration error as one message: its text already holds every cause, which anyhow would repeat.
fn flat(err: CalibrateError) -> anyhow::Error {
    anyhow!("{err}")
}

/// Runs `sweetspot calibrate`.
pub fn run(args: CalibrateArgs) -> Result<()> {
    // The bag tools' damage rule, before anything is fitted or written.
    let skipped = crate::bag_tools::check_damage(&args.bag, args.skip_damaged)?;
    run_checked(args)?;
    if let Some(skipped) = skipped {
        eprintln!("skipped (--skip-damaged): {skipped}");
    }
    Ok(())
}

fn run_checked(args: CalibrateArgs) -> Result<()> {
    if args.fit_batter || args.batter_out.is_some() || args.reference_bat.is_some() {
        return run_batter(&args);
    }
    if let Some(path) = &args.write {
        refuse_onto_the_bag("--write", path, &args.bag)?;
        refuse_onto_the_bag("--write", &bats_path(path), &args.bag)?;
    }
    let problem = problem_from_bag(&args.bag, args.ball.as_deref())
        .map_err(flat)
        .with_context(|| format!("calibrating from '{}'", args.bag.display()))?;
    let assumed = assumed_inputs(&args.bag)?;
    if let Some(warning) = assumed_warning(&assumed, problem.observations.len(), &args.bag) {
        eprintln!("{warning}");
    }
    let fits = Fits::of(&args, &problem)?;
    let written = match &args.write {
        Some(_) if !fits.converged() && !args.force => Vec::new(),
        Some(path) => {
            // The fitted e_T when there is one, else the contact the bag's BallParams gave the node.
            let contact = fits.tangential.as_ref().map_or(problem.contact, |t| t.contact);
            write_params(path, &problem, &fits.result, &contact)?
        }
        None => Vec::new(),
    };
    if args.json {
        print_json(&fits.json(&args.bag, &problem, &assumed, &written))?;
    } else {
        fits.print(&problem, args.show, &written)?;
    }
    if !fits.converged() {
        let limit = args.max_iterations;
        if args.force {
            eprintln!("warning: a fit did not converge within --max-iterations {limit}; written anyway (--force)");
        } else {
            let nothing = if args.write.is_some() { "; nothing written (--force writes anyway)" } else { "" };
            bail!("a fit did not converge within --max-iterations {limit} (raise it){nothing}");
        }
    }
    Ok(())
}

/// The fits `calibrate` makes of a bag: the exit-speed fit, and the COR's speed law and e_T when asked for.
struct Fits {
    result: Fit,
    cor_law: Option<crate::calibrate::cor_speed::CorLawFit>,
    tangential: Option<crate::calibrate::tangential::TangentialFit>,
}

impl Fits {
    fn of(args: &CalibrateArgs, problem: &Problem) -> Result<Fits> {
        let options =
            FitOptions { fit_youngs: args.fit_youngs, max_iterations: args.max_iterations, ..FitOptions::default() };
        let result = fit(problem, &options).map_err(flat).context("fitting")?;
        let cor_law = match args.fit_cor_exponent {
            true => Some(fit_cor_law(problem, &options).map_err(flat).context("fitting the COR's speed law")?),
            false => None,
        };
        // With --fit-cor-exponent the ball written (and handed to the e_T fit) is the one with the fitted law.
        let result = match &cor_law {
            Some(law) => Fit { ball: law.ball, ..result },
            None => result,
        };
        let tangential = match args.fit_tangential {
            true => Some(fit_tangential_of(args, &result)?),
            false => None,
        };
        Ok(Fits { result, cor_law, tangential })
    }

    fn converged(&self) -> bool {
        self.result.converged
            && self.cor_law.as_ref().is_none_or(|l| l.converged)
            && self.tangential.as_ref().is_none_or(|t| t.converged)
    }

    /// The `--json` document.
    fn json(&self, bag: &Path, problem: &Problem, assumed: &[(String, u64)], written: &[PathBuf]) -> serde_json::Value {
        let result = &self.result;
        json!({
            "bag": bag,
            "ball_id": problem.ball_id,
            "swings": problem.observations.len(),
            "assumed": assumed.iter().map(|(k, n)| (k.clone(), json!(n))).collect::<serde_json::Map<_, _>>(),
            "skipped": problem.skipped,
            "parameters": result.parameters,
            "rms_before": result.rms_before,
            "rms": result.rms,
            "residual_sigma": result.residual_sigma,
            "dof": result.dof,
            "iterations": result.iterations,
            "converged": result.converged,
            "residuals": result.residuals,
            "written": written,
            "cor_law": self.cor_law.as_ref().map(|l| json!({
                "parameters": l.parameters, "reference_speed": l.reference_speed, "speed_range": l.speed_range,
                "rms_before": l.rms_before, "rms": l.rms, "residual_sigma": l.residual_sigma, "dof": l.dof,
                "converged": l.converged,
            })),
            "tangential": self.tangential.as_ref().map(|t| json!({
                "parameters": t.parameters, "residual_sigma": t.residual_sigma, "dof": t.dof,
                "iterations": t.iterations, "converged": t.converged, "residuals": t.residuals, "skipped": t.skipped,
            })),
        })
    }

    /// The reports of the fits, the files written and how to send them to a node.
    fn print(&self, problem: &Problem, show: usize, written: &[PathBuf]) -> Result<()> {
        emit(&report(problem, &self.result, show))?;
        if let Some(law) = &self.cor_law {
            emit(&format!("\n{}", crate::calibrate::cor_speed::report(law)))?;
        }
        if let Some(t) = &self.tangential {
            emit(&format!("\n{}", crate::calibrate::tangential::report(t)))?;
        }
        for path in written {
            outln!("wrote {}", path.display())?;
        }
        if let Some(path) = written.first() {
            outln!("send it to a running node:  sweetspot pub ball --file {}", path.display())?;
        }
        if let Some(path) = written.get(1) {
            outln!("                            sweetspot pub bat --file {}", path.display())?;
        }
        Ok(())
    }
}

/// What the swings of an imported session did not measure: `sweetspot import` writes it into the bag's
/// custom_data (`sweetspot/import/assumed`, field:swings), in its order; empty for a recorded session.
fn assumed_inputs(bag: &Path) -> Result<Vec<(String, u64)>> {
    let scans = crate::bag::reader::read_bag(bag, |_| {}).with_context(|| format!("reading '{}'", bag.display()))?;
    let custom = crate::bag::info::custom_data_of(&scans);
    let Some(list) = custom.get("sweetspot/import/assumed") else { return Ok(Vec::new()) };
    Ok(list
        .split(',')
        .filter_map(|item| {
            let (field, n) = item.split_once(':')?;
            Some((field.trim().to_string(), n.trim().parse().ok()?))
        })
        .filter(|(_, n)| *n > 0)
        .collect())
}

/// The warning a fit to assumed inputs must carry: which inputs, for how many swings, and what σ does not cover.
fn assumed_warning(assumed: &[(String, u64)], swings: usize, bag: &Path) -> Option<String> {
    let what = |field: &str| match field {
        "impact_z" => "the impact point (the batter's usual one)".to_string(),
        "bat_speed" => "the bat speed (the batter model's swing)".to_string(),
        other => other.replace('_', " "),
    };
    // The two that set the COR's answer first: an exit speed is as much the bat's speed and where it met the ball.
    let rank = |field: &str| match field {
        "impact_z" => 0,
        "bat_speed" => 1,
        _ => 2,
    };
    let mut items: Vec<&(String, u64)> = assumed.iter().collect();
    items.sort_by_key(|(field, _)| rank(field));
    if !items.iter().any(|(field, _)| rank(field) < 2) {
        return None;
    }
    let list: Vec<String> = items.iter().map(|(field, n)| format!("{} for {n} swings", what(field))).collect();
    Some(format!(
        "warning: imported session: the fit's inputs were assumed, not measured: {} (of {swings} fitted). The COR \
         and its ± σ below hold only as far as those assumptions do: σ is the scatter of the measured exit speeds, \
         not the uncertainty of what was assumed. `sweetspot locate {}` estimates each impact point from the \
         measured launch angle and spin.",
        list.join(", "),
        bag.display()
    ))
}

/// Refuses an output of `calibrate` that is a file of the bag being read, or a new file in its directory.
fn refuse_onto_the_bag(flag: &str, output: &Path, bag: &Path) -> Result<()> {
    crate::files::refuse_clobber(flag, output, &[], &[bag.to_path_buf()]).map_err(|e| anyhow!(e))
}

/// Where `--write FILE` puts the fitted bats: FILE with `.bats` before the extension.
fn bats_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("fitted");
    let ext = path.extension().and_then(|s| s.to_str()).unwrap_or("jsonl");
    path.with_file_name(format!("{stem}.bats.{ext}"))
}

/// `sweetspot calibrate --fit-batter`: fits, prints and (with `--batter-out`) writes the batter.
fn run_batter(args: &CalibrateArgs) -> Result<()> {
    if let Some(path) = &args.batter_out {
        refuse_onto_the_bag("--batter-out", path, &args.bag)?;
    }
    let options = BatterFitOptions { reference_bat: args.reference_bat.clone(), ..BatterFitOptions::default() };
    let result = batter_fit_from_bag(&args.bag, &options)
        .map_err(flat)
        .with_context(|| format!("fitting a batter to '{}'", args.bag.display()))?;
    let written = match &args.batter_out {
        Some(path) => write_batter_file(path, &result, &args.bag)?,
        None => Vec::new(),
    };
    if args.json {
        let mut doc = serde_json::to_value(&result).context("serialising the result")?;
        doc["bag"] = json!(args.bag);
        doc["written"] = json!(written);
        return print_json(&doc);
    }
    emit(&render_batter_fit(&result))?;
    for path in &written {
        outln!("wrote {}", path.display())?;
    }
    if let Some(path) = written.last() {
        outln!("compare bats as this batter swings them:  sweetspot compare --batter {}", path.display())?;
    }
    Ok(())
}

/// Writes the batter file of `result` to `path` (and, for a reference bat that is no preset, its bat file
/// `STEM.BAT_ID.toml` + `.csv` beside it); returns the files written, the batter file last.
pub fn write_batter_file(path: &Path, result: &BatterFit, bag: &Path) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let reference = match &result.reference_preset {
        Some(preset) => preset.clone(),
        None => {
            let dir = path.parent().unwrap_or(Path::new(""));
            let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("batter");
            let id: String = result
                .reference_bat
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' })
                .collect();
            for ext in ["toml", "csv"] {
                let file = dir.join(format!("{stem}.{id}.{ext}"));
                refuse_onto_the_bag("--batter-out", &file, bag)?;
            }
            let bat_file = super::bat_file::write_bat_files(&result.reference, dir, &format!("{stem}.{id}"))?;
            let name = bat_file.file_name().and_then(|s| s.to_str()).unwrap_or_default().to_string();
            written.push(bat_file);
            name
        }
    };
    let text = result.batter_toml(&reference, &bag.display().to_string()).map_err(flat).context("--batter-out")?;
    // Again now that the fit has read its inputs (a reference bat file among them).
    refuse_onto_the_bag("--batter-out", path, bag)?;
    std::fs::write(path, text).with_context(|| format!("cannot write '{}'", path.display()))?;
    written.push(path.to_path_buf());
    Ok(written)
}

/// The e_T fit of the bag, with the ball of the exit-speed fit (`--fit-tangential`).
fn fit_tangential_of(args: &CalibrateArgs, result: &Fit) -> Result<crate::calibrate::tangential::TangentialFit> {
    use crate::calibrate::tangential::{fit_tangential_with_progress, problem_from_bag, Progress, TangentialOptions};
    use std::io::IsTerminal as _;
    let problem =
        problem_from_bag(&args.bag, args.ball.as_deref()).map_err(flat).context("reading the launch measurements")?;
    // Start from the contact the node was given (μ and the moment of inertia stay as they were).
    let options = TangentialOptions {
        contact: problem.contact,
        max_iterations: args.max_iterations,
        ..TangentialOptions::default()
    };
    // Progress on a terminal once the fit has taken a few seconds (a large session takes minutes).
    let started = std::time::Instant::now();
    let on_terminal = std::io::stderr().is_terminal();
    let mut shown = false;
    let swings = problem.observations.len();
    let progress = |p: Progress| {
        if on_terminal && started.elapsed() > std::time::Duration::from_secs(2) {
            eprint!(
                "\re_T fit, {swings} swings: iteration {}, {} evaluations, Σr² {:.6e}, {:.0} s   ",
                p.iteration,
                p.evaluations,
                p.cost,
                started.elapsed().as_secs_f64()
            );
            shown = true;
        }
    };
    let fitted = fit_tangential_with_progress(&problem, &result.ball, &options, progress);
    if shown {
        eprintln!();
    }
    fitted.map_err(flat).context("fitting e_T")
}

/// The human-readable report of a fit: parameters with uncertainty, residual summary per bat, worst residuals.
pub fn report(problem: &Problem, result: &Fit, show: usize) -> String {
    let mut out = String::new();
    let bats: Vec<&str> = problem.bats.keys().map(String::as_str).collect();
    out.push_str(&format!(
        "Calibration: {} measured swings, ball '{}', bats {}; Levenberg–Marquardt, {} iteration(s){}\n\n",
        problem.observations.len(),
        problem.ball_id,
        bats.join(", "),
        result.iterations,
        if result.converged { ", converged" } else { ", NOT converged (raise --max-iterations)" }
    ));
    if !problem.skipped.is_empty() {
        out.push_str(&format!("left out {} input(s):\n", problem.skipped.len()));
        for reason in problem.skipped.iter().take(10) {
            out.push_str(&format!("  {reason}\n"));
        }
        if problem.skipped.len() > 10 {
            out.push_str(&format!("  … and {} more\n", problem.skipped.len() - 10));
        }
        out.push('\n');
    }
    let mut t = Table::new(["parameter", "start", "fitted", "± 1σ", "unit"]);
    for p in &result.parameters {
        t.row([p.name.clone(), num(p.initial, 5), num(p.value, 5), num(p.std_error, 2), p.unit.to_string()]);
    }
    out.push_str(&t.render());
    out.push_str(&format!(
        "\nresiduals (measured − predicted exit speed): RMS {} m/s before, {} m/s after; s = {} m/s on {} degrees of freedom\n\n",
        num(result.rms_before, 3),
        num(result.rms, 3),
        num(result.residual_sigma, 3),
        result.dof
    ));
    let mut t = Table::new(["bat", "swings", "mean before (m/s)", "mean after (m/s)", "RMS after (m/s)"]);
    for bat in &bats {
        let rs: Vec<_> = result.residuals.iter().filter(|r| r.bat_id == *bat).collect();
        if rs.is_empty() {
            continue;
        }
        let n = rs.len() as f64;
        let before = rs.iter().map(|r| r.measured - r.predicted_before).sum::<f64>() / n;
        let after = rs.iter().map(|r| r.residual).sum::<f64>() / n;
        let rms = (rs.iter().map(|r| r.residual * r.residual).sum::<f64>() / n).sqrt();
        t.row([bat.to_string(), rs.len().to_string(), num(before, 3), num(after, 3), num(rms, 3)]);
    }
    out.push_str(&t.render());
    let mut worst: Vec<_> = result.residuals.iter().collect();
    worst.sort_by(|a, b| b.residual.abs().total_cmp(&a.residual.abs()));
    let shown = if show == 0 { worst.len() } else { show.min(worst.len()) };
    out.push_str(&format!("\nlargest residuals ({shown} of {}):\n", worst.len()));
    let mut t = Table::new(["swing_id", "bat", "impact_z (m)", "measured (m/s)", "predicted (m/s)", "residual (m/s)"]);
    for r in worst.into_iter().take(shown) {
        t.row([
            r.swing_id.to_string(),
            r.bat_id.clone(),
            num(r.impact_z, 4),
            num(r.measured, 4),
            num(r.predicted, 4),
            num(r.residual, 3),
        ]);
    }
    out.push_str(&t.render());
    out
}

/// Writes the fitted ball (and bats) as JSON lines `sweetspot pub` reads; returns the files written.
/// The ball carries `contact` (its tangential contact fields).
pub fn write_params(path: &Path, problem: &Problem, result: &Fit, contact: &TangentialContact) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let ball = params_from_ball(&problem.ball_id, &result.ball, Some(contact), Header::default());
    write_lines(path, &[ball.to_json()])?;
    written.push(path.to_path_buf());
    if !result.bats.is_empty() {
        let bats_path = bats_path(path);
        let lines: Vec<_> = result
            .bats
            .iter()
            .map(|(id, bat)| {
                let modes = problem.bats.get(id).map_or(0, |b| b.modes);
                params_from_bat(id, bat, modes, Header::default()).to_json()
            })
            .collect();
        write_lines(&bats_path, &lines)?;
        written.push(bats_path);
    }
    Ok(written)
}

fn write_lines(path: &Path, values: &[serde_json::Value]) -> Result<()> {
    let mut file = std::fs::File::create(path).with_context(|| format!("cannot create '{}'", path.display()))?;
    for v in values {
        let mut v = v.clone();
        // The node stamps what it receives; an all-zero header would only be noise in the file.
        if let Some(obj) = v.as_object_mut() {
            obj.remove("header");
        }
        writeln!(file, "{v}").with_context(|| format!("cannot write '{}'", path.display()))?;
    }
    Ok(())
}
