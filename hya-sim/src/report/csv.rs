//! One run's time series as CSV, in the command line's table format (a header naming each column
//! with its unit): `t [s]`, then per joint J `q_J`, `q_des_J` (rad, or m for a prismatic
//! joint), `d_true_J`, `d_hat_J`, `tau_cmd_J` (N m, or N), written through the csv crate.

use std::fmt::Write as _;

use hya_core::model::{JointKind, TreeModel};

use crate::analysis::simulate::RunOutcome;
use crate::SimError;

/// The header: `t [s]`, then each signal's column per joint of `model`.
fn header(model: &TreeModel) -> Vec<String> {
    // Each signal, and whether it is a position (else a torque).
    let signals = [("q", true), ("q_des", true), ("d_true", false), ("d_hat", false), ("tau_cmd", false)];
    let mut names = vec!["t [s]".to_string()];
    for (signal, position) in signals {
        let unit = |kind: JointKind| if position { kind.position_unit() } else { kind.effort_unit() };
        names.extend(model.bodies().iter().map(|b| format!("{signal}_{} [{}]", b.joint, unit(b.kind))));
    }
    names
}

/// The run's trace as CSV text for the file `name`, each number in the shortest text that reads
/// back to it.
pub(super) fn csv<const N: usize>(o: &RunOutcome<N>, model: &TreeModel, name: &str) -> Result<String, SimError> {
    let failed =
        |e: &dyn std::fmt::Display| SimError::Io { path: name.into(), source: std::io::Error::other(e.to_string()) };
    let mut out = csv::WriterBuilder::new().comment(Some(b'#')).from_writer(Vec::new());
    out.write_record(header(model)).map_err(|e| failed(&e))?;
    let t = &o.trace;
    let mut number = String::new();
    for k in 0..t.time.len() {
        let signals = [&t.q[k], &t.q_des[k], &t.d_true[k], &t.d_hat[k], &t.tau_cmd[k]];
        for v in std::iter::once(t.time[k]).chain(signals.iter().flat_map(|s| s.iter().copied())) {
            number.clear();
            let _ = write!(number, "{v:?}");
            out.write_field(&number).map_err(|e| failed(&e))?;
        }
        out.write_record(None::<&[u8]>).map_err(|e| failed(&e))?;
    }
    let bytes = out.into_inner().map_err(|e| failed(&e))?;
    String::from_utf8(bytes).map_err(|e| failed(&e))
}
