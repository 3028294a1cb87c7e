//! The force law of MODEL.md §1: Gent elasticity, loss of tension, and the frames.
//!
//! These are the readable reference forms; the solvers' hot loop uses an algebraically equal
//! form with one division per stage (see `solver::field`), tested against these.

use super::params::Params;

/// The two stretches where the Gent denominator vanishes, `|λ − 1/λ| = √J`:
/// `((√(J+4) − √J)/2, (√(J+4) + √J)/2)`, i.e. (√5 − 2, √5 + 2) for J = 16.
pub fn gent_poles(j: f64) -> (f64, f64) {
    let (s, r) = (j.sqrt(), (j + 4.0).sqrt());
    (0.5 * (r - s), 0.5 * (r + s))
}

/// Gent elastic tension g(λ) = (λ − λ⁻³)/(1 − (λ² + λ⁻² − 2)/J), valid between the poles.
pub fn gent(lambda: f64, j: f64) -> f64 {
    let l2 = lambda * lambda;
    (lambda - 1.0 / (l2 * lambda)) / (1.0 - (l2 + 1.0 / l2 - 2.0) / j)
}

/// Slope g′(λ) of the Gent tension, from g = N/D with N = λ − λ⁻³, D = 1 − (λ² + λ⁻² − 2)/J:
/// g′ = (N′D − N D′)/D², N′ = 1 + 3λ⁻⁴, D′ = −2(λ − λ⁻³)/J.
pub fn gent_slope(lambda: f64, j: f64) -> f64 {
    let (l2, n) = (lambda * lambda, lambda - lambda.powi(-3));
    let d = 1.0 - (l2 + 1.0 / l2 - 2.0) / j;
    let (dn, dd) = (1.0 + 3.0 / (l2 * l2), -2.0 * n / j);
    (dn * d - n * dd) / (d * d)
}

/// Gent strain energy W(λ) = −(J/2)·ln(1 − (λ² + λ⁻² − 2)/J), with dW/dλ = g(λ).
pub fn gent_energy(lambda: f64, j: f64) -> f64 {
    let l2 = lambda * lambda;
    -0.5 * j * (1.0 - (l2 + 1.0 / l2 - 2.0) / j).ln()
}

/// Tension p = g(λ) − φ²λ + c̃·λ̇ of a taut membrane (negative means it would be compressed).
pub fn tension(lambda: f64, phi_sq: f64, lambda_dot: f64, c_tilde: f64, j: f64) -> f64 {
    gent(lambda, j) - phi_sq * lambda + c_tilde * lambda_dot
}

/// Force a membrane carries: `max(p, 0)`, and 0 below the lower Gent pole, where the membrane
/// is slack whatever the formula says.
pub fn membrane_force(lambda: f64, phi_sq: f64, lambda_dot: f64, c_tilde: f64, j: f64) -> f64 {
    if lambda <= gent_poles(j).0 {
        return 0.0;
    }
    tension(lambda, phi_sq, lambda_dot, c_tilde, j).max(0.0)
}

/// Forces (f_I, f_II) the two membranes carry at λ_I = `x`, dλ_I/dτ = `v` under the squared
/// voltages φ_I², φ_II² (membrane II at λ_II = 2λ_p − λ_I, stretching at −v).
pub fn membrane_forces(p: &Params, x: f64, v: f64, phi_sq_i: f64, phi_sq_ii: f64) -> (f64, f64) {
    let (c, j) = (p.c_tilde(), p.j());
    (
        membrane_force(x, phi_sq_i, v, c, j),
        membrane_force(2.0 * p.lambda_p() - x, phi_sq_ii, -v, c, j),
    )
}

/// Net force f_II − f_I on the mass (= d²λ_I/dτ²) for membrane stretches set by λ_I = `x`.
pub fn net_force(p: &Params, x: f64, v: f64, phi_sq_i: f64, phi_sq_ii: f64) -> f64 {
    let (f_i, f_ii) = membrane_forces(p, x, v, phi_sq_i, phi_sq_ii);
    f_ii - f_i
}

/// True when λ_I = `x` puts the mass on a frame (λ_I ≤ 0 or λ_II ≤ 0) or stretches a
/// membrane to its Gent limit: the trajectory has left the model.
pub fn outside_model(p: &Params, x: f64) -> bool {
    let upper = gent_poles(p.j()).1;
    let x_ii = 2.0 * p.lambda_p() - x;
    !(x > 0.0 && x_ii > 0.0 && x < upper && x_ii < upper)
}
