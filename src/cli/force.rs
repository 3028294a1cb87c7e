//! `isola force`: static force curves f_II − f_I against Δλ (Fig 2).

use std::path::PathBuf;

use clap::Args;
use isola::analysis::orbit::force_curve::{ForceCurveSpec, force_curves};

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

pub fn run(args: &ForceArgs) -> anyhow::Result<()> {
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
    for c in &curves {
        let (lo, hi) = c
            .points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p[1]), hi.max(p[1]))
            });
        println!(
            "λ_p {:<5} φ_I {:<4}  {} points, force from {lo:.4} to {hi:.4}",
            c.lambda_p,
            c.phi_i,
            c.points.len()
        );
    }
    if let Some(path) = &args.csv {
        isola::session::export::force_csv(&curves, path)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
