//! `isola map`: how many stable responses coexist over ω_e × one model parameter, where
//! hidden responses are, and the fold and period-doubling curves over it.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::continuation::bifurcation_curve::{Extremum, Turning};
use isola::analysis::continuation::branch::{BifurcationKind, BranchEnd};
use isola::analysis::continuation::map::{MapSpec, WindowCut, map};
use isola::analysis::global::frequency_response::FrequencyResponseSpec;
use isola::analysis::grid::Axis;
use isola::analysis::parameter::ContinuationParameter;
use isola::analysis::parameter::FamilyParameter;
use isola::analysis::resolution::ResolutionSetting;
use isola::jobs::JobContext;
use serde::Serialize;

use super::model_args::ModelArgs;
use super::output::{Done, Model, Output, Summary};
use super::parse;
use super::start_ranges::StartRanges;

#[derive(Debug, Args)]
pub struct MapArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// The parameter along each row: omega (default; its values by --omega START:END:STEP)
    /// or a model parameter (its values by --x-values, at the single --omega).
    #[arg(long, default_value = "omega", value_parser = |s: &str| ContinuationParameter::parse(s).ok_or_else(|| format!("'{s}': one of omega, adr, e_a, c_tilde, lambda_p, j")))]
    x: ContinuationParameter,
    /// Values START:END:STEP of --x when it is not omega.
    #[arg(long = "x-values")]
    x_values: Option<String>,
    /// The parameter of the map's rows: adr, e_a, c_tilde, lambda_p or j.
    #[arg(long, value_parser = |s: &str| FamilyParameter::parse(s).ok_or_else(|| format!("'{s}': one of adr, e_a, c_tilde, lambda_p, j")))]
    vary: FamilyParameter,
    /// Its values START:END:STEP.
    #[arg(long)]
    values: String,
    /// Grid of initial states NΔλ x Nv per cell.
    #[arg(long, default_value = "7x7", value_parser = parse::grid)]
    ics: (usize, usize),
    #[command(flatten)]
    starts: StartRanges,
    /// Skip the fold and period-doubling curves.
    #[arg(long = "no-curves")]
    no_curves: bool,
    /// The integrator's resolution, as a session's `resolution` setting: RK4 steps per
    /// forcing period (`128`; default 64, steps also at most 3.2/N long).
    #[arg(long, value_name = "N", value_parser = super::parse::resolution)]
    resolution: Option<ResolutionSetting>,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Write one row per cell to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Write the curves (one row per point and per turning point) to this CSV file.
    #[arg(long = "curves-csv")]
    curves_csv: Option<PathBuf>,
}

/// A map: its axes, how many cells hold coexisting stable responses, where hidden
/// subharmonic responses are, and the fold and period-doubling curves over it.
#[derive(Serialize)]
struct MapSummary<'a> {
    #[serde(flatten)]
    model: Model,
    /// The parameter along each row (`omega` or a model parameter) and its values.
    x: &'a str,
    x_values: Axis,
    /// The parameter of the rows and its values.
    parameter: &'a str,
    values: Axis,
    /// Initial Δλ and v of each cell's grid of initial states.
    dx: Axis,
    v: Axis,
    initial_states: usize,
    threads: usize,
    cells: usize,
    /// Cells with two or more stable responses, and the most in one cell.
    coexisting: usize,
    most_stable: usize,
    /// The range of the rows' parameter with hidden subharmonic responses.
    hidden_subharmonic_min: Option<f64>,
    hidden_subharmonic_max: Option<f64>,
    curves: Vec<CurveSummary<'a>>,
    /// Subharmonic branches the x window cuts (their curves beyond it are not drawn).
    cut: &'a [WindowCut],
    /// The same in words.
    cut_messages: Vec<String>,
    #[serde(flatten)]
    done: Done,
}

/// One fold or period-doubling curve: its points, ends and the located extrema of the rows'
/// parameter along it.
#[derive(Serialize)]
struct CurveSummary<'a> {
    period: usize,
    kind: BifurcationKind,
    points: usize,
    ends: &'a [BranchEnd; 2],
    extrema: Vec<&'a Extremum>,
}

pub fn run(args: &MapArgs, out: Output) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref(), args.curves_csv.as_deref()])?;
    let values = parse::range(&args.values).map_err(|e| anyhow::anyhow!("--values: {e}"))?;
    let (x_axis, params) = if args.x == ContinuationParameter::Omega {
        args.model.omega_range("1.0:6.0:0.1")?
    } else {
        let text = args.x_values.as_deref().ok_or_else(|| {
            anyhow::anyhow!("--x {} needs --x-values START:END:STEP", args.x.name())
        })?;
        let x_axis = parse::range(text).map_err(|e| anyhow::anyhow!("--x-values: {e}"))?;
        (x_axis, args.model.params()?)
    };
    let (dx, v) = args.starts.axes(args.ics);
    let mut spec = MapSpec {
        hidden_branches: false,
        x: args.x,
        parameter: args.vary,
        values,
        response: FrequencyResponseSpec {
            omega: x_axis,
            dx,
            v,
            ..FrequencyResponseSpec::default()
        },
        curves: !args.no_curves,
    };
    super::parse::set_resolution(&mut spec, args.resolution)?;
    spec.validate(&params)?;
    super::check_memory("map", isola::analysis::cost::map(&spec, params.omega()))?;
    let progress = std::sync::Arc::new(Progress::new(0));
    let ctx = JobContext::new(args.threads, progress.clone())?;
    let started = Instant::now();
    let (rows, found) = ctx.run(|| map(&params, &spec, &progress))??;
    let curves = &found.curves;
    let mut done = Done {
        elapsed_seconds: started.elapsed().as_secs_f64(),
        ..Done::default()
    };
    let name = args.vary.name();
    let cells: Vec<_> = rows
        .iter()
        .flat_map(|r| r.cells.iter().map(move |c| (r.value, c)))
        .collect();
    let hidden = cells
        .iter()
        .filter(|(_, c)| c.hidden && c.subharmonic)
        .map(|(v, _)| *v);
    if let Some(path) = &args.csv {
        isola::session::export::map_csv(
            (args.x.name(), name),
            &spec.response.omega.values(),
            &rows,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::silicone()),
            path,
        )?;
        done.wrote.push(path.clone());
    }
    if let Some(path) = &args.curves_csv {
        isola::session::export::curves_csv(
            curves,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?;
        done.wrote.push(path.clone());
    }
    out.report(&MapSummary {
        model: Model::of(&params),
        x: args.x.name(),
        x_values: x_axis,
        parameter: name,
        values,
        dx,
        v,
        initial_states: args.ics.0 * args.ics.1,
        threads: ctx.pool.current_num_threads(),
        cells: cells.len(),
        coexisting: cells.iter().filter(|(_, c)| c.stable >= 2).count(),
        most_stable: cells.iter().map(|(_, c)| c.stable).max().unwrap_or(0),
        hidden_subharmonic_min: hidden.clone().reduce(f64::min),
        hidden_subharmonic_max: hidden.reduce(f64::max),
        curves: curves
            .iter()
            .map(|c| CurveSummary {
                period: c.period,
                kind: c.kind,
                points: c.points.len(),
                ends: &c.ends,
                extrema: c.extrema_of(Turning::Second).collect(),
            })
            .collect(),
        cut: &found.cut,
        cut_messages: found
            .cut
            .iter()
            .map(|c| c.describe(args.x.name(), name))
            .collect(),
        done,
    })
}

impl Summary for MapSummary<'_> {
    fn print_text(&self) {
        let name = self.parameter;
        say!(
            "map: {} {name} values × {} {} values, {} initial states per cell, in {:.2} s ({} threads)",
            self.values.points,
            self.x_values.points,
            self.x,
            self.initial_states,
            self.done.elapsed_seconds,
            self.threads
        );
        say!(
            "  {} of {} cells with two or more stable responses (at most {})",
            self.coexisting,
            self.cells,
            self.most_stable
        );
        if let (Some(lo), Some(hi)) = (self.hidden_subharmonic_min, self.hidden_subharmonic_max) {
            say!("  hidden subharmonic responses from {name} {lo:.4} to {hi:.4}");
        }
        for c in &self.curves {
            say!(
                "  1:{} {} curve: {} points, ends {} / {}",
                c.period,
                c.kind.as_str(),
                c.points,
                c.ends[0],
                c.ends[1]
            );
            for e in &c.extrema {
                say!(
                    "    {} of {name}: {:.9} (±{:.0e}) at {} {:.6}",
                    if e.minimum { "minimum" } else { "maximum" },
                    e.point.second,
                    e.precision.max(1e-9),
                    self.x,
                    e.point.first
                );
            }
        }
        for message in &self.cut_messages {
            say!("  note: {message}");
        }
        self.done.print_wrote();
    }
}
