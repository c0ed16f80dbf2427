//! Hostile descriptions (issue 18): text built to exhaust the stack or memory, and models that
//! parse but cannot be simulated, are refused with a message naming the limit or the fault.
#![allow(clippy::unwrap_used)] // test helpers: a failed unwrap is a failed test

use hya_urdf::{load_file, load_str, Problem, MAX_FILE_BYTES, MAX_JOINTS, MAX_XML_DEPTH, MAX_XML_NODES};

/// The refusal of `text`, which must not load.
fn refusal(text: &str) -> Problem {
    load_str(text, "hostile.urdf").err().expect("the description is refused").problem
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
    let axis = if i % 2 == 0 { "0 1 0" } else { "0 0 1" };
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
fn an_endless_device_is_read_only_up_to_the_limit() {
    // `/dev/zero` claims 0 bytes and never ends.
    let error = load_file("/dev/zero").unwrap_err();
    assert_eq!(error.problem, Problem::TooLarge { size: None, limit: MAX_FILE_BYTES });
    assert!(error.to_string().contains("/dev/zero"), "{error}");
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
