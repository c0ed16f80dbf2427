//! `hya excite`: rows `t q q̇ q̈` of a trajectory that starts and ends at rest, with the
//! regressor's rank and conditioning on stderr; joints without limits refused by name.

mod common;

use common::{assert_rejected, hya};

#[test]
fn excite_prints_one_period_from_rest_to_rest() {
    let output = hya(&["excite", "--robot", "planar2", "--candidates", "3", "--rate-hz", "20"], "");
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let summary = String::from_utf8_lossy(&output.stderr);
    // A planar two-link arm with gravity in its plane has six base parameters.
    assert!(summary.contains("rank 6 of 20 parameters"), "{summary}");
    let text = String::from_utf8(output.stdout).unwrap_or_default();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("# t q_shoulder q_elbow qd_shoulder qd_elbow qdd_shoulder qdd_elbow"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(' ').map(|v| v.parse().unwrap_or(f64::NAN)).collect()).collect();
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
