//! What rank 0 checks about the files of a run before anything is computed or written: the
//! output is a file name (not a directory), none of the files named after it is one of the
//! run's inputs (the case file, a particle file, the checkpoint restarted from), no other run
//! is writing it (the lock of `output::lock`, taken here and held for the whole run), and it
//! may be written: a fresh run does not replace an existing output (or an interrupted run's
//! `NAME.partial`) without `--overwrite`; a restart continues an output that exists unless
//! `--new-output` is given.

use super::{spacetime_path, RunOptions};
use crate::case::LoadedCase;
use crate::output::checkpoint::{checkpoint_path, tmp_path};
use crate::output::lock::{lock_path, LockError, OutputLock};
use crate::output::partial_path;
use crate::output::xdmf::xdmf_path;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

/// Check the run's paths and take the output's lock (rank 0, before anything else).
pub fn prepare(lc: &LoadedCase, opts: &RunOptions) -> Result<OutputLock, String> {
    let out = &opts.output;
    let trailing_slash = out.as_os_str().to_string_lossy().ends_with('/');
    if out.is_dir() || trailing_slash {
        return Err(format!(
            "output {} is a directory; -o takes a file name, such as {}",
            out.display(),
            out.join("run.h5").display()
        ));
    }
    check_aliases(lc, opts)?;
    let lock = OutputLock::acquire(out).map_err(|e| match e {
        LockError::Held(pid) => format!(
            "output {} is being written by another run ({}); wait for it to end or choose another -o",
            out.display(),
            pid.map_or_else(|| "its lock is held".to_string(), |p| format!("pid {p}"))
        ),
        LockError::Io(e) => format!(
            "cannot open output file {}: its lock file {} cannot be created or locked: {e}",
            out.display(),
            lock_path(out).display()
        ),
    })?;
    let partial = partial_path(out);
    if opts.restart.is_none() {
        if out.exists() && !opts.overwrite {
            return Err(format!(
                "output file {} exists; pass --overwrite to replace it or -o to choose another",
                out.display()
            ));
        }
        if partial.exists() && !opts.overwrite {
            return Err(format!(
                "{} exists: the output of an interrupted run; continue it with --restart {}, or pass --overwrite to start again",
                partial.display(),
                checkpoint_path(out).display()
            ));
        }
    }
    Ok(lock)
}

/// A restart continues the output of the run that wrote its checkpoint: refuse one whose
/// output is missing (unless `--new-output`), and `--new-output` onto an existing file.
pub fn check_restart_output(opts: &RunOptions, ck: &Path) -> Result<(), String> {
    let out = &opts.output;
    let partial = partial_path(out);
    let missing = !out.exists() && !partial.exists();
    if missing && !opts.new_output {
        return Err(format!(
            "restart: the output {} (or {}) does not exist; the checkpoint {} continues that file, so give -o the output of the run that wrote it, or pass --new-output to start a new file holding only the continuation",
            out.display(),
            partial.display(),
            ck.display()
        ));
    }
    if !missing && opts.new_output {
        return Err(format!(
            "--new-output: output {} already exists; choose another -o for the new file, or leave out --new-output to continue it",
            if partial.exists() { &partial } else { out }.display()
        ));
    }
    Ok(())
}

/// Every file the run writes, with what it is.
fn outputs(out: &Path) -> Vec<(&'static str, PathBuf)> {
    let ck = checkpoint_path(out);
    let xmf = xdmf_path(out);
    vec![
        ("output", out.to_path_buf()),
        ("partial output", partial_path(out)),
        ("checkpoint", ck.clone()),
        ("temporary checkpoint", tmp_path(&ck)),
        ("space-time picture", spacetime_path(out)),
        ("XDMF file", xmf.clone()),
        ("temporary XDMF file", tmp_path(&xmf)),
        ("lock file", lock_path(out)),
        ("log", super::run_log::log_path(out)),
    ]
}

fn check_aliases(lc: &LoadedCase, opts: &RunOptions) -> Result<(), String> {
    let mut inputs: Vec<(&str, PathBuf)> = vec![("case file", PathBuf::from(&lc.path))];
    if let Some(f) = &lc.case.init.file {
        inputs.push(("particle file (init.file)", PathBuf::from(f)));
    }
    if let Some(ck) = &opts.restart {
        inputs.push(("checkpoint restarted from (--restart)", ck.clone()));
    }
    let own_checkpoint = checkpoint_path(&opts.output);
    for (what_in, input) in &inputs {
        for (what_out, output) in outputs(&opts.output) {
            // a restart reads its own checkpoint whole before writing the next one over it
            let reads_own = what_in.starts_with("checkpoint") && output == own_checkpoint;
            if !reads_own && same_file(input, &output) {
                return Err(format!(
                    "the {what_out} {} would be the {what_in} {}; choose another -o",
                    output.display(),
                    input.display()
                ));
            }
        }
    }
    Ok(())
}

/// Whether `a` and `b` name the same file: the same device and inode when both exist, else
/// the same path once the directory is made absolute and its links resolved.
pub fn same_file(a: &Path, b: &Path) -> bool {
    if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
        return x.dev() == y.dev() && x.ino() == y.ino();
    }
    match (canonical(a), canonical(b)) {
        (Some(x), Some(y)) => x == y,
        _ => a == b,
    }
}

/// `path` with its directory canonicalized (the file itself need not exist).
fn canonical(path: &Path) -> Option<PathBuf> {
    if let Ok(p) = path.canonicalize() {
        return Some(p);
    }
    let name = path.file_name()?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.canonicalize().ok()?,
        _ => std::env::current_dir().ok()?,
    };
    Some(dir.join(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_file_is_found_through_another_spelling_and_a_hard_link() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.toml");
        std::fs::write(&a, "x").unwrap();
        let sub = dir.path().join("sub");
        std::fs::create_dir(&sub).unwrap();
        assert!(same_file(&a, &sub.join("../a.toml")));
        let link = dir.path().join("b.toml");
        std::fs::hard_link(&a, &link).unwrap();
        assert!(same_file(&a, &link));
        assert!(!same_file(&a, &dir.path().join("c.toml")));
        // neither exists yet
        assert!(same_file(&dir.path().join("n.h5"), &sub.join("../n.h5")));
    }
}
