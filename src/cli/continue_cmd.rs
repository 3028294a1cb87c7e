//! `isola continue`: the branch through the response reached from one initial state,
//! continued both ways with its Floquet stability and located bifurcations.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::continuation::branch::{
    ArcEnds, Bifurcation, BifurcationKind, BranchEnd, ContinuationSpec, ContinuedBranch,
    switch_at_period_doubling,
};
use isola::analysis::continuation::branch_from_state::{BranchFromState, branch_from_state};
use isola::analysis::parameter::ContinuationParameter;
use isola::analysis::resolution::ResolutionSetting;
use serde::Serialize;

use super::model_args::ModelArgs;
use super::output::{Done, Model, Output, Summary};
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
    /// The integrators' resolution, as a session's `resolution` setting: RK4 steps per
    /// forcing period of the steady state the seed settles to (`128`; default 64, steps also
    /// at most 3.2/N long), or the Dormand–Prince tolerance of the shooting along the branch
    /// (`rtol=1e-12`; default rtol=1e-11).
    #[arg(long, value_name = "N|rtol=X", value_parser = super::parse::resolution)]
    resolution: Option<ResolutionSetting>,
    /// Write one row per branch point and per bifurcation to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// A continuation: the branch through the seed, and with --switch the branches born at its
/// period doublings.
#[derive(Serialize)]
struct ContinueSummary<'a> {
    #[serde(flatten)]
    model: Model,
    /// ω_e of the seed.
    omega: f64,
    x0: f64,
    v0: f64,
    parameter: &'a str,
    /// The range --range allowed it.
    range_min: f64,
    range_max: f64,
    /// The seed's branch first, then the branches switched to, in the order of `switches`.
    branches: Vec<BranchSummary<'a>>,
    switches: Vec<Switch>,
    /// Points on all the branches.
    points: usize,
    #[serde(flatten)]
    done: Done,
}

/// What became of a switch at a period doubling of the seed's branch, at `at`.
#[derive(Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
enum Switch {
    /// The branch born there is one switched to already (it ends there).
    Known { at: f64 },
    /// Continued: `branches[branch]`.
    Continued { at: f64, branch: usize },
    /// No branch could be continued from there.
    Failed { at: f64, reason: String },
}

/// One continued branch: its range, ends, stable and unstable arcs and located
/// bifurcations.
#[derive(Serialize)]
pub struct BranchSummary<'a> {
    period: usize,
    parameter: &'a str,
    parameter_min: f64,
    parameter_max: f64,
    pub ends: &'a [BranchEnd; 2],
    closed: bool,
    pub points: usize,
    pub arcs: Vec<ArcEnds>,
    pub bifurcations: &'a [Bifurcation],
}

impl<'a> BranchSummary<'a> {
    /// The summary of `b`.
    pub fn of(b: &'a ContinuedBranch) -> Self {
        let (parameter_min, parameter_max) = b.parameter_range();
        let arcs = b.arc_ends();
        BranchSummary {
            period: b.period,
            parameter: b.parameter.name(),
            parameter_min,
            parameter_max,
            ends: &b.ends,
            closed: b.closed(),
            points: b.points.len(),
            arcs,
            bifurcations: &b.bifurcations,
        }
    }
}

pub fn run(args: &ContinueArgs, out: Output) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref()])?;
    let params = args.model.params()?;
    let started = Instant::now();
    let mut spec = BranchFromState {
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
    super::parse::set_resolution(&mut spec, args.resolution)?;
    let progress = Progress::new(0);
    let branch = branch_from_state(&params, &spec, &progress)?;
    let mut born = Vec::new();
    let mut switches = Vec::new();
    if args.switch {
        for pd in branch.of_kind(BifurcationKind::PeriodDoubling) {
            let at = pd.parameter;
            let known = born.iter().any(|b: &ContinuedBranch| {
                b.of_kind(BifurcationKind::ParentPeriodDoubling)
                    .any(|end| (end.parameter - at).abs() < 1e-6)
            });
            switches.push(if known {
                Switch::Known { at }
            } else {
                match switch_at_period_doubling(&params, &branch, pd, &spec.continuation, &progress)
                {
                    Ok(b) => {
                        born.push(b);
                        Switch::Continued {
                            at,
                            branch: born.len(),
                        }
                    }
                    Err(e) => Switch::Failed {
                        at,
                        reason: e.to_string(),
                    },
                }
            });
        }
    }
    let all: Vec<&ContinuedBranch> = std::iter::once(&branch).chain(&born).collect();
    let mut done = Done {
        elapsed_seconds: started.elapsed().as_secs_f64(),
        ..Done::default()
    };
    if let Some(path) = &args.csv {
        isola::session::export::continued_csv(
            &all,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?;
        done.wrote.push(path.clone());
    }
    out.report(&ContinueSummary {
        model: Model::of(&params),
        omega: params.omega(),
        x0: args.start.x0,
        v0: args.start.v0,
        parameter: args.vary.name(),
        range_min: args.range.0,
        range_max: args.range.1,
        points: all.iter().map(|b| b.points.len()).sum(),
        branches: all.into_iter().map(BranchSummary::of).collect(),
        switches,
        done,
    })
}

impl Summary for ContinueSummary<'_> {
    fn print_text(&self) {
        self.branches[0].print_text();
        let name = self.parameter;
        for switch in &self.switches {
            match switch {
                Switch::Known { at } => {
                    say!("the branch born at {name} = {at:.9} is the one above (it ends there)")
                }
                Switch::Continued { at, branch } => {
                    say!("switching at the period doubling at {name} = {at:.9}:");
                    self.branches[*branch].print_text();
                }
                Switch::Failed { at, reason } => {
                    say!("switching at the period doubling at {name} = {at:.9}:");
                    say!("  no branch: {reason}");
                }
            }
        }
        say!(
            "{} points in {:.2} s",
            self.points,
            self.done.elapsed_seconds
        );
        self.done.print_wrote();
    }
}

impl Summary for BranchSummary<'_> {
    /// The shape of the branch, its arcs and its bifurcations, as lines of text.
    fn print_text(&self) {
        let name = self.parameter;
        say!(
            "period-{} branch, {name} {:.6}–{:.6}, ends: {} / {}{}",
            self.period,
            self.parameter_min,
            self.parameter_max,
            self.ends[0],
            self.ends[1],
            if self.closed { " (closed)" } else { "" }
        );
        for a in &self.arcs {
            say!(
                "  {} arc: {name} {:.4} → {:.4}, amplitude {:.4} → {:.4}",
                if a.stable { "stable  " } else { "unstable" },
                a.parameter_start,
                a.parameter_end,
                a.amplitude_start,
                a.amplitude_end
            );
        }
        for f in self.bifurcations {
            let mu = f.multipliers.0[0];
            say!(
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
}
