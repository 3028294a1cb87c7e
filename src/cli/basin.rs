//! `isola basin`: the basin of attraction on a grid of initial states.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::global::basin::{BasinSpec, basin};
use isola::jobs::JobContext;

use super::model_args::ModelArgs;
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
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Write one row per cell to this CSV file, and the attractor table beside it.
    #[arg(long)]
    csv: Option<PathBuf>,
}

pub fn run(args: &BasinArgs) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref()])?;
    let params = args.model.params()?;
    let (dx, v) = args.starts.axes(args.grid);
    let spec = BasinSpec {
        dx,
        v,
        early_stop: !args.no_early_stop,
        ..BasinSpec::default()
    };
    spec.validate()?;
    super::check_memory("basin", isola::analysis::cost::basin(&spec, params.omega()))?;
    let progress = std::sync::Arc::new(Progress::new(0));
    let (ctx, _partial) = JobContext::<()>::new(args.threads, progress.clone())?;
    let started = Instant::now();
    let result = ctx.run(|| basin(&params, &spec, &progress, &|_| {}))??;
    let elapsed = started.elapsed();
    println!(
        "basin {}x{} at ADR {}, ω_e {}: {} cells in {:.2} s ({} threads)",
        args.grid.0,
        args.grid.1,
        params
            .drive_i()
            .adr()
            .map_or("-".into(), |a| format!("{a}")),
        params.omega(),
        result.labels.len(),
        elapsed.as_secs_f64(),
        ctx.pool.current_num_threads()
    );
    for a in &result.table.attractors {
        let r = &a.response;
        println!(
            "  #{}  {:<18} period {:<4} amplitude {:<10} fraction {:.4}",
            a.id,
            r.response_type(),
            r.period.map_or("-".into(), |k| k.to_string()),
            r.amplitude.map_or("-".into(), |x| format!("{x:.6}")),
            result.fraction(a.id)
        );
    }
    if let Some(path) = &args.csv {
        isola::session::export::basin_csv(
            &result,
            params.omega(),
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?;
        println!("wrote {} and its .attractors.csv", path.display());
    }
    Ok(())
}
