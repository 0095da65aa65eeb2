//! Derived metrics: sweet-spot set, BBCOR / BESR, exit speed swept over impact points.
//!
//! # BBCOR (NCAA / ASTM F2219), as modelled here
//! The lab test fires a ball at 136 mph (60.8 m/s) at a stationary bat held in a free-turning pivot 6 in
//! (0.1524 m) from the knob and reports the bat–ball COR, computed from the measured rebound ratio
//! e_A = v_out/v_in with the bat "assumed unconstrained" (ASTM F2219 §1.3) as BBCOR = e_A(1 + r) + r, r =
//! m_ball/m_eff. We simulate exactly that free-bat collision: ball [`Ball::bbcor_protocol`] at 60.8 m/s,
//! bat at rest, flexible modes on; our BBCOR is the effective COR of eq. 27, which for a bat at rest is
//! e_A(1 + R0) + R0 with R0 = m_ball/m_eff of the free bat — the protocol's formula. The impact location
//! follows the protocol's search for the bat's best spot: BBCOR is evaluated at 0.5-in steps from 3 in to
//! 9 in from the barrel end and refined by golden-section search around the best step; the maximum is reported
//! ([`BbcorReport::impact_z`] says where).
//!
//! # BESR (NCAA 1999–2010 / ASTM F2219 "ball exit speed ratio"), as modelled here
//! Ball at 70 mph (31.3 m/s), bat swung about the 6-in pivot so that the impact point moves at 66 mph
//! (29.5 m/s), impact 6 in (0.1524 m) from the barrel end; BESR = [v_out − ½(V − v)]/(V + v) = e_A + ½.
//! The certification test measured the exit speed "at different impact locations along the barrel" with the
//! bat turning so that the point 6 in from the barrel end moves at 66 mph, and certified a bat whose exit
//! speed stayed under 97 mph "at any of the impact locations" (A. M. Nathan, "Bat performance standards in
//! NCAA baseball", Baseball Research Journal 2003): [`besr_scan`] does that, over the BBCOR search's 3–9 in
//! (the test's own list of locations could not be found), with V the 6-in point's 66 mph in the ratio.

use rayon::prelude::*;

use super::bat::MassProperties;
use super::rigid;
use super::units::{INCH, MPH};
use super::{collide, Ball, CollisionOptions, CollisionResult, Impact, ModeSet, PhysicsError};

// The stands' pivot belongs to the bat's mass properties; the bat tests here quote it too.
pub use super::bat::PIVOT_Z;
/// BBCOR test ball speed, m/s (136 mph).
pub const BBCOR_BALL_SPEED: f64 = 136.0 * MPH;
/// BESR test pitch speed, m/s (70 mph).
pub const BESR_BALL_SPEED: f64 = 70.0 * MPH;
/// BESR test bat speed at the impact point, m/s (66 mph).
pub const BESR_BAT_SPEED: f64 = 66.0 * MPH;

/// The several "sweet spots" of a bat for one swing, m from the knob.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SweetSpotSet {
    /// Impact point of maximum flexible-bat exit speed, m.
    pub max_exit_speed_z: f64,
    /// That maximum exit speed, m/s.
    pub max_exit_speed: f64,
    /// The seed's closed-form rigid optimum, m.
    pub rigid_optimum_z: f64,
    /// Node of the first vibrational mode nearest the barrel, m.
    pub node1_z: f64,
    /// Node of the second vibrational mode nearest the barrel, m.
    pub node2_z: f64,
    /// Centre of percussion for a pivot 6 in (0.1524 m) from the knob, m.
    pub center_of_percussion_z: f64,
}

/// One point of an exit-speed sweep.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SweepPoint {
    /// Impact point, m from the knob.
    pub impact_z: f64,
    /// The collision at that point.
    pub result: CollisionResult,
}

/// BBCOR with the impact point where it was found.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BbcorReport {
    /// Bat–ball COR (dimensionless).
    pub bbcor: f64,
    /// Impact point of the reported value, m from the knob.
    pub impact_z: f64,
    /// Collision efficiency e_A = v_out/v_in there.
    pub collision_efficiency: f64,
    /// Test ball speed, m/s.
    pub ball_speed: f64,
}

/// BESR with its inputs.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BesrReport {
    /// Ball exit speed ratio [v_out − ½(V − v)]/(V + v) with V = 66 mph, v = 70 mph (dimensionless).
    pub besr: f64,
    /// Impact point of the reported value, m from the knob ([`besr`]: 6 in from the barrel end).
    pub impact_z: f64,
    /// Ball exit speed, m/s.
    pub exit_speed: f64,
}

/// Exit speed over `impact_zs`, run in parallel; `template` gives the speeds (its impact_z is ignored).
pub fn sweep(
    modes: &ModeSet,
    ball: &Ball,
    template: &Impact,
    impact_zs: &[f64],
    options: &CollisionOptions,
) -> Result<Vec<SweepPoint>, PhysicsError> {
    impact_zs
        .par_iter()
        .map(|&impact_z| {
            let impact = Impact { impact_z, ..*template };
            collide(modes, ball, &impact, options).map(|result| SweepPoint { impact_z, result })
        })
        .collect()
}

/// `count` evenly spaced impact points from `from` to `to` inclusive, m.
pub fn linspace(from: f64, to: f64, count: usize) -> Vec<f64> {
    match count {
        0 => Vec::new(),
        1 => vec![from],
        _ => (0..count).map(|i| from + (to - from) * i as f64 / (count - 1) as f64).collect(),
    }
}

/// Maximises `f` on [a, b] by golden-section search (f unimodal there), returning (x, f(x)).
fn golden_max<F>(mut a: f64, mut b: f64, tol: f64, mut f: F) -> Result<(f64, f64), PhysicsError>
where
    F: FnMut(f64) -> Result<f64, PhysicsError>,
{
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let mut fc = f(c)?;
    let mut fd = f(d)?;
    while (b - a) > tol {
        if fc >= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c)?;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d)?;
        }
    }
    Ok(if fc >= fd { (c, fc) } else { (d, fd) })
}

/// Grid search over `zs` (in parallel) then golden-section refinement in the bracket around the best point.
fn maximise_over(
    zs: &[f64],
    eval: impl Fn(f64) -> Result<f64, PhysicsError> + Sync,
) -> Result<(f64, f64), PhysicsError> {
    let values: Vec<f64> = zs.par_iter().map(|&z| eval(z)).collect::<Result<_, _>>()?;
    let (best, _) =
        values.iter().enumerate().fold((0, f64::NEG_INFINITY), |acc, (i, &v)| if v > acc.1 { (i, v) } else { acc });
    let lo = zs[best.saturating_sub(1)];
    let hi = zs[(best + 1).min(zs.len() - 1)];
    let (z, v) = golden_max(lo, hi, 1e-4, &eval)?;
    Ok(if v >= values[best] { (z, v) } else { (zs[best], values[best]) })
}

/// `[lo, hi]` cut to where ball and bat approach each other, 1 mm inside that stretch (the approach speed
/// ball_speed + V + ω·(z − z_cm) is linear in z): unchanged when they approach over all of it, m.
fn approaching(mp: &MassProperties, template: &Impact, lo: f64, hi: f64) -> Result<(f64, f64), PhysicsError> {
    let at = |z: f64| template.ball_speed + rigid::bat_speed_at(mp, &Impact { impact_z: z, ..*template });
    if at(lo) > 0.0 && at(hi) > 0.0 {
        return Ok((lo, hi));
    }
    // The point where the approach speed is zero, and 1 mm past it on the approaching side.
    let omega = template.bat_angular_speed;
    let zero = mp.center_of_mass - (template.ball_speed + template.bat_cm_speed) / omega;
    let (lo, hi) = if omega > 0.0 { (lo.max(zero + 1e-3), hi) } else { (lo, hi.min(zero - 1e-3)) };
    if omega != 0.0 && lo < hi && at(lo) > 0.0 && at(hi) > 0.0 {
        Ok((lo, hi))
    } else {
        Err(PhysicsError::out_of_range(
            "ball_speed + bat speed over the barrel",
            at(lo).max(at(hi)),
            "> 0 m/s somewhere on the barrel half (ball and bat must approach each other)",
        ))
    }
}

/// The sweet-spot set of `modes` for the swing `template`.
///
/// The maximum of the flexible exit speed is searched over the barrel half of the bat (41 points from
/// L/2 to L − ball radius, then golden-section to 0.1 mm), or the part of it where ball and bat approach each
/// other (a fast-turning swing moves the barrel's inner end away from the ball); nodes are those of modes 1 and
/// 2 nearest the barrel end (NaN-free: the barrel end itself if a mode is not computed).
pub fn sweet_spots(
    modes: &ModeSet,
    ball: &Ball,
    template: &Impact,
    options: &CollisionOptions,
) -> Result<SweetSpotSet, PhysicsError> {
    let length = modes.length();
    let (lo, hi) =
        approaching(&modes.mass_properties(), template, 0.5 * length, length - ball.radius.min(0.25 * length))?;
    let zs = linspace(lo, hi, 41);
    let (max_z, max_v) = maximise_over(&zs, |impact_z| {
        collide(modes, ball, &Impact { impact_z, ..*template }, options).map(|r| r.exit_speed)
    })?;
    let mp = modes.mass_properties();
    let node = |n: usize| modes.nodes(n).into_iter().fold(f64::NAN, f64::max);
    let node_or_end = |n: usize| {
        let z = node(n);
        if z.is_finite() {
            z
        } else {
            length
        }
    };
    Ok(SweetSpotSet {
        max_exit_speed_z: max_z,
        max_exit_speed: max_v,
        rigid_optimum_z: rigid::optimum_impact_z(&mp, ball.mass, template).clamp(0.0, length),
        node1_z: node_or_end(1),
        node2_z: node_or_end(2),
        center_of_percussion_z: mp.center_of_percussion(PIVOT_Z),
    })
}

/// BBCOR of `modes` per the NCAA protocol implemented here (see the module docs), with the
/// [`Ball::bbcor_protocol`] ball.
pub fn bbcor(modes: &ModeSet, options: &CollisionOptions) -> Result<f64, PhysicsError> {
    bbcor_report(modes, &Ball::bbcor_protocol(), options).map(|r| r.bbcor)
}

/// BBCOR with `ball` and where it was found (see the module docs for the protocol).
pub fn bbcor_report(modes: &ModeSet, ball: &Ball, options: &CollisionOptions) -> Result<BbcorReport, PhysicsError> {
    let length = modes.length();
    let zs: Vec<f64> = (0..13).map(|i| length - (9.0 - 0.5 * i as f64) * INCH).filter(|&z| z > 0.0).collect();
    if zs.is_empty() {
        return Err(PhysicsError::out_of_range("bat length", length, "> 9 in (0.2286 m) for the BBCOR protocol"));
    }
    let at = |impact_z: f64| {
        let impact = Impact { ball_speed: BBCOR_BALL_SPEED, bat_cm_speed: 0.0, bat_angular_speed: 0.0, impact_z };
        collide(modes, ball, &impact, options)
    };
    let (z, value) = maximise_over(&zs, |z| at(z).map(|r| r.effective_cor))?;
    let r = at(z)?;
    Ok(BbcorReport {
        bbcor: value,
        impact_z: z,
        collision_efficiency: r.collision_efficiency,
        ball_speed: BBCOR_BALL_SPEED,
    })
}

/// BESR of `modes` with `ball` (see the module docs for the protocol).
pub fn besr(modes: &ModeSet, ball: &Ball, options: &CollisionOptions) -> Result<BesrReport, PhysicsError> {
    let impact_z = modes.length() - 6.0 * INCH;
    let r = collide(modes, ball, &besr_swing(modes)?(impact_z), options)?;
    Ok(BesrReport { besr: r.collision_efficiency + 0.5, impact_z, exit_speed: r.exit_speed })
}

/// The BESR test's swing of `modes`' bat: turning about the 6-in pivot so that the point 6 in from the barrel
/// end moves at 66 mph, into a 70-mph ball; gives the impact at `impact_z` (m from the knob).
fn besr_swing(modes: &ModeSet) -> Result<impl Fn(f64) -> Impact, PhysicsError> {
    let length = modes.length();
    let arm = length - 6.0 * INCH - PIVOT_Z;
    if !(arm > 0.0) {
        return Err(PhysicsError::out_of_range("bat length", length, "> 12 in (0.3048 m) for the BESR protocol"));
    }
    let omega = BESR_BAT_SPEED / arm;
    let bat_cm_speed = omega * (modes.mass_properties().center_of_mass - PIVOT_Z);
    Ok(move |impact_z| Impact { ball_speed: BESR_BALL_SPEED, bat_cm_speed, bat_angular_speed: omega, impact_z })
}

/// BESR as the certification test ran it: the bat turning about the 6-in pivot so that the point 6 in from
/// the barrel end moves at 66 mph, the ball at 70 mph, the exit speed searched over 3–9 in from the barrel
/// end (0.5-in steps, then golden-section); the largest is reported with its BESR and impact point.
pub fn besr_scan(modes: &ModeSet, ball: &Ball, options: &CollisionOptions) -> Result<BesrReport, PhysicsError> {
    let length = modes.length();
    let swing = besr_swing(modes)?;
    let zs: Vec<f64> = (0..13).map(|i| length - (9.0 - 0.5 * i as f64) * INCH).filter(|&z| z > PIVOT_Z).collect();
    if zs.len() < 2 {
        return Err(PhysicsError::out_of_range("bat length", length, "> 15 in (0.381 m) for the BESR scan"));
    }
    let at = |impact_z: f64| collide(modes, ball, &swing(impact_z), options);
    let (impact_z, exit_speed) = maximise_over(&zs, |z| at(z).map(|r| r.exit_speed))?;
    let besr = (exit_speed - 0.5 * (BESR_BAT_SPEED - BESR_BALL_SPEED)) / (BESR_BAT_SPEED + BESR_BALL_SPEED);
    Ok(BesrReport { besr, impact_z, exit_speed })
}
