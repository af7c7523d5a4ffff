//! Output files and folders: checked before any work, never an input overwritten.

use std::path::Path;

use anyhow::{bail, Context, Result};

/// Creates the pairs folder, refusing a path that exists and is not a folder.
pub fn prepare_dir(dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!("{}: exists and is not a folder", dir.display());
    }
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create", dir.display()))
}

/// Fails if `output` names the same file as one of `inputs`.
pub fn refuse_overwrite(output: &Path, inputs: &[&Path]) -> Result<()> {
    let canon = |p: &Path| std::fs::canonicalize(p).ok();
    if let Some(out) = canon(output) {
        for input in inputs {
            if canon(input).as_ref() == Some(&out) {
                bail!(
                    "{}: refusing to overwrite an input file with output",
                    output.display()
                );
            }
        }
    }
    Ok(())
}

/// Fails now, before any work, if `out` cannot be written: its folder is missing, it is a
/// folder, or the file cannot be opened for writing (a probe that leaves an existing file as it
/// is, and removes the empty one it made).
pub fn writable(out: &Path) -> Result<()> {
    let folder = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !folder.is_dir() {
        bail!(
            "{}: cannot write: the folder {} does not exist",
            out.display(),
            folder.display()
        );
    }
    if out.is_dir() {
        bail!("{}: cannot write: it is a folder", out.display());
    }
    let existed = out.exists();
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(out)
        .with_context(|| format!("{}: cannot write", out.display()))?;
    if !existed {
        // The probe's empty file: the picture replaces it once drawn.
        let _ = std::fs::remove_file(out);
    }
    Ok(())
}

/// Whether two paths name the same file (the same text, or the same file once resolved).
pub fn same_file(a: &Path, b: &Path) -> bool {
    if a == b {
        return true;
    }
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
