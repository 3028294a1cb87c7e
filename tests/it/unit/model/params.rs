//! Unit tests of `model::params` (`src/model/params.rs`).

use isola::model::drive::DriveSpec;
use isola::model::params::*;

#[test]
fn baseline_is_the_papers() {
    let p = Params::baseline();
    assert_eq!(p.lambda_p(), 1.02);
    assert_eq!(p.j(), 16.0);
    assert_eq!(p.c_tilde(), 0.04);
    assert!((p.drive_i().e_a() - 0.04).abs() < 1e-15);
    assert!((p.drive_i().adr().unwrap() - 0.6).abs() < 1e-14);
    assert!(p.drive_ii().is_off());
    assert_eq!(p.to_spec().build().unwrap(), p);
}

#[test]
fn every_bad_field_is_named_with_its_range() {
    let base = ParamSpec::default();
    let cases: Vec<(ParamSpec, &str)> = vec![
        (
            ParamSpec {
                lambda_p: 0.0,
                ..base
            },
            "lambda_p",
        ),
        (
            ParamSpec {
                lambda_p: -1.0,
                ..base
            },
            "lambda_p",
        ),
        (
            ParamSpec {
                lambda_p: 5.0,
                ..base
            },
            "lambda_p",
        ),
        (
            ParamSpec {
                lambda_p: f64::NAN,
                ..base
            },
            "lambda_p",
        ),
        (ParamSpec { j: 0.0, ..base }, "j"),
        (
            ParamSpec {
                j: f64::INFINITY,
                ..base
            },
            "j",
        ),
        (
            ParamSpec {
                c_tilde: -0.01,
                ..base
            },
            "c_tilde",
        ),
        (ParamSpec { omega: 0.0, ..base }, "omega"),
        (
            ParamSpec {
                omega: -3.0,
                ..base
            },
            "omega",
        ),
        (
            ParamSpec {
                phase_ii: f64::NAN,
                ..base
            },
            "phase_ii",
        ),
        (
            ParamSpec {
                drive: DriveSpec::EaAdr {
                    e_a: 0.04,
                    adr: -0.5,
                },
                ..base
            },
            "adr",
        ),
        (
            ParamSpec {
                drive_ii: Some(DriveSpec::EaAdr {
                    e_a: -1.0,
                    adr: 0.5,
                }),
                ..base
            },
            "e_a_ii",
        ),
        (
            ParamSpec {
                omega: 1e-9,
                ..base
            },
            "omega",
        ),
        (
            ParamSpec {
                c_tilde: 1e100,
                ..base
            },
            "c_tilde",
        ),
        (
            ParamSpec {
                drive: DriveSpec::EaAdr {
                    e_a: 0.04,
                    adr: 3e154,
                },
                ..base
            },
            "adr",
        ),
    ];
    for (spec, field) in cases {
        let err = spec.build().unwrap_err();
        assert_eq!(err.field, field, "{err}");
        let msg = err.to_string();
        assert!(msg.starts_with(field) && msg.contains("allowed"), "{msg}");
    }
    let msg = ParamSpec {
        lambda_p: 0.1,
        ..base
    }
    .build()
    .unwrap_err()
    .to_string();
    assert!(msg.contains("0.23607") && msg.contains("4.23607"), "{msg}");
    // a NaN the user gave is shown; a choice that is not a number has no value to show
    let msg = ParamSpec {
        lambda_p: f64::NAN,
        ..base
    }
    .build()
    .unwrap_err()
    .to_string();
    assert!(msg.starts_with("lambda_p = NaN is out of range"), "{msg}");
    let e = isola::analysis::parameter::FamilyParameter::parse("omega")
        .unwrap()
        .check_built_in()
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "parameter `omega` is out of range: allowed one of the built-in model's but omega, \
         which each member spans: adr, e_a, c_tilde, lambda_p, j"
    );
}
