//! Unit tests of `model::forcing` (`src/model/forcing.rs`).

use isola::model::forcing::*;
/// The phase's derivative is the instantaneous frequency (not twice it).
#[test]
fn a_sweeps_phase_derivative_is_omega() {
    let c = Sweep {
        omega_start: 0.0,
        omega_end: 6.0,
        span: 12000.0,
    };
    for &tau in &[10.0, 3000.0, 6000.0, 11999.0, 12500.0] {
        let d = 1e-3;
        let rate = (c.phase_at(tau + d) - c.phase_at(tau - d)) / (2.0 * d);
        assert!((rate - c.omega_at(tau)).abs() < 1e-6, "{tau}: {rate}");
    }
    assert!((c.omega_at(6000.0) - 3.0).abs() < 1e-12);
}
