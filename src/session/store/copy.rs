//! A complete result copied under another name or into another session's results folder (a
//! duplicated or renamed analysis, a session saved as another file): a result of its own,
//! checksummed again and committed like a computed one.

use std::path::PathBuf;

use super::manifest::{StoredFile, Unverified};
use super::{ResultPaths, Work, io_at};

/// Copies the complete, verified result at `from` to `to`: files copied into staging under `from`'s read lock, checked against `from`'s manifest, then committed at
/// `to`. `Ok(false)` if `from` holds no complete result; a damaged one is not copied.
pub fn copy_result(from: &ResultPaths, to: &ResultPaths) -> anyhow::Result<bool> {
    if from.dir == to.dir && from.name == to.name {
        anyhow::bail!(
            "{}: a result cannot be copied onto itself",
            from.csv.display()
        );
    }
    let staged = super::with_verified(from, |m| -> anyhow::Result<_> {
        let work = Work::join(to, &m.fingerprint)?;
        let Some(_assembling) = work.assembler(&|| false)? else {
            anyhow::bail!("{}: not free to write", work.dir.display());
        };
        let staging = work.staging()?;
        let mut files: Vec<PathBuf> = Vec::new();
        for record in &m.files {
            let source = from.dir.join(&record.name);
            let target = staging.join(renamed(&record.name, &from.name, &to.name));
            // copied, not linked: damage to one file is never damage to both results
            std::fs::copy(&source, &target).map_err(io_at(&target))?;
            let copied = StoredFile::of(&target).map_err(io_at(&target))?;
            if (copied.bytes, &copied.sha256) != (record.bytes, &record.sha256) {
                anyhow::bail!("{}: changed while being copied", source.display());
            }
            files.push(target);
        }
        let mut manifest = m.clone();
        manifest.analysis = to.name.clone();
        Ok((work, files, manifest))
    });
    let (work, files, manifest) = match staged {
        Ok(staged) => staged?,
        Err(Unverified::Missing) => return Ok(false),
        Err(why) => anyhow::bail!("{}: not copied: {why}", from.csv.display()),
    };
    work.commit(&files, manifest, &|| None)?;
    work.retire();
    Ok(true)
}

/// What [`carry`] copied: the complete result (as [`copy_result`] says) and how many kept
/// results of earlier settings.
#[derive(Debug)]
pub struct Carried {
    pub result: anyhow::Result<bool>,
    pub kept: usize,
}

/// The result at `from` and the results kept for its earlier settings
/// ([`super::earlier::copy_kept`]) copied as `to`'s: a copied or renamed analysis, a session
/// saved as another file. Kept results that cannot be copied are logged, not an error.
pub fn carry(from: &ResultPaths, to: &ResultPaths) -> Carried {
    let kept = super::earlier::copy_kept(from, to).unwrap_or_else(|e| {
        tracing::warn!(error = %format!("{e:#}"), "kept results not copied");
        0
    });
    Carried {
        result: copy_result(from, to),
        kept,
    }
}

/// `A.attractors.csv` of analysis `A` as a file of analysis `B`: `B.attractors.csv`.
pub fn renamed(file: &str, from: &str, to: &str) -> String {
    match file.strip_prefix(from).filter(|rest| rest.starts_with('.')) {
        Some(rest) => format!("{to}{rest}"),
        None => file.to_string(),
    }
}
