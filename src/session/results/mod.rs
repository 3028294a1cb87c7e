//! Results read back for viewing: the CSV of a finished analysis, or the chunks of one under
//! way (in this process or in a headless `isola run` elsewhere), as plot-ready data.
//!
//! A [`ResultReader`] is polled: each call reads only what changed on disk (new chunks, a new
//! manifest or CSV), so a viewer can follow a long run at a few polls per second.

use std::collections::HashMap;
use std::path::Path;
use std::time::SystemTime;

use super::run::{basin_content, chunk_count, family_content, map_content, response_content};
use super::schema::{AnalysisEntry, Session, Settings};
use super::store::chunk::{self, ChunkId};
use super::store::manifest::{Manifest, Unverified};
use super::store::{self, ResultPaths};
use crate::analysis::Ratio;
use crate::analysis::continuation::hunt::HuntSpec;
use crate::analysis::continuation::map::{MapCell, MapRow};
use crate::analysis::global::family::FamilyMember;
use crate::analysis::global::frequency_response::{Response, chunk_omegas};
use crate::analysis::orbit::attractor::{AttractorTable, SAME_POINT_TOL};
use crate::analysis::{Class, SteadyState};

mod view;
pub use view::{
    AttractorRow, BasinView, BifurcationPoint, ChirpView, ContinuationView, ContinuedPoint,
    ContinuedView, CurveView, FamilyView, ForceView, HistoryView, HuntView, MapView, ResponsePoint,
    ResultView, branches, start_of,
};

/// Where an analysis' stored result stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ResultStatus {
    /// Nothing on disk.
    Missing,
    /// Chunks done of total, no final file yet.
    Partial { done: usize, total: usize },
    /// Complete, verified, for the current model, device, settings and numerics.
    Complete,
    /// Complete and verified, but computed for another model, device, settings or numerics.
    Stale,
}

/// Follows one analysis' result files; [`ResultReader::poll`] reads what changed.
#[derive(Debug)]
pub struct ResultReader {
    name: String,
    kind: &'static str,
    /// The fingerprint the last poll looked for.
    fingerprint: String,
    /// (manifest, main file) as last seen: a change of either means verifying again.
    seen: Option<(Option<Stamp>, Option<Stamp>)>,
    /// The stored result, verified, and its view.
    stored: Option<(Manifest, std::sync::Arc<ResultView>)>,
    chunks_read: Vec<bool>,
    partial: Partial,
    /// The indices of the states the model's grid spans, as at the last poll.
    grid: [usize; 2],
    pub status: ResultStatus,
    pub view: Option<ResultView>,
    /// While a partial result of the current settings is shown, the complete result of the
    /// settings before (stale), to draw beside it until the new one is complete.
    pub previous: Option<std::sync::Arc<ResultView>>,
    /// Why the files could not be read or verified, if they could not.
    pub error: Option<String>,
}

/// What is kept of the chunks read so far.
#[derive(Debug, Default)]
enum Partial {
    #[default]
    None,
    Basin {
        table: AttractorTable,
        labels: Vec<Option<usize>>,
    },
    Response(Vec<Vec<ResponsePoint>>),
    Family(Vec<Option<(f64, Vec<ResponsePoint>)>>),
    Map(Vec<Option<Vec<MapCell>>>),
}

/// A file's modification time and length: a change of either means reading it again.
type Stamp = (SystemTime, u64);

fn stamp(path: &Path) -> Option<Stamp> {
    let m = std::fs::metadata(path).ok()?;
    Some((m.modified().ok()?, m.len()))
}

impl ResultReader {
    pub fn new(entry: &AnalysisEntry) -> Self {
        ResultReader {
            name: entry.name.clone(),
            kind: entry.settings.kind(),
            fingerprint: String::new(),
            seen: None,
            stored: None,
            chunks_read: Vec::new(),
            partial: Partial::None,
            grid: [0, 1],
            status: ResultStatus::Missing,
            view: None,
            previous: None,
            error: None,
        }
    }

    /// Reads what changed since the last poll; true if the view or status changed.
    pub fn poll(&mut self, session: &Session, entry: &AnalysisEntry) -> bool {
        if entry.name != self.name || entry.settings.kind() != self.kind {
            *self = ResultReader::new(entry);
        }
        let paths = ResultPaths::new(session, &entry.name);
        let fingerprint = session.fingerprint(entry);
        self.grid = session.grid();
        let before = (
            self.status,
            self.view.is_some(),
            self.previous.is_some(),
            self.error.clone(),
        );
        let mut changed = false;
        if fingerprint != self.fingerprint {
            self.fingerprint = fingerprint.clone();
            self.chunks_read.clear();
            self.partial = Partial::None;
            changed = true;
        }
        let seen = Some((stamp(&paths.manifest), stamp(&paths.csv)));
        if seen != self.seen {
            self.seen = seen;
            self.error = None;
            self.stored = match store::verified(&paths) {
                Ok(m) => match read_csv_view(&entry.settings, &paths) {
                    Ok(ResultView::History(h)) => {
                        let h = match &session.written {
                            Some(w) => {
                                h.summarised_written(w.values(&entry.values)[w.model.frequency()])
                            }
                            None => match session.params(Some(entry)) {
                                Ok(p) => h.summarised(&p),
                                Err(_) => h,
                            },
                        };
                        Some((m, std::sync::Arc::new(ResultView::History(h))))
                    }
                    Ok(view) => Some((m, std::sync::Arc::new(view))),
                    Err(e) => {
                        self.error = Some(format!("{}: {e:#}", paths.csv.display()));
                        None
                    }
                },
                Err(Unverified::Missing) => None,
                Err(why) => {
                    self.error = Some(why.to_string());
                    None
                }
            };
            changed = true;
        }
        match &self.stored {
            Some((m, view)) if m.fingerprint == fingerprint => {
                self.chunks_read.clear();
                self.partial = Partial::None;
                self.status = ResultStatus::Complete;
                self.previous = None;
                if changed {
                    self.view = Some((**view).clone());
                }
            }
            stored => {
                let stale = stored.as_ref().map(|(_, view)| view.clone());
                let work = paths.work_dir(&fingerprint);
                let total = chunk_count(&entry.settings);
                changed |= self.read_new_chunks(&entry.settings, &work, &fingerprint, total);
                let done = self.chunks_read.iter().filter(|&&r| r).count();
                if done > 0 {
                    self.status = ResultStatus::Partial { done, total };
                    self.previous = stale;
                } else if let Some(view) = stale {
                    self.status = ResultStatus::Stale;
                    self.previous = None;
                    if changed {
                        self.view = Some((*view).clone());
                    }
                } else {
                    self.status = ResultStatus::Missing;
                    self.view = None;
                    self.previous = None;
                }
            }
        }
        changed
            || before
                != (
                    self.status,
                    self.view.is_some(),
                    self.previous.is_some(),
                    self.error.clone(),
                )
    }

    /// Reads the good chunk files of the current fingerprint not read yet; true if any was.
    fn read_new_chunks(
        &mut self,
        settings: &Settings,
        work: &Path,
        fingerprint: &str,
        n: usize,
    ) -> bool {
        if self.chunks_read.len() != n {
            self.chunks_read = vec![false; n];
            self.partial = Partial::None;
        }
        if !work.is_dir() {
            return false;
        }
        let mut any = false;
        for i in 0..n {
            if self.chunks_read[i] {
                continue;
            }
            let file = work.join(store::chunk_name(i));
            let Ok(bytes) = std::fs::read(&file) else {
                continue;
            };
            let id = ChunkId {
                fingerprint,
                index: i,
                chunks: n,
            };
            if self.absorb_chunk(settings, &id, &bytes).is_some() {
                self.chunks_read[i] = true;
                any = true;
            }
        }
        if any {
            self.view = self.partial_view(settings);
        }
        any
    }

    /// Adds chunk `id` to the partial result; `None` if it is not good (yet).
    fn absorb_chunk(&mut self, settings: &Settings, id: &ChunkId, bytes: &[u8]) -> Option<()> {
        let i = id.index;
        match settings {
            Settings::Basin(spec) => {
                let outcomes: Vec<SteadyState> =
                    chunk::decode(bytes, id, |o: &Vec<SteadyState>| basin_content(spec, i, o))
                        .ok()?
                        .value;
                let cells = spec.dx.points * spec.v.points;
                if !matches!(self.partial, Partial::Basin { .. }) {
                    self.partial = Partial::Basin {
                        table: AttractorTable::default(),
                        labels: vec![None; cells],
                    };
                }
                let Partial::Basin { table, labels } = &mut self.partial else {
                    unreachable!()
                };
                let start = i * crate::analysis::global::basin::cells_per_chunk(cells);
                for (k, s) in outcomes.iter().enumerate() {
                    if let Some(l) = labels.get_mut(start + k) {
                        *l = Some(table.classify(s, SAME_POINT_TOL));
                    }
                }
            }
            Settings::FrequencyResponse(spec) | Settings::Hunt(HuntSpec { response: spec, .. }) => {
                let responses: Vec<Response> =
                    chunk::decode(bytes, id, |r: &Vec<Response>| response_content(spec, i, r))
                        .ok()?
                        .value;
                if !matches!(self.partial, Partial::Response(_)) {
                    self.partial = Partial::Response(vec![Vec::new(); spec.omega.points]);
                }
                let Partial::Response(per_omega) = &mut self.partial else {
                    unreachable!()
                };
                for j in chunk_omegas(spec.omega.points, i) {
                    *per_omega.get_mut(j)? = responses
                        .iter()
                        .filter(|r| r.omega_index == j)
                        .map(|r| ResponsePoint::from_response(r, self.grid))
                        .collect();
                }
            }
            Settings::Family(spec) => {
                let member: FamilyMember =
                    chunk::decode(bytes, id, |m: &FamilyMember| family_content(spec, i, m))
                        .ok()?
                        .value;
                if !matches!(self.partial, Partial::Family(_)) {
                    self.partial = Partial::Family(vec![None; spec.values.len()]);
                }
                let Partial::Family(members) = &mut self.partial else {
                    unreachable!()
                };
                let points = member
                    .response
                    .responses
                    .iter()
                    .map(|r| ResponsePoint::from_response(r, self.grid))
                    .collect();
                *members.get_mut(i)? = Some((member.value, points));
            }
            Settings::Map(spec) => {
                let row: MapRow = chunk::decode(bytes, id, |r: &MapRow| map_content(spec, i, r))
                    .ok()?
                    .value;
                if !matches!(self.partial, Partial::Map(_)) {
                    self.partial = Partial::Map(vec![None; spec.values.points]);
                }
                let Partial::Map(rows) = &mut self.partial else {
                    unreachable!()
                };
                *rows.get_mut(i)? = Some(row.cells);
            }
            _ => return None,
        }
        Some(())
    }

    fn partial_view(&self, settings: &Settings) -> Option<ResultView> {
        Some(match (&self.partial, settings) {
            (Partial::Basin { table, labels }, Settings::Basin(spec)) => {
                let done = labels.iter().filter(|l| l.is_some()).count().max(1);
                ResultView::Basin(BasinView {
                    dx: spec.dx.values(),
                    v: spec.v.values(),
                    labels: labels.clone(),
                    attractors: AttractorRow::of_table(table, done, self.grid),
                })
            }
            (Partial::Response(per_omega), Settings::Hunt(_)) => ResultView::Hunt(HuntView {
                responses: per_omega.iter().flatten().cloned().collect(),
                continued: Vec::new(),
            }),
            (Partial::Response(per_omega), _) => {
                ResultView::Response(per_omega.iter().flatten().cloned().collect())
            }
            (Partial::Map(rows), Settings::Map(spec)) => ResultView::Map(MapView {
                x: spec.x.name().into(),
                parameter: spec.parameter.name().into(),
                omegas: spec.response.omega.values(),
                values: spec.values.values(),
                rows: rows.clone(),
                curves: Vec::new(),
            }),
            (Partial::Family(members), Settings::Family(spec)) => ResultView::Family(FamilyView {
                parameter: spec.parameter.name().into(),
                members: members.iter().flatten().cloned().collect(),
            }),
            _ => return None,
        })
    }
}

/// Header-indexed access to a CSV row: the columns by name, and a written model's columns
/// by the built-in model's names too.
struct Columns(HashMap<String, usize>, HashMap<String, usize>);

impl Columns {
    fn new(reader: &mut csv::Reader<std::fs::File>) -> anyhow::Result<Self> {
        let mut c = Columns(
            reader
                .headers()?
                .iter()
                .enumerate()
                .map(|(i, h)| (h.to_string(), i))
                .collect(),
            HashMap::new(),
        );
        c.alias_written();
        Ok(c)
    }

    /// A written model's columns also under the built-in model's names, which the readers
    /// use (see [`super::export::ModelColumns`]): `amplitude` as `amplitude_stretch` (and
    /// `envelope_amplitude` as `envelope_amplitude_stretch`), the
    /// output's extremes after it as `lambda_min` and `lambda_max`, the grid's Poincaré
    /// columns as `poincare_lambda` and `poincare_v`, a basin's offsets as `dx_stretch` and
    /// `v_per_tau`.
    fn alias_written(&mut self) {
        let mut by_index: Vec<(usize, String)> =
            self.0.iter().map(|(n, &i)| (i, n.clone())).collect();
        by_index.sort();
        let names = &self.0;
        let map = &mut self.1;
        let add = |alias: &str, i: usize, map: &mut HashMap<String, usize>| {
            if !names.contains_key(alias) {
                map.insert(alias.to_string(), i);
            }
        };
        let name_of = |i: usize| by_index.get(i).map(|(_, n)| n.as_str()).unwrap_or("");
        for (i, name) in &by_index {
            for stem in ["", "largest_", "peak_", "envelope_"] {
                if *name == format!("{stem}amplitude") {
                    add(&format!("{stem}amplitude_stretch"), *i, map);
                }
            }
            if name == "amplitude" && name_of(i + 1).ends_with("_min") {
                add("lambda_min", i + 1, map);
                add("lambda_max", i + 2, map);
            }
        }
        let offsets: Vec<usize> = by_index
            .iter()
            .filter(|(_, n)| n.ends_with("_offset"))
            .map(|(i, _)| *i)
            .collect();
        if let [a, b, ..] = offsets[..] {
            add("dx_stretch", a, map);
            add("v_per_tau", b, map);
        }
    }

    /// The name of column `i` (files whose columns are named after a parameter).
    fn name_at(&self, i: usize) -> anyhow::Result<String> {
        self.0
            .iter()
            .find(|(_, j)| **j == i)
            .map(|(name, _)| name.clone())
            .ok_or_else(|| anyhow::anyhow!("no column {i}"))
    }

    fn str<'r>(&self, row: &'r csv::StringRecord, name: &str) -> anyhow::Result<&'r str> {
        let i = self
            .0
            .get(name)
            .or_else(|| self.1.get(name))
            .ok_or_else(|| anyhow::anyhow!("no column '{name}'"))?;
        Ok(row.get(*i).unwrap_or(""))
    }

    fn f64(&self, row: &csv::StringRecord, name: &str) -> anyhow::Result<f64> {
        let s = self.str(row, name)?;
        s.parse()
            .map_err(|_| anyhow::anyhow!("column '{name}': '{s}' is not a number"))
    }

    fn opt<T: std::str::FromStr>(&self, row: &csv::StringRecord, name: &str) -> Option<T> {
        self.str(row, name).ok().and_then(|s| s.parse().ok())
    }

    /// The first stroboscopic point, if the row has one: every `start_` column, in order.
    fn start(&self, row: &csv::StringRecord) -> Option<Vec<f64>> {
        let mut columns: Vec<usize> = (self.0.iter())
            .filter(|(name, _)| name.starts_with("start_"))
            .map(|(_, &i)| i)
            .collect();
        columns.sort_unstable();
        let start: Option<Vec<f64>> = (columns.iter())
            .map(|&i| row.get(i).and_then(|s| s.parse().ok()))
            .collect();
        start.filter(|s| s.len() >= 2)
    }

    /// The ratio ω_r:ω_e of its two integer columns.
    fn ratio(&self, row: &csv::StringRecord, prefix: &str) -> Option<Ratio> {
        let response = self.opt(row, &format!("{prefix}ratio_response"))?;
        let excitation: u32 = self.opt(row, &format!("{prefix}ratio_excitation"))?;
        (excitation > 0).then(|| Ratio::new(response, excitation))
    }

    /// The starts that reached no periodic response at one ω_e of an outcomes table
    /// (`export::ResponseTables`), as responses without an amplitude: one per outcome
    /// that any start had.
    fn outcome_points(&self, row: &csv::StringRecord) -> anyhow::Result<Vec<ResponsePoint>> {
        let omega = self.f64(row, "omega")?;
        let mut points = Vec::new();
        for class in [Class::NonPeriodic, Class::Collision] {
            let share = self.f64(row, &format!("{}_share", class.as_str().replace('-', "_")))?;
            if share > 0.0 {
                points.push(ResponsePoint {
                    omega,
                    amplitude: None,
                    response_type: class.as_str().into(),
                    period: None,
                    ratio: None,
                    hidden: None,
                    branch: None,
                    share,
                    start: None,
                });
            }
        }
        Ok(points)
    }

    fn response_point(&self, row: &csv::StringRecord) -> anyhow::Result<ResponsePoint> {
        Ok(ResponsePoint {
            omega: self.f64(row, "omega")?,
            amplitude: self.opt(row, "amplitude_stretch"),
            response_type: self.str(row, "response_type")?.to_string(),
            period: self.opt(row, "period_forcing_periods"),
            ratio: self.ratio(row, ""),
            hidden: self.opt(row, "hidden"),
            branch: self.opt(row, "branch"),
            share: self.opt(row, "share").unwrap_or(0.0),
            start: self.start(row),
        })
    }
}

fn rows(path: &Path) -> anyhow::Result<(Columns, Vec<csv::StringRecord>)> {
    let mut reader = csv::Reader::from_path(path)?;
    let columns = Columns::new(&mut reader)?;
    let rows = reader.records().collect::<Result<Vec<_>, _>>()?;
    Ok((columns, rows))
}

/// The stored result of `entry`, if it is complete and current (for the session's model,
/// device, settings and numerics); an error saying where it stands otherwise.
pub fn current_view(session: &Session, entry: &AnalysisEntry) -> anyhow::Result<ResultView> {
    let mut reader = ResultReader::new(entry);
    reader.poll(session, entry);
    match (reader.status, reader.view, reader.error) {
        (ResultStatus::Complete, Some(view), _) => Ok(view),
        (_, _, Some(error)) => Err(anyhow::anyhow!("{}: {error}", entry.name)),
        (status, _, None) => Err(anyhow::anyhow!(
            "{}: no current result ({status:?})",
            entry.name
        )),
    }
}

/// Reads a finished result's CSV files.
fn read_csv_view(settings: &Settings, paths: &ResultPaths) -> anyhow::Result<ResultView> {
    let (c, rows) = rows(&paths.csv)?;
    Ok(match settings {
        Settings::ForceCurve(_) => {
            let mut curves: Vec<(f64, f64, Vec<[f64; 2]>)> = Vec::new();
            for r in &rows {
                let key = (c.f64(r, "lambda_p")?, c.f64(r, "phi_i")?);
                let point = [c.f64(r, "dx_stretch")?, c.f64(r, "force_nondim")?];
                match curves.last_mut() {
                    Some(last) if (last.0, last.1) == key => last.2.push(point),
                    _ => curves.push((key.0, key.1, vec![point])),
                }
            }
            ResultView::Force(ForceView { curves })
        }
        Settings::TimeHistory(_) => {
            let mut h = HistoryView::default();
            // a written model's history has its two grid states after τ, under their names
            let (x, v) = match c.0.contains_key("lambda_stretch") {
                true => ("lambda_stretch".to_string(), "v_per_tau".to_string()),
                false => {
                    let names = [c.name_at(1)?, c.name_at(2)?];
                    h.states = Some(names.clone());
                    (names[0].clone(), names[1].clone())
                }
            };
            // a written model's amplitude output, for its steady summary
            let output = h.states.is_some() && c.0.contains_key("amplitude_output");
            for r in &rows {
                h.tau.push(c.f64(r, "tau")?);
                h.lambda.push(c.f64(r, &x)?);
                h.v.push(c.f64(r, &v)?);
                h.steady.push(c.str(r, "steady")? == "true");
                if output {
                    h.output.push(c.f64(r, "amplitude_output")?);
                }
                if c.opt::<bool>(r, "collision") == Some(true) {
                    h.collision = h.tau.last().copied();
                }
            }
            ResultView::History(h)
        }
        Settings::ChirpSweep(_) => {
            let mut s = ChirpView::default();
            // a written model's output under its name, after τ, time, ω and Hz
            let output = match c.0.contains_key("lambda_stretch") {
                true => "lambda_stretch".to_string(),
                false => c.name_at(4)?,
            };
            let mut last_envelope = f64::NAN;
            for (j, r) in rows.iter().enumerate() {
                let omega = c.f64(r, "omega")?;
                let envelope = c.f64(r, "envelope_amplitude_stretch")?;
                if j == 1 {
                    s.dt = c.f64(r, "tau")?;
                }
                if envelope != last_envelope {
                    s.envelope.push([omega, envelope]);
                    last_envelope = envelope;
                }
                s.omega.push(omega);
                s.lambda.push(c.f64(r, &output)?);
            }
            ResultView::Chirp(s)
        }
        Settings::SteppedSweep(_) => ResultView::Stepped(
            rows.iter()
                .map(|r| c.response_point(r))
                .collect::<anyhow::Result<_>>()?,
        ),
        Settings::FrequencyResponse(_) => {
            ResultView::Response(response_points(&c, &rows, &paths.csv)?)
        }
        Settings::Hunt(_) => {
            let responses = response_points(&c, &rows, &paths.csv)?;
            let continued = read_continued(&super::export::beside(&paths.csv, "branches"))?;
            ResultView::Hunt(HuntView {
                responses,
                continued: continued.branches,
            })
        }
        Settings::Continuation(_) => ResultView::Continuation(read_continued(&paths.csv)?),
        Settings::Map(spec) => {
            let parameter = spec.parameter.name();
            let (omegas, values) = (spec.response.omega.values(), spec.values.values());
            let mut rows_out: Vec<Option<Vec<MapCell>>> = vec![None; values.len()];
            for (k, r) in rows.iter().enumerate() {
                let row = k / omegas.len().max(1);
                let cell = MapCell {
                    stable: c.f64(r, "stable")? as usize,
                    largest_amplitude: c.opt(r, "largest_amplitude_stretch"),
                    // the short form, `1:2` of `1:2 subharmonic`
                    largest_type: c
                        .str(r, "largest_type")?
                        .split_whitespace()
                        .next()
                        .map(String::from),
                    hidden: c.str(r, "hidden")? == "true",
                    subharmonic: c.str(r, "subharmonic")? == "true",
                    collision_share: c.f64(r, "collision_share")?,
                    non_periodic_share: c.f64(r, "non_periodic_share")?,
                };
                if let Some(slot) = rows_out.get_mut(row) {
                    slot.get_or_insert_with(Vec::new).push(cell);
                }
            }
            ResultView::Map(MapView {
                x: spec.x.name().into(),
                parameter: parameter.into(),
                omegas,
                values,
                rows: rows_out,
                curves: read_curves(&super::export::beside(&paths.csv, "curves"))?,
            })
        }
        Settings::Basin(spec) => {
            let labels = rows
                .iter()
                .map(|r| c.opt::<usize>(r, "attractor"))
                .collect();
            let (t, table_rows) = self::rows(&paths.csv.with_extension("attractors.csv"))?;
            let attractors = table_rows
                .iter()
                .map(|r| {
                    Ok(AttractorRow {
                        id: t.f64(r, "attractor")? as usize,
                        response_type: t.str(r, "response_type")?.to_string(),
                        amplitude: t.opt(r, "amplitude_stretch"),
                        cells: t.f64(r, "cells")? as usize,
                        fraction: t.f64(r, "fraction")?,
                        start: t.start(r),
                    })
                })
                .collect::<anyhow::Result<_>>()?;
            ResultView::Basin(BasinView {
                dx: spec.dx.values(),
                v: spec.v.values(),
                labels,
                attractors,
            })
        }
        Settings::Family(spec) => {
            let parameter = spec.parameter.name();
            let (rc, response_rows) = self::rows(&super::export::beside(&paths.csv, "responses"))?;
            let mut members: Vec<(f64, Vec<ResponsePoint>)> = Vec::new();
            let mut add = |value: f64, points: Vec<ResponsePoint>| match members
                .iter_mut()
                .find(|m| m.0 == value)
            {
                Some(member) => member.1.extend(points),
                None => members.push((value, points)),
            };
            for r in &response_rows {
                add(rc.f64(r, parameter)?, vec![rc.response_point(r)?]);
            }
            let (oc, outcome_rows) = self::rows(&super::export::beside(&paths.csv, "outcomes"))?;
            for r in &outcome_rows {
                add(oc.f64(r, parameter)?, oc.outcome_points(r)?);
            }
            ResultView::Family(FamilyView {
                parameter: parameter.into(),
                members,
            })
        }
    })
}

/// A frequency response's periodic responses (`rows` of `csv`) and, from its outcomes table,
/// the starts that reached none.
fn response_points(
    c: &Columns,
    rows: &[csv::StringRecord],
    csv: &Path,
) -> anyhow::Result<Vec<ResponsePoint>> {
    let mut points = rows
        .iter()
        .map(|r| c.response_point(r))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let (oc, outcome_rows) = self::rows(&super::export::beside(csv, "outcomes"))?;
    for r in &outcome_rows {
        points.extend(oc.outcome_points(r)?);
    }
    Ok(points)
}

/// Item `id` of `items`, numbered from 0 as a file's rows name them (the list grown to hold
/// it).
fn numbered<T: Default + Clone>(items: &mut Vec<T>, id: usize) -> &mut T {
    if items.len() <= id {
        items.resize(id + 1, T::default());
    }
    &mut items[id]
}

/// Reads a continued-branch file (see [`super::export::continued_csv`]).
fn read_continued(path: &Path) -> anyhow::Result<ContinuationView> {
    let (c, rows) = rows(path)?;
    let parameter = c.name_at(4)?;
    // the state columns after ω_e (a written model's own names)
    let first = c.name_at(6)?;
    let second = Some(c.name_at(7)?)
        .filter(|name| name.ends_with("_0"))
        .unwrap_or_else(|| first.clone());
    let mut branches: Vec<ContinuedView> = Vec::new();
    for r in &rows {
        let b = numbered(&mut branches, c.f64(r, "branch")? as usize);
        b.period = c.f64(r, "period")? as usize;
        b.verdict = c.str(r, "verdict")?.to_string();
        let (value, omega, amplitude) = (
            c.f64(r, &parameter)?,
            c.f64(r, "omega_e")?,
            c.f64(r, "amplitude_stretch")?,
        );
        match c.str(r, "kind")? {
            "point" => b.points.push(ContinuedPoint {
                parameter: value,
                omega,
                amplitude,
                stable: c.str(r, "stable")? == "true",
                start: [c.f64(r, &first)?, c.f64(r, &second)?],
            }),
            kind => b.bifurcations.push(BifurcationPoint {
                kind: kind.to_string(),
                parameter: value,
                omega,
                amplitude,
            }),
        }
    }
    Ok(ContinuationView {
        parameter,
        branches,
    })
}

/// Reads a curves file (see [`super::export::curves_csv`]).
fn read_curves(path: &Path) -> anyhow::Result<Vec<CurveView>> {
    let (c, rows) = rows(path)?;
    let (first, second) = (c.name_at(5)?, c.name_at(6)?);
    let mut curves: Vec<CurveView> = Vec::new();
    for r in &rows {
        let curve = numbered(&mut curves, c.f64(r, "curve")? as usize);
        curve.kind = c.str(r, "kind")?.to_string();
        curve.period = c.f64(r, "period")? as usize;
        let at = [c.f64(r, &first)?, c.f64(r, &second)?];
        match c.str(r, "at")? {
            "point" => curve.points.push(at),
            turning => curve
                .extrema
                .push((turning.into(), c.str(r, "of")?.into(), at)),
        }
    }
    Ok(curves)
}
