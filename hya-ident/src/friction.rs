//! Identified joint friction, one type for the fit that finds it, the file that holds it
//! (`friction.toml`, written by `hya identify`) and everything that reads it back (the
//! estimator, the controller, the simulator). Per joint
//!
//! ```text
//! τ_f = coulomb_nm · tanh(q̇ / smoothing_rad_s) + viscous_nm_s · q̇ + offset_nm  (+ armature_kg_m2 · q̈)
//! ```
//!
//! the torque the joint needs beyond the rigid body (`τ = ID(q, q̇, q̈) + τ_f`), so the part of
//! the disturbance `d = ID − τ` that the friction does not explain is `d + τ_f`. The optional
//! `armature_kg_m2` is the motor's inertia reflected through the gear, `I_a q̈`, which no URDF
//! link carries (an industrial arm's torque from motor currents holds it); a file without it
//! has none.
//!
//! It lives here, beside the fit, rather than in hya-core: the file format needs serde and toml,
//! which hya-core (no_std, for the control loop on a microcontroller) does not take.

use std::path::Path;

use hya_core::Short;
use serde::Deserialize;

/// The largest `friction.toml` read, bytes: a few numbers per joint.
pub const MAX_FRICTION_BYTES: u64 = 64 * 1024;

/// The plausible range of each key of a friction file, `(key, low, high, unit)`, as a
/// scenario's friction keys have theirs. Coulomb and viscous
/// terms may fall a little below zero, as an unconstrained fit of a joint with little friction
/// can; far below, they would feed energy into the loop (−500 N·m·s/rad is refused).
pub const PLAUSIBLE_FRICTION: [(&str, f64, f64, &str); 5] = [
    ("smoothing_rad_s", 1e-6, 10.0, "rad/s"),
    ("coulomb_nm", -100.0, 1e4, "N·m"),
    ("viscous_nm_s", -100.0, 1e4, "N·m·s/rad"),
    ("offset_nm", -1e4, 1e4, "N·m"),
    ("armature_kg_m2", 0.0, 1e3, "kg·m²"),
];

/// Identified joint friction (see the module's notes).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointFriction {
    /// `s`, rad/s.
    pub smoothing_rad_s: f64,
    /// Coulomb levels, N·m, per joint.
    pub coulomb_nm: Vec<f64>,
    /// Viscous coefficients, N·m·s/rad, per joint.
    pub viscous_nm_s: Vec<f64>,
    /// Constant offsets, N·m, per joint.
    pub offset_nm: Vec<f64>,
    /// Reflected motor inertias `I_a`, kg·m², per joint; empty for none.
    #[serde(default)]
    pub armature_kg_m2: Vec<f64>,
}

impl JointFriction {
    /// Reads and checks `path` for an arm of `joints` joints; the error names the file, the key
    /// and the value.
    pub fn from_file(path: &Path, joints: usize) -> Result<Self, String> {
        let origin = path.display();
        let text = hya_urdf::file::read_text(path, MAX_FRICTION_BYTES).map_err(|e| format!("{origin}: {e}"))?;
        Self::from_toml(&text, joints).map_err(|e| format!("{origin}: {e}"))
    }

    /// Parses and checks `text` for an arm of `joints` joints: every value within its
    /// [`PLAUSIBLE_FRICTION`] range. A syntax error names its line and column.
    pub fn from_toml(text: &str, joints: usize) -> Result<Self, String> {
        let friction: Self = toml::from_str(text).map_err(|e| e.to_string().trim_end().to_owned())?;
        for (key, values) in [
            ("smoothing_rad_s", std::slice::from_ref(&friction.smoothing_rad_s)),
            ("coulomb_nm", &friction.coulomb_nm),
            ("viscous_nm_s", &friction.viscous_nm_s),
            ("offset_nm", &friction.offset_nm),
            ("armature_kg_m2", &friction.armature_kg_m2),
        ] {
            let optional = key == "armature_kg_m2" && values.is_empty();
            if key != "smoothing_rad_s" && !optional && values.len() != joints {
                return Err(format!("{key}: {} values for an arm of {joints} joints", values.len()));
            }
            let (lo, hi, unit) = PLAUSIBLE_FRICTION
                .iter()
                .find(|(k, ..)| *k == key)
                .map(|&(_, lo, hi, unit)| (lo, hi, unit))
                .unwrap_or((f64::NEG_INFINITY, f64::INFINITY, ""));
            if let Some(i) = values.iter().position(|v| !(v.is_finite() && (lo..=hi).contains(v))) {
                let index = if key == "smoothing_rad_s" { String::new() } else { format!("[{i}]") };
                return Err(format!(
                    "{key}{index} = {}: must be finite, between {} and {} {unit} (a unit mistake, or a fit gone wrong?)",
                    Short(values[i]),
                    Short(lo),
                    Short(hi)
                ));
            }
        }
        Ok(friction)
    }

    /// Joint `i`'s friction torque at velocity `qd`, N·m.
    pub fn torque(&self, i: usize, qd: f64) -> f64 {
        self.coulomb_nm[i] * (qd / self.smoothing_rad_s).tanh() + self.viscous_nm_s[i] * qd + self.offset_nm[i]
    }

    /// Joint `i`'s armature `I_a`, kg·m² (0 without one).
    pub fn armature(&self, i: usize) -> f64 {
        self.armature_kg_m2.get(i).copied().unwrap_or(0.0)
    }

    /// Joint `i`'s whole torque beyond the rigid body at velocity `qd` and acceleration `qdd`:
    /// the friction and the armature's `I_a q̈`, N·m.
    pub fn joint_torque(&self, i: usize, qd: f64, qdd: f64) -> f64 {
        self.torque(i, qd) + self.armature(i) * qdd
    }

    /// Whether any joint has an armature.
    pub fn has_armature(&self) -> bool {
        self.armature_kg_m2.iter().any(|a| *a != 0.0)
    }

    /// The file [`from_toml`](Self::from_toml) reads: the law and the `joints`' names as
    /// comments, each per-joint list, and under it its standard deviations (`std[i]` in the order
    /// `c`, `v`, `o` and, with an armature, `I_a` of joint `i`) where given. Values with six
    /// decimals; the armature's list only if the friction has one.
    pub fn to_toml(&self, joints: &[&str], std: Option<&[Vec<f64>]>) -> String {
        let list =
            |values: &mut dyn Iterator<Item = f64>| values.map(|v| format!("{v:.6}")).collect::<Vec<_>>().join(", ");
        let mut text = format!(
            "# Joint friction identified by hya identify: the torque each joint needs beyond the rigid\n\
             # body, tau_f = coulomb_nm * tanh(qd / smoothing_rad_s) + viscous_nm_s * qd + offset_nm.\n\
             # Joints: {}\n\
             smoothing_rad_s = {}\n",
            hya_urdf::name_list(joints.iter().copied()),
            self.smoothing_rad_s
        );
        let lists = [
            ("coulomb_nm", &self.coulomb_nm),
            ("viscous_nm_s", &self.viscous_nm_s),
            ("offset_nm", &self.offset_nm),
            ("armature_kg_m2", &self.armature_kg_m2),
        ];
        for (k, (key, values)) in lists.into_iter().enumerate().filter(|(_, (_, v))| !v.is_empty()) {
            text += &format!("{key} = [{}]\n", list(&mut values.iter().copied()));
            if let Some(std) = std.filter(|s| s.iter().all(|s| s.len() > k)) {
                text += &format!("# standard deviations: [{}]\n", list(&mut std.iter().map(|s| s[k])));
            }
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO_JOINTS: &str = "smoothing_rad_s = 0.05\ncoulomb_nm = [1.5, 0.8]\n# a comment\n\
                              viscous_nm_s = [0.6, 0.3]\noffset_nm = [0.1, -0.2]\n";

    /// The shared corpus of refused friction files (`tests/friction/refused/`, for a 2-joint
    /// arm; each file's first line `# expect: a | b` lists words its message must hold), which
    /// the CLI, the C ABI and Python are each held to as well.
    #[test]
    fn the_refused_corpus_is_refused_naming_the_file_and_the_problem() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/friction/refused");
        let mut files = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let text = std::fs::read_to_string(&path).unwrap();
            let expect = text.lines().next().and_then(|l| l.strip_prefix("# expect: ")).unwrap();
            let message = JointFriction::from_file(&path, 2).expect_err(&path.display().to_string());
            let file = path.file_name().unwrap().to_str().unwrap();
            for word in std::iter::once(file).chain(expect.split(" | ")) {
                assert!(message.contains(word), "{file}: `{message}` does not mention `{word}`");
            }
            files += 1;
        }
        assert!(files >= 9, "the corpus in {} was not found", dir.display());
    }

    #[test]
    fn what_it_writes_reads_back() {
        let f = JointFriction::from_toml(TWO_JOINTS, 2).unwrap();
        // A joint name cannot forge a line of the file.
        let text =
            f.to_toml(&["shoulder", "elbow\nsmoothing_rad_s = 9"], Some(&[vec![0.1, 0.2, 0.3], vec![0.4, 0.5, 0.6]]));
        assert_eq!(JointFriction::from_toml(&text, 2).unwrap(), f);
        assert!(text.contains("# standard deviations: [0.200000, 0.500000]"), "{text}");
        assert_eq!(text.lines().filter(|l| l.starts_with("smoothing_rad_s")).count(), 1, "{text}");
    }

    #[test]
    fn an_armature_is_written_read_and_adds_its_inertia() {
        let mut f = JointFriction::from_toml(TWO_JOINTS, 2).unwrap();
        assert!(!f.has_armature() && f.armature(1) == 0.0);
        f.armature_kg_m2 = vec![0.25, 0.0];
        let text = f.to_toml(&["a", "b"], Some(&[vec![0.1, 0.2, 0.3, 0.01], vec![0.4, 0.5, 0.6, 0.02]]));
        assert!(text.contains("armature_kg_m2 = [0.250000, 0.000000]"), "{text}");
        assert!(text.contains("# standard deviations: [0.010000, 0.020000]"), "{text}");
        assert_eq!(JointFriction::from_toml(&text, 2).unwrap(), f);
        assert_eq!(f.joint_torque(0, 0.0, 2.0), f.torque(0, 0.0) + 0.5);
        let short = format!("{TWO_JOINTS}armature_kg_m2 = [0.1]\n");
        assert!(JointFriction::from_toml(&short, 2).unwrap_err().contains("armature_kg_m2: 1 values"));
    }

    #[test]
    fn reads_what_identify_writes_and_evaluates_the_law() {
        let f = JointFriction::from_toml(TWO_JOINTS, 2).unwrap();
        let want = 1.5 * (0.1f64 / 0.05).tanh() + 0.6 * 0.1 + 0.1;
        assert_eq!(f.torque(0, 0.1), want);
        assert_eq!(f.torque(1, 0.0), -0.2);
    }

    #[test]
    fn refuses_files_that_do_not_fit_the_arm_by_key() {
        let error = |text: &str, joints| JointFriction::from_toml(text, joints).unwrap_err();
        assert!(error(TWO_JOINTS, 3).contains("coulomb_nm: 2 values for an arm of 3 joints"));
        assert!(error(&TWO_JOINTS.replace("0.05", "0"), 2).contains("smoothing_rad_s = 0"));
        assert!(error(&TWO_JOINTS.replace("0.6", "nan"), 2).contains("viscous_nm_s[0] = NaN"));
        assert!(error(&format!("{TWO_JOINTS}stribeck = 1\n"), 2).contains("stribeck"));
    }

    #[test]
    fn refuses_implausible_values_and_names_the_line_of_a_syntax_error() {
        let error = |text: &str| JointFriction::from_toml(text, 2).unwrap_err();
        for (from, to, expected) in [
            ("1.5", "1e300", "coulomb_nm[0] = 1e300: must be finite, between -100 and 10000 N·m"),
            ("0.6", "-500", "viscous_nm_s[0] = -500"),
            ("-0.2", "1e6", "offset_nm[1] = 1e6"),
            ("0.05", "1e-300", "smoothing_rad_s = 1e-300"),
        ] {
            let message = error(&TWO_JOINTS.replacen(from, to, 1));
            assert!(message.contains(expected), "{message}");
        }
        // A small negative term, as a fit of a joint with little friction gives, is read.
        assert!(JointFriction::from_toml(&TWO_JOINTS.replace("0.3]", "-0.01]"), 2).is_ok());
        let message = error(&TWO_JOINTS.replace("coulomb_nm = [1.5", "coulomb_nm = [1.5 x"));
        assert!(message.contains("line 2"), "{message}");
    }
}
