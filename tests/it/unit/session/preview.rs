//! Unit tests of `session::preview` (`src/session/preview.rs`).

use isola::analysis::grid::Axis;
use isola::session::preview::*;

#[test]
fn a_thinned_axis_keeps_its_ends_and_every_kth_point_where_k_divides_its_steps() {
    let dx = thinned(&Axis::new(-0.8, 0.8, 201), 8);
    assert_eq!((dx.min, dx.max, dx.points), (-0.8, 0.8, 26));
    assert!((dx.step() - 8.0 * 0.008).abs() < 1e-15);
    // 250 steps: every 10th; 14: every 7th; 50: every 10th; 17 (prime, beyond twice 8):
    // about every 8th
    assert_eq!(thinned(&Axis::new(-1.0, 1.0, 251), 8).points, 26);
    assert_eq!(thinned(&Axis::new(-1.0, 1.0, 15), 8).points, 3);
    assert_eq!(thinned(&Axis::new(-1.0, 1.0, 51), 8).points, 6);
    assert_eq!(thinned(&Axis::new(-1.0, 1.0, 18), 8).points, 4);
    assert_eq!(thinned(&Axis::new(0.0, 1.0, 2), 8).points, 2);
    assert_eq!(thinned(&Axis::new(0.0, 1.0, 1), 8).points, 1);
    assert_eq!(thinned(&Axis::new(0.0, 1.0, 9), 1).points, 9);
    // every full-grid value maps to the nearest coarse point, ends to ends
    let full = Axis::new(-0.8, 0.8, 201);
    assert_eq!(nearest(&dx, full.at(0)), 0);
    assert_eq!(nearest(&dx, full.at(200)), 25);
    assert_eq!(nearest(&dx, full.at(8)), 1);
    assert_eq!(nearest(&dx, full.at(11)), 1);
    assert_eq!(nearest(&dx, full.at(13)), 2);
}

/// The paper's grids come within the budget: Fig 6A's basin 11 × 11 starts, Fig 4's
/// response 3 × 3 starts at 21 ω; a small grid is taken whole.
#[test]
fn the_papers_grids_fit_the_budget() {
    let s = stride_for(201 * 251, 2);
    let (dx, v) = (
        thinned(&Axis::new(-0.8, 0.8, 201), s),
        thinned(&Axis::new(-1.0, 1.0, 251), s),
    );
    assert_eq!((s, dx.points, v.points), (16, 11, 11));
    let omega = thinned(&Axis::new(0.2, 6.0, 117), stride_for(117 * 9, 1));
    assert_eq!(omega.points, 21);
    assert!(omega.points * 9 <= BUDGET);
    assert_eq!(stride_for(41 * 51, 2), 4);
    assert_eq!(stride_for(200, 2), 1);
}
