hya_macros::robot!(Bad, "tests/urdf/does_not_exist.urdf");
fn main() {}
