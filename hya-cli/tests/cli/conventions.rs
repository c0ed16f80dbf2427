//! What a command-line user expects of any tool: shell completions, a version that names its
//! commit, options blamed by the names they type.

use crate::common::{assert_rejected, hya};

#[test]
fn completions_cover_every_command_in_each_shell() {
    for shell in ["bash", "zsh", "fish"] {
        let output = hya(&["completions", shell], "");
        assert!(output.status.success(), "{shell}");
        let script = String::from_utf8(output.stdout).unwrap();
        for command in ["estimate", "identify", "scenarios", "completions"] {
            assert!(script.contains(command), "{shell} completions lack {command}");
        }
    }
    assert_rejected(&["completions", "cmd.exe"], "", &["invalid value"]);
}

#[test]
fn the_version_names_its_commit_and_a_bad_step_is_blamed_on_dt() {
    let version = String::from_utf8(hya(&["--version"], "").stdout).unwrap();
    assert!(version.starts_with("hya ") && version.contains("(commit "), "{version}");
    assert_rejected(&["filter", "--dt", "1000"], "", &["--dt 1000: must be between"]);
    assert_rejected(&["filter", "--omega1", "1e6"], "", &["--omega1 1e6: must be such that it times --dt"]);
}
