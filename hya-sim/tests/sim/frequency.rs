//! On a clean plant every observer's measured `d̂/d` follows its design's transfer function:
//! the observers are implemented as designed, so the report's frequency figure is trustworthy.

use hya_sim::{frequency, Scenario};

#[test]
fn observers_follow_their_designs_at_one_hertz() {
    let base = Scenario::builtin("estimator_noise_low").unwrap();
    let robot = hya_sim::Robot::<6>::load(&base.robot).unwrap();
    for point in frequency::measure(&robot, &base, &[1.0]).unwrap() {
        let ratio = point.measured / point.design;
        let (gain, phase) = (ratio.norm(), ratio.arg().to_degrees());
        assert!((gain - 1.0).abs() < 0.03, "{}: gain {gain} of the design at 1 Hz", point.method.name());
        assert!(phase.abs() < 3.0, "{}: phase {phase}° off the design at 1 Hz", point.method.name());
    }
}
