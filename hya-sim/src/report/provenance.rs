//! What produced a report: the command line, the build (commit, compiler, profile, flags), how
//! generated code met fused multiply-add, and the CPU, so that a reader can repeat it to the bit.

use serde::Serialize;

/// The report's provenance, printed in its header and kept in `summary.json`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Provenance {
    /// The command line that wrote the report.
    pub command: String,
    /// The git commit the binary was built from (`-dirty` with uncommitted changes), or "not a
    /// git checkout".
    pub commit: String,
    /// `rustc --version` of the build.
    pub rustc: String,
    /// The cargo profile (`release`, `debug`).
    pub profile: String,
    /// The `RUSTFLAGS` of the build (`none`).
    pub rustflags: String,
    /// How generated dynamics use fused multiply-add here ([`hya_core::FMA_SUPPORT`]).
    pub fma: String,
    /// The CPU's model name, as the operating system reports it.
    pub cpu: String,
}

impl Provenance {
    /// This machine's provenance for `command`, with the build's `[commit, rustc, profile,
    /// rustflags]` as the binary recorded them.
    pub fn here(command: String, [commit, rustc, profile, rustflags]: [&str; 4]) -> Self {
        Self {
            command,
            commit: commit.into(),
            rustc: rustc.into(),
            profile: profile.into(),
            rustflags: rustflags.into(),
            fma: match (hya_core::FMA_SUPPORT, hya_core::with_fma(|| ()).is_some()) {
                (hya_core::FmaSupport::Compiled, _) => "fused (compiled in)",
                (_, true) => "fused (detected at run time)",
                (_, false) => "plain (no FMA)",
            }
            .into(),
            cpu: cpu_model(),
        }
    }

    /// What decides a run's last bits: the commit, rustc, profile, flags and the use of fused
    /// multiply-add (shards merge only where these agree).
    pub fn build(&self) -> String {
        format!("{}; {}; {} profile; RUSTFLAGS {}; {}", self.commit, self.rustc, self.profile, self.rustflags, self.fma)
    }

    /// The command and the build as the reports print them: "`command` (commit …, rustc …, …
    /// profile, RUSTFLAGS …; generated dynamics …; CPU …)".
    pub fn described(&self) -> String {
        format!(
            "`{}` (commit {}, {}, {} profile, RUSTFLAGS {}; generated dynamics {}; CPU {})",
            self.command, self.commit, self.rustc, self.profile, self.rustflags, self.fma, self.cpu
        )
    }

    /// A provenance for tests and library callers that know nothing of their build.
    pub fn unknown(command: &str) -> Self {
        Self::here(command.into(), ["unknown"; 4])
    }
}

/// The first `model name` of `/proc/cpuinfo`, else the architecture.
fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|info| {
            info.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, name)| name.trim().to_owned())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_owned())
}
