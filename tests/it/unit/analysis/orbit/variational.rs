//! Unit tests of `analysis::orbit::variational` (a written model's period flow and its
//! monodromy), against a linear oscillator's exact flow.

use isola::analysis::orbit::variational::period_flow;
use isola::solver::Tolerance;

/// The period flow through a branch not taken: x'' + 0.1 x' + x = 0.5 cos τ plus terms that
/// are 0 wherever they are defined, on its periodic orbit x = 5 sin τ (through x = 2, where
/// they stop being defined on the branch before it). The orbit closes, and the monodromy is
/// exp(A T) with A = [[0, 1], [−1, −0.1]], to 1e-9. Before a stage took the piece it is on,
/// the flow stopped: "not finite at τ = 0.2: a value of the model".
#[test]
fn the_flow_through_a_branch_not_taken_is_the_linear_flow() {
    let (c, period) = (0.1, 2.0 * std::f64::consts::PI);
    let (zeta, wd) = (c / 2.0, (1.0f64 - c * c / 4.0).sqrt());
    let (s, co) = (wd * period).sin_cos();
    let e = (-zeta * period).exp();
    let exact = [
        [e * (co + zeta / wd * s), e * s / wd],
        [-e * s / wd, e * (co - zeta / wd * s)],
    ];
    for zero in [
        "if(x < 2, sqrt(2 - x) - sqrt(2 - x), 0)",
        "if(x >= 2 || ln(2 - x) > 0, x - x, 0)",
        "if(x < 2 && ln(2 - x) > 0, x - x, 0)",
    ] {
        let sys = crate::unit::analysis::global::history::linear_with(c, 1.0, "", zero);
        let tol = Tolerance {
            rtol: 1e-12,
            atol: 1e-14,
        };
        let flow = period_flow(&sys, &[0.0, 5.0], 1, tol).unwrap();
        assert!(flow.switches >= 2, "{zero}: {} switches", flow.switches);
        assert!(
            flow.end[0].abs() < 1e-9 && (flow.end[1] - 5.0).abs() < 1e-9,
            "{zero}"
        );
        for (i, row) in exact.iter().enumerate() {
            for (j, value) in row.iter().enumerate() {
                let d = (flow.monodromy[(i, j)] - value).abs();
                assert!(d < 1e-9, "{zero}: Φ[{i}][{j}] off by {d:e}");
            }
        }
    }
}
