//! # hya-urdf
//!
//! Reads a URDF and validates it into a [`hya_core::model::TreeModel`] ([`load_file`],
//! [`load_str`]): every description that makes no physical sense is refused with a
//! [`LoadError`] naming the file and the link or joint; fixed joints are merged into their
//! parent body. Used by the code generator, the `robot!` macro, the simulator and the `hya`
//! command alike. [`with_inertias`] writes a description back with new inertias.
//!
//! Hostile text is bounded before it is parsed: at most [`MAX_FILE_BYTES`] bytes,
//! [`MAX_XML_DEPTH`] levels of nesting, [`MAX_XML_NODES`] XML nodes, [`MAX_XML_ATTRIBUTES`] attributes, [`MAX_JOINTS`] joints and
//! [`MAX_LINKS`] links (see [`limits`]).
//!
//! ```no_run
//! let loaded = hya_urdf::load_file("robots/urdf/hya.urdf")?;
//! println!("{} joints, SHA-256 {}", loaded.model.dof(), loaded.source.sha256);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod error;
pub mod file;
pub mod limits;
pub mod load;
pub mod name;
pub mod write;

pub use error::{LoadError, Problem, Warning};
pub use limits::{MAX_FILE_BYTES, MAX_JOINTS, MAX_LINKS, MAX_XML_ATTRIBUTES, MAX_XML_DEPTH, MAX_XML_NODES};
pub use load::{load_file, load_str, read_file, LoadedModel, Source};
pub use name::{escape_name, joints_differ, name_list};
pub use write::{with_body_inertias, with_inertias};
