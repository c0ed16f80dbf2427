//! `hya robots`, `hya id [--derivatives]`, `hya fd [--derivatives]`, `hya mass`, `hya gravity`:
//! rigid-body dynamics from the shell.

use std::io::{BufRead, Write};

use hya_core::model::TreeModel;
use hya_core::SliceDynamics;
use hya_robots::{RobotInfo, ROBOTS};

use crate::table::names::{Joints, Unit};
use crate::table::{Column, ColumnsArg, HeaderArg, RowWriter, Table};
use crate::CliError;

/// Which robot, and through which path.
#[derive(Debug, clap::Args)]
pub struct RobotArgs {
    /// A shipped robot's name (see `hya robots`) or the path of a URDF file.
    #[arg(long)]
    robot: String,
    /// With a shipped robot: use the generic tree model instead of the generated code.
    #[arg(long)]
    generic: bool,
    #[command(flatten)]
    columns: ColumnsArg,
    #[command(flatten)]
    header: HeaderArg,
}

/// Parameters of `hya id`.
#[derive(Debug, clap::Args)]
pub struct IdArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Print after `τ` its derivatives `∂τ/∂q` and `∂τ/∂q̇`, each row-major (row i is ∂τ_i),
    /// all on one line.
    #[arg(long)]
    derivatives: bool,
}

impl IdArgs {
    /// What `hya id` computes, and for which robot.
    pub fn quantity(&self) -> (Quantity, &RobotArgs) {
        let quantity = if self.derivatives { Quantity::Derivatives } else { Quantity::InverseDynamics };
        (quantity, &self.robot)
    }
}

/// Parameters of `hya fd`.
#[derive(Debug, clap::Args)]
pub struct FdArgs {
    #[command(flatten)]
    robot: RobotArgs,
    /// Print instead of `q̈` its derivatives `∂q̈/∂q`, `∂q̈/∂q̇` and `M⁻¹` (= `∂q̈/∂τ`), each
    /// row-major (row i is ∂q̈_i), all on one line.
    #[arg(long)]
    derivatives: bool,
}

impl FdArgs {
    /// What `hya fd` computes, and for which robot.
    pub fn quantity(&self) -> (Quantity, &RobotArgs) {
        let quantity = if self.derivatives { Quantity::FdDerivatives } else { Quantity::ForwardDynamics };
        (quantity, &self.robot)
    }
}

/// Parameters of `hya robots`.
#[derive(Debug, clap::Args)]
pub struct RobotsArgs {
    /// Describe this URDF file instead of the shipped robots.
    #[arg(long)]
    urdf: Option<String>,
    /// A JSON array of `{"name", "dof", "joints"}` (names as the file has them, JSON-escaped)
    /// instead of one line per robot.
    #[arg(long)]
    json: bool,
}

/// The dynamics a command runs on.
enum Source {
    Generated(&'static RobotInfo),
    Model(TreeModel),
}

impl Source {
    fn dynamics(&self) -> &dyn SliceDynamics {
        match self {
            Source::Generated(robot) => robot.generated,
            Source::Model(model) => model,
        }
    }
}

/// The dynamics of `args`, and the model's joints (for the columns' names and units).
fn resolve(args: &RobotArgs) -> Result<(Source, Joints), CliError> {
    let model = crate::common::model(&args.robot)?;
    let joints = Joints::of(&model);
    match hya_robots::find(&args.robot) {
        Some(robot) if !args.generic => Ok((Source::Generated(robot), joints)),
        _ => Ok((Source::Model(model), joints)),
    }
}

/// `hya robots`: name, degrees of freedom and joint names in order, one robot per line.
pub fn list(args: &RobotsArgs, output: &mut impl Write) -> Result<(), CliError> {
    let model = args.urdf.as_deref().map(crate::common::load).transpose()?;
    let robots: Vec<(String, usize, Vec<String>)> = match &model {
        Some(model) => vec![(model.name().to_owned(), model.dof(), model.joint_names().map(String::from).collect())],
        None => ROBOTS
            .iter()
            .map(|r| (r.name.to_owned(), r.dof, r.joint_names.iter().map(|j| j.to_string()).collect()))
            .collect(),
    };
    if args.json {
        let rows: Vec<serde_json::Value> = robots
            .iter()
            .map(|(name, dof, joints)| serde_json::json!({ "name": name, "dof": dof, "joints": joints }))
            .collect();
        let text = serde_json::to_string_pretty(&rows).map_err(|e| CliError::Input(e.to_string()))?;
        writeln!(output, "{text}")?;
        return Ok(());
    }
    for (name, dof, joints) in robots {
        // Names come from the file: escaped, so that none can break the line.
        let joints: Vec<String> = joints.iter().map(|j| hya_urdf::escape_name(j)).collect();
        writeln!(output, "{} {dof} {}", hya_urdf::escape_name(&name), joints.join(" "))?;
    }
    Ok(())
}

/// What a dynamics command computes from one input row.
#[derive(Debug, Clone, Copy)]
pub enum Quantity {
    /// Rows `q qd qdd` to `τ`.
    InverseDynamics,
    /// Rows `q` to `M`, row-major.
    MassMatrix,
    /// Rows `q` to `G`.
    Gravity,
    /// Rows `q qd τ` to `q̈`.
    ForwardDynamics,
    /// Rows `q qd qdd` to `τ`, `∂τ/∂q`, `∂τ/∂q̇`.
    Derivatives,
    /// Rows `q qd τ` to `∂q̈/∂q`, `∂q̈/∂q̇`, `M⁻¹`.
    FdDerivatives,
}

impl Quantity {
    /// The columns a row in holds, and what they are for the messages.
    fn input(self, joints: &Joints) -> (Vec<Column>, &'static str) {
        let q = joints.columns("q", Unit::Position);
        let qd = joints.columns("qd", Unit::Velocity);
        match self {
            Self::InverseDynamics | Self::Derivatives => {
                ([q, qd, joints.columns("qdd", Unit::Acceleration)].concat(), "q, qd, qdd: one per joint each")
            }
            Self::ForwardDynamics | Self::FdDerivatives => {
                ([q, qd, joints.columns("tau", Unit::Effort)].concat(), "q, qd, tau: one per joint each")
            }
            Self::MassMatrix | Self::Gravity => (q, "q: one per joint"),
        }
    }

    /// The columns a row out holds: `τ`, `q̈`, `G` per joint, `M` or `∂τ` per pair of joints
    /// (row-major), each in the units of its joints (`∂τ_i/∂q_j` in N m/rad for two revolute
    /// joints).
    fn output(self, joints: &Joints) -> Vec<Column> {
        let effort = |i| Unit::Effort.of(i);
        let position = |j| Unit::Position.of(j);
        let acceleration = |i| Unit::Acceleration.of(i);
        match self {
            Self::InverseDynamics => joints.columns("tau", Unit::Effort),
            Self::Gravity => joints.columns("g", Unit::Effort),
            Self::ForwardDynamics => joints.columns("qdd", Unit::Acceleration),
            Self::MassMatrix => joints.pairs("M", |i, j| format!("{} s^2/{}", effort(i), position(j))),
            Self::Derivatives => [
                joints.columns("tau", Unit::Effort),
                joints.pairs("dtau_dq", |i, j| format!("{}/{}", effort(i), position(j))),
                joints.pairs("dtau_dqd", |i, j| format!("{} s/{}", effort(i), position(j))),
            ]
            .concat(),
            Self::FdDerivatives => [
                joints.pairs("dqdd_dq", |i, j| format!("{}/{}", acceleration(i), position(j))),
                joints.pairs("dqdd_dqd", |i, j| format!("{} s/{}", acceleration(i), position(j))),
                joints.pairs("Minv", |i, j| format!("{}/({})", acceleration(i), effort(j))),
            ]
            .concat(),
        }
    }
}

/// Runs `quantity` over every row of `input`.
pub fn run(quantity: Quantity, args: &RobotArgs, input: impl BufRead, output: &mut impl Write) -> Result<(), CliError> {
    let (source, joints) = resolve(args)?;
    let dynamics = source.dynamics();
    let n = dynamics.dof();
    let (wanted, what) = quantity.input(&joints);
    let table = Table::new(input, args.columns.spec()?, wanted, what.to_string())?;
    let writer = RowWriter::new(output, quantity.output(&joints), args.header.header());
    let width = match quantity {
        Quantity::MassMatrix => n * n,
        Quantity::Derivatives => n + 2 * n * n,
        Quantity::FdDerivatives => 3 * n * n,
        _ => n,
    };
    each_row(table, writer, width, |v, result| {
        let (a, b, c) = (&v[..n.min(v.len())], v.get(n..2 * n).unwrap_or(&[]), v.get(2 * n..).unwrap_or(&[]));
        match quantity {
            Quantity::InverseDynamics => dynamics.inverse_dynamics_into(a, b, c, result),
            Quantity::MassMatrix => dynamics.mass_matrix_into(v, result),
            Quantity::Gravity => dynamics.gravity_into(v, result),
            Quantity::ForwardDynamics => dynamics.forward_dynamics_into(a, b, c, result).map_err(|e| e.to_string())?,
            Quantity::Derivatives => {
                let (tau, rest) = result.split_at_mut(n);
                let (by_q, by_qd) = rest.split_at_mut(n * n);
                dynamics.inverse_dynamics_into(a, b, c, tau);
                dynamics.inverse_dynamics_derivatives_into(a, b, c, by_q, by_qd);
            }
            Quantity::FdDerivatives => {
                let (by_q, rest) = result.split_at_mut(n * n);
                let (by_qd, inverse) = rest.split_at_mut(n * n);
                dynamics
                    .forward_dynamics_derivatives_into(a, b, c, [by_q, by_qd, inverse])
                    .map_err(|e| e.to_string())?
            }
        }
        Ok(())
    })
}

/// Writes, for every row of `table`, the `width` values `compute` makes of its values; an error
/// names the line (`compute`'s own, or a value that is not finite).
pub(crate) fn each_row(
    mut table: Table<impl BufRead>,
    mut writer: RowWriter<impl Write>,
    width: usize,
    mut compute: impl FnMut(&[f64], &mut [f64]) -> Result<(), String>,
) -> Result<(), CliError> {
    let mut result = vec![0.0; width];
    while let Some(line) = table.next_line() {
        let line = line?;
        compute(table.values(), &mut result).map_err(|e| CliError::Input(format!("line {line}: {e}")))?;
        if let Some(j) = result.iter().position(|v| !v.is_finite()) {
            return Err(CliError::Input(format!(
                "line {line}: the result overflows (entry {} is {}): the inputs are beyond what the model can evaluate",
                j + 1,
                result[j]
            )));
        }
        writer.write(result.iter().copied())?;
    }
    Ok(())
}
