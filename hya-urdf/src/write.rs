//! Writing a URDF back with new inertias: identified parameters in a file every hya command
//! (and every other URDF tool) loads.
//!
//! Each listed link's `<inertial>` becomes the given spatial inertia (about the link frame's
//! origin), written as URDF wants it: mass, the centre of mass as the inertial origin (no
//! rotation) and the rotational inertia about the centre of mass, `Ī = I − m (|c|² 1 − c cᵀ)`.
//! Everything else comes through `urdf-rs`'s writer unchanged in meaning (comments and
//! formatting are not kept).

use hya_core::model::TreeModel;
use hya_core::spatial::RigidBodyInertia;
use urdf_rs::{Inertia, Inertial, Mass, Pose, Vec3};

use crate::error::{LoadError, Problem};
use crate::limits::check_text;

/// The URDF `text` (from `source`, for messages) with the inertials of the links named in
/// `inertias` replaced. A massless inertia is written as mass 0 with zero inertia.
pub fn with_inertias(text: &str, source: &str, inertias: &[(&str, RigidBodyInertia)]) -> Result<String, LoadError> {
    check_text(text).map_err(|problem| LoadError::new(source, problem))?;
    let parse = |message: String| LoadError::new(source, Problem::Parse { message });
    let mut robot = urdf_rs::read_from_string(text).map_err(|e| parse(e.to_string()))?;
    for (name, inertia) in inertias {
        let link =
            robot.links.iter_mut().find(|l| l.name == *name).ok_or_else(|| {
                parse(format!("no link named `{}` to write an inertia into", crate::escape_name(name)))
            })?;
        link.inertial = urdf_inertial(inertia);
    }
    urdf_rs::write_to_string(&robot).map_err(|e| parse(format!("cannot write the URDF back: {e}")))
}

/// The URDF `text` of `model` (from `source`) with body `b`'s inertia `inertias[b]` on the link
/// of its joint, and the links merged into a body by fixed joints made massless (their mass is
/// in the body's); checked by loading it back as `file`, whose bodies must have those inertias.
pub fn with_body_inertias(
    text: &str,
    source: &str,
    model: &TreeModel,
    inertias: &[RigidBodyInertia],
    file: &str,
) -> Result<String, LoadError> {
    let mut links: Vec<(&str, RigidBodyInertia)> =
        model.bodies().iter().zip(inertias).map(|(body, inertia)| (body.link.as_str(), *inertia)).collect();
    for frame in model.frames() {
        if frame.body.is_some_and(|b| model.bodies()[b].link != frame.name) {
            links.push((frame.name.as_str(), RigidBodyInertia::zero()));
        }
    }
    let written_text = with_inertias(text, source, &links)?;
    let written = crate::load_str(&written_text, file)?.model;
    for (body, want) in written.bodies().iter().zip(inertias) {
        let got = &body.inertia;
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + b.abs());
        let same = close(got.mass, want.mass)
            && (0..3).all(|k| close(got.first_moment[k], want.first_moment[k]))
            && (0..9).all(|k| close(got.rotational[k], want.rotational[k]));
        if !same {
            let message = format!(
                "would not reproduce body `{}`'s inertia (a bug: please report it)",
                crate::escape_name(&body.link)
            );
            return Err(LoadError::new(file, Problem::Model { message }));
        }
    }
    Ok(written_text)
}

fn urdf_inertial(inertia: &RigidBodyInertia) -> Inertial {
    let Some((mass, com, about_com)) = inertia.centre_of_mass_form() else {
        return Inertial { origin: Pose::default(), mass: Mass { value: 0.0 }, inertia: Inertia::default() };
    };
    Inertial {
        origin: Pose { xyz: Vec3([com.x, com.y, com.z]), rpy: Vec3([0.0; 3]) },
        mass: Mass { value: mass },
        inertia: Inertia {
            ixx: about_com[(0, 0)],
            ixy: about_com[(0, 1)],
            ixz: about_com[(0, 2)],
            iyy: about_com[(1, 1)],
            iyz: about_com[(1, 2)],
            izz: about_com[(2, 2)],
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load_str;
    use nalgebra::{Matrix3, Vector3};

    const ARM: &str = r#"<robot name="arm">
      <link name="base"/>
      <link name="upper"><inertial><origin xyz="0.1 0 0"/><mass value="2"/>
        <inertia ixx="0.01" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="tool"><inertial><mass value="0.5"/>
        <inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
        <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
      <joint name="flange" type="fixed"><parent link="upper"/><child link="tool"/>
        <origin xyz="0.3 0 0"/></joint>
    </robot>"#;

    #[test]
    fn written_inertias_load_back_and_the_rest_is_kept() {
        let new = RigidBodyInertia::from_centre_of_mass(
            3.0,
            Vector3::new(0.12, 0.01, -0.02),
            Matrix3::new(0.02, 0.001, 0.0, 0.001, 0.03, 0.002, 0.0, 0.002, 0.025),
        );
        let massless = RigidBodyInertia::zero();
        let text = with_inertias(ARM, "arm.urdf", &[("upper", new), ("tool", massless)]).unwrap();
        let model = load_str(&text, "written").unwrap().model;
        let body = &model.bodies()[0];
        assert!((body.inertia.mass - 3.0).abs() < 1e-12);
        assert!((body.inertia.first_moment - new.first_moment).norm() < 1e-12);
        assert!((body.inertia.rotational - new.rotational).norm() < 1e-12);
        assert_eq!(body.joint, "shoulder");
        assert_eq!((body.limits.lower, body.limits.upper, body.limits.velocity), (Some(-1.0), Some(1.0), Some(2.0)));
        assert!(model.frames().iter().any(|f| f.name == "tool"), "the fixed link is kept as a frame");
    }

    #[test]
    fn an_unknown_link_is_named() {
        let message = with_inertias(ARM, "arm.urdf", &[("elbow", RigidBodyInertia::zero())]).unwrap_err().to_string();
        assert!(message.contains("arm.urdf") && message.contains("`elbow`"), "{message}");
    }
}
