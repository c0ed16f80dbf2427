hya_macros::robot!("Bad", "tests/urdf/arm.urdf");
fn main() {}
