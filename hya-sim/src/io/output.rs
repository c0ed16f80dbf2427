//! The report folder (`--out`): taken by one run at a time, and written so that nothing outside
//! it is ever touched.
//!
//! - **One run at a time**: [`OutputDir::open`] takes an exclusive lock on the folder (an
//!   advisory `flock` on the folder itself); a second run into it is refused, naming the holder
//!   that the first wrote into [`LOCK_NOTE`].
//! - **Nothing followed**: every file is written to a fresh temporary name (created exclusively,
//!   so an entry planted there is never opened) and renamed into place; a rename replaces a
//!   symbolic or hard link by a new file and never writes through it. A name that already
//!   stands in the folder and was not written by this run is refused, not replaced.
//! - **`--force` removes only what hya wrote**: the [`MANIFEST`] lists each file hya wrote with
//!   the SHA-256 of its content. It is trusted only if it is a regular file of plain names;
//!   a listed entry is removed only if it is still a regular file with that content. A listed
//!   file that changed since, or that is not a regular file, makes `--force` refuse before
//!   anything is removed.
//! - **The manifest is a journal**: a name is listed with the SHA-256 of its content before its
//!   file is renamed into place, and a `--force` that cleared a folder writes an empty manifest
//!   at once; so a run killed (or failed) at any point leaves a folder whose every report file is
//!   listed, absent or with its listed content, and the next `--force` removes them all. (A name
//!   saved twice by one run, which no command does, would list only its new checksum while the
//!   old content still stands, and `--force` would refuse: safe, not clean.) Temporary files
//!   `.hya-tmp-PID-NAME` left by a killed run are removed when the folder is next taken and
//!   found empty or trusted: the lock proves that no run that could still rename them is alive.
//! - **`--force` never removes what the run reads**: the caller names the files the run reads
//!   (scenario, URDFs, friction files); a listed report file that is one of them (the same
//!   file, whatever path names it) makes `--force` refuse before anything is removed.
//! - **`--force` never removes a shard's runs** ([`SHARD_FILE`], written by `--shard`): they
//!   may be hours of computing and are a merge's input; they are removed by hand or not at all.
//! - **A refused run leaves nothing**: a folder that [`OutputDir::open`] created is removed again
//!   if the run saved nothing into it.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{Read, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;

use sha2::{Digest, Sha256};

use crate::error::SimError;

/// The file in a report folder that lists every file hya wrote there with its SHA-256.
pub const MANIFEST: &str = ".hya-files";
/// The note naming the run that holds the folder (removed when it ends).
pub const LOCK_NOTE: &str = ".hya-lock";
/// The file a shard of `hya run`/`hya reproduce` (`--shard`) keeps its runs in
/// ([`crate::seed_shards`]); `--force` never removes it.
pub const SHARD_FILE: &str = "runs.cbor";
/// The manifest's first line; a manifest without it (or from an older hya) is not trusted.
const MANIFEST_HEADER: &str = "# hya report files: sha256, two spaces, file name";
/// The prefix of every temporary file name (`.hya-tmp-PID-NAME`).
const TEMPORARY_PREFIX: &str = ".hya-tmp-";
/// The largest manifest read, bytes (a report has a few hundred files at most).
const MAX_MANIFEST_BYTES: u64 = 1 << 20;

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> SimError {
    let path = path.display().to_string();
    move |source| SimError::Io { path, source }
}

fn refused(dir: &Path, why: impl std::fmt::Display) -> SimError {
    SimError::Output { dir: dir.display().to_string(), message: why.to_string() }
}

/// SHA-256 of `bytes`, lower-case hex.
pub(crate) fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// Whether `name` is one plain file name: no separator, `..`, root, drive or hidden-file dot.
fn is_plain_name(name: &str) -> bool {
    let mut components = Path::new(name).components();
    matches!((components.next(), components.next()), (Some(Component::Normal(_)), None))
        && !name.contains(['/', '\\'])
        && !name.starts_with('.')
        && !name.chars().any(char::is_control)
}

/// A report folder held by this run: see the module's documentation.
#[derive(Debug)]
pub struct OutputDir {
    path: PathBuf,
    /// The open folder, holding the exclusive lock until dropped.
    lock: File,
    /// Whether [`OutputDir::open`] created the folder.
    created: bool,
    /// Every file this run wrote (or is writing), with its SHA-256.
    written: Mutex<BTreeMap<String, String>>,
    /// Whether this run wrote the [`LOCK_NOTE`] (only then does it remove it).
    noted: bool,
}

impl OutputDir {
    /// Takes `dir` for a report, before anything is simulated. A folder that does not exist is
    /// created; an empty one is used as it is; a non-empty one only with `force`, and only if it
    /// holds an earlier report, whose files are then removed so that no stale figure stays mixed
    /// in. Anything else in it is kept and returned, for the caller to name. `reads` are the
    /// files the run reads (paths that name no file are passed over): a report file among them
    /// is never removed, and `--force` then refuses.
    pub fn open(dir: &Path, force: bool, holder: &str, reads: &[&Path]) -> Result<(Self, Vec<PathBuf>), SimError> {
        let created = match std::fs::metadata(dir) {
            Ok(m) if m.is_dir() => false,
            Ok(_) => return Err(refused(dir, "exists and is not a folder")),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                if std::fs::symlink_metadata(dir).is_ok() {
                    return Err(refused(dir, "is a symbolic link to nothing; remove it or name another folder"));
                }
                std::fs::create_dir_all(dir).map_err(io_error(dir))?;
                true
            }
            Err(e) => return Err(io_error(dir)(e)),
        };
        let lock = File::open(dir).map_err(io_error(dir))?;
        if let Err(e) = lock.try_lock() {
            return Err(match e {
                std::fs::TryLockError::WouldBlock => refused(
                    dir,
                    format!("is in use by another hya run ({}); wait for it, or name another folder", holder_of(dir)),
                ),
                std::fs::TryLockError::Error(e) => io_error(dir)(e),
            });
        }
        let mut out = Self { path: dir.to_owned(), lock, created, written: Mutex::new(BTreeMap::new()), noted: false };
        let kept = out.clear_earlier_report(force, reads)?;
        out.write_atomically(LOCK_NOTE, format!("pid {}, {holder}\n", std::process::id()).as_bytes())?;
        out.noted = true;
        Ok((out, kept))
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The folder's entries other than the lock note and leftover temporary files, sorted.
    fn entries(&self) -> Result<Vec<PathBuf>, SimError> {
        let dir = &self.path;
        let mut entries = Vec::new();
        for entry in std::fs::read_dir(dir).map_err(io_error(dir))? {
            let path = entry.map_err(io_error(dir))?.path();
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            if name != LOCK_NOTE && !name.starts_with(TEMPORARY_PREFIX) {
                entries.push(path);
            }
        }
        entries.sort();
        Ok(entries)
    }

    /// Removes the temporary files (regular files or links, never followed, named
    /// `.hya-tmp-PID-NAME`) a killed run left, once the folder is known to be empty or hya's:
    /// with the folder locked, no run that could still rename them is alive.
    fn remove_stale_temporaries(&self) -> Result<(), SimError> {
        let dir = &self.path;
        for entry in std::fs::read_dir(dir).map_err(io_error(dir))? {
            let entry = entry.map_err(io_error(dir))?;
            let name = entry.file_name();
            let temporary = name.to_str().and_then(|n| n.strip_prefix(TEMPORARY_PREFIX)).and_then(|rest| {
                let (pid, file) = rest.split_once('-')?;
                let hya_file = is_plain_name(file) || file == MANIFEST || file == LOCK_NOTE;
                Some(!pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()) && hya_file)
            });
            let stale = temporary == Some(true) && entry.file_type().is_ok_and(|t| t.is_file() || t.is_symlink());
            if stale {
                std::fs::remove_file(entry.path()).map_err(io_error(&entry.path()))?;
            }
        }
        Ok(())
    }

    /// See [`OutputDir::open`]: checks the folder and, with `force`, removes a verified report.
    fn clear_earlier_report(&self, force: bool, reads: &[&Path]) -> Result<Vec<PathBuf>, SimError> {
        let dir = &self.path;
        let entries = self.entries()?;
        // Nothing, or only the empty manifest a cleared folder keeps: an empty folder.
        let only_empty_manifest =
            entries.len() == 1 && entries[0] == dir.join(MANIFEST) && read_manifest(dir).is_ok_and(|m| m.is_empty());
        if entries.is_empty() || only_empty_manifest {
            self.remove_stale_temporaries()?;
            return Ok(Vec::new());
        }
        if !force {
            return Err(refused(
                dir,
                format!(
                    "the folder is not empty ({} entries, first {}); name a new or empty folder, or pass --force to \
                     replace the hya report in it",
                    entries.len(),
                    entries[0].display()
                ),
            ));
        }
        let listed = read_manifest(dir)?;
        let inputs: Vec<(PathBuf, &Path)> =
            reads.iter().filter_map(|read| Some((std::fs::canonicalize(read).ok()?, *read))).collect();
        // Every listed file is checked before any is removed: all or nothing.
        let mut remove = Vec::new();
        for (name, sha256) in &listed {
            let path = dir.join(name);
            if name == SHARD_FILE && std::fs::symlink_metadata(&path).is_ok() {
                return Err(refused(
                    dir,
                    format!(
                        "--force would remove {SHARD_FILE}, a shard's runs; nothing was removed: name another \
                         folder, or remove the file yourself if you mean to"
                    ),
                ));
            }
            let same = std::fs::canonicalize(&path).ok();
            if let Some((_, read)) = inputs.iter().find(|(input, _)| Some(input) == same.as_ref()) {
                return Err(refused(
                    dir,
                    format!(
                        "--force would remove {name}, which this run reads ({}); nothing was removed: write the \
                         report to another folder, or move the file out of this one first",
                        read.display()
                    ),
                ));
            }
            match std::fs::symlink_metadata(&path) {
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => return Err(io_error(&path)(e)),
                Ok(m) if !m.file_type().is_file() => {
                    return Err(refused(
                        dir,
                        format!("{name} is listed in {MANIFEST} but is not a regular file; nothing was removed"),
                    ))
                }
                Ok(_) => {
                    let content = std::fs::read(&path).map_err(io_error(&path))?;
                    if sha256_hex(&content) != *sha256 {
                        return Err(refused(
                            dir,
                            format!(
                                "{name} changed since hya wrote it (its SHA-256 differs from {MANIFEST}); nothing was \
                                 removed: move it away or name another folder"
                            ),
                        ));
                    }
                    remove.push(path);
                }
            }
        }
        for path in &remove {
            std::fs::remove_file(path).map_err(io_error(path))?;
        }
        // Before any new temporary: a killed run's, under this run's PID, would block it.
        self.remove_stale_temporaries()?;
        // The folder stays hya's (an empty manifest) until this run lists its first file: a run
        // that fails or is killed before that leaves a folder the next `--force` still trusts.
        self.write_manifest(&BTreeMap::new())?;
        remove.push(dir.join(MANIFEST));
        Ok(entries.into_iter().filter(|p| !remove.contains(p)).collect())
    }

    /// Writes `text` to the file `name` inside the folder and lists it in the [`MANIFEST`];
    /// `name` must be one plain file name, and no entry of that name may stand in the folder
    /// unless this run wrote it.
    pub fn save(&self, name: &str, text: &str) -> Result<(), SimError> {
        self.save_bytes(name, text.as_bytes())
    }

    /// [`Self::save`] for bytes that are not text (a shard's runs).
    pub fn save_bytes(&self, name: &str, bytes: &[u8]) -> Result<(), SimError> {
        if !is_plain_name(name) || name.len() > 255 {
            return Err(refused(&self.path, format!("report file name {name:?} is not a plain file name")));
        }
        let mut written = self.written.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        let path = self.path.join(name);
        if !written.contains_key(name) && std::fs::symlink_metadata(&path).is_ok() {
            return Err(refused(
                &self.path,
                format!("{name} already stands there and is not from this run; hya does not replace it"),
            ));
        }
        // Listed (with the content's checksum) before the file is renamed into place.
        written.insert(name.to_owned(), sha256_hex(bytes));
        self.write_manifest(&written)?;
        self.write_atomically(name, bytes)
    }

    /// Writes the [`MANIFEST`] of `written`.
    fn write_manifest(&self, written: &BTreeMap<String, String>) -> Result<(), SimError> {
        let manifest: String = std::iter::once(format!("{MANIFEST_HEADER}\n"))
            .chain(written.iter().map(|(name, sha256)| format!("{sha256}  {name}\n")))
            .collect();
        self.write_atomically(MANIFEST, manifest.as_bytes())
    }

    /// Writes `bytes` to a new temporary file in the folder and renames it to `name`.
    fn write_atomically(&self, name: &str, bytes: &[u8]) -> Result<(), SimError> {
        let temporary = self.path.join(format!("{TEMPORARY_PREFIX}{}-{name}", std::process::id()));
        let result = File::options()
            .write(true)
            .create_new(true)
            .open(&temporary)
            .and_then(|mut file| file.write_all(bytes).and_then(|()| file.sync_data()))
            .and_then(|()| std::fs::rename(&temporary, self.path.join(name)));
        if result.is_err() {
            let _ = std::fs::remove_file(&temporary);
        }
        result.map_err(io_error(&self.path.join(name)))
    }
}

impl Drop for OutputDir {
    /// Removes the lock note this run wrote, and the folder itself if this run created it and
    /// no file it listed stands there (it saved nothing, or every save failed): then only the
    /// manifest goes with it, and `remove_dir` leaves a folder anything else was put into.
    fn drop(&mut self) {
        if self.noted {
            let _ = std::fs::remove_file(self.path.join(LOCK_NOTE));
        }
        let nothing_stands = self.written.get_mut().is_ok_and(|w| w.keys().all(|n| !self.path.join(n).exists()));
        if self.created && nothing_stands {
            let _ = std::fs::remove_file(self.path.join(MANIFEST));
            let _ = std::fs::remove_dir(&self.path);
        }
        let _ = self.lock.unlock();
    }
}

/// What the [`LOCK_NOTE`] of a held folder says, for the refusal's message.
fn holder_of(dir: &Path) -> String {
    let path = dir.join(LOCK_NOTE);
    let regular = std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_file());
    let mut note = String::new();
    if regular {
        if let Ok(file) = File::open(&path) {
            let _ = file.take(200).read_to_string(&mut note);
        }
    }
    let note: String = note.trim().chars().filter(|c| !c.is_control()).collect();
    if note.is_empty() {
        "holder unknown".into()
    } else {
        note
    }
}

/// The trusted [`MANIFEST`] of `dir`: name → SHA-256, or the reason `--force` cannot trust it.
/// The SHA-256 the [`MANIFEST`] of `dir` lists for the file `name`, if the folder has a manifest
/// hya wrote and it lists the file: what a reader of that file checks its bytes against.
pub fn listed_sha256(dir: &Path, name: &str) -> Option<String> {
    read_manifest(dir).ok()?.remove(name)
}

fn read_manifest(dir: &Path) -> Result<BTreeMap<String, String>, SimError> {
    let path = dir.join(MANIFEST);
    let none = || {
        refused(
            dir,
            format!("--force replaces an earlier hya report, but this folder holds none (no {MANIFEST}); nothing was removed"),
        )
    };
    let metadata = std::fs::symlink_metadata(&path).map_err(|_| none())?;
    if !metadata.file_type().is_file() {
        return Err(refused(dir, format!("{MANIFEST} is not a regular file; nothing was removed")));
    }
    if metadata.len() > MAX_MANIFEST_BYTES {
        return Err(refused(dir, format!("{MANIFEST} is larger than {MAX_MANIFEST_BYTES} bytes; nothing was removed")));
    }
    let mut text = String::new();
    File::open(&path).and_then(|f| f.take(MAX_MANIFEST_BYTES).read_to_string(&mut text)).map_err(io_error(&path))?;
    let mut lines = text.lines();
    if lines.next() != Some(MANIFEST_HEADER) {
        return Err(refused(
            dir,
            format!("{MANIFEST} is not one this hya wrote (no checksums); nothing was removed: delete the old report yourself"),
        ));
    }
    let mut listed = BTreeMap::new();
    for (number, line) in lines.enumerate() {
        let entry = line.split_once("  ").filter(|(sha, name)| {
            sha.len() == 64 && sha.bytes().all(|b| b.is_ascii_hexdigit()) && is_plain_name(name) && *name != MANIFEST
        });
        let Some((sha256, name)) = entry else {
            return Err(refused(
                dir,
                format!("{MANIFEST} line {}: not `sha256  plain-file-name`; nothing was removed", number + 2),
            ));
        };
        listed.insert(name.to_owned(), sha256.to_owned());
    }
    Ok(listed)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    fn scratch(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("hya-output-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn names_with_separators_or_parents_are_refused() {
        let dir = scratch("names");
        let (out, _) = OutputDir::open(&dir, false, "test", &[]).unwrap();
        for bad in ["../x.csv", "/tmp/x.csv", "a/b.csv", "..", "", "a\\b.csv", ".hya-files", ".hidden", "a\nb"] {
            assert!(out.save(bad, "x").is_err(), "{bad:?} accepted");
        }
        out.save("goto_lu.csv", "x").unwrap();
        assert!(dir.join("goto_lu.csv").is_file());
        let manifest = std::fs::read_to_string(dir.join(MANIFEST)).unwrap();
        assert_eq!(manifest, format!("{MANIFEST_HEADER}\n{}  goto_lu.csv\n", sha256_hex(b"x")));
        drop(out);
        assert!(!dir.join(LOCK_NOTE).exists(), "the lock note goes with the run");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_non_empty_folder_needs_force_and_an_earlier_report() {
        let dir = scratch("force");
        let (out, kept) = OutputDir::open(&dir, false, "test", &[]).unwrap();
        assert!(kept.is_empty() && dir.is_dir(), "a new folder is created");
        for name in ["summary.json", "report.md", "old_lu.csv", "old_joints.svg"] {
            out.save(name, "old").unwrap();
        }
        drop(out);
        std::fs::write(dir.join("measurements.csv"), "mine").unwrap();
        let refused = OutputDir::open(&dir, false, "test", &[]).unwrap_err().to_string();
        assert!(refused.contains("not empty") && refused.contains("--force"), "{refused}");
        let (_out, kept) = OutputDir::open(&dir, true, "test", &[]).unwrap();
        assert_eq!(kept, vec![dir.join("measurements.csv")]);
        assert!(!dir.join("old_lu.csv").exists() && !dir.join("summary.json").exists());
        let manifest = std::fs::read_to_string(dir.join(MANIFEST)).unwrap();
        assert_eq!(manifest, format!("{MANIFEST_HEADER}\n"), "the cleared folder keeps an empty manifest");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn force_without_a_trusted_manifest_removes_nothing() {
        let dir = scratch("untrusted");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("data.csv"), "precious").unwrap();
        let refused = OutputDir::open(&dir, true, "test", &[]).unwrap_err().to_string();
        assert!(refused.contains("no .hya-files"), "{refused}");
        // A planted manifest of the old kind (bare names), or with a wrong checksum.
        std::fs::write(dir.join(MANIFEST), "data.csv\n").unwrap();
        assert!(OutputDir::open(&dir, true, "test", &[]).unwrap_err().to_string().contains("not one this hya wrote"));
        std::fs::write(dir.join(MANIFEST), format!("{MANIFEST_HEADER}\n{}  data.csv\n", sha256_hex(b"other"))).unwrap();
        assert!(OutputDir::open(&dir, true, "test", &[])
            .unwrap_err()
            .to_string()
            .contains("changed since hya wrote it"));
        std::fs::write(dir.join(MANIFEST), format!("{MANIFEST_HEADER}\n{}  ../data.csv\n", sha256_hex(b"x"))).unwrap();
        assert!(OutputDir::open(&dir, true, "test", &[]).unwrap_err().to_string().contains("line 2"));
        assert_eq!(std::fs::read_to_string(dir.join("data.csv")).unwrap(), "precious");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A `--force` run of three files over an earlier report in `dir`, killed after `cut` of
    /// its steps: each file is listed with its checksum, written to a temporary and renamed into
    /// place (three steps each).
    fn killed_run(dir: &Path, cut: usize) {
        let (earlier, _) = OutputDir::open(dir, false, "test", &[]).unwrap();
        earlier.save("old.csv", "old").unwrap();
        drop(earlier);
        std::fs::write(dir.join("mine.txt"), "user data").unwrap();
        let (out, _) = OutputDir::open(dir, true, "test", &[]).unwrap();
        let mut written = BTreeMap::new();
        for (step, name) in ["summary.json", "a.csv", "report.md"].iter().flat_map(|n| [n; 3]).enumerate().take(cut) {
            match step % 3 {
                0 => {
                    written.insert(name.to_string(), sha256_hex(b"x"));
                    out.write_manifest(&written).unwrap();
                }
                1 => std::fs::write(dir.join(format!("{TEMPORARY_PREFIX}999999-{name}")), "x").unwrap(),
                _ => std::fs::rename(dir.join(format!("{TEMPORARY_PREFIX}999999-{name}")), dir.join(name)).unwrap(),
            }
        }
        // SIGKILL runs no destructor; the lock note is what dropping would have removed.
        drop(out);
        std::fs::write(dir.join(LOCK_NOTE), "pid 999999, test").unwrap();
    }

    #[test]
    fn force_cleans_a_run_killed_at_any_point() {
        let dir = scratch("killed");
        for cut in 0..=9 {
            killed_run(&dir, cut);
            let (out, kept) = OutputDir::open(&dir, true, "test", &[]).unwrap_or_else(|e| panic!("cut {cut}: {e}"));
            assert_eq!(kept, vec![dir.join("mine.txt")], "cut {cut}");
            let mut left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
            left.sort();
            assert_eq!(left, [MANIFEST, LOCK_NOTE, "mine.txt"], "cut {cut}: the report and its temporaries are gone");
            // The next run writes the same names.
            for name in ["summary.json", "a.csv", "report.md"] {
                out.save(name, "new").unwrap();
            }
            drop(out);
            std::fs::remove_dir_all(&dir).unwrap();
        }
    }

    #[test]
    fn a_file_changed_after_it_was_listed_is_not_removed() {
        // Killed after listing summary.json's checksum and renaming it; then someone edits it.
        let dir = scratch("edited");
        killed_run(&dir, 3);
        std::fs::write(dir.join("summary.json"), "edited by hand").unwrap();
        let refused = OutputDir::open(&dir, true, "test", &[]).unwrap_err().to_string();
        assert!(refused.contains("summary.json changed since hya wrote it"), "{refused}");
        assert_eq!(std::fs::read_to_string(dir.join("summary.json")).unwrap(), "edited by hand");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_killed_manifest_write_leaves_nothing_the_next_run_trips_on() {
        // Killed while writing the manifest or the lock note, under a PID the next run may reuse.
        let dir = scratch("manifest-temporary");
        killed_run(&dir, 4);
        let pid = std::process::id();
        for name in [MANIFEST, LOCK_NOTE] {
            std::fs::write(dir.join(format!("{TEMPORARY_PREFIX}{pid}-{name}")), "partial").unwrap();
        }
        let (out, _) = OutputDir::open(&dir, true, "test", &[]).unwrap();
        out.save("summary.json", "new").unwrap();
        drop(out);
        let left: Vec<String> =
            std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        assert!(left.iter().all(|n| !n.starts_with(TEMPORARY_PREFIX)), "{left:?}");
        // A folder --force cleared and nothing was saved into holds an empty manifest: empty.
        std::fs::remove_dir_all(&dir).unwrap();
        killed_run(&dir, 0);
        std::fs::remove_file(dir.join("mine.txt")).unwrap();
        assert!(OutputDir::open(&dir, false, "test", &[]).is_ok(), "a cleared folder needs no --force");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn temporaries_are_left_alone_in_a_folder_not_known_to_be_hya_s() {
        let dir = scratch("foreign");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(".hya-tmp-12-data.csv"), "theirs").unwrap();
        std::fs::write(dir.join("data.csv"), "theirs").unwrap();
        assert!(OutputDir::open(&dir, true, "test", &[]).is_err());
        assert!(dir.join(".hya-tmp-12-data.csv").is_file(), "a refused run removed a file");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn force_never_removes_a_file_the_run_reads() {
        let dir = scratch("reads");
        let (out, _) = OutputDir::open(&dir, false, "test", &[]).unwrap();
        out.save("identified.urdf", "<robot/>").unwrap();
        out.save("report.md", "old").unwrap();
        drop(out);
        // Named through another path to the same file: still the same file.
        let roundabout = dir.join("..").join(dir.file_name().unwrap()).join("identified.urdf");
        let refused = OutputDir::open(&dir, true, "test", &[Path::new("hya"), &roundabout]).unwrap_err().to_string();
        assert!(refused.contains("would remove identified.urdf, which this run reads"), "{refused}");
        assert!(dir.join("identified.urdf").is_file() && dir.join("report.md").is_file(), "nothing removed");
        let (_out, _) = OutputDir::open(&dir, true, "test", &[Path::new("/nonexistent/x.urdf")]).unwrap();
        assert!(!dir.join("identified.urdf").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn links_are_never_written_through() {
        let dir = scratch("links");
        let victim = scratch("links-victim");
        std::fs::write(&victim, "victim").unwrap();
        // A manifest that is a symbolic link to a file elsewhere: --force refuses, the file keeps.
        std::fs::create_dir_all(&dir).unwrap();
        std::os::unix::fs::symlink(&victim, dir.join(MANIFEST)).unwrap();
        assert!(OutputDir::open(&dir, true, "test", &[]).unwrap_err().to_string().contains("not a regular file"));
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "victim");
        std::fs::remove_dir_all(&dir).unwrap();
        // A report name that is a hard link or a symbolic link to the user's file: not replaced.
        let (out, _) = OutputDir::open(&dir, false, "test", &[]).unwrap();
        std::fs::hard_link(&victim, dir.join("report.md")).unwrap();
        std::os::unix::fs::symlink(&victim, dir.join("summary.json")).unwrap();
        for name in ["report.md", "summary.json"] {
            assert!(out.save(name, "report").unwrap_err().to_string().contains("not from this run"));
        }
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "victim");
        // A planted temporary name is not opened either: the write fails, the file keeps.
        let planted = dir.join(format!(".hya-tmp-{}-x.csv", std::process::id()));
        std::os::unix::fs::symlink(&victim, &planted).unwrap();
        assert!(out.save("x.csv", "x").is_err());
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "victim");
        drop(out);
        std::fs::remove_dir_all(&dir).unwrap();
        std::fs::remove_file(&victim).unwrap();
    }

    #[test]
    fn a_held_folder_is_refused_naming_its_holder() {
        let dir = scratch("held");
        let (first, _) = OutputDir::open(&dir, false, "hya sweep --shard 0/64", &[]).unwrap();
        let refused = OutputDir::open(&dir, true, "hya sweep --shard 1/64", &[]).unwrap_err().to_string();
        assert!(refused.contains("in use by another hya run") && refused.contains("--shard 0/64"), "{refused}");
        first.save("sweep.json", "{}").unwrap();
        drop(first);
        let (_again, _) = OutputDir::open(&dir, true, "again", &[]).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_created_for_a_run_that_saved_nothing_is_removed() {
        let dir = scratch("refused-run");
        let (out, _) = OutputDir::open(&dir, false, "test", &[]).unwrap();
        assert!(dir.is_dir());
        drop(out);
        assert!(!dir.exists(), "an empty --out is left behind");
    }

    #[test]
    fn a_file_or_a_dangling_link_as_the_folder_is_refused() {
        let file = scratch("file");
        std::fs::write(&file, "x").unwrap();
        assert!(OutputDir::open(&file, true, "test", &[]).unwrap_err().to_string().contains("not a folder"));
        std::fs::remove_file(&file).unwrap();
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("/nonexistent/hya", &file).unwrap();
            assert!(OutputDir::open(&file, false, "test", &[])
                .unwrap_err()
                .to_string()
                .contains("symbolic link to nothing"));
            std::fs::remove_file(&file).unwrap();
        }
    }
}
