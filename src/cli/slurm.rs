//! `isola slurm`: a session's analyses as a Slurm job array whose tasks share the work chunk
//! by chunk (each claims what nobody has; slow and fast nodes balance), and a job that starts
//! when the array has ended, computes whatever is left (a task that died), assembles and
//! verifies. A task that fails is requeued, twice at most; a pre-empted one is requeued by
//! Slurm. No finished chunk is ever lost: chunks are saved whole as they finish.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use clap::Args;
use isola::session::Session;
use isola::session::budget::{self, Budget};
use serde::Serialize;

use super::output::{Done, Output, Summary};

#[derive(Debug, Args)]
pub struct SlurmArgs {
    /// The session file (on a folder every node sees).
    session: PathBuf,
    /// Only this analysis.
    #[arg(long)]
    only: Option<String>,
    /// Tasks of the array.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=10000))]
    tasks: u32,
    /// CPUs per task (each task runs that many worker threads).
    #[arg(long = "cpus-per-task", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
    cpus_per_task: u32,
    /// Time limit of each task, as Slurm writes it (`30`, `2:00:00`, `1-00:00:00`).
    #[arg(long)]
    time: Option<String>,
    /// Partition to run in.
    #[arg(long)]
    partition: Option<String>,
    /// Another `#SBATCH` option for both jobs, e.g. `--sbatch-arg=--account=proj42`.
    #[arg(long = "sbatch-arg", allow_hyphen_values = true)]
    sbatch_args: Vec<String>,
    /// Submit the two jobs with `sbatch` and print their ids.
    #[arg(long)]
    submit: bool,
    /// The isola the tasks run (default: this one).
    #[arg(long)]
    isola: Option<PathBuf>,
}

/// A value put in a shell script between single quotes.
fn quoted(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

/// A path as a word to paste into a shell: as it is if it is plain, quoted otherwise.
fn shell_word(path: &Path) -> String {
    let text = path.to_string_lossy();
    let plain = |c: char| c.is_ascii_alphanumeric() || "/._-+,:@=".contains(c);
    if !text.is_empty() && text.chars().all(plain) {
        text.into_owned()
    } else {
        quoted(&text)
    }
}

/// A Slurm option value must not break the `#SBATCH` line it is on.
fn sbatch_value(what: &str, value: &str) -> anyhow::Result<String> {
    if value.is_empty() || value.chars().any(|c| c.is_whitespace() || c == '#') {
        anyhow::bail!("{what} '{value}': no spaces or '#' in a Slurm option");
    }
    Ok(value.to_string())
}

/// A folder as an `#SBATCH` line takes it between double quotes: refused if it holds what
/// such a line cannot carry (`"`, `\\`, a line break) or what Slurm would expand (`%`).
fn sbatch_path(path: &Path) -> anyhow::Result<String> {
    let text = path.to_string_lossy();
    match text
        .chars()
        .find(|c| matches!(c, '"' | '\\' | '%' | '\n' | '\r'))
    {
        Some(c) => anyhow::bail!(
            "{text}: Slurm cannot write its output in a folder whose path holds {c:?}; \
             move the session"
        ),
        None => Ok(text.into_owned()),
    }
}

/// The `#SBATCH` lines both jobs share.
fn common_options(args: &SlurmArgs) -> anyhow::Result<String> {
    let mut lines = format!("#SBATCH --cpus-per-task={}\n", args.cpus_per_task);
    if let Some(t) = &args.time {
        lines.push_str(&format!("#SBATCH --time={}\n", sbatch_value("--time", t)?));
    }
    if let Some(p) = &args.partition {
        lines.push_str(&format!(
            "#SBATCH --partition={}\n",
            sbatch_value("--partition", p)?
        ));
    }
    for a in &args.sbatch_args {
        let a = sbatch_value("--sbatch-arg", a)?;
        if !a.starts_with('-') {
            anyhow::bail!("--sbatch-arg '{a}': an sbatch option starts with '-'");
        }
        lines.push_str(&format!("#SBATCH {a}\n"));
    }
    Ok(lines)
}

/// The `#SBATCH` lines of a job called `job` writing its output to `out/output`: requeued by
/// Slurm when pre-empted, its output appended across restarts, then the shared options.
fn sbatch_header(job: &str, out: &Path, output: &str, args: &SlurmArgs) -> anyhow::Result<String> {
    Ok(format!(
        "#SBATCH --job-name={job}\n#SBATCH --output=\"{out}/{output}\"\n\
         #SBATCH --open-mode=append\n#SBATCH --requeue\n{common}",
        out = sbatch_path(out)?,
        common = common_options(args)?,
    ))
}

/// The job-array script: each task is a worker (`isola run --worker`).
fn work_script(
    name: &str,
    out: &Path,
    isola: &str,
    run: &str,
    args: &SlurmArgs,
) -> anyhow::Result<String> {
    Ok(format!(
        "#!/bin/bash
# The work of {name}: one task of a job array, written by `isola slurm`. Each task computes the
# chunks no other task has claimed; chunks are saved whole as they finish, so a task killed,
# pre-empted or requeued loses none.
#SBATCH --array=0-{last}
{header}
echo \"task ${{SLURM_ARRAY_TASK_ID:-?}} of job ${{SLURM_ARRAY_JOB_ID:-?}} on $(hostname), start ${{SLURM_RESTART_COUNT:-0}}, $(date -u +%FT%TZ)\"
{isola} run {run} --threads \"${{SLURM_CPUS_PER_TASK:-1}}\" --worker --force
status=$?
# a task that failed (rather than one cancelled or killed by Slurm) is tried again, twice at most
if [ \"$status\" -ne 0 ] && [ \"${{SLURM_RESTART_COUNT:-0}}\" -lt 2 ]; then
  echo \"isola exited with $status: requeueing this task\"
  scontrol requeue \"${{SLURM_ARRAY_JOB_ID}}_${{SLURM_ARRAY_TASK_ID}}\"
fi
exit \"$status\"
",
        last = args.tasks - 1,
        header = sbatch_header(&format!("isola-{name}"), out, "work-%A_%a.out", args)?,
    ))
}

/// The job that runs after the array: computes what is left, assembles, verifies.
fn assemble_script(
    name: &str,
    out: &Path,
    isola: &str,
    run: &str,
    args: &SlurmArgs,
) -> anyhow::Result<String> {
    Ok(format!(
        "#!/bin/bash
# Assembles and verifies {name} once its job array has ended (written by `isola slurm`): chunks a
# task left undone are computed here, the result is written and checked against its manifest.
{header}
set -e
{isola} run {run} --threads \"${{SLURM_CPUS_PER_TASK:-1}}\" --force
{isola} status {run} --verify
",
        header = sbatch_header(
            &format!("isola-{name}-assemble"),
            out,
            "assemble-%j.out",
            args
        )?,
    ))
}

pub fn run(args: &SlurmArgs, output: Output) -> anyhow::Result<()> {
    let started = Instant::now();
    let session = Session::load(&args.session)?;
    let entries = super::run::selected(&session, args.only.as_deref())?;
    // the time budget of the whole array (each task then runs with --force); memory and disk
    // are checked again by every task on its own node
    let threads = (args.tasks * args.cpus_per_task) as usize;
    budget::check_all(
        &session,
        entries.iter().copied(),
        &Budget::on_this_machine(threads, None, false),
    )?;
    let session_path = args
        .session
        .canonicalize()
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.session.display()))?;
    let isola = match &args.isola {
        Some(p) => p.clone(),
        None => std::env::current_exe()?,
    };
    let isola = isola
        .canonicalize()
        .map_err(|e| anyhow::anyhow!("{}: {e}", isola.display()))?;
    let name = session_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let out = isola::session::schema::results_dir_of(&session_path).join("slurm");
    std::fs::create_dir_all(&out).map_err(|e| anyhow::anyhow!("{}: {e}", out.display()))?;
    let mut run_args = quoted(&session_path.to_string_lossy());
    if let Some(only) = &args.only {
        run_args.push_str(&format!(" --only {}", quoted(only)));
    }
    let isola = quoted(&isola.to_string_lossy());
    let scripts = [
        (
            "work.sh",
            work_script(&name, &out, &isola, &run_args, args)?,
        ),
        (
            "assemble.sh",
            assemble_script(&name, &out, &isola, &run_args, args)?,
        ),
    ];
    let mut done = Done::default();
    for (file, text) in &scripts {
        let path = out.join(file);
        isola::session::atomic::write_atomic(&path, text.as_bytes())
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        done.wrote.push(path);
    }
    let (work, assemble) = (out.join("work.sh"), out.join("assemble.sh"));
    let submitted = if args.submit {
        let array = sbatch(&[work.as_os_str()])?;
        let dependency = format!("--dependency=afterany:{array}");
        let after = sbatch(&[std::ffi::OsStr::new(&dependency), assemble.as_os_str()])?;
        Some(Submitted {
            array_job: array,
            assembly_job: after,
        })
    } else {
        None
    };
    done.elapsed_seconds = started.elapsed().as_secs_f64();
    output.report(&SlurmSummary {
        session: session_path,
        tasks: args.tasks,
        cpus_per_task: args.cpus_per_task,
        work_script: work,
        assemble_script: assemble,
        submitted,
        done,
    })
}

/// The scripts written and, with --submit, the jobs submitted.
#[derive(Serialize)]
struct SlurmSummary {
    session: PathBuf,
    tasks: u32,
    cpus_per_task: u32,
    work_script: PathBuf,
    assemble_script: PathBuf,
    submitted: Option<Submitted>,
    #[serde(flatten)]
    done: Done,
}

/// The ids Slurm gave the job array and the assembly job.
#[derive(Serialize)]
struct Submitted {
    array_job: String,
    assembly_job: String,
}

impl Summary for SlurmSummary {
    fn print_text(&self) {
        self.done.print_wrote();
        match &self.submitted {
            None => say!(
                "submit with:\n  jobid=$(sbatch --parsable {})\n  sbatch --dependency=afterany:$jobid {}\nwatch with:\n  isola status {}",
                shell_word(&self.work_script),
                shell_word(&self.assemble_script),
                shell_word(&self.session)
            ),
            Some(jobs) => {
                say!(
                    "submitted job array {} ({} tasks) and assembly job {}",
                    jobs.array_job,
                    self.tasks,
                    jobs.assembly_job
                );
                say!("watch with: isola status {}", shell_word(&self.session));
            }
        }
    }
}

/// Runs `sbatch --parsable ARGS` and returns the job id it prints.
fn sbatch(args: &[&std::ffi::OsStr]) -> anyhow::Result<String> {
    let out = Command::new("sbatch")
        .arg("--parsable")
        .args(args)
        .output()
        .map_err(|e| anyhow::anyhow!("sbatch: {e} (is Slurm installed here?)"))?;
    if !out.status.success() {
        anyhow::bail!(
            "sbatch failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    // `jobid` or `jobid;cluster`
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        anyhow::bail!("sbatch printed no job id: {text}");
    }
    Ok(id)
}
