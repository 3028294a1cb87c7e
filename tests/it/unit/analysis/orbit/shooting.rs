//! Unit tests of `analysis::orbit::shooting` (`src/analysis/orbit/shooting.rs`).

use isola::analysis::orbit::shooting::*;
use isola::model::Params;
use isola::solver::isa::Isa;

#[test]
fn gent_slope_matches_a_difference_quotient() {
    for &l in &[0.5, 0.9, 1.0, 1.3, 2.0, 3.5] {
        let h = 1e-6;
        let fd = (isola::model::forces::gent(l + h, 16.0)
            - isola::model::forces::gent(l - h, 16.0))
            / (2.0 * h);
        assert!((gent_slope(l, 16.0) - fd).abs() < 1e-6 * (1.0 + fd.abs()));
    }
}

/// The monodromy equals difference quotients of the map, across switches.
#[test]
fn monodromy_matches_difference_quotients() {
    let p = Params::paper(0.6, 3.7).unwrap();
    let flow = VariationalFlow::new(&p, ShootingSpec::default().tol);
    let x0 = [1.02 + 0.3, 0.0];
    let o = flow.orbit(x0, 2).unwrap();
    assert!(o.switches > 0, "this orbit goes slack");
    let d = 1e-6;
    for c in 0..2 {
        let mut a = x0;
        let mut b = x0;
        a[c] += d;
        b[c] -= d;
        let (pa, pb) = (flow.map(a, 2).unwrap(), flow.map(b, 2).unwrap());
        for r in 0..2 {
            let fd = (pa[r] - pb[r]) / (2.0 * d);
            let m = o.monodromy[(r, c)];
            assert!(
                (fd - m).abs() < 1e-5 * (1.0 + m.abs()),
                "{r}{c}: {fd} vs {m}"
            );
        }
    }
    assert!(o.liouville_error() < 1e-9, "{}", o.liouville_error());
}

/// The version compiled with FMA and AVX2 computes the baseline's bits, on orbits that go
/// slack (located switches, turning points) and one that hits a frame.
#[test]
#[cfg(target_arch = "x86_64")]
fn every_instruction_set_gives_the_same_bits() {
    if !Isa::X86_64V3.available() {
        eprintln!("skipped: this CPU lacks x86-64-v3");
        return;
    }
    let tol = ShootingSpec::default().tol;
    let mut compared = 0;
    for (adr, omega, x0, k) in [
        (0.6, 3.7, [1.32, 0.0], 2),
        (0.6, 1.8, [1.1, 0.2], 1),
        (1.0, 3.6, [1.3, -0.4], 3),
        (0.6, 3.7, [1.9, 0.0], 1),
    ] {
        let flow = VariationalFlow::new(&Params::paper(adr, omega).unwrap(), tol);
        let base = flow.clone().orbit_body(x0, k);
        // SAFETY: the CPU has x86-64-v3 (checked above)
        let v3 = unsafe { flow.clone().orbit_v3(x0, k) };
        match (base, v3) {
            (Ok(a), Ok(b)) => {
                assert!(a.switches > 0, "{adr} {omega}: no switch met");
                let bits = |o: &PeriodFlow| {
                    let mut v: Vec<u64> = o.monodromy.iter().map(|x| x.to_bits()).collect();
                    v.extend(o.end.pair().map(f64::to_bits));
                    v.extend([o.lambda_min, o.lambda_max, o.trace_integral].map(f64::to_bits));
                    v
                };
                assert_eq!(bits(&a), bits(&b), "{adr} {omega} {x0:?}");
                compared += 1;
            }
            (Err(a), Err(b)) => {
                assert_eq!(a.tau.to_bits(), b.tau.to_bits());
                assert_eq!(a.lambda_i.to_bits(), b.lambda_i.to_bits());
            }
            (a, b) => panic!("{adr} {omega}: {a:?} against {b:?}"),
        }
    }
    assert!(compared >= 3);
}

/// The paper's coexisting responses at ADR 0.6, ω_e 3.7, found by Newton from rough seeds.
#[test]
fn newton_finds_the_harmonic_and_the_subharmonic() {
    let p = Params::paper(0.6, 3.7).unwrap();
    let spec = ShootingSpec::default();
    let low = shoot(&p, 1, &[1.02, 0.0], &spec).unwrap();
    assert!((low.amplitude - 0.012292).abs() < 2e-6, "{}", low.amplitude);
    assert!(low.stable());
    // seeded from the brute-force steady state reached from Δλ = 0.3, v = 0
    let brute = isola::analysis::steady_state(&p, 1.32, 0.0, &Default::default());
    let high = shoot(&p, 2, &brute.poincare[0], &spec).unwrap();
    assert!(
        (high.amplitude - 0.415622).abs() < 2e-6,
        "{}",
        high.amplitude
    );
    assert!(high.stable());
    // the same Newton from the start itself lands on the unstable 1:2 orbit of the isola
    let saddle = shoot(&p, 2, &[1.32, 0.0], &spec).unwrap();
    assert!(!saddle.stable() && saddle.multipliers.0[0].re > 1.0);
    assert!(high.liouville_error().abs() < 1e-9);
}
