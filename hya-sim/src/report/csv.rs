//! One run's time series as CSV: `t`, then `q`, `q_des`, `d_true`, `d_hat`, `tau_cmd` per joint.

use std::fmt::Write as _;

use crate::analysis::outcome::RunOutcome;

pub(super) fn csv<const N: usize>(o: &RunOutcome<N>) -> String {
    let mut text = String::from("t");
    for name in ["q", "q_des", "d_true", "d_hat", "tau_cmd"] {
        for j in 1..=N {
            let _ = write!(text, ",{name}{j}");
        }
    }
    text.push('\n');
    let t = &o.trace;
    for k in 0..t.time.len() {
        let _ = write!(text, "{:?}", t.time[k]);
        for v in [&t.q[k], &t.q_des[k], &t.d_true[k], &t.d_hat[k], &t.tau_cmd[k]] {
            for x in v.iter() {
                let _ = write!(text, ",{x:?}");
            }
        }
        text.push('\n');
    }
    text
}
