//! `isola hunt`: the frequency response from many initial states, then each subharmonic
//! branch it finds continued both ways in ω: isola or attached, folds, period doublings and
//! stable and unstable arcs.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::continuation::branch::ContinuationSpec;
use isola::analysis::continuation::hunt::{HuntSpec, hunt_in};
use isola::analysis::continuation::hunt_family::{HuntFamilySpec, hunt_family};
use isola::analysis::continuation::isola_limits::locate_limits;
use isola::analysis::global::frequency_response::FrequencyResponseSpec;
use isola::analysis::global::frequency_response::frequency_response;
use isola::analysis::parameter::FamilyParameter;
use isola::jobs::JobContext;
use isola::model::Device;

use super::model_args::ModelArgs;
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
    /// Range MIN:MAX the branches are continued over (default: the --omega grid's).
    #[arg(long, value_parser = parse::interval)]
    range: Option<(f64, f64)>,
    /// Largest arclength step of the continuation.
    #[arg(long = "step-max", default_value_t = ContinuationSpec::default().step_max, value_parser = super::parse::finite)]
    step_max: f64,
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

pub fn run(args: &HuntArgs) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref(), args.response_csv.as_deref()])?;
    let (omega, params) = args.model.omega_range("0.2:6.0:0.05")?;
    let (dx, v) = args.starts.axes(args.ics);
    let (min, max) = args
        .range
        .unwrap_or((omega.min.min(omega.max), omega.min.max(omega.max)));
    let spec = HuntSpec {
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
    super::check_memory("hunt", isola::analysis::cost::hunt(&spec))?;
    let progress = std::sync::Arc::new(Progress::new(0));
    let (ctx, _partial) = JobContext::<()>::new(args.threads, progress.clone())?;
    let started = Instant::now();
    if let Some(parameter) = args.vary {
        let family = HuntFamilySpec {
            parameter,
            values: args.values.clone(),
            hunt: spec,
        };
        let members = ctx.run(|| {
            hunt_family(&params, &family, &progress, |m| {
                let line: Vec<String> = m.branches.iter().map(|b| b.describe()).collect();
                println!(
                    "{} {}: {}",
                    parameter.name(),
                    m.value,
                    if line.is_empty() {
                        "no subharmonic branch".into()
                    } else {
                        line.join("; ")
                    }
                );
            })
        })??;
        let name = parameter.name();
        for (t, limit) in locate_limits(&params, &family, &members, 1e-4, &progress)? {
            match limit {
                Some(l) => println!(
                    "{}: at {name} = {:.9} ± {:.0e} (ω {:.6}, amplitude {:.6})",
                    t.describe(name),
                    l.value,
                    l.precision,
                    l.omega,
                    l.amplitude
                ),
                None => println!("{}", t.describe(name)),
            }
        }
        println!(
            "{} values in {:.2} s",
            members.len(),
            started.elapsed().as_secs_f64()
        );
        if let Some(path) = &args.csv {
            isola::session::export::hunt_family_csv(parameter.name(), &members, path)?;
            println!("wrote {}", path.display());
        }
        return Ok(());
    }
    spec.validate(&params)?;
    let response = ctx.run(|| frequency_response(&params, &spec.response, &progress))??;
    let brute_force = started.elapsed().as_secs_f64();
    let found = ctx.run(|| hunt_in(&params, response, &spec.continuation, &progress))??;
    let dev = Device::silicone();
    let subharmonic = found
        .response
        .branches
        .iter()
        .filter(|b| b.is_subharmonic())
        .count();
    println!(
        "hunt: {} ω values × {} initial states, {subharmonic} subharmonic brute-force branches → {} continued, in {:.2} s ({brute_force:.2} s brute force, {:.2} s continuation; {} threads)",
        found.response.omegas.len(),
        args.ics.0 * args.ics.1,
        found.branches.len(),
        started.elapsed().as_secs_f64(),
        started.elapsed().as_secs_f64() - brute_force,
        ctx.pool.current_num_threads(),
    );
    for (i, h) in found.branches.iter().enumerate() {
        println!(
            "#{i} {} (brute-force branches {:?}, {} points)",
            h.describe(),
            h.seeds,
            h.branch.points.len()
        );
        println!(
            "   ω {:.4}–{:.4} = {:.2}–{:.2} Hz; ends: {} / {}",
            h.omega_min,
            h.omega_max,
            dev.hz(h.omega_min),
            dev.hz(h.omega_max),
            h.branch.ends[0],
            h.branch.ends[1]
        );
        let arcs = |a: &[[f64; 2]]| {
            a.iter()
                .map(|r| format!("{:.4}–{:.4}", r[0], r[1]))
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!(
            "   stable ω {}; unstable ω {}",
            arcs(&h.stable_arcs),
            arcs(&h.unstable_arcs)
        );
        for b in &h.branch.bifurcations {
            println!(
                "   {:<16} ω {:.9} (±{:.0e}), amplitude {:.6}",
                b.kind.as_str(),
                b.omega,
                b.precision.max(f64::EPSILON),
                b.amplitude
            );
        }
    }
    for f in &found.failures {
        println!("brute-force branch {} not continued: {}", f.seed, f.reason);
    }
    if let Some(path) = &args.csv {
        let branches: Vec<_> = found.branches.iter().map(|h| &h.branch).collect();
        isola::session::export::continued_csv(
            &branches,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.response_csv {
        isola::session::export::response_csv(
            &found.response,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
