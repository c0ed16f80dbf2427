//! `hya excite`: rows `t q q̇ q̈` of a trajectory that starts and ends at rest, with the
//! regressor's rank and conditioning on stderr; joints without limits refused by name.

use crate::common::{assert_rejected, hya};

#[test]
fn excite_prints_one_period_from_rest_to_rest() {
    let output = hya(&["excite", "--robot", "planar2", "--candidates", "3", "--rate-hz", "20"], "");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let summary = String::from_utf8_lossy(&output.stderr);
    // A planar two-link arm with gravity in its plane has six base parameters.
    assert!(summary.contains("rank 6 of 20 parameters"), "{summary}");
    let text = String::from_utf8(output.stdout).unwrap_or_default();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(
            "t [s],q_shoulder [rad],q_elbow [rad],qd_shoulder [rad/s],qd_elbow [rad/s],\
             qdd_shoulder [rad/s^2],qdd_elbow [rad/s^2]"
        )
    );
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().unwrap_or(f64::NAN)).collect()).collect();
    // One period of 10 s at 20 rows per second, both ends included.
    assert_eq!(rows.len(), 201);
    for row in [&rows[0], &rows[200]] {
        assert_eq!(row.len(), 7);
        assert!(row[3..].iter().all(|v| v.abs() < 1e-8), "not at rest: {row:?}");
    }
    assert!((rows[200][0] - 10.0).abs() < 1e-9);
    // Within 80 % of the ±3.14 rad range and half the 5 rad/s velocity limit.
    for row in &rows {
        let limit: f64 = "3.14".parse().unwrap_or_default(); // planar2.urdf: lower="-3.14" upper="3.14"
        assert!(row[1..3].iter().all(|q| q.abs() <= 0.8 * limit + 1e-6), "{row:?}");
        assert!(row[3..5].iter().all(|v| v.abs() <= 0.5 * 5.0 + 1e-6), "{row:?}");
    }
}

#[test]
fn excite_refuses_a_joint_without_limits_and_bad_settings() {
    let dir = std::env::temp_dir().join(format!("hya-excite-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap_or_default();
    let urdf = dir.join("no_limits.urdf");
    std::fs::write(
        &urdf,
        r#"<robot name="x"><link name="a"/><link name="b"><inertial><mass value="1"/>
        <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
        <joint name="spin" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint></robot>"#,
    )
    .unwrap_or_default();
    let path = urdf.to_str().unwrap_or_default();
    assert_rejected(&["excite", "--robot", path], "", &["`spin`", "position limit"]);
    assert_rejected(&["excite", "--robot", "planar2", "--base-hz", "0"], "", &["--base-hz"]);
    assert_rejected(&["excite", "--robot", "planar2", "--velocity-fraction", "2"], "", &["velocity fraction = 2"]);
    assert_rejected(&["excite", "--robot", "planar2", "--harmonics", "0"], "", &["harmonics"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A URDF chain of `n` revolute joints with limits, written to a scratch file.
fn chain_urdf(n: usize) -> std::path::PathBuf {
    let mut text = String::from("<robot name=\"chain\"><link name=\"l0\"/>");
    for k in 1..=n {
        text += &format!(
            "<link name=\"l{k}\"><inertial><mass value=\"1\"/><origin xyz=\"0.1 0 0\"/>\
             <inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\
             <joint name=\"j{k}\" type=\"revolute\"><parent link=\"l{}\"/><child link=\"l{k}\"/>\
             <origin xyz=\"0.2 0 0\"/><axis xyz=\"0 {} {}\"/>\
             <limit lower=\"-1\" upper=\"1\" velocity=\"2\" effort=\"10\"/></joint>",
            k - 1,
            k % 2,
            (k + 1) % 2
        );
    }
    text += "</robot>";
    let path = std::env::temp_dir().join(format!("hya-chain-{n}-{}.urdf", std::process::id()));
    std::fs::write(&path, text).unwrap_or_else(|e| panic!("{e}"));
    path
}

#[test]
fn identification_refuses_arms_beyond_seven_joints_before_allocating() {
    // 400 joints once asked for a 100 GB allocation; 60 ran 12 s and 665 MB before refusing.
    for n in [60, 400] {
        let path = chain_urdf(n);
        let urdf = path.to_str().unwrap_or_default();
        let expected = format!("has {n} joints; identification handles arms of 1 to 7");
        let started = std::time::Instant::now();
        assert_rejected(&["excite", "--robot", urdf], "", &[expected.as_str()]);
        assert_rejected(&["identify", "--robot", urdf, "--dt", "0.001"], "", &[expected.as_str()]);
        assert!(started.elapsed().as_secs_f64() < 20.0, "{n} joints took {:?}", started.elapsed());
        let _ = std::fs::remove_file(path);
    }
    // A million candidates (about 9 ms each on the Panda) is refused, not run for hours.
    assert_rejected(
        &["excite", "--robot", "panda", "--candidates", "1000000"],
        "",
        &["candidates = 1e6", "at most 100000"],
    );
    // Tiny numbers print short, not in 300 digits.
    let output = hya(&["excite", "--robot", "planar2", "--base-hz", "1e-300"], "");
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(message.contains("1e-300") && message.len() < 300, "{message}");
}
