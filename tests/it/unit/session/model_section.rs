//! Unit tests of `session::model_section` (`src/session/model_section.rs`).

use isola::model::Device;
use isola::session::model_section::*;

#[test]
fn an_override_replaces_both_forms_of_a_quantity() {
    let session = ModelSection {
        frequency_hz: Some(50.0),
        damping_n_s_per_m: Some(0.4),
        ..ModelSection::default()
    };
    let analysis = ModelSection {
        omega: Some(3.7),
        ..ModelSection::default()
    };
    let merged = analysis.over(&session);
    assert_eq!((merged.omega, merged.frequency_hz), (Some(3.7), None));
    assert_eq!(merged.damping_n_s_per_m, Some(0.4));
    let spec = merged.to_spec(&Device::silicone()).unwrap();
    assert_eq!(spec.omega, 3.7);
}
