//! Hostile URDFs given to the `hya` binary (issue 18): every command that reads one refuses it
//! with exit code 2 and a message naming the limit or the fault, and never crashes.
#![allow(clippy::expect_used)] // test helpers: a failed expect is a failed test

use std::path::PathBuf;

use crate::common::assert_rejected;

/// A temporary folder of this test process, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("hya-cli-hostile-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    /// Writes `text` to `name` in the folder, returning its path.
    fn file(&self, name: &str, text: &str) -> String {
        let path = self.0.join(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_owned()
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn deeply_nested_xml_exits_2_naming_the_limit_in_every_command() {
    let dir = TempDir::new("deep");
    let deep =
        dir.file("deep.urdf", &format!("<robot name=\"r\">{}{}</robot>", "<x>".repeat(20_000), "</x>".repeat(20_000)));
    let limit = hya_urdf::MAX_XML_DEPTH.to_string();
    let expected = ["deep.urdf", "MAX_XML_DEPTH", limit.as_str()];
    assert_rejected(&["robots", "--urdf", &deep], "", &expected);
    for command in ["id", "fd", "mass", "gravity"] {
        assert_rejected(&[command, "--robot", &deep], "0\n", &expected);
    }
    assert_rejected(&["generate", &deep, "--name", "Deep"], "", &expected);
}

#[test]
fn an_oversized_file_exits_2_naming_the_limit() {
    let dir = TempDir::new("large");
    let large = dir.file("large.urdf", &" ".repeat(hya_urdf::MAX_FILE_BYTES + 1));
    assert_rejected(&["robots", "--urdf", &large], "", &["large.urdf", "MAX_FILE_BYTES"]);
    #[cfg(unix)]
    assert_rejected(&["robots", "--urdf", "/dev/zero"], "", &["/dev/zero", "a device, not a regular file"]);
}

/// A one-joint arm whose robot, link and joint names are the given (XML-escaped) texts.
fn arm(robot: &str, link: &str, joint: &str) -> String {
    format!(
        r#"<robot name="{robot}">
  <link name="base"/>
  <link name="{link}"><inertial><mass value="1"/><origin xyz="0.1 0 0"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="{joint}" type="revolute"><parent link="base"/><child link="{link}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>"#
    )
}

#[test]
fn names_with_line_breaks_are_printed_escaped() {
    let dir = TempDir::new("names");
    let forged = dir.file("forged.urdf", &arm("arm&#10;ur5 6 forged", "link", "j1&#10;panda 7 forged"));
    let output = crate::common::hya(&["robots", "--urdf", &forged], "");
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert_eq!(stdout, "arm\\nur5 6 forged 1 j1\\npanda 7 forged\n");
}

#[test]
fn unusable_models_exit_2_naming_the_joint() {
    let dir = TempDir::new("unusable");
    let inverted = dir.file(
        "inverted.urdf",
        &arm("arm", "link", "j1").replace("lower=\"-1\" upper=\"1\"", "lower=\"3\" upper=\"-3\""),
    );
    assert_rejected(
        &["robots", "--urdf", &inverted],
        "",
        &["inverted.urdf", "`j1`", "lower limit 3 is above upper limit -3"],
    );
    let unnamed = dir.file("unnamed.urdf", &arm("arm", "link", ""));
    assert_rejected(&["robots", "--urdf", &unnamed], "", &["unnamed.urdf", "joint number 1", "empty name"]);
}

/// A serial chain of `n` revolute joints, alternating axes, all joints listed before the links.
fn chain(n: usize) -> String {
    let inertial = r#"<inertial><mass value="1"/><origin xyz="0.05 0.02 0.01"/><inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial>"#;
    let mut joints = String::new();
    let mut links = String::from("<link name=\"l0\"/>");
    for i in 1..=n {
        let axis = if i.is_multiple_of(2) { "0 1 0" } else { "0 0 1" };
        joints += &format!(
            "<joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{}\"/><child link=\"l{i}\"/><origin xyz=\"0.1 0 0\"/><axis xyz=\"{axis}\"/></joint>\n",
            i - 1
        );
        links += &format!("<link name=\"l{i}\">{inertial}</link>\n");
    }
    format!("<robot name=\"chain\">\n{joints}{links}</robot>\n")
}

#[test]
fn long_chains_are_refused_by_the_loader_and_the_generator_naming_their_caps() {
    let dir = TempDir::new("chains");
    // Loading it took 3.4 GB.
    let huge = dir.file("huge.urdf", &chain(20_000));
    assert_rejected(&["robots", "--urdf", &huge], "", &["huge.urdf", "MAX_JOINTS", &hya_urdf::MAX_JOINTS.to_string()]);
    // Generating code for 128 joints took over 5 GB; the generator's cap is far lower.
    let n = hya_codegen::MAX_JOINTS + 1;
    let long = dir.file("long.urdf", &chain(n));
    let output = crate::common::hya(&["robots", "--urdf", &long], "");
    assert_eq!(output.status.code(), Some(0), "the loader takes it: {}", String::from_utf8_lossy(&output.stderr));
    assert_rejected(&["generate", &long, "--name", "Long"], "", &["hya_codegen::MAX_JOINTS", &format!("{n} joints")]);
}
