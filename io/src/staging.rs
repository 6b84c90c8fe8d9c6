//! Whole-or-nothing writes ([`write_atomic`], [`AtomicFile`]) and the
//! checks before one ([`check_not_an_input`], [`check_writable`]).
//!
//! Hidden siblings of an output while it is written. Every partial output
//! of a command is a sibling `.{name}.{kind}-{pid}` of its final path (a
//! temporary file renamed into place, a staging directory), held under an
//! exclusive advisory lock while the writing process lives: a file's own
//! lock, or a directory's lock file `.{name}.lock-{pid}` ([`claim`]). A run
//! killed before it finished (kill -9, a power cut) leaves its siblings
//! behind; the next run that writes the same output removes every sibling
//! whose lock nobody holds ([`sweep`]), so they never pile up. A sibling
//! whose lock cannot be tested (a file system without locks) is kept.

use crate::error::ReadError;
use std::fs::{File, TryLockError};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The kinds of sibling a command leaves while it writes.
const KINDS: [&str; 5] = ["tmp", "partial", "old", "probe", "lock"];

/// The directory and file name of `out`.
fn parts(out: &Path) -> (&Path, String) {
    let dir = out
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = out
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    (dir, name)
}

/// This process's sibling of kind `kind` for `out`: `.{name}.{kind}-{pid}`.
pub fn sibling(out: &Path, kind: &str) -> PathBuf {
    let (dir, name) = parts(out);
    dir.join(format!(".{name}.{kind}-{}", std::process::id()))
}

/// True when `file` is locked by a live process (false when nobody holds
/// it; true, to be safe, when the lock cannot be tested).
fn held(file: &Path) -> bool {
    match File::open(file).map(|f| f.try_lock()) {
        Ok(Ok(())) => false,
        Ok(Err(TryLockError::WouldBlock)) => true,
        Ok(Err(TryLockError::Error(_))) => true,
        // Gone meanwhile: nobody writes through it.
        Err(_) => false,
    }
}

/// Removes the siblings of `out` left by runs that no longer live (their
/// lock file and temporary file are unlocked); returns what it removed.
/// Errors are ignored: a sibling that cannot be removed stays, and the
/// command goes on.
pub fn sweep(out: &Path) -> Vec<PathBuf> {
    let (dir, name) = parts(out);
    let prefix = format!(".{name}.");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    // (pid, kind, path) of every sibling.
    let siblings: Vec<(u32, &str, PathBuf)> = entries
        .flatten()
        .filter_map(|e| {
            let file = e.file_name().to_str()?.to_string();
            let (kind, pid) = file.strip_prefix(&prefix)?.rsplit_once('-')?;
            let kind = KINDS.into_iter().find(|&k| k == kind)?;
            Some((pid.parse().ok()?, kind, e.path()))
        })
        .collect();
    let alive = |pid: u32| {
        siblings.iter().any(|(p, kind, path)| {
            *p == pid && matches!(*kind, "lock" | "tmp") && path.is_file() && held(path)
        })
    };
    let mut removed = Vec::new();
    for (pid, _, path) in &siblings {
        if alive(*pid) {
            continue;
        }
        let gone = if path.is_dir() {
            std::fs::remove_dir_all(path)
        } else {
            std::fs::remove_file(path)
        };
        if gone.is_ok() {
            removed.push(path.clone());
        }
    }
    removed
}

/// A claim on `out` for this process's lifetime: its lock file
/// `.{name}.lock-{pid}`, locked, so that [`sweep`] keeps this run's
/// staging siblings; removed when dropped.
#[derive(Debug)]
pub struct Claim {
    _file: File,
    path: PathBuf,
}

/// Sweeps `out`'s stale siblings, then claims it ([`Claim`]).
///
/// # Errors
/// [`ReadError::Io`] when the lock file cannot be created.
pub fn claim(out: &Path) -> Result<Claim, ReadError> {
    sweep(out);
    let path = sibling(out, "lock");
    let file = File::create(&path).map_err(|e| ReadError::io(&path, "create", e))?;
    // A file system without locks: the claim still names the run.
    let _ = file.try_lock();
    Ok(Claim { _file: file, path })
}

impl Drop for Claim {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// Writes `contents` to `path` whole or not at all (temporary file, then rename).
///
/// # Errors
/// [`ReadError::Io`] when the file cannot be written.
pub fn write_atomic(path: &Path, contents: &str) -> Result<(), ReadError> {
    write_atomic_bytes(path, contents.as_bytes())
}

/// Writes `contents` to `path` whole or not at all (temporary file, then rename).
///
/// # Errors
/// [`ReadError::Io`] when the file cannot be written.
pub fn write_atomic_bytes(path: &Path, contents: &[u8]) -> Result<(), ReadError> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(contents)
        .map_err(|e| ReadError::io(path, "write", e))?;
    file.commit()
}

/// A file written whole or not at all, streamed: a temporary file beside
/// `path` that [`AtomicFile::commit`] renames over it. Dropped without a
/// commit (an error on the way), it removes the temporary file and leaves
/// `path` as it was.
pub struct AtomicFile {
    path: PathBuf,
    tmp: PathBuf,
    file: Option<std::io::BufWriter<std::fs::File>>,
}

impl AtomicFile {
    /// Creates the temporary file for `path`.
    ///
    /// # Errors
    /// [`ReadError::Io`] when it cannot be created.
    pub fn create(path: &Path) -> Result<Self, ReadError> {
        // Temporary files of earlier runs that were killed go first.
        crate::staging::sweep(path);
        let tmp = crate::staging::sibling(path, "tmp");
        let file = std::fs::File::create(&tmp).map_err(|e| ReadError::io(path, "write", e))?;
        // Held while this process lives ([`crate::staging`]); a file system
        // without locks still gets the file.
        let _ = file.try_lock();
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            file: Some(std::io::BufWriter::new(file)),
        })
    }

    /// Flushes, syncs and renames the file into place.
    ///
    /// # Errors
    /// [`ReadError::Io`] when any of those fails (the temporary file is removed).
    pub fn commit(mut self) -> Result<(), ReadError> {
        let file = self.file.take().expect("committed once");
        let result = file
            .into_inner()
            .map_err(|e| e.into_error())
            .and_then(|f| f.sync_all())
            .and_then(|()| std::fs::rename(&self.tmp, &self.path));
        result.map_err(|e| ReadError::io(&self.path, "write", e))
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.as_mut().expect("not committed").write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.as_mut().expect("not committed").flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Not committed, or the rename failed: nothing of it stays.
        if self.file.is_some() || self.tmp.exists() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Refuses `out` when it is the same file as one of `inputs`, however the
/// paths are spelled (`./v.csv` and `v.csv`, symbolic or hard links): the
/// file's identity is compared, not its name. An `out` that does not exist
/// yet is none of them.
///
/// ```
/// # let dir = std::env::temp_dir().join(format!("laminar-doc-{}", std::process::id()));
/// # std::fs::create_dir_all(&dir).unwrap();
/// let input = dir.join("values.csv");
/// std::fs::write(&input, "1,2\n").unwrap();
/// let spelled = dir.join(".").join("values.csv");
/// assert!(laminar_brdf_io::check_not_an_input(&spelled, &[&input]).is_err());
/// assert!(laminar_brdf_io::check_not_an_input(&dir.join("out.csv"), &[&input]).is_ok());
/// # std::fs::remove_dir_all(&dir).unwrap();
/// ```
///
/// # Errors
/// [`ReadError::OutputIsInput`] naming both paths.
pub fn check_not_an_input<P: AsRef<Path>>(out: &Path, inputs: &[P]) -> Result<(), ReadError> {
    match inputs
        .iter()
        .find(|input| same_file::is_same_file(out, input).unwrap_or(false))
    {
        Some(input) => Err(ReadError::OutputIsInput {
            out: out.to_path_buf(),
            input: input.as_ref().to_path_buf(),
        }),
        None => Ok(()),
    }
}

/// Checks before any work that `path` can be written: its directory exists
/// and accepts a new file (a probe file is created and removed; an existing
/// `path` is left untouched).
///
/// # Errors
/// [`ReadError::Io`] when `path` is a directory or its directory refuses a new file.
pub fn check_writable(path: &Path) -> Result<(), ReadError> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if path.is_dir() {
        return Err(ReadError::io(
            path,
            "write",
            std::io::Error::other("it is a directory"),
        ));
    }
    let probe = dir.join(format!(".laminar-probe-{}", std::process::id()));
    std::fs::File::create(&probe).map_err(|e| ReadError::io(path, "write", e))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Siblings of a dead run go; a live run's (its lock held) stay.
    #[test]
    fn stale_siblings_are_swept_and_live_ones_kept() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("fits.json");
        let dead = |kind: &str| d.path().join(format!(".fits.json.{kind}-999999999"));
        std::fs::write(dead("tmp"), "partial").unwrap();
        std::fs::create_dir(dead("partial")).unwrap();
        std::fs::write(dead("partial").join("table.md"), "x").unwrap();
        std::fs::write(dead("lock"), "").unwrap();
        // Another output's sibling, and a live run's, are not touched.
        let other = d.path().join(".other.json.tmp-999999999");
        std::fs::write(&other, "").unwrap();
        let live = d.path().join(".fits.json.tmp-888888888");
        let held_file = File::create(&live).unwrap();
        held_file.try_lock().unwrap();
        let mut removed = sweep(&out);
        removed.sort();
        let mut want = vec![dead("lock"), dead("partial"), dead("tmp")];
        want.sort();
        assert_eq!(removed, want);
        assert!(other.exists() && live.exists());
        drop(held_file);
        assert_eq!(sweep(&out), vec![live]);
        // A claim keeps its run's staging directory until it is dropped.
        let c = claim(&out).unwrap();
        std::fs::create_dir(sibling(&out, "partial")).unwrap();
        assert!(sweep(&out).is_empty());
        drop(c);
        assert_eq!(sweep(&out), vec![sibling(&out, "partial")]);
    }
}
