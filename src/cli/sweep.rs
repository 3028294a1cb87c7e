//! `isola sweep`: frequency sweeps, as a chirp (with envelope and scalogram) or stepped (Fig 3).

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use clap::Args;
use isola::analysis::SteadyState;
use isola::analysis::global::stepped_sweep::stepped_sweep;
use isola::analysis::grid::Axis;
use isola::analysis::orbit::chirp_sweep::{ChirpSpec, chirp_sweep};
use isola::analysis::orbit::scalogram::{ScalogramSpec, scalogram};
use isola::analysis::resolution::ResolutionSetting;
use isola::model::Device;
use serde::Serialize;

use super::model_args::ModelArgs;
use super::output::{Done, Model, Output, Summary};
use super::parse;

#[derive(Debug, Args)]
pub struct SweepArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Duration of the chirp in τ.
    #[arg(long, default_value_t = 12000.0, value_parser = super::parse::finite)]
    span: f64,
    /// Step through the frequencies, settling to steady state at each (instead of a chirp).
    #[arg(long)]
    stepped: bool,
    /// Envelope window of the chirp, in τ.
    #[arg(long, default_value_t = 20.0, value_parser = super::parse::finite)]
    window: f64,
    /// The integrator's resolution, as a session's `resolution` setting: RK4 steps per
    /// forcing period (`128`; default 64, steps also at most 3.2/N long) for --stepped; for a chirp the Dormand–Prince tolerance (`rtol=1e-12`; default rtol=1e-8).
    #[arg(long, value_name = "N|rtol=X", value_parser = super::parse::resolution)]
    resolution: Option<ResolutionSetting>,
    /// Write the samples with their envelope (chirp) or the steps (stepped) to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Write the chirp's Morlet scalogram (one row per time × frequency) to this CSV file.
    #[arg(long = "scalogram-csv")]
    scalogram_csv: Option<PathBuf>,
}

/// A stepped sweep: each step's steady state.
#[derive(Serialize)]
struct SteppedSummary<'a> {
    stepped: bool,
    #[serde(flatten)]
    model: Model,
    steps: Vec<StepSummary<'a>>,
    #[serde(flatten)]
    done: Done,
}

/// One step: ω_e and the steady state it settled to (its fields as `orbit`'s).
#[derive(Serialize)]
struct StepSummary<'a> {
    omega: f64,
    frequency_hz: f64,
    /// The step began from rest because the previous one ended on a frame.
    restarted: bool,
    response_type: String,
    #[serde(flatten)]
    steady: &'a SteadyState,
}

/// A chirp: its span, samples, where it met a frame and its largest envelope.
#[derive(Serialize)]
struct ChirpSummary {
    stepped: bool,
    #[serde(flatten)]
    model: Model,
    omega_start: f64,
    omega_end: f64,
    span: f64,
    span_seconds: f64,
    window: f64,
    samples: usize,
    /// Where the mass met a frame, if it did (the record stops there).
    collision_tau: Option<f64>,
    /// The largest envelope (max − min of λ_I over a window) and the window's ω_e and τ.
    largest_envelope: f64,
    largest_envelope_omega: f64,
    largest_envelope_tau: f64,
    #[serde(flatten)]
    done: Done,
}

pub fn run(args: &SweepArgs, out: Output) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref(), args.scalogram_csv.as_deref()])?;
    let omega_text = args
        .model
        .omega_text(if args.stepped { "0.2:6.0:0.05" } else { "0:6" });
    let first = omega_text
        .split(':')
        .next()
        .unwrap_or("")
        .trim()
        .parse::<f64>()
        .unwrap_or(0.0);
    // ω_e of the parameter set only seeds validation; the sweep sets its own
    let params = args.model.params_at(first.max(1e-3))?;
    let never = AtomicBool::new(false);
    let dev = Device::silicone();
    let started = Instant::now();
    let mut done = Done::default();
    if args.stepped {
        let axis: Axis = parse::range(omega_text).map_err(|e| anyhow::anyhow!("--omega: {e}"))?;
        let mut spec = isola::session::schema::SteppedSweepSpec {
            omega: axis,
            ..Default::default()
        };
        parse::set_resolution(&mut spec, args.resolution)?;
        let omegas: Vec<f64> = axis.values();
        let start = [params.lambda_p(), 0.0];
        let steps = stepped_sweep(&params, &omegas, start, &spec.steady, &never, |_| {})?;
        done.elapsed_seconds = started.elapsed().as_secs_f64();
        if let Some(path) = &args.csv {
            isola::session::export::stepped_csv(
                &steps,
                &isola::session::export::ModelColumns::built_in(&dev),
                path,
            )?;
            done.wrote.push(path.clone());
        }
        let steps = steps
            .iter()
            .map(|s| StepSummary {
                omega: s.omega,
                frequency_hz: dev.hz(s.omega),
                restarted: s.restarted,
                response_type: s.steady.response_type(),
                steady: &s.steady,
            })
            .collect();
        return out.report(&SteppedSummary {
            stepped: true,
            model: Model::of(&params),
            steps,
            done,
        });
    }
    let (a, b) = parse::interval_any(omega_text)
        .map_err(|e| anyhow::anyhow!("--omega: {e} (a chirp takes START:END)"))?;
    let mut spec = ChirpSpec {
        omega_start: a,
        omega_end: b,
        span: args.span,
        window: args.window,
        ..ChirpSpec::default()
    };
    parse::set_resolution(&mut spec, args.resolution)?;
    let sweep = chirp_sweep(&params, &spec, &never, |_| {})?;
    done.elapsed_seconds = started.elapsed().as_secs_f64();
    let peak = sweep
        .envelope
        .iter()
        .fold([0.0; 3], |m, e| if e[2] > m[2] { *e } else { m });
    if let Some(path) = &args.csv {
        isola::session::export::chirp_csv(&sweep, &dev, path)?;
        done.wrote.push(path.clone());
    }
    if let Some(path) = &args.scalogram_csv {
        let sc = scalogram(&sweep.lambda, sweep.dt, &ScalogramSpec::default())?;
        let omega_e = |t: f64| a + (b - a) * (t / args.span).clamp(0.0, 1.0);
        isola::session::export::write_atomic(path, |w| {
            w.write_record([
                "tau",
                "omega_e",
                "omega_r",
                "magnitude_stretch",
                "ridge_ratio",
            ])?;
            for (c, &t) in sc.times.iter().enumerate() {
                for (f, &om) in sc.frequencies.iter().enumerate() {
                    w.write_record([
                        format!("{t:.3}"),
                        format!("{:.6}", omega_e(t)),
                        format!("{om:.6}"),
                        format!("{:.9}", sc.magnitude[f][c]),
                        format!("{:.4}", sc.ridge[c] / omega_e(t)),
                    ])?;
                }
            }
            Ok(())
        })?;
        done.wrote.push(path.clone());
    }
    out.report(&ChirpSummary {
        stepped: false,
        model: Model::of(&params),
        omega_start: a,
        omega_end: b,
        span: args.span,
        span_seconds: dev.seconds(args.span),
        window: args.window,
        samples: sweep.lambda.len(),
        collision_tau: sweep.collision_tau,
        largest_envelope: peak[2],
        largest_envelope_omega: peak[1],
        largest_envelope_tau: peak[0],
        done,
    })
}

impl Summary for SteppedSummary<'_> {
    fn print_text(&self) {
        println!(
            "stepped sweep, {} steps in {:.2} s",
            self.steps.len(),
            self.done.elapsed_seconds
        );
        for s in &self.steps {
            println!(
                "  ω_e {:.3} ({:.2} Hz)  {:<18} amplitude {}",
                s.omega,
                s.frequency_hz,
                s.response_type,
                s.steady.amplitude.map_or("-".into(), |a| format!("{a:.5}"))
            );
        }
        self.done.print_wrote();
    }
}

impl Summary for ChirpSummary {
    fn print_text(&self) {
        println!(
            "chirp ω_e {} → {} over τ = {} ({:.1} s): {} samples in {:.2} s{}",
            self.omega_start,
            self.omega_end,
            self.span,
            self.span_seconds,
            self.samples,
            self.done.elapsed_seconds,
            self.collision_tau
                .map_or(String::new(), |t| format!(", hit a frame at τ = {t:.1}"))
        );
        println!(
            "  largest envelope {:.4} at ω_e {:.3}",
            self.largest_envelope, self.largest_envelope_omega
        );
        self.done.print_wrote();
    }
}
