//! Continued branches against brute force and time integration (issue 6).
//!
//! Tolerances: branch amplitudes equal the brute-force responses (fine-step RK4, converged to
//! 1e-11) within 1e-6; the Liouville check det M = exp(∫ tr A dτ) holds to 1e-8 at every
//! point; stability from the multipliers is confirmed by integrating perturbed orbits on both
//! sides of a fold.

use isola::analysis::continuation::branch::{
    BifurcationKind, BranchEnd, ContinuationSpec, ContinuedBranch, continue_branch,
    switch_at_period_doubling,
};
use isola::analysis::global::frequency_response::{FrequencyResponseSpec, frequency_response};
use isola::analysis::grid::Axis;
use isola::analysis::orbit::shooting::{PeriodicOrbit, ShootingSpec, VariationalFlow};
use isola::analysis::{Progress, SteadyStateSpec, steady_state};
use isola::model::Params;
use isola::solver::Resolution;

use crate::common::written;

fn spec(min: f64, max: f64) -> ContinuationSpec {
    ContinuationSpec {
        min,
        max,
        ..ContinuationSpec::default()
    }
}

/// The 1:2 branch through the response reached from Δλ = `dx`, v = 0.
fn subharmonic(adr: f64, omega: f64, dx: f64) -> ContinuedBranch {
    let p = Params::paper(adr, omega).unwrap();
    let brute = steady_state(&p, p.lambda_p() + dx, 0.0, &SteadyStateSpec::default());
    assert_eq!(brute.period, Some(2));
    continue_branch(
        &p,
        2,
        &brute.poincare[0],
        &spec(2.0, 6.0),
        &Progress::new(0),
    )
    .unwrap()
}

fn liouville_ok(b: &ContinuedBranch) {
    let worst = b
        .points
        .iter()
        .map(|p| p.liouville_error.abs())
        .fold(0.0, f64::max);
    eprintln!("Liouville check: worst |det M − exp∫tr A| = {worst:e}");
    assert!(worst < 1e-8, "det check off by {worst:e}");
}

/// ADR 0.6: the 1:2 branch near ω 3.7 closes on itself, with two folds that bound the range
/// the brute force found it in (≈ 3.60–5.40), one stable and one unstable arc.
#[test]
fn adr_0_6_subharmonic_is_an_isola() {
    let b = subharmonic(0.6, 3.7, 0.3);
    assert_eq!(b.ends, [BranchEnd::Closed, BranchEnd::Closed]);
    let folds: Vec<_> = b.of_kind(BifurcationKind::Fold).collect();
    assert_eq!(folds.len(), 2, "{:?}", b.bifurcations);
    assert_eq!(b.of_kind(BifurcationKind::PeriodDoubling).count(), 0);
    let (lo, hi) = b.parameter_range();
    assert!(lo < 3.60 && lo > 3.55 && hi > 5.40 && hi < 5.5, "{lo} {hi}");
    for f in folds {
        assert!(f.precision < 1e-8);
        assert!((f.multipliers.0[0].re - 1.0).abs() < 1e-6, "{f:?}");
        assert!((f.omega - lo).abs() < 1e-6 || (f.omega - hi).abs() < 1e-6);
    }
    let arcs = b.arcs();
    let stable_runs = arcs.iter().filter(|a| a.2).count();
    assert!(stable_runs <= 2 && arcs.len() <= 3, "{arcs:?}");
    liouville_ok(&b);
}

/// ADR 1.0: the 1:2 branch through the response at ω 3.6 ends at both sides on period
/// doublings of the 1:1 branch, which continuing the 1:1 branch finds at the same ω; branch
/// switching there gives back the same 1:2 branch.
#[test]
fn adr_1_0_subharmonic_ends_on_period_doublings_of_the_harmonic() {
    let b = subharmonic(1.0, 3.6, -0.3);
    assert_eq!(
        b.ends,
        [
            BranchEnd::Parent { period: 1 },
            BranchEnd::Parent { period: 1 }
        ]
    );
    let mut ends: Vec<f64> = b
        .of_kind(BifurcationKind::ParentPeriodDoubling)
        .map(|f| {
            assert!((f.multipliers.0[0].re + 1.0).abs() < 1e-6, "{f:?}");
            f.omega
        })
        .collect();
    ends.sort_by(f64::total_cmp);
    liouville_ok(&b);

    let p = Params::paper(1.0, 4.0).unwrap();
    let harmonic = steady_state(&p, p.lambda_p(), 0.0, &SteadyStateSpec::default());
    let main = continue_branch(
        &p,
        1,
        &harmonic.poincare[0],
        &spec(3.0, 6.0),
        &Progress::new(0),
    )
    .unwrap();
    let pds: Vec<_> = main.of_kind(BifurcationKind::PeriodDoubling).collect();
    assert_eq!(pds.len(), 2);
    for (pd, end) in pds.iter().zip(&ends) {
        assert!((pd.omega - end).abs() < 1e-8, "{} vs {end}", pd.omega);
    }
    let switched =
        switch_at_period_doubling(&p, &main, pds[0], &spec(2.0, 6.0), &Progress::new(0)).unwrap();
    let (lo, _) = switched.parameter_range();
    assert!((lo - b.parameter_range().0).abs() < 1e-8, "{lo}");
    assert_eq!(
        switched
            .of_kind(BifurcationKind::ParentPeriodDoubling)
            .count(),
        2
    );
}

/// Brute force with fine RK4 steps (error far below 1e-6) at a few ω: every periodic
/// response found is on a continued branch with the same amplitude within 1e-6.
#[test]
fn continued_branches_pass_through_the_brute_force_responses() {
    let p = Params::paper(0.6, 3.7).unwrap();
    let fr_spec = FrequencyResponseSpec {
        omega: Axis::new(3.7, 4.9, 4),
        dx: Axis::new(-0.3, 0.3, 3),
        v: Axis::new(-0.5, 0.5, 2),
        steady: SteadyStateSpec {
            tol_converged: 1e-11,
            resolution: Resolution {
                min_steps_per_period: 1024,
                max_step: 0.05,
            },
            ..SteadyStateSpec::default()
        },
        sweeps: false,
        ..FrequencyResponseSpec::default()
    };
    let fr = frequency_response(&p, &fr_spec, &Progress::new(0)).unwrap();
    let seed = |k: usize| {
        fr.responses
            .iter()
            .find(|r| r.steady.period == Some(k))
            .unwrap()
            .steady
            .poincare[0]
    };
    let at = p.with_omega(fr.omegas[0]).unwrap();
    let branches = [1, 2]
        .map(|k| continue_branch(&at, k, &seed(k), &spec(3.5, 5.5), &Progress::new(0)).unwrap());
    let shooting = ShootingSpec::default();
    let mut checked = 0;
    let mut worst: f64 = 0.0;
    for r in fr.responses.iter().filter(|r| r.steady.period.is_some()) {
        let k = r.steady.period.unwrap();
        let orbits: Vec<PeriodicOrbit> =
            branches[k - 1].orbits_at(&at, r.omega, &shooting).unwrap();
        let a = r.steady.amplitude.unwrap();
        let d = orbits
            .iter()
            .map(|o| (o.amplitude - a).abs())
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
        checked += 1;
    }
    eprintln!("{checked} brute-force responses, worst amplitude difference {worst:e}");
    assert!(checked >= 6, "only {checked} responses");
    assert!(worst < 1e-6, "branch off the brute force by {worst:e}");
}

/// Distance after `n` periods of a trajectory started `eps` from the orbit along `dir`.
fn drift(p: &Params, orbit: &PeriodicOrbit, dir: [f64; 2], eps: f64, n: usize) -> f64 {
    let flow = VariationalFlow::new(p, ShootingSpec::default().tol);
    let x = orbit.poincare[0];
    let start = [x[0] + eps * dir[0], x[1] + eps * dir[1]];
    let end = flow.map(start, n * orbit.period).unwrap();
    (end[0] - x[0]).hypot(end[1] - x[1])
}

/// Near each fold of the ADR 0.6 isola the stable side attracts a perturbed trajectory and the
/// unstable side repels one, as the multipliers say.
#[test]
fn stability_from_multipliers_agrees_with_time_integration_at_the_folds() {
    let b = subharmonic(0.6, 3.7, 0.3);
    let shooting = ShootingSpec::default();
    let base = Params::paper(0.6, 3.7).unwrap();
    for fold in b.of_kind(BifurcationKind::Fold) {
        // 0.01 inside the fold in ω: one orbit on each side of the fold
        let w = if fold.omega < 4.5 {
            fold.omega + 0.01
        } else {
            fold.omega - 0.01
        };
        let p = base.with_omega(w).unwrap();
        let orbits = b.orbits_at(&base, w, &shooting).unwrap();
        let near: Vec<_> = orbits
            .iter()
            .filter(|o| (o.amplitude - fold.amplitude).abs() < 0.1)
            .collect();
        assert_eq!(near.len(), 2, "{w}: {:?}", orbits.len());
        for o in near {
            let mu = o.multipliers.0[0].re;
            let m = &o.monodromy;
            if o.stable() {
                // shrinks like the spectral radius
                let d = drift(&p, o, [1.0, 0.0], 1e-6, 100);
                assert!(
                    d < 1e-6 * o.multipliers.spectral_radius().powi(50),
                    "{w}: {d}"
                );
            } else {
                // grows along the unstable eigenvector of M (multiplier μ > 1)
                let e = [m[0][1], mu - m[0][0]];
                let n = e[0].hypot(e[1]);
                let d = drift(&p, o, [e[0] / n, e[1] / n], 1e-8, 10);
                assert!(mu > 1.0 && d > 1e-8 * mu.powi(5), "{w}: μ {mu} d {d}");
            }
        }
    }
}

/// The paper's model as a session writes it (sessions/user_model_paper.toml), at `overrides`.
fn written_paper(overrides: &[(&str, f64)]) -> isola::model::equations::EquationSystem {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/user_model_paper.toml"),
    )
    .unwrap();
    let written = isola::session::written::WrittenModel::read(&text).unwrap();
    let overrides = overrides.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    written.system(&overrides).unwrap()
}

/// The monodromy of `k` periods from `x0` against central differences of the k-period map
/// (step 1e-6: the difference quotient's error is about 1e-11 / 1e-6 from the integration
/// tolerance, hence the tolerance 2e-5 relative), and Liouville's formula to 1e-9.
fn monodromy_matches_differences<S: isola::analysis::orbit::shooting::Shootable>(
    model: &S,
    x0: &[f64],
    k: usize,
) -> usize {
    let tol = ShootingSpec::default().tol;
    let flow = model.period_flow(x0, k, tol).unwrap();
    let n = x0.len();
    let d = 1e-6;
    for c in 0..n {
        let (mut up, mut down) = (x0.to_vec(), x0.to_vec());
        up[c] += d;
        down[c] -= d;
        let (a, b) = (
            model.period_flow(&up, k, tol).unwrap().end,
            model.period_flow(&down, k, tol).unwrap().end,
        );
        for r in 0..n {
            let fd = (a[r] - b[r]) / (2.0 * d);
            let m = flow.monodromy[(r, c)];
            assert!(
                (fd - m).abs() < 2e-5 * (1.0 + m.abs()),
                "∂x_{r}/∂x0_{c}: differences {fd}, variational {m}"
            );
        }
    }
    let liouville = (flow.monodromy.determinant() - flow.trace_integral.exp()).abs();
    assert!(liouville < 1e-9, "Liouville check off by {liouville:e}");
    flow.switches
}

/// The written paper model's monodromy (symbolic Jacobian, switches of its max/if kinks
/// located) matches difference quotients across the membranes' loss of tension, and agrees
/// with the built-in model's hand-written variational equations to 1e-7.
#[test]
fn a_written_model_s_monodromy_matches_differences_and_the_built_in() {
    let sys = written_paper(&[("ADR", 0.6), ("omega", 3.7)]);
    let x0 = [1.02 + 0.3, 0.0];
    let switches = monodromy_matches_differences(&sys, &x0, 2);
    assert!(switches >= 4, "the orbit goes slack ({switches} switches)");
    use isola::analysis::orbit::shooting::Shootable;
    let tol = ShootingSpec::default().tol;
    let built_in = Params::paper(0.6, 3.7)
        .unwrap()
        .period_flow(&x0, 2, tol)
        .unwrap();
    let ours = sys.period_flow(&x0, 2, tol).unwrap();
    for r in 0..2 {
        assert!((built_in.end[r] - ours.end[r]).abs() < 1e-9);
        for c in 0..2 {
            let (a, b) = (built_in.monodromy[(r, c)], ours.monodromy[(r, c)]);
            assert!(
                (a - b).abs() < 1e-7 * (1.0 + a.abs()),
                "M[{r}][{c}]: {a} vs {b}"
            );
        }
    }
    assert!((built_in.lambda_max - ours.lambda_max).abs() < 1e-10);
    assert!((built_in.lambda_min - ours.lambda_min).abs() < 1e-10);
}

/// A field that jumps where x crosses 1/2 (an `if` whose branches differ): the monodromy
/// needs the saltation jump S = I + (f⁺ − f⁻)∇hᵀ/ḣ at each crossing; without it the
/// difference quotients disagree by the jump's size (0.3/v). Liouville holds with det S.
#[test]
fn a_field_that_jumps_gets_the_saltation_jump() {
    let sys = written(
        r#"[model]
states = ["x", "v"]
frequency = "omega"
amplitude = "x"
[model.parameters]
omega = 1.2
c = 0.2
F = 1.0
[model.derivatives]
x = "v"
v = "-c*v - x + if(x > 0.5, -0.3, 0) + F*cos(omega*t)"
"#,
    );
    let switches = monodromy_matches_differences(&sys, &[0.0, 0.0], 3);
    assert!(switches >= 4, "{switches} crossings");
}

/// The paper's isola continued on the model written as equations: the same folds as the
/// built-in model's within 1e-8 (README: ω 3.589644726 and 5.443868901), a closed branch.
#[test]
fn the_written_paper_model_continues_to_the_built_in_isola() {
    let built_in = subharmonic(0.6, 3.7, 0.3);
    let sys = written_paper(&[("ADR", 0.6), ("omega", 3.7)]);
    let brute = steady_state(
        &Params::paper(0.6, 3.7).unwrap(),
        1.32,
        0.0,
        &SteadyStateSpec::default(),
    );
    let ours = continue_branch(
        &sys,
        2,
        &brute.poincare[0],
        &spec(2.0, 6.0),
        &Progress::new(0),
    )
    .unwrap();
    assert_eq!(ours.ends, [BranchEnd::Closed, BranchEnd::Closed]);
    let folds = |b: &ContinuedBranch| {
        let mut f: Vec<f64> = b.of_kind(BifurcationKind::Fold).map(|f| f.omega).collect();
        f.sort_by(f64::total_cmp);
        f
    };
    let (a, b) = (folds(&built_in), folds(&ours));
    eprintln!("folds: built-in {a:?}, written {b:?}");
    assert_eq!(a.len(), 2);
    assert_eq!(b.len(), 2);
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-8, "fold {x} vs {y}");
    }
    liouville_ok(&ours);
}

/// The catalogue's Duffing oscillator with nonlinear damping (sessions/
/// user_model_duffing_isola.toml), at `overrides`.
fn duffing(overrides: &[(&str, f64)]) -> isola::model::equations::EquationSystem {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sessions/user_model_duffing_isola.toml"),
    )
    .unwrap();
    let written = isola::session::written::WrittenModel::read(&text).unwrap();
    let overrides = overrides.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    written.system(&overrides).unwrap()
}

/// The Duffing isola continued in ω and its lowest fold continued in (ω, F): against the
/// independent integration quoted in the session (SciPy DOP853 with Newton shooting): the
/// isola's amplitude at ω 1.06 is 3.683103850380 (to 1e-7), it is born at F ≈ 0.008893 (the
/// minimum of F along its fold curve; harmonic balance says 0.00908), and it loses
/// stability below ω ≈ 1.0466 at a Neimark–Sacker point.
#[test]
fn the_duffing_isola_is_continued_and_born_where_an_independent_integration_says() {
    use isola::analysis::Oscillator;
    use isola::analysis::continuation::bifurcation_curve::{
        CurveSpec, Turning, continue_bifurcation,
    };
    use isola::analysis::parameter::{ContinuationParameter, FamilyParameter, Name};
    let sys = duffing(&[]);
    let seed = sys
        .steady_state(sys.grid_start([0.0, 2.0]), &SteadyStateSpec::default())
        .unwrap();
    assert_eq!(seed.period, Some(1));
    let start = sys.state_vec(&sys.poincare_states(&seed)[0]);
    let in_omega = ContinuationSpec {
        min: 0.9,
        max: 1.2,
        step: 0.01,
        step_max: 0.01,
        ..ContinuationSpec::default()
    };
    let isola = continue_branch(&sys, 1, &start, &in_omega, &Progress::new(0)).unwrap();
    assert_eq!(
        isola.ends,
        [BranchEnd::Closed, BranchEnd::Closed],
        "{:?}",
        isola.ends
    );
    let at = isola
        .orbits_at(&sys, 1.06, &ShootingSpec::default())
        .unwrap();
    let big = at.iter().map(|o| o.amplitude).fold(0.0, f64::max);
    assert!((big - 3.683103850380).abs() < 1e-7, "{big}");
    let ns: Vec<f64> = isola
        .of_kind(BifurcationKind::NeimarkSacker)
        .map(|b| b.omega)
        .collect();
    let folds: Vec<f64> = isola
        .of_kind(BifurcationKind::Fold)
        .map(|b| b.omega)
        .collect();
    eprintln!("Duffing isola: amplitude {big} at ω 1.06, folds {folds:?}, Neimark–Sacker {ns:?}");
    assert!(ns.iter().any(|w| (w - 1.0466).abs() < 1e-3), "{ns:?}");
    let low = isola
        .of_kind(BifurcationKind::Fold)
        .min_by(|a, b| a.omega.total_cmp(&b.omega))
        .unwrap();
    let f = ContinuationParameter::Model(FamilyParameter::Named(Name::new("F").unwrap()));
    let curve_spec = CurveSpec {
        second: f,
        min: 0.005,
        max: 0.0106,
        first_min: 0.9,
        first_max: 1.2,
        step: 2e-3,
        step_max: 5e-3,
        ..CurveSpec::default()
    };
    let curve = continue_bifurcation(
        &sys,
        ContinuationParameter::Omega,
        low,
        &curve_spec,
        &Progress::new(0),
    )
    .unwrap();
    let birth = curve
        .extrema_of(Turning::Second)
        .filter(|e| e.minimum)
        .map(|e| e.point.second)
        .fold(f64::INFINITY, f64::min);
    eprintln!("Duffing isola born at F = {birth}");
    assert!((birth - 0.008893).abs() < 5e-6, "{birth}");
}

/// A written model of four states (sessions/user_model_viscoelastic.toml: a Zener branch per
/// membrane): the 4 × 4 monodromy across the membranes' loss of tension against difference
/// quotients and Liouville's formula, and its 1:1 response at ω 3.7 shot and continued in ω
/// with four multipliers per point.
#[test]
fn a_four_state_model_is_shot_and_continued() {
    use isola::analysis::Oscillator;
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sessions/user_model_viscoelastic.toml"),
    )
    .unwrap();
    let sys = isola::session::written::WrittenModel::read(&text)
        .unwrap()
        .system(&Default::default())
        .unwrap();
    let x0 = [1.12, 0.0, 1.02, 1.02];
    let switches = monodromy_matches_differences(&sys, &x0, 1);
    assert!(switches >= 2, "the orbit goes slack ({switches} switches)");
    let seed = sys
        .steady_state(sys.grid_start([0.0, 0.0]), &SteadyStateSpec::default())
        .unwrap();
    assert_eq!(seed.period, Some(1));
    let start = sys.state_vec(&sys.poincare_states(&seed)[0]);
    let orbit =
        isola::analysis::orbit::shooting::shoot(&sys, 1, &start, &ShootingSpec::default()).unwrap();
    // the independent integration's amplitude (SciPy DOP853, rtol 1e-13), quoted in the session
    assert!(
        (orbit.amplitude - 0.014387070707).abs() < 1e-7,
        "{}",
        orbit.amplitude
    );
    assert_eq!(orbit.multipliers.0.len(), 4);
    let b = continue_branch(&sys, 1, &start, &spec(3.5, 3.9), &Progress::new(0)).unwrap();
    assert!(b.points.len() > 5);
    assert!(
        b.points
            .iter()
            .all(|p| p.multipliers.0.len() == 4 && p.x.len() == 4)
    );
    liouville_ok(&b);
}

/// Two coupled oscillators, one meeting a stop (`max(x2 - d, 0)`): four multipliers, whose
/// complex pairs meet on the real axis inside the unit circle near ω 1.062 and 1.079 (there
/// the product of |μ|² − 1 over the pairs changes sign, and Neimark–Sacker points were
/// reported where every |μ| is below 0.91). Only the two true ones below are: a pair of
/// modulus 1 at ω 0.84629 and 0.89406 (an independent shooting, scipy DOP853 at 1e-12,
/// put every |μ| at 1.000000 there).
#[test]
fn pairs_meeting_on_the_real_axis_are_no_neimark_sacker_points() {
    let mut torus: Vec<f64> = special_points(
        "coupled",
        r#"schema = 1
[model]
states = ["x1", "v1", "x2", "v2"]
frequency = "omega"
amplitude = "x1"
[model.parameters]
c = 0.05
kc = 0.5
a = 0.3
kn = 5.0
d = 0.3
F = 0.3
omega = 1.1
[model.derivatives]
x1 = "v1"
v1 = "F*cos(omega*t) - c*v1 - x1 - kc*(x1 - x2) - a*x1^3"
x2 = "v2"
v2 = "-c*v2 - x2 - kc*(x2 - x1) - kn*max(x2 - d, 0)"

[[analysis]]
name = "cont"
kind = "continuation"
[analysis.settings]
dx0 = 0.2
[analysis.settings.continuation]
min = 0.8
max = 1.12
"#,
    )
    .into_iter()
    .filter(|(kind, _)| kind == "neimark-sacker")
    .map(|(_, omega)| omega)
    .collect();
    torus.sort_by(f64::total_cmp);
    assert_eq!(torus.len(), 2, "{torus:?}");
    for (found, want) in torus.iter().zip([0.846293, 0.894064]) {
        assert!((found - want).abs() < 1e-5, "{torus:?}");
    }
}

/// A symmetric clearance oscillator's 1:3 branch: a real multiplier crosses +1 at ω
/// 1.7993322533 (an independent shooting, scipy DOP853 at 1e-12), where the branch goes on in
/// ω (a symmetry-breaking pitchfork): a branch point, not a fold, which it was called.
#[test]
fn a_multiplier_through_one_where_the_branch_goes_on_is_a_branch_point() {
    let special = special_points(
        "clearance",
        r#"schema = 1
[model]
states = ["x", "v"]
frequency = "omega"
amplitude = "x"
[model.parameters]
c = 0.05
k0 = 0.2
k1 = 2.0
d = 0.5
F = 0.3
omega = 1.0
[model.let]
fs = "k1*(max(x - d, 0) + min(x + d, 0))"
[model.derivatives]
x = "v"
v = "F*cos(omega*t) - c*v - k0*x - fs"

[[analysis]]
name = "c13"
kind = "continuation"
model = { omega = 1.9 }
[analysis.settings]
dx0 = -0.3628785814339019
v0 = -0.3430263290485984
[analysis.settings.continuation]
min = 1.5
max = 2.5
"#,
    );
    assert_eq!(special.len(), 1, "{special:?}");
    let (kind, omega) = &special[0];
    assert_eq!(kind, "branch-point");
    // the corrector lands on the crossing branch near it: the point of the smallest test is
    // kept (1.7993267 was reported, 5.5e-6 off, before; 1.79933225 now, 8e-9)
    assert!((omega - 1.7993322533).abs() < 1e-7, "{omega}");
}

/// The located special points (kind, parameter) of the one continuation in the session
/// `text`, run as `isola run` would from a file `NAME.toml`.
fn special_points(name: &str, text: &str) -> Vec<(String, f64)> {
    use isola::analysis::Progress;
    use isola::session::Session;
    use isola::session::run::{Shard, run_analysis};
    use isola::session::store::ResultPaths;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let s = Session::load(&path).unwrap();
    run_analysis(&s, &s.analyses[0], Shard::ALL, &Progress::new(0)).unwrap();
    let csv = ResultPaths::new(&s, &s.analyses[0].name).csv;
    csv::Reader::from_path(csv)
        .unwrap()
        .records()
        .map(|r| r.unwrap())
        .filter(|r| &r[3] != "point")
        .map(|r| (r[3].to_string(), r[4].parse().unwrap()))
        .collect()
}
