//! Running a session's analyses headless through the results store ([`super::store`]): a
//! killed run resumes where it stopped and produces the same files, byte for byte; runs of
//! one session at once, and shards on the nodes of a cluster, share the work chunk by chunk;
//! exactly one of them assembles the result.

use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use anyhow::Context;
use rayon::prelude::*;

use super::export;
use super::schema::{AnalysisEntry, Session, Settings};
use super::store::chunk::Payload;
use super::store::finite::first_non_finite;
use super::store::manifest::{MANIFEST_FORMAT, Manifest};
use super::store::saver::ChunkSaver;
use super::store::survey::{Survey, survey};
use super::store::{self, ResultPaths, Work, lock, unix_now};
use super::written::ModelPoint;
use crate::analysis::continuation::branch_from_state::branch_from_state;
use crate::analysis::continuation::hunt::{HuntSpec, hunt_in};
use crate::analysis::continuation::map::{MapRow, MapSpec, map_curves, map_row};
use crate::analysis::continuation::model::Continuable;
use crate::analysis::global::basin::{BasinPlan, BasinSpec, cells_per_chunk};
use crate::analysis::global::family::{FamilyMember, FamilySpec, family_member};
use crate::analysis::global::frequency_response::{
    FrequencyResponseSpec, Response, ResponsePlan, chunk_omegas, omegas_per_chunk,
};
use crate::analysis::global::oscillator::chirp::written_chirp_sweep;
use crate::analysis::global::oscillator::history::state_history;
use crate::analysis::global::stepped_sweep::{SweepFindings, stepped_sweep};
use crate::analysis::orbit::chirp_sweep::{ChirpSpec, ChirpSweep, chirp_sweep};
use crate::analysis::orbit::force_curve::force_curves;
use crate::analysis::orbit::scalogram::scalogram;
use crate::analysis::orbit::time_history::time_history;
use crate::analysis::windows::in_windows;
use crate::analysis::{AnalysisError, Oscillator, Progress, SteadyState};
use crate::model::Params;
use crate::model::equations::EquationSystem;

impl ResultPaths {
    /// Where analysis `name` of `session` keeps its result.
    pub fn new(session: &Session, name: &str) -> Self {
        ResultPaths::in_dir(&session.results_dir(), name)
    }
}

/// Which chunks this process computes: all, or those with index ≡ `index` mod `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    fn owns(&self, chunk: usize) -> bool {
        chunk % self.count == self.index
    }
}

/// What happened to one analysis.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Its result was already complete, verified and current.
    UpToDate,
    /// The result of these settings, kept when other settings' replaced it, is the stored
    /// result again (verified, nothing computed); `seconds` it had taken to compute.
    BroughtBack { seconds: f64 },
    /// Complete now: assembled by this run, or by another run this one worked beside.
    Completed {
        chunks_computed: usize,
        /// Seconds of computing in all (every chunk, on whichever host, and the assembly).
        seconds: f64,
        assembled_here: bool,
        /// What the user should know about a result assembled here (a map's window that cuts
        /// a branch, so that its curves beyond are missing).
        notes: Vec<String>,
    },
    /// This shard's chunks are done; others are still missing.
    ShardDone {
        chunks_computed: usize,
        missing: usize,
    },
    /// Computed but not stored: the session file was edited during the run, and the stored
    /// result is of its settings now.
    Superseded { chunks_computed: usize },
}

impl Outcome {
    /// The same outcome with `more` notes, if it completed a result.
    fn with_notes(self, more: Vec<String>) -> Self {
        match self {
            Outcome::Completed {
                chunks_computed,
                seconds,
                assembled_here,
                mut notes,
            } => {
                notes.extend(more);
                Outcome::Completed {
                    chunks_computed,
                    seconds,
                    assembled_here,
                    notes,
                }
            }
            other => other,
        }
    }
}

/// True when `entry`'s stored result is complete, passes its checksums and belongs to the
/// session's current model, device, settings and numerics.
pub fn is_current(session: &Session, entry: &AnalysisEntry) -> bool {
    store::is_current(
        &ResultPaths::new(session, &entry.name),
        &session.fingerprint(entry),
    )
}

/// How many chunks an analysis of these settings is cut into (1 for those computed whole).
pub fn chunk_count(settings: &Settings) -> usize {
    match settings {
        Settings::Basin(spec) => {
            let cells = spec.dx.points * spec.v.points;
            cells.div_ceil(cells_per_chunk(cells))
        }
        Settings::FrequencyResponse(spec) | Settings::Hunt(HuntSpec { response: spec, .. }) => {
            let points = spec.omega.points;
            points.div_ceil(omegas_per_chunk(points))
        }
        Settings::Map(spec) => spec.values.points,
        Settings::Family(spec) => spec.values.len(),
        _ => 1,
    }
}

/// The files of a result whose main file is `csv`, in the order they are recorded.
pub fn output_files(settings: &Settings, csv: &Path) -> Vec<PathBuf> {
    let mut files = vec![csv.to_path_buf()];
    let tables: &[&str] = match settings {
        Settings::Basin(_) => &export::BASIN_TABLES,
        Settings::FrequencyResponse(_) => &export::RESPONSE_TABLES,
        Settings::Hunt(_) => &["branches", "points", "outcomes"],
        Settings::Map(_) => &["curves"],
        Settings::Family(_) => &export::FAMILY_TABLES,
        Settings::ChirpSweep(_) => &export::CHIRP_TABLES,
        Settings::SteppedSweep(_) => &export::STEPPED_TABLES,
        _ => &[],
    };
    files.extend(tables.iter().map(|t| export::beside(csv, t)));
    if let Settings::ChirpSweep(spec) = settings
        && spec.scalogram.is_some()
    {
        files.extend(
            export::SCALOGRAM_TABLES
                .iter()
                .map(|t| export::beside(csv, t)),
        );
    }
    files
}

impl Payload for MapRow {
    fn items(&self) -> usize {
        self.cells.len()
    }
}

impl Payload for FamilyMember {
    fn items(&self) -> usize {
        self.response.responses.len()
    }
}

/// [`survey_of`] from the chunks' header lines only
/// ([`crate::session::store::survey::glance`]): progress for the workbench.
pub fn glance_of(session: &Session, entry: &AnalysisEntry) -> Survey {
    let paths = ResultPaths::new(session, &entry.name);
    crate::session::store::survey::glance(
        &paths,
        &session.fingerprint(entry),
        chunk_count(&entry.settings),
    )
}

/// The work under way on `entry` for the session's current settings: chunks done (by which
/// host), claimed, missing.
pub fn survey_of(session: &Session, entry: &AnalysisEntry) -> Survey {
    let paths = ResultPaths::new(session, &entry.name);
    let fingerprint = session.fingerprint(entry);
    let n = chunk_count(&entry.settings);
    match &entry.settings {
        Settings::Basin(spec) => survey(&paths, &fingerprint, n, |i, o: &Vec<SteadyState>| {
            basin_content(spec, i, o)
        }),
        Settings::FrequencyResponse(spec) | Settings::Hunt(HuntSpec { response: spec, .. }) => {
            survey(&paths, &fingerprint, n, |i, r: &Vec<Response>| {
                response_content(spec, i, r)
            })
        }
        Settings::Map(spec) => survey(&paths, &fingerprint, n, |i, r: &MapRow| {
            map_content(spec, i, r)
        }),
        Settings::Family(spec) => survey(&paths, &fingerprint, n, |i, m: &FamilyMember| {
            family_content(spec, i, m)
        }),
        // computed whole: no chunk file, only a claim while it runs
        _ => survey(
            &paths,
            &fingerprint,
            n,
            |_, _: &Vec<f64>| Err("none".into()),
        ),
    }
}

/// What chunk `i` of a basin must hold: one outcome per cell of the chunk.
pub fn basin_content(spec: &BasinSpec, i: usize, outcomes: &[SteadyState]) -> Result<(), String> {
    let cells = spec.dx.points * spec.v.points;
    let per_chunk = cells_per_chunk(cells);
    let expected = per_chunk.min(cells.saturating_sub(i * per_chunk));
    if outcomes.len() == expected {
        Ok(())
    } else {
        Err(format!(
            "{} cells, chunk {i} has {expected}",
            outcomes.len()
        ))
    }
}

/// What chunk `i` of a frequency response must hold: responses at each of its ω_e
/// ([`chunk_omegas`]) whose counts add up to the grid of initial states.
pub fn response_content(
    spec: &FrequencyResponseSpec,
    i: usize,
    responses: &[Response],
) -> Result<(), String> {
    let omegas = chunk_omegas(spec.omega.points, i);
    if let Some(r) = responses
        .iter()
        .find(|r| !omegas.contains(&r.omega_index) || r.omega != spec.omega.at(r.omega_index))
    {
        return Err(format!(
            "a response at ω_e {} (index {}), chunk {i} is ω_e indices {omegas:?}",
            r.omega, r.omega_index
        ));
    }
    let starts = spec.dx.points * spec.v.points;
    for j in omegas {
        let counted: usize = responses
            .iter()
            .filter(|r| r.omega_index == j)
            .map(|r| r.count)
            .sum();
        if counted != starts {
            return Err(format!(
                "{counted} starts counted at ω_e {}, the grid has {starts}",
                spec.omega.at(j)
            ));
        }
    }
    Ok(())
}

/// What row `i` of a map must hold: its value of the parameter and a cell per value of x.
pub fn map_content(spec: &MapSpec, i: usize, row: &MapRow) -> Result<(), String> {
    let (value, columns) = (spec.values.at(i), spec.response.omega.points);
    if row.value != value || row.cells.len() != columns {
        return Err(format!(
            "row at {} with {} cells, row {i} is at {value} with {columns}",
            row.value,
            row.cells.len()
        ));
    }
    Ok(())
}

/// What member `i` of a family must hold: its value and a response over the whole ω grid.
pub fn family_content(spec: &FamilySpec, i: usize, member: &FamilyMember) -> Result<(), String> {
    let value = spec.values.get(i).copied();
    let columns = spec.response.omega.points;
    if Some(member.value) != value || member.response.omegas.len() != columns {
        return Err(format!(
            "member at {} over {} ω_e, member {i} is at {value:?} over {columns}",
            member.value,
            member.response.omegas.len()
        ));
    }
    for (j, r) in member.response.responses.iter().enumerate() {
        if r.omega_index >= columns {
            return Err(format!("response {j} at ω_e index {}", r.omega_index));
        }
    }
    Ok(())
}

/// How a run takes part in computing an analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Role {
    /// The chunks it may compute.
    pub shard: Shard,
    /// A worker of a cluster job: it computes the chunks nobody has claimed, again and again
    /// until none is left, and never waits for chunks claimed by other runs (a whole run
    /// waits for them, and computes those whose claimer died).
    pub worker: bool,
}

impl Role {
    /// A run that computes, or waits for, every chunk of `shard`.
    pub fn whole(shard: Shard) -> Role {
        Role {
            shard,
            worker: false,
        }
    }
}

/// Runs one analysis of `session`: returns at once if its stored result is current, else
/// computes the chunks this shard owns that no other run has done or is doing, and
/// assembles the result once every chunk is there.
pub fn run_analysis(
    session: &Session,
    entry: &AnalysisEntry,
    shard: Shard,
    progress: &Progress,
) -> anyhow::Result<Outcome> {
    run_analysis_as(session, entry, Role::whole(shard), progress)
}

/// Brings back the result of `entry`'s settings kept from before (replaced by other
/// settings'), verified, computing nothing: [`Outcome::BroughtBack`], or `None` where no kept
/// result passes its checks (a damaged one is removed).
pub fn bring_back(session: &Session, entry: &AnalysisEntry) -> anyhow::Result<Option<Outcome>> {
    let paths = ResultPaths::new(session, &entry.name);
    let fingerprint = session.fingerprint(entry);
    let Some(m) = store::earlier::bring_back(&paths, &fingerprint)? else {
        return Ok(None);
    };
    store::remove_unused_work(&paths, &fingerprint);
    Ok(Some(Outcome::BroughtBack {
        seconds: m.compute_seconds,
    }))
}

/// [`run_analysis`] in a given role.
pub fn run_analysis_as(
    session: &Session,
    entry: &AnalysisEntry,
    role: Role,
    progress: &Progress,
) -> anyhow::Result<Outcome> {
    let paths = ResultPaths::new(session, &entry.name);
    let fingerprint = session.fingerprint(entry);
    std::fs::create_dir_all(&paths.dir)
        .with_context(|| format!("results folder {}", paths.dir.display()))?;
    match store::verified(&paths) {
        Ok(m) if m.fingerprint == fingerprint => {
            tracing::info!(analysis = %entry.name, "up to date");
            store::remove_unused_work(&paths, &fingerprint);
            return Ok(Outcome::UpToDate);
        }
        Ok(m) => tracing::info!(analysis = %entry.name, old = %m.fingerprint, new = %fingerprint,
            "stored result is stale: kept until the new one is complete"),
        Err(why) => tracing::info!(analysis = %entry.name, reason = %why, "no usable result"),
    }
    if let Some(outcome) = bring_back(session, entry)? {
        return Ok(outcome);
    }
    let work = Work::join(&paths, &fingerprint)?;
    let run = Run {
        session,
        entry,
        shard: role.shard,
        worker: role.worker,
        progress,
        work: &work,
        chunks: chunk_count(&entry.settings),
        as_on_disk: on_disk(session, &entry.name).as_ref() == Some(&fingerprint),
    };
    let outcome = run.run();
    work.retire();
    match &outcome {
        Ok(o) => tracing::info!(analysis = %entry.name, outcome = ?o, "run ended"),
        Err(e) => tracing::warn!(analysis = %entry.name, error = %format!("{e:#}"), "run failed"),
    }
    outcome
}

/// One run's part in computing one analysis.
struct Run<'a> {
    session: &'a Session,
    entry: &'a AnalysisEntry,
    shard: Shard,
    worker: bool,
    progress: &'a Progress,
    work: &'a Work,
    chunks: usize,
    /// Whether it computes the analysis as the session file on disk had it at the start (a
    /// headless run); not a workbench's edits not saved yet.
    as_on_disk: bool,
}

/// The fingerprint of analysis `name` as the session file of `session` on disk has it now.
fn on_disk(session: &Session, name: &str) -> Option<String> {
    let on_disk = Session::load(&session.path).ok()?;
    let entry = on_disk.analysis(name)?;
    Some(on_disk.fingerprint(entry))
}

/// The chunks of a result in index order, read as they are taken; an error names a chunk
/// that was damaged or removed since it was checked.
type Chunks<'a, T> = Box<dyn Iterator<Item = anyhow::Result<T>> + 'a>;

/// Chunks read and parsed side by side while the assembly takes them in order.
const LOAD_AHEAD: usize = 32;

/// What became of one chunk in one pass.
enum Step {
    /// Its file was there and good (or another run finished it while this one waited).
    Existing,
    Computed,
    /// Another run is computing it.
    Claimed,
    Cancelled,
}

impl Run<'_> {
    fn cancelled(&self) -> bool {
        self.progress.is_cancelled()
    }

    fn cancelled_error(&self) -> anyhow::Error {
        anyhow::anyhow!("{}: cancelled", self.entry.name)
    }

    fn named(&self) -> impl Fn(AnalysisError) -> anyhow::Error + '_ {
        move |e| anyhow::anyhow!("{}: {e}", self.entry.name)
    }

    fn run(&self) -> anyhow::Result<Outcome> {
        match self.session.point(Some(self.entry))? {
            ModelPoint::BuiltIn(params) => self.run_on(
                &params,
                &export::ModelColumns::built_in(&self.session.device()),
            ),
            ModelPoint::Written(sys) => {
                let columns = export::ModelColumns::written(sys.model());
                self.run_on(&sys, &columns)
            }
        }
    }

    /// The analysis on `params`, the built-in model or a written one; `columns` name its
    /// states in continued branches.
    fn run_on<M: Continuable + Single>(
        &self,
        params: &M,
        columns: &export::ModelColumns,
    ) -> anyhow::Result<Outcome> {
        let entry = self.entry;
        let progress = self.progress;
        let named = self.named();
        match &entry.settings {
            Settings::Basin(spec) => self.basin(params, spec, params.omega(), columns),
            Settings::FrequencyResponse(spec) => self.response(params, spec, None, columns),
            Settings::Hunt(hunt) => self.response(params, &hunt.response, Some(hunt), columns),
            Settings::Map(spec) => {
                spec.validate(params)?;
                // the rows' work announced at once (rows found done count as done), so the
                // gauge runs once from 0 to 100 %
                let row_work = spec.response.work();
                progress.grow_total(spec.values.points * row_work);
                let mut notes = Vec::new();
                let outcome = self.chunked(
                    |_| progress.add(row_work),
                    |i| optional(map_row(params, spec, i, progress)),
                    |i, row: &MapRow| map_content(spec, i, row),
                    |i| format!("{} = {}", spec.parameter.name(), spec.values.at(i)),
                    |chunks, csv| {
                        let rows: Vec<MapRow> = chunks.collect::<anyhow::Result<_>>()?;
                        let curves = if spec.curves {
                            let found =
                                map_curves(params, spec, &rows, progress).map_err(&named)?;
                            let names = (spec.x.name(), spec.parameter.name());
                            for cut in &found.cut {
                                let note = cut.describe(names.0, names.1);
                                tracing::warn!("{note}");
                                notes.push(note);
                            }
                            found.curves
                        } else {
                            Vec::new()
                        };
                        finite(&curves, "the map's curves")?;
                        export::curves_csv(&curves, columns, &export::beside(csv, "curves"))?;
                        let omegas = spec.response.omega.values();
                        let names = (spec.x.name(), spec.parameter.name());
                        export::map_csv(names, &omegas, &rows, columns, csv)
                    },
                )?;
                Ok(outcome.with_notes(notes))
            }
            Settings::Family(spec) => {
                spec.validate(params)?;
                // the members' work announced at once, as a map's rows
                let member_work = spec.response.work();
                progress.grow_total(spec.values.len() * member_work);
                self.chunked(
                    |_| progress.add(member_work),
                    |i| optional(family_member(params, spec, i, progress)),
                    |i, member: &FamilyMember| family_content(spec, i, member),
                    |i| format!("{} = {}", spec.parameter.name(), spec.values[i]),
                    |chunks, csv| {
                        let members: Vec<FamilyMember> = chunks.collect::<anyhow::Result<_>>()?;
                        let name = spec.parameter.name();
                        export::family_csv(name, &members, columns, csv)?;
                        export::family_responses_csv(name, &members, columns, csv)
                    },
                )
            }
            Settings::Continuation(spec) => self.whole(|csv| {
                let branch = branch_from_state(params, spec, progress)?;
                finite(&branch, "the continued branch")?;
                export::continued_csv(&[&branch], columns, csv).map(|()| Vec::new())
            }),
            single => self.whole(|csv| params.run_single(single, columns, csv, progress)),
        }
    }

    /// A basin, chunk by chunk; `omega` for its attractor table.
    fn basin<O: Oscillator>(
        &self,
        osc: &O,
        spec: &BasinSpec,
        omega: f64,
        columns: &export::ModelColumns,
    ) -> anyhow::Result<Outcome> {
        let progress = self.progress;
        let named = self.named();
        let plan = BasinPlan::new(osc, spec, progress).map_err(&named)?;
        progress.grow_total(plan.cells());
        let (dx, v) = (spec.dx.values(), spec.v.values());
        self.chunked(
            |i| progress.add(plan.chunk_cells(i).len()),
            |i| optional(plan.chunk(i, progress)),
            |i, outcomes: &Vec<SteadyState>| basin_content(spec, i, outcomes),
            |i| {
                let first = i * plan.per_chunk();
                let last = (first + plan.per_chunk()).min(dx.len() * v.len()) - 1;
                // the offsets as the settings name them (a written model's grid states too)
                let at = |c: usize| format!("(dx {}, v {})", dx[c / v.len()], v[c % v.len()]);
                format!("cells {first}–{last}, {} to {}", at(first), at(last))
            },
            |chunks, csv| {
                let mut failed = None;
                let basin =
                    plan.assemble(chunks.map_while(|c| c.map_err(|e| failed = Some(e)).ok()));
                if let Some(e) = failed {
                    return Err(e);
                }
                finite(&basin, "the assembled basin")?;
                export::basin_csv(&basin, omega, columns, csv).map(drop)
            },
        )
    }

    /// A frequency response (and, with `hunt`, the isola hunt on it), a chunk per
    /// [`omegas_per_chunk`] ω_e.
    fn response<M: Continuable>(
        &self,
        osc: &M,
        spec: &FrequencyResponseSpec,
        hunt: Option<&HuntSpec>,
        columns: &export::ModelColumns,
    ) -> anyhow::Result<Outcome> {
        let progress = self.progress;
        let named = self.named();
        let plan = ResponsePlan::new(osc, spec).map_err(&named)?;
        progress.grow_total(plan.work());
        let (points, starts) = (spec.omega.points, spec.dx.points * spec.v.points);
        self.chunked(
            |i| progress.add(starts * chunk_omegas(points, i).len()),
            |i| {
                let grids: Result<Vec<Vec<Response>>, _> = chunk_omegas(points, i)
                    .map(|j| plan.grid_at(j, progress))
                    .collect();
                optional(grids.map(|g| g.concat()))
            },
            |i, responses: &Vec<Response>| response_content(spec, i, responses),
            |i| {
                let omegas = chunk_omegas(points, i);
                let (first, last) = (omegas.start, omegas.end - 1);
                match first == last {
                    true => format!("ω_e = {}", spec.omega.at(first)),
                    false => format!("ω_e = {} to {}", spec.omega.at(first), spec.omega.at(last)),
                }
            },
            |chunks, csv| {
                // each ω_e's responses in the order its grid found them
                let mut per_omega: Vec<Vec<Response>> = vec![Vec::new(); points];
                for chunk in chunks {
                    for r in chunk? {
                        let j = r.omega_index;
                        per_omega[j].push(r);
                    }
                }
                let fr = plan.finish(per_omega, progress).map_err(&named)?;
                if let Some(hunt) = hunt {
                    let found = hunt_in(osc, fr, &hunt.continuation, progress).map_err(&named)?;
                    finite(&found, "the hunt")?;
                    let branches: Vec<_> = found.branches.iter().map(|h| &h.branch).collect();
                    export::continued_csv(&branches, columns, &export::beside(csv, "branches"))?;
                    export::response_csv(&found.response, columns, csv).map(drop)
                } else {
                    finite(&fr, "the frequency response")?;
                    export::response_csv(&fr, columns, csv).map(drop)
                }
            },
        )
    }

    /// An analysis computed whole, as chunk 0: by the run that claims it. `compute` writes the
    /// result and returns what the user should know about it.
    fn whole(
        &self,
        compute: impl FnOnce(&Path) -> anyhow::Result<Vec<String>>,
    ) -> anyhow::Result<Outcome> {
        let progress = self.progress;
        if !self.shard.owns(0) {
            return Ok(Outcome::ShardDone {
                chunks_computed: 0,
                missing: 1,
            });
        }
        progress.grow_total(1);
        let claim = if self.worker {
            self.work.try_claim(0)?
        } else {
            match self.work.claim(0, &|| self.cancelled())? {
                Some(c) => Some(c),
                None => return Err(self.cancelled_error()),
            }
        };
        let Some(_claim) = claim else {
            // another run computes it
            return Ok(Outcome::ShardDone {
                chunks_computed: 0,
                missing: 1,
            });
        };
        if let Ok(m) = store::verified(&self.work.paths)
            && m.fingerprint == self.work.fingerprint
        {
            progress.add(1);
            return Ok(Outcome::Completed {
                chunks_computed: 0,
                seconds: m.compute_seconds,
                assembled_here: false,
                notes: Vec::new(),
            });
        }
        let started = Instant::now();
        let staging = self.work.staging()?;
        let csv = staging.join(file_name(&self.work.paths.csv));
        let notes = compute(&csv).with_context(|| self.entry.name.clone())?;
        if self.cancelled() {
            return Err(self.cancelled_error());
        }
        progress.add(1);
        let Some(m) = self.commit(&csv, started.elapsed().as_secs_f64())? else {
            return Ok(Outcome::Superseded { chunks_computed: 1 });
        };
        Ok(Outcome::Completed {
            chunks_computed: 1,
            seconds: m.compute_seconds,
            assembled_here: true,
            notes,
        })
    }

    /// A chunked analysis: this shard's missing chunks computed (claimed one by one, shared
    /// with other runs), then, if every chunk is there and good, the result assembled.
    fn chunked<T: Payload>(
        &self,
        on_existing: impl Fn(usize) + Sync,
        compute: impl Fn(usize) -> anyhow::Result<Option<T>> + Sync,
        content: impl Fn(usize, &T) -> Result<(), String> + Sync,
        describe: impl Fn(usize) -> String + Sync,
        mut finish: impl FnMut(Chunks<'_, T>, &Path) -> anyhow::Result<()>,
    ) -> anyhow::Result<Outcome> {
        let n = self.chunks;
        let counted: Vec<AtomicBool> = (0..n).map(|_| AtomicBool::new(false)).collect();
        let existing = |i: usize| {
            if !counted[i].swap(true, Ordering::Relaxed) {
                on_existing(i);
            }
        };
        let mine: Vec<usize> = (0..n).filter(|&i| self.shard.owns(i)).collect();
        let mut computed = 0;
        // a chunk that is good when computed but fails when checked or assembled (damaged
        // meanwhile, or a payload this build cannot read) sends the run round again; a file
        // system that damages everything ends in an error
        for _round in 0..3 {
            let saver = ChunkSaver::start(&self.work.dir)?;
            let one = |i: usize, wait: bool| -> anyhow::Result<Step> {
                self.one_chunk(i, wait, &saver, &existing, &compute, &describe)
            };
            let mut steps: Vec<(usize, Step)> = mine
                .par_iter()
                .map(|&i| one(i, false).map(|s| (i, s)))
                .collect::<anyhow::Result<_>>()?;
            let claimed = |steps: &[(usize, Step)]| -> Vec<usize> {
                steps
                    .iter()
                    .filter(|(_, s)| matches!(s, Step::Claimed))
                    .map(|(i, _)| *i)
                    .collect()
            };
            // a worker goes round the chunks claimed elsewhere while that finds work (their
            // claimer may have died); a whole run waits for each of them
            let mut waited: Vec<Step> = Vec::new();
            loop {
                let waiting = claimed(&steps);
                if waiting.is_empty() {
                    break;
                }
                if !self.worker {
                    waited = waiting
                        .par_iter()
                        .map(|&i| one(i, true))
                        .collect::<anyhow::Result<_>>()?;
                    break;
                }
                let again: Vec<(usize, Step)> = waiting
                    .par_iter()
                    .map(|&i| one(i, false).map(|s| (i, s)))
                    .collect::<anyhow::Result<_>>()?;
                let found_work = again.iter().any(|(_, s)| matches!(s, Step::Computed));
                steps.retain(|(_, s)| !matches!(s, Step::Claimed));
                steps.extend(again);
                if !found_work {
                    break;
                }
            }
            // every chunk computed is on disk before any is checked
            saver.finish()?;
            computed += steps
                .iter()
                .map(|(_, s)| s)
                .chain(&waited)
                .filter(|s| matches!(s, Step::Computed))
                .count();
            if self.cancelled()
                || steps
                    .iter()
                    .map(|(_, s)| s)
                    .chain(&waited)
                    .any(|s| matches!(s, Step::Cancelled))
            {
                return Err(self.cancelled_error());
            }
            let (seconds, missing) = self.check_all()?;
            if missing.is_empty() {
                match self.assemble(&content, seconds, computed, &mut finish)? {
                    Some(outcome) => return Ok(outcome),
                    None => continue,
                }
            }
            // missing: other shards' chunks, or (for a worker) chunks other runs compute
            if self.worker || missing.iter().all(|&i| !self.shard.owns(i)) {
                return Ok(Outcome::ShardDone {
                    chunks_computed: computed,
                    missing: missing.len(),
                });
            }
        }
        anyhow::bail!(
            "{}: chunks in {} fail their checks again and again (see run.log)",
            self.entry.name,
            self.work.dir.display()
        )
    }

    /// Chunk `i` in one pass: used if its file is good, computed if this run gets its claim,
    /// left to its claimer otherwise (or, with `wait`, waited for and then used or computed).
    fn one_chunk<T: Payload>(
        &self,
        i: usize,
        wait: bool,
        saver: &ChunkSaver,
        existing: &(impl Fn(usize) + Sync),
        compute: &(impl Fn(usize) -> anyhow::Result<Option<T>> + Sync),
        describe: &(impl Fn(usize) -> String + Sync),
    ) -> anyhow::Result<Step> {
        let (work, n) = (self.work, self.chunks);
        if self.cancelled() {
            return Ok(Step::Cancelled);
        }
        // a chunk that could not be written ends the run: computing more would be in vain
        saver.healthy()?;
        if let Ok(Some(_)) = work.check_chunk(i, n) {
            existing(i);
            return Ok(Step::Existing);
        }
        let claim = if wait {
            match work.claim(i, &|| self.cancelled())? {
                Some(c) => c,
                None => return Ok(Step::Cancelled),
            }
        } else {
            match work.try_claim(i)? {
                Some(c) => c,
                None => return Ok(Step::Claimed),
            }
        };
        // checked again under the claim: its previous holder may have just finished it
        match work.check_chunk(i, n) {
            Ok(Some(_)) => {
                existing(i);
                return Ok(Step::Existing);
            }
            Ok(None) => {}
            Err(why) => work.reject(i, &why),
        }
        let started = Instant::now();
        let at_chunk = || {
            format!(
                "{} ({}): chunk {i}, {}",
                self.entry.name,
                self.entry.settings.kind(),
                describe(i)
            )
        };
        let Some(value) = compute(i).with_context(at_chunk)? else {
            return Ok(Step::Cancelled);
        };
        if self.cancelled() {
            // a chunk cut short by a cancel is not a chunk
            return Ok(Step::Cancelled);
        }
        let bytes = work
            .encode_chunk(i, n, &value, started.elapsed().as_secs_f64())
            .with_context(at_chunk)?;
        // written by the saver's thread, which releases the claim then
        work.save_chunk(saver, i, bytes, claim, at_chunk());
        Ok(Step::Computed)
    }

    /// The seconds the good chunks took, and the indices of those missing (a chunk found
    /// damaged now is moved aside and counted missing); each file's checksum is checked, its
    /// payload is parsed only by the assembly.
    fn check_all(&self) -> anyhow::Result<(f64, Vec<usize>)> {
        let (work, n) = (self.work, self.chunks);
        // each chunk's seconds, or None if it is missing (read side by side)
        let checked: Vec<Option<f64>> = (0..n)
            .into_par_iter()
            .map(|i| match work.check_chunk(i, n) {
                Ok(seconds) => Ok(seconds),
                Err(_) => {
                    work.reject_if_still_bad(i, || work.check_chunk(i, n))?;
                    Ok(None)
                }
            })
            .collect::<anyhow::Result<_>>()?;
        let seconds = checked.iter().flatten().sum();
        let missing = (0..n).filter(|&i| checked[i].is_none()).collect();
        Ok((seconds, missing))
    }

    /// Assembles the result from every chunk, unless another run has just done so; only one
    /// run assembles at a time. `None` where a chunk fails to load (damaged since it was
    /// checked, or a payload this build cannot read): it is moved aside, to be computed again.
    fn assemble<T: Payload>(
        &self,
        content: &(impl Fn(usize, &T) -> Result<(), String> + Sync),
        chunk_seconds: f64,
        computed: usize,
        finish: &mut impl FnMut(Chunks<'_, T>, &Path) -> anyhow::Result<()>,
    ) -> anyhow::Result<Option<Outcome>> {
        let Some(_assembler) = self.work.assembler(&|| self.cancelled())? else {
            return Err(self.cancelled_error());
        };
        if let Ok(m) = store::verified(&self.work.paths)
            && m.fingerprint == self.work.fingerprint
        {
            return Ok(Some(Outcome::Completed {
                chunks_computed: computed,
                seconds: m.compute_seconds,
                assembled_here: false,
                notes: Vec::new(),
            }));
        }
        let started = Instant::now();
        let staging = self.work.staging()?;
        let csv = staging.join(file_name(&self.work.paths.csv));
        // the first chunk that failed to load, if any
        let failed: Cell<Option<usize>> = Cell::new(None);
        finish(self.loaded(content, &failed), &csv).or_else(|e| {
            // a chunk that failed is recomputed; any other failure is the run's
            let Some(i) = failed.get() else {
                return Err(e);
            };
            let (work, n) = (self.work, self.chunks);
            work.reject_if_still_bad(i, || work.read_chunk::<T>(i, n, |v| content(i, v)))
        })?;
        if failed.get().is_some() {
            return Ok(None);
        }
        if self.cancelled() {
            return Err(self.cancelled_error());
        }
        let Some(m) = self.commit(&csv, chunk_seconds + started.elapsed().as_secs_f64())? else {
            return Ok(Some(Outcome::Superseded {
                chunks_computed: computed,
            }));
        };
        Ok(Some(Outcome::Completed {
            chunks_computed: computed,
            seconds: m.compute_seconds,
            assembled_here: true,
            notes: Vec::new(),
        }))
    }

    /// Every chunk's value in index order, parsed and checked as the assembly takes them: a
    /// window of [`LOAD_AHEAD`] chunks side by side, so only a window is held in memory. The
    /// index of the first that fails goes to `failed`.
    fn loaded<'s, T: Payload + 's>(
        &'s self,
        content: &'s (impl Fn(usize, &T) -> Result<(), String> + Sync),
        failed: &'s Cell<Option<usize>>,
    ) -> Chunks<'s, T> {
        let (work, n) = (self.work, self.chunks);
        let load = move |i: usize| match work.read_chunk::<T>(i, n, |v| content(i, v)) {
            Ok(Some(d)) => Ok(d.value),
            Ok(None) => Err(anyhow::anyhow!(
                "{}: gone while assembling",
                work.chunk_path(i).display()
            )),
            Err(why) => Err(anyhow::anyhow!("{}: {why}", work.chunk_path(i).display())),
        };
        let chunks = in_windows(n, LOAD_AHEAD, move |i| (i, load(i)));
        Box::new(chunks.map(move |(i, value)| {
            value.inspect_err(|_| {
                if failed.get().is_none() {
                    failed.set(Some(i));
                }
            })
        }))
    }

    /// Moves the staged result into place with its manifest; `None` where it is superseded
    /// ([`Outcome::Superseded`]).
    fn commit(&self, staged_csv: &Path, seconds: f64) -> anyhow::Result<Option<Manifest>> {
        let entry = self.entry;
        let manifest = Manifest {
            format: MANIFEST_FORMAT,
            analysis: entry.name.clone(),
            kind: entry.settings.kind().into(),
            fingerprint: self.work.fingerprint.clone(),
            computed_from: self
                .session
                .fingerprint_input(entry, crate::analysis::NUMERICS_VERSION),
            numerics: crate::analysis::NUMERICS_VERSION,
            isola_version: crate::BUILD.into(),
            chunks_total: self.chunks,
            compute_seconds: seconds,
            assembled_by: lock::holder(),
            assembled_unix: unix_now(),
            files: Vec::new(),
        };
        // a run of the session file keeps a result of the file's settings now (edited during
        // the run, and computed since); a workbench's run is of the settings it shows
        let now = || {
            (self.as_on_disk)
                .then(|| on_disk(self.session, &entry.name))
                .flatten()
        };
        self.work
            .commit(&output_files(&entry.settings, staged_csv), manifest, &now)
    }
}

fn file_name(path: &Path) -> &std::ffi::OsStr {
    path.file_name().unwrap_or_default()
}

/// A chunk's value, `None` for a cancel, an error for anything else.
fn optional<T>(result: Result<T, AnalysisError>) -> anyhow::Result<Option<T>> {
    match result {
        Ok(v) => Ok(Some(v)),
        Err(AnalysisError::Cancelled) => Ok(None),
        Err(e) => Err(e.into()),
    }
}

/// An error naming the first non-finite number of `value`, which no result may hold.
fn finite<T: serde::Serialize>(value: &T, what: &str) -> anyhow::Result<()> {
    match first_non_finite(value) {
        Some(found) => anyhow::bail!("{what}: {found}; nothing written"),
        None => Ok(()),
    }
}

/// The analyses without chunks that depend on the model: computed at once and written to
/// `csv`; what the user should know about the result is returned.
trait Single {
    fn run_single(
        &self,
        settings: &Settings,
        columns: &export::ModelColumns,
        csv: &Path,
        progress: &Progress,
    ) -> anyhow::Result<Vec<String>>;
}

/// A written model's analyses that have no chunks.
impl Single for EquationSystem {
    fn run_single(
        &self,
        settings: &Settings,
        columns: &export::ModelColumns,
        csv: &Path,
        progress: &Progress,
    ) -> anyhow::Result<Vec<String>> {
        let sys = self;
        match settings {
            Settings::TimeHistory(spec) => {
                let h = state_history(sys, spec, progress.cancel_flag())?;
                finite(&h, "the time history")?;
                let bytes = export::state_history_bytes(&h, sys.model().grid())?;
                super::output::write_output(csv, &bytes, &super::output::Protected::none())?;
                Ok(h.collision.iter().map(|c| c.describe()).collect())
            }
            Settings::SteppedSweep(spec) => {
                let start = sys.grid_start([spec.dx0, spec.v0]);
                let omegas = spec.omega.values();
                let swept = stepped_sweep(
                    sys,
                    &omegas,
                    start,
                    &spec.steady,
                    progress.cancel_flag(),
                    |_| {},
                )?;
                finite(&swept, "the stepped sweep")?;
                let found = SweepFindings::of(&swept, spec.jump_ratio);
                export::stepped_csv(&swept, &found, columns, csv)?;
                Ok(Vec::new())
            }
            Settings::ChirpSweep(spec) => {
                let s = written_chirp_sweep(sys, spec, progress.cancel_flag(), share_of(progress))?;
                chirp_outputs(&s, spec, columns, csv)
            }
            other => anyhow::bail!("a written model cannot run a {} yet", other.kind()),
        }
    }
}

/// A sweep's progress, told as the share of its span done, as `progress`'s: a thousand steps
/// (so the workbench's gauge moves through a long sweep).
fn share_of(progress: &Progress) -> impl FnMut(f64) + '_ {
    const STEPS: usize = 1000;
    progress.grow_total(STEPS);
    let mut done = 0;
    move |share| {
        let now = (share.clamp(0.0, 1.0) * STEPS as f64) as usize;
        if now > done {
            progress.add(now - done);
            done = now;
        }
    }
}

/// A chirp sweep's tables, and its scalogram's where `spec` asks for it.
fn chirp_outputs(
    s: &ChirpSweep,
    spec: &ChirpSpec,
    columns: &export::ModelColumns,
    csv: &Path,
) -> anyhow::Result<Vec<String>> {
    finite(s, "the chirp sweep")?;
    export::chirp_csv(s, columns, csv)?;
    if let Some(spec) = &spec.scalogram {
        let sc = scalogram(&s.lambda, s.dt, spec)?;
        finite(&sc, "the scalogram")?;
        export::scalogram_csv(&sc, s, columns, &export::beside(csv, "scalogram"))?;
    }
    Ok(Vec::new())
}

/// The built-in model's analyses that have no chunks.
impl Single for Params {
    fn run_single(
        &self,
        settings: &Settings,
        columns: &export::ModelColumns,
        csv: &Path,
        progress: &Progress,
    ) -> anyhow::Result<Vec<String>> {
        let params = self;
        let device = columns.device.unwrap_or_default();
        match settings {
            Settings::ForceCurve(spec) => {
                let curves = force_curves(spec)?;
                finite(&curves, "the force curves")?;
                export::force_csv(&curves, csv).map(|()| Vec::new())
            }
            Settings::TimeHistory(spec) => {
                let h = time_history(params, spec)?;
                finite(&h, "the time history")?;
                export::history_csv(&h, &device, csv).map(|()| Vec::new())
            }
            Settings::ChirpSweep(spec) => {
                let s = chirp_sweep(params, spec, progress.cancel_flag(), share_of(progress))?;
                chirp_outputs(&s, spec, columns, csv)
            }
            Settings::SteppedSweep(spec) => {
                let start = params.grid_start([spec.dx0, spec.v0]);
                let steps = stepped_sweep(
                    params,
                    &spec.omega.values(),
                    start,
                    &spec.steady,
                    progress.cancel_flag(),
                    |_| {},
                )?;
                finite(&steps, "the stepped sweep")?;
                let found = SweepFindings::of(&steps, spec.jump_ratio);
                export::stepped_csv(&steps, &found, columns, csv).map(|_| Vec::new())
            }
            Settings::Continuation(_)
            | Settings::Basin(_)
            | Settings::FrequencyResponse(_)
            | Settings::Family(_)
            | Settings::Map(_)
            | Settings::Hunt(_) => {
                unreachable!("chunked kinds and continuations are run by run_on")
            }
        }
    }
}
