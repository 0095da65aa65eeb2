//! The batter model: swing weight against closed forms, the power law against hand-computed numbers, the
//! equal-speed limit, reaction time against swing weight, and the seed's corking argument with numbers.

use sweetspot::physics::batter::{
    pitch_travel, reaction_time_gained, speed_ratio, swing_time, swing_weight, Batter, ReferenceSwing, SwingShape,
    DEFAULT_SWING_LENGTH,
};
use sweetspot::physics::{Bat, MassProperties, Material, PhysicsError, RigidBat, Station};

/// The 6-in pivot of ASTM F2398, written out here rather than taken from the code under test.
const PIVOT: f64 = 0.1524;

fn reference_swing(bat: MassProperties) -> ReferenceSwing {
    ReferenceSwing { bat, bat_cm_speed: 25.0, bat_angular_speed: 45.0 }
}

fn batter(bat: MassProperties, exponent: f64, shape: SwingShape) -> Batter {
    Batter::new(reference_swing(bat), exponent, 0.1524, DEFAULT_SWING_LENGTH, shape).expect("valid batter")
}

fn table1(name: &str) -> MassProperties {
    RigidBat::preset(name).expect("seed preset").mass_properties()
}

#[test]
fn swing_weight_of_a_sliced_uniform_cylinder_matches_the_closed_form_about_the_pivot() {
    // A solid cylinder of radius r: ∫ (M/L)(z − p)² dz + M r²/4 = M((L − p)³ + p³)/(3L) + M r²/4.
    let (length, radius) = (0.84, 0.03);
    let stations = vec![
        Station { z: 0.0, outer_radius: radius, inner_radius: 0.0 },
        Station { z: length, outer_radius: radius, inner_radius: 0.0 },
    ];
    let bat = Bat::new("cylinder", stations, Material::R161_WOOD, None, 0.001).expect("bat");
    let mp = bat.mass_properties();
    let mass = Material::R161_WOOD.density * std::f64::consts::PI * radius * radius * length;
    let expected = mass * ((length - PIVOT).powi(3) + PIVOT.powi(3)) / (3.0 * length) + mass * radius * radius / 4.0;
    // The midpoint rule misses M Δz²/12 ≈ 1.1e-7 kg·m² here.
    assert!((swing_weight(&mp) - expected).abs() < 1e-6, "{} vs {expected}", swing_weight(&mp));
    assert!((mp.mass - mass).abs() < 1e-9 * mass);
}

#[test]
fn the_same_bat_gives_exactly_the_reference_speed() {
    let bat = Bat::preset("r161").expect("preset").mass_properties();
    for shape in [SwingShape::SamePivot, SwingShape::SameRatio] {
        for n in [0.0, 0.25, 0.5] {
            let p = batter(bat, n, shape).predict(&bat).expect("prediction");
            assert_eq!(p.speed_ratio, 1.0);
            assert_eq!((p.bat_cm_speed, p.bat_angular_speed), (25.0, 45.0), "{shape:?} n = {n}");
        }
    }
}

#[test]
fn the_power_law_scales_speed_by_the_hand_computed_ratio() {
    // (0.16 / 0.20)^(−0.25) = 0.8^(−1/4) = 1.0573712634405641 (computed by hand, to 16 digits).
    let s = speed_ratio(0.16, 0.20, 0.25).expect("ratio");
    assert!((s - 1.057_371_263_440_564).abs() < 1e-14, "{s}");
    // Two rods of the same length (same impact point, same pivot): the impact-point speed scales by s.
    let heavy = MassProperties::from_totals(1.0, 0.84, 0.50, 0.05);
    let light = MassProperties::from_totals(0.8, 0.84, 0.48, 0.045);
    let b = batter(heavy, 0.25, SwingShape::SamePivot);
    let (p_heavy, p_light) = (b.predict(&heavy).expect("heavy"), b.predict(&light).expect("light"));
    // Swing weights by the parallel-axis theorem, by hand: 0.05 + 1.0·0.3476² = 0.17082576,
    // 0.045 + 0.8·0.3276² = 0.130857408; s = (0.130857408/0.17082576)^(−0.25) = 1.06895...
    assert!((p_heavy.swing_weight - 0.170_825_76).abs() < 1e-12);
    assert!((p_light.swing_weight - 0.130_857_408).abs() < 1e-12);
    let expected = (0.130_857_408_f64 / 0.170_825_76).powf(-0.25);
    assert!((p_light.bat_speed / p_heavy.bat_speed - expected).abs() < 1e-12);
    // Same pivot: both turn about the same point, so ω scales by s too and the arm is unchanged.
    assert!((p_light.bat_angular_speed / p_heavy.bat_angular_speed - expected).abs() < 1e-12);
    let pivot_heavy = heavy.center_of_mass - p_heavy.bat_cm_speed / p_heavy.bat_angular_speed;
    let pivot_light = light.center_of_mass - p_light.bat_cm_speed / p_light.bat_angular_speed;
    assert!((pivot_heavy - pivot_light).abs() < 1e-12, "{pivot_heavy} vs {pivot_light}");
    // T = 2S/v, so the faster swing is shorter by exactly the speed ratio.
    assert!((p_heavy.swing_time / p_light.swing_time - expected).abs() < 1e-12);
}

#[test]
fn exponent_zero_reproduces_the_equal_speed_comparison_exactly() {
    let reference = Bat::preset("r161").expect("r161").mass_properties();
    for other in ["r161-corked", "aluminum", "torpedo"] {
        let bat = Bat::preset(other).expect("preset").mass_properties();
        // Same ratio: the very same V and ω as today's comparisons use for every bat.
        let p = batter(reference, 0.0, SwingShape::SameRatio).predict(&bat).expect("prediction");
        assert_eq!((p.bat_cm_speed, p.bat_angular_speed), (25.0, 45.0), "{other}");
        // Same pivot: the same speed at the usual impact point (6 in from the barrel end).
        let b = batter(reference, 0.0, SwingShape::SamePivot);
        let p = b.predict(&bat).expect("prediction");
        let reference_speed = 25.0 + 45.0 * (reference.length - 0.1524 - reference.center_of_mass);
        assert!((p.bat_speed - reference_speed).abs() < 1e-12, "{other}: {} vs {reference_speed}", p.bat_speed);
        assert_eq!(p.speed_ratio, 1.0);
    }
}

#[test]
fn swing_time_falls_and_reaction_time_gained_rises_as_swing_weight_falls() {
    let reference = MassProperties::from_totals(0.9, 0.84, 0.56, 0.05);
    let b = batter(reference, 0.25, SwingShape::SamePivot);
    let baseline = b.predict(&reference).expect("baseline");
    // Same geometry, more and more inertia about the CM: swing weight rises strictly.
    let predictions: Vec<_> = (0..8)
        .map(|i| {
            let bat = MassProperties::from_totals(0.9, 0.84, 0.56, 0.03 + 0.01 * i as f64);
            b.predict(&bat).expect("prediction")
        })
        .collect();
    for pair in predictions.windows(2) {
        assert!(pair[1].swing_weight > pair[0].swing_weight);
        assert!(pair[1].bat_speed < pair[0].bat_speed);
        assert!(pair[1].swing_time > pair[0].swing_time);
        assert!(reaction_time_gained(&baseline, &pair[1]) < reaction_time_gained(&baseline, &pair[0]));
    }
    // The bat lighter than the reference gains time, the heavier loses it.
    assert!(reaction_time_gained(&baseline, &predictions[0]) > 0.0);
    assert!(reaction_time_gained(&baseline, &predictions[7]) < 0.0);
}

#[test]
fn the_seeds_table1_corked_bat_swings_faster_and_buys_the_batter_time() {
    let normal = table1("seed-table1-normal");
    let corked = table1("seed-table1-corked");
    // Swing weights by hand from Table 1: 0.047 + 0.846·(0.51 − 0.1524)² = 0.15518458496 kg·m²,
    // 0.040 + 0.800·(0.40 − 0.1524)² = 0.089044608 kg·m².
    assert!((swing_weight(&normal) - 0.155_184_584_96).abs() < 1e-12);
    assert!((swing_weight(&corked) - 0.089_044_608).abs() < 1e-12);
    let b = Batter::typical(normal).expect("typical batter");
    let (p_normal, p_corked) = (b.predict(&normal).expect("normal"), b.predict(&corked).expect("corked"));
    // 71.5 mph = 31.96336 m/s at 6 in from the barrel end; s = (0.089044608/0.15518458496)^(−1/4) = 1.148974.
    assert!((p_normal.bat_speed - 31.963_36).abs() < 1e-9);
    assert!((p_corked.bat_speed / p_normal.bat_speed - 1.148_974_097_807).abs() < 1e-9);
    // T = 2·(7.3·0.3048 m)/31.96336 m/s = 0.139224 s; corked 0.121173 s: 18.05 ms later, 0.722 m of a 40 m/s pitch.
    assert!((p_normal.swing_time - 0.139_224_411_95).abs() < 1e-9);
    let gained = reaction_time_gained(&p_normal, &p_corked);
    assert!((gained - 0.018_051_609).abs() < 1e-8, "{gained}");
    let travel = pitch_travel(gained, 40.0).expect("travel");
    assert!((travel - 0.722_064_36).abs() < 1e-7, "{travel}");
}

#[test]
fn swing_time_is_twice_the_arc_over_the_contact_speed() {
    assert_eq!(swing_time(2.0, 40.0).expect("time"), 0.1);
    assert!(matches!(swing_time(2.0, f64::NAN), Err(PhysicsError::OutOfRange { .. })));
    assert!(matches!(swing_time(-1.0, 30.0), Err(PhysicsError::OutOfRange { .. })));
}

#[test]
fn batter_round_trips_through_json() {
    let b = Batter::typical(Bat::preset("r161").expect("r161").mass_properties()).expect("typical");
    let text = serde_json::to_string(&b).expect("json");
    assert!(text.contains("\"same-pivot\""), "{text}");
    let back: Batter = serde_json::from_str(&text).expect("parse");
    assert_eq!(back, b);
}

#[test]
fn a_shorter_bat_turns_about_the_same_pivot_at_the_scaled_speed() {
    // The typical batter turns the R161 about its knob; the 0.81-m aluminum bat's usual impact point sits
    // 3 cm nearer the knob, yet the swing must keep the pivot and scale the impact-point speed by s alone.
    let r161 = Bat::preset("r161").expect("r161").mass_properties();
    let aluminum = Bat::preset("aluminum").expect("aluminum").mass_properties();
    let b = Batter::typical(r161).expect("typical");
    let p = b.predict(&aluminum).expect("prediction");
    let pivot = aluminum.center_of_mass - p.bat_cm_speed / p.bat_angular_speed;
    assert!(pivot.abs() < 1e-12, "pivot {pivot} m from the knob");
    let s = (p.swing_weight / swing_weight(&r161)).powf(-0.25);
    assert!((p.bat_speed - 31.963_36 * s).abs() < 1e-9, "{} vs {}", p.bat_speed, 31.963_36 * s);
    assert!((p.impact_z - (0.81 - 0.1524)).abs() < 1e-9);
    assert!((p.bat_speed - p.bat_angular_speed * p.impact_z).abs() < 1e-9);
}
