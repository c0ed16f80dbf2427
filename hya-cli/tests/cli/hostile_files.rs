//! Paths that are not regular files (issue 35): a named pipe (FIFO) blocks `open` until a writer
//! comes, so every command that reads a path must refuse one by its type instead of hanging.
#![cfg(unix)]

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A scratch folder holding a FIFO named `name`.
fn fifo(name: &str) -> (PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("hya-cli-fifo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    let _ = std::fs::remove_file(&path);
    assert!(Command::new("mkfifo").arg(&path).status().unwrap().success());
    (dir, path)
}

/// Runs `hya ARGS` with an empty stdin; kills it and fails if it has not exited within 60 s.
fn exits_with_message(args: &[&str], expected: &[&str]) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hya"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("hya {args:?} blocked on the FIFO");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = child.wait_with_output().unwrap();
    let message = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "hya {args:?}: {message}");
    for part in expected {
        assert!(message.contains(part), "hya {args:?}: {message:?} lacks {part:?}");
    }
}

#[test]
fn no_command_blocks_on_a_fifo() {
    let (dir, path) = fifo("f");
    let f = path.to_str().unwrap();
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    exits_with_message(&["estimate", "--robot", "planar2", "--friction", f], &["named pipe"]);
    exits_with_message(&["estimate", "--robot", f], &["named pipe"]);
    exits_with_message(&["robots", "--urdf", f], &["named pipe"]);
    exits_with_message(
        &["identify", "--robot", "planar2", "--dt", "0.002", "--compare", f, "--out", out],
        &["named pipe"],
    );
    exits_with_message(&["run", f], &["named pipe"]);
    let scenario = dir.join("scenario.toml");
    std::fs::write(
        &scenario,
        format!(
            "name = \"tiny\"\nduration_s = 0.6\nmethods = [\"none\"]\n[task]\nkind = \"hold\"\n[controller]\n\
             model_urdf = {f:?}\n[plant]\nactuator = \"ideal\"\nfriction = \"smooth\"\n"
        ),
    )
    .unwrap();
    exits_with_message(&["run", scenario.to_str().unwrap(), "--out", out], &["named pipe"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The friction files every front end refuses (hya-ident's corpus, for a 2-joint arm; each
/// file's first line lists the words its message must hold), refused by `hya estimate` before
/// it reads a row.
#[test]
fn bad_friction_files_are_refused_as_the_library_refuses_them() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../hya-ident/tests/friction/refused");
    let mut files = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        let expect = text.lines().next().and_then(|l| l.strip_prefix("# expect: ")).unwrap();
        let file = path.file_name().unwrap().to_str().unwrap();
        let words: Vec<&str> = std::iter::once(file).chain(expect.split(" | ")).collect();
        exits_with_message(&["estimate", "--robot", "planar2", "--friction", path.to_str().unwrap()], &words);
        files += 1;
    }
    assert!(files >= 9, "the corpus was not found");
}
