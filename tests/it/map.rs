//! Two-parameter maps (issue 6): each row is the frequency response at that value; the
//! curves drawn over the map turn where the hunt's independent bisection puts the merging.

use isola::analysis::Progress;
use isola::analysis::continuation::bifurcation_curve::Turning;
use isola::analysis::continuation::map::{MapSpec, map, summarise};
use isola::analysis::global::frequency_response::{FrequencyResponseSpec, frequency_response};
use isola::analysis::grid::Axis;
use isola::analysis::parameter::ContinuationParameter;
use isola::analysis::parameter::FamilyParameter;
use isola::model::Params;

#[test]
fn a_map_over_adr_and_omega_around_the_merging() {
    let p = Params::paper(0.6, 3.0).unwrap();
    let spec = MapSpec {
        hidden_branches: false,
        x: ContinuationParameter::Omega,
        parameter: FamilyParameter::Adr,
        values: Axis::new(0.55, 0.7, 4),
        response: FrequencyResponseSpec {
            omega: Axis::new(3.0, 6.0, 31),
            dx: Axis::new(-0.8, 0.8, 5),
            v: Axis::new(-1.0, 1.0, 5),
            ..FrequencyResponseSpec::default()
        },
        curves: true,
    };
    let progress = Progress::new(0);
    let (rows, found) = map(&p, &spec, &progress).unwrap();
    let curves = &found.curves;
    assert!(found.cut.is_empty(), "{:?}", found.cut);
    // the curves are work of unknown length: counted as steps, not as a gauge stuck at 100 %
    let (done, total) = progress.get();
    assert_eq!(done, total, "the rows' work is exactly what was announced");
    assert!(progress.open_steps() > 0 && progress.in_open_phase());
    assert_eq!(rows.len(), 4);
    // the ADR 0.6 row is the frequency response at ADR 0.6, cell for cell
    let at_06 = Params::paper(0.6, 3.0).unwrap();
    let fr = frequency_response(&at_06, &spec.response, &Progress::new(0)).unwrap();
    assert_eq!(rows[1], summarise(&at_06, 0.6, &fr, false));
    // at (ADR 0.6, ω 3.7): the 1:1 and the hidden 1:2 of Fig 4
    let cell = &rows[1].cells[7];
    assert!(
        cell.stable >= 2 && cell.hidden && cell.subharmonic,
        "{cell:?}"
    );
    assert_eq!(cell.largest_type.as_deref(), Some("1:2"));
    let a = cell.largest_amplitude.unwrap();
    assert!((a - 0.4156).abs() < 1e-3, "{a}");
    // a fold curve turns at the merging: `isola_merge` (`isola reproduce`, tests/it/reproduce.rs)
    // locates it at ADR 0.6452597 on the same kind of curve, and brackets it by bisection
    // to within 1e-4
    let turning: Vec<f64> = curves
        .iter()
        .filter(|c| c.period == 2)
        .flat_map(|c| c.extrema_of(Turning::Second).filter(|e| e.minimum))
        .map(|e| e.point.second)
        .collect();
    eprintln!("minima of ADR on the 1:2 fold curves: {turning:?}");
    assert!(
        turning.iter().any(|v| (v - 0.6452597).abs() < 1e-6),
        "{turning:?}"
    );
}

/// A map along c̃ (x) at ω 3.7 over ADR (y): its cell at (c̃ 0.04, ADR 0.6) finds the same
/// responses as the ω map's cell at (ω 3.7, ADR 0.6) — the same model reached by the other
/// parameter — and a bad pair of axes is refused by name.
#[test]
fn a_map_along_a_model_parameter() {
    let p = Params::paper(0.6, 3.7).unwrap();
    let grid = FrequencyResponseSpec {
        omega: Axis::new(0.03, 0.05, 3),
        dx: Axis::new(-0.8, 0.8, 5),
        v: Axis::new(-1.0, 1.0, 5),
        ..FrequencyResponseSpec::default()
    };
    let spec = MapSpec {
        hidden_branches: false,
        x: ContinuationParameter::Model(FamilyParameter::CTilde),
        parameter: FamilyParameter::Adr,
        values: Axis::new(0.6, 0.6, 1),
        response: grid.clone(),
        curves: false,
    };
    let (rows, _) = map(&p, &spec, &Progress::new(0)).unwrap();
    let along_c = &rows[0].cells[1];
    let in_omega = FrequencyResponseSpec {
        omega: Axis::new(3.7, 3.7, 1),
        ..grid
    };
    let fr = frequency_response(&p, &in_omega, &Progress::new(0)).unwrap();
    let at = &summarise(&p, 0.6, &fr, false).cells[0];
    assert_eq!(along_c.stable, at.stable);
    assert_eq!(along_c.largest_type, at.largest_type);
    let (a, b) = (
        along_c.largest_amplitude.unwrap(),
        at.largest_amplitude.unwrap(),
    );
    assert!((a - b).abs() < 1e-7, "{a} vs {b}");
    let same_axes = MapSpec {
        hidden_branches: false,
        x: ContinuationParameter::Model(FamilyParameter::Adr),
        ..spec
    };
    let err = map(&p, &same_axes, &Progress::new(0))
        .unwrap_err()
        .to_string();
    assert!(err.contains("x"), "{err}");
}

/// A map's gauge runs once from 0 to 100 % over its rows: the rows' whole work is announced
/// before the first trajectory, and it is exactly the work done (it used to restart every row,
/// reading 92–100 % throughout).
#[test]
fn a_map_announces_all_its_rows_at_once() {
    let p = Params::baseline();
    let spec = MapSpec {
        hidden_branches: false,
        x: ContinuationParameter::Omega,
        parameter: FamilyParameter::Adr,
        values: Axis::new(0.4, 0.8, 5),
        response: FrequencyResponseSpec {
            omega: Axis::new(3.0, 4.0, 6),
            dx: Axis::new(-0.6, 0.6, 3),
            v: Axis::new(-0.8, 0.8, 3),
            ..FrequencyResponseSpec::default()
        },
        curves: false,
    };
    let total = 5 * spec.response.work();
    let progress = std::sync::Arc::new(Progress::new(0));
    let watched = progress.clone();
    let run = std::thread::spawn(move || map(&p, &spec, &watched).map(|_| ()));
    let mut seen = Vec::new();
    while !run.is_finished() {
        let (done, announced) = progress.get();
        if done > 0 {
            seen.push((done, announced));
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    run.join().unwrap().unwrap();
    assert!(
        seen.iter().all(|&(_, announced)| announced == total),
        "{seen:?}"
    );
    assert!(seen.windows(2).all(|w| w[0].0 <= w[1].0), "monotone");
    assert_eq!(progress.get(), (total, total));
}

/// A map whose ω window (3–4.5) cuts the ADR 0.6 isola (ω 3.59–5.44) says so: the branch
/// leaves the window at ω 4.5, where its folds beyond are not drawn.
#[test]
fn a_window_that_cuts_the_isola_says_so() {
    let p = Params::paper(0.6, 3.7).unwrap();
    let spec = MapSpec {
        hidden_branches: false,
        x: ContinuationParameter::Omega,
        parameter: FamilyParameter::Adr,
        values: Axis::new(0.6, 0.6, 1),
        response: FrequencyResponseSpec {
            omega: Axis::new(3.0, 4.5, 16),
            dx: Axis::new(-0.8, 0.8, 5),
            v: Axis::new(-1.0, 1.0, 5),
            ..FrequencyResponseSpec::default()
        },
        curves: true,
    };
    let (_, found) = map(&p, &spec, &Progress::new(0)).unwrap();
    let cut: Vec<_> = found.cut.iter().filter(|c| c.period == 2).collect();
    assert_eq!(cut.len(), 1, "{:?}", found.cut);
    assert_eq!(cut[0].edges, [4.5], "{:?}", cut[0]);
    let text = cut[0].describe("omega", "adr");
    assert!(
        text.starts_with("the 1:2 branch at adr = 0.6 leaves the omega window at omega = 4.5"),
        "{text}"
    );
}

/// The same map as a session: `isola run` prints the note under the map's line (and `--json`
/// carries it in the analysis' `notes`) when it computes the result.
#[test]
fn a_session_map_whose_window_cuts_the_isola_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("s.toml");
    std::fs::write(
        &session,
        "schema = 1\n[model]\nadr = 0.6\n\n[[analysis]]\nname = \"map\"\nkind = \"map\"\n\
         [analysis.settings]\nparameter = \"adr\"\nvalues = { min = 0.6, max = 0.6, points = 1 }\n\
         [analysis.settings.response]\nomega = { min = 3.0, max = 4.5, points = 16 }\n\
         dx = { min = -0.8, max = 0.8, points = 5 }\nv = { min = -1.0, max = 1.0, points = 5 }\n",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_isola"))
        .arg("run")
        .arg(&session)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("  note: the 1:2 branch at adr = 0.6 leaves the omega window at omega = 4.5"),
        "{text}"
    );
}
