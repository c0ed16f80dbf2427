//! Files: reading them bounded ([`input`]; identified friction is read by [`hya_ident::JointFriction`]), the report folder
//! that nothing escapes ([`output`]), and SVG drawing ([`svg`]).

pub mod input;
pub mod output;
pub mod svg;
