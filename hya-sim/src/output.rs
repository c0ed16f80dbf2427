//! The report folder: checked before any simulation starts, and every file written into it
//! named by one plain file-name component, so nothing lands outside it.

use std::path::{Component, Path, PathBuf};

use crate::SimError;

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> SimError {
    let path = path.display().to_string();
    move |source| SimError::Io { path, source }
}

/// The file in a report folder that lists, one per line, every file hya wrote there.
pub const MANIFEST: &str = ".hya-files";

/// Makes `dir` ready for a report, before anything is simulated: a folder that does not exist
/// is created; an empty one is used as it is; a non-empty one only with `force`, and only if it
/// holds an earlier report (a [`MANIFEST`]), whose listed files are then removed so that no
/// stale figure stays mixed in. Anything else in it (and any symbolic link) is kept and
/// returned, for the caller to name.
pub fn prepare(dir: &Path, force: bool) -> Result<Vec<PathBuf>, SimError> {
    if !dir.exists() {
        std::fs::create_dir_all(dir).map_err(io_error(dir))?;
        return Ok(Vec::new());
    }
    if !dir.is_dir() {
        return Err(SimError::Config(format!("--out {}: exists and is not a folder", dir.display())));
    }
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(io_error(dir))?
        .map(|e| e.map(|e| e.path()))
        .collect::<Result<_, _>>()
        .map_err(io_error(dir))?;
    entries.sort();
    if entries.is_empty() {
        return Ok(Vec::new());
    }
    if !force {
        return Err(SimError::Config(format!(
            "--out {}: the folder is not empty ({} entries, first {}); name a new or empty folder, or pass \
             --force to replace the hya report in it",
            dir.display(),
            entries.len(),
            entries[0].display()
        )));
    }
    let manifest = dir.join(MANIFEST);
    let listed = match std::fs::read_to_string(&manifest) {
        Ok(text) => text.lines().map(str::to_owned).collect::<Vec<_>>(),
        Err(_) => {
            return Err(SimError::Config(format!(
                "--out {}: --force replaces an earlier hya report, but this folder holds none (no {MANIFEST}); \
                 nothing was removed",
                dir.display()
            )))
        }
    };
    let mut kept = Vec::new();
    for path in entries {
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
        let plain_file = std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_file());
        if plain_file && (name == MANIFEST || listed.iter().any(|l| l == name)) {
            std::fs::remove_file(&path).map_err(io_error(&path))?;
        } else {
            kept.push(path);
        }
    }
    Ok(kept)
}

/// Writes `text` to the file `name` inside `dir` and lists it in the [`MANIFEST`]; `name` must
/// be one plain file name (no separator, `..`, root or drive), and nothing may stand at that
/// path as a symbolic link (which would write outside `dir`).
pub fn save(dir: &Path, name: &str, text: &str) -> Result<(), SimError> {
    let mut components = Path::new(name).components();
    let plain = matches!((components.next(), components.next()), (Some(Component::Normal(_)), None));
    if !plain || name.contains(['/', '\\']) || name == MANIFEST {
        return Err(SimError::Config(format!("report file name {name:?} is not a plain file name")));
    }
    let path = dir.join(name);
    if std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) {
        return Err(SimError::Config(format!("{}: is a symbolic link; hya writes only plain files", path.display())));
    }
    std::fs::write(&path, text).map_err(io_error(&path))?;
    let manifest = dir.join(MANIFEST);
    let mut listed = std::fs::read_to_string(&manifest).unwrap_or_default();
    if !listed.lines().any(|l| l == name) {
        listed.push_str(name);
        listed.push('\n');
        std::fs::write(&manifest, listed).map_err(io_error(&manifest))?;
    }
    Ok(())
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
        std::fs::create_dir_all(&dir).unwrap();
        for bad in ["../x.csv", "/tmp/x.csv", "a/b.csv", "..", "", "a\\b.csv"] {
            assert!(save(&dir, bad, "x").is_err(), "{bad:?} accepted");
        }
        save(&dir, "goto_lu.csv", "x").unwrap();
        assert!(dir.join("goto_lu.csv").is_file());
        assert_eq!(std::fs::read_to_string(dir.join(MANIFEST)).unwrap(), "goto_lu.csv\n");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("/tmp/hya-elsewhere.md", dir.join("report.md")).unwrap();
            assert!(save(&dir, "report.md", "x").unwrap_err().to_string().contains("symbolic link"));
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_non_empty_folder_needs_force_and_an_earlier_report() {
        let dir = scratch("force");
        assert!(prepare(&dir, false).unwrap().is_empty(), "a new folder is created");
        assert!(dir.is_dir());
        std::fs::write(dir.join("notes.txt"), "mine").unwrap();
        let refused = prepare(&dir, false).unwrap_err().to_string();
        assert!(refused.contains("not empty") && refused.contains("--force"), "{refused}");
        let refused = prepare(&dir, true).unwrap_err().to_string();
        assert!(refused.contains(MANIFEST), "{refused}");
        assert!(dir.join("notes.txt").is_file(), "nothing removed on refusal");
        for name in ["summary.json", "report.md", "old_lu.csv", "old_joints.svg"] {
            save(&dir, name, "old").unwrap();
        }
        std::fs::write(dir.join("measurements.csv"), "mine").unwrap();
        let kept = prepare(&dir, true).unwrap();
        assert_eq!(kept, vec![dir.join("measurements.csv"), dir.join("notes.txt")]);
        assert!(!dir.join("old_lu.csv").exists() && !dir.join("summary.json").exists());
        assert!(!dir.join(MANIFEST).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_file_as_the_folder_is_refused() {
        let file = scratch("file");
        std::fs::write(&file, "x").unwrap();
        assert!(prepare(&file, true).unwrap_err().to_string().contains("not a folder"));
        std::fs::remove_file(&file).unwrap();
    }
}
