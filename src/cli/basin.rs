//! `isola basin`: the basin of attraction on a grid of initial states.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::global::basin::{BasinSpec, basin};
use isola::analysis::grid::Axis;
use isola::analysis::resolution::ResolutionSetting;
use isola::analysis::{Progress, SteadyState};
use isola::jobs::JobContext;
use serde::Serialize;

use super::model_args::ModelArgs;
use super::output::{Done, Model, Output, Summary};
use super::parse;
use super::start_ranges::StartRanges;

#[derive(Debug, Args)]
pub struct BasinArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Grid size NΔλ x Nv.
    #[arg(long, default_value = "201x251", value_parser = parse::grid)]
    grid: (usize, usize),
    #[command(flatten)]
    starts: StartRanges,
    /// Integrate every cell to full convergence (no early stop on known attractors).
    #[arg(long = "no-early-stop")]
    no_early_stop: bool,
    /// The integrator's resolution, as a session's `resolution` setting: RK4 steps per
    /// forcing period (`128`; default 64, steps also at most 3.2/N long).
    #[arg(long, value_name = "N", value_parser = super::parse::resolution)]
    resolution: Option<ResolutionSetting>,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Write one row per cell to this CSV file, and the attractor table beside it.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// A basin: its grid and the attractors the cells reach, with their shares.
#[derive(Serialize)]
struct BasinSummary<'a> {
    #[serde(flatten)]
    model: Model,
    omega: f64,
    /// Initial Δλ and v of the grid's cells.
    dx: Axis,
    v: Axis,
    cells: usize,
    threads: usize,
    attractors: Vec<AttractorSummary<'a>>,
    #[serde(flatten)]
    done: Done,
}

/// One attractor: a representative steady state (fields as `orbit`'s), the cells that reach
/// it and their share of the grid.
#[derive(Serialize)]
struct AttractorSummary<'a> {
    id: usize,
    response_type: String,
    cells: usize,
    fraction: f64,
    #[serde(flatten)]
    steady: &'a SteadyState,
}

pub fn run(args: &BasinArgs, out: Output) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref()])?;
    let params = args.model.params()?;
    let (dx, v) = args.starts.axes(args.grid);
    let mut spec = BasinSpec {
        dx,
        v,
        early_stop: !args.no_early_stop,
        ..BasinSpec::default()
    };
    parse::set_resolution(&mut spec, args.resolution)?;
    spec.validate()?;
    super::check_memory("basin", isola::analysis::cost::basin(&spec, params.omega()))?;
    let progress = std::sync::Arc::new(Progress::new(0));
    let ctx = JobContext::new(args.threads, progress.clone())?;
    let started = Instant::now();
    let result = ctx.run(|| basin(&params, &spec, &progress, &|_| {}))??;
    let mut done = Done {
        elapsed_seconds: started.elapsed().as_secs_f64(),
        ..Done::default()
    };
    if let Some(path) = &args.csv {
        done.wrote.extend(isola::session::export::basin_csv(
            &result,
            params.omega(),
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?);
    }
    let attractors = result
        .table
        .attractors
        .iter()
        .map(|a| AttractorSummary {
            id: a.id,
            response_type: a.response.response_type(),
            cells: a.count,
            fraction: result.fraction(a.id),
            steady: &a.response,
        })
        .collect();
    out.report(&BasinSummary {
        model: Model::of(&params),
        omega: params.omega(),
        dx: spec.dx,
        v: spec.v,
        cells: result.labels.len(),
        threads: ctx.pool.current_num_threads(),
        attractors,
        done,
    })
}

impl Summary for BasinSummary<'_> {
    fn print_text(&self) {
        say!(
            "basin {}x{} at ADR {}, ω_e {}: {} cells in {:.2} s ({} threads)",
            self.dx.points,
            self.v.points,
            self.model.adr.map_or("-".into(), |a| format!("{a}")),
            self.omega,
            self.cells,
            self.done.elapsed_seconds,
            self.threads
        );
        for a in &self.attractors {
            say!(
                "  #{}  {:<18} period {:<4} amplitude {:<10} fraction {:.4}",
                a.id,
                a.response_type,
                a.steady.period.map_or("-".into(), |k| k.to_string()),
                a.steady.amplitude.map_or("-".into(), |x| format!("{x:.6}")),
                a.fraction
            );
        }
        self.done.print_wrote();
    }
}
