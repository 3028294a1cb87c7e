//! `isola hunt`: the frequency response from many initial states, then each subharmonic
//! branch it finds continued both ways in ω: isola or attached, folds, period doublings and
//! stable and unstable arcs.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::continuation::branch::ContinuationSpec;
use isola::analysis::continuation::hunt::{HuntFailure, HuntSpec, HuntedBranch, Verdict, hunt_in};
use isola::analysis::continuation::hunt_family::{
    HuntFamilySpec, HuntMember, Transition, hunt_family,
};
use isola::analysis::continuation::isola_limits::{IsolaLimit, locate_limits};
use isola::analysis::global::frequency_response::FrequencyResponseSpec;
use isola::analysis::global::frequency_response::frequency_response;
use isola::analysis::grid::Axis;
use isola::analysis::parameter::FamilyParameter;
use isola::analysis::resolution::ResolutionSetting;
use isola::jobs::JobContext;
use serde::Serialize;

use super::continue_cmd::BranchSummary;
use super::model_args::ModelArgs;
use super::output::{Done, Model, Output, Summary, hz};
use super::parse;
use super::start_ranges::StartRanges;

#[derive(Debug, Args)]
pub struct HuntArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Grid of initial states NΔλ x Nv of the frequency response.
    #[arg(long, default_value = "15x15", value_parser = parse::grid)]
    ics: (usize, usize),
    #[command(flatten)]
    starts: StartRanges,
    /// Hunt at each value of this parameter (adr, e_a, c_tilde, lambda_p, j), given by
    /// --values: where isolas are born and where they merge.
    #[arg(long, requires = "values", value_parser = |s: &str| FamilyParameter::parse(s).ok_or_else(|| format!("'{s}': one of adr, e_a, c_tilde, lambda_p, j")))]
    vary: Option<FamilyParameter>,
    /// The values of --vary, increasing, comma-separated.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    values: Vec<f64>,
    /// Range MIN:MAX the branches are continued over (default: the paper's 0.2:6, widened to
    /// hold the --omega grid), so that a branch found in a narrow --omega window is followed
    /// to where it closes or attaches, not cut at the window's edges.
    #[arg(long, value_parser = parse::interval)]
    range: Option<(f64, f64)>,
    /// Largest arclength step of the continuation.
    #[arg(long = "step-max", default_value_t = ContinuationSpec::default().step_max, value_parser = super::parse::finite)]
    step_max: f64,
    /// The integrator's resolution, as a session's `resolution` setting: RK4 steps per
    /// forcing period (`128`; default 64, steps also at most 3.2/N long), or the Dormand–Prince tolerance of the shooting (default rtol=1e-11) (`rtol=1e-12`).
    #[arg(long, value_name = "N|rtol=X", value_parser = super::parse::resolution)]
    resolution: Option<ResolutionSetting>,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Write the continued branches (one row per point and per bifurcation) to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Write the frequency response (one row per response per ω) to this CSV file.
    #[arg(long = "response-csv")]
    response_csv: Option<PathBuf>,
}

/// A hunt: the frequency response's grids and each subharmonic (or hidden) branch it found,
/// continued.
#[derive(Serialize)]
struct HuntSummary<'a> {
    #[serde(flatten)]
    model: Model,
    omega: Axis,
    /// Initial Δλ and v of the grid of initial states.
    dx: Axis,
    v: Axis,
    initial_states: usize,
    threads: usize,
    /// Subharmonic branches of the brute-force frequency response.
    subharmonic_branches: usize,
    branches: Vec<HuntedSummary<'a>>,
    /// Brute-force branches whose continuation could not start.
    failures: &'a [HuntFailure],
    brute_force_seconds: f64,
    continuation_seconds: f64,
    #[serde(flatten)]
    done: Done,
}

/// A hunt per value of a parameter: the branches at each, and where the picture changes.
#[derive(Serialize)]
struct HuntFamilySummary<'a> {
    #[serde(flatten)]
    model: Model,
    omega: Axis,
    parameter: &'a str,
    members: Vec<MemberSummary<'a>>,
    transitions: Vec<TransitionSummary<'a>>,
    #[serde(flatten)]
    done: Done,
}

/// The hunted branches at one value.
#[derive(Serialize)]
struct MemberSummary<'a> {
    #[serde(skip)]
    parameter: &'a str,
    value: f64,
    branches: Vec<HuntedSummary<'a>>,
}

/// Between two adjacent values the period-k picture changes, and where exactly, when it is
/// an isola's birth or merger that could be located.
#[derive(Serialize)]
struct TransitionSummary<'a> {
    #[serde(skip)]
    parameter: &'a str,
    /// `birth`, `vanishing`, `merging`, `detaching` or `change`.
    event: &'static str,
    #[serde(flatten)]
    transition: Transition,
    limit: Option<IsolaLimit>,
}

/// One continued branch: what it is, its ω_e range (also in Hz), peak and arcs, and the
/// branch itself as `continue` reports it.
#[derive(Serialize)]
struct HuntedSummary<'a> {
    #[serde(skip)]
    hunted: &'a HuntedBranch,
    response_type: &'a str,
    verdict: Verdict,
    hidden: bool,
    /// Ids of the brute-force branches on it (the first was the seed).
    seeds: &'a [usize],
    omega_min: f64,
    omega_max: f64,
    frequency_hz_min: f64,
    frequency_hz_max: f64,
    peak_amplitude: f64,
    peak_omega: f64,
    stable_arcs: &'a [[f64; 2]],
    unstable_arcs: &'a [[f64; 2]],
    branch: BranchSummary<'a>,
}

impl<'a> HuntedSummary<'a> {
    fn of(h: &'a HuntedBranch) -> Self {
        HuntedSummary {
            hunted: h,
            response_type: &h.response_type,
            verdict: h.verdict,
            hidden: h.hidden,
            seeds: &h.seeds,
            omega_min: h.omega_min,
            omega_max: h.omega_max,
            frequency_hz_min: hz(h.omega_min),
            frequency_hz_max: hz(h.omega_max),
            peak_amplitude: h.peak_amplitude,
            peak_omega: h.peak_omega,
            stable_arcs: &h.stable_arcs,
            unstable_arcs: &h.unstable_arcs,
            branch: BranchSummary::of(&h.branch),
        }
    }
}

impl<'a> MemberSummary<'a> {
    fn of(parameter: &'a str, m: &'a HuntMember) -> Self {
        MemberSummary {
            parameter,
            value: m.value,
            branches: m.branches.iter().map(HuntedSummary::of).collect(),
        }
    }
}

pub fn run(args: &HuntArgs, out: Output) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref(), args.response_csv.as_deref()])?;
    let (omega, params) = args.model.omega_range("0.2:6.0:0.05")?;
    let (dx, v) = args.starts.axes(args.ics);
    let paper = ContinuationSpec::default();
    let (min, max) = args.range.unwrap_or((
        paper.min.min(omega.min.min(omega.max)),
        paper.max.max(omega.min.max(omega.max)),
    ));
    let mut spec = HuntSpec {
        response: FrequencyResponseSpec {
            omega,
            dx,
            v,
            ..FrequencyResponseSpec::default()
        },
        continuation: ContinuationSpec {
            min,
            max,
            step_max: args.step_max,
            step: ContinuationSpec::default().step.min(args.step_max),
            ..ContinuationSpec::default()
        },
    };
    super::parse::set_resolution(&mut spec, args.resolution)?;
    super::check_memory("hunt", isola::analysis::cost::hunt(&spec))?;
    let progress = std::sync::Arc::new(Progress::new(0));
    let ctx = JobContext::new(args.threads, progress.clone())?;
    let started = Instant::now();
    if let Some(parameter) = args.vary {
        let family = HuntFamilySpec {
            parameter,
            values: args.values.clone(),
            hunt: spec,
        };
        let name = parameter.name();
        let members = ctx.run(|| {
            hunt_family(&params, &family, &progress, |m| {
                out.show(&MemberSummary::of(name, m))
            })
        })??;
        let limits = locate_limits(&params, &family, &members, 1e-4, &progress)?;
        let mut done = Done {
            elapsed_seconds: started.elapsed().as_secs_f64(),
            ..Done::default()
        };
        if let Some(path) = &args.csv {
            done.wrote.extend(isola::session::export::hunt_family_csv(
                name, &members, &limits, path,
            )?);
        }
        let transitions = limits
            .into_iter()
            .map(|(transition, limit)| TransitionSummary {
                parameter: name,
                event: transition.event(),
                transition,
                limit,
            })
            .collect();
        return out.report(&HuntFamilySummary {
            model: Model::of(&params),
            omega,
            parameter: name,
            members: members.iter().map(|m| MemberSummary::of(name, m)).collect(),
            transitions,
            done,
        });
    }
    spec.validate(&params)?;
    let response = ctx.run(|| frequency_response(&params, &spec.response, &progress))??;
    let brute_force = started.elapsed().as_secs_f64();
    let found = ctx.run(|| hunt_in(&params, response, &spec.continuation, &progress))??;
    let elapsed = started.elapsed().as_secs_f64();
    let mut done = Done {
        elapsed_seconds: elapsed,
        ..Done::default()
    };
    let columns = isola::session::export::ModelColumns::built_in(&isola::model::Device::default());
    if let Some(path) = &args.csv {
        let branches: Vec<_> = found.branches.iter().map(|h| &h.branch).collect();
        isola::session::export::continued_csv(&branches, &columns, path)?;
        done.wrote.push(path.clone());
    }
    if let Some(path) = &args.response_csv {
        done.wrote.extend(isola::session::export::response_csv(
            &found.response,
            &columns,
            path,
        )?);
    }
    out.report(&HuntSummary {
        model: Model::of(&params),
        omega,
        dx,
        v,
        initial_states: args.ics.0 * args.ics.1,
        threads: ctx.pool.current_num_threads(),
        subharmonic_branches: found
            .response
            .branches
            .iter()
            .filter(|b| b.is_subharmonic())
            .count(),
        branches: found.branches.iter().map(HuntedSummary::of).collect(),
        failures: &found.failures,
        brute_force_seconds: brute_force,
        continuation_seconds: elapsed - brute_force,
        done,
    })
}

impl Summary for HuntSummary<'_> {
    fn print_text(&self) {
        say!(
            "hunt: {} ω values × {} initial states, {} subharmonic brute-force branches → {} continued, in {:.2} s ({:.2} s brute force, {:.2} s continuation; {} threads)",
            self.omega.points,
            self.initial_states,
            self.subharmonic_branches,
            self.branches.len(),
            self.done.elapsed_seconds,
            self.brute_force_seconds,
            self.continuation_seconds,
            self.threads,
        );
        for (i, h) in self.branches.iter().enumerate() {
            say!(
                "#{i} {} (brute-force branches {:?}, {} points)",
                h.hunted.describe(),
                h.seeds,
                h.branch.points
            );
            let ends = h.branch.ends;
            say!(
                "   ω {:.4}–{:.4} = {:.2}–{:.2} Hz; ends: {} / {}",
                h.omega_min,
                h.omega_max,
                h.frequency_hz_min,
                h.frequency_hz_max,
                ends[0],
                ends[1]
            );
            for line in arc_lines(&h.branch) {
                say!("   {line}");
            }
            for b in h.branch.bifurcations {
                say!(
                    "   {:<16} ω {:.9} (±{:.0e}), amplitude {:.6}",
                    b.kind.as_str(),
                    b.omega,
                    b.precision.max(f64::EPSILON),
                    b.amplitude
                );
            }
        }
        for f in self.failures {
            say!("brute-force branch {} not continued: {}", f.seed, f.reason);
        }
        self.done.print_wrote();
    }
}

/// The arcs of a branch in order along it, each with where it starts and ends in ω and in
/// amplitude, so that a folded branch reads as it turns: `stable   ω 3.5896 → 5.4439,
/// amplitude 0.5094 → 0.0266`, then the unstable arc back.
fn arc_lines(b: &BranchSummary) -> Vec<String> {
    b.arcs
        .iter()
        .map(|a| {
            format!(
                "{:<8} ω {:.4} → {:.4}, amplitude {:.4} → {:.4}",
                if a.stable { "stable" } else { "unstable" },
                a.parameter_start,
                a.parameter_end,
                a.amplitude_start,
                a.amplitude_end
            )
        })
        .collect()
}

impl Summary for MemberSummary<'_> {
    fn print_text(&self) {
        let line: Vec<String> = self.branches.iter().map(|b| b.hunted.describe()).collect();
        say!(
            "{} {}: {}",
            self.parameter,
            self.value,
            if line.is_empty() {
                "no subharmonic branch".into()
            } else {
                line.join("; ")
            }
        );
    }
}

impl Summary for TransitionSummary<'_> {
    fn print_text(&self) {
        let (t, name) = (&self.transition, self.parameter);
        match &self.limit {
            Some(l) => say!(
                "{}: at {name} = {:.9} ± {:.0e} (ω {:.6}, amplitude {:.6})",
                t.describe(name),
                l.value,
                l.precision,
                l.omega,
                l.amplitude
            ),
            None => say!("{}", t.describe(name)),
        }
    }
}

impl Summary for HuntFamilySummary<'_> {
    /// The members were shown as each finished.
    fn print_text(&self) {
        for t in &self.transitions {
            t.print_text();
        }
        say!(
            "{} values in {:.2} s",
            self.members.len(),
            self.done.elapsed_seconds
        );
        self.done.print_wrote();
    }
}
