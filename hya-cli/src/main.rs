//! The `hya` command.

use std::io::{self, Write};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub use common::CliError;

mod bench;
mod common;
mod estimate;
mod excite;
mod experiments;
mod filter;
mod generate;
mod identify;
mod kinematics;
mod open_loop;
mod rigid_body;
mod sweep;
mod table;
mod track;

/// The version `--version` prints: the crate's, the commit it was built from, and the profile.
const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("HYA_BUILD_COMMIT"),
    ", ",
    env!("HYA_BUILD_PROFILE"),
    " build)"
);

/// hya: model-based control of robot arms under disturbances.
#[derive(Debug, Parser)]
#[command(name = "hya", version = VERSION, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run the paper's third-order filter over rows of samples read from stdin.
    ///
    /// Each row holds one sample per channel (whitespace- or comma-separated); the first row fixes
    /// the channel count and the initial state (x1 = u0, x2 = x3 = 0). Each output row holds all
    /// channels' x1, then all x2, then all x3.
    #[command(allow_negative_numbers = true)]
    Filter(filter::FilterArgs),
    /// List the shipped robots (or a URDF's model): name, degrees of freedom, joint names.
    Robots(rigid_body::RobotsArgs),
    /// Inverse dynamics: rows `q qd qdd` (one value per joint each) to rows `τ`.
    ///
    /// A shipped robot's name uses its generated code (`--generic`: the runtime tree model); a
    /// URDF path is loaded at run time. Joint order is the model's (see `hya robots`). With
    /// `--derivatives`, each row also holds `∂τ/∂q` and `∂τ/∂q̇`, row-major.
    Id(rigid_body::IdArgs),
    /// Forward dynamics by the articulated-body algorithm: rows `q qd τ` to rows `q̈`.
    ///
    /// With `--derivatives`, rows `∂q̈/∂q`, `∂q̈/∂q̇` and `M⁻¹`, each row-major.
    Fd(rigid_body::FdArgs),
    /// A frame's geometric Jacobian: rows `q` to rows `J` (6 × n, row-major, world-aligned: the
    /// linear velocity of the frame's origin, then the angular velocity, in the base's axes).
    ///
    /// With `--bias`, rows `q q̇` to rows `J̇ q̇` (the frame origin's classical acceleration and
    /// its angular acceleration at `q̈ = 0`). The run-time kinematic tree of the model.
    Jacobian(kinematics::JacobianArgs),
    /// Mass matrix: rows `q` to rows `M`, row-major.
    Mass(rigid_body::RobotArgs),
    /// Gravity torques: rows `q` to rows `G`.
    Gravity(rigid_body::RobotArgs),
    /// The disturbance estimator over a recorded log: rows `q τ` (angles in rad, torques in
    /// N·m, one row per control tick, joints in the model's order) to rows `d̂` (N·m).
    ///
    /// The first row starts the estimator at rest there (`d̂ = G(q) − τ`); the filters take the
    /// paper's ζ = 0.8, ω1 = ω2 = 50 rad/s unless given. With `--timestamps`, rows `t q τ` (t in
    /// s, strictly increasing, steps of any length) to rows `t d̂`; `--columns` picks t, q and τ
    /// from a wider log by header name or position.
    #[command(allow_negative_numbers = true)]
    Estimate(estimate::EstimateArgs),
    /// Reproduce the paper's experiments on the simulated HyA and write a report.
    Reproduce(experiments::ReproduceArgs),
    /// Run a scenario of your own (TOML) and write a report.
    Run(experiments::RunArgs),
    /// List the built-in scenarios (`hya run NAME` runs one): name, robot, duration, methods,
    /// what it shows.
    Scenarios(experiments::ScenariosArgs),
    /// Open-loop rollout of the simulated arm: rows `t τ1 … τn` (held until the next row) on
    /// stdin, rows `t q1 … qn q̇1 … q̇n` every `--dt` on stdout, from rest at `--q0`.
    Plant(open_loop::PlantArgs),
    /// Sweep every observer's bandwidth (10 to 200 rad/s): `sweep.json` and a Pareto figure of
    /// estimate and tracking error against command noise; `--shard I/N` runs a part, `--merge`
    /// joins the parts.
    Sweep(sweep::SweepArgs),
    /// Generate unrolled Rust dynamics from a URDF (`--stats`: operation counts instead).
    Generate(generate::GenerateArgs),
    /// An exciting trajectory for identification: rows `t q… q̇… q̈…`, a Fourier series per joint
    /// within the joints' position and velocity limits, chosen for a well-conditioned regressor
    Excite(excite::ExciteArgs),
    /// Base parameters and joint friction from a log of rows `[t] q τ` (filtered as the
    /// estimator does): `identified.urdf`, `friction.toml`, `report.md` and `held_out.svg` in
    /// `--out`, with held-out torque predictions
    Identify(identify::IdentifyArgs),
    /// The simulated arm follows a reference (rows `t q q̇ q̈`, as `hya excite` prints) under a
    /// scenario's controller: rows `t q τ` as its sensors measure them on stdout, the log a real
    /// arm would record; `--out` also writes the plant's true rigid body
    Track(track::TrackArgs),
    /// Time the generated and generic dynamics and the HyA control tick (medians, ns).
    Bench(bench::BenchArgs),
    /// Print a completion script for a shell: `hya completions bash > ~/.local/share/bash-completion/completions/hya`
    /// (zsh: a file `_hya` on `$fpath`; fish: `~/.config/fish/completions/hya.fish`).
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let stdin = io::stdin().lock();
    let mut stdout = io::BufWriter::new(io::stdout().lock());
    let result = match cli.command {
        Command::Filter(args) => filter::run(&args, stdin, &mut stdout),
        Command::Estimate(args) => estimate::run(&args, stdin, &mut stdout),
        Command::Robots(args) => rigid_body::list(&args, &mut stdout),
        Command::Id(args) => {
            let (quantity, robot) = args.quantity();
            rigid_body::run(quantity, robot, stdin, &mut stdout)
        }
        Command::Fd(args) => {
            let (quantity, robot) = args.quantity();
            rigid_body::run(quantity, robot, stdin, &mut stdout)
        }
        Command::Jacobian(args) => kinematics::run(&args, stdin, &mut stdout),
        Command::Generate(args) => generate::run(&args, &mut stdout),
        Command::Excite(args) => excite::run(&args, &mut stdout),
        Command::Identify(args) => identify::run(&args, stdin),
        Command::Track(args) => track::run(&args, stdin, &mut stdout),
        Command::Mass(args) => rigid_body::run(rigid_body::Quantity::MassMatrix, &args, stdin, &mut stdout),
        Command::Gravity(args) => rigid_body::run(rigid_body::Quantity::Gravity, &args, stdin, &mut stdout),
        Command::Reproduce(args) => experiments::reproduce(&args, &mut stdout),
        Command::Run(args) => experiments::run(&args, &mut stdout),
        Command::Scenarios(args) => experiments::scenarios(&args, &mut stdout),
        Command::Sweep(args) => sweep::run(&args),
        Command::Plant(args) => open_loop::run(&args, stdin, &mut stdout),
        Command::Bench(args) => bench::run(&args, &mut stdout),
        Command::Completions { shell } => {
            clap_complete::generate(shell, &mut <Cli as clap::CommandFactory>::command(), "hya", &mut stdout);
            Ok(())
        }
    };
    match result.and_then(|()| stdout.flush().map_err(CliError::from)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(CliError::Io(e)) if e.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("hya: {e}");
            ExitCode::from(2)
        }
    }
}
