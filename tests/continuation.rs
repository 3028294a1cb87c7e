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
    continue_branch(&p, 2, brute.poincare[0], &spec(2.0, 6.0), &Progress::new(0)).unwrap()
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
        harmonic.poincare[0],
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
        switch_at_period_doubling(&main, pds[0], &spec(2.0, 6.0), &Progress::new(0)).unwrap();
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
        .map(|k| continue_branch(&at, k, seed(k), &spec(3.5, 5.5), &Progress::new(0)).unwrap());
    let shooting = ShootingSpec::default();
    let mut checked = 0;
    let mut worst: f64 = 0.0;
    for r in fr.responses.iter().filter(|r| r.steady.period.is_some()) {
        let k = r.steady.period.unwrap();
        let orbits: Vec<PeriodicOrbit> = branches[k - 1].orbits_at(r.omega, &shooting).unwrap();
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
    let base = b.base.build().unwrap();
    for fold in b.of_kind(BifurcationKind::Fold) {
        // 0.01 inside the fold in ω: one orbit on each side of the fold
        let w = if fold.omega < 4.5 {
            fold.omega + 0.01
        } else {
            fold.omega - 0.01
        };
        let p = base.with_omega(w).unwrap();
        let orbits = b.orbits_at(w, &shooting).unwrap();
        let near: Vec<_> = orbits
            .iter()
            .filter(|o| (o.amplitude - fold.amplitude).abs() < 0.1)
            .collect();
        assert_eq!(near.len(), 2, "{w}: {:?}", orbits.len());
        for o in near {
            let mu = o.multipliers.0[0].re;
            let m = o.monodromy;
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
