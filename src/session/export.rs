//! Tidy CSV for every result (one header row naming units), written atomically.

use std::path::{Path, PathBuf};

use crate::analysis::continuation::isola_limits::IsolaLimit;
use crate::analysis::global::basin::Basin;
use crate::analysis::global::frequency_response::{FrequencyResponse, Response};
use crate::analysis::{Class, SteadyState};
use crate::model::Device;
use crate::model::system::outside_grid;

/// Writes a CSV file whole (see [`super::output`]: a regular file is replaced atomically, a
/// FIFO or device written through): the rows are built in memory, so a failure while filling
/// leaves the old file as it was.
pub fn write_atomic(
    path: &Path,
    fill: impl FnOnce(&mut csv::Writer<&mut Vec<u8>>) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let bytes = csv_bytes(fill)?;
    super::output::write_output(path, &bytes, &super::output::Protected::none())?;
    Ok(())
}

/// The bytes of a CSV file filled by `fill`.
pub fn csv_bytes(
    fill: impl FnOnce(&mut csv::Writer<&mut Vec<u8>>) -> anyhow::Result<()>,
) -> anyhow::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    {
        let mut w = csv::Writer::from_writer(&mut bytes);
        fill(&mut w)?;
        w.flush()?;
    }
    Ok(bytes)
}

/// A number as the shortest text that reads back to exactly the same f64 (`0.1`, `1e-12`,
/// `3.7`): nothing a result computed is lost in its CSV.
pub fn num(x: f64) -> String {
    if x.is_finite() {
        ryu::Buffer::new().format_finite(x).to_string()
    } else {
        x.to_string()
    }
}

/// A number that may be missing: empty when it is.
fn opt(x: Option<f64>) -> String {
    x.map_or(String::new(), num)
}

/// How a model's quantities are named in the columns of its results, and the device its
/// frequencies are given in Hz for: the built-in model's `lambda_i`, `v`, `amplitude_stretch`
/// and device; a written model's own state names, `amplitude`, and no device (no column in
/// Hz is filled in).
#[derive(Debug, Clone, PartialEq)]
pub struct ModelColumns {
    /// Every state, in order (a continued branch's `STATE_0`).
    pub states: Vec<String>,
    /// The two states a grid spans (`poincare_STATE`).
    pub grid: [String; 2],
    /// The indices in `states` of the grid's two.
    pub grid_index: [usize; 2],
    /// The grid's two offsets from its origin (a basin's cells).
    pub offsets: [String; 2],
    /// The output whose extremes are `OUTPUT_min`, `OUTPUT_max`.
    pub output: String,
    /// The suffix of a value in the output's unit: `_stretch` for the built-in's λ_I.
    pub unit: &'static str,
    pub device: Option<Device>,
}

impl ModelColumns {
    pub fn built_in(device: &Device) -> ModelColumns {
        ModelColumns {
            states: vec!["lambda_i".into(), "v".into()],
            grid: ["lambda".into(), "v".into()],
            grid_index: [0, 1],
            offsets: ["dx_stretch".into(), "v_per_tau".into()],
            output: "lambda".into(),
            unit: "_stretch",
            device: Some(*device),
        }
    }

    /// A written model's: its states, grid and output (named after the amplitude's
    /// expression where that is a name, else `output`).
    pub fn written(model: &crate::model::equations::EquationModel) -> ModelColumns {
        let states = model.states().to_vec();
        let grid_index = model.grid();
        let [a, b] = grid_index.map(|i| states[i].clone());
        let output = model.amplitude_text();
        let is_name = output.chars().all(|c| c.is_alphanumeric() || c == '_');
        ModelColumns {
            offsets: [format!("{a}_offset"), format!("{b}_offset")],
            grid: [a, b],
            grid_index,
            states,
            output: if is_name {
                output.to_string()
            } else {
                "output".into()
            },
            unit: "",
            device: None,
        }
    }

    /// The columns describing one steady state.
    pub fn steady(&self) -> Vec<String> {
        let mut c: Vec<String> = [
            "class",
            "period_forcing_periods",
            "ratio_response",
            "ratio_excitation",
            "response_type",
        ]
        .map(String::from)
        .to_vec();
        c.push(self.amplitude());
        c.push(format!("{}_min", self.output));
        c.push(format!("{}_max", self.output));
        c
    }

    /// The stroboscopic points' columns (a points table).
    fn poincare(&self) -> [String; 2] {
        self.grid.clone().map(|s| format!("poincare_{s}"))
    }

    /// The first stroboscopic point's columns (beside a response): the grid's two states,
    /// then a written model's others in its order (the whole state to start from).
    fn start(&self) -> Vec<String> {
        let others = outside_grid(self.states.len(), self.grid_index).map(|i| &self.states[i]);
        self.grid
            .iter()
            .chain(others)
            .map(|s| format!("start_{s}"))
            .collect()
    }

    /// The first stroboscopic point under [`Self::start`]'s columns (at τ = 0 on the orbit:
    /// where to start to see it again), empty without one; all the grid's points are in the
    /// points table.
    fn start_fields(&self, s: &SteadyState) -> Vec<String> {
        let start = crate::session::results::start_of(s, self.grid_index).unwrap_or_default();
        (0..2 + outside_grid(self.states.len(), self.grid_index).count())
            .map(|i| start.get(i).map_or(String::new(), |&x| num(x)))
            .collect()
    }

    /// `omega` in Hz on the device, empty without one.
    fn hz(&self, omega: f64) -> String {
        self.device.map_or(String::new(), |d| num(d.hz(omega)))
    }

    /// τ in seconds on the device, empty without one.
    fn seconds(&self, tau: f64) -> String {
        self.device.map_or(String::new(), |d| num(d.seconds(tau)))
    }

    /// The amplitude's column (max − min of the output): `amplitude_stretch`, a written
    /// model's `amplitude`.
    pub fn amplitude(&self) -> String {
        self.in_unit("amplitude")
    }

    /// The column of a value `name` in the output's unit (`magnitude_stretch`).
    fn in_unit(&self, name: &str) -> String {
        format!("{name}{}", self.unit)
    }
}

/// A steady state's fields under [`ModelColumns::steady`]: the ratio ω_r:ω_e as two integer
/// columns (a spreadsheet reads the text `1:2` as a time), empty where there is none.
pub fn steady_fields(s: &SteadyState) -> [String; 8] {
    let int = |n: Option<u32>| n.map_or(String::new(), |n| n.to_string());
    [
        s.class.as_str().into(),
        s.period.map_or(String::new(), |k| k.to_string()),
        int(s.ratio.map(|r| r.response)),
        int(s.ratio.map(|r| r.excitation)),
        s.response_type(),
        opt(s.amplitude),
        opt(s.lambda_min),
        opt(s.lambda_max),
    ]
}

/// The tables a basin writes beside its cells (`A.attractors.csv`, `A.points.csv`).
pub const BASIN_TABLES: [&str; 2] = ["attractors", "points"];
/// The tables a frequency response writes beside its responses.
pub const RESPONSE_TABLES: [&str; 2] = ["points", "outcomes"];
/// The tables a family writes beside its branches.
pub const FAMILY_TABLES: [&str; 3] = ["responses", "points", "outcomes"];
/// The tables a chirp sweep writes beside its samples.
pub const CHIRP_TABLES: [&str; 2] = ["jumps", "extremes"];
/// The tables a chirp sweep with a scalogram writes besides: the scalogram and, beside it,
/// its ridge ([`scalogram_csv`]).
pub const SCALOGRAM_TABLES: [&str; 2] = ["scalogram", "scalogram.ridge"];
/// The tables a stepped sweep writes beside its steps.
pub const STEPPED_TABLES: [&str; 2] = ["jumps", "peaks"];

/// Where a table beside a result's main file `A.csv` lives: `A.TABLE.csv`.
pub fn beside(main: &Path, table: &str) -> PathBuf {
    main.with_extension(format!("{table}.csv"))
}

/// One row per cell (`dx_stretch, v_per_tau, attractor, response_type`, the offsets named
/// after a written model's grid states), and beside it the attractor table
/// (`A.attractors.csv`) and the attractors' stroboscopic points (`A.points.csv`: one row per
/// point, numbered from 0 along the orbit). Returns the files written, `path` first.
pub fn basin_csv(
    b: &Basin,
    omega: f64,
    columns: &ModelColumns,
    path: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    write_atomic(path, |w| {
        let [x, y] = &columns.offsets;
        w.write_record([x.as_str(), y, "attractor", "response_type"])?;
        let nv = b.v.len();
        let types: Vec<String> = b
            .table
            .attractors
            .iter()
            .map(|a| a.response.response_type())
            .collect();
        for (c, &label) in b.labels.iter().enumerate() {
            w.write_record([
                &num(b.dx[c / nv]),
                &num(b.v[c % nv]),
                &label.to_string(),
                &types[label],
            ])?;
        }
        Ok(())
    })?;
    write_atomic(&beside(path, "attractors"), |w| {
        let mut header: Vec<String> = ["attractor", "omega", "cells", "fraction"]
            .map(String::from)
            .to_vec();
        header.extend(columns.steady());
        header.extend(columns.start());
        w.write_record(&header)?;
        for a in &b.table.attractors {
            let mut row = vec![
                a.id.to_string(),
                num(omega),
                a.count.to_string(),
                num(b.fraction(a.id)),
            ];
            row.extend(steady_fields(&a.response));
            row.extend(columns.start_fields(&a.response));
            w.write_record(&row)?;
        }
        Ok(())
    })?;
    write_atomic(&beside(path, "points"), |w| {
        let mut header = vec!["attractor".to_string(), "point".into()];
        header.extend(columns.poincare());
        w.write_record(&header)?;
        for a in &b.table.attractors {
            for (k, p) in a.response.poincare.iter().enumerate() {
                w.write_record([a.id.to_string(), k.to_string(), num(p[0]), num(p[1])])?;
            }
        }
        Ok(())
    })?;
    Ok(written(path, &BASIN_TABLES))
}

/// `main` and the tables beside it.
fn written(main: &Path, tables: &[&str]) -> Vec<PathBuf> {
    std::iter::once(main.to_path_buf())
        .chain(tables.iter().map(|t| beside(main, t)))
        .collect()
}

/// The columns of one periodic response at one ω_e, after its number.
const RESPONSE_COLUMNS: [&str; 6] = [
    "omega",
    "frequency_hz",
    "branch",
    "hidden",
    "seeded",
    "share",
];

/// Frequency responses written as three tidy tables: the periodic responses (numbered, one
/// row each), their stroboscopic points (one row per point), and the outcomes per ω_e (the
/// shares of the starts that settled on a periodic response, on no periodic one, or hit a
/// frame), each led by `lead` (a family member's parameter value) where given.
struct ResponseTables<'a> {
    lead: Option<&'a str>,
    columns: &'a ModelColumns,
}

impl ResponseTables<'_> {
    fn header(&self, rest: &[String]) -> Vec<String> {
        self.lead
            .map(String::from)
            .into_iter()
            .chain(rest.iter().cloned())
            .collect()
    }

    fn row(&self, value: Option<f64>, rest: Vec<String>) -> Vec<String> {
        value
            .map(|v| v.to_string())
            .into_iter()
            .chain(rest)
            .collect()
    }

    /// Writes `main`, `points` and `outcomes` for the responses of each member.
    fn write(
        &self,
        members: &[(Option<f64>, &FrequencyResponse)],
        main: &Path,
        points: &Path,
        outcomes: &Path,
    ) -> anyhow::Result<()> {
        let columns = self.columns;
        // the periodic responses, numbered once for both tables that name them
        let responses: Vec<(Option<f64>, &Response)> = members
            .iter()
            .flat_map(|&(value, fr)| periodic(fr).map(move |r| (value, r)))
            .collect();
        write_atomic(main, |w| {
            let mut rest = vec!["response".to_string()];
            rest.extend(RESPONSE_COLUMNS.map(String::from));
            rest.extend(columns.steady());
            rest.extend(columns.start());
            w.write_record(self.header(&rest))?;
            for (id, &(value, r)) in responses.iter().enumerate() {
                let mut rest = vec![
                    id.to_string(),
                    num(r.omega),
                    columns.hz(r.omega),
                    r.branch.map_or(String::new(), |b| b.to_string()),
                    r.hidden.map_or(String::new(), |h| h.to_string()),
                    r.seeded.to_string(),
                    num(r.share),
                ];
                rest.extend(steady_fields(&r.steady));
                rest.extend(columns.start_fields(&r.steady));
                w.write_record(self.row(value, rest))?;
            }
            Ok(())
        })?;
        write_atomic(points, |w| {
            let mut rest = vec!["response".to_string(), "omega".into(), "point".into()];
            rest.extend(columns.poincare());
            w.write_record(self.header(&rest))?;
            for (id, &(value, r)) in responses.iter().enumerate() {
                for (k, p) in r.steady.poincare.iter().enumerate() {
                    let rest = vec![
                        id.to_string(),
                        num(r.omega),
                        k.to_string(),
                        num(p[0]),
                        num(p[1]),
                    ];
                    w.write_record(self.row(value, rest))?;
                }
            }
            Ok(())
        })?;
        write_atomic(outcomes, |w| {
            let rest = OUTCOME_COLUMNS.map(String::from);
            w.write_record(self.header(&rest))?;
            for &(value, fr) in members {
                for (i, &omega) in fr.omegas.iter().enumerate() {
                    let mut shares = [0.0; 3];
                    for r in fr.responses.iter().filter(|r| r.omega_index == i) {
                        let k = match r.steady.class {
                            Class::Periodic => 0,
                            Class::NonPeriodic => 1,
                            Class::Collision => 2,
                        };
                        shares[k] += r.share;
                    }
                    let mut rest = vec![num(omega), columns.hz(omega)];
                    rest.extend(shares.map(num));
                    w.write_record(self.row(value, rest))?;
                }
            }
            Ok(())
        })
    }
}

/// The periodic responses of `fr`, in order.
fn periodic(fr: &FrequencyResponse) -> impl Iterator<Item = &Response> {
    fr.responses
        .iter()
        .filter(|r| r.steady.class == Class::Periodic)
}

/// The columns of the outcomes per ω_e of a frequency response (see [`ResponseTables`]).
const OUTCOME_COLUMNS: [&str; 5] = [
    "omega",
    "frequency_hz",
    "periodic_share",
    "non_periodic_share",
    "collision_share",
];

/// One row per periodic response per ω_e (`frequency_hz` for the columns' device), with its
/// stroboscopic points in `A.points.csv` and the shares of the starts per outcome in
/// `A.outcomes.csv`. Returns the files written, `path` first.
pub fn response_csv(
    fr: &FrequencyResponse,
    columns: &ModelColumns,
    path: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    ResponseTables {
        lead: None,
        columns,
    }
    .write(
        &[(None, fr)],
        path,
        &beside(path, "points"),
        &beside(path, "outcomes"),
    )?;
    Ok(written(path, &RESPONSE_TABLES))
}

/// One row per periodic response per ω_e per member of a family, the parameter's value
/// first; their points and the outcomes per ω_e beside the family's branch table
/// (`A.points.csv`, `A.outcomes.csv`).
pub fn family_responses_csv(
    parameter: &str,
    members: &[crate::analysis::global::family::FamilyMember],
    columns: &ModelColumns,
    family_csv: &Path,
) -> anyhow::Result<()> {
    let members: Vec<(Option<f64>, &FrequencyResponse)> = members
        .iter()
        .map(|m| (Some(m.value), &m.response))
        .collect();
    ResponseTables {
        lead: Some(parameter),
        columns,
    }
    .write(
        &members,
        &beside(family_csv, "responses"),
        &beside(family_csv, "points"),
        &beside(family_csv, "outcomes"),
    )
}

/// One row per point of each force curve.
pub fn force_csv(
    curves: &[crate::analysis::orbit::force_curve::ForceCurve],
    path: &Path,
) -> anyhow::Result<()> {
    write_atomic(path, |w| {
        w.write_record(["lambda_p", "phi_i", "dx_stretch", "force_nondim"])?;
        for c in curves {
            for p in &c.points {
                w.write_record([
                    c.lambda_p.to_string(),
                    c.phi_i.to_string(),
                    num(p[0]),
                    num(p[1]),
                ])?;
            }
        }
        Ok(())
    })
}

/// One row per sample of a time history, with each membrane's tension and whether it is slack.
pub fn history_csv(
    h: &crate::analysis::orbit::time_history::TimeHistory,
    device: &Device,
    path: &Path,
) -> anyhow::Result<()> {
    let bytes = history_bytes(h, device)?;
    super::output::write_output(path, &bytes, &super::output::Protected::none())?;
    Ok(())
}

/// [`history_csv`]'s file, in memory.
pub fn history_bytes(
    h: &crate::analysis::orbit::time_history::TimeHistory,
    device: &Device,
) -> anyhow::Result<Vec<u8>> {
    csv_bytes(|w| {
        w.write_record([
            "tau",
            "time_s",
            "lambda_stretch",
            "v_per_tau",
            "phi_i",
            "steady",
            "tension_i_nondim",
            "tension_ii_nondim",
            "slack_i",
            "slack_ii",
        ])?;
        for s in &h.samples {
            let (slack_i, slack_ii) = s.slack();
            w.write_record([
                num(s.tau),
                num(device.seconds(s.tau)),
                num(s.lambda),
                num(s.v),
                num(s.phi_i),
                s.steady.to_string(),
                num(s.tension_i),
                num(s.tension_ii),
                slack_i.to_string(),
                slack_ii.to_string(),
            ])?;
        }
        Ok(())
    })
}

/// One row per sample of a written model's time history: τ, its two grid states first, the
/// other states, the amplitude's output, whether the sample is on the steady response, and
/// whether it is where a collision ended the orbit (the last row only, if one did).
pub fn state_history_bytes(
    h: &crate::analysis::global::oscillator::history::StateHistory,
    grid: [usize; 2],
) -> anyhow::Result<Vec<u8>> {
    let mut order: Vec<usize> = vec![grid[0]];
    if grid[1] != grid[0] {
        order.push(grid[1]);
    }
    order.extend(outside_grid(h.states.len(), grid));
    csv_bytes(|w| {
        let mut header = vec!["tau"];
        header.extend(order.iter().map(|&i| h.states[i].as_str()));
        header.extend(["amplitude_output", "steady", "collision"]);
        w.write_record(&header)?;
        let last = h.samples.len().saturating_sub(1);
        for (j, s) in h.samples.iter().enumerate() {
            let mut row = vec![num(s.tau)];
            row.extend(order.iter().map(|&i| num(s.state[i])));
            let collided = j == last && h.collision.is_some();
            row.extend([num(s.output), s.steady.to_string(), collided.to_string()]);
            w.write_record(&row)?;
        }
        Ok(())
    })
}

/// The Morlet scalogram of chirp sweep `s` (Fig 3C/D): one row per time column and analysis
/// frequency (`tau, time_s, omega_r, frequency_hz, magnitude_stretch`, a written model's
/// `magnitude`), and beside it its ridge
/// (`A.ridge.csv`, one row per time column: the forcing's `omega_e` and `frequency_hz_e` then,
/// the frequency of the largest magnitude `ridge_omega_r` and `ridge_frequency_hz`, and their
/// ratio `ridge_ratio` = ω_r/ω_e, 0.5 on a 1:2 response, empty where ω_e is 0). Returns the
/// files written, `path` first.
pub fn scalogram_csv(
    sc: &crate::analysis::orbit::scalogram::Scalogram,
    s: &crate::analysis::orbit::chirp_sweep::ChirpSweep,
    columns: &ModelColumns,
    path: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    write_atomic(path, |w| {
        let magnitude = columns.in_unit("magnitude");
        w.write_record(["tau", "time_s", "omega_r", "frequency_hz", &magnitude])?;
        for (c, &tau) in sc.times.iter().enumerate() {
            for (row, &omega_r) in sc.magnitude.iter().zip(&sc.frequencies) {
                w.write_record([
                    num(tau),
                    columns.seconds(tau),
                    num(omega_r),
                    columns.hz(omega_r),
                    num(row[c]),
                ])?;
            }
        }
        Ok(())
    })?;
    write_atomic(&beside(path, "ridge"), |w| {
        w.write_record([
            "tau",
            "time_s",
            "omega_e",
            "frequency_hz_e",
            "ridge_omega_r",
            "ridge_frequency_hz",
            "ridge_ratio",
        ])?;
        let forcing = sc.forcing(&s.omega);
        for ((&tau, &ridge), &omega_e) in sc.times.iter().zip(&sc.ridge).zip(&forcing) {
            w.write_record([
                num(tau),
                columns.seconds(tau),
                num(omega_e),
                columns.hz(omega_e),
                num(ridge),
                columns.hz(ridge),
                // no ratio where the forcing is at ω_e = 0 (a sweep up from rest), or so near
                // it that the ratio overflows
                opt(Some(ridge / omega_e).filter(|r| r.is_finite())),
            ])?;
        }
        Ok(())
    })?;
    Ok(written(path, &["ridge"]))
}

/// One row per sample of a chirp sweep (τ and the time in seconds on the device), the output
/// (`lambda_stretch`, a written model's under its name), with the envelope (max − min of the
/// output over the sample's window, `envelope_amplitude_stretch`, a written model's
/// `envelope_amplitude`) beside it; beside the samples, one row per located jump of the
/// envelope (`A.jumps.csv`: `jump, direction, window, tau, time_s, omega, frequency_hz`, the
/// envelope before and after) and one row of extremes (`A.extremes.csv`: the largest envelope
/// with its τ and ω_e, the output's least and greatest values, and where the trajectory
/// collided, empty if it did not). Seconds and Hz are empty without a device. Returns the
/// files written, `path` first.
pub fn chirp_csv(
    s: &crate::analysis::orbit::chirp_sweep::ChirpSweep,
    columns: &ModelColumns,
    path: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    let per_window = s.window_samples.max(1);
    let envelope = columns.in_unit("envelope_amplitude");
    write_atomic(path, |w| {
        let output = columns.in_unit(&columns.output);
        w.write_record(["tau", "time_s", "omega", "frequency_hz", &output, &envelope])?;
        for (j, (&lambda, &omega)) in s.lambda.iter().zip(&s.omega).enumerate() {
            let amplitude = s.envelope.get(j / per_window).map_or(0.0, |e| e[2]);
            let tau = j as f64 * s.dt;
            w.write_record([
                num(tau),
                columns.seconds(tau),
                num(omega),
                columns.hz(omega),
                num(lambda),
                num(amplitude),
            ])?;
        }
        Ok(())
    })?;
    let found = &s.findings;
    write_atomic(&beside(path, "jumps"), |w| {
        w.write_record([
            "jump",
            "direction",
            "window",
            "tau",
            "time_s",
            "omega",
            "frequency_hz",
            &format!("{envelope}_before"),
            &format!("{envelope}_after"),
        ])?;
        for (id, j) in found.jumps.iter().enumerate() {
            w.write_record([
                id.to_string(),
                j.direction.as_str().into(),
                j.window.to_string(),
                num(j.tau),
                columns.seconds(j.tau),
                num(j.omega),
                columns.hz(j.omega),
                num(j.amplitude_before),
                num(j.amplitude_after),
            ])?;
        }
        Ok(())
    })?;
    write_atomic(&beside(path, "extremes"), |w| {
        let output = &columns.output;
        w.write_record([
            &format!("peak_{envelope}"),
            "peak_tau",
            "peak_time_s",
            "peak_omega",
            "peak_frequency_hz",
            &format!("{output}_min"),
            &format!("{output}_max"),
            "collision_tau",
            "collision_time_s",
            "collision_omega",
            "collision_frequency_hz",
        ])?;
        let c = found.collision;
        w.write_record([
            num(found.peak_amplitude),
            num(found.peak_tau),
            columns.seconds(found.peak_tau),
            num(found.peak_omega),
            columns.hz(found.peak_omega),
            num(found.lambda_min),
            num(found.lambda_max),
            opt(c.map(|c| c.tau)),
            c.map_or(String::new(), |c| columns.seconds(c.tau)),
            opt(c.map(|c| c.omega)),
            c.map_or(String::new(), |c| columns.hz(c.omega)),
        ])?;
        Ok(())
    })?;
    Ok(written(path, &CHIRP_TABLES))
}

/// One row per step of a stepped sweep (with where its orbit starts, as a response's), and
/// beside it one row per jump between steps
/// (`A.jumps.csv`: `jump, step, direction,` ω_e before and after, the response types and
/// amplitudes before and after) and one row per response type with its largest amplitude
/// (`A.peaks.csv`: `response_type, steps,` the peak amplitude, its ω_e). Returns the files
/// written, `path` first.
pub fn stepped_csv(
    steps: &[crate::analysis::global::stepped_sweep::SweepStep],
    found: &crate::analysis::global::stepped_sweep::SweepFindings,
    columns: &ModelColumns,
    path: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    write_atomic(path, |w| {
        let mut header: Vec<String> = ["step", "omega", "frequency_hz", "restarted"]
            .map(String::from)
            .to_vec();
        header.extend(columns.steady());
        header.extend(columns.start());
        w.write_record(&header)?;
        for (i, s) in steps.iter().enumerate() {
            let mut row = vec![
                i.to_string(),
                num(s.omega),
                columns.hz(s.omega),
                s.restarted.to_string(),
            ];
            row.extend(steady_fields(&s.steady));
            row.extend(columns.start_fields(&s.steady));
            w.write_record(&row)?;
        }
        Ok(())
    })?;
    write_atomic(&beside(path, "jumps"), |w| {
        let amplitude = &columns.amplitude();
        w.write_record([
            "jump",
            "step",
            "direction",
            "omega_before",
            "omega_after",
            "frequency_hz_before",
            "frequency_hz_after",
            "response_type_before",
            "response_type_after",
            &format!("{amplitude}_before"),
            &format!("{amplitude}_after"),
        ])?;
        for (id, j) in found.jumps.iter().enumerate() {
            w.write_record([
                id.to_string(),
                j.step.to_string(),
                j.direction.map_or("", |d| d.as_str()).into(),
                num(j.omega_before),
                num(j.omega_after),
                columns.hz(j.omega_before),
                columns.hz(j.omega_after),
                j.type_before.clone(),
                j.type_after.clone(),
                opt(j.amplitude_before),
                opt(j.amplitude_after),
            ])?;
        }
        Ok(())
    })?;
    write_atomic(&beside(path, "peaks"), |w| {
        w.write_record([
            "response_type",
            "steps",
            &format!("peak_{}", columns.amplitude()),
            "peak_omega",
            "peak_frequency_hz",
        ])?;
        for p in &found.peaks {
            w.write_record([
                p.response_type.clone(),
                p.steps.to_string(),
                num(p.peak_amplitude),
                num(p.peak_omega),
                columns.hz(p.peak_omega),
            ])?;
        }
        Ok(())
    })?;
    Ok(written(path, &STEPPED_TABLES))
}

/// One row per branch per member of a family.
pub fn family_csv(
    parameter: &str,
    members: &[crate::analysis::global::family::FamilyMember],
    columns: &ModelColumns,
    path: &Path,
) -> anyhow::Result<()> {
    let peak = format!("peak_{}", columns.amplitude());
    write_atomic(path, |w| {
        w.write_record([
            parameter,
            "branch",
            "period_forcing_periods",
            "ratio_response",
            "ratio_excitation",
            "response_type",
            "omega_min",
            "omega_max",
            &peak,
            "peak_omega",
            "points",
            "hidden",
            "partly_hidden",
        ])?;
        for m in members {
            for b in &m.response.branches {
                w.write_record([
                    m.value.to_string(),
                    b.id.to_string(),
                    b.period.to_string(),
                    b.ratio.response.to_string(),
                    b.ratio.excitation.to_string(),
                    b.response_type.clone(),
                    num(b.omega_min),
                    num(b.omega_max),
                    num(b.peak_amplitude),
                    num(b.peak_omega),
                    b.points.to_string(),
                    b.hidden.to_string(),
                    b.partly_hidden.to_string(),
                ])?;
            }
        }
        Ok(())
    })
}

/// One row per point (kind `point`, in order along the branch) and per located bifurcation
/// (its kind) of each branch, numbered from 0. Columns: branch, period, verdict (isola,
/// attached, half-attached, open), kind, the continuation parameter, `omega_e`, the state at
/// τ = 0 (`STATE_0` for each state), the amplitude, `stable` and each Floquet multiplier
/// (`muK_re`, `muK_im`, by decreasing modulus).
pub fn continued_csv(
    branches: &[&crate::analysis::continuation::branch::ContinuedBranch],
    columns: &ModelColumns,
    path: &Path,
) -> anyhow::Result<()> {
    use crate::analysis::continuation::hunt::Verdict;
    use crate::analysis::orbit::floquet::Multipliers;
    let parameter = branches.first().map_or("omega", |b| b.parameter.name());
    let n = columns.states.len();
    write_atomic(path, |w| {
        let mut header: Vec<String> = ["branch", "period", "verdict", "kind", parameter, "omega_e"]
            .map(String::from)
            .to_vec();
        header.extend(columns.states.iter().map(|s| format!("{s}_0")));
        header.extend([columns.amplitude(), "stable".into()]);
        for k in 1..=n {
            header.extend([format!("mu{k}_re"), format!("mu{k}_im")]);
        }
        w.write_record(&header)?;
        for (id, b) in branches.iter().enumerate() {
            let verdict = Verdict::of(b).as_str();
            let row = |kind: &str,
                       par: f64,
                       omega: f64,
                       x: &[f64],
                       amp: f64,
                       stable: Option<bool>,
                       m: &Multipliers| {
                let mut r = vec![
                    id.to_string(),
                    b.period.to_string(),
                    verdict.to_string(),
                    kind.to_string(),
                    num(par),
                    num(omega),
                ];
                r.extend(x.iter().map(|v| num(*v)));
                r.extend([num(amp), stable.map(|s| s.to_string()).unwrap_or_default()]);
                for mu in &m.0 {
                    r.push(num(mu.re));
                    r.push(num(mu.im));
                }
                r
            };
            for p in &b.points {
                let r = row(
                    "point",
                    p.parameter,
                    p.omega,
                    &p.x,
                    p.amplitude,
                    Some(p.stable),
                    &p.multipliers,
                );
                w.write_record(&r)?;
            }
            for f in &b.bifurcations {
                let r = row(
                    f.kind.as_str(),
                    f.parameter,
                    f.omega,
                    &f.x,
                    f.amplitude,
                    None,
                    &f.multipliers,
                );
                w.write_record(&r)?;
            }
        }
        Ok(())
    })
}

/// One row per hunted branch per value of a hunt family: `PARAMETER, branch, period,
/// verdict, hidden, omega_min, omega_max, peak_amplitude_stretch, peak_omega` (the branch
/// numbered within its member), and beside it one row per located bifurcation
/// (`A.bifurcations.csv`: `PARAMETER, branch, kind, omega, amplitude_stretch, precision`).
/// Returns the files written, `path` first.
pub fn hunt_family_csv(
    parameter: &str,
    members: &[crate::analysis::continuation::hunt_family::HuntMember],
    limits: &[(
        crate::analysis::continuation::hunt_family::Transition,
        Option<IsolaLimit>,
    )],
    path: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    write_atomic(path, |w| {
        w.write_record([
            parameter,
            "branch",
            "period",
            "verdict",
            "hidden",
            "omega_min",
            "omega_max",
            "peak_amplitude_stretch",
            "peak_omega",
        ])?;
        for m in members {
            for (id, b) in m.branches.iter().enumerate() {
                w.write_record([
                    m.value.to_string(),
                    id.to_string(),
                    b.branch.period.to_string(),
                    b.verdict.as_str().to_string(),
                    b.hidden.to_string(),
                    num(b.omega_min),
                    num(b.omega_max),
                    num(b.peak_amplitude),
                    num(b.peak_omega),
                ])?;
            }
        }
        Ok(())
    })?;
    write_atomic(&beside(path, "bifurcations"), |w| {
        w.write_record([
            parameter,
            "branch",
            "kind",
            "omega",
            "amplitude_stretch",
            "precision",
        ])?;
        for m in members {
            for (id, b) in m.branches.iter().enumerate() {
                for f in &b.branch.bifurcations {
                    w.write_record([
                        m.value.to_string(),
                        id.to_string(),
                        f.kind.as_str().to_string(),
                        num(f.omega),
                        num(f.amplitude),
                        num(f.precision),
                    ])?;
                }
            }
        }
        Ok(())
    })?;
    // each change of the picture between two values, and where it happens when located
    write_atomic(&beside(path, "limits"), |w| {
        w.write_record([
            "period".to_string(),
            "event".into(),
            "before".into(),
            "after".into(),
            format!("{parameter}_from"),
            format!("{parameter}_to"),
            "located".into(),
            parameter.into(),
            "precision".into(),
            "omega".into(),
            "amplitude_stretch".into(),
        ])?;
        let verdict = |v: Option<crate::analysis::continuation::hunt::Verdict>| {
            v.map_or("none", |v| v.as_str()).to_string()
        };
        for (t, limit) in limits {
            let located = |f: fn(&IsolaLimit) -> f64| opt(limit.as_ref().map(f));
            let row = [
                t.period.to_string(),
                t.event().to_string(),
                verdict(t.before),
                verdict(t.after),
                num(t.from),
                num(t.to),
                limit.is_some().to_string(),
                located(|l| l.value),
                located(|l| l.precision),
                located(|l| l.omega),
                located(|l| l.amplitude),
            ];
            w.write_record(row)?;
        }
        Ok(())
    })?;
    Ok(written(path, &["bifurcations", "limits"]))
}

/// One row per cell of a map: `Y, X, frequency_hz` (with x = ω_e, for `device`; empty
/// otherwise)`,
/// stable, largest_amplitude_stretch, largest_type, largest_ratio_response,
/// largest_ratio_excitation, hidden, subharmonic, collision_share, non_periodic_share`, the
/// parameters named in the header.
pub fn map_csv(
    (x, parameter): (&str, &str),
    xs: &[f64],
    rows: &[crate::analysis::continuation::map::MapRow],
    columns: &ModelColumns,
    path: &Path,
) -> anyhow::Result<()> {
    let is_omega = x == "omega";
    let largest = format!("largest_{}", columns.amplitude());
    write_atomic(path, |w| {
        w.write_record([
            parameter,
            x,
            "frequency_hz",
            "stable",
            &largest,
            "largest_type",
            "largest_ratio_response",
            "largest_ratio_excitation",
            "hidden",
            "subharmonic",
            "collision_share",
            "non_periodic_share",
        ])?;
        for row in rows {
            for (cell, at) in row.cells.iter().zip(xs) {
                let short = cell.largest_type.as_deref().unwrap_or("");
                let (largest_type, ratio) = full_type(short);
                w.write_record([
                    row.value.to_string(),
                    num(*at),
                    if is_omega {
                        columns.hz(*at)
                    } else {
                        String::new()
                    },
                    cell.stable.to_string(),
                    cell.largest_amplitude.map_or(String::new(), num),
                    largest_type.clone(),
                    ratio.map_or(String::new(), |r| r.response.to_string()),
                    ratio.map_or(String::new(), |r| r.excitation.to_string()),
                    cell.hidden.to_string(),
                    cell.subharmonic.to_string(),
                    num(cell.collision_share),
                    num(cell.non_periodic_share),
                ])?;
            }
        }
        Ok(())
    })
}

/// One row per point of each two-parameter curve (`kind` `fold` or `period-doubling`,
/// `at` = `point`) and per located turning point (`at` = `minimum` or `maximum` of the
/// parameter named in `of`): `curve, kind, period, at, of, FIRST, SECOND, amplitude_stretch`.
pub fn curves_csv(
    curves: &[crate::analysis::continuation::bifurcation_curve::BifurcationCurve],
    columns: &ModelColumns,
    path: &Path,
) -> anyhow::Result<()> {
    use crate::analysis::continuation::bifurcation_curve::Turning;
    let (first, second) = curves.first().map_or(("omega", "parameter"), |c| {
        (c.first.name(), c.second.name())
    });
    write_atomic(path, |w| {
        w.write_record([
            "curve",
            "kind",
            "period",
            "at",
            "of",
            first,
            second,
            &columns.amplitude(),
        ])?;
        for (id, c) in curves.iter().enumerate() {
            let kind = c.kind.as_str();
            for p in &c.points {
                w.write_record([
                    id.to_string(),
                    kind.into(),
                    c.period.to_string(),
                    "point".into(),
                    String::new(),
                    num(p.first),
                    num(p.second),
                    num(p.amplitude),
                ])?;
            }
            for e in &c.extrema {
                let of = match e.of {
                    Turning::First => first,
                    Turning::Second => second,
                };
                w.write_record([
                    id.to_string(),
                    kind.into(),
                    c.period.to_string(),
                    if e.minimum { "minimum" } else { "maximum" }.into(),
                    of.into(),
                    num(e.point.first),
                    num(e.point.second),
                    num(e.point.amplitude),
                ])?;
            }
        }
        Ok(())
    })
}

/// A map cell's response type in full (`1:2 subharmonic`; the cell keeps `1:2`, which a
/// spreadsheet would read as a time) and its ratio.
fn full_type(short: &str) -> (String, Option<crate::analysis::Ratio>) {
    match short.parse::<crate::analysis::Ratio>() {
        Ok(r) if r.excitation > 1 => (format!("{short} subharmonic"), Some(r)),
        Ok(r) if r.response > 1 => (format!("{short} super-harmonic"), Some(r)),
        Ok(r) => (format!("{short} harmonic"), Some(r)),
        Err(_) => (short.to_string(), None),
    }
}
