//! `isola family`: a frequency response per value of one parameter (Fig 7–12).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::global::family::{FamilySpec, family};
use isola::analysis::global::frequency_response::FrequencyResponseSpec;
use isola::analysis::grid::Axis;
use isola::analysis::parameter::FamilyParameter;
use isola::jobs::JobContext;

use super::model_args::ModelArgs;
use super::parse;

#[derive(Debug, Args)]
pub struct FamilyArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// The parameter to vary: adr, e_a, c_tilde, lambda_p or j.
    #[arg(long, value_parser = |s: &str| FamilyParameter::parse(s).ok_or_else(|| format!("'{s}': one of adr, e_a, c_tilde, lambda_p, j")))]
    vary: FamilyParameter,
    /// Its values, comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        required = true,
        allow_negative_numbers = true
    )]
    values: Vec<f64>,
    /// Grid of initial states NΔλ x Nv.
    #[arg(long, default_value = "15x15", value_parser = parse::grid)]
    ics: (usize, usize),
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Write one row per branch per value to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

pub fn run(args: &FamilyArgs) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref()])?;
    let (omega, params) = args.model.omega_range("0.2:6.0:0.05")?;
    let spec = FamilySpec {
        parameter: args.vary,
        values: args.values.clone(),
        response: FrequencyResponseSpec {
            omega,
            dx: Axis::new(-0.8, 0.8, args.ics.0),
            v: Axis::new(-1.0, 1.0, args.ics.1),
            ..FrequencyResponseSpec::default()
        },
    };
    spec.validate(&params)?;
    super::check_memory("family", isola::analysis::cost::family(&spec))?;
    let progress = std::sync::Arc::new(Progress::new(0));
    let (ctx, _partial) = JobContext::<()>::new(args.threads, progress.clone())?;
    let started = Instant::now();
    let name = args.vary.name();
    let members = ctx.run(|| {
        family(&params, &spec, &progress, |m| {
            let subs: Vec<String> = m.subharmonic_branches().map(|b| b.describe()).collect();
            println!(
                "{name} = {:<8} {}",
                m.value,
                if subs.is_empty() {
                    "no subharmonic".into()
                } else {
                    subs.join("; ")
                }
            );
        })
    })??;
    println!(
        "{} members in {:.2} s",
        members.len(),
        started.elapsed().as_secs_f64()
    );
    if let Some(path) = &args.csv {
        isola::session::export::family_csv(
            name,
            &members,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
