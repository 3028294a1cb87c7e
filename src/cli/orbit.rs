//! `isola orbit`: one trajectory to its steady state, classified.

use clap::Args;
use isola::analysis::orbit::period_map::Rk4PeriodMap;
use isola::analysis::orbit::time_history::{TimeHistorySpec, time_history};
use isola::analysis::{DopriPeriodMap, SteadyState, SteadyStateSpec, steady_state_with};
use isola::model::{Device, Params};
use isola::solver::{Resolution, Tolerance};
use serde::Serialize;

use super::model_args::ModelArgs;

#[derive(Debug, Args)]
pub struct OrbitArgs {
    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    start: super::start_ranges::Start,
    /// Longest response period (in forcing periods) still called periodic.
    #[arg(long = "max-period", default_value_t = 8)]
    max_period: usize,
    /// Forcing periods to integrate before calling the response non-periodic.
    #[arg(long = "max-periods", default_value_t = 6000)]
    max_periods: usize,
    /// Minimum RK4 steps per forcing period.
    #[arg(long = "steps-per-period", default_value_t = Resolution::default().min_steps_per_period)]
    steps_per_period: u32,
    /// Use the adaptive Dormand–Prince reference integrator (slower, error-controlled).
    #[arg(long)]
    reference: bool,
    /// Relative tolerance of the reference integrator.
    #[arg(long, default_value_t = 1e-10, requires = "reference", value_parser = super::parse::finite)]
    rtol: f64,
    /// Print one JSON object instead of a summary.
    #[arg(long)]
    json: bool,
    /// Write the time history and phase path (transient and steady part) to this CSV file.
    #[arg(long = "history-csv")]
    history_csv: Option<std::path::PathBuf>,
}

/// The JSON record of one orbit: the inputs and the classified steady state.
#[derive(Serialize)]
struct OrbitReport<'a> {
    lambda_p: f64,
    j: f64,
    c_tilde: f64,
    e_a: f64,
    adr: Option<f64>,
    phi_dc: f64,
    phi_ac: f64,
    omega: f64,
    x0: f64,
    v0: f64,
    integrator: &'static str,
    /// The paper's name for the response ("1:3 subharmonic"...).
    response_type: String,
    #[serde(flatten)]
    steady: &'a SteadyState,
}

pub fn run(args: &OrbitArgs) -> anyhow::Result<()> {
    super::check_outputs([args.history_csv.as_deref()])?;
    let params = args.model.params()?;
    let spec = SteadyStateSpec {
        max_period: args.max_period,
        max_forcing_periods: args.max_periods,
        resolution: Resolution {
            min_steps_per_period: args.steps_per_period,
            ..Resolution::default()
        },
        ..SteadyStateSpec::default()
    };
    spec.validate()?;
    let x0 = params.lambda_p() + args.start.x0;
    let steady = if args.reference {
        let tol = Tolerance {
            rtol: args.rtol,
            atol: args.rtol * 1e-2,
        };
        tol.validate()?;
        steady_state_with(
            &mut DopriPeriodMap::new(&params, tol, x0, args.start.v0),
            &spec,
        )
    } else {
        steady_state_with(
            &mut Rk4PeriodMap::new(&params, &spec.resolution, x0, args.start.v0),
            &spec,
        )
    };
    if let Some(path) = &args.history_csv {
        let spec = TimeHistorySpec {
            dx0: args.start.x0,
            v0: args.start.v0,
            steady: spec,
            ..TimeHistorySpec::default()
        };
        let history = time_history(&params, &spec)?;
        isola::session::export::history_csv(&history, &Device::silicone(), path)?;
        if !args.json {
            println!(
                "wrote {} ({} samples)",
                path.display(),
                history.samples.len()
            );
        }
    }
    if args.json {
        let d = params.drive_i();
        let report = OrbitReport {
            lambda_p: params.lambda_p(),
            j: params.j(),
            c_tilde: params.c_tilde(),
            e_a: d.e_a(),
            adr: d.adr(),
            phi_dc: d.phi_dc(),
            phi_ac: d.phi_ac(),
            omega: params.omega(),
            x0: args.start.x0,
            v0: args.start.v0,
            integrator: if args.reference { "dopri5" } else { "rk4" },
            response_type: steady.response_type(),
            steady: &steady,
        };
        println!("{}", serde_json::to_string(&report)?);
    } else {
        print_summary(&params, args, &steady);
    }
    Ok(())
}

fn print_summary(p: &Params, args: &OrbitArgs, s: &SteadyState) {
    let dev = Device::silicone();
    let d = p.drive_i();
    println!(
        "model      λ_p {}  J {}  c̃ {} ({:.3} N·s/m)",
        p.lambda_p(),
        p.j(),
        p.c_tilde(),
        dev.damping(p.c_tilde())
    );
    println!(
        "drive I    E_a {:.5}  ADR {}  φ_DC {:.4} ({:.2} kV)  φ_AC {:.4} ({:.2} kV)  peak {:.1} MV/m",
        d.e_a(),
        d.adr().map_or("-".into(), |a| format!("{a:.4}")),
        d.phi_dc(),
        dev.kv(d.phi_dc()),
        d.phi_ac(),
        dev.kv(d.phi_ac()),
        dev.mv_per_m(d.phi_peak()),
    );
    let dii = p.drive_ii();
    if !dii.is_off() {
        println!(
            "drive II   φ_DC {:.4} ({:.2} kV)  φ_AC {:.4} ({:.2} kV)  phase {:.3} rad",
            dii.phi_dc(),
            dev.kv(dii.phi_dc()),
            dii.phi_ac(),
            dev.kv(dii.phi_ac()),
            p.phase_ii()
        );
    }
    println!("forcing    ω_e {} ({:.2} Hz)", p.omega(), dev.hz(p.omega()));
    println!(
        "start      Δλ {}  v {}  at τ = 0",
        args.start.x0, args.start.v0
    );
    println!(
        "(physical units for the paper's silicone device: 20 × 200 × 0.1 mm, 50 g, μ 400 kPa)"
    );
    println!();
    if let Some(c) = s.collision {
        println!(
            "collision  the mass reached a frame at τ ≈ {:.3} ({:.4} s), λ_I = {:.4}, after {} forcing periods",
            c.tau,
            dev.seconds(c.tau),
            c.lambda_i,
            s.transient_periods
        );
        return;
    }
    match (s.period, s.ratio) {
        (Some(k), Some(r)) => println!(
            "response   periodic, period {k}: {} (strongest line ω_r:ω_e = {r})",
            s.response_type()
        ),
        _ => println!(
            "response   non-periodic (no period up to {} found in {} forcing periods)",
            args.max_period, args.max_periods
        ),
    }
    if let (Some(a), Some(lo), Some(hi), Some(mean)) =
        (s.amplitude, s.lambda_min, s.lambda_max, s.lambda_mean)
    {
        println!(
            "amplitude  {a:.6} ({:.3} mm)   λ_I in [{lo:.6}, {hi:.6}], mean {mean:.6}",
            a * dev.l1 * 1e3
        );
    }
    println!(
        "transient  {} forcing periods ({:.2} s)",
        s.transient_periods,
        dev.seconds(s.transient_periods as f64 * p.period())
    );
    for (i, pt) in s.poincare.iter().enumerate() {
        println!("poincaré   #{i}  λ_I {:.8}  v {:.8}", pt[0], pt[1]);
    }
}
