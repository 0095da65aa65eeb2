//! The fuzz harness: one function per fuzz target, taking the raw input bytes exactly as libFuzzer hands them
//! over. The cargo-fuzz targets in `fuzz_targets/` are one-line wrappers around these functions, and
//! `tests/fuzz_regressions.rs` includes this very file (`#[path]`) to replay every committed input through the
//! same code in the normal `cargo test`. A panic here is a finding: either sweetspot panicked on bad input, or
//! an invariant asserted below (no NaN or infinity in an accepted result, lossless CDR round trip, …) broke.
//!
//! Throughput caps (documented in docs/fuzzing.md): bats cut into more than [`MAX_FUZZ_SLICES`] slices and
//! collisions with a time step below [`MIN_FUZZ_TIME_STEP`] are validated but not solved, so that each
//! iteration stays in the millisecond range on a loaded 2-core machine. Everything else runs the real code.

// `!(x >= lo)` also catches NaN, deliberately.
#![allow(dead_code, clippy::neg_cmp_op_on_partial_ord)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use arbitrary::{Arbitrary, Unstructured};

use sweetspot::model::convert;
use sweetspot::model::engine::{self, BatEntry, ModeCacheCount, Registry};
use sweetspot::model::settings::ModelSettings;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};
use sweetspot::msgs::{decode_cdr, encode_cdr};
use sweetspot::physics::{
    collide, Ball, Bat, CollisionOptions, CollisionResult, CoreFill, Impact, Material, ModeSet, Station,
};

/// Bats with more slices than this are built and validated but their modes are not computed.
pub const MAX_FUZZ_SLICES: f64 = 300.0;
/// Collisions with a smaller RK4 step (s) are validated but not integrated.
pub const MIN_FUZZ_TIME_STEP: f64 = 5e-7;
/// Most vibrational modes a fuzzed bat keeps.
pub const MAX_FUZZ_MODES: usize = 30;

/// A fuzz target: runs one input, panics on a finding.
pub type Target = fn(&[u8]);

/// Every fuzz target by name, for the regression replay.
pub const TARGETS: &[(&str, Target)] = &[
    ("cdr_bat_params", cdr_bat_params),
    ("cdr_ball_params", cdr_ball_params),
    ("cdr_swing", cdr_swing),
    ("cdr_outputs", cdr_outputs),
    ("node_messages", node_messages),
    ("physics", physics),
    ("case_file", case_file),
    ("bat_toml", bat_toml),
    ("bag_reader", bag_reader),
    ("bag_hostile", bag_hostile),
];

// ------------------------------------------------------------------------------------------------------------
// Shared checks

/// Panics unless every value is finite, naming the first that is not.
fn assert_finite(what: &str, values: &[(&str, f64)]) {
    for (name, v) in values {
        assert!(v.is_finite(), "{what}: {name} = {v} is not finite");
    }
}

/// Every number of an accepted collision must be finite, and the energies that are sums of squares ≥ 0.
pub fn check_collision(result: &CollisionResult) {
    let r = result;
    assert_finite(
        "collision",
        &[
            ("exit_speed", r.exit_speed),
            ("rigid_exit_speed", r.rigid_exit_speed),
            ("effective_cor", r.effective_cor),
            ("collision_efficiency", r.collision_efficiency),
            ("contact_time", r.contact_time),
            ("peak_force", r.peak_force),
            ("impulse", r.impulse),
            ("max_compression", r.max_compression),
            ("bat_cm_speed_after", r.bat_cm_speed_after),
            ("bat_angular_speed_after", r.bat_angular_speed_after),
            ("energy.initial", r.energy.initial),
            ("energy.ball", r.energy.ball),
            ("energy.bat_rigid", r.energy.bat_rigid),
            ("energy.vibration", r.energy.vibration),
            ("energy.hysteresis_loss", r.energy.hysteresis_loss),
            ("energy.residual", r.energy.residual),
        ],
    );
    for (k, m) in r.mode_energies.iter().enumerate() {
        assert!(m.frequency.is_finite() && m.frequency > 0.0, "collision: mode {k} frequency = {}", m.frequency);
        assert!(m.energy.is_finite() && m.energy >= 0.0, "collision: mode {k} energy = {}", m.energy);
    }
    assert!(r.contact_time > 0.0, "collision: contact_time = {}", r.contact_time);
    // The energy budget closes to the integration error; a result that loses or creates more than 2 % of the
    // initial energy is numerical garbage (e.g. an RK4 step too large for the contact stiffness).
    assert!(
        r.energy.residual.abs() <= 0.02 * r.energy.initial,
        "collision: energy residual {} J of {} J initial (exit speed {} m/s)",
        r.energy.residual,
        r.energy.initial,
        r.exit_speed
    );
    assert!(r.max_compression >= 0.0 && r.peak_force >= 0.0, "collision: negative compression or force");
}

/// An accepted mode set has finite, positive mass properties and finite, ascending, positive frequencies.
pub fn check_modes(modes: &ModeSet) {
    let mp = modes.mass_properties();
    assert_finite(
        "modes",
        &[
            ("mass", mp.mass),
            ("center_of_mass", mp.center_of_mass),
            ("moment_of_inertia", mp.moment_of_inertia),
            ("radius_of_gyration", mp.radius_of_gyration),
        ],
    );
    assert!(mp.mass > 0.0 && mp.moment_of_inertia > 0.0, "modes: non-positive mass or inertia {mp:?}");
    let f = modes.frequencies_hz();
    for (k, w) in f.windows(2).enumerate() {
        assert!(w[1] >= w[0], "modes: frequencies not ascending at {k}: {f:?}");
    }
    for (k, v) in f.iter().enumerate() {
        assert!(v.is_finite() && *v > 0.0, "modes: frequency {k} = {v}");
    }
    for (k, mode) in modes.all_modes().iter().enumerate() {
        assert!(
            mode.displacement.iter().chain(&mode.rotation).all(|x| x.is_finite()),
            "modes: mode {k} has a non-finite shape value"
        );
    }
}

/// The bit pattern of a value's CDR encoding must survive decode → encode unchanged (NaN payloads included).
fn cdr_round_trip<T>(bytes: &[u8])
where
    T: serde::Serialize + serde::de::DeserializeOwned + std::fmt::Debug,
{
    let Ok(value) = decode_cdr::<T>(bytes) else { return };
    let encoded = encode_cdr(&value).unwrap_or_else(|e| panic!("decoded {value:?} but cannot re-encode it: {e}"));
    let again: T = decode_cdr(&encoded).unwrap_or_else(|e| panic!("cannot decode our own encoding of {value:?}: {e}"));
    let encoded_again = encode_cdr(&again).unwrap_or_else(|e| panic!("cannot re-encode {again:?}: {e}"));
    assert_eq!(encoded, encoded_again, "CDR round trip is not lossless for {value:?}");
}

/// Bats small enough to solve while fuzzing.
fn solvable(bat: &Bat) -> bool {
    bat.length() / bat.slice_length <= MAX_FUZZ_SLICES
}

// ------------------------------------------------------------------------------------------------------------
// CDR decoding of every message (the bytes a DDS writer or a bag hands us)

/// `decode_cdr::<BatParams>` on arbitrary bytes, then the lossless round trip.
pub fn cdr_bat_params(data: &[u8]) {
    cdr_round_trip::<BatParams>(data);
}

/// `decode_cdr::<BallParams>` on arbitrary bytes, then the lossless round trip.
pub fn cdr_ball_params(data: &[u8]) {
    cdr_round_trip::<BallParams>(data);
}

/// `decode_cdr::<Swing>` on arbitrary bytes, then the lossless round trip.
pub fn cdr_swing(data: &[u8]) {
    cdr_round_trip::<Swing>(data);
}

/// The output messages (what `bag export` / `echo` decode): the first byte picks the type.
pub fn cdr_outputs(data: &[u8]) {
    let Some((&kind, rest)) = data.split_first() else { return };
    match kind % 3 {
        0 => cdr_round_trip::<ExitVelocity>(rest),
        1 => cdr_round_trip::<ModalEnergies>(rest),
        _ => cdr_round_trip::<SweetSpot>(rest),
    }
}

// ------------------------------------------------------------------------------------------------------------
// The node's pure path: CDR → params/swing → Bat/Ball/Impact → modes → collision → answer messages

/// A sequence of records `[kind u8][len u16 LE][CDR bytes]`; kind % 3 = 0 BatParams, 1 BallParams, 2 Swing.
/// Each is decoded and handled exactly as the node's event loop does (without DDS), with the node's default
/// settings: params are converted (`max_bat_slices` enforced) and stored, swings planned, computed and
/// answered. Every answer must encode; an OK answer has no NaN.
pub fn node_messages(data: &[u8]) {
    let settings = ModelSettings::default();
    let stats = ModeCacheCount::default();
    let mut registry = Registry::with_limits(settings.max_bats, settings.max_balls);
    let mut rest = data;
    let mut handled = 0;
    while rest.len() >= 3 && handled < 8 {
        let kind = rest[0];
        let len = (u16::from_le_bytes([rest[1], rest[2]]) as usize).min(rest.len() - 3);
        let bytes = &rest[3..3 + len];
        rest = &rest[3 + len..];
        handled += 1;
        match kind % 3 {
            0 => {
                let Ok(params) = decode_cdr::<BatParams>(bytes) else { continue };
                // The node's own rule, slice cap included.
                match convert::bat_from_params_capped(&params, settings.max_bat_slices) {
                    Ok(built) => {
                        built.bat.validate().unwrap_or_else(|e| panic!("bat_from_params accepted an invalid bat: {e}"));
                        if let Some(m) = built.max_modes {
                            assert!(m <= 200, "bat_from_params accepted max_modes = {m}");
                        }
                        let slices = built.bat.slice_count();
                        assert!(slices <= settings.max_bat_slices, "accepted a bat of {slices} slices");
                        let max_modes = built.max_modes.map(|m| m.min(MAX_FUZZ_MODES));
                        if solvable(&built.bat) {
                            registry.set_bat(BatEntry::new(&params.bat_id, built.bat, max_modes, &settings));
                        }
                    }
                    Err(reason) => {
                        assert!(reason.starts_with("BatParams"), "rejection does not name the message: {reason}");
                        let probe =
                            Swing { header: params.header.clone(), measured_exit_speed: f64::NAN, ..Swing::default() };
                        let ev = convert::exit_velocity(&probe, &params.bat_id, "", &Err(reason));
                        encode_cdr(&ev).unwrap_or_else(|e| panic!("cannot encode a rejection: {e}"));
                    }
                }
            }
            1 => {
                let Ok(params) = decode_cdr::<BallParams>(bytes) else { continue };
                match convert::ball_from_params(&params) {
                    Ok(model) => {
                        let ball = model.ball;
                        ball.validate().unwrap_or_else(|e| panic!("ball_from_params accepted an invalid ball: {e}"));
                        model
                            .contact
                            .validate()
                            .unwrap_or_else(|e| panic!("ball_from_params accepted a bad contact: {e}"));
                        assert!(ball.unloading_exponent().is_finite(), "accepted ball has a non-finite β: {ball:?}");
                        registry.set_ball(&params.ball_id, model);
                    }
                    Err(reason) => {
                        assert!(reason.starts_with("BallParams"), "rejection does not name the message: {reason}")
                    }
                }
            }
            _ => {
                let Ok(swing) = decode_cdr::<Swing>(bytes) else { continue };
                let input = convert::swing_input(&swing);
                let (plan, _new_bat) =
                    engine::plan_swing(&mut registry, &settings, &swing.bat_id, &swing.ball_id, input);
                let result = engine::compute(&plan, &stats);
                let ev = convert::exit_velocity(&swing, plan.bat_id(), plan.ball_id(), &result);
                encode_cdr(&ev).unwrap_or_else(|e| panic!("cannot encode ExitVelocity: {e}"));
                match &result {
                    Ok(computed) => {
                        check_collision(&computed.collision);
                        assert_eq!(ev.status, ExitVelocity::STATUS_OK);
                        assert_finite(
                            "ExitVelocity",
                            &[
                                ("exit_speed", ev.exit_speed),
                                ("rigid_exit_speed", ev.rigid_exit_speed),
                                ("effective_cor", ev.effective_cor),
                                ("collision_efficiency", ev.collision_efficiency),
                                ("contact_time", ev.contact_time),
                                ("peak_force", ev.peak_force),
                                ("impulse", ev.impulse),
                                ("max_compression", ev.max_compression),
                                ("launch_angle", ev.launch_angle),
                                ("spin", ev.spin),
                            ],
                        );
                        let me = convert::modal_energies(&swing, plan.bat_id(), computed);
                        assert!(
                            computed.collision_energy.is_finite(),
                            "collision_energy = {}",
                            computed.collision_energy
                        );
                        for (k, f) in me.fraction.iter().enumerate() {
                            assert!(
                                f.is_finite(),
                                "ModalEnergies.fraction[{k}] = {f} (collision_energy {})",
                                computed.collision_energy
                            );
                        }
                        encode_cdr(&me).unwrap_or_else(|e| panic!("cannot encode ModalEnergies: {e}"));
                    }
                    Err(reason) => {
                        assert!(!reason.is_empty(), "empty rejection reason");
                        assert_eq!(ev.status, ExitVelocity::STATUS_REJECTED);
                    }
                }
            }
        }
    }
}

// ------------------------------------------------------------------------------------------------------------
// Physics entry points with arbitrary numbers

/// A fuzzed f64: raw bits (NaN payloads, subnormals, infinities), a special value, or a value spread over (a
/// little beyond) the field's allowed range, so that inputs also get past validation.
#[derive(Debug, Clone, Copy, Arbitrary)]
pub enum Num {
    /// Any bit pattern.
    Bits(u64),
    /// One of [`SPECIALS`] or the range's ends.
    Special(u8),
    /// `lo + (hi − lo)·(1.2·u − 0.1)`, u = x/65535.
    InRange(u16),
}

/// Values that break naive range checks.
pub const SPECIALS: [f64; 12] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -0.0,
    f64::MIN_POSITIVE,
    5e-324,
    f64::MAX,
    -1.0,
    1e300,
    -1e-300,
    1.0,
];

impl Num {
    /// The value for a field whose allowed range is [lo, hi].
    pub fn get(self, lo: f64, hi: f64) -> f64 {
        match self {
            Num::Bits(b) => f64::from_bits(b),
            Num::Special(k) => match k as usize % (SPECIALS.len() + 4) {
                i if i < SPECIALS.len() => SPECIALS[i],
                i if i == SPECIALS.len() => lo,
                i if i == SPECIALS.len() + 1 => hi,
                i if i == SPECIALS.len() + 2 => lo - (hi - lo) * 1e-12,
                _ => hi + (hi - lo) * 1e-12,
            },
            Num::InRange(x) => lo + (hi - lo) * (1.2 * (x as f64 / 65535.0) - 0.1),
        }
    }
}

/// A structured physics input: a bat (≤ 6 stations), a ball, a swing and collision options.
#[derive(Debug, Clone, Arbitrary)]
pub struct PhysicsInput {
    /// Station z values are cumulative sums of these when `cumulative_z`, raw otherwise.
    pub cumulative_z: bool,
    /// (z or Δz, outer radius, inner radius as a fraction of the outer radius).
    pub stations: Vec<(Num, Num, Num)>,
    /// Shell density, Y, S.
    pub shell: [Num; 3],
    /// Core density, Y, S, z_start, z_end (fractions of the length).
    pub core: Option<[Num; 5]>,
    /// Slice length as a fraction of the length / 100.
    pub slice_length: Num,
    /// Vibrational modes to compute.
    pub max_modes: u8,
    /// Vibrational modes to integrate.
    pub modes: u8,
    /// Ball mass, radius, k1, α, e0.
    pub ball: [Num; 5],
    /// Ball speed, bat CM speed, angular speed, impact_z (fraction of the length).
    pub impact: [Num; 4],
    /// RK4 step.
    pub time_step: Num,
}

/// The physics inputs a [`PhysicsInput`] stands for: bat (unvalidated), ball, max_modes, impact as fractions
/// resolved later, options. `None` when the bytes do not make a `PhysicsInput`.
pub struct PhysicsCase {
    /// The bat as given to `Bat::new`.
    pub stations: Vec<Station>,
    /// Shell material.
    pub shell: Material,
    /// Core fill.
    pub core: Option<CoreFill>,
    /// Slice length, m.
    pub slice_length: f64,
    /// The ball.
    pub ball: Ball,
    /// Vibrational modes computed.
    pub max_modes: usize,
    /// The swing; `impact_z` is a fraction of the bat length.
    pub impact: Impact,
    /// Integrated modes (reduced modulo `max_modes + 2`) and RK4 step.
    pub options: CollisionOptions,
}

impl std::fmt::Debug for PhysicsCase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "stations {:?}\nshell {:?}\ncore {:?}\nslice_length {:e}\nball {:?}\nmax_modes {}\nimpact {:?} (impact_z × length)\noptions {:?}",
            self.stations, self.shell, self.core, self.slice_length, self.ball, self.max_modes, self.impact, self.options
        )
    }
}

/// Decodes the bytes of the `physics` target.
pub fn physics_case(data: &[u8]) -> Option<PhysicsCase> {
    let input = PhysicsInput::arbitrary_take_rest(Unstructured::new(data)).ok()?;
    let mut z = 0.0;
    let stations: Vec<Station> = input
        .stations
        .iter()
        .take(6)
        .enumerate()
        .map(|(i, (zn, outer, inner))| {
            let zi = if input.cumulative_z {
                if i > 0 {
                    z += zn.get(0.0, 0.4);
                }
                z
            } else {
                zn.get(0.0, 1.2)
            };
            let outer = outer.get(0.005, 0.04);
            Station { z: zi, outer_radius: outer, inner_radius: outer * inner.get(0.0, 0.9) }
        })
        .collect();
    let length = stations.last().map(|s| s.z).unwrap_or(0.0);
    let [d, y, s] = input.shell;
    let shell =
        Material { density: d.get(100.0, 3000.0), youngs_modulus: y.get(1e9, 1e11), shear_modulus: s.get(1e8, 3e10) };
    let core = input.core.map(|[d, y, s, a, b]| CoreFill {
        material: Material {
            density: d.get(50.0, 3000.0),
            youngs_modulus: y.get(1e6, 1e11),
            shear_modulus: s.get(1e5, 3e10),
        },
        z_start: a.get(0.0, 1.0) * length,
        z_end: b.get(0.0, 1.0) * length,
    });
    let slice_length = input.slice_length.get(0.004, 0.1) * length.max(1e-3);
    let [m, r, k, a, e] = input.ball;
    let ball = Ball {
        mass: m.get(0.01, 1.0),
        radius: r.get(0.01, 0.1),
        stiffness: k.get(1e5, 1e9),
        exponent: a.get(1.0, 4.0),
        cor: e.get(0.05, 1.0),
        ..Ball::default()
    };
    let max_modes = input.max_modes as usize % (MAX_FUZZ_MODES + 1);
    let [vb, vcm, w, zk] = input.impact;
    let impact = Impact {
        ball_speed: vb.get(0.0, 60.0),
        bat_cm_speed: vcm.get(-10.0, 40.0),
        bat_angular_speed: w.get(-50.0, 100.0),
        impact_z: zk.get(0.0, 1.0),
    };
    let options =
        CollisionOptions { modes: input.modes as usize % (max_modes + 2), time_step: input.time_step.get(1e-6, 2e-5) };
    Some(PhysicsCase { stations, shell, core, slice_length, ball, max_modes, impact, options })
}

/// Bat::new, Ball::validate, ModeSet::compute and collide on [`PhysicsInput`]: typed errors only, never a
/// panic, and no NaN/infinity in anything they accept.
pub fn physics(data: &[u8]) {
    let Some(case) = physics_case(data) else { return };
    let bat = match Bat::new("fuzz", case.stations, case.shell, case.core, case.slice_length) {
        Ok(bat) => bat,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    let ball = case.ball;
    let ball_ok = ball.validate().is_ok();
    if ball_ok {
        assert!(
            ball.unloading_exponent().is_finite() && ball.unloading_exponent() > 0.0,
            "ball {ball:?}: β not finite"
        );
    }
    if !solvable(&bat) {
        return;
    }
    let modes = match ModeSet::compute(&bat, case.max_modes) {
        Ok(modes) => modes,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    check_modes(&modes);
    let impact = Impact { impact_z: case.impact.impact_z * modes.length(), ..case.impact };
    let options = case.options;
    if !(options.time_step >= MIN_FUZZ_TIME_STEP) {
        // Still exercise validation of the tiny or NaN step.
        let _ = options.validate(&modes);
        return;
    }
    match collide(&modes, &ball, &impact, &options) {
        Ok(result) => {
            assert!(ball_ok, "collide accepted an invalid ball {ball:?}");
            check_collision(&result);
        }
        Err(e) => assert!(!e.to_string().is_empty()),
    }
}

// ------------------------------------------------------------------------------------------------------------
// The command line's file formats

/// A directory that does not exist, so relative bat paths in fuzzed case files resolve to nothing.
const NO_SUCH_DIR: &str = "/nonexistent/sweetspot-fuzz";

/// `parse_case` on arbitrary text (a `simulate --case` file); an accepted case is simulated as the command
/// does (small bats only) and must give finite numbers or a typed error.
pub fn case_file(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let case = match sweetspot::cli::case_file::parse_case(&text, Path::new(NO_SUCH_DIR)) {
        Ok(case) => case,
        Err(e) => {
            assert!(!format!("{e:#}").is_empty());
            return;
        }
    };
    case.bat.validate().unwrap_or_else(|e| panic!("parse_case accepted an invalid bat: {e}"));
    case.ball.validate().unwrap_or_else(|e| panic!("parse_case accepted an invalid ball: {e}"));
    assert!(case.options.time_step.is_finite(), "parse_case accepted time_step = {}", case.options.time_step);
    if !solvable(&case.bat) || case.options.time_step < MIN_FUZZ_TIME_STEP || case.options.modes > MAX_FUZZ_MODES {
        return;
    }
    let Ok(modes) = ModeSet::compute(&case.bat, case.options.modes) else { return };
    check_modes(&modes);
    for &z in case.impact_zs.iter().take(3) {
        let impact = Impact { impact_z: z, ..case.swing };
        if let Ok(result) = collide(&modes, &case.ball, &impact, &case.options) {
            check_collision(&result);
        }
    }
}

/// `parse_bat_toml` on arbitrary text: bytes up to the first NUL are the TOML, the rest the profile CSV that
/// `profile = "…"` reads. An accepted bat must be valid and survive `spec_to_toml` → `parse_bat_toml` exactly
/// (what `sweetspot bat export` writes must read back as the same bat).
pub fn bat_toml(data: &[u8]) {
    let (toml_part, csv_part) = match data.iter().position(|&b| b == 0) {
        Some(i) => (&data[..i], &data[i + 1..]),
        None => (data, &data[..0]),
    };
    let toml_text = String::from_utf8_lossy(toml_part);
    let csv_text = String::from_utf8_lossy(csv_part).into_owned();
    use sweetspot::cli::bat_file::{parse_bat_toml, spec_to_toml, BatSpec};
    let bat = match parse_bat_toml(&toml_text, "fuzz", |_| Ok(csv_text)) {
        Ok(bat) => bat,
        Err(e) => {
            assert!(!format!("{e:#}").is_empty());
            return;
        }
    };
    bat.validate().unwrap_or_else(|e| panic!("parse_bat_toml accepted an invalid bat: {e}"));
    let written = spec_to_toml(&BatSpec::from_bat(&bat, None));
    let reread = parse_bat_toml(&written, "other", |_| unreachable!("inline stations need no CSV"))
        .unwrap_or_else(|e| panic!("cannot read back our own bat file: {e:#}\n{written}"));
    assert_eq!(reread, bat, "bat file round trip changed the bat:\n{written}");
}

// ------------------------------------------------------------------------------------------------------------
// Bags

static SCRATCH_COUNTER: AtomicU64 = AtomicU64::new(0);

/// A fresh scratch directory under the system temp dir (removed by [`ScratchDir`]'s drop).
struct ScratchDir(PathBuf);

impl ScratchDir {
    fn new() -> ScratchDir {
        let n = SCRATCH_COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("sweetspot-fuzz-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch directory in the temp dir");
        ScratchDir(dir)
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Arbitrary bytes as a one-file bag: the lenient reader (`bag info`), `bag export`'s CDR decoding and
/// `bag recover` must not panic; a recovered file must read back complete with every kept message.
pub fn bag_reader(data: &[u8]) {
    use sweetspot::bag::{export, info, reader, recover};
    let scratch = ScratchDir::new();
    let bag_dir = scratch.0.join("bag");
    std::fs::create_dir_all(&bag_dir).expect("bag directory");
    // A bag directory is what its metadata.yaml lists.
    let listing = "rosbag2_bagfile_information:\n  relative_file_paths:\n    - bag_0.mcap\n";
    std::fs::write(bag_dir.join("metadata.yaml"), listing).expect("metadata.yaml");
    let file = bag_dir.join("bag_0.mcap");
    std::fs::write(&file, data).expect("write the fuzzed file");

    let mut messages = 0u64;
    let scans = match reader::read_bag(&bag_dir, |m| {
        messages += 1;
        let _ = m.channel.topic.type_name.len();
    }) {
        Ok(scans) => scans,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    let summary = info::info_of(&scans);
    assert_eq!(summary.messages, messages, "bag info counts differ from the messages delivered");
    let _ = info::metadata_of(&scans);
    let _ = info::custom_data_of(&scans);
    let _ = export::swing_rows(&bag_dir);

    for damage in scans.iter().flat_map(|s| s.damage.iter()) {
        assert!(damage.to_string().contains("bag_0.mcap"), "damage names its file: {damage}");
    }

    let recovery = match recover::recover(&file, None, |_| {}) {
        Ok(recovery) => recovery,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            assert_eq!(std::fs::read(&file).expect("the original"), data, "a refused recovery left the file alone");
            return;
        }
    };
    assert_eq!(std::fs::read(&file).expect("the original"), data, "recovery never modifies the original");
    let needed = scans.iter().any(|s| !s.complete || !s.damage.is_empty());
    assert_eq!(recovery.output.is_some(), needed, "a copy is written exactly when something needed repair");
    for entry in recovery.files.iter().filter(|r| r.rebuilt) {
        let output = entry.output.as_ref().expect("a rebuilt file has an output");
        let scan = reader::scan_file(output, |_| {}).unwrap_or_else(|e| panic!("cannot read the recovered file: {e}"));
        assert!(scan.complete, "the recovered file has no footer");
        assert!(scan.damage.is_empty(), "the recovered file is damaged: {:?}", scan.damage);
        assert_eq!(scan.message_count(), entry.messages, "the recovered file lost messages");
    }
}

/// A zstd frame of `size` copies of `byte`: RLE blocks of at most 128 KiB, 4 bytes each (a decompression bomb
/// of ratio ~32,000 written without holding what it expands to).
pub fn zstd_rle_frame(byte: u8, size: u64) -> Vec<u8> {
    // Magic, frame header descriptor (no content size, no checksum), window descriptor 2^17.
    let mut out = vec![0x28, 0xB5, 0x2F, 0xFD, 0x00, 0x38];
    let mut left = size;
    loop {
        let n = left.min(128 * 1024);
        left -= n;
        let header = u32::from(left == 0) | (1 << 1) | ((n as u32) << 3);
        out.extend_from_slice(&header.to_le_bytes()[..3]);
        out.push(byte);
        if left == 0 {
            return out;
        }
    }
}

fn mcap_record(opcode: u8, body: &[u8]) -> Vec<u8> {
    let mut out = vec![opcode];
    out.extend_from_slice(&(body.len() as u64).to_le_bytes());
    out.extend_from_slice(body);
    out
}

/// An MCAP file of zstd chunks, each (compressed frame, claimed uncompressed size), closed by a data end
/// and a footer without summary.
pub fn mcap_of_chunks(chunks: &[(Vec<u8>, u64)]) -> Vec<u8> {
    let string = |s: &str| [(s.len() as u32).to_le_bytes().to_vec(), s.as_bytes().to_vec()].concat();
    let mut out = sweetspot::bag::reader::MCAP_MAGIC.to_vec();
    out.extend(mcap_record(0x01, &[string("ros2"), string("fuzz")].concat()));
    for (frame, claimed) in chunks {
        let mut body = Vec::new();
        body.extend_from_slice(&[0u8; 16]);
        body.extend_from_slice(&claimed.to_le_bytes());
        body.extend_from_slice(&0u32.to_le_bytes());
        body.extend(string("zstd"));
        body.extend_from_slice(&(frame.len() as u64).to_le_bytes());
        body.extend_from_slice(frame);
        out.extend(mcap_record(0x06, &body));
    }
    out.extend(mcap_record(0x0f, &0u32.to_le_bytes()));
    out.extend(mcap_record(0x02, &[0u8; 20]));
    out.extend_from_slice(sweetspot::bag::reader::MCAP_MAGIC);
    out
}

/// The first byte picks what the bag's `bag_0.mcap` is: 0 the other bytes as a file, 1 a symlink to such a
/// file, 2 a symlink to /dev/zero, 3 to /dev/urandom, 4 a FIFO, 5 a directory, 6 a dangling symlink, 7 an MCAP
/// file of decompression bombs built from the other bytes, 3 per chunk (the byte repeated, log2 of how many
/// times, what size the chunk claims). Non-regular files are refused with a typed error without blocking or
/// reading a device, and `bag recover` writes nothing for them; every bomb chunk is reported as damage, the
/// ones claiming more than the limits refused unread.
pub fn bag_hostile(data: &[u8]) {
    use sweetspot::bag::reader::{self, DamageKind};
    use sweetspot::bag::{recover, BagError};
    let Some((&kind, rest)) = data.split_first() else { return };
    let scratch = ScratchDir::new();
    let dir = scratch.0.join("bag");
    std::fs::create_dir_all(&dir).expect("bag directory");
    // A bag directory is what its metadata.yaml lists.
    let listing = "rosbag2_bagfile_information:\n  relative_file_paths:\n    - bag_0.mcap\n";
    std::fs::write(dir.join("metadata.yaml"), listing).expect("metadata.yaml");
    let file = dir.join("bag_0.mcap");
    let mut claims = Vec::new();
    match kind % 8 {
        0 => std::fs::write(&file, rest).expect("write"),
        1 => {
            let target = scratch.0.join("target.mcap");
            std::fs::write(&target, rest).expect("write");
            std::os::unix::fs::symlink(&target, &file).expect("symlink");
        }
        2 => std::os::unix::fs::symlink("/dev/zero", &file).expect("symlink"),
        3 => std::os::unix::fs::symlink("/dev/urandom", &file).expect("symlink"),
        4 => {
            let made = std::process::Command::new("mkfifo").arg(&file).status().expect("mkfifo");
            assert!(made.success(), "mkfifo");
        }
        5 => std::fs::create_dir(&file).expect("directory"),
        6 => std::os::unix::fs::symlink(scratch.0.join("missing"), &file).expect("symlink"),
        _ => {
            let chunks: Vec<(Vec<u8>, u64)> = rest
                .chunks_exact(3)
                .take(64)
                .map(|spec| {
                    let size = 1u64 << (spec[1] % 29);
                    let claimed = match spec[2] % 8 {
                        0 => size,
                        1 => 1024,
                        2 => 255_000_000,
                        3 => u64::MAX,
                        _ => 1 << (spec[2] % 64),
                    };
                    (zstd_rle_frame(spec[0], size), claimed)
                })
                .collect();
            claims = chunks.iter().map(|(frame, claimed)| (frame.len() as u64, *claimed)).collect();
            std::fs::write(&file, mcap_of_chunks(&chunks)).expect("write");
        }
    }
    let before: Vec<_> = std::fs::read_dir(&dir).expect("list").map(|e| e.expect("entry").file_name()).collect();
    let mut messages = 0u64;
    let result = reader::read_bag(&dir, |_| messages += 1);
    match kind % 8 {
        2..=5 => assert!(matches!(result, Err(BagError::NotRegularFile { .. })), "refused: {result:?}"),
        6 => assert!(matches!(result, Err(BagError::Io { .. })), "a dangling symlink is an I/O error: {result:?}"),
        7 => {
            let scans = result.expect("a file of bombs is an MCAP file");
            assert_eq!(messages, 0, "no message comes out of a bomb");
            let damage = &scans[0].damage;
            assert_eq!(damage.len(), claims.len(), "every bomb chunk is reported: {damage:?}");
            for (i, (d, &(compressed, claimed))) in damage.iter().zip(&claims).enumerate() {
                assert_eq!(d.chunk, Some(i as u64));
                let too_large = claimed > reader::chunk_size_limit(compressed);
                assert_eq!(matches!(d.kind, DamageKind::ChunkTooLarge { .. }), too_large, "chunk {i}: {d}");
            }
        }
        _ => return,
    }
    if kind % 8 != 7 {
        assert!(recover::recover(&file, None, |_| {}).is_err(), "recover refuses what is not an MCAP file");
        let after: Vec<_> = std::fs::read_dir(&dir).expect("list").map(|e| e.expect("entry").file_name()).collect();
        assert_eq!(before, after, "recover wrote nothing");
    }
}
