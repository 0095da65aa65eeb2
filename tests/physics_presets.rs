//! Bat presets, their mass properties, validation of bad bats and balls, and the seed's rigid bats.

use sweetspot::physics::{
    rigid, Ball, Bat, CoreFill, Impact, MassProperties, Material, PhysicsError, RigidBat, Station,
};

#[test]
fn r161_mass_properties_are_in_line_with_nathans_description() {
    // Nathan (2000): ≈ 0.87–0.885 kg, CM ≈ 0.56 m, radius of gyration ≈ 0.23 m. Wide bands: a check of the
    // geometry reading (diameter column, slice centres), not a tuning target.
    let bat = Bat::preset("r161").expect("preset");
    let mp = bat.mass_properties();
    assert!((bat.length() - 0.84).abs() < 1e-12);
    assert_eq!(bat.slice_count(), 84);
    assert!((0.85..0.90).contains(&mp.mass), "mass {}", mp.mass);
    assert!((0.55..0.57).contains(&mp.center_of_mass), "CM {}", mp.center_of_mass);
    assert!((0.22..0.24).contains(&mp.radius_of_gyration), "r_γ {}", mp.radius_of_gyration);
    // The slices reproduce the table exactly: slice 3 has diameter 35.436 mm.
    let s3 = bat.slices()[2];
    let expected = 649.0 * std::f64::consts::PI * (0.035436f64 / 2.0).powi(2) * 0.01;
    assert!((s3.mass - expected).abs() < 1e-12, "{} vs {expected}", s3.mass);
    assert!((s3.z - 0.025).abs() < 1e-12);
}

#[test]
fn aluminum_preset_matches_the_seeds_table_2() {
    let mp = Bat::preset("aluminum").expect("preset").mass_properties();
    let check = |what: &str, ours: f64, table: f64| {
        assert!((ours - table).abs() <= 0.01 * table, "{what}: {ours} vs Table 2 {table}");
    };
    check("mass", mp.mass, 0.825);
    check("length", mp.length, 0.81);
    check("centre of mass", mp.center_of_mass, 0.46);
    check("moment of inertia", mp.moment_of_inertia, 0.046);
}

/// Mass (kg) and moment of inertia about the 6-in pivot (kg·m²) summed slice by slice about the pivot itself
/// (no parallel-axis step), from the bat's slices.
fn mass_and_swing_weight(bat: &Bat) -> (f64, f64) {
    let pivot = 6.0 * 0.0254;
    bat.slices()
        .iter()
        .fold((0.0, 0.0), |(m, i), s| (m + s.mass, i + s.mass * (s.z - pivot).powi(2) + s.rotary_inertia))
}

#[test]
fn weight_matched_alloy_walls_keep_aluminums_mass_and_swing_weight_with_a_real_end_plug() {
    let aluminum = Bat::preset("aluminum").expect("preset");
    let (mass, weight) = mass_and_swing_weight(&aluminum);
    let rho_area = |r: f64| 2700.0 * std::f64::consts::PI * r * r * 0.01;
    for wall in [1.2e-3, 1.6e-3, 2.0e-3] {
        let matched = Bat::alloy_weight_matched("m", wall).expect("a wall thinner than aluminum's can be matched");
        let plain = Bat::alloy_profile("p", wall).expect("bat");
        let (m, w) = mass_and_swing_weight(&matched);
        assert!((m - mass).abs() < 1e-9, "wall {wall}: mass {m} vs {mass}");
        assert!((w - weight).abs() < 1e-9, "wall {wall}: swing weight {w} vs {weight}");
        assert!((matched.length() - aluminum.length()).abs() < 1e-15);
        // The barrel (from the taper's end to the plug) and its hoop mode are the plain wall's, bit for bit.
        let (a, b) = (matched.slices(), plain.slices());
        for z in [0.55, 0.62, 0.68, 0.7] {
            assert_eq!(matched.hoop_at(z), plain.hoop_at(z), "wall {wall}, z {z}");
        }
        let plugged: Vec<usize> = (0..a.len()).filter(|&i| a[i].mass != b[i].mass && a[i].z > 0.5).collect();
        assert!(!plugged.is_empty() && plugged.iter().all(|&i| a[i].z > 0.75), "plug at {plugged:?}");
        // The plug is solid alloy: every plugged slice but the innermost has no bore left, and its mass is
        // that of a solid disc of the barrel's outer radius.
        for &i in &plugged[1..] {
            let r_o = matched.radii_at(a[i].z).0;
            assert_eq!(matched.radii_at(a[i].z).1, 0.0, "slice {i}");
            assert!((a[i].mass - rho_area(r_o)).abs() < 1e-12, "slice {i}: {} vs {}", a[i].mass, rho_area(r_o));
            assert_eq!(matched.hoop_at(a[i].z), None, "a plugged section has no hoop mode");
        }
        // The handle wall is what restores the mass: thicker than aluminum's for a thinner barrel.
        assert!(a[10].mass > aluminum.slices()[10].mass, "wall {wall}");
    }
    // A barrel heavier than aluminum's cannot be brought to its swing weight by a handle and an end plug.
    match Bat::alloy_weight_matched("m", 3.0e-3) {
        Err(PhysicsError::OutOfRange { field, .. }) => assert_eq!(field, "barrel_wall"),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

#[test]
fn corking_makes_the_bat_lighter_with_its_centre_of_mass_toward_the_handle() {
    let wood = Bat::preset("r161").expect("preset").mass_properties();
    let corked_bat = Bat::preset("r161-corked").expect("preset");
    let corked = corked_bat.mass_properties();
    assert!(corked.mass < wood.mass && corked.center_of_mass < wood.center_of_mass);
    assert!(corked.moment_of_inertia < wood.moment_of_inertia);
    // Removed wood minus added cork over the drilled slices: (649 − 200)·π·(0.0127 m)²·0.25 m.
    let expected_loss = (649.0 - 200.0) * std::f64::consts::PI * 0.0127f64.powi(2) * 0.25;
    assert!((wood.mass - corked.mass - expected_loss).abs() < 1e-9, "{} vs {expected_loss}", wood.mass - corked.mass);
    let core = corked_bat.core.expect("cork core");
    assert!((core.z_end - core.z_start - 0.254).abs() < 1e-12);
}

#[test]
fn every_preset_is_valid_and_unknown_names_are_typed_errors() {
    for name in Bat::preset_names() {
        let bat = Bat::preset(name).expect("preset");
        bat.validate().expect("valid");
        assert_eq!(&bat.name, name);
        let mp = bat.mass_properties();
        assert!(mp.mass > 0.5 && mp.mass < 1.2, "{name}: {}", mp.mass);
    }
    let err = Bat::preset("corked-r161").unwrap_err();
    assert!(matches!(err, PhysicsError::UnknownPreset { .. }));
    assert!(err.to_string().contains("r161-corked"), "the message lists the known presets: {err}");
    assert!(matches!(Ball::preset("softball"), Err(PhysicsError::UnknownBallPreset { .. })));
}

fn simple(stations: Vec<Station>) -> Result<Bat, PhysicsError> {
    Bat::new("t", stations, Material::R161_WOOD, None, 0.01)
}

fn st(z: f64, outer: f64, inner: f64) -> Station {
    Station { z, outer_radius: outer, inner_radius: inner }
}

#[test]
fn malformed_bats_are_refused_with_the_field_named() {
    assert!(matches!(simple(vec![st(0.0, 0.03, 0.0)]), Err(PhysicsError::BadProfile(_))));
    assert!(
        matches!(simple(vec![st(0.0, 0.03, 0.0), st(0.5, 0.03, 0.0), st(0.5, 0.03, 0.0)]), Err(PhysicsError::BadProfile(m)) if m.contains("stations[2].z"))
    );
    let inner = simple(vec![st(0.0, 0.03, 0.0), st(0.8, 0.03, 0.03)]);
    assert!(
        matches!(inner, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "stations[1].inner_radius"),
        "{inner:?}"
    );
    let nan = simple(vec![st(0.0, f64::NAN, 0.0), st(0.8, 0.03, 0.0)]);
    assert!(
        matches!(nan, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "stations[0].outer_radius"),
        "{nan:?}"
    );
    let not_at_knob = simple(vec![st(0.1, 0.03, 0.0), st(0.8, 0.03, 0.0)]);
    assert!(matches!(not_at_knob, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "stations[0].z"));
    let ok = vec![st(0.0, 0.03, 0.0), st(0.8, 0.03, 0.0)];
    for bad_slice in [0.0, -0.01, f64::INFINITY, 0.5, 1e-5] {
        let bat = Bat::new("t", ok.clone(), Material::R161_WOOD, None, bad_slice);
        assert!(
            matches!(bat, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "slice_length"),
            "{bad_slice}: {bat:?}"
        );
    }
    let bad_material = Material { shear_modulus: -1.0, ..Material::R161_WOOD };
    let bat = Bat::new("t", ok.clone(), bad_material, None, 0.01);
    assert!(matches!(bat, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "shell.shear_modulus"));
    // A core outside the bat, or a core where there is no bore.
    let core = CoreFill { material: Material::CORK, z_start: 0.5, z_end: 0.9 };
    let bat = Bat::new("t", ok.clone(), Material::R161_WOOD, Some(core), 0.01);
    assert!(matches!(bat, Err(PhysicsError::OutOfRange { ref field, .. }) if field == "core.z_end"), "{bat:?}");
    let core = CoreFill { material: Material::CORK, z_start: 0.5, z_end: 0.8 };
    let bat = Bat::new("t", ok, Material::R161_WOOD, Some(core), 0.01);
    assert!(matches!(bat, Err(PhysicsError::BadProfile(_))), "{bat:?}");
}

#[test]
fn slice_tables_parse_robustly_and_refuse_garbage() {
    let text = "# index diameter\n1, 50\n2\t40\n\n3 30 # comment\n4 30\n";
    let bat = Bat::from_slice_table("t", text, Material::R161_WOOD, 0.02).expect("parses");
    assert_eq!(bat.slice_count(), 4);
    assert!((bat.length() - 0.08).abs() < 1e-12);
    assert!((bat.slices()[1].z - 0.03).abs() < 1e-12);
    let r = bat.radii_at(0.03).0;
    assert!((r - 0.020).abs() < 1e-12, "slice 2 radius {r}");
    let gap = Bat::from_slice_table("t", "1 50\n2 40\n4 30\n5 30\n", Material::R161_WOOD, 0.01);
    assert!(matches!(gap, Err(PhysicsError::BadProfile(m)) if m.contains("expected 3")));
    let junk = Bat::from_slice_table("t", "1 50\n2 forty\n", Material::R161_WOOD, 0.01);
    assert!(matches!(junk, Err(PhysicsError::BadProfile(_))));
    let negative = Bat::from_slice_table("t", "1 50\n2 -4\n3 4\n4 4\n", Material::R161_WOOD, 0.01);
    assert!(matches!(negative, Err(PhysicsError::OutOfRange { .. })));
}

#[test]
fn ball_validation_and_hysteresis_parameters() {
    let ball = Ball::default();
    ball.validate().expect("default ball");
    Ball::bbcor_protocol().validate().expect("protocol ball");
    // β = (1+α)/e0² − 1 and continuity of the two curves at u_m.
    let beta = ball.unloading_exponent();
    assert!((beta - (2.84 / (0.53 * 0.53) - 1.0)).abs() < 1e-12);
    let um = 0.02;
    let k2 = ball.unloading_stiffness(um);
    assert!(
        (k2 * um.powf(beta) - ball.stiffness * um.powf(ball.exponent)).abs()
            < 1e-6 * ball.stiffness * um.powf(ball.exponent)
    );
    for (field, bad) in [
        ("ball.mass", Ball { mass: 0.0, ..ball }),
        ("ball.radius", Ball { radius: f64::NAN, ..ball }),
        ("ball.stiffness", Ball { stiffness: -1.0, ..ball }),
        ("ball.exponent", Ball { exponent: 0.5, ..ball }),
        ("ball.cor", Ball { cor: 1.01, ..ball }),
    ] {
        assert!(matches!(bad.validate(), Err(PhysicsError::OutOfRange { field: ref f, .. }) if f == field), "{field}");
    }
}

#[test]
fn seed_rigid_bats_and_closed_forms() {
    let normal = RigidBat::preset("seed-table1-normal").expect("preset");
    assert_eq!(
        (normal.mass, normal.center_of_mass, normal.moment_of_inertia, normal.effective_cor),
        (0.846, 0.51, 0.047, 0.40)
    );
    let corked = RigidBat::preset("seed-table1-corked").expect("preset");
    assert_eq!((corked.mass, corked.center_of_mass, corked.moment_of_inertia), (0.800, 0.40, 0.040));
    let al = RigidBat::preset("seed-table2-aluminum").expect("preset");
    assert_eq!(
        (al.mass, al.length, al.center_of_mass, al.moment_of_inertia, al.effective_cor),
        (0.825, 0.81, 0.46, 0.046, 0.58)
    );
    assert_eq!(RigidBat::preset("seed-table2-wood").expect("preset").mass, 0.846);
    for name in RigidBat::preset_names() {
        RigidBat::preset(name).expect("preset").validate().expect("valid");
    }
    assert!(matches!(RigidBat::preset("nope"), Err(PhysicsError::UnknownPreset { .. })));

    // The rigid optimum is the maximum of the closed form (checked by brute force), for several swings.
    for (vb, vcm, w) in [(40.0, 20.0, 40.0), (8.0, 1.0, 8.0), (30.0, 25.0, 0.0), (35.0, 15.0, -10.0)] {
        let swing = Impact { ball_speed: vb, bat_cm_speed: vcm, bat_angular_speed: w, impact_z: 0.0 };
        let z_opt = normal.optimum_impact_z(0.145, &swing);
        let v = |z: f64| normal.exit_speed(0.145, &Impact { impact_z: z, ..swing });
        let (mut best_z, mut best_v) = (0.0, f64::NEG_INFINITY);
        for i in 0..=200_000 {
            let z = -1.0 + 3.0 * i as f64 / 200_000.0;
            if v(z) > best_v {
                best_v = v(z);
                best_z = z;
            }
        }
        assert!((z_opt - best_z).abs() < 1e-4, "swing {vb},{vcm},{w}: formula {z_opt} vs brute force {best_z}");
    }
    // Without rotation the optimum is the centre of mass (the seed's remark after eq. 4).
    let still = Impact { ball_speed: 30.0, bat_cm_speed: 10.0, bat_angular_speed: 0.0, impact_z: 0.0 };
    assert!((normal.optimum_impact_z(0.145, &still) - 0.51).abs() < 1e-12);

    // Eq. 25 with the bat speed at the impact point (Fig. 6 usage) equals the swing form.
    let z = 0.7;
    let swing = Impact { ball_speed: 8.0, bat_cm_speed: 2.0, bat_angular_speed: 5.0, impact_z: z };
    let v_bat = 2.0 + 5.0 * (z - 0.51);
    assert!((normal.exit_speed(0.145, &swing) - normal.exit_speed_at(0.145, 8.0, v_bat, z)).abs() < 1e-12);
    // Momentum bookkeeping of eq. 25: e = 1 and a huge bat returns the ball at v_ball + 2 v_bat.
    let wall = MassProperties::from_totals(1e12, 1.0, 0.5, 1e12);
    let v = rigid::exit_speed(
        &wall,
        0.145,
        1.0,
        &Impact { ball_speed: 10.0, bat_cm_speed: 3.0, bat_angular_speed: 0.0, impact_z: 0.5 },
    );
    assert!((v - 16.0).abs() < 1e-9);
}

#[test]
fn centre_of_percussion_is_the_conjugate_point() {
    let mp = Bat::preset("r161").expect("preset").mass_properties();
    let pivot = 0.1524;
    let cop = mp.center_of_percussion(pivot);
    // (z_cop − z_cm)(z_cm − z_pivot) = r_γ².
    let lhs = (cop - mp.center_of_mass) * (mp.center_of_mass - pivot);
    assert!((lhs - mp.radius_of_gyration.powi(2)).abs() < 1e-12);
    assert!(cop > mp.center_of_mass && cop < mp.length);
}
