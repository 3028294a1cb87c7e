//! `isola model`: what the model's parameters imply before anything moves — the drive's
//! coefficients, the static equilibrium under the mean drive and the natural frequency.

use clap::Args;
use isola::model::Device;
use isola::model::statics::derived;
use serde::Serialize;

use super::model_args::ModelArgs;
use super::output::{Model, Output, Summary, hz};

#[derive(Debug, Args)]
pub struct ModelCmdArgs {
    #[command(flatten)]
    model: ModelArgs,
}

/// The derived quantities, non-dimensional and for the paper's device.
#[derive(Serialize)]
struct ModelSummary {
    #[serde(flatten)]
    model: Model,
    e_b: f64,
    e_c: f64,
    /// λ_I* under the mean drive; none when the mean drive pulls the mass onto a frame.
    lambda_i_equilibrium: Option<f64>,
    /// Linear natural frequency ω₀ about λ_I*, and 2ω₀ where the principal parametric
    /// resonance lies; none without a linear restoring force there.
    omega_0: Option<f64>,
    omega_parametric: Option<f64>,
    physical: Physical,
}

/// The same in the units of the paper's silicone device.
#[derive(Serialize)]
struct Physical {
    phi_dc_kv: f64,
    phi_ac_kv: f64,
    omega_0_hz: Option<f64>,
    omega_parametric_hz: Option<f64>,
}

pub fn run(args: &ModelCmdArgs, out: Output) -> anyhow::Result<()> {
    let params = args.model.params()?;
    let d = derived(&params);
    let omega_0 = d.equilibrium.and_then(|e| e.omega_0);
    let omega_parametric = omega_0.map(|w| 2.0 * w);
    let dev = Device::silicone();
    out.report(&ModelSummary {
        model: Model::of(&params),
        e_b: d.e_b,
        e_c: d.e_c,
        lambda_i_equilibrium: d.equilibrium.map(|e| e.lambda_i),
        omega_0,
        omega_parametric,
        physical: Physical {
            phi_dc_kv: dev.kv(d.phi_dc),
            phi_ac_kv: dev.kv(d.phi_ac),
            omega_0_hz: omega_0.map(hz),
            omega_parametric_hz: omega_parametric.map(hz),
        },
    })
}

impl Summary for ModelSummary {
    fn print_text(&self) {
        let (m, ph) = (&self.model, &self.physical);
        say!("model      λ_p {}  J {}  c̃ {}", m.lambda_p, m.j, m.c_tilde);
        say!(
            "drive I    E_a {:.6}  E_b {:.6}  E_c {:.6}  ADR {}",
            m.e_a,
            self.e_b,
            self.e_c,
            m.adr.map_or("-".into(), |a| format!("{a:.4}")),
        );
        say!(
            "           φ_DC {:.6} ({:.3} kV)  φ_AC {:.6} ({:.3} kV)",
            m.phi_dc,
            ph.phi_dc_kv,
            m.phi_ac,
            ph.phi_ac_kv
        );
        match self.lambda_i_equilibrium {
            Some(lambda) => say!(
                "statics    λ_I* {lambda:.10} (Δλ {:+.3e}) under the mean drive",
                lambda - m.lambda_p
            ),
            None => {
                say!("statics    no equilibrium: the mean drive pulls the mass onto a frame")
            }
        }
        match (
            self.omega_0,
            self.omega_parametric,
            ph.omega_0_hz,
            ph.omega_parametric_hz,
        ) {
            (Some(w0), Some(w2), Some(hz0), Some(hz2)) => {
                say!("natural    ω₀ {w0:.8} ({hz0:.3} Hz)");
                say!("parametric 2ω₀ {w2:.8} ({hz2:.3} Hz), the principal parametric resonance");
            }
            _ if self.lambda_i_equilibrium.is_some() => say!(
                "natural    none: no linear restoring force there (a membrane exactly at loss of \
                 tension, or both slack)"
            ),
            _ => {}
        }
        say!(
            "(physical units for the paper's silicone device: 20 × 200 × 0.1 mm, 50 g, μ 400 kPa)"
        );
    }
}
