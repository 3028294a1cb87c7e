//! Unit tests of `analysis::global::capture` (`src/analysis/global/capture.rs`).

use isola::analysis::global::capture::*;
use isola::analysis::global::ellipse::Shape;
use isola::analysis::global::flow::Flow;
use isola::analysis::orbit::attractor::same_attractor;
use isola::analysis::orbit::steady_state::{SteadyState, SteadyStateSpec, steady_state};
use isola::model::Params;
use isola::solver::Resolution;
use nalgebra::{Matrix2, Vector2};

/// The Jordan-form shape shrinks |u|² by |μ|² for a focus and by max μ² for a node, and
/// its ellipse lies in the unit ball with V = 1 on its boundary.
#[test]
fn shape_follows_the_linear_map() {
    for (m, shrink) in [
        (Matrix2::new(0.6, -1.4, 0.35, 0.6), 0.36 + 0.49),
        (Matrix2::new(0.9, 0.3, 0.0, -0.5), 0.81),
    ] {
        let shape = Shape::of(&m).expect("stable");
        assert!((shape.shrink - shrink).abs() < 1e-12, "{m:?}");
        let region = CaptureRegion::new([0.0, 0.0], &shape, 1.0);
        for i in 0..12 {
            let (sin, cos) = (i as f64).sin_cos();
            let d = shape.t * Vector2::new(cos, sin);
            assert!((region.v(d.into()) - 1.0).abs() < 1e-12);
            assert!(d.norm() <= 1.0 + 1e-12);
            // |T⁻¹ M d|² = shrink · |T⁻¹ d|² for a focus, at most that for a node
            let md = m * d;
            assert!(region.v(md.into()) <= shrink + 1e-12, "{m:?}");
        }
    }
    assert!(Shape::of(&Matrix2::new(1.1, 0.0, 0.0, 0.5)).is_none());
}

/// The responses of `params` from `starts` (near their Poincaré points).
fn responses_from(p: &Params, starts: &[[f64; 2]]) -> Vec<SteadyState> {
    let spec = SteadyStateSpec::default();
    starts
        .iter()
        .map(|s| steady_state(p, s[0], s[1], &spec))
        .collect()
}

/// Every region of every response (capped as the early stop caps them: at most half-way
/// to another response's point, at most 0.1) is at least `least` of its cap in radius,
/// holds no point of another response, and starts spread over it, integrated to full
/// convergence on their own, all reach the region's response.
fn regions_hold_only_their_response(
    p: &Params,
    responses: &[SteadyState],
    verification: Verification,
    least: f64,
) {
    let spec = SteadyStateSpec::default();
    let rk = Flow::BuiltIn(Box::new(isola::solver::Rk4::new(p, &Resolution::default())));
    for r in responses {
        let caps: Vec<f64> = r
            .poincare
            .iter()
            .map(|p| {
                let others = responses.iter().filter(|o| *o != r);
                let nearest = others
                    .flat_map(|o| o.poincare.iter())
                    .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
                    .fold(f64::INFINITY, f64::min);
                (0.5 * nearest).min(0.1)
            })
            .collect();
        for (region, cap) in capture_regions(&rk, &r.poincare, &caps, verification)
            .iter()
            .zip(&caps)
        {
            assert!(region.radius() >= least * cap, "{region:?} under {cap}");
            for other in responses.iter().filter(|o| *o != r) {
                assert!(other.poincare.iter().all(|&q| !region.contains(q)));
            }
            // 24 starts on rings at 0.95, 0.6 and 0.3 of the radius, along the ellipse
            for i in 0..24 {
                let (sin, cos) = (i as f64 * 0.7).sin_cos();
                let fraction = [0.95, 0.6, 0.3][i % 3];
                let d = region.radius() * fraction;
                // step out along (cos, sin) until just inside the ellipse's boundary
                let mut x = [region.center[0] + d * cos, region.center[1] + d * sin];
                while !region.contains(x) {
                    x = [
                        0.5 * (x[0] + region.center[0]),
                        0.5 * (x[1] + region.center[1]),
                    ];
                }
                let end = steady_state(p, x[0], x[1], &spec);
                assert!(same_attractor(&end, r, 1e-6), "from {x:?}: {end:?}");
            }
        }
    }
}

/// Fig 6B's model (a 1:3 response born beside the 1:1 focus), both verifications: the 1:1,
/// 1:2 and 1:3 responses (from near their points, `isola basin --adr 1 --omega 3.6`).
#[test]
fn fig6b_regions_hold_only_their_response() {
    let p = Params::paper(1.0, 3.6).unwrap();
    let responses = responses_from(&p, &[[1.017, 0.001], [1.1208, 0.4402], [1.02594, 0.06897]]);
    let periods: Vec<usize> = responses.iter().map(|r| r.poincare.len()).collect();
    assert_eq!(periods, [1, 2, 3]);
    regions_hold_only_their_response(&p, &responses, Verification::OneReturn, 1.0 / 32.0);
    regions_hold_only_their_response(&p, &responses, Verification::Covered, 1.0 / 64.0);
}

/// Fig 6A's model, covered: the 1:1 and 1:2 regions reach at least 0.7 of their cap 0.1
/// (0.025 and 0.05 over one return) and hold only their response.
#[test]
fn fig6a_covered_regions_hold_only_their_response() {
    let p = Params::paper(0.6, 3.7).unwrap();
    let responses = responses_from(&p, &[[1.02, 0.0], [1.32, 0.0]]);
    let periods: Vec<usize> = responses.iter().map(|r| r.poincare.len()).collect();
    assert_eq!(periods, [1, 2]);
    regions_hold_only_their_response(&p, &responses, Verification::Covered, 0.7);
}

/// Fig 5's model at ω_e 3.55–3.65 with the 1:1 response alone known (as when no start has
/// reached the 1:3 yet): its covered region (cap 0.1) keeps out the 1:3 response, whose
/// points lie 0.04–0.07 from the 1:1's and whose thin basin a test of samples alone
/// misses, yet is larger than the one-return region.
#[test]
fn covered_region_keeps_out_a_nearby_1_3_response() {
    for (omega, one, three) in [
        (3.55, [1.016559, 0.001233], [1.030497, 0.074272]),
        (3.6, [1.016985, 0.001140], [1.025937, 0.068965]),
        (3.65, [1.017377, 0.001059], [1.024182, 0.062779]),
    ] {
        let p = Params::paper(1.0, omega).unwrap();
        let rk = Flow::BuiltIn(Box::new(isola::solver::Rk4::new(
            &p,
            &Resolution::default(),
        )));
        let found = responses_from(&p, &[one, three]);
        let [r_1, r_3] = [&found[0], &found[1]];
        assert_eq!((r_1.poincare.len(), r_3.poincare.len()), (1, 3));
        let covered = &capture_regions(&rk, &r_1.poincare, &[0.1], Verification::Covered)[0];
        let one_return = &capture_regions(&rk, &r_1.poincare, &[0.1], Verification::OneReturn)[0];
        assert!(
            covered.radius() > one_return.radius(),
            "ω {omega}: {covered:?}"
        );
        for &q in &r_3.poincare {
            assert!(!covered.contains(q), "ω {omega}: {q:?} in {covered:?}");
        }
    }
}

/// Fig 6A's 1:1 response, covered under the cap 0.1: the ladder's rung at 0.1/√2 passes and
/// the cap fails, and the ring half-way between them (0.1·2^(−1/4)) is tried and passes. Starts
/// in that added band (at 0.9 and 0.99 of the region's radius, in 24 directions) each reach the
/// 1:1 integrated to full convergence on their own.
#[test]
fn a_covered_region_grows_to_the_ring_between_two_rungs() {
    let p = Params::paper(0.6, 3.7).unwrap();
    let rk = Flow::BuiltIn(Box::new(isola::solver::Rk4::new(
        &p,
        &Resolution::default(),
    )));
    let one = &responses_from(&p, &[[1.02, 0.0]])[0];
    assert_eq!(one.poincare.len(), 1);
    let region = &capture_regions(&rk, &one.poincare, &[0.1], Verification::Covered)[0];
    let refined = 0.1 * 0.5f64.powf(0.25);
    assert!(
        (region.radius() - refined).abs() < 1e-12,
        "{} against {refined}",
        region.radius()
    );
    band_reaches_its_response(&p, region, one, 0.1 * 0.5f64.sqrt(), 24);
}

/// The responses of Fig 6A, 6B and Fig 4 at ω_e 4.25 over one return under the cap 0.1: each
/// region's radius is a rung of the ladder 0.1·2^(−n) or the ring half-way (in ratio) above
/// one; at least one of them is half-way; and starts in the band a half-way ring adds (at 0.9
/// and 0.99 of the radius, in 16 directions) reach the region's response integrated to full
/// convergence on their own.
#[test]
fn a_one_return_region_grows_to_the_ring_between_two_rungs() {
    let mut half_way = 0;
    for (adr, omega, starts) in [
        (0.6, 3.7, vec![[1.02, 0.0], [1.32, 0.0]]),
        (1.0, 3.6, vec![[1.017, 0.001], [1.1208, 0.4402]]),
        (0.6, 4.25, vec![[1.02, 0.0], [1.0400473, 0.1608259]]),
    ] {
        let p = Params::paper(adr, omega).unwrap();
        let rk = Flow::BuiltIn(Box::new(isola::solver::Rk4::new(
            &p,
            &Resolution::default(),
        )));
        for r in responses_from(&p, &starts) {
            let caps = vec![0.1; r.poincare.len()];
            for region in capture_regions(&rk, &r.poincare, &caps, Verification::OneReturn) {
                let rung = (0.1 / region.radius()).log2();
                let twice = 2.0 * rung;
                assert!((twice - twice.round()).abs() < 1e-9, "{region:?}");
                if twice.round() as i64 % 2 == 0 {
                    continue;
                }
                half_way += 1;
                let inner = region.radius() * 0.5f64.sqrt();
                band_reaches_its_response(&p, &region, &r, inner, 16);
            }
        }
    }
    assert!(half_way > 0, "no region grew half a rung");
}

/// Starts at 0.9 and 0.99 of `region`'s radius (in its own metric) in `directions`
/// directions, all beyond `inner` (in the band a half-way ring adds), each reach `response`
/// integrated to full convergence on their own.
fn band_reaches_its_response(
    p: &Params,
    region: &CaptureRegion,
    response: &SteadyState,
    inner: f64,
    directions: usize,
) {
    let spec = SteadyStateSpec::default();
    let center = region.center;
    for i in 0..directions {
        let turn = i as f64 * std::f64::consts::TAU / directions as f64;
        let (sin, cos) = turn.sin_cos();
        let d = [center[0] + 0.01 * cos, center[1] + 0.01 * sin];
        // V grows as the square of the distance along a direction from the centre
        let unit = 0.01 / region.v(d).sqrt();
        for fraction in [0.9, 0.99] {
            let s = fraction * region.radius() * unit;
            let x = [center[0] + s * cos, center[1] + s * sin];
            assert!(region.contains(x));
            assert!(region.v(x).sqrt() > inner, "{x:?} in the band");
            let end = steady_state(p, x[0], x[1], &spec);
            assert!(same_attractor(&end, response, 1e-6), "from {x:?}: {end:?}");
        }
    }
}
