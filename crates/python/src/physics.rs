//! Bats, balls and collisions: `Bat`, `Ball`, one collision as `sweetspot simulate --json`'s document, and
//! many collisions as columns (in parallel, the GIL released).

use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use crate::cli_shared::{
    check_options, load_bat_file, modes_document, oblique_impact, simulate, spatial_impact, BallOverrides,
    ObliqueFlags, ObliqueInputs, DEFAULT_IMPACT_FROM_TIP,
};
use crate::engine::answer::inputs::batter_side;
use crate::engine::physics::{self, collide, collide_oblique, collide_spatial, CollisionOptions, Impact, ModeSet};
use crate::engine::report::json::{BatJson, CollisionJson};
use crate::errors::{require_exists, value_error};

/// A bat: a preset or a bat file, as `sweetspot --bat` takes it.
#[pyclass(module = "sweetspot._sweetspot", name = "Bat", frozen)]
pub struct Bat {
    pub(crate) bat: physics::Bat,
}

#[pymethods]
impl Bat {
    /// The preset `name` (r161, r161-corked, aluminum, torpedo).
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Bat> {
        physics::Bat::preset(name)
            .map(|bat| Bat { bat })
            .map_err(|e| PyValueError::new_err(format!("bat preset '{name}': {e}")))
    }

    /// A bat file (TOML, docs/file-formats.md).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Bat> {
        require_exists(&path, "bat file")?;
        load_bat_file(&path).map(|bat| Bat { bat }).map_err(value_error)
    }

    /// The preset names.
    #[staticmethod]
    fn preset_names() -> Vec<&'static str> {
        physics::Bat::preset_names().to_vec()
    }

    /// The bat's name.
    #[getter]
    fn name(&self) -> String {
        self.bat.name.clone()
    }

    /// The mass properties as `sweetspot simulate --json`'s `bat` object (JSON text).
    fn properties_json(&self) -> PyResult<String> {
        let props = self.bat.mass_properties();
        to_json(&BatJson::new(&self.bat.name, &props))
    }

    /// `sweetspot modes --json --modes COUNT` (JSON text).
    fn modes_json(&self, py: Python<'_>, count: usize) -> PyResult<String> {
        let bat = &self.bat;
        let document = py.allow_threads(|| modes_document(bat, count)).map_err(value_error)?;
        to_json(&document)
    }

    fn __repr__(&self) -> String {
        format!("Bat({:?})", self.bat.name)
    }
}

/// A ball: a preset with `sweetspot`'s `--ball-*` overrides.
#[pyclass(module = "sweetspot._sweetspot", name = "Ball", frozen)]
pub struct Ball {
    pub(crate) ball: physics::Ball,
}

#[pymethods]
impl Ball {
    /// The preset `name` with the given fields replaced, checked as the command line checks them.
    #[staticmethod]
    #[pyo3(signature = (name, *, mass=None, radius=None, cor=None, stiffness=None, exponent=None,
        cor_speed_exponent=None, cor_reference_speed=None))]
    #[allow(clippy::too_many_arguments)]
    fn preset(
        name: &str,
        mass: Option<f64>,
        radius: Option<f64>,
        cor: Option<f64>,
        stiffness: Option<f64>,
        exponent: Option<f64>,
        cor_speed_exponent: Option<f64>,
        cor_reference_speed: Option<f64>,
    ) -> PyResult<Ball> {
        let args = BallOverrides {
            preset: Some(name.to_string()),
            mass,
            radius,
            cor,
            stiffness,
            exponent,
            cor_speed_exponent,
            cor_reference_speed,
        };
        args.apply(physics::Ball::game()).map(|ball| Ball { ball }).map_err(value_error)
    }

    /// The preset names.
    #[staticmethod]
    fn preset_names() -> Vec<&'static str> {
        physics::Ball::preset_names().to_vec()
    }

    /// kg.
    #[getter]
    fn mass(&self) -> f64 {
        self.ball.mass
    }
    /// m.
    #[getter]
    fn radius(&self) -> f64 {
        self.ball.radius
    }
    /// e0 (at `cor_reference_speed` when the COR falls with speed).
    #[getter]
    fn cor(&self) -> f64 {
        self.ball.cor
    }
    /// k1, N/m^α.
    #[getter]
    fn stiffness(&self) -> f64 {
        self.ball.stiffness
    }
    /// α.
    #[getter]
    fn exponent(&self) -> f64 {
        self.ball.exponent
    }
    /// p of e0 ∝ v^(−p) (0: constant COR).
    #[getter]
    fn cor_speed_exponent(&self) -> f64 {
        self.ball.cor_speed_exponent
    }
    /// m/s at which e0 = cor.
    #[getter]
    fn cor_reference_speed(&self) -> f64 {
        self.ball.cor_reference_speed
    }

    fn __repr__(&self) -> String {
        let b = &self.ball;
        format!(
            "Ball(mass={}, radius={}, cor={}, stiffness={}, exponent={}, cor_speed_exponent={}, cor_reference_speed={})",
            b.mass, b.radius, b.cor, b.stiffness, b.exponent, b.cor_speed_exponent, b.cor_reference_speed
        )
    }
}

fn to_json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| PyValueError::new_err(format!("cannot serialise the output as JSON: {e}")))
}

/// Refuses NaN and ±∞ as the command line's number parser does.
fn finite(name: &str, value: f64) -> anyhow::Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        anyhow::bail!("{name} = {value} is not allowed: expected a finite number")
    }
}

/// The head-on swing `simulate` and `sweep` start from (its impact point left to each), its speeds and the
/// oblique `flags` refused when not finite, as the command line's number parser refuses them.
fn swing_of(
    ball_speed: f64,
    bat_cm_speed: f64,
    bat_angular_speed: f64,
    flags: &ObliqueFlags,
) -> anyhow::Result<Impact> {
    let swing = Impact {
        ball_speed: finite("ball_speed", ball_speed)?,
        bat_cm_speed: finite("bat_cm_speed", bat_cm_speed)?,
        bat_angular_speed: finite("bat_angular_speed", bat_angular_speed)?,
        impact_z: f64::NAN,
    };
    for (name, v) in [
        ("undercut", flags.undercut),
        ("attack_angle", flags.attack_angle),
        ("pitch_angle", flags.pitch_angle),
        ("pitch_spin", flags.pitch_spin),
        ("tangential_cor", flags.tangential_cor),
        ("friction", flags.friction),
        ("tangential_stiffness_ratio", flags.tangential_stiffness_ratio),
        ("bat_tilt", flags.bat_tilt),
        ("swing_direction", flags.swing_direction),
    ] {
        if let Some(v) = v {
            finite(name, v)?;
        }
    }
    Ok(swing)
}

/// The oblique keyword arguments `simulate` and `sweep` share (`sweep` has no `undercut`), as the command
/// line's flags (undercut m, angles degrees, spin rpm; None = not given). An unknown keyword is a `TypeError`,
/// as for any Python function.
fn oblique_flags(oblique: Option<&Bound<'_, PyDict>>, takes_undercut: bool) -> PyResult<ObliqueFlags> {
    let mut flags = ObliqueFlags::default();
    for (key, value) in oblique.into_iter().flat_map(|kwargs| kwargs.iter()) {
        let key: String = key.extract()?;
        if key == "batter_side" {
            flags.batter_side = side_of(value.extract::<Option<String>>()?.as_deref())?;
            continue;
        }
        let slot = match key.as_str() {
            "undercut" if takes_undercut => &mut flags.undercut,
            "attack_angle" => &mut flags.attack_angle,
            "pitch_angle" => &mut flags.pitch_angle,
            "pitch_spin" => &mut flags.pitch_spin,
            "tangential_cor" => &mut flags.tangential_cor,
            "friction" => &mut flags.friction,
            "tangential_stiffness_ratio" => &mut flags.tangential_stiffness_ratio,
            "bat_tilt" => &mut flags.bat_tilt,
            "swing_direction" => &mut flags.swing_direction,
            _ => return Err(PyTypeError::new_err(format!("got an unexpected keyword argument '{key}'"))),
        };
        *slot = value.extract()?;
    }
    Ok(flags)
}

fn side_of(text: Option<&str>) -> PyResult<Option<physics::BatterSide>> {
    text.map(batter_side).transpose().map_err(PyValueError::new_err)
}

/// `sweetspot simulate --json` with these inputs: the document as JSON text (the command line's own
/// function, so every number is the command line's).
#[pyfunction]
#[pyo3(signature = (bat, ball, ball_speed, bat_cm_speed, bat_angular_speed, impact_z, *, modes=18, dt=5e-6,
    **oblique))]
#[allow(clippy::too_many_arguments)]
pub fn simulate_document(
    py: Python<'_>,
    bat: &Bat,
    ball: &Ball,
    ball_speed: f64,
    bat_cm_speed: f64,
    bat_angular_speed: f64,
    impact_z: Vec<f64>,
    modes: usize,
    dt: f64,
    oblique: Option<&Bound<'_, PyDict>>,
) -> PyResult<String> {
    let flags = oblique_flags(oblique, true)?;
    let (bat, ball) = (&bat.bat, &ball.ball);
    let document = py.allow_threads(|| -> anyhow::Result<_> {
        let swing = swing_of(ball_speed, bat_cm_speed, bat_angular_speed, &flags)?;
        for (i, z) in impact_z.iter().enumerate() {
            finite(&format!("impact_z[{i}]"), *z)?;
        }
        let options = check_options(CollisionOptions { modes, time_step: dt })?;
        simulate(bat, ball, &swing, &flags.inputs()?, &impact_z, &options)
    });
    to_json(&document.map_err(value_error)?)
}

/// The swing columns `simulate_columns` reads (all of one length): the first four are required; the others,
/// when present, are given for every row (NaN in `impact_z` = the default point, in
/// `tangential_stiffness_ratio` = a constant e_T; `batter_side` 0 right, 1 left).
const REQUIRED: [&str; 4] = ["ball_speed", "bat_cm_speed", "bat_angular_speed", "impact_z"];
const OPTIONAL: [&str; 10] = [
    "undercut",
    "attack_angle",
    "pitch_angle",
    "pitch_spin",
    "tangential_cor",
    "friction",
    "tangential_stiffness_ratio",
    "bat_tilt",
    "swing_direction",
    "batter_side",
];

/// The result columns: `sweetspot simulate --json`'s `results[]` fields, nested names joined by `_`
/// (`energy.ball` → `energy_ball`, `oblique.exit_speed` → `oblique_exit_speed`); NaN where a document leaves
/// the field out (no hoop mode, a head-on row); `oblique_sliding` is 1/0. The per-mode energies come apart.
pub const COLUMNS: [&str; 45] = [
    "impact_z",
    "exit_speed",
    "rigid_exit_speed",
    "effective_cor",
    "collision_efficiency",
    "contact_time",
    "peak_force",
    "impulse",
    "max_compression",
    "energy_initial",
    "energy_ball",
    "energy_bat_rigid",
    "energy_vibration",
    "energy_hysteresis_loss",
    "energy_hoop",
    "energy_hoop_stored",
    "energy_hoop_returned",
    "energy_residual",
    "hoop_frequency_hz",
    "hoop_stiffness",
    "hoop_effective_mass",
    "hoop_decay_length",
    "hoop_radius",
    "hoop_wall_thickness",
    "hoop_coupling",
    "oblique_barrel_radius",
    "oblique_exit_speed",
    "oblique_launch_angle_deg",
    "oblique_spin_rpm",
    "oblique_spray_angle_deg",
    "oblique_backspin_rpm",
    "oblique_sidespin_rpm",
    "oblique_gyro_spin_rpm",
    "oblique_total_spin_rpm",
    "oblique_spin_axis_deg",
    "oblique_normal_exit_speed",
    "oblique_tangential_exit_speed",
    "oblique_sliding",
    "oblique_line_of_centres_angle_deg",
    "oblique_tangential_impulse",
    "oblique_slip_before",
    "oblique_slip_after",
    "oblique_bat_cm_tangential_speed_after",
    "oblique_bat_tangential_angular_speed_after",
    "oblique_bat_roll_rate_after",
];

/// One result as a row of [`COLUMNS`].
fn flatten(c: &CollisionJson) -> [f64; COLUMNS.len()] {
    let nan = f64::NAN;
    let opt = |v: Option<f64>| v.unwrap_or(nan);
    let e = &c.energy;
    let h = c.hoop.as_ref();
    let o = c.oblique.as_ref();
    let of = |f: fn(&crate::engine::report::json::ObliqueJson) -> f64| o.map_or(nan, f);
    let ofo = |f: fn(&crate::engine::report::json::ObliqueJson) -> Option<f64>| o.and_then(f).unwrap_or(nan);
    [
        c.impact_z,
        c.exit_speed,
        c.rigid_exit_speed,
        c.effective_cor,
        c.collision_efficiency,
        c.contact_time,
        c.peak_force,
        c.impulse,
        c.max_compression,
        e.initial,
        e.ball,
        e.bat_rigid,
        e.vibration,
        e.hysteresis_loss,
        opt(e.hoop),
        opt(e.hoop_stored),
        opt(e.hoop_returned),
        e.residual,
        h.map_or(nan, |h| h.frequency_hz),
        h.map_or(nan, |h| h.stiffness),
        h.map_or(nan, |h| h.effective_mass),
        h.map_or(nan, |h| h.decay_length),
        h.map_or(nan, |h| h.radius),
        h.map_or(nan, |h| h.wall_thickness),
        h.map_or(nan, |h| h.coupling),
        of(|o| o.barrel_radius),
        of(|o| o.exit_speed),
        of(|o| o.launch_angle_deg),
        of(|o| o.spin_rpm),
        of(|o| o.flight.spray_angle_deg),
        of(|o| o.flight.backspin_rpm),
        of(|o| o.flight.sidespin_rpm),
        of(|o| o.flight.gyro_spin_rpm),
        of(|o| o.flight.total_spin_rpm),
        of(|o| o.flight.spin_axis_deg),
        of(|o| o.normal_exit_speed),
        ofo(|o| o.tangential_exit_speed),
        of(|o| f64::from(u8::from(o.sliding))),
        ofo(|o| o.line_of_centres_angle_deg),
        ofo(|o| o.tangential_impulse),
        ofo(|o| o.slip_before),
        ofo(|o| o.slip_after),
        ofo(|o| o.bat_cm_tangential_speed_after),
        ofo(|o| o.bat_tangential_angular_speed_after),
        ofo(|o| o.bat_roll_rate_after),
    ]
}

/// The swing columns, borrowed from numpy.
struct Swings<'a> {
    required: [&'a [f64]; 4],
    optional: [Option<&'a [f64]>; 10],
    len: usize,
}

impl Swings<'_> {
    fn oblique(&self, i: usize) -> anyhow::Result<ObliqueInputs> {
        let at = |k: usize| self.optional[k].map(|c| c[i]);
        let side = match at(9) {
            None => None,
            Some(0.0) => Some(physics::BatterSide::Right),
            Some(1.0) => Some(physics::BatterSide::Left),
            Some(v) => anyhow::bail!("batter_side = {v}: expected right (0) or left (1)"),
        };
        let flags = ObliqueFlags {
            undercut: at(0),
            attack_angle: at(1),
            pitch_angle: at(2),
            pitch_spin: at(3),
            tangential_cor: at(4),
            friction: at(5),
            tangential_stiffness_ratio: at(6).filter(|v| !v.is_nan()),
            bat_tilt: at(7),
            swing_direction: at(8),
            batter_side: side,
        };
        for (k, name) in OPTIONAL.iter().enumerate().take(9) {
            if let Some(v) = at(k) {
                if !(k == 6 && v.is_nan()) {
                    finite(name, v)?;
                }
            }
        }
        flags.inputs()
    }

    /// Row `i` as `sweetspot simulate` computes it (the same functions, in the same order).
    fn collide(&self, i: usize, model: &Model<'_>) -> anyhow::Result<CollisionJson> {
        use anyhow::Context as _;
        let [v, cm, w, z] = self.required.map(|c| c[i]);
        let impact_z = if z.is_nan() { model.default_z } else { finite("impact_z", z)? };
        let impact = Impact {
            ball_speed: finite("ball_speed", v)?,
            bat_cm_speed: finite("bat_cm_speed", cm)?,
            bat_angular_speed: finite("bat_angular_speed", w)?,
            impact_z,
        };
        let oblique = self.oblique(i)?;
        let (modes, ball, options) = (model.modes, model.ball, model.options);
        let context = || format!("collision at impact_z = {impact_z} m");
        if oblique.active {
            let barrel_radius = model.bat.radii_at(impact_z).0;
            let planar = oblique_impact(impact, barrel_radius, &oblique);
            if oblique.is_planar() {
                let result = collide_oblique(modes, ball, &planar, &oblique.contact, options).with_context(context)?;
                Ok(CollisionJson::oblique(impact_z, &result, barrel_radius))
            } else {
                let swing = spatial_impact(planar, &oblique);
                let result = collide_spatial(modes, ball, &swing, &oblique.contact, options).with_context(context)?;
                Ok(CollisionJson::spatial(impact_z, &result, barrel_radius))
            }
        } else {
            let result = collide(modes, ball, &impact, options).with_context(context)?;
            Ok(CollisionJson::new(impact_z, &result))
        }
    }
}

/// What every row shares: the bat and its modes, the ball, the options, the default impact point.
struct Model<'a> {
    bat: &'a physics::Bat,
    modes: &'a ModeSet,
    ball: &'a physics::Ball,
    options: &'a CollisionOptions,
    default_z: f64,
}

/// What `simulate_columns` computed: the rows' values in [`COLUMNS`] order, their mode energies, and the
/// rows that failed with why.
struct Computed {
    values: Vec<f64>,
    mode_energies: Vec<f64>,
    frequencies_hz: Vec<f64>,
    errors: Vec<(usize, String)>,
}

fn compute(
    swings: &Swings<'_>,
    bat: &physics::Bat,
    ball: &physics::Ball,
    options: CollisionOptions,
) -> anyhow::Result<Computed> {
    use anyhow::Context as _;
    let options = check_options(options)?;
    let modes = ModeSet::compute(bat, options.modes).with_context(|| format!("normal modes of bat '{}'", bat.name))?;
    let default_z = modes.mass_properties().length - DEFAULT_IMPACT_FROM_TIP;
    let model = Model { bat, modes: &modes, ball, options: &options, default_z };
    let count = modes.vibrational_count();
    let rows: Vec<anyhow::Result<CollisionJson>> =
        (0..swings.len).into_par_iter().map(|i| swings.collide(i, &model)).collect();
    let mut computed = Computed {
        values: Vec::with_capacity(swings.len * COLUMNS.len()),
        mode_energies: Vec::with_capacity(swings.len * count),
        frequencies_hz: modes.frequencies_hz().into_iter().take(count).collect(),
        errors: Vec::new(),
    };
    for (i, row) in rows.into_iter().enumerate() {
        match row {
            Ok(c) => {
                computed.values.extend_from_slice(&flatten(&c));
                computed
                    .mode_energies
                    .extend((0..count).map(|k| c.mode_energies.get(k).map_or(f64::NAN, |m| m.energy)));
            }
            Err(e) => {
                computed.values.extend(std::iter::repeat_n(f64::NAN, COLUMNS.len()));
                computed.mode_energies.extend(std::iter::repeat_n(f64::NAN, count));
                computed.errors.push((i, format!("{e:#}")));
            }
        }
    }
    Ok(computed)
}

/// A float64 column's values in place (no copy), checked to be `len` long.
fn column_slice<'a>(array: &'a PyReadonlyArray1<'_, f64>, len: usize) -> PyResult<&'a [f64]> {
    let s = array.as_slice().map_err(|e| PyValueError::new_err(format!("a column is not contiguous: {e}")))?;
    if s.len() == len {
        Ok(s)
    } else {
        Err(PyValueError::new_err(format!("columns of different lengths: {} and {len}", s.len())))
    }
}

/// Many collisions: `columns` maps the swing's fields (REQUIRED and any of OPTIONAL, the command line's
/// units) to float64 arrays of one length. Returns a dict: every name of [`COLUMNS`] → array,
/// `mode_energies` → (rows × modes) array, `mode_frequencies_hz`, and `errors` → [(row, message)] for rows
/// that could not be computed (their values NaN). Rows run on every core, the GIL released.
#[pyfunction]
#[pyo3(signature = (bat, ball, columns, *, modes=18, dt=5e-6))]
pub fn simulate_columns<'py>(
    py: Python<'py>,
    bat: &Bat,
    ball: &Ball,
    columns: &Bound<'py, PyDict>,
    modes: usize,
    dt: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let array = |name: &str| -> PyResult<Option<PyReadonlyArray1<'py, f64>>> {
        columns.get_item(name)?.map(|v| v.extract::<PyReadonlyArray1<'py, f64>>()).transpose()
    };
    let mut required = Vec::new();
    for name in REQUIRED {
        required.push(array(name)?.ok_or_else(|| PyValueError::new_err(format!("missing column {name}")))?);
    }
    let optional: Vec<Option<PyReadonlyArray1<'py, f64>>> =
        OPTIONAL.iter().map(|n| array(n)).collect::<PyResult<_>>()?;
    let len = required[0].len()?;
    let slice = |a| column_slice(a, len);
    let swings = Swings {
        required: [slice(&required[0])?, slice(&required[1])?, slice(&required[2])?, slice(&required[3])?],
        optional: {
            let mut out = [None; 10];
            for (k, a) in optional.iter().enumerate() {
                out[k] = a.as_ref().map(slice).transpose()?;
            }
            out
        },
        len,
    };
    let options = CollisionOptions { modes, time_step: dt };
    let (bat, ball) = (&bat.bat, &ball.ball);
    let computed = py.allow_threads(|| compute(&swings, bat, ball, options)).map_err(value_error)?;
    let out = PyDict::new(py);
    let width = COLUMNS.len();
    for (k, name) in COLUMNS.iter().enumerate() {
        let column: Vec<f64> = computed.values.iter().skip(k).step_by(width).copied().collect();
        out.set_item(*name, column.into_pyarray(py))?;
    }
    let count = computed.frequencies_hz.len();
    let energies = Array2::from_shape_vec((len, count), computed.mode_energies)
        .map_err(|e| PyValueError::new_err(format!("mode energies: {e}")))?;
    out.set_item("mode_energies", energies.into_pyarray(py))?;
    out.set_item("mode_frequencies_hz", PyArray1::from_vec(py, computed.frequencies_hz))?;
    out.set_item("errors", computed.errors)?;
    Ok(out)
}

/// `sweetspot bbcor --json` (the protocol ball `bbcor` unless `ball` is given): the document as JSON text.
#[pyfunction]
#[pyo3(signature = (bat, ball=None, *, modes=18, dt=5e-6))]
pub fn bbcor_document(py: Python<'_>, bat: &Bat, ball: Option<&Ball>, modes: usize, dt: f64) -> PyResult<String> {
    let ball = ball.map_or_else(physics::Ball::bbcor_protocol, |b| b.ball);
    let bat = &bat.bat;
    let document = py.allow_threads(|| -> anyhow::Result<_> {
        let options = check_options(CollisionOptions { modes, time_step: dt })?;
        crate::cli_shared::bbcor(bat, &ball, &options)
    });
    to_json(&document.map_err(value_error)?)
}

/// `sweetspot compare --bats … [--batter FILE] --pitch-speed V --json`: the document as JSON text.
#[pyfunction]
#[pyo3(signature = (bats, ball, *, batter=None, pitch_speed=40.0, modes=18, dt=5e-6))]
pub fn compare_document(
    py: Python<'_>,
    bats: Vec<PyRef<'_, Bat>>,
    ball: &Ball,
    batter: Option<PathBuf>,
    pitch_speed: f64,
    modes: usize,
    dt: f64,
) -> PyResult<String> {
    use crate::cli_shared::{batter_from_spec, compare, load_batter_file, BatterSpec};
    let bats: Vec<physics::Bat> = bats.iter().map(|b| b.bat.clone()).collect();
    if let Some(path) = &batter {
        require_exists(path, "batter file")?;
    }
    let ball = &ball.ball;
    let document = py.allow_threads(|| -> anyhow::Result<_> {
        let (batter, reference) = match &batter {
            Some(path) => load_batter_file(path)?,
            None => batter_from_spec(&BatterSpec::default(), None)?,
        };
        let options = check_options(CollisionOptions { modes, time_step: dt })?;
        // NaN is refused too, as the command line refuses it.
        if pitch_speed.is_nan() || pitch_speed <= 0.0 {
            anyhow::bail!("--pitch-speed = {pitch_speed} m/s is out of range: expected > 0");
        }
        compare(&batter, &reference, &bats, ball, pitch_speed, &options)
    });
    to_json(&document.map_err(value_error)?)
}

/// `sweetspot sweep [--over undercut] --json` with these inputs: the document as JSON text. `over` is `"z"`
/// (impact points `from_` … `to` m from the knob, head-on) or `"undercut"` (undercuts `from_` … `to` m at
/// `impact_z`, the other oblique inputs held, in the command line's units).
#[pyfunction]
#[pyo3(signature = (bat, ball, ball_speed, bat_cm_speed, bat_angular_speed, *, over="z", impact_z=None,
    from_=None, to=None, step=None, points=None, modes=18, dt=5e-6, **oblique))]
#[allow(clippy::too_many_arguments)]
pub fn sweep_document(
    py: Python<'_>,
    bat: &Bat,
    ball: &Ball,
    ball_speed: f64,
    bat_cm_speed: f64,
    bat_angular_speed: f64,
    over: &str,
    impact_z: Option<f64>,
    from_: Option<f64>,
    to: Option<f64>,
    step: Option<f64>,
    points: Option<usize>,
    modes: usize,
    dt: f64,
    oblique: Option<&Bound<'_, PyDict>>,
) -> PyResult<String> {
    use crate::engine::answer::sweep::{sweep, SweepOver};
    use crate::engine::report::sweep::SweepRange;
    let over = match over {
        "z" => SweepOver::ImpactPoint,
        "undercut" => SweepOver::Undercut,
        other => return Err(PyValueError::new_err(format!("over = {other:?}: expected \"z\" or \"undercut\""))),
    };
    let flags = oblique_flags(oblique, false)?;
    let (bat, ball) = (&bat.bat, &ball.ball);
    let document = py.allow_threads(|| -> anyhow::Result<_> {
        let swing = swing_of(ball_speed, bat_cm_speed, bat_angular_speed, &flags)?;
        for (name, v) in [("impact_z", impact_z), ("from_", from_), ("to", to), ("step", step)] {
            if let Some(v) = v {
                finite(name, v)?;
            }
        }
        let options = check_options(CollisionOptions { modes, time_step: dt })?;
        let range = SweepRange { from: from_, to, step, points };
        sweep(bat, ball, &swing, over, &flags, impact_z, range, &options)
    });
    to_json(&document.map_err(value_error)?)
}
