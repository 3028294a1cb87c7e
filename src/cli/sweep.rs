//! `isola sweep`: frequency sweeps, as a chirp (with envelope and scalogram) or stepped (Fig 3).

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use clap::Args;
use isola::analysis::SteadyState;
use isola::analysis::global::stepped_sweep::{StepJump, SweepFindings, TypePeak, stepped_sweep};
use isola::analysis::grid::Axis;
use isola::analysis::orbit::chirp_sweep::{
    ChirpFindings, ChirpSpec, DEFAULT_JUMP_RATIO, Direction, check_jump_ratio, chirp_sweep,
};
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
    /// Write the chirp's Morlet scalogram (one row per time × frequency) to this CSV file,
    /// and its ridge (one row per time: ω_e, the strongest ω_r, their ratio) beside it in
    /// `FILE.ridge.csv`.
    #[arg(long = "scalogram-csv")]
    scalogram_csv: Option<PathBuf>,
    /// A jump changes the envelope (chirp) or the amplitude between steps (stepped) by at
    /// least this factor.
    #[arg(long = "jump-ratio", default_value_t = DEFAULT_JUMP_RATIO, value_parser = super::parse::finite)]
    jump_ratio: f64,
}

/// A stepped sweep: each step's steady state.
#[derive(Serialize)]
struct SteppedSummary<'a> {
    stepped: bool,
    #[serde(flatten)]
    model: Model,
    steps: Vec<StepSummary<'a>>,
    /// Jumps between neighbouring steps (response type or amplitude), in the sweep's order.
    jumps: &'a [StepJump],
    /// Each response type's largest amplitude.
    peaks: &'a [TypePeak],
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

/// A chirp: its span, samples, where it met a frame, its largest envelope, the range of λ_I
/// and the jumps of its envelope.
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
    /// Where the mass met a frame, if it did (the record stops there), and ω_e there.
    collision_tau: Option<f64>,
    collision_omega: Option<f64>,
    /// The largest envelope (max − min of λ_I over a window) and the window's ω_e and τ.
    largest_envelope: f64,
    largest_envelope_omega: f64,
    largest_envelope_tau: f64,
    lambda_min: f64,
    lambda_max: f64,
    jump_ratio: f64,
    /// The envelope's jumps, in the sweep's order.
    jumps: Vec<ChirpJump>,
    #[serde(flatten)]
    done: Done,
}

/// A jump of the chirp's envelope, with its time in seconds and ω_e in Hz.
#[derive(Serialize)]
struct ChirpJump {
    direction: Direction,
    window: usize,
    tau: f64,
    time_s: f64,
    omega: f64,
    frequency_hz: f64,
    envelope_before: f64,
    envelope_after: f64,
}

impl ChirpJump {
    fn all(found: &ChirpFindings, dev: &Device) -> Vec<ChirpJump> {
        found
            .jumps
            .iter()
            .map(|j| ChirpJump {
                direction: j.direction,
                window: j.window,
                tau: j.tau,
                time_s: dev.seconds(j.tau),
                omega: j.omega,
                frequency_hz: dev.hz(j.omega),
                envelope_before: j.amplitude_before,
                envelope_after: j.amplitude_after,
            })
            .collect()
    }
}

pub fn run(args: &SweepArgs, out: Output) -> anyhow::Result<()> {
    super::check_outputs([args.csv.as_deref(), args.scalogram_csv.as_deref()])?;
    check_jump_ratio(args.jump_ratio).map_err(|mut e| {
        e.field = "--jump-ratio".into();
        e
    })?;
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
    let params = args
        .model
        .params_at(first.max(isola::model::limits::OMEGA.0))?;
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
        let found = SweepFindings::of(&steps, args.jump_ratio);
        if let Some(path) = &args.csv {
            done.wrote.extend(isola::session::export::stepped_csv(
                &steps,
                &found,
                &isola::session::export::ModelColumns::built_in(&dev),
                path,
            )?);
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
            jumps: &found.jumps,
            peaks: &found.peaks,
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
        jump_ratio: args.jump_ratio,
        ..ChirpSpec::default()
    };
    parse::set_resolution(&mut spec, args.resolution)?;
    let sweep = chirp_sweep(&params, &spec, &never, |_| {})?;
    done.elapsed_seconds = started.elapsed().as_secs_f64();
    let columns = isola::session::export::ModelColumns::built_in(&dev);
    if let Some(path) = &args.csv {
        done.wrote
            .extend(isola::session::export::chirp_csv(&sweep, &columns, path)?);
    }
    if let Some(path) = &args.scalogram_csv {
        let sc = scalogram(&sweep.lambda, sweep.dt, &ScalogramSpec::default())?;
        done.wrote.extend(isola::session::export::scalogram_csv(
            &sc, &sweep, &columns, path,
        )?);
    }
    let found = &sweep.findings;
    out.report(&ChirpSummary {
        stepped: false,
        model: Model::of(&params),
        omega_start: a,
        omega_end: b,
        span: args.span,
        span_seconds: dev.seconds(args.span),
        window: args.window,
        samples: sweep.lambda.len(),
        collision_tau: found.collision.map(|c| c.tau),
        collision_omega: found.collision.map(|c| c.omega),
        largest_envelope: found.peak_amplitude,
        largest_envelope_omega: found.peak_omega,
        largest_envelope_tau: found.peak_tau,
        lambda_min: found.lambda_min,
        lambda_max: found.lambda_max,
        jump_ratio: args.jump_ratio,
        jumps: ChirpJump::all(found, &dev),
        done,
    })
}

impl Summary for SteppedSummary<'_> {
    fn print_text(&self) {
        say!(
            "stepped sweep, {} steps in {:.2} s",
            self.steps.len(),
            self.done.elapsed_seconds
        );
        for s in &self.steps {
            say!(
                "  ω_e {:.3} ({:.2} Hz)  {:<18} amplitude {}",
                s.omega,
                s.frequency_hz,
                s.response_type,
                s.steady.amplitude.map_or("-".into(), |a| format!("{a:.5}"))
            );
        }
        let amplitude = |a: Option<f64>| a.map_or("-".into(), |a| format!("{a:.5}"));
        say!("jumps between steps: {}", self.jumps.len());
        for j in self.jumps {
            say!(
                "  {} ω_e {:.3} → {:.3}: {} {} → {} {}",
                j.direction.map_or("type", |d| d.as_str()),
                j.omega_before,
                j.omega_after,
                j.type_before,
                amplitude(j.amplitude_before),
                j.type_after,
                amplitude(j.amplitude_after)
            );
        }
        say!("peak amplitude per response type:");
        for p in self.peaks {
            say!(
                "  {:<18} {:.5} at ω_e {:.3} ({} steps)",
                p.response_type,
                p.peak_amplitude,
                p.peak_omega,
                p.steps
            );
        }
        self.done.print_wrote();
    }
}

impl Summary for ChirpSummary {
    fn print_text(&self) {
        say!(
            "chirp ω_e {} → {} over τ = {} ({:.1} s): {} samples in {:.2} s{}",
            self.omega_start,
            self.omega_end,
            self.span,
            self.span_seconds,
            self.samples,
            self.done.elapsed_seconds,
            self.collision_tau
                .zip(self.collision_omega)
                .map_or(String::new(), |(t, w)| format!(
                    ", hit a frame at τ = {t:.1} (ω_e {w:.3})"
                ))
        );
        say!(
            "  largest envelope {:.4} at ω_e {:.3}; λ_I from {:.4} to {:.4}",
            self.largest_envelope,
            self.largest_envelope_omega,
            self.lambda_min,
            self.lambda_max
        );
        say!(
            "  jumps of the envelope (×{} or more): {}",
            self.jump_ratio,
            self.jumps.len()
        );
        for j in &self.jumps {
            say!(
                "  {:<4} at ω_e {:.3} ({:.2} Hz), τ {:.0} ({:.2} s): envelope {:.4} → {:.4}",
                j.direction.as_str(),
                j.omega,
                j.frequency_hz,
                j.tau,
                j.time_s,
                j.envelope_before,
                j.envelope_after
            );
        }
        self.done.print_wrote();
    }
}
