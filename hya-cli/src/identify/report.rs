//! `report.md` and `held_out.svg`: what `hya identify` found and how well it predicts.

use std::fmt::Write as _;

use hya_core::model::TreeModel;
use hya_ident::{BaseParameters, Consistent, Fit, PARAMETERS_PER_BODY};
use hya_sim::svg::{line_grid, Panel, Series, PALETTE};

/// Torques on the held-out samples: measured (after the filter) and each model's prediction.
pub struct Predictions {
    /// The samples' times, s.
    pub time_s: Vec<f64>,
    /// `τ̂` per sample, N·m.
    pub measured: Vec<Vec<f64>>,
    /// Each model's name and prediction per sample, N·m.
    pub models: Vec<(String, Vec<Vec<f64>>)>,
}

impl Predictions {
    /// Per-joint RMS of model `m`'s prediction error, N·m.
    pub fn rms(&self, m: usize) -> Vec<f64> {
        hya_ident::identify::rms_error(&self.models[m].1, &self.measured)
    }

    /// Per joint, the RMS of the measured torque itself, N·m.
    pub fn measured_rms(&self) -> Vec<f64> {
        let zeros: Vec<Vec<f64>> = self.measured.iter().map(|m| vec![0.0; m.len()]).collect();
        hya_ident::identify::rms_error(&zeros, &self.measured)
    }

    /// Model `m`'s error relative to the measured torque, `RMS(τ − τ̂_m) / RMS(τ)`, mean over
    /// the joints.
    pub fn relative(&self, m: usize) -> f64 {
        let (errors, scale) = (self.rms(m), self.measured_rms());
        errors.iter().zip(&scale).map(|(e, s)| e / s.max(1e-12)).sum::<f64>() / errors.len().max(1) as f64
    }
}

/// A model to hold the identified one against (`--compare`): its base parameters.
pub struct Compared {
    /// The file given.
    pub name: String,
    /// Its base parameters `K π`.
    pub base: Vec<f64>,
}

/// Everything the report states.
pub struct Findings<'a> {
    /// The nominal model.
    pub model: &'a TreeModel,
    /// Its joints' names.
    pub joints: &'a [&'a str],
    /// The base parameters' definition.
    pub base: &'a BaseParameters,
    /// The fit.
    pub fitted: &'a Fit,
    /// Full parameters of real bodies matching the fit.
    pub full: &'a Consistent,
    /// The nominal model's base parameters.
    pub nominal_base: Vec<f64>,
    /// The model of `--compare`.
    pub compared: Option<Compared>,
    /// The held-out predictions.
    pub predictions: &'a Predictions,
    /// The prior's weight `λ` the fit used (0: the log alone).
    pub prior_weight: f64,
    /// How `λ` was chosen on the data, if it was.
    pub validation: Option<&'a hya_ident::prior::Validation>,
    /// A paragraph on the data and how it was used.
    pub setup: String,
}

/// The name of parameter `column` of the regressor (`joint: m·c_x`, …).
fn parameter_name(joints: &[&str], column: usize) -> String {
    const NAMES: [&str; 10] = ["m", "m·c_x", "m·c_y", "m·c_z", "I_xx", "I_xy", "I_yy", "I_xz", "I_yz", "I_zz"];
    format!("{} {}", joints[column / NAMES.len()], NAMES[column % NAMES.len()])
}

impl Findings<'_> {
    /// The largest `|π̂_b − π_b,compared| / σ` over the base parameters.
    pub fn largest_deviation(&self) -> Option<f64> {
        let compared = self.compared.as_ref()?;
        let deviation = |j: usize| (self.fitted.base[j] - compared.base[j]).abs() / self.fitted.base_std[j];
        Some((0..self.base.rank()).map(deviation).fold(0.0, f64::max))
    }

    /// `report.md`.
    pub fn markdown(&self) -> String {
        let mut report = String::new();
        let _ = writeln!(report, "# Identification of `{}`\n\n{}\n", self.model.name(), self.setup);
        self.prediction_table(&mut report);
        self.prior(&mut report);
        self.base_table(&mut report);
        self.friction_table(&mut report);
        self.bodies(&mut report);
        report
    }

    fn prediction_table(&self, report: &mut String) {
        let models = &self.predictions.models;
        let _ = writeln!(report, "## Torque prediction on the held-out part, RMS (N·m)\n");
        let names: Vec<&str> = models.iter().map(|(name, _)| name.as_str()).collect();
        let _ = writeln!(
            report,
            "| joint | measured torque | {} |\n|---|---|{}",
            names.join(" | "),
            "---|".repeat(names.len())
        );
        let rms: Vec<Vec<f64>> = (0..models.len()).map(|m| self.predictions.rms(m)).collect();
        let measured = self.predictions.measured_rms();
        for (i, joint) in self.joints.iter().enumerate() {
            let cells: Vec<String> = rms.iter().map(|r| format!("{:.4}", r[i])).collect();
            let _ = writeln!(report, "| {joint} | {:.4} | {} |", measured[i], cells.join(" | "));
        }
        let relative: Vec<String> = (0..models.len()).map(|m| format!("{:.4}", self.predictions.relative(m))).collect();
        let _ = writeln!(report, "| RMS(error)/RMS(torque), mean over joints | 1 | {} |", relative.join(" | "));
        let _ = writeln!(
            report,
            "\nThe identified model and \"nominal model + friction fit\" have the joint law (`friction.toml`'s: \
             friction, and the armature if asked); the others are rigid bodies. \"Nominal model + friction fit\" \
             keeps the nominal bodies and fits the joint law alone on the same samples: identifying the bodies is \
             worth it where the identified model predicts better. `held_out.svg` shows the torques over time.\n"
        );
    }

    /// Base parameter `j` in standard deviations from the nominal model's.
    fn moved(&self, j: usize) -> f64 {
        (self.fitted.base[j] - self.nominal_base[j]) / self.fitted.base_std[j]
    }

    fn prior(&self, report: &mut String) {
        let _ = writeln!(
            report,
            "## Prior
"
        );
        let _ = match self.prior_weight {
            0.0 => writeln!(report, "The fit uses the log alone (`--prior-weight 0`)."),
            lambda => writeln!(
                report,
                "The fit is pulled toward the nominal model with weight λ = {lambda:e}: each body by the log-det \
                 divergence of its pseudo-inertia from the nominal one's (which keeps every body physical), each \
                 friction term toward zero (`hya_ident::prior`)."
            ),
        };
        if let Some(validation) = self.validation {
            let _ = writeln!(
                report,
                "\nλ was chosen on the data: the fitted part cut into {} blocks in time, each held out in turn and \
                 predicted by a fit to the others. Their whitened mean square error (1 is the noise level of the \
                 fit; lower is better), and the standard error over the blocks of its excess over the least \
                 error (block by block); the chosen λ is the largest whose excess is within that standard \
                 error (where the blocks cannot tell weights apart, the prior is trusted more):\n\n\
                 | λ | held-out error | standard error of the excess |\n|---|---|---|",
                hya_ident::prior::FOLDS
            );
            for point in &validation.curve {
                let mark = if point.lambda == validation.chosen { " (chosen)" } else { "" };
                let _ =
                    writeln!(report, "| {:e}{mark} | {:.4} | {:.4} |", point.lambda, point.error, point.standard_error);
            }
        }
        let r = self.base.rank();
        let moved = (0..r).filter(|&j| self.moved(j).abs() > 3.0).count();
        // A base parameter is undetermined when its standard deviation exceeds both its nominal
        // and its identified magnitude (a zero nominal product of inertia is not flagged for
        // being zero).
        let undetermined: Vec<String> = (0..r)
            .filter(|&j| {
                let magnitude = self.nominal_base[j].abs().max(self.fitted.base[j].abs()).max(1e-9);
                self.fitted.base_std[j] > magnitude
            })
            .map(|j| j.to_string())
            .collect();
        let _ = writeln!(
            report,
            "\nThe log moved {moved} of the {r} base parameters more than three standard deviations from the \
             nominal model's. {}",
            match undetermined.len() {
                0 => "Every base parameter's standard deviation is below its nominal magnitude.".to_owned(),
                _ => format!(
                    "Warning: the log leaves {} of them undetermined (standard deviation above both the \
                     nominal and the identified magnitude: # {}); excite them before trusting them.",
                    undetermined.len(),
                    undetermined.join(", ")
                ),
            }
        );
        let _ = writeln!(report);
    }

    fn base_table(&self, report: &mut String) {
        let _ = writeln!(report, "## Base parameters\n");
        let _ = writeln!(
            report,
            "Each is the named parameter plus the dependent ones it absorbs (`π_b = K π`, `hya_ident::base`).\n"
        );
        let compared = self.compared.as_ref();
        let extra = compared.map_or(String::new(), |c| format!(" {} | (identified − it)/σ |", c.name));
        let _ = writeln!(
            report,
            "| # | named after | nominal | identified | standard deviation | (identified − nominal)/σ |{extra}\n|---|---|---|---|---|---|{}",
            if compared.is_some() { "---|---|" } else { "" }
        );
        for (j, &column) in self.base.independent.iter().enumerate() {
            let (value, std) = (self.fitted.base[j], self.fitted.base_std[j]);
            let extra =
                compared.map_or(String::new(), |c| format!(" {:.6} | {:+.2} |", c.base[j], (value - c.base[j]) / std));
            let _ = writeln!(
                report,
                "| {j} | {} | {:.6} | {value:.6} | {std:.2e} | {:+.2} |{extra}",
                parameter_name(self.joints, column),
                self.nominal_base[j],
                self.moved(j),
            );
        }
        if let (Some(c), Some(largest)) = (compared, self.largest_deviation()) {
            let _ = writeln!(
                report,
                "\nThe identified base parameters lie within {largest:.2} of their standard deviations of {}'s.",
                c.name
            );
        }
    }

    fn friction_table(&self, report: &mut String) {
        let f = &self.fitted.friction;
        let armature = !f.armature_kg_m2.is_empty();
        let (head, rule) = if armature { (" armature (kg·m²) |", "---|") } else { ("", "") };
        let _ = writeln!(
            report,
            "\n## Friction\n\n| joint | coulomb (N·m) | viscous (N·m·s/rad) | offset (N·m) |{head}\n|---|---|---|---|{rule}"
        );
        for (i, joint) in self.joints.iter().enumerate() {
            let values = [f.coulomb_nm[i], f.viscous_nm_s[i], f.offset_nm[i], f.armature(i)];
            let cells: String =
                values.iter().zip(&self.fitted.friction_std[i]).map(|(v, s)| format!(" {v:.4} ± {s:.1e} |")).collect();
            let _ = writeln!(report, "| {joint} |{cells}");
        }
    }

    fn bodies(&self, report: &mut String) {
        let (full, model) = (self.full, self.model);
        let mismatch =
            (0..self.base.rank()).map(|j| full.base_mismatch[j].abs() / self.fitted.base_std[j]).fold(0.0, f64::max);
        let inconsistent = if full.inconsistent_nominal_bodies.is_empty() {
            String::new()
        } else {
            let names = full.inconsistent_nominal_bodies.iter().map(|&b| model.bodies()[b].link.as_str());
            format!(" The nominal description's inertia of {} is not that of a real body.", hya_urdf::name_list(names))
        };
        let how = match self.prior_weight {
            0.0 => format!(
                "from the nominal ones by {} alternating projections (`hya_ident::physical`); they match the \
                 identified base parameters to within {mismatch:.2} of their standard deviations",
                full.iterations
            ),
            _ => format!(
                "found with the prior in {} Newton steps (`hya_ident::prior`): physical by construction, and \
                 exactly the identified base parameters",
                full.iterations
            ),
        };
        let _ = writeln!(
            report,
            "\n## Bodies (`identified.urdf`)\n\nFull parameters of real bodies (every pseudo-inertia positive \
             definite), {how}.{inconsistent}\n"
        );
        let _ = writeln!(
            report,
            "A body's own mass is identifiable only where a base parameter is that mass alone; elsewhere the \
             masses below are one consistent choice among many that predict the same torques.\n"
        );
        let _ = writeln!(report, "| link | nominal mass (kg) | identified mass (kg) |\n|---|---|---|");
        for (b, body) in model.bodies().iter().enumerate() {
            let mass = full.parameters[b * PARAMETERS_PER_BODY];
            let _ = writeln!(report, "| {} | {:.4} | {mass:.4} |", body.link, body.inertia.mass);
        }
    }

    /// `held_out.svg`: per joint, the measured torque and each model's prediction over the first
    /// [`FIGURE_SAMPLES`] held-out samples.
    pub fn figure(&self) -> String {
        let p = self.predictions;
        let shown = p.time_s.len().min(FIGURE_SAMPLES);
        let series = |label: &str, values: &[Vec<f64>], i: usize, color: &'static str, dashed: bool| Series {
            label: label.to_owned(),
            points: p.time_s[..shown].iter().zip(values).map(|(&t, v)| (t, v[i])).collect(),
            color,
            dashed,
            markers: false,
        };
        let panels: Vec<Panel> =
            self.joints
                .iter()
                .enumerate()
                .map(|(i, joint)| Panel {
                    title: (*joint).to_owned(),
                    y_label: "torque (N·m)".into(),
                    series: std::iter::once(series("measured (filtered)", &p.measured, i, PALETTE[0], false))
                        .chain(p.models.iter().enumerate().map(|(m, (name, values))| {
                            series(name, values, i, PALETTE[1 + m % (PALETTE.len() - 1)], true)
                        }))
                        .collect(),
                })
                .collect();
        line_grid(&format!("{}: held-out torques, measured and predicted", self.model.name()), "time (s)", &panels, 2)
    }
}

/// The most held-out samples `held_out.svg` draws (at one per `1/ω`, 40 s at the default 50 rad/s).
pub const FIGURE_SAMPLES: usize = 2000;
