//! Tidy CSV for every result (one header row naming units), written atomically.

use std::path::{Path, PathBuf};

use crate::analysis::SteadyState;
use crate::analysis::global::basin::Basin;
use crate::analysis::global::frequency_response::FrequencyResponse;
use crate::model::Device;

/// Writes a CSV file whole (see [`super::output`]: a regular file is replaced atomically, a
/// FIFO or device written through): the rows are built in memory, so a failure while filling
/// leaves the old file as it was.
pub fn write_atomic(
    path: &Path,
    fill: impl FnOnce(&mut csv::Writer<&mut Vec<u8>>) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let bytes = csv_bytes(fill)?;
    super::output::write_output(path, &bytes, &super::output::Protected::none())?;
    Ok(())
}

/// The bytes of a CSV file filled by `fill`.
pub fn csv_bytes(
    fill: impl FnOnce(&mut csv::Writer<&mut Vec<u8>>) -> anyhow::Result<()>,
) -> anyhow::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    {
        let mut w = csv::Writer::from_writer(&mut bytes);
        fill(&mut w)?;
        w.flush()?;
    }
    Ok(bytes)
}

/// A number as the shortest text that reads back to exactly the same f64 (`0.1`, `1e-12`,
/// `3.7`): nothing a result computed is lost in its CSV.
pub fn num(x: f64) -> String {
    if x.is_finite() {
        ryu::Buffer::new().format_finite(x).to_string()
    } else {
        x.to_string()
    }
}

/// The columns describing one steady state.
pub const STEADY_COLUMNS: [&str; 7] = [
    "class",
    "period_forcing_periods",
    "ratio",
    "response_type",
    "amplitude_stretch",
    "lambda_min",
    "lambda_max",
];

pub fn steady_fields(s: &SteadyState) -> [String; 7] {
    let opt = |x: Option<f64>| x.map_or(String::new(), num);
    [
        s.class.as_str().into(),
        s.period.map_or(String::new(), |k| k.to_string()),
        s.ratio.map_or(String::new(), |r| r.to_string()),
        s.response_type(),
        opt(s.amplitude),
        opt(s.lambda_min),
        opt(s.lambda_max),
    ]
}

/// The stroboscopic points as two columns, λ_I values and v values, each `;`-separated.
fn poincare_fields(s: &SteadyState) -> [String; 2] {
    [0, 1].map(|i| {
        s.poincare
            .iter()
            .map(|p| num(p[i]))
            .collect::<Vec<_>>()
            .join(";")
    })
}

/// One row per cell (`dx_stretch, v_per_tau, attractor`) and, beside it, the attractor table.
pub fn basin_csv(b: &Basin, omega: f64, path: &Path) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        w.write_record(["dx_stretch", "v_per_tau", "attractor", "ratio"])?;
        let nv = b.v.len();
        for (c, &label) in b.labels.iter().enumerate() {
            let r = &b.table.attractors[label].response;
            w.write_record([
                num(b.dx[c / nv]),
                num(b.v[c % nv]),
                label.to_string(),
                r.ratio.map_or(r.class.as_str().into(), |r| r.to_string()),
            ])?;
        }
        Ok(())
    })?;
    let table: PathBuf = path.with_extension("attractors.csv");
    write_atomic(&table, |w| {
        let mut header = vec!["attractor", "omega", "cells", "fraction"];
        header.extend(STEADY_COLUMNS);
        header.extend(["poincare_lambda", "poincare_v"]);
        w.write_record(&header)?;
        for a in &b.table.attractors {
            let mut row = vec![
                a.id.to_string(),
                omega.to_string(),
                a.count.to_string(),
                num(b.fraction(a.id)),
            ];
            row.extend(steady_fields(&a.response));
            row.extend(poincare_fields(&a.response));
            w.write_record(&row)?;
        }
        Ok(())
    })
}

/// The columns of one response at one ω_e.
const RESPONSE_COLUMNS: [&str; 6] = [
    "omega",
    "frequency_hz",
    "branch",
    "hidden",
    "seeded",
    "share",
];

fn response_fields(
    r: &crate::analysis::global::frequency_response::Response,
    device: &Device,
) -> Vec<String> {
    let mut row = vec![
        num(r.omega),
        num(device.hz(r.omega)),
        r.branch.map_or(String::new(), |b| b.to_string()),
        r.hidden.map_or(String::new(), |h| h.to_string()),
        r.seeded.to_string(),
        num(r.share),
    ];
    row.extend(steady_fields(&r.steady));
    row.extend(poincare_fields(&r.steady));
    row
}

/// One row per response per ω_e (`frequency_hz` for `device`).
pub fn response_csv(fr: &FrequencyResponse, device: &Device, path: &Path) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        let mut header = RESPONSE_COLUMNS.to_vec();
        header.extend(STEADY_COLUMNS);
        header.extend(["poincare_lambda", "poincare_v"]);
        w.write_record(&header)?;
        for r in &fr.responses {
            w.write_record(response_fields(r, device))?;
        }
        Ok(())
    })
}

/// Where a family's per-response file lives beside its branch table: `A.responses.csv`.
pub fn family_responses_path(family_csv: &Path) -> PathBuf {
    family_csv.with_extension("responses.csv")
}

/// One row per response per ω_e per member of a family, the parameter's value first.
pub fn family_responses_csv(
    parameter: &str,
    members: &[crate::analysis::global::family::FamilyMember],
    device: &Device,
    path: &Path,
) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        let mut header = vec![parameter];
        header.extend(RESPONSE_COLUMNS);
        header.extend(STEADY_COLUMNS);
        header.extend(["poincare_lambda", "poincare_v"]);
        w.write_record(&header)?;
        for m in members {
            for r in &m.response.responses {
                let mut row = vec![m.value.to_string()];
                row.extend(response_fields(r, device));
                w.write_record(&row)?;
            }
        }
        Ok(())
    })
}

/// One row per point of each force curve.
pub fn force_csv(
    curves: &[crate::analysis::orbit::force_curve::ForceCurve],
    path: &Path,
) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        w.write_record(["lambda_p", "phi_i", "dx_stretch", "force_nondim"])?;
        for c in curves {
            for p in &c.points {
                w.write_record([
                    c.lambda_p.to_string(),
                    c.phi_i.to_string(),
                    num(p[0]),
                    num(p[1]),
                ])?;
            }
        }
        Ok(())
    })
}

/// One row per sample of a time history.
pub fn history_csv(
    h: &crate::analysis::orbit::time_history::TimeHistory,
    device: &Device,
    path: &Path,
) -> anyhow::Result<()> {
    let bytes = history_bytes(h, device)?;
    super::output::write_output(path, &bytes, &super::output::Protected::none())?;
    Ok(())
}

/// [`history_csv`]'s file, in memory.
pub fn history_bytes(
    h: &crate::analysis::orbit::time_history::TimeHistory,
    device: &Device,
) -> anyhow::Result<Vec<u8>> {
    csv_bytes(|w| {
        w.write_record([
            "tau",
            "time_s",
            "lambda_stretch",
            "v_per_tau",
            "phi_i",
            "steady",
        ])?;
        for s in &h.samples {
            w.write_record([
                num(s.tau),
                num(device.seconds(s.tau)),
                num(s.lambda),
                num(s.v),
                num(s.phi_i),
                s.steady.to_string(),
            ])?;
        }
        Ok(())
    })
}

/// One row per sample of a written model's time history: τ, its two grid states first, the
/// other states, the amplitude's output, and whether the sample is on the steady response.
pub fn state_history_bytes(
    h: &crate::analysis::global::oscillator::history::StateHistory,
    grid: [usize; 2],
) -> anyhow::Result<Vec<u8>> {
    let mut order: Vec<usize> = vec![grid[0]];
    if grid[1] != grid[0] {
        order.push(grid[1]);
    }
    order.extend((0..h.states.len()).filter(|i| !grid.contains(i)));
    csv_bytes(|w| {
        let mut header = vec!["tau"];
        header.extend(order.iter().map(|&i| h.states[i].as_str()));
        header.extend(["amplitude_output", "steady"]);
        w.write_record(&header)?;
        for s in &h.samples {
            let mut row = vec![num(s.tau)];
            row.extend(order.iter().map(|&i| num(s.state[i])));
            row.extend([num(s.output), s.steady.to_string()]);
            w.write_record(&row)?;
        }
        Ok(())
    })
}

/// One row per sample of a chirp sweep, with the envelope (max − min of λ_I over the sample's
/// window) beside it.
pub fn chirp_csv(
    s: &crate::analysis::orbit::chirp_sweep::ChirpSweep,
    device: &Device,
    path: &Path,
) -> anyhow::Result<()> {
    let per_window = s.window_samples.max(1);
    write_atomic(path, |w| {
        w.write_record([
            "tau",
            "omega",
            "frequency_hz",
            "lambda_stretch",
            "envelope_amplitude_stretch",
        ])?;
        for (j, (&lambda, &omega)) in s.lambda.iter().zip(&s.omega).enumerate() {
            let envelope = s.envelope.get(j / per_window).map_or(0.0, |e| e[2]);
            w.write_record([
                num(j as f64 * s.dt),
                num(omega),
                num(device.hz(omega)),
                num(lambda),
                num(envelope),
            ])?;
        }
        Ok(())
    })
}

/// One row per step of a stepped sweep.
pub fn stepped_csv(
    steps: &[crate::analysis::global::stepped_sweep::SweepStep],
    device: &Device,
    path: &Path,
) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        let mut header = vec!["step", "omega", "frequency_hz", "restarted"];
        header.extend(STEADY_COLUMNS);
        w.write_record(&header)?;
        for (i, s) in steps.iter().enumerate() {
            let mut row = vec![
                i.to_string(),
                num(s.omega),
                num(device.hz(s.omega)),
                s.restarted.to_string(),
            ];
            row.extend(steady_fields(&s.steady));
            w.write_record(&row)?;
        }
        Ok(())
    })
}

/// One row per branch per member of a family.
pub fn family_csv(
    parameter: &str,
    members: &[crate::analysis::global::family::FamilyMember],
    path: &Path,
) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        w.write_record([
            parameter,
            "branch",
            "period_forcing_periods",
            "ratio",
            "response_type",
            "omega_min",
            "omega_max",
            "peak_amplitude_stretch",
            "peak_omega",
            "points",
            "hidden",
            "partly_hidden",
        ])?;
        for m in members {
            for b in &m.response.branches {
                w.write_record([
                    m.value.to_string(),
                    b.id.to_string(),
                    b.period.to_string(),
                    b.ratio.to_string(),
                    b.response_type.clone(),
                    num(b.omega_min),
                    num(b.omega_max),
                    num(b.peak_amplitude),
                    num(b.peak_omega),
                    b.points.to_string(),
                    b.hidden.to_string(),
                    b.partly_hidden.to_string(),
                ])?;
            }
        }
        Ok(())
    })
}

/// Where a hunt's continued branches live beside its frequency response: `A.branches.csv`.
pub fn branches_path(response_csv: &Path) -> PathBuf {
    response_csv.with_extension("branches.csv")
}

/// The columns of a continued-branch file (see [`continued_csv`]); the parameter column is
/// named after the continuation parameter.
const CONTINUED_COLUMNS: [&str; 13] = [
    "branch",
    "period",
    "verdict",
    "kind",
    "omega_e",
    "lambda_i_0",
    "v_0",
    "amplitude_stretch",
    "stable",
    "mu1_re",
    "mu1_im",
    "mu2_re",
    "mu2_im",
];

/// One row per point (kind `point`, in order along the branch) and per located bifurcation
/// (its kind) of each branch, numbered from 0. Columns: branch, period, verdict (isola,
/// attached, half-attached, open), kind, the continuation parameter, ω_e, the state at τ = 0,
/// amplitude, stability and both Floquet multipliers.
pub fn continued_csv(
    branches: &[&crate::analysis::continuation::branch::ContinuedBranch],
    path: &Path,
) -> anyhow::Result<()> {
    use crate::analysis::continuation::hunt::Verdict;
    use crate::analysis::orbit::floquet::Multipliers;
    let parameter = branches.first().map_or("omega", |b| b.parameter.name());
    write_atomic(path, |w| {
        let mut header = CONTINUED_COLUMNS[..4].to_vec();
        header.push(parameter);
        header.extend(&CONTINUED_COLUMNS[4..]);
        w.write_record(&header)?;
        for (id, b) in branches.iter().enumerate() {
            let verdict = Verdict::of(b).as_str();
            let row = |kind: &str,
                       par: f64,
                       omega: f64,
                       x: [f64; 2],
                       amp: f64,
                       stable: Option<bool>,
                       m: &Multipliers| {
                let mut r = vec![
                    id.to_string(),
                    b.period.to_string(),
                    verdict.to_string(),
                    kind.to_string(),
                    num(par),
                    num(omega),
                    num(x[0]),
                    num(x[1]),
                    num(amp),
                    stable.map(|s| s.to_string()).unwrap_or_default(),
                ];
                for mu in m.0 {
                    r.push(num(mu.re));
                    r.push(num(mu.im));
                }
                r
            };
            for p in &b.points {
                let r = row(
                    "point",
                    p.parameter,
                    p.omega,
                    p.x,
                    p.amplitude,
                    Some(p.stable),
                    &p.multipliers,
                );
                w.write_record(&r)?;
            }
            for f in &b.bifurcations {
                let r = row(
                    f.kind.as_str(),
                    f.parameter,
                    f.omega,
                    f.x,
                    f.amplitude,
                    None,
                    &f.multipliers,
                );
                w.write_record(&r)?;
            }
        }
        Ok(())
    })
}

/// One row per hunted branch per value of a hunt family: `PARAMETER, period, verdict,
/// hidden, omega_min, omega_max, peak_amplitude_stretch, peak_omega, folds,
/// period_doublings` (the located ω_e of each kind, `;`-separated).
pub fn hunt_family_csv(
    parameter: &str,
    members: &[crate::analysis::continuation::hunt_family::HuntMember],
    path: &Path,
) -> anyhow::Result<()> {
    use crate::analysis::continuation::branch::BifurcationKind;
    write_atomic(path, |w| {
        w.write_record([
            parameter,
            "period",
            "verdict",
            "hidden",
            "omega_min",
            "omega_max",
            "peak_amplitude_stretch",
            "peak_omega",
            "folds",
            "period_doublings",
        ])?;
        for m in members {
            for b in &m.branches {
                let located = |kinds: &[BifurcationKind]| {
                    b.branch
                        .bifurcations
                        .iter()
                        .filter(|f| kinds.contains(&f.kind))
                        .map(|f| num(f.omega))
                        .collect::<Vec<_>>()
                        .join(";")
                };
                w.write_record([
                    m.value.to_string(),
                    b.branch.period.to_string(),
                    b.verdict.as_str().to_string(),
                    b.hidden.to_string(),
                    num(b.omega_min),
                    num(b.omega_max),
                    num(b.peak_amplitude),
                    num(b.peak_omega),
                    located(&[BifurcationKind::Fold]),
                    located(&[
                        BifurcationKind::PeriodDoubling,
                        BifurcationKind::ParentPeriodDoubling,
                    ]),
                ])?;
            }
        }
        Ok(())
    })
}

/// One row per cell of a map: `Y, X, frequency_hz` (with x = ω_e, for `device`; empty
/// otherwise)`,
/// stable, largest_amplitude_stretch, largest_type, hidden, subharmonic, collision_share,
/// non_periodic_share`, the parameters named in the header.
pub fn map_csv(
    (x, parameter): (&str, &str),
    xs: &[f64],
    rows: &[crate::analysis::continuation::map::MapRow],
    device: &Device,
    path: &Path,
) -> anyhow::Result<()> {
    let is_omega = x == "omega";
    write_atomic(path, |w| {
        w.write_record([
            parameter,
            x,
            "frequency_hz",
            "stable",
            "largest_amplitude_stretch",
            "largest_type",
            "hidden",
            "subharmonic",
            "collision_share",
            "non_periodic_share",
        ])?;
        for row in rows {
            for (cell, at) in row.cells.iter().zip(xs) {
                w.write_record([
                    row.value.to_string(),
                    num(*at),
                    if is_omega {
                        num(device.hz(*at))
                    } else {
                        String::new()
                    },
                    cell.stable.to_string(),
                    cell.largest_amplitude.map_or(String::new(), num),
                    cell.largest_type.clone().unwrap_or_default(),
                    cell.hidden.to_string(),
                    cell.subharmonic.to_string(),
                    num(cell.collision_share),
                    num(cell.non_periodic_share),
                ])?;
            }
        }
        Ok(())
    })
}

/// Where a map's curves live beside its cells: `A.curves.csv`.
pub fn curves_path(map_csv: &Path) -> PathBuf {
    map_csv.with_extension("curves.csv")
}

/// One row per point of each two-parameter curve (`kind` `fold` or `period-doubling`,
/// `at` = `point`) and per located turning point (`at` = `minimum` or `maximum` of the
/// parameter named in `of`): `curve, kind, period, at, of, FIRST, SECOND, amplitude_stretch`.
pub fn curves_csv(
    curves: &[crate::analysis::continuation::bifurcation_curve::BifurcationCurve],
    path: &Path,
) -> anyhow::Result<()> {
    use crate::analysis::continuation::bifurcation_curve::Turning;
    let (first, second) = curves.first().map_or(("omega", "parameter"), |c| {
        (c.first.name(), c.second.name())
    });
    write_atomic(path, |w| {
        w.write_record([
            "curve",
            "kind",
            "period",
            "at",
            "of",
            first,
            second,
            "amplitude_stretch",
        ])?;
        for (id, c) in curves.iter().enumerate() {
            let kind = c.kind.as_str();
            for p in &c.points {
                w.write_record([
                    id.to_string(),
                    kind.into(),
                    c.period.to_string(),
                    "point".into(),
                    String::new(),
                    num(p.first),
                    num(p.second),
                    num(p.amplitude),
                ])?;
            }
            for e in &c.extrema {
                let of = match e.of {
                    Turning::First => first,
                    Turning::Second => second,
                };
                w.write_record([
                    id.to_string(),
                    kind.into(),
                    c.period.to_string(),
                    if e.minimum { "minimum" } else { "maximum" }.into(),
                    of.into(),
                    num(e.point.first),
                    num(e.point.second),
                    num(e.point.amplitude),
                ])?;
            }
        }
        Ok(())
    })
}
