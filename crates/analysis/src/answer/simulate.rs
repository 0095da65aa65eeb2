//! The answer of `sweetspot simulate` (and the Python package's `simulate`): one collision per impact point,
//! head-on, oblique or in 3-D, as the document [`SimulateJson`] and its text rendering.

use anyhow::{Context, Result};
use serde::Serialize;

use super::inputs::ObliqueInputs;
use crate::report::json::{BallJson, BatJson, CollisionJson, ObliqueInputsJson, OptionsJson, SwingJson};
use crate::report::table::{num, Table};
use sweetspot_physics::BatterSide;
use sweetspot_physics::{
    collide, collide_oblique, collide_spatial, Ball, Bat, CollisionOptions, Impact, ModeSet, ObliqueImpact,
    SpatialImpact,
};

/// Distance of the default impact point from the barrel end, m (6 in).
pub const DEFAULT_IMPACT_FROM_TIP: f64 = 0.15;

/// The JSON document of `sweetspot simulate --json`.
#[derive(Debug, Serialize)]
pub struct SimulateJson {
    /// The bat's mass properties (of the discretised beam).
    pub bat: BatJson,
    /// The ball.
    pub ball: BallJson,
    /// The swing.
    pub swing: SwingJson,
    /// Numerical options.
    pub options: OptionsJson,
    /// The oblique inputs (absent for a head-on run).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub oblique: Option<ObliqueInputsJson>,
    /// One result per impact point, in the order given.
    pub results: Vec<CollisionJson>,
}

/// Simulates every impact point (the default point when `impact_zs` is empty); head-on unless `oblique` is
/// active.
pub fn simulate(
    bat: &Bat,
    ball: &Ball,
    swing: &Impact,
    oblique: &ObliqueInputs,
    impact_zs: &[f64],
    options: &CollisionOptions,
) -> Result<SimulateJson> {
    let modes = ModeSet::compute(bat, options.modes).with_context(|| format!("normal modes of bat '{}'", bat.name))?;
    let props = modes.mass_properties();
    let default_z = [props.length - DEFAULT_IMPACT_FROM_TIP];
    let zs = if impact_zs.is_empty() { &default_z[..] } else { impact_zs };
    let mut results = Vec::with_capacity(zs.len());
    for &impact_z in zs {
        let impact = Impact { impact_z, ..*swing };
        let context = || format!("collision at impact_z = {impact_z} m");
        if oblique.active {
            let barrel_radius = bat.radii_at(impact_z).0;
            let planar = oblique_impact(impact, barrel_radius, oblique);
            // A level square swing is collide_spatial's planar case, answered by collide_oblique itself; its
            // result also carries the parts defined in the vertical plane.
            if oblique.is_planar() {
                let result = collide_oblique(&modes, ball, &planar, &oblique.contact, options).with_context(context)?;
                results.push(CollisionJson::oblique(impact_z, &result, barrel_radius));
            } else {
                let result = collide_spatial(&modes, ball, &spatial_impact(planar, oblique), &oblique.contact, options)
                    .with_context(context)?;
                results.push(CollisionJson::spatial(impact_z, &result, barrel_radius));
            }
        } else {
            let result = collide(&modes, ball, &impact, options).with_context(context)?;
            results.push(CollisionJson::new(impact_z, &result));
        }
    }
    Ok(SimulateJson {
        bat: BatJson::new(&bat.name, &props),
        ball: ball.into(),
        swing: swing.into(),
        options: options.into(),
        oblique: oblique.active.then(|| oblique_inputs_json(oblique)),
        results,
    })
}

/// The oblique swing at `impact`'s point on a barrel of radius `barrel_radius` (m).
pub fn oblique_impact(impact: Impact, barrel_radius: f64, oblique: &ObliqueInputs) -> ObliqueImpact {
    ObliqueImpact {
        impact,
        barrel_radius,
        undercut: oblique.undercut,
        attack_angle: oblique.attack_angle,
        pitch_angle: oblique.pitch_angle,
        pitch_spin: oblique.pitch_spin,
    }
}

/// The three-dimensional swing: `planar` with the bat's tilt, the swing's direction and the batter's side.
pub fn spatial_impact(planar: ObliqueImpact, oblique: &ObliqueInputs) -> SpatialImpact {
    SpatialImpact {
        oblique: planar,
        bat_tilt: oblique.bat_tilt,
        swing_direction: oblique.swing_direction,
        batter_side: oblique.batter_side,
    }
}

/// The oblique inputs as documented (degrees, rpm).
pub fn oblique_inputs_json(oblique: &ObliqueInputs) -> ObliqueInputsJson {
    ObliqueInputsJson::new(
        oblique.undercut,
        oblique.attack_angle,
        oblique.pitch_angle,
        oblique.pitch_spin,
        &oblique.contact,
    )
    .with_spatial(oblique.bat_tilt, oblique.swing_direction, oblique.batter_side)
}

/// The header line of the oblique inputs (the bat's tilt, the swing's direction and the batter's side when
/// any differs from a right-handed level square swing).
pub fn describe_oblique(o: &ObliqueInputsJson) -> String {
    let spatial = if o.bat_tilt_deg != 0.0 || o.swing_direction_deg != 0.0 || o.batter_side != BatterSide::Right {
        let side = match o.batter_side {
            BatterSide::Right => "right",
            BatterSide::Left => "left",
        };
        format!(
            ", bat tilt {}°, swing direction {}° (right field +), {side}-handed batter",
            num(o.bat_tilt_deg, 4),
            num(o.swing_direction_deg, 4)
        )
    } else {
        String::new()
    };
    // With η² the compliant law replaces the constant e_T, which is then not used.
    let tangential = match o.tangential_stiffness_ratio {
        Some(eta2) => format!("compliant tangential law η² {}", num(eta2, 4)),
        None => format!("e_T {}", num(o.tangential_cor, 4)),
    };
    format!(
        "oblique undercut {} m, attack angle {}°, pitch descent {}°, pitch spin {} rpm{spatial}; {tangential}, μ {}, \
         I/(mR²) {}\n",
        num(o.undercut, 4),
        num(o.attack_angle_deg, 4),
        num(o.pitch_angle_deg, 4),
        num(o.pitch_spin_rpm, 4),
        num(o.friction, 4),
        num(o.ball_inertia_ratio, 4),
    )
}

/// Header lines describing the bat, ball, swing and options.
pub fn describe_inputs(bat: &BatJson, ball: &BallJson, swing: &SwingJson, options: &OptionsJson) -> String {
    format!(
        "bat    {}: mass {} kg, length {} m, CM {} m from knob, I_cm {} kg·m²\n\
         ball   mass {} kg, radius {} m, k1 {} N/m^α, α {}, e0 {}\n\
         swing  ball {} m/s, bat CM {} m/s, bat ω {} rad/s\n\
         model  {} vibrational modes, RK4 step {} s\n",
        bat.name,
        num(bat.mass, 4),
        num(bat.length, 4),
        num(bat.center_of_mass, 4),
        num(bat.moment_of_inertia, 4),
        num(ball.mass, 4),
        num(ball.radius, 4),
        num(ball.stiffness, 4),
        num(ball.exponent, 4),
        super::inputs::cor_text(ball),
        num(swing.ball_speed, 4),
        num(swing.bat_cm_speed, 4),
        num(swing.bat_angular_speed, 4),
        options.modes,
        num(options.time_step, 3),
    )
}

/// The human-readable report: inputs, then one column per impact point.
pub fn render(doc: &SimulateJson) -> String {
    let mut out = describe_inputs(&doc.bat, &doc.ball, &doc.swing, &doc.options);
    if let Some(oblique) = &doc.oblique {
        out.push_str(&describe_oblique(oblique));
    }
    out.push('\n');
    if doc.oblique.is_some() {
        out.push_str(&oblique_table(doc));
        out.push_str("\nthe collision along the line of centres\n");
    }
    out.push_str(&collision_table(doc));
    out.push_str(&mode_energy_table(doc));
    out
}

/// The header of a table with one column per impact point.
fn impact_columns(doc: &SimulateJson) -> impl Iterator<Item = String> + '_ {
    std::iter::once("quantity".to_string()).chain(doc.results.iter().map(|r| format!("z = {} m", num(r.impact_z, 4))))
}

/// The oblique collision's launch, spin and flight per impact point.
fn oblique_table(doc: &SimulateJson) -> String {
    let mut t = Table::new(impact_columns(doc));
    let mut row = |name: &str, f: &dyn Fn(&crate::report::json::ObliqueJson) -> String| {
        t.row(
            std::iter::once(name.to_string())
                .chain(doc.results.iter().map(|r| r.oblique.as_ref().map(f).unwrap_or_default())),
        );
    };
    let optional = |v: Option<f64>, digits: usize| v.map(|v| num(v, digits)).unwrap_or_default();
    row("exit speed (m/s)", &|o| num(o.exit_speed, 5));
    row("launch angle (deg)", &|o| num(o.launch_angle_deg, 4));
    row("spray angle (deg, right field +)", &|o| num(o.flight.spray_angle_deg, 4));
    row("spin (rpm, backspin +)", &|o| num(o.spin_rpm, 5));
    row("sidespin (rpm, hook +)", &|o| num(o.flight.sidespin_rpm, 5));
    row("total spin (rpm)", &|o| num(o.flight.total_spin_rpm, 5));
    row("spin axis (deg, 180 = backspin)", &|o| num(o.flight.spin_axis_deg, 4));
    row("normal exit speed (m/s)", &|o| num(o.normal_exit_speed, 5));
    // The parts defined in a vertical plane: shown when a planar swing is among the results.
    let planar = doc.results.iter().any(|r| r.oblique.as_ref().is_some_and(|o| o.tangential_exit_speed.is_some()));
    if planar {
        row("tangential exit speed (m/s)", &|o| optional(o.tangential_exit_speed, 4));
    }
    row("sliding", &|o| if o.sliding { "yes" } else { "no" }.to_string());
    if planar {
        row("line of centres (deg)", &|o| optional(o.line_of_centres_angle_deg, 4));
    }
    row("barrel radius (m)", &|o| num(o.barrel_radius, 4));
    t.render()
}

/// The collision along the line of centres per impact point: speeds, contact and where the energy went.
fn collision_table(doc: &SimulateJson) -> String {
    let mut t = Table::new(impact_columns(doc));
    let mut row = |name: &str, f: &dyn Fn(&CollisionJson) -> String| {
        t.row(std::iter::once(name.to_string()).chain(doc.results.iter().map(f)));
    };
    row("exit speed (m/s)", &|r| num(r.exit_speed, 5));
    row("rigid-bat exit speed (m/s)", &|r| num(r.rigid_exit_speed, 5));
    row("effective COR e_eff", &|r| num(r.effective_cor, 4));
    row("collision efficiency e_A", &|r| num(r.collision_efficiency, 4));
    row("contact time (ms)", &|r| num(r.contact_time * 1e3, 4));
    row("peak force (kN)", &|r| num(r.peak_force * 1e-3, 4));
    row("impulse (N·s)", &|r| num(r.impulse, 4));
    row("max compression (mm)", &|r| num(r.max_compression * 1e3, 4));
    row("energy before contact (J)", &|r| num(r.energy.initial, 5));
    row("  ball after (J)", &|r| num(r.energy.ball, 5));
    row("  bat rigid motion after (J)", &|r| num(r.energy.bat_rigid, 5));
    row("  bat vibration after (J)", &|r| num(r.energy.vibration, 5));
    row("  ball hysteresis loss (J)", &|r| num(r.energy.hysteresis_loss, 5));
    if doc.results.iter().any(|r| r.hoop.is_some()) {
        let wall = |v: Option<f64>| v.map(|v| num(v, 5)).unwrap_or_default();
        row("  wall hoop mode after (J)", &|r| wall(r.energy.hoop));
        row("  wall stored during contact (J)", &|r| wall(r.energy.hoop_stored));
        row("  wall returned during contact (J)", &|r| wall(r.energy.hoop_returned));
        row("hoop frequency at z (Hz)", &|r| r.hoop.map(|h| num(h.frequency_hz, 5)).unwrap_or_default());
    }
    row("  residual (J)", &|r| num(r.energy.residual, 3));
    t.render()
}

/// The vibrational energy of each mode per impact point; empty when no result has modes.
fn mode_energy_table(doc: &SimulateJson) -> String {
    let mut out = String::new();
    let mode_count = doc.results.iter().map(|r| r.mode_energies.len()).max().unwrap_or(0);
    if mode_count > 0 {
        out.push_str("\nvibrational energy per mode after separation (J)\n");
        let header = ["mode".to_string(), "f (Hz)".to_string()]
            .into_iter()
            .chain(doc.results.iter().map(|r| format!("z = {} m", num(r.impact_z, 4))));
        let mut t = Table::new(header);
        for n in 0..mode_count {
            let frequency = doc.results.iter().find_map(|r| r.mode_energies.get(n)).map(|m| m.frequency_hz);
            let cells = [(n + 1).to_string(), frequency.map(|f| num(f, 5)).unwrap_or_default()].into_iter().chain(
                doc.results.iter().map(|r| r.mode_energies.get(n).map(|m| num(m.energy, 4)).unwrap_or_default()),
            );
            t.row(cells);
        }
        out.push_str(&t.render());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use sweetspot_physics::TangentialContact;

    #[test]
    fn the_oblique_header_names_the_tangential_law_in_use() {
        let constant = TangentialContact::default();
        let compliant = TangentialContact { stiffness_ratio: Some(4.75), ..TangentialContact::default() };
        let line =
            |contact: &TangentialContact| describe_oblique(&ObliqueInputsJson::new(0.01, 0.1, 0.1, 0.0, contact));
        let (with_eta2, without) = (line(&compliant), line(&constant));
        assert!(with_eta2.contains("compliant tangential law η² 4.750,"), "{with_eta2}");
        assert!(!with_eta2.contains("e_T"), "e_T is not used by the compliant law: {with_eta2}");
        assert!(without.contains("; e_T ") && !without.contains("η²"), "{without}");
    }
}
