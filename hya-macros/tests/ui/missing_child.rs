hya_macros::robot!(Bad, "../../../../hya-macros/tests/urdf/missing_child.urdf");
fn main() {}
