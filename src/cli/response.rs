//! `isola response`: the frequency response from many initial states (Fig 4/5).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::global::frequency_response::{
    Branch, FrequencyResponseSpec, frequency_response,
};
use isola::analysis::grid::Axis;
use isola::analysis::resolution::ResolutionSetting;
use isola::jobs::JobContext;
use serde::Serialize;

use super::model_args::ModelArgs;
use super::output::{Done, Model, Output, Summary, hz};
use super::parse;
use super::start_ranges::StartRanges;

#[derive(Debug, Args)]
pub struct ResponseArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Grid of initial states NΔλ x Nv.
    #[arg(long, default_value = "15x15", value_parser = parse::grid)]
    ics: (usize, usize),
    #[command(flatten)]
    starts: StartRanges,
    /// Do not seed each ω with its neighbours' responses.
    #[arg(long = "no-seeding")]
    no_seeding: bool,
    /// Skip the stepped sweeps (no hidden flags).
    #[arg(long = "no-sweeps")]
    no_sweeps: bool,
    /// Integrate every trajectory to full convergence.
    #[arg(long = "no-early-stop")]
    no_early_stop: bool,
    /// The integrator's resolution, as a session's `resolution` setting: RK4 steps per
    /// forcing period (`128`; default 64, steps also at most 3.2/N long).
    #[arg(long, value_name = "N", value_parser = super::parse::resolution)]
    resolution: Option<ResolutionSetting>,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Write one row per response per ω to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// A frequency response: its grids, how many responses it found, and its branches.
#[derive(Serialize)]
struct ResponseSummary<'a> {
    #[serde(flatten)]
    model: Model,
    omega: Axis,
    /// Initial Δλ and v of the grid of initial states.
    dx: Axis,
    v: Axis,
    initial_states: usize,
    threads: usize,
    /// Distinct responses over all ω_e (collisions and non-periodic ones included).
    responses: usize,
    branches: Vec<BranchSummary<'a>>,
    #[serde(flatten)]
    done: Done,
}

/// One branch of a frequency response, its ω_e range also in Hz, and the range of its
/// response frequency ω_r (ω_e times the ratio: half of it for a 1:2 subharmonic) in Hz.
#[derive(Serialize)]
pub struct BranchSummary<'a> {
    #[serde(flatten)]
    pub branch: &'a Branch,
    frequency_hz_min: f64,
    frequency_hz_max: f64,
    response_frequency_hz_min: f64,
    response_frequency_hz_max: f64,
}

impl<'a> BranchSummary<'a> {
    /// The branch with its ω_e and ω_r ranges in Hz.
    pub fn of(branch: &'a Branch) -> Self {
        let ratio = f64::from(branch.ratio.response) / f64::from(branch.ratio.excitation);
        BranchSummary {
            branch,
            frequency_hz_min: hz(branch.omega_min),
            frequency_hz_max: hz(branch.omega_max),
            response_frequency_hz_min: hz(branch.omega_min * ratio),
            response_frequency_hz_max: hz(branch.omega_max * ratio),
        }
    }
}

pub fn run(args: &ResponseArgs, out: Output) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref()])?;
    let (omega, params) = args.model.omega_range("0.2:6.0:0.05")?;
    let (dx, v) = args.starts.axes(args.ics);
    let mut spec = FrequencyResponseSpec {
        omega,
        dx,
        v,
        seed_neighbours: !args.no_seeding,
        sweeps: !args.no_sweeps,
        early_stop: !args.no_early_stop,
        ..FrequencyResponseSpec::default()
    };
    parse::set_resolution(&mut spec, args.resolution)?;
    spec.validate()?;
    super::check_memory("response", isola::analysis::cost::response(&spec, None))?;
    let progress = std::sync::Arc::new(Progress::new(0));
    let ctx = JobContext::new(args.threads, progress.clone())?;
    let started = Instant::now();
    let fr = ctx.run(|| frequency_response(&params, &spec, &progress))??;
    let mut done = Done {
        elapsed_seconds: started.elapsed().as_secs_f64(),
        ..Done::default()
    };
    if let Some(path) = &args.csv {
        done.wrote.extend(isola::session::export::response_csv(
            &fr,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?);
    }
    out.report(&ResponseSummary {
        model: Model::of(&params),
        omega: spec.omega,
        dx: spec.dx,
        v: spec.v,
        initial_states: args.ics.0 * args.ics.1,
        threads: ctx.pool.current_num_threads(),
        responses: fr.responses.len(),
        branches: fr.branches.iter().map(BranchSummary::of).collect(),
        done,
    })
}

impl Summary for ResponseSummary<'_> {
    fn print_text(&self) {
        say!(
            "frequency response: {} ω values × {} initial states in {:.2} s ({} threads): {} responses, {} branches",
            self.omega.points,
            self.initial_states,
            self.done.elapsed_seconds,
            self.threads,
            self.responses,
            self.branches.len()
        );
        say!(
            "  branch  type                 ω_e range (Hz)                    peak amplitude at ω_e   hidden  response ω_r (Hz)"
        );
        for s in &self.branches {
            let b = s.branch;
            say!(
                "  #{:<5}  {:<19}  {:.2}–{:.2} ({:.1}–{:.1} Hz){:>8}  {:.4} at {:.2}{:>10}  {:.1}–{:.1}",
                b.id,
                b.response_type,
                b.omega_min,
                b.omega_max,
                s.frequency_hz_min,
                s.frequency_hz_max,
                format!("{} pts", b.points),
                b.peak_amplitude,
                b.peak_omega,
                if b.hidden {
                    "hidden"
                } else if b.partly_hidden {
                    "partly"
                } else {
                    "no"
                },
                s.response_frequency_hz_min,
                s.response_frequency_hz_max
            );
        }
        self.done.print_wrote();
    }
}
