//! The isola hunter against the brute force it starts from (issue 6).
//!
//! What can fail here: every brute-force subharmonic response (an attractor, so stable) must
//! lie on a continued branch, on a stable arc of it, within 1e-4 in its stroboscopic points
//! (the fixed-step RK4 of the brute force against Dormand–Prince shooting at 1e-11); the
//! continued ω range must contain the brute-force range and extend past it by less than one
//! grid step (0.1); the verdicts (isola at ADR 0.6, attached at 1.0) follow the paper's claims.

use isola::analysis::Progress;
use isola::analysis::continuation::branch::{BifurcationKind, BranchEnd, ContinuationSpec};
use isola::analysis::continuation::hunt::{Hunt, HuntSpec, Verdict, hunt};
use isola::analysis::global::frequency_response::FrequencyResponseSpec;
use isola::analysis::grid::Axis;
use isola::model::Params;

/// A hunt over ω 3.0–6.0 by 0.1 from 7 × 7 initial states, continued over ω 2–6.5.
fn coarse_hunt() -> HuntSpec {
    HuntSpec {
        response: FrequencyResponseSpec {
            omega: Axis::new(3.0, 6.0, 31),
            dx: Axis::new(-0.8, 0.8, 7),
            v: Axis::new(-1.0, 1.0, 7),
            ..FrequencyResponseSpec::default()
        },
        continuation: ContinuationSpec {
            min: 2.0,
            max: 6.5,
            ..ContinuationSpec::default()
        },
    }
}

fn hunt_at(adr: f64) -> Hunt {
    let p = Params::paper(adr, 3.0).unwrap();
    hunt(&p, &coarse_hunt(), &Progress::new(0)).unwrap()
}

/// Every brute-force response of every subharmonic branch lies on the hunted branch it was
/// attached to, at a stable point, and the continued range covers the brute-force one.
fn brute_force_lies_on_stable_arcs(h: &Hunt, adr: f64) {
    let p = Params::paper(adr, 3.0).unwrap();
    let grid_step = 0.1;
    let subharmonic: Vec<_> = h
        .response
        .branches
        .iter()
        .filter(|b| b.is_subharmonic())
        .collect();
    for b in &subharmonic {
        let hunted = h
            .branches
            .iter()
            .find(|x| x.seeds.contains(&b.id))
            .unwrap_or_else(|| panic!("brute-force branch {} was not continued", b.id));
        assert!(
            hunted.omega_min <= b.omega_min + 1e-9 && hunted.omega_max >= b.omega_max - 1e-9,
            "continued {}–{} does not cover brute force {}–{}",
            hunted.omega_min,
            hunted.omega_max,
            b.omega_min,
            b.omega_max
        );
        for r in h
            .response
            .responses
            .iter()
            .filter(|r| r.branch == Some(b.id))
        {
            let orbits = hunted
                .branch
                .orbits_at(&p, r.omega, &Default::default())
                .unwrap();
            let matching = orbits.iter().find(|o| {
                r.steady.poincare.iter().all(|p| {
                    o.poincare
                        .iter()
                        .any(|q| (p[0] - q[0]).abs().max((p[1] - q[1]).abs()) < 1e-4)
                })
            });
            let orbit = matching
                .unwrap_or_else(|| panic!("the response at ω {} is not on the branch", r.omega));
            assert!(
                orbit.stable(),
                "brute force found an unstable orbit at ω {}",
                r.omega
            );
            let amplitude = r.steady.amplitude.unwrap();
            assert!(
                (orbit.amplitude - amplitude).abs() < 1e-4,
                "ω {}: {} vs {amplitude}",
                r.omega,
                orbit.amplitude
            );
        }
    }
    // the folds bound the brute-force range to within one grid step
    for hunted in &h.branches {
        let ids = &hunted.seeds;
        let (lo, hi) = h
            .response
            .branches
            .iter()
            .filter(|b| ids.contains(&b.id))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), b| {
                (lo.min(b.omega_min), hi.max(b.omega_max))
            });
        assert!(
            lo - hunted.omega_min < grid_step,
            "{lo} vs {}",
            hunted.omega_min
        );
        assert!(
            hunted.omega_max - hi < grid_step,
            "{hi} vs {}",
            hunted.omega_max
        );
    }
}

/// ADR 0.6 (Fig 4): one subharmonic branch, the hidden 1:2 near ω 3.7, and it is an isola
/// bounded by two folds with multipliers at +1.
#[test]
fn adr_0_6_hunt_finds_one_hidden_isola() {
    let h = hunt_at(0.6);
    let adr = 0.6;
    assert!(h.failures.is_empty(), "{:?}", h.failures);
    assert_eq!(
        h.branches.len(),
        1,
        "{:#?}",
        h.branches.iter().map(|b| b.describe()).collect::<Vec<_>>()
    );
    let isola = &h.branches[0];
    eprintln!("{}", isola.describe());
    assert_eq!(isola.branch.period, 2);
    assert_eq!(isola.verdict, Verdict::Isola);
    assert!(isola.hidden);
    assert!(isola.omega_min < 3.7 && isola.omega_max > 3.7);
    let folds: Vec<_> = isola.folds().collect();
    assert_eq!(folds.len(), 2);
    for f in folds {
        assert!((f.multipliers.0[0].re - 1.0).abs() < 1e-6, "{f:?}");
    }
    assert_eq!(isola.stable_arcs.len(), 1, "{:?}", isola.stable_arcs);
    assert_eq!(isola.unstable_arcs.len(), 1, "{:?}", isola.unstable_arcs);
    brute_force_lies_on_stable_arcs(&h, adr);
}

/// ADR 1.0 (Fig 5): the 1:2 branch is attached (both ends on period doublings of the 1:1
/// branch, multipliers at −1 there) and reached by a sweep; a small 1:3 branch near ω 3.6 is
/// found too.
#[test]
fn adr_1_0_hunt_finds_the_attached_branch_and_the_1_3() {
    let h = hunt_at(1.0);
    let adr = 1.0;
    for b in &h.branches {
        eprintln!("{}", b.describe());
    }
    assert!(h.failures.is_empty(), "{:?}", h.failures);
    let attached = h
        .branches
        .iter()
        .find(|b| b.branch.period == 2)
        .expect("a 1:2 branch");
    assert_eq!(attached.verdict, Verdict::Attached);
    assert!(!attached.hidden);
    assert_eq!(
        attached.branch.ends,
        [
            BranchEnd::Parent { period: 1 },
            BranchEnd::Parent { period: 1 }
        ]
    );
    let pds: Vec<_> = attached
        .branch
        .of_kind(BifurcationKind::ParentPeriodDoubling)
        .collect();
    assert_eq!(pds.len(), 2);
    for pd in pds {
        let mu = pd
            .multipliers
            .0
            .iter()
            .map(|m| m.re)
            .fold(f64::INFINITY, f64::min);
        assert!((mu + 1.0).abs() < 1e-6, "{pd:?}");
    }
    let third = h
        .branches
        .iter()
        .find(|b| b.branch.period == 3)
        .expect("a 1:3 branch");
    assert!(third.omega_min < 3.6 && third.omega_max > 3.6);
    brute_force_lies_on_stable_arcs(&h, adr);
}

/// Across ADR (Fig 7's family): no subharmonic at 0.15, a hidden isola at 0.3 and 0.6, an
/// attached branch at 0.8: born between 0.15 and 0.3 and merged between 0.6 and 0.8, as the
/// paper estimates (≈ 0.25 and ≈ 0.65).
#[test]
fn the_isola_is_born_and_merges_across_adr() {
    use isola::analysis::continuation::hunt_family::{HuntFamilySpec, hunt_family, transitions};
    use isola::analysis::parameter::FamilyParameter;
    let p = Params::paper(0.6, 3.0).unwrap();
    let spec = HuntFamilySpec {
        parameter: FamilyParameter::Adr,
        values: vec![0.15, 0.3, 0.6, 0.8],
        hunt: coarse_hunt(),
    };
    let members = hunt_family(&p, &spec, &Progress::new(0), |_| {}).unwrap();
    let verdicts: Vec<_> = members.iter().map(|m| m.verdict(2)).collect();
    assert_eq!(
        verdicts,
        [
            None,
            Some(Verdict::Isola),
            Some(Verdict::Isola),
            Some(Verdict::Attached)
        ]
    );
    let t = transitions(&members);
    let of_1_2: Vec<_> = t.iter().filter(|t| t.period == 2).collect();
    assert_eq!(of_1_2.len(), 2, "{t:?}");
    assert_eq!((of_1_2[0].from, of_1_2[0].to), (0.15, 0.3));
    assert_eq!((of_1_2[1].from, of_1_2[1].to), (0.6, 0.8));
    assert!(of_1_2[1].describe("adr").contains("merges"));
}
