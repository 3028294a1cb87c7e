//! `isola continue`: the branch through the response reached from one initial state,
//! continued both ways with its Floquet stability and located bifurcations.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use isola::analysis::continuation::{
    ContinuationParameter, ContinuationSpec, ContinuedBranch, continue_branch,
};
use isola::analysis::{Progress, SteadyStateSpec, steady_state};

use super::model_args::ModelArgs;
use super::parse;

#[derive(Debug, Args)]
pub struct ContinueArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// The initial state of the trajectory that finds the seed.
    #[command(flatten)]
    start: super::start_ranges::Start,
    /// The parameter to continue in: omega, adr, e_a, c_tilde, lambda_p or j.
    #[arg(long, default_value = "omega", value_parser = |s: &str| ContinuationParameter::parse(s).ok_or_else(|| format!("'{s}': one of omega, adr, e_a, c_tilde, lambda_p, j")))]
    vary: ContinuationParameter,
    /// Range MIN:MAX of that parameter.
    #[arg(long, default_value = "0.2:6.0", value_parser = parse::interval)]
    range: (f64, f64),
    /// Largest arclength step.
    #[arg(long = "step-max", default_value_t = ContinuationSpec::default().step_max)]
    step_max: f64,
    /// Write one row per branch point and per bifurcation to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

pub fn run(args: &ContinueArgs) -> anyhow::Result<()> {
    let params = args.model.params()?;
    let started = Instant::now();
    let seed = steady_state(
        &params,
        params.lambda_p() + args.start.x0,
        args.start.v0,
        &SteadyStateSpec::default(),
    );
    let k = seed.period.ok_or_else(|| {
        anyhow::anyhow!(
            "the trajectory from Δλ {}, v {} settles to a {} response: nothing to continue",
            args.start.x0,
            args.start.v0,
            seed.class.as_str()
        )
    })?;
    let spec = ContinuationSpec {
        parameter: args.vary,
        min: args.range.0,
        max: args.range.1,
        step_max: args.step_max,
        step: ContinuationSpec::default().step.min(args.step_max),
        ..ContinuationSpec::default()
    };
    let branch = continue_branch(&params, k, seed.poincare[0], &spec, &Progress::new(0))?;
    print_summary(&branch);
    println!(
        "{} points in {:.2} s",
        branch.points.len(),
        started.elapsed().as_secs_f64()
    );
    if let Some(path) = &args.csv {
        branch_csv(&branch, path)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The shape of a branch, its arcs and its bifurcations, as lines of text.
pub fn print_summary(b: &ContinuedBranch) {
    let name = b.parameter.name();
    let (lo, hi) = b.parameter_range();
    println!(
        "period-{} branch, {name} {lo:.6}–{hi:.6}, ends: {:?} / {:?}{}",
        b.period,
        b.ends[0],
        b.ends[1],
        if b.closed() { " (closed)" } else { "" }
    );
    for (i, j, stable) in b.arcs() {
        let (p, q) = (&b.points[i], &b.points[j]);
        println!(
            "  {} arc: {name} {:.4} → {:.4}, amplitude {:.4} → {:.4}",
            if stable { "stable  " } else { "unstable" },
            p.parameter,
            q.parameter,
            p.amplitude,
            q.amplitude
        );
    }
    for f in &b.bifurcations {
        let mu = f.multipliers.0[0];
        println!(
            "  {:<22} {name} = {:.9} (±{:.0e}), ω {:.6}, amplitude {:.6}, μ₁ = {:.6}{:+.6}i",
            f.kind.as_str(),
            f.parameter,
            f.precision.max(f64::EPSILON),
            f.omega,
            f.amplitude,
            mu.re,
            mu.im
        );
    }
}

/// One row per point (kind `point`) and per bifurcation (its kind), units in the header.
pub fn branch_csv(b: &ContinuedBranch, path: &Path) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record([
        "kind",
        b.parameter.name(),
        "omega_e",
        "lambda_i_0",
        "v_0",
        "amplitude",
        "stable",
        "mu1_re",
        "mu1_im",
        "mu2_re",
        "mu2_im",
    ])?;
    let row = |kind: &str,
               par: f64,
               w_e: f64,
               x: [f64; 2],
               amp: f64,
               stable: Option<bool>,
               m: &isola::analysis::floquet::Multipliers| {
        let mut r = vec![
            kind.to_string(),
            par.to_string(),
            w_e.to_string(),
            x[0].to_string(),
            x[1].to_string(),
            amp.to_string(),
            stable.map(|s| s.to_string()).unwrap_or_default(),
        ];
        for mu in m.0 {
            r.push(mu.re.to_string());
            r.push(mu.im.to_string());
        }
        r
    };
    for p in &b.points {
        w.write_record(row(
            "point",
            p.parameter,
            p.omega,
            p.x,
            p.amplitude,
            Some(p.stable),
            &p.multipliers,
        ))?;
    }
    for f in &b.bifurcations {
        w.write_record(row(
            f.kind.as_str(),
            f.parameter,
            f.omega,
            f.x,
            f.amplitude,
            None,
            &f.multipliers,
        ))?;
    }
    w.flush()?;
    Ok(())
}
