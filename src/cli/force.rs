//! `isola force`: static force curves f_II − f_I against Δλ (Fig 2).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::orbit::force_curve::{ForceCurveSpec, force_curves};
use serde::Serialize;

use super::output::{Done, Output, Summary};
use super::parse;

#[derive(Debug, Args)]
pub struct ForceArgs {
    /// Pre-stretches, comma-separated (one curve each).
    #[arg(
        long = "lambda-p",
        value_delimiter = ',',
        default_value = "1.0,1.02,1.05"
    )]
    lambda_p: Vec<f64>,
    /// Static voltages φ_I on membrane I, comma-separated.
    #[arg(long = "phi", value_delimiter = ',', default_value = "0")]
    phi: Vec<f64>,
    /// Gent constant J.
    #[arg(long, default_value_t = 16.0, value_parser = super::parse::finite)]
    j: f64,
    /// Range of Δλ.
    #[arg(long = "dx-range", default_value = "-0.8:0.8", value_parser = parse::interval, allow_hyphen_values = true)]
    dx_range: (f64, f64),
    /// Points per curve.
    #[arg(long, default_value_t = 401)]
    points: usize,
    /// Write one row per point to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// The force curves: per curve its range of force over the Δλ range.
#[derive(Serialize)]
struct ForceSummary {
    j: f64,
    dx_min: f64,
    dx_max: f64,
    curves: Vec<CurveSummary>,
    #[serde(flatten)]
    done: Done,
}

/// One curve: λ_p, φ_I and the smallest and largest f_II − f_I along it.
#[derive(Serialize)]
struct CurveSummary {
    lambda_p: f64,
    phi_i: f64,
    points: usize,
    force_min: f64,
    force_max: f64,
}

pub fn run(args: &ForceArgs, out: Output) -> anyhow::Result<()> {
    let started = Instant::now();
    super::check_outputs([args.csv.as_deref()])?;
    let spec = ForceCurveSpec {
        lambda_p: args.lambda_p.clone(),
        phi_i: args.phi.clone(),
        j: args.j,
        dx_min: args.dx_range.0,
        dx_max: args.dx_range.1,
        points: args.points,
    };
    let curves = force_curves(&spec)?;
    let mut done = Done::default();
    if let Some(path) = &args.csv {
        isola::session::export::force_csv(&curves, path)?;
        done.wrote.push(path.clone());
    }
    done.elapsed_seconds = started.elapsed().as_secs_f64();
    let curves = curves
        .iter()
        .map(|c| {
            let (force_min, force_max) = c
                .points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p[1]), hi.max(p[1]))
                });
            CurveSummary {
                lambda_p: c.lambda_p,
                phi_i: c.phi_i,
                points: c.points.len(),
                force_min,
                force_max,
            }
        })
        .collect();
    out.report(&ForceSummary {
        j: spec.j,
        dx_min: spec.dx_min,
        dx_max: spec.dx_max,
        curves,
        done,
    })
}

impl Summary for ForceSummary {
    fn print_text(&self) {
        for c in &self.curves {
            say!(
                "λ_p {:<5} φ_I {:<4}  {} points, force from {:.4} to {:.4}",
                c.lambda_p,
                c.phi_i,
                c.points,
                c.force_min,
                c.force_max
            );
        }
        self.done.print_wrote();
    }
}
