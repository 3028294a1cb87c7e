//! `isola family`: a frequency response per value of one parameter (Fig 7–12).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use isola::analysis::Progress;
use isola::analysis::global::family::{FamilyMember, FamilySpec, family};
use isola::analysis::global::frequency_response::FrequencyResponseSpec;
use isola::analysis::grid::Axis;
use isola::analysis::parameter::FamilyParameter;
use isola::analysis::resolution::ResolutionSetting;
use isola::jobs::JobContext;
use serde::Serialize;

use super::model_args::ModelArgs;
use super::output::{Done, Model, Output, Summary};
use super::parse;
use super::response::BranchSummary;

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
    /// The integrator's resolution, as a session's `resolution` setting: RK4 steps per
    /// forcing period (`128`; default 64, steps also at most 3.2/N long).
    #[arg(long, value_name = "N", value_parser = super::parse::resolution)]
    resolution: Option<ResolutionSetting>,
    /// Worker threads (0: one per core).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Write one row per branch per value to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// A family: the parameter varied and, per value, the branches of its frequency response.
#[derive(Serialize)]
struct FamilySummary<'a> {
    #[serde(flatten)]
    model: Model,
    omega: Axis,
    parameter: &'a str,
    members: Vec<MemberSummary<'a>>,
    #[serde(flatten)]
    done: Done,
}

/// One value of the family and every branch of its frequency response (the text shows the
/// subharmonic ones).
#[derive(Serialize)]
struct MemberSummary<'a> {
    #[serde(skip)]
    parameter: &'a str,
    value: f64,
    branches: Vec<BranchSummary<'a>>,
}

impl<'a> MemberSummary<'a> {
    fn of(parameter: &'a str, m: &'a FamilyMember) -> Self {
        MemberSummary {
            parameter,
            value: m.value,
            branches: m.response.branches.iter().map(BranchSummary::of).collect(),
        }
    }
}

pub fn run(args: &FamilyArgs, out: Output) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref()])?;
    let (omega, params) = args.model.omega_range("0.2:6.0:0.05")?;
    let mut spec = FamilySpec {
        parameter: args.vary,
        values: args.values.clone(),
        response: FrequencyResponseSpec {
            omega,
            dx: Axis::new(-0.8, 0.8, args.ics.0),
            v: Axis::new(-1.0, 1.0, args.ics.1),
            ..FrequencyResponseSpec::default()
        },
    };
    super::parse::set_resolution(&mut spec, args.resolution)?;
    spec.validate(&params)?;
    super::check_memory("family", isola::analysis::cost::family(&spec))?;
    let progress = std::sync::Arc::new(Progress::new(0));
    let ctx = JobContext::new(args.threads, progress.clone())?;
    let started = Instant::now();
    let name = args.vary.name();
    let members = ctx.run(|| {
        family(&params, &spec, &progress, |m| {
            out.show(&MemberSummary::of(name, m))
        })
    })??;
    let mut done = Done {
        elapsed_seconds: started.elapsed().as_secs_f64(),
        ..Done::default()
    };
    if let Some(path) = &args.csv {
        isola::session::export::family_csv(
            name,
            &members,
            &isola::session::export::ModelColumns::built_in(&isola::model::Device::default()),
            path,
        )?;
        done.wrote.push(path.clone());
    }
    out.report(&FamilySummary {
        model: Model::of(&params),
        omega: spec.response.omega,
        parameter: name,
        members: members.iter().map(|m| MemberSummary::of(name, m)).collect(),
        done,
    })
}

impl Summary for MemberSummary<'_> {
    fn print_text(&self) {
        let subs: Vec<String> = self
            .branches
            .iter()
            .filter(|b| b.branch.is_subharmonic())
            .map(|b| b.branch.describe())
            .collect();
        say!(
            "{} = {:<8} {}",
            self.parameter,
            self.value,
            if subs.is_empty() {
                "no subharmonic".into()
            } else {
                subs.join("; ")
            }
        );
    }
}

impl Summary for FamilySummary<'_> {
    /// The members were shown as each finished.
    fn print_text(&self) {
        say!(
            "{} members in {:.2} s",
            self.members.len(),
            self.done.elapsed_seconds
        );
        self.done.print_wrote();
    }
}
