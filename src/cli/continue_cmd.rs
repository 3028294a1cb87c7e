//! `isola continue`: the branch through the response reached from one initial state,
//! continued both ways with its Floquet stability and located bifurcations.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::continuation::branch::{
    BifurcationKind, ContinuationSpec, ContinuedBranch, switch_at_period_doubling,
};
use isola::analysis::continuation::branch_from_state::{BranchFromState, branch_from_state};
use isola::analysis::parameter::ContinuationParameter;

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
    #[arg(long = "step-max", default_value_t = ContinuationSpec::default().step_max, value_parser = super::parse::finite)]
    step_max: f64,
    /// At each period doubling, switch to the branch of twice the period born there and
    /// continue it too.
    #[arg(long)]
    switch: bool,
    /// Write one row per branch point and per bifurcation to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

pub fn run(args: &ContinueArgs) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref()])?;
    let params = args.model.params()?;
    let started = Instant::now();
    let spec = BranchFromState {
        dx0: args.start.x0,
        v0: args.start.v0,
        continuation: ContinuationSpec {
            parameter: args.vary,
            min: args.range.0,
            max: args.range.1,
            step_max: args.step_max,
            step: ContinuationSpec::default().step.min(args.step_max),
            ..ContinuationSpec::default()
        },
        ..BranchFromState::default()
    };
    let progress = Progress::new(0);
    let branch = branch_from_state(&params, &spec, &progress)?;
    print_summary(&branch);
    let mut born = Vec::new();
    if args.switch {
        for pd in branch.of_kind(BifurcationKind::PeriodDoubling) {
            let known = born.iter().any(|b: &ContinuedBranch| {
                b.of_kind(BifurcationKind::ParentPeriodDoubling)
                    .any(|end| (end.parameter - pd.parameter).abs() < 1e-6)
            });
            if known {
                println!(
                    "the branch born at {} = {:.9} is the one above (it ends there)",
                    args.vary.name(),
                    pd.parameter
                );
                continue;
            }
            println!(
                "switching at the period doubling at {} = {:.9}:",
                args.vary.name(),
                pd.parameter
            );
            match switch_at_period_doubling(&params, &branch, pd, &spec.continuation, &progress) {
                Ok(b) => {
                    print_summary(&b);
                    born.push(b);
                }
                Err(e) => println!("  no branch: {e}"),
            }
        }
    }
    let points: usize = std::iter::once(&branch)
        .chain(&born)
        .map(|b| b.points.len())
        .sum();
    println!(
        "{points} points in {:.2} s",
        started.elapsed().as_secs_f64()
    );
    if let Some(path) = &args.csv {
        let all: Vec<&ContinuedBranch> = std::iter::once(&branch).chain(&born).collect();
        isola::session::export::continued_csv(
            &all,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The shape of a branch, its arcs and its bifurcations, as lines of text.
pub fn print_summary(b: &ContinuedBranch) {
    let name = b.parameter.name();
    let (lo, hi) = b.parameter_range();
    println!(
        "period-{} branch, {name} {lo:.6}–{hi:.6}, ends: {} / {}{}",
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
