//! Many plants of one scenario, differing by seed, advanced together: [`Plant::advance`] of each,
//! with the rigid bodies' forward dynamics of every RK4 stage in one batch over the plants, one
//! plant per vector lane, each with its own perturbed bodies ([`hya_core::BodiesBatch`]).
//!
//! Each plant's arithmetic is its own advance's, in the same order, and the batch equals the
//! single call bit for bit, so a plant stepped here ends where it would have ended alone, bit
//! for bit (`hya-sim/tests/sim/lockstep.rs`). Where the plants part ways, each keeps its own
//! course and the batch takes the plants that need it: a plant that sub-cycles its step more
//! for its bristles' stiffness takes its extra RK4 steps while the others wait, a plant whose
//! hydraulic sample instant falls within a step splits it there on its own clock. A state the
//! batch refuses sends every plant of that step to its own methods, so that a plant that fails
//! stops with its own error; the others go on together.

use hya_core::bodies_batch::BODY_PARAMETERS;
use hya_core::{BodiesBatch, JointVector};

use super::{rk4_sum, Plant, PlantState};
use crate::error::SimError;

/// The per-plant buffers of a lockstep, sized once for its plants.
pub struct Lockstep<'k, const N: usize> {
    kernel: &'k (dyn BodiesBatch<N> + Send + Sync),
    /// The plants stepped together now, by index.
    live: Vec<usize>,
    /// Each plant's stage: its time, state, command and derivative.
    t: Vec<f64>,
    states: Vec<PlantState<N>>,
    /// The four RK4 stages of each plant (the first given, or not).
    k: [Vec<PlantState<N>>; 4],
    given: Vec<bool>,
    /// The plants taking an RK4 step now, by index (of the live ones).
    active: Vec<usize>,
    /// Each plant's RK4 cycles in this step, what is left of its cycle, the span of its next
    /// RK4 step, s, and whether that step ends its cycle.
    cycles: Vec<usize>,
    left: Vec<f64>,
    span: Vec<f64>,
    last: Vec<bool>,
    /// The batch's arguments, packed over the live plants.
    q: Vec<JointVector<N>>,
    qd: Vec<JointVector<N>>,
    tau: Vec<JointVector<N>>,
    qdd: Vec<JointVector<N>>,
    bristle: Vec<JointVector<N>>,
    bodies: [Vec<JointVector<N>>; BODY_PARAMETERS],
    /// RK4 steps taken: by plants together, by plants alone.
    taken: Steps,
}

/// How many RK4 steps a [`Lockstep`]'s plants took together (their stages batched) and alone.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Steps {
    /// RK4 steps of one plant whose stages were batched with the others'.
    pub together: usize,
    /// Evaluations one plant made by its own methods after the batch refused a state: an RK4
    /// step, or the derivative at the start of a period.
    pub alone: usize,
}

/// What one plant's advance came to: `None` while it runs, its error once it failed.
pub type Failure = Option<SimError>;

impl<'k, const N: usize> Lockstep<'k, N> {
    /// Buffers for `plants` plants, their rigid bodies by `kernel`: the parametric twin of the
    /// arm whose factory built the plants ([`crate::robot::Robot::bodies`] beside
    /// [`crate::robot::Robot::plant`]), which reads each plant's bodies as its own dynamics does.
    pub fn new(kernel: &'k (dyn BodiesBatch<N> + Send + Sync), plants: usize) -> Self {
        let vectors = || vec![JointVector::zeros(); plants];
        let states = || vec![PlantState::zeros(); plants];
        Self {
            kernel,
            live: Vec::with_capacity(plants),
            t: vec![0.0; plants],
            states: states(),
            k: core::array::from_fn(|_| states()),
            given: vec![false; plants],
            active: Vec::with_capacity(plants),
            cycles: vec![1; plants],
            left: vec![0.0; plants],
            span: vec![0.0; plants],
            last: vec![false; plants],
            q: vectors(),
            qd: vectors(),
            tau: vectors(),
            qdd: vectors(),
            bristle: vectors(),
            bodies: core::array::from_fn(|_| vectors()),
            taken: Steps::default(),
        }
    }

    /// The RK4 steps taken so far, together and alone.
    pub fn steps(&self) -> Steps {
        self.taken
    }

    /// [`Plant::advance`] of every plant whose `failed` entry is `None`, plant `j` under command
    /// `commands[j]`; its joint accelerations at the start into `accelerations[j]`. A plant
    /// that fails gets its error in `failed[j]` and is not stepped further.
    ///
    /// # Panics
    /// If the slices' lengths differ from the plants' count given to [`Self::new`].
    pub fn advance(
        &mut self,
        plants: &mut [Plant<N>],
        (dt, substeps): (f64, usize),
        commands: &[JointVector<N>],
        (accelerations, failed): (&mut [JointVector<N>], &mut [Failure]),
    ) {
        assert!(
            [plants.len(), commands.len(), accelerations.len(), failed.len()].iter().all(|&n| n == self.t.len()),
            "one entry per plant"
        );
        self.live.clear();
        self.live.extend((0..plants.len()).filter(|&j| failed[j].is_none()));
        for &j in &self.live {
            plants[j].sample_if_due(&commands[j]);
            (self.t[j], self.states[j], self.given[j]) = (plants[j].time, plants[j].state, false);
        }
        self.active.clone_from(&self.live);
        if self.stages(plants, commands, 0).is_err() {
            self.taken.alone += self.live.len();
            for &j in &self.live {
                match plants[j].stage(plants[j].time, &plants[j].state, &commands[j]) {
                    Ok(k1) => self.k[0][j] = k1,
                    Err(e) => failed[j] = Some(e),
                }
            }
            self.live.retain(|&j| failed[j].is_none());
        }
        for &j in &self.live {
            accelerations[j] = self.k[0][j].qd;
            self.given[j] = true;
        }
        let h = dt / substeps.max(1) as f64;
        for _ in 0..substeps.max(1) {
            self.step(plants, h, commands, failed);
        }
    }

    /// [`Plant::step_from`] of every live plant over `h`: plant `j` in `c_j` equal RK4 cycles
    /// ([`Plant::cycles`]), the plants still cycling stepped together in each round.
    fn step(&mut self, plants: &mut [Plant<N>], h: f64, commands: &[JointVector<N>], failed: &mut [Failure]) {
        self.live.retain(|&j| failed[j].is_none());
        let mut rounds = 0;
        for &j in &self.live {
            self.cycles[j] = plants[j].cycles(h);
            rounds = rounds.max(self.cycles[j]);
        }
        for round in 0..rounds {
            self.active.clear();
            self.active.extend(self.live.iter().copied().filter(|&j| failed[j].is_none() && self.cycles[j] > round));
            for &j in &self.active {
                self.left[j] = h / self.cycles[j] as f64;
            }
            self.sampled(plants, commands, failed);
        }
    }

    /// [`Plant::rk4_sampled`] of every active plant over what is left of its step: each plant's
    /// RK4 steps end at its hydraulic inner loops' sample instants (which run the loops), and
    /// the plants with a step left take the next one together.
    fn sampled(&mut self, plants: &mut [Plant<N>], commands: &[JointVector<N>], failed: &mut [Failure]) {
        while !self.active.is_empty() {
            for &j in &self.active {
                if plants[j].sample_if_due(&commands[j]) {
                    self.given[j] = false;
                }
                // To the next sample instant if it falls within what is left, else all of it.
                let split = plants[j].sample_split(self.left[j]);
                (self.span[j], self.last[j]) = (split.unwrap_or(self.left[j]), split.is_none());
            }
            self.rk4(plants, commands, failed);
            for &j in &self.active {
                self.left[j] -= self.span[j];
            }
            let last = &self.last;
            self.active.retain(|&j| failed[j].is_none() && !last[j]);
        }
    }

    /// [`Plant::rk4`] of every active plant `j` over `span[j]`, its four stages batched; if the
    /// batch refused a stage, every active plant takes the step alone instead, so that a plant
    /// that fails names its own failure.
    fn rk4(&mut self, plants: &mut [Plant<N>], commands: &[JointVector<N>], failed: &mut [Failure]) {
        let together = self.rk4_stages(plants, commands);
        for &j in &self.active {
            let h = self.span[j];
            let result = if together.is_ok() {
                self.taken.together += 1;
                let k = [&self.k[0][j], &self.k[1][j], &self.k[2][j], &self.k[3][j]];
                plants[j].commit(h, rk4_sum(&plants[j].state, k, h))
            } else {
                self.taken.alone += 1;
                plants[j].rk4(h, &commands[j], self.given[j].then_some(self.k[0][j]))
            };
            if let Err(e) = result {
                failed[j] = Some(e);
            }
            self.given[j] = false;
        }
    }

    /// The four RK4 stages of every active plant over its span into [`Self::k`] (the first
    /// where it is not given).
    fn rk4_stages(&mut self, plants: &[Plant<N>], commands: &[JointVector<N>]) -> Result<(), hya_core::Error> {
        if self.active.iter().any(|&j| !self.given[j]) {
            // Every plant's first stage, the given ones kept aside in the second's place.
            for &j in &self.active {
                (self.t[j], self.states[j]) = (plants[j].time, plants[j].state);
                self.k[1][j] = self.k[0][j];
            }
            let first = self.stages(plants, commands, 0);
            for &j in &self.active {
                if self.given[j] {
                    self.k[0][j] = self.k[1][j];
                }
            }
            first?;
        }
        // Stage `i` at `t + c h` from `s + c h k_{i−1}`, `c` = ½, ½, 1.
        for stage in 1..4 {
            for &j in &self.active {
                let (plant, h) = (&plants[j], self.span[j]);
                let step = if stage == 3 { h } else { h / 2.0 };
                (self.t[j], self.states[j]) = (plant.time + step, plant.state.along(&self.k[stage - 1][j], step));
            }
            self.stages(plants, commands, stage)?;
        }
        Ok(())
    }

    /// The derivative of every active plant `j` at `(t[j], states[j])` into `k[stage][j]`, the
    /// rigid bodies' accelerations in one batch; the batch's error if it refused a state.
    fn stages(
        &mut self,
        plants: &[Plant<N>],
        commands: &[JointVector<N>],
        stage: usize,
    ) -> Result<(), hya_core::Error> {
        let n = self.active.len();
        for (m, &j) in self.active.iter().enumerate() {
            let (plant, s) = (&plants[j], &self.states[j]);
            let (total, bristle) = plant.joint_torque(self.t[j], s, &commands[j]);
            (self.q[m], self.qd[m], self.tau[m], self.bristle[m]) = (s.q, s.qd, total, bristle);
            let bodies = plant.bodies(self.t[j]);
            for (column, value) in self.bodies.iter_mut().zip(bodies) {
                column[m] = *value;
            }
        }
        let bodies: hya_core::BodyColumns<N> = core::array::from_fn(|p| &self.bodies[p][..n]);
        let (q, qd, tau) = (&self.q[..n], &self.qd[..n], &self.tau[..n]);
        self.kernel.forward_dynamics_of_bodies_batch(bodies, q, qd, tau, &mut self.qdd[..n])?;
        for (m, &j) in self.active.iter().enumerate() {
            self.k[stage][j] = plants[j].rate(&self.states[j], &commands[j], (self.qdd[m], self.bristle[m]));
        }
        Ok(())
    }
}
