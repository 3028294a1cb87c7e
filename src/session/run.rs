//! Running a session's analyses headless, with results checkpointed chunk by chunk beside the
//! session so that a killed run resumes where it stopped and produces the same files.
//!
//! Layout, for analysis `A` of `sessions/NAME.toml`:
//! - `sessions/NAME.results/A.csv`: the result (see README for the columns); a hunt's
//!   continued branches go beside it in `A.branches.csv`;
//! - `sessions/NAME.results/A.manifest.json`: fingerprint, version, chunks, timing, completion;
//! - `sessions/NAME.results/A.chunks/000012.json`: finished chunks while the run is under way.
//!
//! Chunks are addressed by index, so a run can be split across machines (`shard`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::atomic::write_atomic;
use super::export;
use super::schema::{AnalysisEntry, Session, Settings};
use crate::analysis::basin::BasinPlan;
use crate::analysis::branch_from_state::branch_from_state;
use crate::analysis::chirp_sweep::chirp_sweep;
use crate::analysis::family::{FamilyMember, family_member};
use crate::analysis::force_curve::force_curves;
use crate::analysis::frequency_response::{Response, ResponsePlan};
use crate::analysis::hunt::{HuntSpec, hunt_in};
use crate::analysis::map::{MapRow, map_curves, map_row};
use crate::analysis::stepped_sweep::stepped_sweep;
use crate::analysis::time_history::time_history;
use crate::analysis::{AnalysisError, Progress};

/// The small record kept beside each result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub analysis: String,
    pub kind: String,
    /// Fingerprint of the model and settings the result belongs to.
    pub fingerprint: String,
    pub isola_version: String,
    pub chunks_total: usize,
    pub chunks_done: usize,
    pub complete: bool,
    /// Seconds spent computing, summed over runs.
    pub compute_seconds: f64,
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
    /// Its result was already complete and current.
    UpToDate,
    /// Computed (or finished) now.
    Completed {
        chunks_computed: usize,
        seconds: f64,
    },
    /// This shard's chunks are done; others are still missing.
    ShardDone {
        chunks_computed: usize,
        missing: usize,
    },
}

/// Where analysis `name`'s files live.
pub struct ResultPaths {
    pub csv: PathBuf,
    pub manifest: PathBuf,
    pub chunks: PathBuf,
}

impl ResultPaths {
    pub fn new(session: &Session, name: &str) -> Self {
        let dir = session.results_dir();
        ResultPaths {
            csv: dir.join(format!("{name}.csv")),
            manifest: dir.join(format!("{name}.manifest.json")),
            chunks: dir.join(format!("{name}.chunks")),
        }
    }

    fn chunk(&self, i: usize) -> PathBuf {
        self.chunks.join(format!("{i:06}.json"))
    }
}

/// Reads an analysis' manifest, if any.
pub fn read_manifest(path: &Path) -> Option<Manifest> {
    serde_json::from_slice(&std::fs::read(path).ok()?).ok()
}

/// True when `entry`'s result is complete and belongs to its current model and settings.
pub fn is_current(session: &Session, entry: &AnalysisEntry) -> bool {
    let paths = ResultPaths::new(session, &entry.name);
    read_manifest(&paths.manifest).is_some_and(|m| {
        m.complete && m.fingerprint == session.fingerprint(entry) && paths.csv.exists()
    })
}

/// Runs one analysis of `session`, resuming from any chunks a previous run left.
pub fn run_analysis(
    session: &Session,
    entry: &AnalysisEntry,
    shard: Shard,
    progress: &Progress,
) -> anyhow::Result<Outcome> {
    let paths = ResultPaths::new(session, &entry.name);
    let fingerprint = session.fingerprint(entry);
    std::fs::create_dir_all(&paths.chunks)?;
    let previous = read_manifest(&paths.manifest);
    if let Some(m) = &previous {
        if m.fingerprint == fingerprint && m.complete && paths.csv.exists() {
            tracing::info!(analysis = %entry.name, "up to date");
            return Ok(Outcome::UpToDate);
        }
        if m.fingerprint != fingerprint {
            tracing::warn!(analysis = %entry.name, old = %m.fingerprint, new = %fingerprint, "stale result discarded");
            // stale: another model or settings; never mix its chunks in
            std::fs::remove_dir_all(&paths.chunks)?;
            std::fs::create_dir_all(&paths.chunks)?;
            let _ = std::fs::remove_file(&paths.csv);
        }
    }
    let spent = previous
        .as_ref()
        .filter(|m| m.fingerprint == fingerprint)
        .map_or(0.0, |m| m.compute_seconds);
    let started = Instant::now();
    let params = session.params(Some(entry))?;
    let device = session.device();
    let mut manifest = Manifest {
        analysis: entry.name.clone(),
        kind: entry.settings.kind().into(),
        fingerprint,
        isola_version: env!("CARGO_PKG_VERSION").into(),
        chunks_total: 1,
        chunks_done: 0,
        complete: false,
        compute_seconds: spent,
    };
    let save_manifest = |m: &Manifest| -> anyhow::Result<()> {
        write_atomic(&paths.manifest, serde_json::to_string_pretty(m)?.as_bytes())?;
        Ok(())
    };
    let cancelled = |e: AnalysisError| anyhow::anyhow!("{}: {e}", entry.name);
    // chunked kinds: compute the missing chunks this shard owns, then assemble if all exist
    let (computed, missing) = match &entry.settings {
        Settings::Basin(spec) => {
            let plan = BasinPlan::new(&params, spec, progress).map_err(cancelled)?;
            let n = plan.chunks();
            manifest.chunks_total = n;
            save_manifest(&manifest)?;
            progress.grow_total(plan.cells());
            let done = |i: usize| progress.add(plan.chunk_cells(i).len());
            run_chunks(
                &paths,
                n,
                shard,
                done,
                |i| plan.chunk(i, progress),
                |chunks| export::basin_csv(&plan.assemble(chunks), &params, &paths.csv),
            )?
        }
        Settings::FrequencyResponse(spec) | Settings::Hunt(HuntSpec { response: spec, .. }) => {
            let plan = ResponsePlan::new(&params, spec).map_err(cancelled)?;
            let n = plan.chunks();
            manifest.chunks_total = n;
            save_manifest(&manifest)?;
            progress.grow_total(plan.work());
            let per_chunk = spec.dx.points * spec.v.points;
            run_chunks(
                &paths,
                n,
                shard,
                |_| progress.add(per_chunk),
                |i| plan.grid_at(i, progress),
                |per_omega: Vec<Vec<Response>>| {
                    let fr = plan.finish(per_omega, progress).map_err(cancelled)?;
                    if let Settings::Hunt(hunt) = &entry.settings {
                        let found = hunt_in(&params, fr, &hunt.continuation, progress)
                            .map_err(cancelled)?;
                        let branches: Vec<_> = found.branches.iter().map(|h| &h.branch).collect();
                        export::continued_csv(&branches, &export::branches_path(&paths.csv))?;
                        export::response_csv(&found.response, &paths.csv)
                    } else {
                        export::response_csv(&fr, &paths.csv)
                    }
                },
            )?
        }
        Settings::Map(spec) => {
            let n = spec.values.points;
            manifest.chunks_total = n;
            save_manifest(&manifest)?;
            spec.validate(&params)?;
            // each row announces its own work as it starts; rows run side by side
            run_chunks(
                &paths,
                n,
                shard,
                |_| {},
                |i| map_row(&params, spec, i, progress).ok(),
                |rows: Vec<MapRow>| {
                    let curves = if spec.curves {
                        map_curves(&params, spec, &rows, progress).map_err(cancelled)?
                    } else {
                        Vec::new()
                    };
                    export::curves_csv(&curves, &export::curves_path(&paths.csv))?;
                    let omegas = spec.response.omega.values();
                    let names = (spec.x.name(), spec.parameter.name());
                    export::map_csv(names, &omegas, &rows, &paths.csv)
                },
            )?
        }
        Settings::Family(spec) => {
            let n = spec.values.len();
            manifest.chunks_total = n;
            save_manifest(&manifest)?;
            spec.validate(&params)?;
            // each member announces its own work as it starts; members run side by side
            run_chunks(
                &paths,
                n,
                shard,
                |_| {},
                |i| family_member(&params, spec, i, progress).ok(),
                |members: Vec<FamilyMember>| {
                    export::family_csv(spec.parameter.name(), &members, &paths.csv)?;
                    export::family_responses_csv(
                        spec.parameter.name(),
                        &members,
                        &export::family_responses_path(&paths.csv),
                    )
                },
            )?
        }
        single => {
            save_manifest(&manifest)?;
            progress.grow_total(1);
            if shard.owns(0) {
                run_single(single, &params, &device, &paths.csv, progress)?;
            }
            progress.add(1);
            (1, usize::from(!paths.csv.exists()))
        }
    };
    manifest.compute_seconds = spent + started.elapsed().as_secs_f64();
    manifest.chunks_done = manifest.chunks_total - missing;
    if progress.is_cancelled() {
        save_manifest(&manifest)?;
        anyhow::bail!("{}: cancelled", entry.name);
    }
    if missing > 0 {
        save_manifest(&manifest)?;
        tracing::info!(analysis = %entry.name, computed_now = computed, missing, "shard done");
        return Ok(Outcome::ShardDone {
            chunks_computed: computed,
            missing,
        });
    }
    manifest.complete = true;
    save_manifest(&manifest)?;
    tracing::info!(
        analysis = %entry.name,
        chunks = manifest.chunks_total,
        computed_now = computed,
        seconds = manifest.compute_seconds,
        "complete"
    );
    let _ = std::fs::remove_dir_all(&paths.chunks);
    Ok(Outcome::Completed {
        chunks_computed: computed,
        seconds: manifest.compute_seconds,
    })
}

/// The analyses that have no chunks: computed at once and written.
fn run_single(
    settings: &Settings,
    params: &crate::model::Params,
    device: &crate::model::Device,
    csv: &Path,
    progress: &Progress,
) -> anyhow::Result<()> {
    match settings {
        Settings::ForceCurve(spec) => export::force_csv(&force_curves(spec)?, csv),
        Settings::TimeHistory(spec) => {
            export::history_csv(&time_history(params, spec)?, device, csv)
        }
        Settings::ChirpSweep(spec) => {
            let s = chirp_sweep(params, spec, progress.cancel_flag(), |_| {})?;
            export::chirp_csv(&s, device, csv)
        }
        Settings::SteppedSweep(spec) => {
            let start = [params.lambda_p() + spec.dx0, spec.v0];
            let steps = stepped_sweep(
                params,
                &spec.omega.values(),
                start,
                &spec.steady,
                progress.cancel_flag(),
                |_| {},
            )?;
            export::stepped_csv(&steps, device, csv)
        }
        Settings::Continuation(spec) => {
            let branch = branch_from_state(params, spec, progress)?;
            export::continued_csv(&[&branch], csv)
        }
        Settings::Basin(_)
        | Settings::FrequencyResponse(_)
        | Settings::Family(_)
        | Settings::Map(_)
        | Settings::Hunt(_) => {
            unreachable!("chunked kinds are run chunk by chunk")
        }
    }
}

/// Computes the chunks this shard owns, then, if every chunk exists, `finish`es with all of
/// them in index order. Returns (chunks computed now, chunks still missing).
fn run_chunks<T: Serialize + serde::de::DeserializeOwned + Send>(
    paths: &ResultPaths,
    n: usize,
    shard: Shard,
    on_existing: impl Fn(usize) + Sync,
    compute: impl Fn(usize) -> Option<T> + Sync,
    finish: impl FnOnce(Vec<T>) -> anyhow::Result<()>,
) -> anyhow::Result<(usize, usize)> {
    let computed = compute_chunks(paths, n, shard, on_existing, compute)?;
    match load_chunks(paths, n) {
        Some(chunks) => {
            finish(chunks)?;
            Ok((computed, 0))
        }
        None => Ok((computed, missing_count(paths, n))),
    }
}

/// Computes, in parallel, the chunks this shard owns that have no file yet; each is saved as
/// soon as it is done. Returns how many were computed.
fn compute_chunks<T: Serialize + Send>(
    paths: &ResultPaths,
    n: usize,
    shard: Shard,
    on_existing: impl Fn(usize) + Sync,
    compute: impl Fn(usize) -> Option<T> + Sync,
) -> anyhow::Result<usize> {
    let todo: Vec<usize> = (0..n).filter(|&i| shard.owns(i)).collect();
    let results: Vec<anyhow::Result<bool>> = todo
        .par_iter()
        .map(|&i| {
            if paths.chunk(i).exists() {
                on_existing(i);
                return Ok(false);
            }
            match compute(i) {
                Some(value) => {
                    write_atomic(&paths.chunk(i), &serde_json::to_vec(&value)?)?;
                    tracing::debug!(chunk = i, "chunk saved");
                    Ok(true)
                }
                None => Ok(false),
            }
        })
        .collect();
    let mut computed = 0;
    for r in results {
        computed += usize::from(r?);
    }
    Ok(computed)
}

/// Every chunk in index order, if all are there.
fn load_chunks<T: serde::de::DeserializeOwned>(paths: &ResultPaths, n: usize) -> Option<Vec<T>> {
    (0..n)
        .map(|i| serde_json::from_slice(&std::fs::read(paths.chunk(i)).ok()?).ok())
        .collect()
}

fn missing_count(paths: &ResultPaths, n: usize) -> usize {
    (0..n).filter(|&i| !paths.chunk(i).exists()).count()
}
