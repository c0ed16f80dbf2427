//! Running the `hya` binary from tests.
#![allow(dead_code)]

use std::io::Write;
use std::process::{Command, Output, Stdio};

/// Runs `hya ARGS` with `stdin` as its input.
pub fn hya(args: &[&str], stdin: &str) -> Output {
    hya_bytes(args, stdin.as_bytes())
}

/// Runs `hya ARGS` with the raw bytes `stdin` as its input.
pub fn hya_bytes(args: &[&str], stdin: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hya"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the hya binary runs");
    // Feed stdin from its own thread, so a full stdout pipe cannot deadlock the two processes.
    let mut pipe = child.stdin.take().expect("stdin is piped");
    let input = stdin.to_owned();
    let writer = std::thread::spawn(move || pipe.write_all(&input));
    let output = child.wait_with_output().expect("hya exits");
    // hya may stop reading early after a bad row; a broken pipe then is expected.
    let _ = writer.join().expect("the writer thread does not panic");
    output
}

/// A new empty folder for one test, `tag` naming it (with the process, so runs side by side do
/// not meet).
pub fn scratch(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("hya-cli-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a scratch folder is created");
    dir
}

/// `hya ARGS` on `input` must exit with code 2 and a message containing every `expected` part.
pub fn assert_rejected(args: &[&str], input: &str, expected_message: &[&str]) {
    let output = hya(args, input);
    assert_eq!(output.status.code(), Some(2), "exit code for {input:?}");
    let message = String::from_utf8_lossy(&output.stderr);
    for part in expected_message {
        assert!(message.contains(part), "message {message:?} lacks {part:?}");
    }
    assert!(!message.contains("panicked"), "{message}");
}

/// The data rows of a command's output: the header line hya writes first left out (a line whose
/// first cell is not a number), cells split at commas or blanks.
pub fn data_rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .map(|line| line.split(|c: char| c == ',' || c.is_whitespace()).filter(|c| !c.is_empty()))
        .filter_map(|cells| cells.map(|c| c.parse::<f64>().ok()).collect::<Option<Vec<f64>>>())
        .filter(|row| !row.is_empty())
        .collect()
}
