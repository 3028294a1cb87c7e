//! The model flags every analysis command shares; defaults are the paper's baseline.

use clap::Args;
use isola::analysis::grid::Axis;
use isola::model::{Device, Params};
use isola::session::model_section::ModelSection;

use super::parse;

/// Model parameters. The drive is (--ea, --adr) or (--phi-dc, --phi-ac).
#[derive(Debug, Clone, Args)]
pub struct ModelArgs {
    /// Pre-stretch λ_p.
    #[arg(
        long = "lambda-p",
        default_value_t = 1.02,
        allow_negative_numbers = true,
        value_parser = parse::finite
    )]
    pub lambda_p: f64,
    /// Gent constant J.
    #[arg(long, default_value_t = 16.0, allow_negative_numbers = true, value_parser = parse::finite)]
    pub j: f64,
    /// Non-dimensional damping c̃.
    #[arg(long, default_value_t = 0.04, allow_negative_numbers = true, value_parser = parse::finite)]
    pub damping: f64,
    /// Mean-square voltage E_a = φ_DC² + φ_AC²/2.
    #[arg(long, default_value_t = 0.04, allow_negative_numbers = true, value_parser = parse::finite,
          conflicts_with_all = ["phi_dc", "phi_ac"])]
    pub ea: f64,
    /// AC-to-DC ratio ADR = φ_AC/φ_DC.
    #[arg(long, default_value_t = 0.6, allow_negative_numbers = true, value_parser = parse::finite,
          conflicts_with_all = ["phi_dc", "phi_ac"])]
    pub adr: f64,
    /// DC voltage φ_DC (non-dimensional); give with --phi-ac instead of --ea/--adr.
    #[arg(long = "phi-dc", requires = "phi_ac", allow_negative_numbers = true, value_parser = parse::finite)]
    pub phi_dc: Option<f64>,
    /// AC voltage amplitude φ_AC (non-dimensional).
    #[arg(long = "phi-ac", requires = "phi_dc", allow_negative_numbers = true, value_parser = parse::finite)]
    pub phi_ac: Option<f64>,
    /// Forcing frequency ω_e (non-dimensional, default 3.7); commands over many frequencies
    /// take a range START:END:STEP (response, family, stepped sweep) or START:END (chirp).
    #[arg(long, allow_hyphen_values = true)]
    pub omega: Option<String>,
    /// DC voltage on membrane II, φ_DC,II (default: membrane II undriven).
    #[arg(
        long = "phi-dc-ii",
        requires = "phi_ac_ii",
        allow_negative_numbers = true,
        value_parser = parse::finite
    )]
    pub phi_dc_ii: Option<f64>,
    /// AC voltage on membrane II, φ_AC,II.
    #[arg(
        long = "phi-ac-ii",
        requires = "phi_dc_ii",
        allow_negative_numbers = true,
        value_parser = parse::finite
    )]
    pub phi_ac_ii: Option<f64>,
    /// Phase lead of membrane II's AC voltage, radians.
    #[arg(
        long = "phase-ii",
        default_value_t = 0.0,
        allow_negative_numbers = true,
        value_parser = parse::finite
    )]
    pub phase_ii: f64,
}

impl ModelArgs {
    /// The validated parameters at the single --omega given (3.7 by default).
    pub fn params(&self) -> anyhow::Result<Params> {
        let omega = match &self.omega {
            None => 3.7,
            Some(text) => parse::finite(text).map_err(|e| {
                anyhow::anyhow!("--omega: {e}; this command takes one value, e.g. --omega 3.7")
            })?,
        };
        self.params_at(omega)
    }

    /// The text of --omega, or `default` when it was not given.
    pub fn omega_text<'a>(&'a self, default: &'a str) -> &'a str {
        self.omega.as_deref().unwrap_or(default)
    }

    /// The --omega range (or `default`) and the validated parameters at its first ω.
    pub fn omega_range(&self, default: &str) -> anyhow::Result<(Axis, Params)> {
        let omega =
            parse::range(self.omega_text(default)).map_err(|e| anyhow::anyhow!("--omega: {e}"))?;
        let params = self.params_at(omega.min)?;
        Ok((omega, params))
    }

    /// The validated parameters at forcing frequency `omega`, or an error naming the bad field;
    /// built like a session's `[model]` table, so both read a drive the same way.
    pub fn params_at(&self, omega: f64) -> anyhow::Result<Params> {
        let by_voltage = self.phi_dc.is_some();
        let section = ModelSection {
            lambda_p: Some(self.lambda_p),
            j: Some(self.j),
            c_tilde: Some(self.damping),
            omega: Some(omega),
            e_a: (!by_voltage).then_some(self.ea),
            adr: (!by_voltage).then_some(self.adr),
            phi_dc: self.phi_dc,
            phi_ac: self.phi_ac,
            phi_dc_ii: self.phi_dc_ii,
            phi_ac_ii: self.phi_ac_ii,
            phase_ii: Some(self.phase_ii),
            ..ModelSection::default()
        };
        section
            .to_spec(&Device::silicone())
            .and_then(|spec| spec.build())
            .map_err(|e| anyhow::anyhow!("{}", as_flag(e)))
    }
}

/// A model error named by the flag that sets the field (`adr` is `--adr`).
fn as_flag(mut e: isola::model::ParamError) -> isola::model::ParamError {
    let flag = match e.field.as_str() {
        "lambda_p" => "--lambda-p",
        "j" => "--j",
        "c_tilde" => "--damping",
        "omega" => "--omega",
        "e_a" => "--ea",
        "adr" => "--adr",
        "phi_dc" => "--phi-dc",
        "phi_ac" => "--phi-ac",
        "phi_dc_ii" => "--phi-dc-ii",
        "phi_ac_ii" => "--phi-ac-ii",
        "phase_ii" => "--phase-ii",
        _ => return e,
    };
    e.field = flag.into();
    e
}
