//! Unit tests of `analysis::resolution` (`src/analysis/resolution.rs`).

use isola::analysis::continuation::hunt::HuntSpec;
use isola::analysis::resolution::*;
use isola::solver::{Resolution, Tolerance};

#[test]
fn the_default_is_64_steps_per_period() {
    assert_eq!(Resolution::steps(64), Resolution::default());
    assert_eq!(
        ResolutionSetting::tolerance(1e-10).rtol,
        Tolerance::default().rtol
    );
}

#[test]
fn both_forms_read_and_bad_values_name_the_range() {
    assert_eq!(
        ResolutionSetting::parse("128"),
        Ok(ResolutionSetting::StepsPerPeriod(128))
    );
    assert_eq!(
        ResolutionSetting::parse("rtol=1e-12"),
        Ok(ResolutionSetting::Reference { rtol: 1e-12 })
    );
    for bad in ["4", "0", "-3", "1.5", "rtol=2", "rtol=1e-15", "fine"] {
        let e = ResolutionSetting::parse(bad).unwrap_err();
        assert!(e.starts_with(&format!("{bad} is out of range")), "{e}");
        assert!(e.contains("[8, 100000]"), "{e}");
    }
}

#[test]
fn twice_the_resolution_halves_every_step() {
    let mut spec = HuntSpec::default();
    spec.double_resolution().unwrap();
    assert_eq!(spec.response.steady.resolution, Resolution::steps(128));
    assert_eq!(spec.continuation.shooting.tol.rtol, 1e-11 / 32.0);
}
