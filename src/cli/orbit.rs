//! `isola orbit`: one trajectory to its steady state, classified.

use std::time::Instant;

use clap::Args;
use isola::analysis::orbit::period_map::Rk4PeriodMap;
use isola::analysis::orbit::time_history::{SAMPLES_PER_PERIOD, TimeHistorySpec, time_history};
use isola::analysis::resolution::ResolutionSetting;
use isola::analysis::{DopriPeriodMap, SteadyState, SteadyStateSpec, steady_state_with};
use isola::model::{Device, Params};
use isola::solver::Resolution;
use serde::Serialize;

use super::model_args::ModelArgs;
use super::output::{Done, Model, Output, Summary};

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
    /// Minimum RK4 steps per forcing period (steps at most 0.05 long; --resolution N makes
    /// them at most 3.2/N).
    #[arg(long = "steps-per-period", default_value_t = Resolution::default().min_steps_per_period,
          conflicts_with = "resolution")]
    steps_per_period: u32,
    /// Use the adaptive Dormand–Prince reference integrator (slower, error-controlled).
    #[arg(long, conflicts_with = "resolution")]
    reference: bool,
    /// Relative tolerance of the reference integrator.
    #[arg(long, default_value_t = 1e-10, requires = "reference", value_parser = super::parse::finite)]
    rtol: f64,
    /// The integrator's resolution, as a session's `resolution` setting: RK4 with N steps per
    /// forcing period (`128`; default 64, steps also at most 3.2/N long) or the Dormand–Prince
    /// reference with that tolerance (`rtol=1e-12`: --reference --rtol 1e-12).
    #[arg(long, value_name = "N|rtol=X", value_parser = super::parse::resolution)]
    resolution: Option<ResolutionSetting>,
    /// Write the time history and phase path (transient and steady part) to this CSV file.
    #[arg(long = "history-csv")]
    history_csv: Option<std::path::PathBuf>,
    /// Samples of the time history per forcing period (4 to 4096).
    #[arg(long = "samples-per-period", value_name = "N", value_parser = samples_per_period,
          default_value_t = TimeHistorySpec::default().samples_per_period, requires = "history_csv")]
    samples_per_period: usize,
}

/// A whole number of samples per forcing period in [`SAMPLES_PER_PERIOD`].
fn samples_per_period(s: &str) -> Result<usize, String> {
    let (lo, hi) = SAMPLES_PER_PERIOD;
    s.trim()
        .parse()
        .ok()
        .filter(|n| (lo..=hi).contains(n))
        .ok_or_else(|| format!("'{s}' is not a whole number in [{lo}, {hi}]"))
}

/// One orbit: the inputs, the classified steady state, and the same in the paper's device's
/// units.
#[derive(Serialize)]
struct OrbitSummary {
    #[serde(flatten)]
    model: Model,
    omega: f64,
    x0: f64,
    v0: f64,
    integrator: &'static str,
    max_period: usize,
    max_forcing_periods: usize,
    /// The paper's name for the response ("1:3 subharmonic"...).
    response_type: String,
    #[serde(flatten)]
    steady: SteadyState,
    /// Samples of the time history written with --history-csv.
    history_samples: Option<usize>,
    physical: Physical,
    #[serde(flatten)]
    done: Done,
}

/// The orbit's numbers in the units of the paper's silicone device (20 × 200 × 0.1 mm, 50 g,
/// μ 400 kPa).
#[derive(Serialize)]
struct Physical {
    damping_n_s_per_m: f64,
    phi_dc_kv: f64,
    phi_ac_kv: f64,
    peak_field_mv_per_m: f64,
    phi_dc_ii_kv: Option<f64>,
    phi_ac_ii_kv: Option<f64>,
    frequency_hz: f64,
    amplitude_mm: Option<f64>,
    transient_seconds: f64,
    collision_seconds: Option<f64>,
}

impl Physical {
    fn of(p: &Params, s: &SteadyState) -> Self {
        let dev = Device::silicone();
        let (d, dii) = (p.drive_i(), p.drive_ii());
        let ii = |phi: f64| (!dii.is_off()).then(|| dev.kv(phi));
        Physical {
            damping_n_s_per_m: dev.damping(p.c_tilde()),
            phi_dc_kv: dev.kv(d.phi_dc()),
            phi_ac_kv: dev.kv(d.phi_ac()),
            peak_field_mv_per_m: dev.mv_per_m(d.phi_peak()),
            phi_dc_ii_kv: ii(dii.phi_dc()),
            phi_ac_ii_kv: ii(dii.phi_ac()),
            frequency_hz: dev.hz(p.omega()),
            amplitude_mm: s.amplitude.map(|a| a * dev.l1 * 1e3),
            transient_seconds: dev.seconds(s.transient_periods as f64 * p.period()),
            collision_seconds: s.collision.map(|c| dev.seconds(c.tau)),
        }
    }
}

pub fn run(args: &OrbitArgs, out: Output) -> anyhow::Result<()> {
    let started = Instant::now();
    super::check_outputs([args.history_csv.as_deref()])?;
    let params = args.model.params()?;
    let (resolution, reference) = match args.resolution {
        Some(ResolutionSetting::StepsPerPeriod(n)) => (Resolution::steps(n), None),
        Some(ResolutionSetting::Reference { rtol }) => (Resolution::default(), Some(rtol)),
        None => (
            Resolution {
                min_steps_per_period: args.steps_per_period,
                ..Resolution::default()
            },
            args.reference.then_some(args.rtol),
        ),
    };
    let spec = SteadyStateSpec {
        max_period: args.max_period,
        max_forcing_periods: args.max_periods,
        resolution,
        ..SteadyStateSpec::default()
    };
    spec.validate()?;
    let history_spec = TimeHistorySpec {
        dx0: args.start.x0,
        v0: args.start.v0,
        samples_per_period: args.samples_per_period,
        steady: spec,
        ..TimeHistorySpec::default()
    };
    history_spec.validate()?;
    let x0 = params.lambda_p() + args.start.x0;
    let steady = if let Some(rtol) = reference {
        let tol = ResolutionSetting::tolerance(rtol);
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
    let mut done = Done::default();
    let mut history_samples = None;
    if let Some(path) = &args.history_csv {
        let history = time_history(&params, &history_spec)?;
        isola::session::export::history_csv(&history, &Device::silicone(), path)?;
        history_samples = Some(history.samples.len());
        done.wrote.push(path.clone());
    }
    done.elapsed_seconds = started.elapsed().as_secs_f64();
    out.report(&OrbitSummary {
        model: Model::of(&params),
        omega: params.omega(),
        x0: args.start.x0,
        v0: args.start.v0,
        integrator: if reference.is_some() { "dopri5" } else { "rk4" },
        max_period: args.max_period,
        max_forcing_periods: args.max_periods,
        response_type: steady.response_type(),
        physical: Physical::of(&params, &steady),
        steady,
        history_samples,
        done,
    })
}

impl Summary for OrbitSummary {
    fn print_text(&self) {
        let (m, s, ph) = (&self.model, &self.steady, &self.physical);
        if let (Some(path), Some(n)) = (self.done.wrote.first(), self.history_samples) {
            say!("wrote {} ({n} samples)", path.display());
        }
        say!(
            "model      λ_p {}  J {}  c̃ {} ({:.3} N·s/m)",
            m.lambda_p,
            m.j,
            m.c_tilde,
            ph.damping_n_s_per_m
        );
        say!(
            "drive I    E_a {:.5}  ADR {}  φ_DC {:.4} ({:.2} kV)  φ_AC {:.4} ({:.2} kV)  peak {:.1} MV/m",
            m.e_a,
            m.adr.map_or("-".into(), |a| format!("{a:.4}")),
            m.phi_dc,
            ph.phi_dc_kv,
            m.phi_ac,
            ph.phi_ac_kv,
            ph.peak_field_mv_per_m,
        );
        if let (Some(dc), Some(ac), Some(phase), Some(dc_kv), Some(ac_kv)) = (
            m.phi_dc_ii,
            m.phi_ac_ii,
            m.phase_ii,
            ph.phi_dc_ii_kv,
            ph.phi_ac_ii_kv,
        ) {
            say!(
                "drive II   φ_DC {dc:.4} ({dc_kv:.2} kV)  φ_AC {ac:.4} ({ac_kv:.2} kV)  phase {phase:.3} rad"
            );
        }
        say!("forcing    ω_e {} ({:.2} Hz)", self.omega, ph.frequency_hz);
        say!("start      Δλ {}  v {}  at τ = 0", self.x0, self.v0);
        say!(
            "(physical units for the paper's silicone device: 20 × 200 × 0.1 mm, 50 g, μ 400 kPa)"
        );
        say!();
        if let (Some(c), Some(seconds)) = (s.collision, ph.collision_seconds) {
            // located within its step: in forcing period n (from 1); λ_I at the frame, as 0
            // rather than a rounded -0.0000
            let period = 2.0 * std::f64::consts::PI / self.omega;
            let n = (c.tau / period).floor() as u64 + 1;
            let lambda_i = (c.lambda_i * 1e4).round() / 1e4 + 0.0;
            say!(
                "collision  the mass left the model at τ = {:.6} ({seconds:.4} s, in forcing period {n}), λ_I = {lambda_i:.4}",
                c.tau
            );
            return;
        }
        match (s.period, s.ratio) {
            (Some(k), Some(r)) => say!(
                "response   periodic, period {k}: {} (strongest line ω_r:ω_e = {r})",
                self.response_type
            ),
            _ => say!(
                "response   non-periodic (no period up to {} found in {} forcing periods)",
                self.max_period,
                self.max_forcing_periods
            ),
        }
        if let (Some(a), Some(mm), Some(lo), Some(hi), Some(mean)) = (
            s.amplitude,
            ph.amplitude_mm,
            s.lambda_min,
            s.lambda_max,
            s.lambda_mean,
        ) {
            say!("amplitude  {a:.6} ({mm:.3} mm)   λ_I in [{lo:.6}, {hi:.6}], mean {mean:.6}");
        }
        say!(
            "transient  {} forcing periods ({:.2} s)",
            s.transient_periods,
            ph.transient_seconds
        );
        for (i, pt) in s.poincare.iter().enumerate() {
            say!("poincaré   #{i}  λ_I {:.8}  v {:.8}", pt[0], pt[1]);
        }
    }
}
