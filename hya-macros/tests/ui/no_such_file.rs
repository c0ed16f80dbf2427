hya_macros::robot!(Bad, "../../../../hya-macros/tests/urdf/does_not_exist.urdf");
fn main() {}
