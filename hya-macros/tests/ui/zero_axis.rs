hya_macros::robot!(Bad, "../../../../hya-macros/tests/urdf/zero_axis.urdf");
fn main() {}
