//! # hya-sim
//!
//! A closed-loop testbed for the paper's experiments: a simulated hydraulic arm (true dynamics
//! with perturbed parameters, friction, hydraulic torque loops, sensor noise, external loads)
//! under computed-torque control with each disturbance observer, and a report of what each buys.
//!
//! ```no_run
//! let scenario = hya_sim::Scenario::builtin("goto_internal")?;
//! for outcome in hya_sim::run_scenario::<6>(&scenario.quick())? {
//!     println!("{} {}: {:?}", outcome.scenario, outcome.method.name(), outcome.metrics.rmse_q);
//! }
//! # Ok::<(), hya_sim::SimError>(())
//! ```

// The layers, lowest first: error, io, config, robot, linear, plant, run, analysis, then the
// measurements that run the plant and the loop (frequency, torque_response), report; each file
// imports only from the layers before its own (ARCHITECTURE.md).
pub mod analysis;
pub mod config;
pub mod error;
pub mod frequency;
pub mod io;
pub mod linear;
pub mod plant;
pub mod report;
pub mod robot;
pub mod run;
pub mod studies;
pub mod torque_response;

// The modules as they were named before the layers, for users of the crate.
pub use analysis::{claims, metrics, seed_shards, seeds, sweep};
pub use config::{cost, scenario, settings};
pub use io::{input, output, svg};
pub use run::{rollout, sensors, task};

pub use analysis::metrics::Metrics;
pub use analysis::simulate::{simulate, RunOutcome};
pub use config::scenario::{Method, Scenario};
pub use error::SimError;
pub use robot::{with_robot, ForRobot, Robot};
pub use run::trace::Trace;

/// Joints of HyA, the paper's arm: the size of the experiments that only HyA runs (the plant
/// checks against MuJoCo, the viscous-friction and frequency sweeps, the benchmarks).
pub const HYA_JOINTS: usize = 6;

/// The most joints a simulated arm may have (`hya run` instantiates the simulator for each size
/// from 1 to this).
pub const MAX_JOINTS: usize = hya_core::dispatch::MAX_JOINTS;

/// Runs every method of `scenario`, in order.
pub fn run_scenario<const N: usize>(scenario: &Scenario) -> Result<Vec<RunOutcome<N>>, SimError> {
    let robot = Robot::<N>::load(&scenario.robot)?;
    scenario.methods.iter().map(|&method| simulate(scenario, method, &robot)).collect()
}

/// Runs one method of `scenario` on its robot, which must have `N` joints (see [`Robot::load`];
/// [`robot::with_robot`] finds `N` instead).
pub fn run_method<const N: usize>(scenario: &Scenario, method: Method) -> Result<RunOutcome<N>, SimError> {
    simulate(scenario, method, &Robot::<N>::load(&scenario.robot)?)
}

/// What `hya reproduce` and `hya run` do: every method of every scenario (all on one robot)
/// over `seeds` seeds, then the report in `out`; `progress` is told each run's simulated
/// seconds.
pub struct Experiment<'a> {
    /// The scenarios, checked.
    pub scenarios: &'a [Scenario],
    /// Seeds per scenario and method.
    pub seeds: usize,
    /// Told each finished run's simulated seconds.
    pub progress: &'a (dyn Fn(f64) + Sync),
    /// The report's folder, held by this run.
    pub out: &'a output::OutputDir,
    /// Whether the scenarios were shortened (`--quick`).
    pub quick: bool,
    /// Whether the report's bandwidth sweep runs the full grid (`hya sweep`'s) instead of the
    /// reduced one.
    pub full_sweep: bool,
    /// The command that asked and the build that ran it, named in the report.
    pub provenance: &'a report::Provenance,
}

impl<'a> Experiment<'a> {
    /// What an experiment on `scenarios` (checked) over `seeds` seeds costs, `quick` and
    /// `full_sweep` as in [`Experiment`]: every method of every scenario over the seeds, and the
    /// studies after them (the runs' traces held meanwhile).
    pub fn cost(scenarios: &[Scenario], seeds: usize, options: (bool, bool)) -> Result<config::cost::Cost, SimError> {
        Ok(config::cost::Cost::of(scenarios, seeds) + Self::studies_cost(scenarios, seeds, options)?)
    }

    /// What a merge of shards costs: the studies, with the first seeds' traces (taken from the
    /// shards) held meanwhile.
    pub fn merge_cost(
        scenarios: &[Scenario],
        seeds: usize,
        options: (bool, bool),
    ) -> Result<config::cost::Cost, SimError> {
        let held = config::cost::Cost {
            trace_bytes: config::cost::Cost::of(scenarios, seeds).trace_bytes,
            ..config::cost::Cost::NONE
        };
        Ok(held + Self::studies_cost(scenarios, seeds, options)?)
    }

    /// The studies' part of [`Self::cost`].
    pub fn studies_cost(
        scenarios: &[Scenario],
        seeds: usize,
        options: (bool, bool),
    ) -> Result<config::cost::Cost, SimError> {
        let Some(first) = scenarios.first() else { return Ok(config::cost::Cost::NONE) };
        let joints = robot::robot_model(&first.robot)?.dof();
        studies::cost(scenarios, seeds, joints, options)
    }

    /// Runs it on the scenarios' robot, whatever its number of joints.
    pub fn run(self) -> Result<report::Summary, SimError> {
        self.report_from(None)
    }

    /// Runs shard `shard` of its runs ([`seed_shards`]) and writes them to the folder as
    /// [`seed_shards::SHARD_FILE`]; no study and no report (the merge runs those). Returns how
    /// many runs the shard holds.
    pub fn run_shard(self, shard: analysis::sweep::Shard) -> Result<usize, SimError> {
        let robot = self.shared_robot()?;
        robot::with_robot(&robot, Sharding { experiment: self, shard })
    }

    /// Takes its runs from `shards` (each with where it came from; [`seed_shards::merge`] checks
    /// them), then runs the studies and writes the report: the report of the unsharded
    /// experiment.
    pub fn run_merged(self, shards: &'a [(String, seed_shards::RunShard)]) -> Result<report::Summary, SimError> {
        self.report_from(Some(shards))
    }

    /// The report, its runs run here (`None`) or taken from shards.
    fn report_from(self, shards: Option<&'a [(String, seed_shards::RunShard)]>) -> Result<report::Summary, SimError> {
        let robot = self.shared_robot()?;
        robot::with_robot(&robot, Reporting { experiment: self, shards })
    }

    /// The experiment's key and build, as shards record them.
    fn key(&self) -> Result<(seed_shards::ExperimentKey, String), SimError> {
        let key = seed_shards::ExperimentKey::of(self.scenarios, self.seeds, self.quick)?;
        Ok((key, self.provenance.build()))
    }

    /// The robot every scenario runs on.
    fn shared_robot(&self) -> Result<String, SimError> {
        let Some(first) = self.scenarios.first() else { return Err(SimError::Nothing("no scenario to run")) };
        if let Some(cartesian) = self.scenarios.iter().find(|s| s.task.is_cartesian()) {
            return Err(SimError::Scenario {
                origin: cartesian.name.clone(),
                message: "a task set in task space is reported at its frame (CartesianExperiment, `hya run` on it \
                          alone), not among the paper's joint-space experiments"
                    .into(),
            });
        }
        config::scenario::shared_robot(self.scenarios)?;
        Ok(first.robot.clone())
    }
}

/// An experiment's report, its runs run here or taken from `shards`, for [`robot::with_robot`].
struct Reporting<'a> {
    experiment: Experiment<'a>,
    shards: Option<&'a [(String, seed_shards::RunShard)]>,
}

impl ForRobot for Reporting<'_> {
    type Output = report::Summary;
    fn call<const N: usize>(self, robot: Robot<N>) -> Result<report::Summary, SimError> {
        let e = self.experiment;
        let (outcomes, table) = match self.shards {
            None => seeds::run_seeds::<N>(&robot, e.scenarios, e.seeds, e.progress)?,
            Some(shards) => {
                let (key, build) = e.key()?;
                seed_shards::merge::<N>(e.scenarios, (&key, &build), shards)?
            }
        };
        let studies = studies::run(&robot, e.scenarios, &table, (e.quick, e.full_sweep), e.progress)?;
        report::write(&robot, e.out, e.scenarios, &outcomes, &table, studies, e.quick, e.provenance)
    }
}

/// One shard of an experiment's runs, written to its folder, for [`robot::with_robot`].
struct Sharding<'a> {
    experiment: Experiment<'a>,
    shard: analysis::sweep::Shard,
}

impl ForRobot for Sharding<'_> {
    type Output = usize;
    fn call<const N: usize>(self, robot: Robot<N>) -> Result<usize, SimError> {
        let e = self.experiment;
        let (key, build) = e.key()?;
        let stored = seed_shards::run(&robot, e.scenarios, (&key, &build), self.shard, e.progress)?;
        e.out.save_bytes(seed_shards::SHARD_FILE, &stored.to_bytes()?)?;
        Ok(stored.runs.len())
    }
}

/// What `hya run` does with a scenario set in task space ([`config::scenario::Task::Cartesian`]):
/// every method over `seeds` seeds under the Cartesian impedance controller, measured at the
/// controlled frame ([`studies::cartesian`]), and its report in `out`
/// ([`report::cartesian`]).
pub struct CartesianExperiment<'a> {
    /// The scenario, checked.
    pub scenario: &'a Scenario,
    /// Seeds per method.
    pub seeds: usize,
    /// Told each finished run's simulated seconds.
    pub progress: &'a (dyn Fn(f64) + Sync),
    /// The report's folder, held by this run.
    pub out: &'a output::OutputDir,
    /// Whether the scenario was shortened (`--quick`), said in the report.
    pub quick: bool,
    /// The command that asked and the build that ran it, named in the report.
    pub provenance: &'a report::Provenance,
}

impl CartesianExperiment<'_> {
    /// Runs it on the scenario's robot, whatever its number of joints.
    pub fn run(self) -> Result<report::cartesian::CartesianSummary, SimError> {
        let robot = self.scenario.robot.clone();
        robot::with_robot(&robot, self)
    }
}

impl ForRobot for CartesianExperiment<'_> {
    type Output = report::cartesian::CartesianSummary;
    fn call<const N: usize>(self, robot: Robot<N>) -> Result<Self::Output, SimError> {
        let study = studies::cartesian::run(&robot, self.scenario, self.seeds, self.progress)?;
        report::cartesian::write(self.out, &study, (self.quick, self.provenance))
    }
}
