//! `Safety::validate`: the defaults pass, every bound is inclusive where documented, and each
//! out-of-range field is refused with the TOML key, the value and the range in the message.
//! The bounds are the documented constants; the expected range texts are derived here from
//! the rig's amplifier range (`RigSpec::input_limit`) and the time bounds divided by the loop
//! period, independently of the code that formats them.

use pendulab_plants::RigSpec;
use pendulab_rig::emulator::PlantKind;
use pendulab_rig::runtime::{RunConfig, Safety, run};
mod common;
use common::load;
use pendulab_rig::RigError;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

fn message(s: &Safety, plant: PlantKind) -> String {
    match s.validate(plant) {
        Err(RigError::Config(m)) => m.to_string(),
        other => panic!("{s:?} on the {plant:?} rig: expected a config error, got {other:?}"),
    }
}

#[test]
fn the_defaults_and_the_inclusive_bounds_are_accepted() {
    for plant in [PlantKind::Cart, PlantKind::Arm] {
        let d = Safety::default_for(plant);
        d.validate(plant).unwrap();
        let spec = plant.spec();
        let ts = spec.sample_time;
        // Every bound at its inclusive end.
        let edge = Safety {
            voltage_limit: spec.input_limit,
            travel_limit: match plant {
                PlantKind::Cart => Safety::TRAVEL_LIMIT_MAX_CART,
                PlantKind::Arm => Safety::TRAVEL_LIMIT_MAX_ARM,
            },
            angle_window: Some(90f64.to_radians()),
            watchdog_periods: (Safety::WATCHDOG_MAX_TIME / ts).round() as u32,
            stale_hold_periods: (Safety::STALE_HOLD_MAX_TIME / ts).round() as u32,
            connect_timeout: Duration::from_secs(60),
        };
        edge.validate(plant).unwrap();
        // The narrowest window, 1°.
        Safety {
            angle_window: Some(1f64.to_radians()),
            ..d
        }
        .validate(plant)
        .unwrap();
        // No window (swing-up) and no hold.
        Safety {
            angle_window: None,
            stale_hold_periods: 0,
            ..d
        }
        .validate(plant)
        .unwrap();
    }
    // The book rigs: ±5 V amplifiers, 1 ms.
    assert_eq!(RigSpec::cart().input_limit, 5.0);
    assert_eq!(Safety::default_for(PlantKind::Cart).voltage_limit, 5.0);
}

#[test]
fn each_out_of_range_field_is_refused_naming_key_value_and_range() {
    let plant = PlantKind::Cart;
    let d = Safety::default_for(plant);
    // The example, word for word: 0.5 s at 1 ms is 500 periods.
    assert_eq!(
        message(
            &Safety {
                watchdog_periods: u32::MAX,
                ..d
            },
            plant
        ),
        "safety.watchdog_periods = 4294967295: must be in [1, 500]"
    );
    let cases: Vec<(Safety, &str, &str)> = vec![
        (
            Safety {
                voltage_limit: 1e9,
                ..d
            },
            "safety.voltage_limit = 1000000000",
            "(0, 5]",
        ),
        (
            Safety {
                voltage_limit: 5.000001,
                ..d
            },
            "safety.voltage_limit = 5.000001",
            "(0, 5]",
        ),
        (
            Safety {
                voltage_limit: 0.0,
                ..d
            },
            "safety.voltage_limit = 0",
            "(0, 5]",
        ),
        (
            Safety {
                voltage_limit: f64::NAN,
                ..d
            },
            "safety.voltage_limit = NaN",
            "(0, 5]",
        ),
        (
            Safety {
                travel_limit: 1e300,
                ..d
            },
            "safety.travel_limit = 1",
            "(0, 1] m",
        ),
        (
            Safety {
                travel_limit: -0.1,
                ..d
            },
            "safety.travel_limit = -0.1",
            "(0, 1] m",
        ),
        (
            Safety {
                angle_window: Some(1e-300f64.to_radians()),
                ..d
            },
            "safety.angle_window_deg = 0.0000",
            "[1, 90]",
        ),
        (
            Safety {
                angle_window: Some(91f64.to_radians()),
                ..d
            },
            "safety.angle_window_deg = 91",
            "[1, 90]",
        ),
        (
            Safety {
                watchdog_periods: 0,
                ..d
            },
            "safety.watchdog_periods = 0",
            "[1, 500]",
        ),
        (
            Safety {
                watchdog_periods: 501,
                ..d
            },
            "safety.watchdog_periods = 501",
            "[1, 500]",
        ),
        (
            // The hold must end before the watchdog.
            Safety {
                watchdog_periods: 30,
                stale_hold_periods: 30,
                ..d
            },
            "safety.stale_hold_periods = 30",
            "[0, 29]",
        ),
        (
            // And last at most 0.1 s: 100 periods at 1 ms.
            Safety {
                watchdog_periods: 500,
                stale_hold_periods: 101,
                ..d
            },
            "safety.stale_hold_periods = 101",
            "[0, 100]",
        ),
        (
            Safety {
                connect_timeout: Duration::ZERO,
                ..d
            },
            "safety.connect_timeout_s = 0",
            "(0, 60]",
        ),
        (
            Safety {
                connect_timeout: Duration::from_secs(61),
                ..d
            },
            "safety.connect_timeout_s = 61",
            "(0, 60]",
        ),
    ];
    for (s, start, range) in cases {
        let m = message(&s, plant);
        assert!(m.starts_with(start), "{m:?} should start with {start:?}");
        assert!(m.contains(range), "{m:?} should name the range {range}");
    }
    // The arm's travel is an angle, bounded by half a turn.
    let arm = Safety {
        travel_limit: 3.2,
        ..Safety::default_for(PlantKind::Arm)
    };
    let m = message(&arm, PlantKind::Arm);
    assert!(
        m.starts_with("safety.travel_limit = 3.2") && m.contains(" rad"),
        "{m}"
    );
}

#[test]
fn the_time_bounds_scale_with_the_loop_period() {
    let plant = PlantKind::Cart;
    let d = Safety::default_for(plant);
    // At 10 kHz, 0.5 s is 5000 periods and 0.1 s is 1000.
    let fast = Safety {
        watchdog_periods: 5000,
        stale_hold_periods: 1000,
        ..d
    };
    fast.validate_at(plant, 1e-4).unwrap();
    assert!(fast.validate(plant).is_err());
    let m = match (Safety {
        watchdog_periods: 5001,
        ..d
    })
    .validate_at(plant, 1e-4)
    {
        Err(RigError::Config(m)) => m.to_string(),
        other => panic!("{other:?}"),
    };
    assert!(m.contains("[1, 5000]"), "{m}");
}

#[test]
fn run_refuses_unbounded_limits_before_touching_the_network() {
    // No rig at this address: the run must fail on the setting, not on the connection.
    let mut l = load("plant = \"cart\"\n[controller]\nkind = \"state-feedback\"\nlqr = { q = [10.0, 10.0, 0.0, 0.0], r = 1.0 }\n").unwrap();
    let mut cfg = RunConfig::new(PlantKind::Cart, "127.0.0.1:9".parse().unwrap());
    cfg.safety = l.safety;
    cfg.safety.watchdog_periods = u32::MAX;
    match run(&cfg, l.controller.as_mut(), &AtomicBool::new(false), None) {
        Err(RigError::Config(m)) => {
            assert!(m.to_string().contains("safety.watchdog_periods"), "{m}")
        }
        other => panic!("{other:?}"),
    }
    cfg.safety = l.safety;
    cfg.pendulum_centre = f64::NAN;
    match run(&cfg, l.controller.as_mut(), &AtomicBool::new(false), None) {
        Err(RigError::Config(m)) => assert!(m.to_string().contains("pendulum centre"), "{m}"),
        other => panic!("{other:?}"),
    }
}
