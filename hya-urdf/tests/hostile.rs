//! Hostile descriptions (issue 18): text built to exhaust the stack or memory, and models that
//! parse but cannot be simulated, are refused with a message naming the limit or the fault.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_urdf::{load_file, load_str, Problem, MAX_FILE_BYTES, MAX_JOINTS, MAX_XML_DEPTH, MAX_XML_NODES};

/// The refusal of `text`, which must not load.
fn refusal(text: &str) -> Problem {
    load_str(text, "hostile.urdf").expect_err("the description is refused").problem
}

/// A body the loader accepts: 1 kg, off every axis.
const INERTIAL: &str = r#"<inertial><mass value="1"/><origin xyz="0.05 0.02 0.01"/><inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial>"#;

/// A serial chain of `n` revolute joints, alternating axes, each link before its joint.
fn chain(n: usize) -> String {
    let mut urdf = String::from("<robot name=\"chain\"><link name=\"l0\"/>");
    for i in 1..=n {
        urdf += &format!("<link name=\"l{i}\">{INERTIAL}</link>{}", joint(i));
    }
    urdf + "</robot>"
}

/// The same chain with every joint listed before the links.
fn chain_joints_first(n: usize) -> String {
    let joints: String = (1..=n).map(joint).collect();
    let links: String = (1..=n).map(|i| format!("<link name=\"l{i}\">{INERTIAL}</link>")).collect();
    format!("<robot name=\"chain\">{joints}<link name=\"l0\"/>{links}</robot>")
}

/// Joint `j{i}` from link `l{i-1}` to `l{i}`, about z for odd `i`, y for even.
fn joint(i: usize) -> String {
    let axis = if i.is_multiple_of(2) { "0 1 0" } else { "0 0 1" };
    format!(
        "<joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{}\"/><child link=\"l{i}\"/><origin xyz=\"0.1 0 0\"/><axis xyz=\"{axis}\"/></joint>",
        i - 1
    )
}

/// `<robot>` holding `depth` nested `<x>` elements.
fn nested(depth: usize) -> String {
    format!("<robot name=\"r\">{}{}</robot>", "<x>".repeat(depth), "</x>".repeat(depth))
}

#[test]
fn deeply_nested_xml_is_refused_before_it_is_parsed() {
    // 20,000 levels overflowed urdf-rs's recursive parsing (a stack overflow, exit 134).
    let problem = refusal(&nested(20_000));
    assert_eq!(problem, Problem::TooDeep { limit: MAX_XML_DEPTH });
    let message = problem.to_string();
    assert!(message.contains(&MAX_XML_DEPTH.to_string()) && message.contains("MAX_XML_DEPTH"), "{message}");
    // Right at the limit the nesting passes this check (and fails later: no links, no joints).
    assert!(!matches!(refusal(&nested(MAX_XML_DEPTH - 1)), Problem::TooDeep { .. }));
    assert!(matches!(refusal(&nested(MAX_XML_DEPTH)), Problem::TooDeep { .. }));
    // Comments, CDATA and processing instructions do not hide nesting, nor count as elements.
    let disguised = format!(
        "<robot name=\"r\"><!-- <a> --><?pi <b> ?>{}<![CDATA[<c>]]>{}</robot>",
        "<x a='>'>".repeat(MAX_XML_DEPTH),
        "</x>".repeat(MAX_XML_DEPTH)
    );
    assert!(matches!(refusal(&disguised), Problem::TooDeep { .. }));
}

#[test]
fn text_beyond_the_size_limit_is_refused() {
    let mut text = chain(2);
    text += &" ".repeat(MAX_FILE_BYTES + 1 - text.len());
    assert_eq!(refusal(&text), Problem::TooLarge { size: Some(MAX_FILE_BYTES as u64 + 1), limit: MAX_FILE_BYTES });

    let dir = std::env::temp_dir().join(format!("hya-urdf-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("large.urdf");
    std::fs::write(&path, &text).unwrap();
    let error = load_file(&path).unwrap_err();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(error.problem, Problem::TooLarge { size: Some(MAX_FILE_BYTES as u64 + 1), limit: MAX_FILE_BYTES });
    let message = error.to_string();
    assert!(message.contains("large.urdf") && message.contains("MAX_FILE_BYTES"), "{message}");
    // At the limit, the padding is fine.
    text.truncate(MAX_FILE_BYTES);
    assert!(load_str(&text, "padded.urdf").is_ok());
}

#[cfg(unix)]
#[test]
fn a_device_or_a_fifo_is_refused_before_it_is_opened() {
    // `/dev/zero` claims 0 bytes and never ends; a FIFO without a writer blocks `open` for ever.
    let error = load_file("/dev/zero").unwrap_err();
    let message = error.to_string();
    assert!(message.contains("/dev/zero") && message.contains("a device, not a regular file"), "{message}");
    let dir = std::env::temp_dir().join(format!("hya-urdf-fifo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("robot.urdf");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let message = load_file(&fifo).unwrap_err().to_string();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(message.contains("robot.urdf") && message.contains("named pipe (FIFO)"), "{message}");
}

#[test]
fn too_many_xml_nodes_are_refused() {
    let text = format!("<robot name=\"r\">{}</robot>", "<x/>".repeat(MAX_XML_NODES));
    assert_eq!(refusal(&text), Problem::TooMany { what: "XML nodes", limit: MAX_XML_NODES });
}

#[test]
fn a_chain_of_twenty_thousand_joints_is_refused_by_the_joint_cap() {
    // It took 3.4 GB to load; now it stops at the cap, before urdf-rs builds anything.
    // The chain lists each link before its joint, so the link count passes its cap first.
    let problem = refusal(&chain(20_000));
    assert_eq!(problem, Problem::TooMany { what: "links", limit: MAX_JOINTS + 1 });
    assert!(problem.to_string().contains("MAX_JOINTS"), "{problem}");
    // Listed joints first, the joint cap is the one met.
    assert_eq!(refusal(&chain_joints_first(20_000)), Problem::TooMany { what: "joints", limit: MAX_JOINTS });
    // At the cap, the chain loads.
    assert_eq!(load_str(&chain_joints_first(MAX_JOINTS), "long.urdf").unwrap().model.dof(), MAX_JOINTS);
}

/// Two revolute joints `j1`, `j2` about z from `base` through `mid` to `tip`; `mid` and `tip` hold
/// the given `<inertial>`s, `j2` sits at `j2_origin` and both have the `<limit>` given.
fn two_joints(mid: &str, j2_origin: &str, limit: &str) -> String {
    format!(
        r#"<robot name="two">
  <link name="base"/>
  <link name="mid">{mid}</link>
  <link name="tip">{INERTIAL}</link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="mid"/><axis xyz="0 0 1"/>{limit}</joint>
  <joint name="j2" type="revolute"><parent link="mid"/><child link="tip"/><origin xyz="{j2_origin}"/><axis xyz="0 0 1"/>{limit}</joint>
</robot>"#
    )
}

const LIMIT: &str = r#"<limit lower="-1" upper="1" effort="10" velocity="1"/>"#;

#[test]
fn coaxial_joints_with_no_mass_between_are_refused() {
    // Each diagonal entry of M is the tip's inertia about z, but M = [[I, I], [I, I]] is singular:
    // `fd` and `plant` failed on it with "mass matrix is not positive definite".
    let problem = refusal(&two_joints("", "0 0 0.1", LIMIT));
    match &problem {
        Problem::NotPositiveDefinite { joint, pivot, diagonal } => {
            assert_eq!(joint, "j2");
            assert!(pivot.abs() < 1e-10 * diagonal, "pivot {pivot} of {diagonal}");
        }
        other => panic!("refused for {other}"),
    }
    let message = problem.to_string();
    assert!(message.contains("`j2`") && message.contains("singular"), "{message}");
    assert!(message.len() < 300, "{message}");
    // Offset sideways, the same joints are fine; so are coaxial ones with a mass between them.
    assert!(load_str(&two_joints("", "0.1 0 0", LIMIT), "offset.urdf").is_ok());
    assert!(load_str(&two_joints(INERTIAL, "0 0 0.1", LIMIT), "massive.urdf").is_ok());
}

#[test]
fn inverted_and_equal_limits_are_refused_naming_joint_and_values() {
    let inverted =
        refusal(&two_joints(INERTIAL, "0.1 0 0", r#"<limit lower="3" upper="-3" effort="10" velocity="1"/>"#));
    assert_eq!(inverted, Problem::InvertedLimits { joint: "j1".into(), lower: 3.0, upper: -3.0 });
    assert!(inverted.to_string().contains("lower limit 3 is above upper limit -3"), "{inverted}");
    let equal =
        refusal(&two_joints(INERTIAL, "0.1 0 0", r#"<limit lower="0.5" upper="0.5" effort="10" velocity="1"/>"#));
    assert_eq!(equal, Problem::EqualLimits { joint: "j1".into(), value: 0.5 });
    assert!(equal.to_string().contains("`j1`") && equal.to_string().contains("0.5"), "{equal}");
    // Zero for both, what an omitted `lower` and `upper` read as, means no position limits.
    let unlimited = r#"<limit effort="10" velocity="1"/>"#;
    let loaded = load_str(&two_joints(INERTIAL, "0.1 0 0", unlimited), "unlimited.urdf").unwrap();
    let limits = &loaded.model.bodies()[0].limits;
    assert_eq!((limits.lower, limits.upper, limits.effort), (None, None, Some(10.0)));
    // A continuous joint's limits are ignored, whatever they say.
    let continuous = two_joints(INERTIAL, "0.1 0 0", r#"<limit lower="3" upper="-3" effort="10" velocity="1"/>"#)
        .replace("type=\"revolute\"", "type=\"continuous\"");
    assert!(load_str(&continuous, "continuous.urdf").is_ok());
}

#[test]
fn empty_names_are_refused() {
    let valid = two_joints(INERTIAL, "0.1 0 0", LIMIT);
    let robot = valid.replace("<robot name=\"two\">", "<robot name=\"\">");
    assert_eq!(refusal(&robot), Problem::EmptyName { element: "the robot".into() });
    let link = valid.replace("\"mid\"", "\"\"");
    assert_eq!(refusal(&link), Problem::EmptyName { element: "link number 2 in the file".into() });
    let joint = valid.replace("name=\"j2\"", "name=\"\"");
    let problem = refusal(&joint);
    assert_eq!(problem, Problem::EmptyName { element: "joint number 2 in the file (from `mid` to `tip`)".into() });
    assert!(problem.to_string().ends_with("has an empty name"), "{problem}");
}

#[test]
fn absurd_numbers_make_short_messages() {
    let text = two_joints(&INERTIAL.replace("value=\"1\"", "value=\"-1e300\""), "0.1 0 0", LIMIT);
    let message = refusal(&text).to_string();
    assert!(message.contains("-1e300") && message.len() < 100, "{message}");
}

#[test]
fn names_in_messages_are_escaped() {
    // `&#10;` is a newline once parsed: printed raw, it would forge a line of the message.
    let text = two_joints(&INERTIAL.replace("value=\"1\"", "value=\"-2\""), "0.1 0 0", LIMIT)
        .replace("\"mid\"", "\"mid&#10;hya: forged\"");
    let message = refusal(&text).to_string();
    assert!(!message.contains('\n'), "{message:?}");
    assert!(message.contains(r"`mid\nhya: forged`: negative mass -2 kg"), "{message}");
    assert_eq!(hya_urdf::escape_name("a\nb\u{202E}"), r"a\nb\u{202e}");
}
