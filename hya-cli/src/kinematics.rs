//! `hya jacobian [--frame LINK] [--bias]`: a frame's geometric Jacobian, or `J̇ q̇`, from the
//! shell, world-aligned (the frame's origin, the base's axes: Pinocchio's
//! `LOCAL_WORLD_ALIGNED`), from the run-time kinematic tree of the model.

use std::io::{BufRead, Write};

use hya_core::model::{JointKind, TreeModel};

use crate::rigid_body::each_row;
use crate::table::names::{Column, Joints, Unit};
use crate::table::{ColumnsArg, HeaderArg, RowWriter, Table};
use crate::CliError;

/// Parameters of `hya jacobian`.
#[derive(Debug, clap::Args)]
pub struct JacobianArgs {
    /// A shipped robot's name (see `hya robots`) or the path of a URDF file.
    #[arg(long)]
    robot: String,
    /// The frame: any link of the URDF, one behind a fixed joint included (default: the model's
    /// last link).
    #[arg(long)]
    frame: Option<String>,
    /// Read rows `q q̇` and print `J̇ q̇` instead: the classical acceleration of the frame's
    /// origin (3 values, m/s²) and its angular acceleration (3, rad/s²) at `q̈ = 0`.
    #[arg(long)]
    bias: bool,
    #[command(flatten)]
    columns: ColumnsArg,
    #[command(flatten)]
    header: HeaderArg,
}

/// The linear then angular axes of a world-aligned twist.
const AXES: [&str; 6] = ["vx", "vy", "vz", "wx", "wy", "wz"];

/// `frame`, checked by the model (whose error lists its frames), or its last one.
fn frame_of(model: &TreeModel, frame: Option<&str>) -> Result<String, CliError> {
    match frame {
        Some(frame) => model
            .frame(frame)
            .map(|f| f.name.clone())
            .map_err(|e| CliError::Input(format!("--frame {}: {e}", hya_urdf::escape_name(frame)))),
        None => model
            .frames()
            .last()
            .map(|f| f.name.clone())
            .ok_or_else(|| CliError::Input(format!("{} has no links", model.name()))),
    }
}

/// The columns out: `J_AXIS_JOINT` row-major (6 × n), or the six of `J̇ q̇`.
fn output(joints: &Joints, model: &TreeModel, bias: bool) -> Vec<Column> {
    if bias {
        return AXES
            .iter()
            .enumerate()
            .map(|(k, axis)| Column::new(format!("dJ_qd_{axis}"), if k < 3 { "m/s^2" } else { "rad/s^2" }))
            .collect();
    }
    let mut columns = Vec::with_capacity(6 * joints.len());
    for (k, axis) in AXES.iter().enumerate() {
        for body in model.bodies() {
            let rate = if k < 3 { "m" } else { "rad" };
            let per = if body.kind == JointKind::Revolute { "rad" } else { "m" };
            columns.push(Column::new(format!("J_{axis}_{}", body.joint), format!("{rate}/{per}")));
        }
    }
    columns
}

/// `hya jacobian`: rows `q` to rows `J` (6 × n, row-major), or rows `q q̇` to rows `J̇ q̇`.
pub fn run(args: &JacobianArgs, input: impl BufRead, output_to: &mut impl Write) -> Result<(), CliError> {
    let model = crate::common::model(&args.robot)?;
    let frame = frame_of(&model, args.frame.as_deref())?;
    let joints = Joints::of(&model);
    let n = model.dof();
    let q = joints.columns("q", Unit::Position);
    let (wanted, what) = if args.bias {
        ([q, joints.columns("qd", Unit::Velocity)].concat(), "q, qd: one per joint each")
    } else {
        (q, "q: one per joint")
    };
    let table = Table::new(input, args.columns.spec()?, wanted, what.to_string())?;
    let writer = RowWriter::new(output_to, output(&joints, &model, args.bias), args.header.header());
    let width = if args.bias { 6 } else { 6 * n };
    each_row(table, writer, width, |v, out| {
        if args.bias {
            out.copy_from_slice(&model.frame_acceleration_bias(&frame, &v[..n], &v[n..]).map_err(|e| e.to_string())?);
        } else {
            // Row-major: the transpose's column-major storage.
            let jacobian = model.frame_jacobian(&frame, v).map_err(|e| e.to_string())?;
            out.copy_from_slice(jacobian.transpose().as_slice());
        }
        Ok(())
    })
}
