//! `isola response`: the frequency response from many initial states (Fig 4/5).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::global::frequency_response::{FrequencyResponseSpec, frequency_response};
use isola::jobs::JobContext;
use isola::model::Device;

use super::model_args::ModelArgs;
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
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Write one row per response per ω to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

pub fn run(args: &ResponseArgs) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref()])?;
    let (omega, params) = args.model.omega_range("0.2:6.0:0.05")?;
    let (dx, v) = args.starts.axes(args.ics);
    let spec = FrequencyResponseSpec {
        omega,
        dx,
        v,
        seed_neighbours: !args.no_seeding,
        sweeps: !args.no_sweeps,
        early_stop: !args.no_early_stop,
        ..FrequencyResponseSpec::default()
    };
    spec.validate()?;
    super::check_memory("response", isola::analysis::cost::response(&spec, None))?;
    let progress = std::sync::Arc::new(Progress::new(0));
    let (ctx, _partial) = JobContext::<()>::new(args.threads, progress.clone())?;
    let started = Instant::now();
    let fr = ctx.run(|| frequency_response(&params, &spec, &progress))??;
    let dev = Device::silicone();
    println!(
        "frequency response: {} ω values × {} initial states in {:.2} s ({} threads): {} responses, {} branches",
        fr.omegas.len(),
        args.ics.0 * args.ics.1,
        started.elapsed().as_secs_f64(),
        ctx.pool.current_num_threads(),
        fr.responses.len(),
        fr.branches.len()
    );
    println!(
        "  branch  type                 ω_e range (Hz)                    peak amplitude at ω_e   hidden"
    );
    for b in &fr.branches {
        println!(
            "  #{:<5}  {:<19}  {:.2}–{:.2} ({:.1}–{:.1} Hz){:>8}  {:.4} at {:.2}{:>10}",
            b.id,
            b.response_type,
            b.omega_min,
            b.omega_max,
            dev.hz(b.omega_min),
            dev.hz(b.omega_max),
            format!("{} pts", b.points),
            b.peak_amplitude,
            b.peak_omega,
            if b.hidden {
                "hidden"
            } else if b.partly_hidden {
                "partly"
            } else {
                "no"
            }
        );
    }
    if let Some(path) = &args.csv {
        isola::session::export::response_csv(
            &fr,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
