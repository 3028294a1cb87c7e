//! CSV writers for the commands' results: tidy, one header row naming units.

use std::path::{Path, PathBuf};

use isola::analysis::SteadyState;
use isola::analysis::basin::Basin;
use isola::analysis::frequency_response::FrequencyResponse;
use isola::model::Device;
use isola::model::Params;

/// Writes `path` atomically: to a temporary file beside it, then renamed.
pub fn write_atomic(
    path: &Path,
    fill: impl FnOnce(&mut csv::Writer<std::fs::File>) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let tmp = path.with_extension("csv.tmp");
    let file = std::fs::File::create(&tmp)?;
    let mut w = csv::Writer::from_writer(file);
    fill(&mut w)?;
    let file = w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))?;
    file.sync_all()?;
    std::fs::rename(&tmp, path)?;
    Ok(())
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
    let opt = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:.9}"));
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

/// One row per cell (`dx_stretch, v_per_tau, attractor`) and, beside it, the attractor table.
pub fn basin_csv(b: &Basin, params: &Params, path: &Path) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        w.write_record(["dx_stretch", "v_per_tau", "attractor", "ratio"])?;
        let nv = b.v.len();
        for (c, &label) in b.labels.iter().enumerate() {
            let r = &b.table.attractors[label].response;
            w.write_record([
                format!("{:.6}", b.dx[c / nv]),
                format!("{:.6}", b.v[c % nv]),
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
                params.omega().to_string(),
                a.count.to_string(),
                format!("{:.6}", b.fraction(a.id)),
            ];
            row.extend(steady_fields(&a.response));
            let join = |i: usize| {
                a.response
                    .poincare
                    .iter()
                    .map(|p| format!("{:.9}", p[i]))
                    .collect::<Vec<_>>()
                    .join(";")
            };
            row.extend([join(0), join(1)]);
            w.write_record(&row)?;
        }
        Ok(())
    })
}

/// One row per response per ω_e.
pub fn response_csv(fr: &FrequencyResponse, path: &Path) -> anyhow::Result<()> {
    let dev = Device::silicone();
    write_atomic(path, |w| {
        let mut header = vec![
            "omega",
            "frequency_hz",
            "branch",
            "hidden",
            "seeded",
            "share",
        ];
        header.extend(STEADY_COLUMNS);
        header.extend(["poincare_lambda", "poincare_v"]);
        w.write_record(&header)?;
        for r in &fr.responses {
            let mut row = vec![
                format!("{:.6}", r.omega),
                format!("{:.4}", dev.hz(r.omega)),
                r.branch.map_or(String::new(), |b| b.to_string()),
                r.hidden.map_or(String::new(), |h| h.to_string()),
                r.seeded.to_string(),
                format!("{:.6}", r.share),
            ];
            row.extend(steady_fields(&r.steady));
            let join = |i: usize| {
                r.steady
                    .poincare
                    .iter()
                    .map(|p| format!("{:.9}", p[i]))
                    .collect::<Vec<_>>()
                    .join(";")
            };
            row.extend([join(0), join(1)]);
            w.write_record(&row)?;
        }
        Ok(())
    })
}
