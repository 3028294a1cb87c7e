//! How a command reports its result: the summary a person reads (the default), one JSON
//! document (`--json`) or nothing (`--quiet`). Each command builds one summary value, the
//! text and the JSON both come from it, and [`Output::report`] prints one or the other.

use std::io::Write;
use std::path::PathBuf;
use std::sync::OnceLock;

use isola::model::{Device, Params};
use serde::Serialize;

/// Why stdout stopped taking lines, once it has.
static STDOUT_FAILED: OnceLock<String> = OnceLock::new();

/// Prints a line on stdout (the `say!` macro). The first failure (a full disk, a closed
/// descriptor) is kept and nothing more is printed: the command's work goes on, and it ends
/// with that error ([`stdout_failure`]) instead of a panic half-way.
pub fn print_line(line: std::fmt::Arguments) {
    if STDOUT_FAILED.get().is_some() {
        return;
    }
    let mut out = std::io::stdout().lock();
    let written = out
        .write_fmt(line)
        .and_then(|()| out.write_all(b"\n"))
        .and_then(|()| out.flush());
    if let Err(e) = written {
        let _ = STDOUT_FAILED.set(e.to_string());
    }
}

/// The failure that stopped printing, if one did.
pub fn stdout_failure() -> Option<&'static str> {
    STDOUT_FAILED.get().map(String::as_str)
}

/// How a command reports, from the global flags `--json` and `--quiet`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    /// The human summary on stdout, progress on stderr.
    Text,
    /// The summary as one JSON document on one line of stdout; progress on stderr as in text.
    Json,
    /// Nothing on stdout or stderr but errors.
    Quiet,
}

/// A command's summary: serialised as it is for `--json`, printed as lines for a person.
pub trait Summary: Serialize {
    /// Prints the human summary on stdout.
    fn print_text(&self);
}

impl Output {
    /// The mode the flags ask for (clap refuses both at once).
    pub fn new(json: bool, quiet: bool) -> Self {
        match (json, quiet) {
            (true, _) => Output::Json,
            (_, true) => Output::Quiet,
            _ => Output::Text,
        }
    }

    /// Reports a finished command: its text, its JSON document, or nothing.
    pub fn report(self, summary: &impl Summary) -> anyhow::Result<()> {
        match self {
            Output::Text => summary.print_text(),
            Output::Json => say!("{}", serde_json::to_string(summary)?),
            Output::Quiet => {}
        }
        Ok(())
    }

    /// Prints a part of a long command's summary as soon as it is known (a family's member,
    /// a session's analysis), in text mode only: the JSON document carries it at the end.
    pub fn show(self, part: &impl Summary) {
        if self == Output::Text {
            part.print_text();
        }
    }

    /// Whether progress may be shown on stderr.
    pub fn shows_progress(self) -> bool {
        self != Output::Quiet
    }
}

/// The model parameters of a summary but ω_e, which each command reports in its own way
/// (one value, a grid, a chirp's ends). Flattened into the summary: `"adr": 0.6, ...`.
#[derive(Debug, Serialize)]
pub struct Model {
    pub lambda_p: f64,
    pub j: f64,
    pub c_tilde: f64,
    pub e_a: f64,
    /// None where the drive was given as voltages with φ_DC = 0.
    pub adr: Option<f64>,
    pub phi_dc: f64,
    pub phi_ac: f64,
    /// Membrane II's drive: none where it is undriven.
    pub phi_dc_ii: Option<f64>,
    pub phi_ac_ii: Option<f64>,
    pub phase_ii: Option<f64>,
}

impl Model {
    /// The parameters of `p`.
    pub fn of(p: &Params) -> Self {
        let (d, dii) = (p.drive_i(), p.drive_ii());
        let ii = |x: f64| (!dii.is_off()).then_some(x);
        Model {
            lambda_p: p.lambda_p(),
            j: p.j(),
            c_tilde: p.c_tilde(),
            e_a: d.e_a(),
            adr: d.adr(),
            phi_dc: d.phi_dc(),
            phi_ac: d.phi_ac(),
            phi_dc_ii: ii(dii.phi_dc()),
            phi_ac_ii: ii(dii.phi_ac()),
            phase_ii: ii(p.phase_ii()),
        }
    }
}

/// What every summary ends with: the files written, in order, and the seconds the command
/// took. Flattened into the summary: `"wrote": [...], "elapsed_seconds": 1.2`.
#[derive(Debug, Default, Serialize)]
pub struct Done {
    pub wrote: Vec<PathBuf>,
    pub elapsed_seconds: f64,
}

impl Done {
    /// Prints `wrote FILE` for each file written.
    pub fn print_wrote(&self) {
        for path in &self.wrote {
            say!("wrote {}", path.display());
        }
    }
}

/// ω_e in Hz for the paper's silicone device, as the summaries show it.
pub fn hz(omega: f64) -> f64 {
    Device::silicone().hz(omega)
}
