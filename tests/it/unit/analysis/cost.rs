//! Unit tests of `analysis::cost` (`src/analysis/cost.rs`).

use isola::analysis::cost::*;
use isola::analysis::global::basin::BasinSpec;
use isola::model::Params;

#[test]
fn the_papers_basin_and_an_absurd_one() {
    let p = Params::baseline();
    let fig6 = basin(&BasinSpec::default(), p.omega()).unwrap();
    // 50451 cells × 6000 periods × 64 steps
    assert_eq!(fig6.steps, 50451.0 * 6000.0 * 64.0);
    assert!(
        fig6.factors[0].contains("50451 cells"),
        "{:?}",
        fig6.factors
    );
    let mut spec = BasinSpec::default();
    spec.steady.resolution.max_step = 1e-6;
    let e = basin(&spec, Params::paper(0.6, 0.01).unwrap().omega()).unwrap_err();
    assert_eq!(e.field, "steady.resolution.max_step");
}
